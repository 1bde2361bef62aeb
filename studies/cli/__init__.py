"""The ``lfdrom`` command line (console script ``studies.cli:main``).

- :mod:`studies.cli.entry`: the parser and :func:`main`;
- :mod:`studies.cli.commands`: ``cases``, ``run``, ``report``, ``rom``, ``show`` (they validate their inputs,
  then hand over to :func:`studies.run.runner.run_study` and :func:`studies.report.make_report`);
- :mod:`studies.cli.fit` (with ``fit_data``, ``fit_plots``): ``lfdrom fit``, identification of a measured FRF;
- :mod:`studies.cli.demo`, :mod:`studies.cli.synthetic`: the identification demo and a synthetic study;
- :mod:`studies.cli.exit_codes`: the exit statuses.
"""

import importlib

__all__ = ["main", "build_parser", "EXIT_BROKEN_PIPE"]


def __getattr__(name):
    if name in __all__:
        return getattr(importlib.import_module("studies.cli.entry"), name)
    raise AttributeError(f"module 'studies.cli' has no attribute {name!r}")
