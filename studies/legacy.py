"""The import paths of the flat ``studies`` package (before its sub-packages), kept for one release.

``import studies.runner`` (or ``from studies.pieces import frf_piece``) still works: :class:`LegacyFinder`, put on
``sys.meta_path`` by ``import studies`` (the finder of :mod:`cfd.legacy`), answers each old module name of :data:`MOVED` with the module at its
new home (the same module object, so that patching one patches the other) and a ``DeprecationWarning`` that
names the new path. ``studies.config``, ``studies.report`` and ``studies.cli`` are packages now whose names
(``studies.config.load_study``, ``studies.report.make_report``, ``studies.cli:main``) keep working unchanged.
"""

from __future__ import annotations

from cfd.legacy import LegacyFinder
from cfd.legacy import install as install_finder

__all__ = ["MOVED", "LegacyFinder", "install"]

MOVED = {f"studies.{old}": f"studies.{new}" for old, new in {
    "config_reader": "config.reader",
    "config_sections": "config.entries",
    "schema": "config.schema",
    "cases": "config.cases",
    "case_fields": "config.case_fields",
    "case_types": "config.case_types",
    "grid_spec": "config.grid_spec",
    "numbers": "config.numbers",
    "hashing": "config.hashing",
    "cache": "store.cache",
    "provenance": "store.provenance",
    "files": "store.files",
    "rom_export": "store.rom_export",
    "results": "store.results",
    "pieces": "sections.gust_rom.pieces",
    "tasks": "sections.gust_rom.tasks",
    "runner": "run.runner",
    "executors": "run.executors",
    "progress": "run.progress",
    "report_rows": "report.rows",
    "report_figures": "report.figures",
    "report_page": "report.page",
    "tables": "report.tables",
    "plots": "report.plots",
    "plot_data": "report.plot_data",
    "plot_style": "report.plot_style",
    "figure_files": "report.figure_files",
    "frf_plots": "report.frf_plots",
    "hankel_plots": "report.hankel_plots",
    "heatmap_plots": "report.heatmap_plots",
    "history_plots": "report.history_plots",
    "error_plots": "report.error_plots",
    "aeroelastic_schema": "sections.aeroelastic.schema",
    "aeroelastic_study": "sections.aeroelastic.study",
    "aeroelastic_report": "sections.aeroelastic.report",
    "nonlinear_schema": "sections.nonlinear.schema",
    "nonlinear_study": "sections.nonlinear.study",
    "nonlinear_report": "sections.nonlinear.report",
    "commands": "cli.commands",
    "fit": "cli.fit",
    "fit_data": "cli.fit_data",
    "fit_plots": "cli.fit_plots",
    "demo": "cli.demo",
    "synthetic": "cli.synthetic",
    "exit_codes": "cli.exit_codes",
}.items()}
"""Old module name -> its new home."""


def install() -> None:
    """Put the finder of :data:`MOVED` on ``sys.meta_path`` (once): :class:`cfd.legacy.LegacyFinder`, the same
    machinery as the ``cfd`` package's old paths."""
    install_finder(MOVED)
