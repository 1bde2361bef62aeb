"""Executors of a study run's tasks: this process, local worker processes, or a Dask cluster.

Each pool has ``name`` (for the progress line), ``submit(fn, *args)`` -> future, ``wait(pending)`` ->
``(done, rest)`` and ``close(abort=False)``. :func:`make_pool` picks one:

- this process (``workers=1``, the default: the machine this was written on has two cores shared);
- local processes (``workers=N > 1``, :class:`concurrent.futures.ProcessPoolExecutor`), each ending when the
  process that started it ends; with ``progress`` (a
  callable of the main process) the workers' progress events (:mod:`studies.run.progress`) come back on a
  ``multiprocessing`` queue, drained by ``wait`` every :data:`PROGRESS_POLL_S` seconds (no thread) and by
  ``close`` while the workers finish;
- a Dask cluster (``scheduler="tcp://host:port"``, or ``"local"`` for a :class:`distributed.LocalCluster`
  of ``workers`` processes); the store folder must then be on a file system the workers share.

Every task runs with :data:`BLAS_THREADS` BLAS threads (``threadpoolctl``), whichever pool runs it, a lone
worker included: a BLAS reduction split over another number of threads adds in another order, and the stored
results then differ in the last bits with the worker count (5e-9 relative on the paper study's ROMs when this
process used two threads and the workers one each), so that a store resumed with other ``--workers`` would
mix the two. With the threads pinned, a study's results are bit-for-bit the same for any worker count on one
machine (``tests/studies/test_reliability.py::test_results_do_not_depend_on_the_worker_count``).
"""

from __future__ import annotations

import os
import sys
import threading
import time
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor
from concurrent.futures import wait as cf_wait
from typing import Optional

__all__ = ["InlinePool", "ProcessPool", "DaskPool", "make_pool", "check_scheduler", "RunnerError", "PARENT_POLL_S",
           "PROGRESS_POLL_S", "BLAS_THREADS", "pinned_call"]


class RunnerError(ValueError):
    """Bad runner options (workers, scheduler), or Dask asked for but not installed."""


BLAS_THREADS = 1
"""BLAS threads of every task, in every pool (module docstring). One: the runner's parallelism is its worker
processes (one BLAS thread per worker was also the fastest on two cores, :class:`ProcessPool`)."""


def pinned_call(fn, *args):
    """``fn(*args)`` with at most :data:`BLAS_THREADS` BLAS threads in this process (restored afterwards),
    starting from an empty cache of compiled refit problems (:func:`sysid.refit_solvers.clear_refit_cache`).

    The cache matters for reproducibility as the threads do: a refit solved by a problem compiled in this call
    and one re-solved from the cache agree only to round-off, so that a task's results depended on what its
    process had identified before (the tiny study's ROM metrics 1.1e-12 relative apart between the first run in
    a process and a second one, measured 2026-12-03); from an empty cache every task computes the same way in
    any process.
    """
    from threadpoolctl import threadpool_limits

    from sysid.refit_solvers import clear_refit_cache

    clear_refit_cache()
    with threadpool_limits(limits=BLAS_THREADS, user_api="blas"):
        return fn(*args)


class InlinePool:
    """Runs each task at once in this process (``workers=1``), with :data:`BLAS_THREADS` BLAS threads as a
    worker process has; futures are already done."""

    name = f"this process ({BLAS_THREADS} BLAS thread{'s' if BLAS_THREADS > 1 else ''})"

    def submit(self, fn, *args):
        """Run ``fn(*args)`` now; return a future that holds its result or its exception."""
        f: Future = Future()
        try:
            f.set_result(pinned_call(fn, *args))
        except Exception as e:  # noqa: BLE001 - reported by the caller; KeyboardInterrupt propagates
            f.set_exception(e)
        return f

    @staticmethod
    def wait(pending):
        return set(pending), set()

    def close(self, abort: bool = False):
        pass


def _limit_blas_threads(n: int) -> None:
    """At most ``n`` BLAS threads in this process (``threadpoolctl``)."""
    from threadpoolctl import threadpool_limits

    threadpool_limits(limits=n, user_api="blas")


PARENT_POLL_S = 1.0
"""How often a worker process checks that the process that started it is still alive (seconds)."""


def _exit_with_parent(parent_pid: int) -> None:
    """Make this worker process end when ``parent_pid`` ends, however it ends (``kill -9`` included).

    Linux: ``prctl(PR_SET_PDEATHSIG, SIGKILL)``, immediate. Everywhere: a daemon thread that polls the parent
    pid every :data:`PARENT_POLL_S` seconds (a worker blocked on the task pipe would otherwise wait forever,
    reparented). Both end the worker at once: it holds no results of its own (every piece is written to the
    store atomically before its task returns).
    """
    import signal

    if sys.platform.startswith("linux"):
        try:
            import ctypes

            ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG = 1
        except (OSError, AttributeError):  # pragma: no cover - other libc
            pass
    if os.getppid() != parent_pid:  # the parent died before the hook was set
        os._exit(1)

    def watch():
        while True:
            time.sleep(PARENT_POLL_S)
            if os.getppid() != parent_pid:
                os._exit(1)

    threading.Thread(target=watch, name="lfdrom-parent-watch", daemon=True).start()


PROGRESS_POLL_S = 0.25
"""How often the main process drains the workers' progress events while it waits for tasks (seconds)."""


def _init_worker(threads: int, parent_pid: int, queue=None) -> None:
    """Worker initializer: BLAS threads, Ctrl-C left to the parent (which stops the workers), exit with it,
    progress events onto ``queue`` (none without one; a forked worker must not use the parent's sink)."""
    import signal

    from .progress import set_sink

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    _exit_with_parent(parent_pid)
    _limit_blas_threads(threads)
    if queue is not None:  # a SimpleQueue: put writes to the pipe at once (no feeder thread whose buffered
        # events a worker's exit could drop: a test once lost every event of a short task), blocking only while
        # the pipe is full, which the parent drains
        set_sink(queue.put)
    else:
        set_sink(None)


ABORT_JOIN_S = 5.0
"""Seconds an aborted worker gets to end after SIGTERM before it is killed."""


class ProcessPool:
    """Local worker processes, each limited to :data:`BLAS_THREADS` BLAS threads.

    Without the limit every worker's BLAS starts one thread per core: on two cores the demo's fast LFD sweep
    (dense Gram-Schmidt) and its LTD march (block solves) beside it took 262 s and 129 s and the study 341 s;
    with one BLAS thread per worker 176 s and 98 s, the study 263 s (measured one after the other, same
    machine, empty store each time). The limit was ``cores // workers`` until it became one for every pool,
    so that results do not depend on the worker count (module docstring).
    """

    def __init__(self, workers: int, progress=None):
        import multiprocessing

        ctx = multiprocessing.get_context("fork") if "fork" in multiprocessing.get_all_start_methods() else None
        threads = BLAS_THREADS
        self.progress = progress
        self.queue = None if progress is None else (ctx or multiprocessing).SimpleQueue()
        self.ex = ProcessPoolExecutor(max_workers=workers, mp_context=ctx, initializer=_init_worker,
                                      initargs=(threads, os.getpid(), self.queue))
        self.name = f"{workers} local processes ({threads} BLAS thread{'s' if threads > 1 else ''} each)"

    def submit(self, fn, *args):
        return self.ex.submit(pinned_call, fn, *args)

    def wait(self, pending):
        """Wait for a task to finish; meanwhile pass the workers' progress events to ``progress``."""
        while True:
            done, rest = cf_wait(pending, timeout=None if self.queue is None else PROGRESS_POLL_S,
                                 return_when=FIRST_COMPLETED)
            self._drain()
            if done:
                return done, rest

    def _drain(self):
        """Hand every queued progress event to ``progress`` (a failing display never stops the run)."""
        if self.queue is None:
            return
        while True:
            try:
                if self.queue.empty():
                    return
                event = self.queue.get()
            except (OSError, ValueError, EOFError):
                return
            try:
                self.progress(event)
            except Exception:  # noqa: BLE001 - progress output is never worth a failed run
                pass

    def close(self, abort: bool = False):
        """Wait for the running tasks, or (``abort``) stop the workers at once (what they stored is kept)."""
        if abort:
            procs = list((getattr(self.ex, "_processes", None) or {}).values())
            for proc in procs:
                proc.terminate()
            for proc in procs:
                proc.join(ABORT_JOIN_S)
                if proc.is_alive():
                    proc.kill()
            # wait=True joins the executor's manager thread (quick: its workers are gone), which closes its wake-up
            # pipe; left running (wait=False), on Python 3.11 it could close that pipe while the interpreter's exit
            # hook was writing to it: "OSError: [Errno 9] Bad file descriptor" printed after Ctrl-C (seen once in
            # tests/studies/run/test_reliability.py::test_ctrl_c_on_lfdrom_run on 2026-12-03)
            self.ex.shutdown(wait=True, cancel_futures=True)
            self._close_queue()
            return
        if self.queue is None:
            self.ex.shutdown(wait=True, cancel_futures=True)
            return
        # drained meanwhile: a worker still running blocks on a full pipe (the main thread waits in shutdown)
        done = threading.Event()

        def drain_until_done():
            while not done.wait(PROGRESS_POLL_S):
                self._drain()

        drainer = threading.Thread(target=drain_until_done, name="lfdrom-progress-drain", daemon=True)
        drainer.start()
        try:
            self.ex.shutdown(wait=True, cancel_futures=True)
        finally:
            done.set()
            drainer.join()
        self._drain()  # events a worker queued just before its last result (the result's pipe can overtake them)
        self._close_queue()

    def _close_queue(self):
        if self.queue is not None:
            self.queue.close()
            self.queue = None


class DaskPool:
    """Tasks on a Dask cluster: a scheduler's address, or a LocalCluster of ``workers`` processes."""

    def __init__(self, scheduler: str, workers: Optional[int]):
        try:
            from distributed import Client, LocalCluster
        except ImportError:
            raise RunnerError(f"scheduler={scheduler!r} needs Dask distributed; install it with "
                              "pip install 'lfdrom[dask]' (or pip install 'dask[distributed]')") from None
        self.cluster = None
        if scheduler == "local":
            n = workers or 1
            self.cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None)
            self.client = Client(self.cluster)
            self.name = f"Dask LocalCluster of {n} process(es)"
        else:
            try:
                self.client = Client(scheduler, timeout="10s")
            except (OSError, TimeoutError) as e:
                raise RunnerError(f"scheduler {scheduler!r}: cannot connect ({e}); check the address (the Dask "
                                  "scheduler must be running) or leave --scheduler out for local processes") from None
            self.name = f"Dask scheduler {scheduler}"

    def submit(self, fn, *args):
        return self.client.submit(pinned_call, fn, *args, pure=False)

    @staticmethod
    def wait(pending):
        from distributed import wait

        done, rest = wait(list(pending), return_when="FIRST_COMPLETED")
        return set(done), set(rest)

    def close(self, abort: bool = False):
        self.client.close()
        if self.cluster is not None:
            self.cluster.close()




def check_scheduler(scheduler: Optional[str]) -> Optional[str]:
    """``scheduler`` if it is None, ``"local"`` or an address with a scheme (``tcp://host:8786``), else
    :class:`RunnerError` (checked before anything runs, ``--dry-run`` included; reachability is not)."""
    if scheduler is not None and (not isinstance(scheduler, str) or not (scheduler == "local" or "://" in scheduler)):
        raise RunnerError(f"scheduler must be a Dask address such as 'tcp://host:8786' or 'local', got {scheduler!r}")
    return scheduler


def make_pool(scheduler: Optional[str], workers: Optional[int], progress=None):
    """The pool for a run's options (see the module docstring).

    Parameters
    ----------
    scheduler : str or None
        A Dask scheduler's address (``"tcp://host:port"``) or ``"local"``; None: no Dask.
    workers : int or None
        Worker processes; None or 1: this process.
    progress : callable, optional
        Local processes: receives the workers' progress events in this process (:mod:`studies.run.progress`).
        This process's own tasks send theirs to ``studies.run.progress.set_sink``'s sink; Dask workers send none.

    Returns
    -------
    InlinePool, ProcessPool or DaskPool

    Raises
    ------
    RunnerError
        Bad ``workers`` or ``scheduler``; Dask asked for but not installed, or its scheduler unreachable.
    """
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise RunnerError(f"workers must be a positive integer, got {workers!r}")
    if scheduler is not None:
        return DaskPool(check_scheduler(scheduler), workers)
    if workers is None or workers == 1:
        return InlinePool()
    return ProcessPool(workers, progress=progress)
