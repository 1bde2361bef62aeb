"""The study runner: a validated study in, every missing piece computed into the results store, results out.

Pipeline of a case (``studies.config`` names the pieces, ``studies.cache`` keys and stores them)::

    mesh -> steady ------------------> linearise -> LFD FRF per T on mckelvey_grid(M_base, T)
                                                 \\-> LTD history per gust (x0, dt, t_end of the study)
    FRF -> subsample to each M -> identify (order, method variant) -> ROM
    ROM -> d2c (Eq. 26) -> Tustin or ZOH at the LTD step -> simulation per gust -> vs LTD

Tasks and executors
-------------------
The work is split into tasks that each compute and store pieces: one ``steady`` task per case, then (once
its steady flow is stored) one task per FRF (case, T) and per LTD history (case, gust), then one ROM task
per case (every identification and ROM simulation of that case, cheap next to the CFD). A CFD task rebuilds
the linear system from the stored steady state (a converged restart: one residual evaluation and a
linearisation, a few seconds on the paper grid), so the large Jacobians are never stored nor shipped
between processes. Independent tasks run in parallel on

- this process (``workers=1``, the default: the machine this was written on has two cores shared);
- local processes (``workers=N > 1``, :class:`concurrent.futures.ProcessPoolExecutor`);
- a Dask cluster (``scheduler="tcp://host:port"``, or ``"local"`` for a :class:`distributed.LocalCluster`
  of ``workers`` processes); the store folder must then be on a file system the workers share.

Resume, failures, force
-----------------------
Every piece goes through the content-addressed store, so an interrupted study resumes where it stopped and
a second run computes nothing. A piece that raises is stored as a failure (``status = "failed"`` and
``"ExceptionType: message"``) and does not stop the others; a failed steady flow or FRF marks the ROMs
that need it failed (see :mod:`studies.results`). Failed pieces are computed again by the next run (they may
have been transient); ``force=True`` recomputes every piece of the study.
"""

from __future__ import annotations

import json
import math
import os
import sys
import time
import warnings
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor
from concurrent.futures import wait as cf_wait
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Callable, Optional

import numpy as np

from .cache import ResultStore
from .config import StudyConfig, frf_piece, load_study, ltd_piece, rom_piece, sim_piece, steady_piece
from .results import (
    StudyResults,
    error_text,
    failure_payload,
    frf_payload,
    is_failed,
    load_results,
    ltd_payload,
    open_store,
    rom_metrics,
    rom_payload,
    sim_metrics,
    sim_payload,
    steady_payload,
    store_dependencies,
)

__all__ = ["run_study", "RunSummary", "RunInterrupted", "auto_workers", "rom_simulation", "simulate_discrete", "markov_parameters", "RunnerError", "PIECES"]

PIECES = ("steady", "frf", "ltd", "rom", "sim")


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
        super().__init__(f"interrupted after {self.computed} piece(s) stored in {self.store_dir}; they are kept, "
                         "and running the same command again resumes from them")

    def __str__(self) -> str:
        return str(self.args[0]) if self.args else "interrupted"


class RunnerError(ValueError):
    """Bad runner options (workers, scheduler), or Dask asked for but not installed."""


# ---------------------------------------------------------------------------------------------
# Store with the code versions pinned by the main process (workers compute the same keys)
# ---------------------------------------------------------------------------------------------

class _PinnedStore(ResultStore):
    """A :class:`ResultStore` whose per-piece code versions are fixed (computed once, in the main process).

    The sources' hash is computed once per process; pinning it keeps the keys of a run consistent across
    worker processes even if a source file changes while the study runs.
    """

    def __init__(self, root, codes: dict):
        super().__init__(root, dependencies=store_dependencies())
        self._codes = dict(codes)

    def code_version(self, piece: str) -> dict:
        return dict(self._codes[piece]) if piece in self._codes else super().code_version(piece)


def _store(root, codes) -> ResultStore:
    return _PinnedStore(root, codes)


# ---------------------------------------------------------------------------------------------
# CFD helpers
# ---------------------------------------------------------------------------------------------

def _grid(case):
    import cfd

    return cfd.c_grid(cfd.naca(case.naca), **case.grid.kwargs())


def _steady(case):
    """Steady solution of a case from the free stream."""
    import cfd

    return cfd.solve_steady(_grid(case), case.mach, case.alpha_deg)


def _linear_system(case, q):
    """The linear system about a stored steady state (a converged restart, then ``cfd.linearise``)."""
    import cfd

    sol = cfd.solve_steady(_grid(case), case.mach, case.alpha_deg, q0=q)
    return cfd.linearise(sol)


def _lfd(lin, T, M, cfd_opts):
    """LFD response on ``sysid.mckelvey_grid(M, T)``; returns ``(frf, method)``."""
    import sysid
    from cfd.lfd import lfd_response

    grid = sysid.mckelvey_grid(M, T)
    frf = lfd_response(lin, grid, gust=cfd_opts.gust_method, outputs=tuple(cfd_opts.outputs), method="auto")
    used = frf.metadata.get("method")
    if used not in ("direct", "fast"):  # cfd.lfd_response records the path it took; older stores may lack it
        used = "fast" if int(np.sum(np.isfinite(grid[1]))) > 8 else "direct"
    if frf.T is None or not math.isclose(frf.T, T, rel_tol=1e-9):
        frf = frf.with_T(T)
    return frf, used


def _gust(gust_case, x0):
    from .cases import to_gust

    return to_gust(gust_case, x0=x0)


def _ltds(lin, gust_cases, sim, cfd_opts):
    """The LTD histories of several gusts of one case, marched together (one factorisation)."""
    import cfd

    return cfd.ltd_responses(lin, [_gust(g, sim.x0) for g in gust_cases], sim.dt, sim.t_end,
                             method=cfd_opts.gust_method)


# ---------------------------------------------------------------------------------------------
# Tasks (top-level functions: picklable for process pools and Dask)
# ---------------------------------------------------------------------------------------------

def _report(piece, label, entry, seconds, computed=True) -> dict:
    md = entry.metadata if entry is not None else {}
    return dict(piece=piece, label=label, status=md.get("status", "ok"), error=md.get("error"),
                seconds=float(seconds), computed=computed)


def _compute_piece(store, piece, cfg, compute: Callable[[], tuple], catch=True):
    """Compute a piece and store it (a failure is stored as such). Returns ``(entry, seconds)``."""
    t0 = time.perf_counter()
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            arrays, metadata = compute()
        notes = sorted({f"{w.category.__name__}: {w.message}"[:500] for w in caught})
        if notes:
            metadata = dict(metadata, warnings=notes)
    except Exception as e:  # noqa: BLE001 - any failure of a piece is recorded and the study goes on
        if not catch:
            raise
        arrays, metadata = failure_payload(e)
    seconds = time.perf_counter() - t0
    entry = store.put(piece, cfg, arrays, metadata, extra_provenance={"compute_s": seconds})
    return entry, seconds


def _task_steady(config: StudyConfig, case_name: str, root: str, codes: dict) -> list:
    store = _store(root, codes)
    case = config.case(case_name).case

    def compute():
        t0 = time.perf_counter()
        sol = _steady(case)
        return steady_payload(sol, time.perf_counter() - t0)

    entry, s = _compute_piece(store, "steady", steady_piece(case), compute)
    return [_report("steady", f"steady {case.name}", entry, s)]


def _load_lin(store, case):
    e = store.get("steady", steady_piece(case))
    if e is None or is_failed(e):
        why = "missing" if e is None else e.metadata.get("error")
        raise RuntimeError(f"the steady flow of {case.name} is not available ({why})")
    return _linear_system(case, e["q"])


def _task_frf(config: StudyConfig, case_name: str, T: float, root: str, codes: dict) -> list:
    store = _store(root, codes)
    case = config.case(case_name).case
    state = {}

    def compute():
        lin = _load_lin(store, case)
        t0 = time.perf_counter()
        frf, used = _lfd(lin, T, config.M_base, config.cfd)
        seconds = time.perf_counter() - t0
        state["method"] = used
        return frf_payload(frf, config.M_base, used, seconds)

    entry, s = _compute_piece(store, "frf", frf_piece(case, T, config.M_base, config.cfd), compute)
    label = f"frf {case.name} T={T:.6g} ({config.M_base + 1} frequencies, {state.get('method', '-')})"
    return [_report("frf", label, entry, s)]


def _task_ltd(config: StudyConfig, case_name: str, gust_names: list, root: str, codes: dict) -> list:
    """The LTD histories of one case for the gusts ``gust_names``, marched together, one piece per gust.

    Each piece records its share of the march (``seconds``: the march's wall time over the number of gusts)
    and ``marched_with`` (that number).
    """
    store = _store(root, codes)
    case = config.case(case_name).case
    gusts = [g for g in config.gusts if g.name in gust_names]
    t0 = time.perf_counter()
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            hists = _ltds(_load_lin(store, case), gusts, config.simulation, config.cfd)
        error = None
    except Exception as e:  # noqa: BLE001 - stored as the failure of every piece of the march
        hists, error = [None] * len(gusts), e
    share = (time.perf_counter() - t0) / len(gusts)
    n = int(round(config.simulation.t_end / config.simulation.dt))
    reports = []
    for gust, hist in zip(gusts, hists):
        def compute(hist=hist):
            for w in caught:  # the march's warnings, recorded with every piece by _compute_piece
                warnings.warn(w.message, w.category)
            if error is not None:
                raise error
            arrays, metadata = ltd_payload(hist, share, config.cfd.gust_method)
            return arrays, dict(metadata, marched_with=len(gusts))

        entry, _ = _compute_piece(store, "ltd", ltd_piece(case, gust, config.simulation, config.cfd), compute)
        reports.append(_report("ltd", f"ltd {case.name} {gust.name} ({n} steps, {len(gusts)} gusts marched "
                                      "together)", entry, share))
    return reports


def _needs(store, piece, cfg, force) -> bool:
    if force:
        return True
    e = store.get(piece, cfg)
    return e is None or is_failed(e)


def _identify(frf, point, M_base):
    """Identify one sweep point; returns ``(arrays, metadata)`` of the ROM piece."""
    import sysid

    t0 = time.perf_counter()
    sub = frf if point.M == M_base else frf.subsample(point.M)
    kw = point.method.identify_kwargs(H=sub.H)
    res = sysid.identify(sub, point.order, **kw)
    frf_rom = res.evaluate(frf.omega_d)
    dc_model = res.evaluate(np.array([0.0]))[:, :, 0].real
    seconds = time.perf_counter() - t0
    m = res.model
    metrics = rom_metrics(frf_rom, frf.H, np.arange(0, M_base + 1, M_base // point.M), list(frf.outputs), dc_model,
                          res.spectral_radius, seconds)
    bad = sorted(k for k, v in metrics.items() if isinstance(v, float) and not math.isfinite(v))
    if bad:  # never stored as "ok": a model whose errors are NaN or inf is not a result
        raise FloatingPointError(
            f"the identified model gives non-finite {', '.join(bad)} (T = {point.T:g}, M = {point.M}, order "
            f"{point.order}): its matrices or its frequency response overflowed; check that T suits the data's "
            "frequencies (studies.config.T_RANGE) and lower the order")
    return rom_payload(m.A, m.B, m.C, m.D, res.hankel_sv, frf_rom, metrics, identify_method=res.method,
                       enforced=dict(res.enforced), outputs=list(frf.outputs))


def markov_parameters(A, B, C, N):
    """The first ``N`` Markov parameters ``C A^k B``, ``k = 0 .. N - 1``, by doubling.

    ``[B, AB, ..., A^(2L-1) B] = [X, A^L X]`` with ``X = [B, ..., A^(L-1) B]``: ``log2 N`` matrix products
    instead of ``N`` matrix-vector products in Python.

    Parameters
    ----------
    A, B, C : ndarray, shapes (n, n), (n, m), (p, n)
    N : int

    Returns
    -------
    ndarray, shape (p, m, N)
    """
    A = np.asarray(A, dtype=float)
    B = np.asarray(B, dtype=float)
    C = np.asarray(C, dtype=float)
    n, m = B.shape
    X = B.T.reshape(m, n, 1)  # per input: columns A^k b
    P = A
    while X.shape[2] < N:
        X = np.concatenate([X, np.einsum("ij,mjk->mik", P, X)], axis=2)
        P = P @ P
    return np.einsum("pi,mik->pmk", C, X[:, :, :N])


def simulate_discrete(A, B, C, D, u, method="auto"):
    """Response of ``x[k+1] = A x[k] + B u[k], y[k] = C x[k] + D u[k]`` from rest, as python-control's
    ``forced_response`` gives it.

    ``"convolution"``: ``y = D u + g * u`` with the impulse response ``g[0] = 0``, ``g[k] = C A^(k-1) B``
    (:func:`markov_parameters`) and an FFT convolution: the same numbers to round-off, about 20 times
    faster than the step-by-step recursion of ``control.forced_response`` for 2000 steps. ``"control"``:
    ``control.forced_response``. ``"auto"``: the convolution when ``A`` is stable (spectral radius
    ``< 1``), else python-control (the impulse response of an unstable model grows without bound and its
    FFT would lose the small early values).

    Parameters
    ----------
    A, B, C, D : ndarray, shapes (n, n), (n, m), (p, n), (p, m)
    u : ndarray, shape (N,) or (m, N)
    method : {"auto", "convolution", "control"}

    Returns
    -------
    ndarray, shape (p, N)
    """
    import control
    from scipy.signal import fftconvolve

    A, B, C, D = (np.atleast_2d(np.asarray(x, dtype=float)) for x in (A, B, C, D))
    U = np.atleast_2d(np.asarray(u, dtype=float))
    N = U.shape[1]
    if method not in ("auto", "convolution", "control"):
        raise ValueError(f"method must be 'auto', 'convolution' or 'control', got {method!r}")
    if method == "auto":
        rho = float(np.max(np.abs(np.linalg.eigvals(A)))) if A.size else 0.0
        method = "convolution" if rho < 1.0 else "control"
    if method == "control":
        out = control.forced_response(control.ss(A, B, C, D, True), U=U)
        return np.atleast_2d(np.asarray(out.outputs))
    G = markov_parameters(A, B, C, max(N - 1, 1))  # (p, m, N - 1): g[1:]
    Y = D @ U
    for j in range(U.shape[0]):
        Y[:, 1:] += fftconvolve(G[:, j, :], U[j][None, :], axes=1)[:, :N - 1]
    return Y


def rom_simulation(A, B, C, D, T, t, u, discretisation="tustin", method="auto"):
    """Simulate a discrete ROM (sampling period ``T``) at the time step of ``t``.

    The ROM is mapped to continuous time by the inverse bilinear map (paper Eq. 26) and re-discretised at
    ``dt = t[1] - t[0]`` by Tustin (Eq. 31) or zero-order hold (Eq. 32) (python-control state-space models
    and :mod:`sysid.transforms`), then driven by ``u`` from rest (:func:`simulate_discrete`: an FFT
    convolution with its impulse response, or ``control.forced_response`` for an unstable model).

    Parameters
    ----------
    A, B, C, D : ndarray, shapes (n, n), (n, 1), (p, n), (p, 1)
    T : float
        Sampling period of the ROM (convective time).
    t : ndarray, shape (N,)
        Equispaced times from 0 (convective time).
    u : ndarray, shape (N,)
        Input (gust angle ``v_g / U`` at the reference point).
    discretisation : {"tustin", "zoh"}
    method : {"auto", "convolution", "control"}
        See :func:`simulate_discrete`.

    Returns
    -------
    ndarray, shape (p, N)
        Outputs.

    Raises
    ------
    ValueError
        Fewer than two time points, or an unknown discretisation.
    """
    import control

    import sysid

    t = np.asarray(t, dtype=float)
    if t.size < 2:
        raise ValueError(f"need at least two time points, got {t.size}")
    if discretisation not in ("tustin", "zoh"):
        raise ValueError(f"discretisation must be 'tustin' or 'zoh', got {discretisation!r}")
    dt = float(t[1] - t[0])
    rom = control.ss(A, B, C, D, T)
    rc = sysid.d2c_bilinear(rom)
    try:
        rd = sysid.c2d_bilinear(rc, dt) if discretisation == "tustin" else sysid.c2d_zoh(rc, dt)
    except sysid.ModelError as e:  # name the simulation step, not the identification's T
        raise sysid.ModelError(
            f"the ROM identified with T = {T:g} cannot be re-discretised at the simulation step dt = {dt:g} "
            f"({discretisation}): its continuous form has a pole at s = 2/dt = {2.0 / dt:g} ({e}); change "
            "simulation.dt (or the identification's T)") from None
    return simulate_discrete(rd.A, rd.B, rd.C, rd.D, np.asarray(u, dtype=float), method)


def _task_roms(config: StudyConfig, case_name: str, root: str, codes: dict, force: bool) -> list:
    """Every identification and ROM simulation of one case that the store lacks."""
    store = _store(root, codes)
    cs = config.case(case_name)
    case = cs.case
    reports = []
    frfs, ltds = {}, {}
    for T in cs.T:
        e = store.get("frf", frf_piece(case, T, config.M_base, config.cfd))
        if e is not None and not is_failed(e):
            frfs[T] = e
    for g in config.gusts:
        e = store.get("ltd", ltd_piece(case, g, config.simulation, config.cfd))
        if e is not None and not is_failed(e):
            ltds[g.name] = e
    outputs = list(config.cfd.outputs)
    for pt in config.points():
        if pt.case.name != case.name or pt.T not in frfs:
            continue
        label = f"{case.name} T={pt.T:.6g} M={pt.M} N_r={pt.order} {pt.method.name}"
        rcfg = rom_piece(pt, config.M_base, config.cfd)
        fe = frfs[pt.T]
        if _needs(store, "rom", rcfg, force):
            import sysid

            frf = sysid.FrequencyResponse(fe["H"], fe["omega_d"], pt.T, inputs=fe.metadata.get("inputs", ["gust"]),
                                          outputs=fe.metadata.get("outputs", outputs), omega=fe["omega"])
            rom, s = _compute_piece(store, "rom", rcfg, lambda: _identify(frf, pt, config.M_base))
            reports.append(_report("rom", f"rom {label}", rom, s))
        else:
            rom = store.get("rom", rcfg)
        if is_failed(rom):
            continue
        for g in config.gusts:
            if g.name not in ltds:
                continue
            scfg = sim_piece(pt, g, config.M_base, config.simulation, config.cfd)
            if not _needs(store, "sim", scfg, force):
                continue
            le = ltds[g.name]

            def compute(rom=rom, le=le):
                t0 = time.perf_counter()
                Y = rom_simulation(rom["A"], rom["B"], rom["C"], rom["D"], pt.T, le["t"], le["u"],
                                   config.simulation.discretisation)
                seconds = time.perf_counter() - t0
                ys = {name: Y[i] for i, name in enumerate(rom.metadata.get("outputs", outputs))}
                zero = np.zeros_like(le["t"])
                metrics = sim_metrics(le["t"], ys, {"Cl": le["cl"], "Cm": le["cm"]}, seconds,
                                      float(le.metadata.get("seconds", float("nan"))))
                return sim_payload(le["t"], ys.get("Cl", zero), ys.get("Cm", zero), metrics)

            sim, s = _compute_piece(store, "sim", scfg, compute)
            reports.append(_report("sim", f"sim {label} {g.name}", sim, s))
    return reports


# ---------------------------------------------------------------------------------------------
# Executors
# ---------------------------------------------------------------------------------------------

class _InlinePool:
    """Runs each task at once in this process (``workers=1``); futures are already done."""

    name = "this process"

    def submit(self, fn, *args):
        f: Future = Future()
        try:
            f.set_result(fn(*args))
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
    import threading

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


def _init_worker(threads: int, parent_pid: int) -> None:
    """Worker initializer: BLAS threads, Ctrl-C left to the parent (which stops the workers), exit with it."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    _exit_with_parent(parent_pid)
    _limit_blas_threads(threads)


class _ProcessPool:
    """Local worker processes, each limited to ``cores // workers`` BLAS threads.

    Without the limit every worker's BLAS starts one thread per core: on two cores the demo's fast LFD sweep
    (dense Gram-Schmidt) and its LTD march (block solves) beside it took 262 s and 129 s and the study 341 s;
    with one BLAS thread per worker 176 s and 98 s, the study 263 s (measured one after the other, same
    machine, empty store each time).
    """

    def __init__(self, workers: int):
        import multiprocessing

        ctx = multiprocessing.get_context("fork") if "fork" in multiprocessing.get_all_start_methods() else None
        threads = max(1, (os.cpu_count() or 1) // workers)
        self.ex = ProcessPoolExecutor(max_workers=workers, mp_context=ctx, initializer=_init_worker,
                                      initargs=(threads, os.getpid()))
        self.name = f"{workers} local processes ({threads} BLAS thread{'s' if threads > 1 else ''} each)"

    def submit(self, fn, *args):
        return self.ex.submit(fn, *args)

    @staticmethod
    def wait(pending):
        done, rest = cf_wait(pending, return_when=FIRST_COMPLETED)
        return done, rest

    def close(self, abort: bool = False):
        """Wait for the running tasks, or (``abort``) stop the workers at once (what they stored is kept)."""
        if abort:
            for proc in list((getattr(self.ex, "_processes", None) or {}).values()):
                proc.terminate()
            self.ex.shutdown(wait=False, cancel_futures=True)
            return
        self.ex.shutdown(wait=True, cancel_futures=True)


class _DaskPool:
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
        return self.client.submit(fn, *args, pure=False)

    @staticmethod
    def wait(pending):
        from distributed import wait

        done, rest = wait(list(pending), return_when="FIRST_COMPLETED")
        return set(done), set(rest)

    def close(self, abort: bool = False):
        self.client.close()
        if self.cluster is not None:
            self.cluster.close()


def auto_workers(config: StudyConfig, cpus: Optional[int] = None) -> int:
    """Worker processes for ``workers="auto"``: the study's widest stage, at most the CPU count.

    The widest stage is the CFD one: for each case one task per sampling period ``T`` (its LFD sweep) and
    one for its gusts (a single LTD march), at least one per case. Each worker then gets
    ``cpus // workers`` BLAS threads. Memory: a worker on the paper grid (181 x 60) holds about 1.5 GB at its
    peak (the fast sweep's basis and one factorisation).

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
    """Parallel tasks of the study's widest stage: per case, one per ``T`` and one for its gusts."""
    return sum(max(1, len(cs.T) + (1 if config.gusts else 0)) for cs in config.cases)


def _pool(scheduler, workers):
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise RunnerError(f"workers must be a positive integer, got {workers!r}")
    if scheduler is not None:
        if not isinstance(scheduler, str) or not (scheduler == "local" or "://" in scheduler):
            raise RunnerError(f"scheduler must be a Dask address such as 'tcp://host:8786' or 'local', got "
                              f"{scheduler!r}")
        return _DaskPool(scheduler, workers)
    if workers is None or workers == 1:
        return _InlinePool()
    return _ProcessPool(workers)


# ---------------------------------------------------------------------------------------------
# Progress
# ---------------------------------------------------------------------------------------------

@dataclass
class _Progress:
    enabled: bool
    total: int
    t0: float = field(default_factory=time.perf_counter)
    done: int = 0
    failed: int = 0
    log: list = field(default_factory=list)

    def say(self, text: str):
        if self.enabled:
            print(f"[{time.perf_counter() - self.t0:8.1f} s] {text}", flush=True)

    def piece(self, rep: dict):
        self.done += 1
        self.log.append(rep)
        bad = rep["status"] == "failed"
        self.failed += bad
        tail = f" FAILED: {rep['error']}" if bad else ""
        self.say(f"{rep['label']}: {rep['seconds']:.2f} s ({self.done}/{self.total} pieces, {self.failed} failed)"
                 f"{tail}")


# ---------------------------------------------------------------------------------------------
# The runner
# ---------------------------------------------------------------------------------------------

def _as_config(study) -> StudyConfig:
    if isinstance(study, StudyConfig):
        return study
    if isinstance(study, (str, Path)):
        return load_study(study)
    raise TypeError(f"run_study() expects a StudyConfig or the path of a study file, got {type(study).__name__}")


def run_study(study, *, output_dir=None, store_dir=None, scheduler: Optional[str] = None,
              workers=None, progress: bool = True, force: bool = False) -> StudyResults:
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
    progress : bool
        Print one line per finished piece: elapsed time, piece time, counts.
    force : bool
        Recompute every piece even when stored.

    Returns
    -------
    StudyResults
        :func:`studies.results.load_results` after the run.

    Raises
    ------
    StudyConfigError
        Invalid study file.
    RunnerError
        Bad ``workers`` or ``scheduler``; Dask requested but not installed.
    TypeError
        ``study`` is neither a StudyConfig nor a path.
    """
    config = _as_config(study)
    changes = {}
    if output_dir is not None:
        changes["output_dir"] = Path(output_dir).resolve()
    if store_dir is not None:
        changes["store_dir"] = Path(store_dir).resolve()
    if changes:
        config = replace(config, **changes)
    if workers == "auto":
        workers = auto_workers(config)
    elif scheduler in (None, "local") and isinstance(workers, int) and not isinstance(workers, bool) and workers > 1:
        cap = auto_workers(config)
        if workers > cap:
            warnings.warn(f"workers = {workers} is more than this study can use (its widest stage has "
                          f"{_width(config)} parallel task(s); {os.cpu_count() or 1} CPU(s)): using {cap}",
                          RuntimeWarning, stacklevel=2)
            workers = cap
    pool = _pool(scheduler, workers)
    state: dict = {}
    try:
        results = _run(config, pool, progress, bool(force), state)
    except KeyboardInterrupt:
        pool.close(abort=True)
        raise RunInterrupted(state.get("computed", 0), config.store_dir) from None
    pool.close()
    return results


def _run(config: StudyConfig, pool, progress: bool, force: bool, state: dict) -> StudyResults:
    root = str(config.store_dir)
    base = open_store(config)
    codes = {p: base.code_version(p) for p in PIECES}
    store = _store(root, codes)

    # what is needed, per case
    plan = {}
    n_cfd = n_id = 0
    for cs in config.cases:
        c = cs.case
        need_steady = _needs(store, "steady", steady_piece(c), force)
        frfs = [T for T in cs.T if _needs(store, "frf", frf_piece(c, T, config.M_base, config.cfd), force)]
        ltds = [g.name for g in config.gusts if _needs(store, "ltd", ltd_piece(c, g, config.simulation, config.cfd),
                                                          force)]
        n_rom = n_sim = 0
        for pt in config.points():
            if pt.case.name != c.name:
                continue
            n_rom += _needs(store, "rom", rom_piece(pt, config.M_base, config.cfd), force)
            n_sim += sum(_needs(store, "sim", sim_piece(pt, g, config.M_base, config.simulation, config.cfd), force)
                         for g in config.gusts)
        plan[c.name] = dict(steady=need_steady, frf=frfs, ltd=ltds, rom=n_rom, sim=n_sim)
        n_cfd += need_steady + len(frfs) + len(ltds)
        n_id += n_rom + n_sim
    # ROM/sim counts are upper bounds known now; pieces of failed CFD are skipped
    prog = _Progress(progress, n_cfd + n_id)
    prog.say(f"study {config.name!r}: {len(config.cases)} case(s), {len(config.points())} sweep point(s), "
             f"{len(config.gusts)} gust(s); to compute: {n_cfd} CFD piece(s), up to {n_id} ROM piece(s) "
             f"[{pool.name}; store {root}]")

    pending = {}  # future -> (kind, case)
    task_failures: list = []  # tasks that failed outside their pieces (their pieces were not stored)

    def submit(kind, case_name, fn, *args):
        pending[pool.submit(fn, *args)] = (kind, case_name)

    cfd_left = {name: 0 for name in plan}

    def start_cfd(name):
        p = plan[name]
        for T in p["frf"]:
            submit("frf", name, _task_frf, config, name, T, root, codes)
            cfd_left[name] += 1
        if p["ltd"]:  # all the case's gusts in one march: one factorisation, block solves
            submit("ltd", name, _task_ltd, config, name, list(p["ltd"]), root, codes)
            cfd_left[name] += 1
        if cfd_left[name] == 0:
            start_roms(name)

    def start_roms(name):
        p = plan[name]
        if p["rom"] or p["sim"]:
            submit("roms", name, _task_roms, config, name, root, codes, force)

    for name, p in plan.items():
        if p["steady"]:
            submit("steady", name, _task_steady, config, name, root, codes)
        else:
            start_cfd(name)

    while pending:
        done, _ = pool.wait(set(pending))
        for fut in done:
            kind, name = pending.pop(fut)
            try:
                reports = fut.result()
            except Exception as e:  # noqa: BLE001 - a task that failed outside its pieces (e.g. the store)
                prog.say(f"{kind} task of {name} failed: {error_text(e)}")
                task_failures.append(dict(kind=kind, case=name, error=error_text(e),
                                          write=isinstance(e, OSError)))
                reports = []
            for rep in reports:
                prog.piece(rep)
            state["computed"] = prog.done
            if kind == "steady":
                ok = reports and reports[0]["status"] == "ok"
                if ok:
                    start_cfd(name)
                else:
                    prog.say(f"{name}: no steady flow, its FRFs, LTD histories and ROMs are skipped")
            elif kind in ("frf", "ltd"):
                cfd_left[name] -= 1
                if cfd_left[name] == 0:
                    start_roms(name)

    elapsed = time.perf_counter() - prog.t0
    results = load_results(config, store_dir=config.store_dir)
    n_ok_roms = sum(r.ok for r in results.roms)
    prog.say(f"done in {elapsed:.1f} s: {prog.done} piece(s) computed ({prog.failed} failed); "
             f"{n_ok_roms}/{len(config.points())} ROMs ok, {len(results.sims)} ROM simulations, "
             f"{len(results.missing)} piece(s) missing")
    _write_log(config, prog, elapsed)
    summary = RunSummary(computed=prog.done, failed_pieces=prog.failed, task_failures=tuple(task_failures),
                         seconds=elapsed)
    return replace(results, run=summary)


def _write_log(config: StudyConfig, prog: _Progress, elapsed: float) -> None:
    """``run-log.json`` in the output folder: the pieces this run computed, with their times."""
    from .cache import atomic_write_bytes

    by_piece: dict = {}
    for rep in prog.log:
        d = by_piece.setdefault(rep["piece"], {"count": 0, "failed": 0, "seconds": 0.0})
        d["count"] += 1
        d["failed"] += rep["status"] == "failed"
        d["seconds"] += rep["seconds"]
    doc = {"study": config.name, "wall_s": elapsed, "totals": by_piece, "pieces": prog.log,
           "finished_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())}
    try:
        atomic_write_bytes(Path(config.output_dir) / "run-log.json", json.dumps(doc, indent=1).encode())
    except OSError as e:  # the log is a convenience; the results are in the store
        print(f"lfdrom: warning: cannot write the run log: {e}", file=sys.stderr)
