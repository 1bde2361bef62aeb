"""The tasks of a study run: each computes some pieces and stores them (top-level functions, picklable for
process pools and Dask).

One :func:`steady_task` per case, then (once its steady flow is stored) one :func:`frf_task` per FRF
(case, T) and one :func:`ltd_task` per case for all its gusts (one LTD march), then one :func:`rom_task` per
case (every identification and ROM simulation of that case, cheap next to the CFD). A CFD task rebuilds the
linear system from the stored steady state (a converged restart: one residual evaluation and a linearisation,
a few seconds on the paper grid), so the large Jacobians are never stored nor shipped between processes.

Each task opens the store with the code versions the main process pinned (:class:`PinnedStore`), stores
every piece it computes (a piece that raises is stored as a failure) and returns
one report per piece (a dict: ``piece``, ``label``, ``status``, ``error``, ``seconds``, ``computed``). While
they run, the steady, FRF and LTD tasks report from inside the solver (Newton steps, sweep shifts, time steps)
through :mod:`studies.progress` when this process has a sink (observational: nothing of it is stored). The
ROM numerics are :mod:`sysid`'s (``identify``,
:func:`sysid.simulate.rom_simulation`, :func:`sysid.metrics.rom_metrics`); the CFD calls are thin adapters
around :mod:`cfd`.
"""

from __future__ import annotations

import math
import time
import warnings
from typing import Callable

import numpy as np

from sysid.metrics import rom_metrics
from sysid.simulate import rom_simulation

from .cache import ResultStore
from .pieces import (
    PAYLOAD_ARRAYS,
    failure_payload,
    frf_payload,
    frf_piece,
    is_failed,
    ltd_payload,
    ltd_piece,
    rom_payload,
    rom_piece,
    sim_metrics,
    sim_payload,
    sim_piece,
    steady_payload,
    steady_piece,
    store_dependencies,
)
from .progress import piece_reporter, task_key
from .schema import StudyConfig

__all__ = ["PinnedStore", "pinned_store", "lfd_on_mckelvey_grid", "needs_compute", "steady_task", "frf_task",
           "ltd_task", "rom_task", "compute_piece", "piece_report", "load_linear_system",
           "load_steady_solution"]


# ---------------------------------------------------------------------------------------------
# Store with the code versions pinned by the main process (workers compute the same keys)
# ---------------------------------------------------------------------------------------------

class PinnedStore(ResultStore):
    """A :class:`ResultStore` whose per-piece code versions are fixed (computed once, in the main process).

    The sources' hash is computed once per process; pinning it keeps the keys of a run consistent across
    worker processes even if a source file changes while the study runs.
    """

    def __init__(self, root, codes: dict):
        super().__init__(root, dependencies=store_dependencies(), required=PAYLOAD_ARRAYS)
        self._codes = dict(codes)

    def code_version(self, piece: str) -> dict:
        """The pinned code version of ``piece`` (or the store's own for a piece not pinned)."""
        return dict(self._codes[piece]) if piece in self._codes else super().code_version(piece)


def pinned_store(root, codes) -> ResultStore:
    """The store at ``root`` with the code versions ``codes`` (piece -> ``ResultStore.code_version``) pinned."""
    return PinnedStore(root, codes)


# ---------------------------------------------------------------------------------------------
# CFD helpers
# ---------------------------------------------------------------------------------------------

def _grid(case):
    import cfd

    return cfd.c_grid(cfd.naca(case.naca), **case.grid.kwargs())


def _steady(case, progress=None):
    """Steady solution of a case from the free stream (``progress``: see ``cfd.solve_steady``)."""
    import cfd

    kw = {} if progress is None else {"progress": progress}
    return cfd.solve_steady(_grid(case), case.mach, case.alpha_deg, **kw)


def _default(fn, name):
    """The default value of the keyword ``name`` of ``fn`` (the tolerances the tasks leave at their default)."""
    import inspect

    return inspect.signature(fn).parameters[name].default


def lfd_on_mckelvey_grid(lin, T, M, cfd_options, progress=None):
    """The LFD gust response on McKelvey's grid, as a study computes it.

    Parameters
    ----------
    lin : cfd.LinearSystem
        ``cfd.linearise`` of a steady flow.
    T : float
        Sampling period of the bilinear map (convective time).
    M : int
        Grid intervals: ``M + 1`` frequencies ``sysid.mckelvey_grid(M, T)``.
    cfd_options : studies.schema.CFDOptions
        Gust method and outputs.
    progress : PieceReporter, optional
        Reports the fast sweep's shifts (the direct path reports nothing).

    Returns
    -------
    frf : sysid.FrequencyResponse
        ``H`` of shape (p, 1, M + 1), per radian of gust angle, with ``T`` set.
    method : {"direct", "fast"}
        The LFD path that computed it.
    """
    import sysid
    from cfd.lfd import AUTO_FAST_ABOVE, lfd_response

    grid = sysid.mckelvey_grid(M, T)
    kw = {}
    n_finite = int(np.sum(np.isfinite(grid[1])))
    if progress is not None and n_finite > AUTO_FAST_ABOVE:  # the fast path ("auto"): it takes a progress
        kw["progress"] = progress.sweep(n_finite, _default(lfd_response, "tol"))
    frf = lfd_response(lin, grid, gust=cfd_options.gust_method, outputs=tuple(cfd_options.outputs), method="auto",
                       **kw)
    used = frf.metadata.get("method")
    if used not in ("direct", "fast"):  # cfd.lfd_response records the path it took; older stores may lack it
        used = "fast" if int(np.sum(np.isfinite(grid[1]))) > 8 else "direct"
    if frf.T is None or not math.isclose(frf.T, T, rel_tol=1e-9):
        frf = frf.with_T(T)
    return frf, used


def _gust(gust_case, x0):
    from .cases import to_gust

    return to_gust(gust_case, x0=x0)


def _ltds(lin, gust_cases, sim, cfd_options, progress=None):
    """The LTD histories of several gusts of one case, marched together (one factorisation)."""
    import cfd

    kw = {} if progress is None else {"progress": progress}
    return cfd.ltd_responses(lin, [_gust(g, sim.x0) for g in gust_cases], sim.dt, sim.t_end,
                             method=cfd_options.gust_method, scheme=sim.scheme, **kw)


# ---------------------------------------------------------------------------------------------
# Tasks (top-level functions: picklable for process pools and Dask)
# ---------------------------------------------------------------------------------------------

def piece_report(piece, label, entry, seconds, computed=True) -> dict:
    """The report of one stored piece (``piece``, ``label``, ``status``, ``error``, ``seconds``, ``computed``)."""
    md = entry.metadata if entry is not None else {}
    return dict(piece=piece, label=label, status=md.get("status", "ok"), error=md.get("error"),
                seconds=float(seconds), computed=computed)


def compute_piece(store, piece, cfg, compute: Callable[[], tuple], catch=True):
    """Compute a piece with ``compute() -> (arrays, metadata)`` and store it (a failure is stored as such, unless
    ``catch`` is False: then it raises). Returns ``(entry, seconds)``."""
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


def steady_task(config: StudyConfig, case_name: str, root: str, codes: dict) -> list:
    """The steady flow of one case, from the free stream.

    Parameters
    ----------
    config : StudyConfig
    case_name : str
    root : str
        The store's folder.
    codes : dict
        Piece -> code version, pinned by the main process (:func:`pinned_store`).

    Returns
    -------
    list of dict
        One report per piece stored.
    """
    store = pinned_store(root, codes)
    case = config.case(case_name).case

    def compute():
        import cfd

        t0 = time.perf_counter()
        reporter = piece_reporter(task_key("steady", case.name))
        sol = _steady(case) if reporter is None else _steady(
            case, progress=reporter.steady(_default(cfd.solve_steady, "tol")))
        return steady_payload(sol, time.perf_counter() - t0)

    entry, seconds = compute_piece(store, "steady", steady_piece(case), compute)
    return [piece_report("steady", f"steady {case.name}", entry, seconds)]


def _steady_restart(case, q):
    """The steady solution from a stored converged state (a converged restart: one or two Newton steps)."""
    import cfd

    return cfd.solve_steady(_grid(case), case.mach, case.alpha_deg, q0=q)


def _linear_system(case, q):
    """The linear system about a stored steady state (a converged restart, then ``cfd.linearise``)."""
    import cfd

    return cfd.linearise(_steady_restart(case, q))


def _stored_state(store, case):
    e = store.get("steady", steady_piece(case))
    if e is None or is_failed(e):
        why = "missing" if e is None else e.metadata.get("error")
        raise RuntimeError(f"the steady flow of {case.name} is not available ({why})")
    return e["q"]


def load_steady_solution(store, case):
    """The ``cfd.SteadySolution`` of a case from its stored steady flow (a converged restart).

    Raises
    ------
    RuntimeError
        The steady flow is missing or failed.
    """
    return _steady_restart(case, _stored_state(store, case))


def load_linear_system(store, case):
    """The linear system of a case about its stored steady flow (a converged restart and ``cfd.linearise``).

    Raises
    ------
    RuntimeError
        The steady flow is missing or failed.
    """
    return _linear_system(case, _stored_state(store, case))


def frf_task(config: StudyConfig, case_name: str, T: float, root: str, codes: dict) -> list:
    """The LFD response of one case at one ``T`` on ``sysid.mckelvey_grid(M_base, T)`` (its steady flow stored).

    Parameters
    ----------
    config, case_name, root, codes
        As for :func:`steady_task`.
    T : float
        Sampling period of the bilinear map (convective time).

    Returns
    -------
    list of dict
        One report per piece stored.
    """
    store = pinned_store(root, codes)
    case = config.case(case_name).case
    state = {}

    def compute():
        lin = load_linear_system(store, case)
        t0 = time.perf_counter()
        reporter = piece_reporter(task_key("frf", case.name, T))
        kw = {} if reporter is None else {"progress": reporter}
        frf, used = lfd_on_mckelvey_grid(lin, T, config.M_base, config.cfd, **kw)
        seconds = time.perf_counter() - t0
        state["method"] = used
        return frf_payload(frf, config.M_base, used, seconds)

    entry, seconds = compute_piece(store, "frf", frf_piece(case, T, config.M_base, config.cfd), compute)
    label = f"frf {case.name} T={T:.6g} ({config.M_base + 1} frequencies, {state.get('method', '-')})"
    return [piece_report("frf", label, entry, seconds)]


def ltd_task(config: StudyConfig, case_name: str, gust_names: list, root: str, codes: dict) -> list:
    """The LTD histories of one case for the gusts ``gust_names``, marched together, one piece per gust.

    Each piece records its share of the march (``seconds``: the march's wall time over the number of gusts)
    and ``marched_with`` (that number).

    Parameters
    ----------
    config, case_name, root, codes
        As for :func:`steady_task`.
    gust_names : list of str
        Names of the study's gusts to march.

    Returns
    -------
    list of dict
        One report per piece stored.
    """
    store = pinned_store(root, codes)
    case = config.case(case_name).case
    gusts = [g for g in config.gusts if g.name in gust_names]
    t0 = time.perf_counter()
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            lin = load_linear_system(store, case)
            reporter = piece_reporter(task_key("ltd", case.name))
            kw = {} if reporter is None else {"progress": reporter.ltd()}
            histories = _ltds(lin, gusts, config.simulation, config.cfd, **kw)
        error = None
    except Exception as e:  # noqa: BLE001 - stored as the failure of every piece of the march
        histories, error = [None] * len(gusts), e
    share = (time.perf_counter() - t0) / len(gusts)
    sim = config.simulation
    n = int(round(sim.t_end / sim.dt))
    if sim.scheme == "radau5":
        from cfd.ltd import radau_steps, radau_substeps

        steps = f"{radau_steps(n, radau_substeps(sim.dt))} Radau IIA steps, loads at {n} times"
    else:
        steps = f"{n} steps"
    reports = []
    for gust, hist in zip(gusts, histories):
        def compute(hist=hist):
            for w in caught:  # the march's warnings, recorded with every piece by _compute_piece
                warnings.warn(w.message, w.category)
            if error is not None:
                raise error
            arrays, metadata = ltd_payload(hist, share, config.cfd.gust_method)
            return arrays, dict(metadata, marched_with=len(gusts))

        entry, _ = compute_piece(store, "ltd", ltd_piece(case, gust, config.simulation, config.cfd), compute)
        reports.append(piece_report("ltd", f"ltd {case.name} {gust.name} ({steps}, {len(gusts)} gusts marched "
                                      "together)", entry, share))
    return reports


def needs_compute(store, piece, cfg, force) -> bool:
    """Whether a piece must be computed: ``force``, or not stored, or stored as a failure, or unreadable (a
    file in the place of its folder, no permission: its task then meets the :class:`studies.cache.StoreReadError`
    again and is recorded as failed, so that the run goes on with the other pieces and ends with exit status 3
    instead of stopping in its plan)."""
    from .cache import StoreReadError

    if force:
        return True
    try:
        e = store.get(piece, cfg)
    except StoreReadError:
        return True
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


def rom_task(config: StudyConfig, case_name: str, root: str, codes: dict, force: bool) -> list:
    """Every identification and ROM simulation of one case that the store lacks (its FRFs and LTD stored).

    Parameters
    ----------
    config, case_name, root, codes
        As for :func:`steady_task`.
    force : bool
        Recompute pieces even when stored.

    Returns
    -------
    list of dict
        One report per piece stored.
    """
    store = pinned_store(root, codes)
    case_sweep = config.case(case_name)
    case = case_sweep.case
    reports = []
    frfs, ltds = {}, {}
    for T in case_sweep.T:
        e = store.get("frf", frf_piece(case, T, config.M_base, config.cfd))
        if e is not None and not is_failed(e):
            frfs[T] = e
    for g in config.gusts:
        e = store.get("ltd", ltd_piece(case, g, config.simulation, config.cfd))
        if e is not None and not is_failed(e):
            ltds[g.name] = e
    outputs = list(config.cfd.outputs)
    points = [pt for pt in config.points() if pt.case.name == case.name and pt.T in frfs]
    reporter = piece_reporter(task_key("roms", case.name))
    for i, pt in enumerate(points):
        label = f"{case.name} T={pt.T:.6g} M={pt.M} N_r={pt.order} {pt.method.name}"
        if reporter is not None:
            reporter.update(f"sweep point {i + 1}/{len(points)}: {label}", f"point {i + 1}/{len(points)}",
                            i / len(points))
        rom_key = rom_piece(pt, config.M_base, config.cfd)
        frf_entry = frfs[pt.T]
        if needs_compute(store, "rom", rom_key, force):
            import sysid

            frf = sysid.FrequencyResponse(frf_entry["H"], frf_entry["omega_d"], pt.T,
                                          inputs=frf_entry.metadata.get("inputs", ["gust"]),
                                          outputs=frf_entry.metadata.get("outputs", outputs), omega=frf_entry["omega"])
            rom, s = compute_piece(store, "rom", rom_key, lambda: _identify(frf, pt, config.M_base))
            reports.append(piece_report("rom", f"rom {label}", rom, s))
        else:
            rom = store.get("rom", rom_key)
        if is_failed(rom):
            continue
        for g in config.gusts:
            if g.name not in ltds:
                continue
            sim_key = sim_piece(pt, g, config.M_base, config.simulation, config.cfd)
            if not needs_compute(store, "sim", sim_key, force):
                continue
            ltd_entry = ltds[g.name]

            def compute(rom=rom, ltd_entry=ltd_entry):
                t0 = time.perf_counter()
                Y = rom_simulation(rom["A"], rom["B"], rom["C"], rom["D"], pt.T, ltd_entry["t"], ltd_entry["u"],
                                   config.simulation.discretisation)
                seconds = time.perf_counter() - t0
                ys = {name: Y[i] for i, name in enumerate(rom.metadata.get("outputs", outputs))}
                zero = np.zeros_like(ltd_entry["t"])
                metrics = sim_metrics(ltd_entry["t"], ys, {"Cl": ltd_entry["cl"], "Cm": ltd_entry["cm"]}, seconds,
                                      float(ltd_entry.metadata.get("seconds", float("nan"))))
                return sim_payload(ltd_entry["t"], ys.get("Cl", zero), ys.get("Cm", zero), metrics)

            sim, s = compute_piece(store, "sim", sim_key, compute)
            reports.append(piece_report("sim", f"sim {label} {g.name}", sim, s))
    return reports
