"""The ``[nonlinear]`` section behind the section protocol (:mod:`studies.sections.protocol`): nonlinear Euler
marches of the study's gusts at growing amplitudes, against its linear models.

Its table and keys are :mod:`studies.sections.nonlinear.schema`', its tasks, plan and reader
:mod:`studies.sections.nonlinear.study`', its report part :mod:`studies.sections.nonlinear.report`. Per flow case
and gust shape: one task of marches, once the case's steady flow is stored and its FRFs and LTD histories have
ended (so that an interrupted run has the case's ROMs first).
"""

from __future__ import annotations

from ...run.progress import task_key
from ..protocol import PieceKind, Plan, Section, SectionRead, Task, register, step_id
from .report import LINEARITY_COLUMNS, linearity_rows, nonlinear_section
from .schema import NONLINEAR_DEPENDENCIES, NONLINEAR_PIECES, describe, parse_nonlinear
from .study import load_linearity, nonlinear_plan, nonlinear_status, nonlinear_task

__all__ = ["NonlinearSection", "SECTION"]


class NonlinearSection(Section):
    """``[nonlinear]`` (see the module docstring)."""

    name = "nonlinear"
    table = "nonlinear"
    pieces = tuple(PieceKind(kind, NONLINEAR_DEPENDENCIES[kind]) for kind in NONLINEAR_PIECES)

    def parse(self, table, error, study):
        return parse_nonlinear(table, error, study.cases, study.gusts, study.simulation)

    def describe(self, options) -> str:
        return describe(options)

    def width(self, config) -> int:
        """One task per case and gust."""
        return len(config.nonlinear.cases) * len(config.nonlinear.gusts)

    def plan(self, config, store, force: bool) -> Plan:
        root, codes = str(store.root), store.codes
        tasks = []
        n_cfd = 0
        for name, marches in nonlinear_plan(config, store, force).items():
            n_cfd += len(marches)
            by_gust: dict = {}
            for gust, amplitude in marches:
                by_gust.setdefault(gust, []).append(amplitude)
            for gust, amplitudes in by_gust.items():
                tasks.append(Task("nonlinear", name, nonlinear_task,
                                  (config, name, gust, amplitudes, root, codes, force),
                                  task_key("nonlinear", f"{name} {gust}"), after=(step_id("cfd", name),),
                                  needs_ok=(step_id("steady", name),), priority=60))
        return Plan(tasks=tuple(tasks), cfd_pieces=n_cfd)

    def read(self, config, store) -> SectionRead:
        missing, failed = nonlinear_status(config, store)
        return SectionRead(missing=missing, failed=failed)

    def template_tables(self, results) -> dict:
        """The linearity table, which the linearity pages' prose quotes."""
        return {"linearity": (linearity_rows(load_linearity(results)), list(LINEARITY_COLUMNS))}

    def report(self, context) -> str:
        return nonlinear_section(context.results, context.out_dir, context.page_dir, figures=context.figures,
                                 dpi=context.dpi, say=context.say)


SECTION = register(NonlinearSection())
"""The registered instance."""
