"""Reports of a study from its stored results only: tables, figures and a Markdown page (the last stage).

- :mod:`studies.report.make`: :func:`make_report`, :func:`write_report`, :func:`report_paths`; the page is the
  registered sections' report parts, in order (:mod:`studies.sections`);
- :mod:`studies.report.rows`, :mod:`studies.report.tables`: rows from the results and their CSV, Markdown and
  LaTeX tables;
- :mod:`studies.report.figures`, :mod:`studies.report.figure_files`: the figure families, the figure cache and
  the PNG files; :mod:`studies.report.plots` and the ``*_plots`` modules (with ``plot_data``, ``plot_style``) draw
  them;
- :mod:`studies.report.page`: the Markdown page, its prose slots and its findings.

The names of :mod:`studies.report.make` (what ``studies.report`` was before it became a package) are read here
on first use.
"""

import importlib
import pkgutil

__all__ = ['ReportError', 'make_report', 'report_paths', 'write_report', 'read_prose', 'check_page', 'findings',
           'rom_rows', 'sim_rows', 'summary_rows', 'method_rows', 'cost_rows', 'rom_columns', 'sim_columns',
           'summary_columns', 'PAPER_FRF_FIGURES', 'PAPER_HISTORY_FIGURES', 'PAPER_CLAIMS', 'SLOTS', 'FIGURE_MANIFEST',
           'FIGURE_SPECS', 'ERROR_RANGE']


def __getattr__(name):
    # not for the package's own modules: ``from . import plots`` inside it must import the module, not this
    if name.startswith("_") or name in {m.name for m in pkgutil.iter_modules(__path__)}:
        raise AttributeError(f"module 'studies.report' has no attribute {name!r}")
    try:
        return getattr(importlib.import_module("studies.report.make"), name)
    except AttributeError:
        raise AttributeError(f"module 'studies.report' has no attribute {name!r}") from None
