"""The ``[loads]`` section behind the section protocol (:mod:`studies.sections.protocol`): certification gust loads
(CS-25.341: tuned discrete gusts and continuous turbulence, :mod:`loads`) at flight points, from the study's own gust
ROMs, for the rigid aerofoil and for flexible sections.

Its table and keys are :mod:`studies.sections.loads.schema`', its tasks, plan and reader
:mod:`studies.sections.loads.study`', its report part :mod:`studies.sections.loads.report`. Per case: one task that
waits for the case's ROMs (the gust-ROM section's task ``step_id("roms", case)``) and computes the rigid loads piece
of each of its flight points (about 0.3 s each); and, for a case with flexible points, one task that also waits for
the case's motion FRF (the ``[aeroelastic]`` section's task ``step_id("motion", case)``, skipped when it fails) and
computes a piece per flight point and flexible section.
"""

from __future__ import annotations

from ...run.progress import task_key
from ..protocol import PieceKind, Plan, Section, SectionRead, Task, register, step_id
from .report import loads_report
from .schema import LOADS_ARRAYS, LOADS_DEPENDENCIES, describe, parse_loads
from .study import flexible_plan, flexible_task, load_loads, loads_plan, loads_status, loads_task

__all__ = ["LoadsSection", "SECTION"]


class LoadsSection(Section):
    """``[loads]`` (see the module docstring)."""

    name = "loads"
    table = "loads"
    pieces = (PieceKind("loads", LOADS_DEPENDENCIES["loads"], LOADS_ARRAYS),)

    def parse(self, table, error, study):
        return parse_loads(table, error, study)

    def describe(self, options) -> str:
        return describe(options)

    def width(self, config) -> int:
        """One task per case with flight points, and one per case with flexible points."""
        return len(config.loads.cases) + len(config.loads.flexible_cases)

    def plan(self, config, store, force: bool) -> Plan:
        root, codes = str(store.root), store.codes
        tasks, n = [], 0
        for case, count in loads_plan(config, store, force).items():
            if not count:
                continue
            n += count
            tasks.append(Task("loads", case, loads_task, (config, case, root, codes, force), task_key("loads", case),
                              after=(step_id("roms", case),), needs_ok=(step_id("steady", case),), priority=70))
        for case, count in flexible_plan(config, store, force).items():
            if not count:
                continue
            n += count
            tasks.append(Task("flexible loads", case, flexible_task, (config, case, root, codes, force),
                              task_key("flexible loads", case), after=(step_id("roms", case),),
                              needs_ok=(step_id("steady", case), step_id("motion", case)), priority=75))
        return Plan(tasks=tuple(tasks), rom_pieces=n)

    def summary(self, config, results) -> str:
        records = results.sections.get(self.name) or []
        opts = config.loads
        total = len(opts.points) * opts.rigid + sum(len(p.sections) for p in opts.points)
        return f"{len(records)}/{total} loads pieces (flight points" + (" and flexible sections)" if opts.sections
                                                                         else ")")

    def read(self, config, store) -> SectionRead:
        missing, failed = loads_status(config, store)
        return SectionRead(records=load_loads(config, store), missing=missing, failed=failed)

    def has_results(self, results) -> bool:
        return bool(results.sections.get(self.name))

    def report(self, context) -> str:
        return loads_report(context)


SECTION = register(LoadsSection())
"""The registered instance."""
