"""Command line ``lfdrom`` (console script).

Subcommands: ``demo`` (identification demo on a synthetic system), ``cases`` (the paper's T1-T6 and G1-G6),
``run STUDY.toml``, ``report STUDY.toml`` and ``rom CASE --order N`` (implemented in :mod:`studies.cli.commands`:
they validate their inputs first and hand over to ``studies.run.runner.run_study`` / ``studies.report.make_report``).
Every subcommand has ``--help``.
"""

from __future__ import annotations

import argparse


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="lfdrom",
        description="Gust reduced-order models of aerofoils: LFD CFD and frequency-domain subspace identification.",
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    from . import demo

    p_demo = sub.add_parser("demo", help="identification demo on a synthetic gust-like system",
                            description=demo.__doc__.splitlines()[0])
    demo.build_parser(p_demo)
    from . import commands

    commands.add_subcommands(sub)
    return parser


EXIT_BROKEN_PIPE = 141
"""Exit status when the reader of the output went away (``lfdrom cases | head``): 128 + SIGPIPE, as a shell
tool killed by the signal."""


def main(argv=None) -> int:
    """Entry point of the ``lfdrom`` console script; returns the exit status (130 after Ctrl-C, with one line;
    :data:`EXIT_BROKEN_PIPE`, silently, when the output's reader closed the pipe)."""
    import os
    import sys

    try:
        status = _main(argv)
        sys.stdout.flush()   # here, where a closed pipe is caught, not at interpreter exit
        return status
    except KeyboardInterrupt:
        print("lfdrom: interrupted; whatever was stored is kept, and the same command resumes from it",
              file=sys.stderr)
        return 130
    except BrokenPipeError:
        # the reader closed the pipe (``| head``): no traceback, and no second error when Python flushes stdout
        # at exit (the recipe of the Python documentation, "Note on SIGPIPE")
        try:
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, sys.stdout.fileno())
        except (OSError, ValueError):   # stdout without a file descriptor (captured): nothing to redirect
            pass
        return EXIT_BROKEN_PIPE


def _main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return 2
    if args.command == "demo":
        from .demo import cli

        return cli(args)
    from . import commands

    if args.command in commands.COMMANDS:
        return commands.dispatch(args)
    parser.error(f"unknown command {args.command!r}")  # pragma: no cover
    return 2


if __name__ == "__main__":
    raise SystemExit(main())
