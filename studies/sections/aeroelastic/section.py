"""The ``[aeroelastic]`` section behind the section protocol (:mod:`studies.sections.protocol`): flutter and
gust response of typical sections with the study's own aerodynamics.

Its table and keys are :mod:`studies.sections.aeroelastic.schema`', its tasks, plan and reader
:mod:`studies.sections.aeroelastic.study`', its report part :mod:`studies.sections.aeroelastic.report`. Per flow
case: the motion FRF once the case's steady flow (gust-ROM section) is stored, then the flutter of every section.
"""

from __future__ import annotations

from ...run.progress import task_key
from ..protocol import PieceKind, Plan, Section, SectionRead, Task, register, step_id
from .report import aeroelastic_section
from .schema import AEROELASTIC_DEPENDENCIES, AEROELASTIC_PIECES, describe, parse_aeroelastic
from .study import aeroelastic_plan, aeroelastic_status, flutter_task, motion_frf_task

__all__ = ["AeroelasticSection", "SECTION"]


class AeroelasticSection(Section):
    """``[aeroelastic]`` (see the module docstring)."""

    name = "aeroelastic"
    table = "aeroelastic"
    pieces = tuple(PieceKind(kind, AEROELASTIC_DEPENDENCIES[kind]) for kind in AEROELASTIC_PIECES)

    def parse(self, table, error, study):
        return parse_aeroelastic(table, error, study.cases, study.gusts)

    def describe(self, options) -> str:
        return describe(options)

    def width(self, config) -> int:
        """One motion FRF per case."""
        return len(config.aeroelastic.cases)

    def plan(self, config, store, force: bool) -> Plan:
        root, codes = str(store.root), store.codes
        tasks = []
        n_cfd = n_id = 0
        for name, needs in aeroelastic_plan(config, store, force).items():
            steady, motion = step_id("steady", name), step_id("motion", name)
            n_cfd += needs["motion"]
            n_id += needs["flutter"]
            if needs["motion"]:
                tasks.append(Task("motion", name, motion_frf_task, (config, name, root, codes),
                                  task_key("motion", name), ids=(motion,), needs_ok=(steady,), priority=10))
            if needs["flutter"]:
                tasks.append(Task("flutter", name, flutter_task, (config, name, root, codes, force),
                                  task_key("flutter", name), needs_ok=(steady, motion), priority=20))
        return Plan(tasks=tuple(tasks), cfd_pieces=n_cfd, rom_pieces=n_id)

    def read(self, config, store) -> SectionRead:
        missing, failed = aeroelastic_status(config, store)
        return SectionRead(missing=missing, failed=failed)

    def report(self, context) -> str:
        return aeroelastic_section(context.results, context.out_dir, context.page_dir, figures=context.figures,
                                   dpi=context.dpi, say=context.say)


SECTION = register(AeroelasticSection())
"""The registered instance."""
