"""The gust-ROM section: the paper's pipeline (steady flow, LFD FRFs, LTD histories, identified ROMs and their gust
histories) behind the section protocol (:mod:`studies.sections.protocol`).

It has no table of its own: it is always on and reads the study's core tables (cases, gusts, ``[sweep]``,
``[methods]``, ``[simulation]``, ``[cfd]``). Its pieces are :mod:`studies.sections.gust_rom.pieces`', its tasks
:mod:`studies.sections.gust_rom.tasks`', its reader :mod:`studies.sections.gust_rom.read` and its report part
:mod:`studies.sections.gust_rom.report`. Other sections wait for its steady flows by the task name
``step_id("steady", case)`` and for a case's FRFs and LTD histories by ``step_id("cfd", case)``.
"""

from __future__ import annotations

from ...run.compute import needs_compute
from ...run.progress import task_key
from ..protocol import Plan, Section, SectionRead, Task, register, step_id
from .pieces import PIECE_KINDS, frf_piece, ltd_piece, rom_piece, sim_piece, steady_piece
from .read import read_gust_rom
from .report import gust_rom_report
from .tasks import frf_task, ltd_task, rom_task, steady_task

__all__ = ["GustRomSection", "SECTION"]


class GustRomSection(Section):
    """The gust-ROM pipeline (see the module docstring)."""

    name = "gust_rom"
    table = None
    pieces = PIECE_KINDS

    def width(self, config) -> int:
        """Per case, one task per ``T`` (its LFD sweep) and one for its gusts (one LTD march)."""
        return sum(max(1, len(case_sweep.T) + (1 if config.gusts else 0)) for case_sweep in config.cases)

    def plan(self, config, store, force: bool) -> Plan:
        """Per case: its steady flow, then its LTD march and FRFs, then one task for its ROMs and simulations."""
        root, codes = str(store.root), store.codes
        tasks = []
        n_cfd = n_id = 0
        for case_sweep in config.cases:
            case = case_sweep.case
            name = case.name
            steady = step_id("steady", name)
            cfd = step_id("cfd", name)
            if needs_compute(store, "steady", steady_piece(case), force):
                n_cfd += 1
                tasks.append(Task("steady", name, steady_task, (config, name, root, codes), task_key("steady", name),
                                  ids=(steady,), priority=0,
                                  failure_note=f"{name}: no steady flow, its FRFs, LTD histories and ROMs are skipped"))
            ltds = [gust.name for gust in config.gusts
                    if needs_compute(store, "ltd", ltd_piece(case, gust, config.simulation, config.cfd), force)]
            # The LTD first: on the paper grid the march of a case's gusts (2000 steps) costs about twice its
            # 257-frequency sweep; the longer task first leaves a shorter one to end the run.
            if ltds:  # all the case's gusts in one march: one factorisation, block solves
                n_cfd += len(ltds)
                tasks.append(Task("ltd", name, ltd_task, (config, name, ltds, root, codes), task_key("ltd", name),
                                  ids=(cfd,), needs_ok=(steady,), priority=30))
            for T in case_sweep.T:
                if needs_compute(store, "frf", frf_piece(case, T, config.M_base, config.cfd), force):
                    n_cfd += 1
                    tasks.append(Task("frf", name, frf_task, (config, name, T, root, codes), task_key("frf", name, T),
                                      ids=(cfd,), needs_ok=(steady,), priority=40))
            n_rom = n_sim = 0
            for point in config.points():
                if point.case.name != name:
                    continue
                n_rom += needs_compute(store, "rom", rom_piece(point, config.M_base, config.cfd), force)
                n_sim += sum(needs_compute(store, "sim", sim_piece(point, gust, config.M_base, config.simulation,
                                                                    config.cfd), force)
                             for gust in config.gusts)
            n_id += n_rom + n_sim
            if n_rom or n_sim:
                tasks.append(Task("roms", name, rom_task, (config, name, root, codes, force), task_key("roms", name),
                                  ids=(step_id("roms", name),), after=(cfd,), needs_ok=(steady,), priority=50))
        return Plan(tasks=tuple(tasks), cfd_pieces=n_cfd, rom_pieces=n_id)

    def summary(self, config, results) -> str:
        return f"{sum(r.ok for r in results.roms)}/{len(config.points())} ROMs ok, {len(results.sims)} ROM simulations"

    def read(self, config, store) -> SectionRead:
        return read_gust_rom(config, store)

    def has_results(self, results) -> bool:
        return bool(results.steady or results.frf or results.ltd or results.roms or results.sims)

    def report(self, context) -> str:
        return gust_rom_report(context)


SECTION = register(GustRomSection())
"""The registered instance."""
