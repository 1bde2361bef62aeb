"""Worker processes that factorise several sweep shifts side by side (:mod:`cfd.sweep`).

SciPy's SuperLU runs on one core. Two shifts factorised and back-substituted in two threads of one process
took 13.4 - 14.4 s on the paper grid where one after the other took 9.9 s; in two forked processes 5.1 s
(measured on 2026-12-03 on the 2-core machine, T2, 16 blocks per shift). So the workers are processes,
forked from the process that owns the linear system: they inherit it (and its ordering) without pickling
it, and send back only the Krylov blocks (a few tens of MB per shift).

Forking needs the ``fork`` start method (Linux, and macOS where Python allows it) and a process that may
have children: inside a daemonic process (a worker of the study runner's process pool) :func:`shift_workers`
returns None and the shifts run one after the other, which is also right there, since the study's workers
already keep the cores busy.
"""

import logging
import multiprocessing as mp
import os
from concurrent.futures import ProcessPoolExecutor

from threadpoolctl import threadpool_limits

from ..linear import LinearError
from .basis import shift_blocks

__all__ = ["ShiftWorkers", "shift_workers", "can_fork_workers"]

log = logging.getLogger("cfd.sweep")

_SHARED = {}   # token -> (lin, perm, rows), set before the workers fork, read in them


def _one_blas_thread():
    """Worker initialiser: one BLAS thread per process (SuperLU's dense kernels call BLAS; with two
    threads in each of two processes on two cores the factorisations took 24 s instead of 3 s on the paper
    grid, measured on 2026-12-03)."""
    threadpool_limits(1)


def _run(token, omega, n_moments):
    lin, perm, rows = _SHARED[token]
    return shift_blocks(lin, perm, rows, omega, n_moments)


def can_fork_workers():
    """Whether this process can fork worker processes (the ``fork`` start method, not a daemonic process).

    Returns
    -------
    bool
    """
    return "fork" in mp.get_all_start_methods() and not mp.current_process().daemon


class ShiftWorkers:
    """A pool of forked processes computing :func:`cfd.sweep.basis.shift_blocks` for one basis.

    Use as a context manager (the processes end on exit), or call :meth:`close`.

    Parameters
    ----------
    basis : SweepBasis
    workers : int
        Number of processes, ``>= 2``.
    """

    def __init__(self, basis, workers):
        if int(workers) != workers or workers < 2:
            raise LinearError(f"ShiftWorkers needs workers >= 2 (processes); got {workers!r}")
        if not can_fork_workers():
            raise LinearError("worker processes need the 'fork' start method and a non-daemonic process; "
                              "use workers=1 here")
        self.workers = int(workers)
        self._token = f"{os.getpid()}-{id(basis)}"
        _SHARED[self._token] = (basis.lin, basis.ordering, basis.rows)
        self._pool = ProcessPoolExecutor(self.workers, mp_context=mp.get_context("fork"),
                                         initializer=_one_blas_thread)

    def shift_blocks(self, omegas, n_moments):
        """``shift_blocks`` for every shift, side by side; results in the order of ``omegas``.

        Parameters
        ----------
        omegas : sequence of float
        n_moments : sequence of int

        Returns
        -------
        list of tuple
            As :func:`cfd.sweep.basis.shift_blocks`.
        """
        futures = [self._pool.submit(_run, self._token, w, k) for w, k in zip(omegas, n_moments)]
        return [f.result() for f in futures]

    def close(self):
        self._pool.shutdown(wait=True, cancel_futures=True)
        _SHARED.pop(self._token, None)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def shift_workers(basis, workers):
    """Worker processes for ``basis`` if ``workers > 1`` and this process can fork them, else None.

    Parameters
    ----------
    basis : SweepBasis
    workers : int

    Returns
    -------
    ShiftWorkers or None
    """
    if workers <= 1:
        return None
    if not can_fork_workers():
        log.info("fast sweep: worker processes cannot be forked here (daemonic process or no 'fork'); "
                 "the shifts run one after the other")
        return None
    return ShiftWorkers(basis, workers)
