"""``python -m studies.cli``: the ``lfdrom`` command line."""

from .entry import main

raise SystemExit(main())
