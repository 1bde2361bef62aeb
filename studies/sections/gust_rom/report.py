"""The gust-ROM section's part of the report: its tables (``roms``, ``sims``, ``summary``, ``methods``,
``cost``), its figures (FRFs, Hankel singular values, errors, histories, heat maps) and the page's head, prose
slots and findings (:mod:`studies.report.rows`, :mod:`studies.report.figures`, :mod:`studies.report.page`)."""

from __future__ import annotations

from ...report.figures import is_paper_study, report_figures
from ...report.page import page_markdown
from ...report.rows import TABLE_NAMES, report_tables
from ...report.tables import write_tables
from ..protocol import ReportContext

__all__ = ["gust_rom_report"]


def gust_rom_report(context: ReportContext) -> str:
    """Write the gust-ROM tables and figures under ``context.out_dir``; return the page's text (its head, prose
    slots, tables and figures of the gust ROMs).

    Parameters
    ----------
    context : studies.sections.protocol.ReportContext
        ``paper`` None: on for a study of the paper's cases (:func:`studies.report.figures.is_paper_study`).

    Returns
    -------
    str
        Markdown.
    """
    results, say = context.results, context.say
    config = results.config
    fig_dir, tab_dir = context.out_dir / "figures", context.out_dir / "tables"
    say(f"report {config.name}: tables in {tab_dir}")
    tables = report_tables(results)
    for name in TABLE_NAMES:
        rows, columns = tables[name]
        if rows:
            write_tables(rows, tab_dir / name, columns, context.formats,
                         caption=f"{config.name}: {name}", label=f"tab:{config.name}-{name}")

    say(f"report {config.name}: figures in {fig_dir}")
    paper = context.paper if context.paper is not None else is_paper_study(config)
    drawn = None
    if context.figures:
        drawn = report_figures(results, tables, fig_dir, dpi=context.dpi, paper=paper, redraw=context.redraw, say=say)
    else:
        say(f"report {config.name}: figures not drawn (figures=False)")
    return page_markdown(results, {**context.template_tables, **tables}, drawn, context.slots, page_dir=context.page_dir, tab_dir=tab_dir,
                         title=context.title, paper=paper)
