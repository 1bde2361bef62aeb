"""The study runner: a validated study in, every missing piece computed into the results store, results out.

Pipeline of a case in the gust-ROM section (:mod:`studies.sections.gust_rom`)::

    mesh -> steady ------------------> linearise -> LFD FRF per T on mckelvey_grid(M_base, T)
                                                 \\-> LTD history per gust (x0, dt, t_end of the study)
    FRF -> subsample to each M -> identify (order, method variant) -> ROM
    ROM -> d2c (Eq. 26) -> Tustin or ZOH at the LTD step -> simulation per gust -> vs LTD

Tasks and executors
-------------------
Each section of the study (:mod:`studies.sections.protocol`) plans the tasks that compute and store what the
store lacks (the gust-ROM section: one ``steady`` task per case, then, once its steady flow is stored, one task
per FRF (case, T) and one per case for its LTD histories, then one ROM task per case; ``[aeroelastic]`` and
``[nonlinear]`` add theirs after the steady flow). This module starts each task when the tasks it waits for
have ended (:class:`studies.sections.protocol.Task`: ``after``, ``needs_ok``), skips the tasks whose steady flow
(or other needed piece) failed, and reports progress (:mod:`studies.run.progress`: a line per finished piece, and
from inside the steady, FRF and LTD tasks their Newton steps, sweep shifts and time steps, from the ROM tasks
their sweep points, as lines or as a bar on a terminal); independent tasks run in parallel on an executor of
:mod:`studies.run.executors` (this process, local processes or a Dask cluster).

Resume, failures, force
-----------------------
Every piece goes through the content-addressed store, so an interrupted study resumes where it stopped and
a second run computes nothing. Each run's ``run-log.json`` in the output folder lists the pieces it stored (an
interrupted run writes it too, marked ``"interrupted": true``). A piece that raises is stored as a failure (``status = "failed"`` and
``"ExceptionType: message"``) and does not stop the others; a failed steady flow or FRF marks the ROMs
that need it failed (see :mod:`studies.store.results`). Failed pieces are computed again by the next run (they may
have been transient); ``force=True`` recomputes every piece of the study.
"""

from __future__ import annotations

import json
import os
import sys
import time
import warnings
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Optional

from ..config.schema import StudyConfig
from ..config.study import as_config
from ..sections.protocol import active_sections, piece_kinds
from ..store.entries import error_text, open_store
from ..store.files import atomic_write_bytes, probe_writable
from ..store.results import StudyResults, load_results
from .compute import pinned_store
from .executors import RunnerError, make_pool
from .progress import ProgressDisplay, resolve_mode, set_sink

__all__ = ["run_study", "RunSummary", "RunInterrupted", "auto_workers", "RunnerError"]


@dataclass(frozen=True)
class RunSummary:
    """What one :func:`run_study` call did (``StudyResults.run``).

    Attributes
    ----------
    computed : int
        Pieces computed and stored by this run (failures included: they are stored as such).
    failed_pieces : int
        Of those, the pieces that failed.
    task_failures : tuple of dict
        Tasks that failed outside their pieces, so that nothing of theirs was stored: ``kind``, ``case``,
        ``error``, and ``write`` (True for an ``OSError``: the store could not be written).
    seconds : float
        Wall time of the run.
    """

    computed: int
    failed_pieces: int
    task_failures: tuple = ()
    seconds: float = 0.0

    @property
    def write_failures(self) -> int:
        """Tasks whose results could not be written."""
        return sum(bool(t.get("write")) for t in self.task_failures)


class RunInterrupted(KeyboardInterrupt):
    """The run was interrupted (Ctrl-C): every piece stored so far is kept; the same command resumes.

    Attributes
    ----------
    computed : int
        Pieces this run had stored before the interruption.
    store_dir : Path
    """

    def __init__(self, computed: int, store_dir):
        self.computed = int(computed)
        self.store_dir = Path(store_dir)
        super().__init__(f"interrupted after {self.computed} piece(s) stored in {self.store_dir} (and any the "
                         "interrupted tasks had stored); they are kept, and running the same command again resumes "
                         "from them")

    def __str__(self) -> str:
        return str(self.args[0]) if self.args else "interrupted"


def auto_workers(config: StudyConfig, cpus: Optional[int] = None) -> int:
    """Worker processes for ``workers="auto"``: the study's widest stage, at most the CPU count.

    The widest stage is the CFD one: for each case one task per sampling period ``T`` (its LFD sweep) and
    one for its gusts (a single LTD march), at least one per case. Each worker gets one BLAS thread
    (:data:`studies.executors.BLAS_THREADS`, whatever the worker count). Memory: a worker on the paper grid
    (181 x 60) holds about 1.5 GB at its peak (the fast sweep's basis and one factorisation).

    Parameters
    ----------
    config : StudyConfig
    cpus : int, optional
        Default ``os.cpu_count()``.

    Returns
    -------
    int
    """
    cpus = cpus if cpus is not None else (os.cpu_count() or 1)
    return max(1, min(int(cpus), _width(config)))


def _width(config: StudyConfig) -> int:
    """Parallel tasks of the study's widest stage: the sum of its sections' (:meth:`Section.width`; the gust-ROM
    section: per case, one per ``T`` and one for its gusts)."""
    return sum(section.width(config) for section in active_sections(config))


# ---------------------------------------------------------------------------------------------
# Progress
# ---------------------------------------------------------------------------------------------

@dataclass
class _Progress:
    """Counts and prints the pieces of a run as they finish; keeps their reports for the run log."""

    display: ProgressDisplay
    total: int
    t0: float = field(default_factory=time.perf_counter)
    done: int = 0
    failed: int = 0
    log: list = field(default_factory=list)

    def __post_init__(self):
        self.display.counts(self.done, self.total)

    def say(self, text: str):
        self.display.say(text)

    def piece(self, report: dict):
        self.done += 1
        self.display.counts(self.done, self.total)
        self.log.append(report)
        bad = report["status"] == "failed"
        self.failed += bad
        tail = (f" FAILED: {report['error']}" if bad else
                f" STOPPED (a result, not retried): {report['error']}" if report["status"] == "stopped" else "")
        self.say(f"{report['label']}: {report['seconds']:.2f} s ({self.done}/{self.total} pieces, {self.failed} failed)"
                 f"{tail}")


# ---------------------------------------------------------------------------------------------
# The runner
# ---------------------------------------------------------------------------------------------

def run_study(study, *, output_dir=None, store_dir=None, scheduler: Optional[str] = None,
              workers=None, progress=True, force: bool = False, progress_interval: float = 10.0) -> StudyResults:
    """Compute every piece of a study that the results store lacks, then read the results back.

    Parameters
    ----------
    study : StudyConfig or path-like
        A validated study, or the path of a TOML study file (validated first).
    output_dir : path-like, optional
        Overrides the study's output folder (a run log ``run-log.json`` is written there).
    store_dir : path-like, optional
        Overrides the study's results store.
    scheduler : str, optional
        ``"tcp://host:port"`` of a Dask scheduler, or ``"local"`` for a Dask LocalCluster of ``workers``
        processes. Default: no Dask.
    workers : int or "auto", optional
        Local worker processes (default 1: everything in this process). Tasks are parallel over cases and
        FRFs (a case's gusts are marched together, beside its FRFs). ``"auto"`` (the command line's default):
        :func:`auto_workers`.
    progress : bool or {"auto", "bar", "lines", "pieces", "off"}
        What to print while running (:mod:`studies.run.progress`): one line per finished piece (elapsed time, piece
        time, counts) in every mode but ``"off"``, and the progress of the running steady, FRF and LTD tasks
        (Newton steps, sweep shifts, time steps): ``"lines"`` as indented lines (at most one per task every
        ``progress_interval`` seconds), ``"bar"`` as a status line redrawn on stderr, ``"pieces"`` not at all.
        ``True`` is ``"auto"``: the bar when stderr is a terminal (and the ``CI`` variable is unset), else lines;
        ``False`` is ``"off"``. Local worker processes send their progress back to this process; Dask workers
        send none.
    force : bool
        Recompute every piece even when stored.
    progress_interval : float
        Seconds between two progress lines of the same task in mode ``"lines"``.

    Returns
    -------
    StudyResults
        :func:`studies.store.results.load_results` after the run.

    Raises
    ------
    StudyConfigError
        Invalid study file.
    RunnerError
        Bad ``workers`` or ``scheduler``; Dask requested but not installed.
    TypeError
        ``study`` is neither a StudyConfig nor a path.
    ValueError
        An unknown ``progress`` mode.
    studies.store.files.NotWritableError
        The results store cannot be written (checked before anything is computed; a ``PermissionError``).
    """
    mode = resolve_mode(progress)
    config = as_config(study)
    changes = {}
    if output_dir is not None:
        changes["output_dir"] = Path(output_dir).resolve()
    if store_dir is not None:
        changes["store_dir"] = Path(store_dir).resolve()
    if changes:
        config = replace(config, **changes)
    # the store is written as each piece is computed: an unwritable one would lose every piece (it failed late and
    # reported "0 failed"); the command line probes the same way (exit 4)
    probe_writable(config.store_dir, what="results store", fix="give store_dir= a folder you may write")
    if workers == "auto":
        workers = auto_workers(config)
    elif scheduler in (None, "local") and isinstance(workers, int) and not isinstance(workers, bool) and workers > 1:
        cap = auto_workers(config)
        if workers > cap:
            warnings.warn(f"workers = {workers} is more than this study can use (its widest stage has "
                          f"{_width(config)} parallel task(s); {os.cpu_count() or 1} CPU(s)): using {cap}",
                          RuntimeWarning, stacklevel=2)
            workers = cap
    display = ProgressDisplay(mode, interval=progress_interval)
    pool = make_pool(scheduler, workers, progress=display.sink)
    state: dict = {}
    previous = set_sink(display.sink)  # the tasks run in this process (workers = 1) report to the display
    try:
        try:
            results = _run(config, pool, display, bool(force), state)
        except KeyboardInterrupt:
            pool.close(abort=True)
            raise RunInterrupted(state.get("computed", 0), config.store_dir) from None
        pool.close()
    finally:
        set_sink(previous)
        display.close()
    return results


#: What a task lost with its worker process is told (a BrokenProcessPool says nothing of the cause).
LOST_WORKER = ("a worker process died (killed, e.g. out of memory) and the pool with it; what is stored is kept, "
               "run again to compute the rest: ")


def _ordered(config: StudyConfig, tasks: list) -> list:
    """The tasks in the order they start when ready together: by case (the study's order), priority, plan order."""
    position = {case_sweep.case.name: i for i, case_sweep in enumerate(config.cases)}
    return sorted(tasks, key=lambda task: (position.get(task.case, len(position)), task.priority))


def _run(config: StudyConfig, pool, display: ProgressDisplay, force: bool, state: dict) -> StudyResults:
    root = str(config.store_dir)
    base = open_store(config)
    codes = {p: base.code_version(p) for p in piece_kinds()}
    store = pinned_store(root, codes)

    # what is needed: each section's plan (studies.sections.protocol)
    sections = active_sections(config)
    plans = [section.plan(config, store, force) for section in sections]
    n_cfd = sum(plan.cfd_pieces for plan in plans)
    n_id = sum(plan.rom_pieces for plan in plans)  # upper bounds known now; pieces of failed CFD are skipped
    tasks = _ordered(config, [task for plan in plans for task in plan.tasks])
    tracker = _Progress(display, n_cfd + n_id)
    tracker.say(f"study {config.name!r}: {len(config.cases)} case(s), {len(config.points())} sweep point(s), "
                f"{len(config.gusts)} gust(s); to compute: {n_cfd} CFD piece(s), up to {n_id} ROM piece(s) "
                f"[{pool.name}; store {root}]")

    pending = {}  # future -> index of its task
    task_failures: list = []  # tasks that failed outside their pieces (their pieces were not stored)
    status = ["waiting"] * len(tasks)  # waiting, running, ok, failed, skipped
    named: dict = {}  # task name -> indices of the tasks that carry it
    for i, task in enumerate(tasks):
        for name in task.ids:
            named.setdefault(name, []).append(i)

    def fail_task(task, e):
        text = (LOST_WORKER if isinstance(e, BrokenProcessPool) else "") + error_text(e)
        tracker.say(f"{task.kind} task of {task.case} failed: {text}")
        task_failures.append(dict(kind=task.kind, case=task.case, error=text, write=isinstance(e, OSError)))

    def submit(i) -> bool:
        task = tasks[i]
        try:
            pending[pool.submit(task.fn, *task.args)] = i
            return True
        except BrokenProcessPool as e:  # a worker died before: this task cannot start, the others still end
            display.task_done(task.progress_key)
            fail_task(task, e)
            return False

    def readiness(task):
        """None: wait; False: skip (a task it needs did not end ok); True: start."""
        for name in task.after + task.needs_ok:
            if any(status[j] in ("waiting", "running") for j in named.get(name, ())):
                return None
        for name in task.needs_ok:
            if any(status[j] != "ok" for j in named.get(name, ())):
                return False
        return True

    def start_ready():
        changed = True
        while changed:
            changed = False
            for i, task in enumerate(tasks):
                if status[i] != "waiting":
                    continue
                ready = readiness(task)
                if ready is None:
                    continue
                changed = True
                status[i] = "skipped" if ready is False else ("running" if submit(i) else "failed")

    try:
        start_ready()
        while pending:
            done, _ = pool.wait(set(pending))
            for future in done:
                i = pending.pop(future)
                task = tasks[i]
                display.task_done(task.progress_key)
                try:
                    reports = future.result()
                except Exception as e:  # noqa: BLE001 - a task that failed outside its pieces (e.g. the store)
                    fail_task(task, e)
                    reports = []
                for report in reports:
                    tracker.piece(report)
                state["computed"] = tracker.done
                ok = bool(reports) and reports[0]["status"] == "ok"
                status[i] = "ok" if ok else "failed"
                if not ok and task.failure_note:
                    tracker.say(task.failure_note)
            start_ready()
    except KeyboardInterrupt:
        # tasks that ended but were not handed back yet (with one process every task runs inside submit, so
        # an interruption can leave finished ones behind) stored their pieces too: count them for the message
        ended = [f for f in pending if f.done() and not f.cancelled() and f.exception() is None]
        late = [report for f in ended for report in f.result()]
        state["computed"] = tracker.done + len(late)
        tracker.log.extend(late)
        _write_log(config, tracker, time.perf_counter() - tracker.t0, interrupted=True)
        raise

    elapsed = time.perf_counter() - tracker.t0
    results = load_results(config, store_dir=config.store_dir)
    said = [text for text in (section.summary(config, results) for section in sections) if text]
    tracker.say(f"done in {elapsed:.1f} s: {tracker.done} piece(s) computed ({tracker.failed} failed); "
                + "".join(f"{text}, " for text in said) + f"{len(results.missing)} piece(s) missing")
    _write_log(config, tracker, elapsed)
    summary = RunSummary(computed=tracker.done, failed_pieces=tracker.failed,
                         task_failures=tuple(task_failures), seconds=elapsed)
    return replace(results, run=summary)


def _write_log(config: StudyConfig, tracker: _Progress, elapsed: float, *, interrupted: bool = False) -> None:
    """``run-log.json`` in the output folder: the pieces this run computed, with their times.

    Parameters
    ----------
    config : StudyConfig
    tracker : _Progress
        The run's reports of the pieces stored (``tracker.log``).
    elapsed : float
        Wall time of the run, to its end or its interruption.
    interrupted : bool
        The run was interrupted (Ctrl-C): the log has ``"interrupted": true`` and lists the pieces stored until
        then (those of the tasks still running when it came are not).
    """
    by_piece: dict = {}
    for report in tracker.log:
        totals = by_piece.setdefault(report["piece"], {"count": 0, "failed": 0, "seconds": 0.0})
        totals["count"] += 1
        totals["failed"] += report["status"] == "failed"
        totals["seconds"] += report["seconds"]
    doc = {"study": config.name, "wall_s": elapsed, "totals": by_piece, "pieces": tracker.log,
           "finished_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())}
    if interrupted:
        doc["interrupted"] = True
    try:
        atomic_write_bytes(Path(config.output_dir) / "run-log.json", json.dumps(doc, indent=1).encode())
    except OSError as e:  # the log is a convenience; the results are in the store
        print(f"lfdrom: warning: cannot write the run log: {e}", file=sys.stderr)
