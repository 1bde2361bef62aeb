"""Exit statuses of the ``lfdrom`` subcommands (the study commands and ``fit`` share them).

- ``EXIT_OK`` (0): everything asked for was computed and written;
- ``EXIT_FAILED`` (1): the computation failed (an unexpected error, reported with its type);
- ``EXIT_UNAVAILABLE`` (2): bad input (file, options), found before any computation;
- ``EXIT_INCOMPLETE`` (3): some pieces failed or are missing; a rerun retries them;
- ``EXIT_NOT_WRITTEN`` (4): nothing could be written;
- ``EXIT_INTERRUPTED`` (130): interrupted (Ctrl-C), the shell's convention (128 + SIGINT).

This module imports nothing, so that every command module may use it.
"""

__all__ = ["EXIT_OK", "EXIT_FAILED", "EXIT_UNAVAILABLE", "EXIT_INCOMPLETE", "EXIT_NOT_WRITTEN", "EXIT_INTERRUPTED"]

EXIT_OK, EXIT_FAILED, EXIT_UNAVAILABLE, EXIT_INCOMPLETE, EXIT_NOT_WRITTEN = 0, 1, 2, 3, 4
EXIT_INTERRUPTED = 130
