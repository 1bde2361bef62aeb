"""The ``[nonlinear]`` section's tasks, run plan and reader (schema, parsing and keys:
:mod:`studies.sections.nonlinear.schema`).

:func:`nonlinear_task` marches the nonlinear Euler equations (``cfd.unsteady_response``) for one flow case, gust
shape and amplitude once the case's steady flow is stored, and stores one ``nonlinear`` piece (through
:func:`studies.run.compute.compute_piece`: a march that raises is stored as a failure, so an interrupted run keeps what
it stored and a second run computes nothing). :func:`load_linearity` reads the pieces back and compares each with
the linear models of the same gust shape the study stored: the LTD history and the ROM histories, scaled from the
gust's own angle to the march's (they are linear in the amplitude).

Measures (per output ``y`` in Cl, Cm; over the march's time window, ``A = tan(amplitude)``)
-----------------------------------------------------------------------------------------
- peak ratio: ``max_t |y_NL| / max_t |y_lin|`` (1 where the linear model holds; above 1: the linear model
  under-predicts the peak load);
- history error: ``max_t |y_NL / A - y_lin / A| / max_t |y_lin / A|``, the linear model's error relative to its
  own peak (the definitions of :func:`cfd.linearity`).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from .schema import gust_shapes, march_end, nonlinear_piece
from ..gust_rom.pieces import is_failed
from ...run.progress import piece_reporter, task_key
from ..gust_rom.tasks import compute_piece, load_steady_solution, piece_report, pinned_store

__all__ = [
    "nonlinear_plan",
    "nonlinear_status",
    "nonlinear_task",
    "LinearityRecord",
    "load_linearity",
    "compare_histories",
]

OUTPUTS = ("Cl", "Cm")


def _marches(config):
    """``(case, gust, amplitude, label)`` of every march of the section, in case, shape, angle order: one per
    gust shape and angle (:func:`studies.sections.nonlinear.schema.gust_shapes`; ``gust`` is the shape's first gust,
    ``label`` names all of them)."""
    opts = config.nonlinear
    shapes = gust_shapes(opts, config.gusts)
    out = []
    for name in opts.cases:
        case = config.case(name).case
        for label, gust, angles in shapes:
            out += [(case, gust, a, label) for a in angles]
    return out


def nonlinear_plan(config, store, force: bool) -> dict:
    """What the store lacks: case name -> list of ``(gust name, amplitude)`` (empty without the section).

    A march stored as stopped by the solver (:func:`is_limit`: the flow left what the solver resolves, a result
    rather than a transient failure) is not marched again unless ``force``."""
    if getattr(config, "nonlinear", None) is None:
        return {}
    plan: dict = {}
    for case, gust, a, _ in _marches(config):
        e = store.get("nonlinear", nonlinear_piece(config, case, gust, a))
        if force or e is None or (is_failed(e) and not is_limit(e)):
            plan.setdefault(case.name, []).append((gust.name, a))
    return plan


def is_limit(entry) -> bool:
    """Whether a stored march stopped at the solver's limits (a step that did not converge, a local Mach number
    beyond the limit, a non-physical state) or was skipped after a smaller angle of its gust stopped."""
    return entry is not None and is_failed(entry) and bool(entry.metadata.get("limit"))


def nonlinear_status(config, store) -> tuple:
    """``(missing, failed)`` lists of the nonlinear pieces (for :func:`studies.store.results.load_results`)."""
    missing, failed = [], []
    if getattr(config, "nonlinear", None) is None:
        return missing, failed
    for case, gust, a, label in _marches(config):
        e = store.get("nonlinear", nonlinear_piece(config, case, gust, a))
        if e is None:
            missing.append(f"nonlinear {case.name} {label} {a:g} deg")
        elif is_failed(e) and not is_limit(e):  # a march stopped at the solver's limits is a result (the report)
            failed.append(f"nonlinear response of {case.name} to {label} at {a:g} deg failed: "
                          f"{e.metadata.get('error')}")
    return missing, failed


# ---------------------------------------------------------------------------------------------
# The march
# ---------------------------------------------------------------------------------------------

def _march(config, case, gust, amplitude, sol, progress=None):
    """``(arrays, metadata)`` of the nonlinear piece."""
    from dataclasses import replace

    import cfd

    from ...config.cases import to_gust

    sim = config.simulation
    g = replace(to_gust(gust, x0=sim.x0), angle_deg=float(amplitude))
    t_end = march_end(config.nonlinear, gust, sim)
    t0 = time.perf_counter()
    kw = {} if progress is None else {"progress": progress}
    h = cfd.unsteady_response(sol, g, sim.dt, t_end, method=config.cfd.gust_method, **kw)
    seconds = time.perf_counter() - t0
    steps = max(len(h.t) - 1, 1)
    arrays = {"t": h.t, "u": h.u, "cl": h.cl, "cm": h.cm, "cd": h.cd, "iterations": h.iterations,
              "max_mach": h.max_mach}
    meta = dict(status="ok", amplitude_deg=float(amplitude), steady_loads=[float(v) for v in h.steady_loads],
                n_factorisations=int(h.n_factorisations), iterations_per_step=float(np.sum(h.iterations) / steps),
                max_iterations=int(np.max(h.iterations)), max_local_mach=float(np.max(h.max_mach)),
                steady_max_mach=float(h.info.get("steady_max_mach", math.nan)), seconds=seconds,
                dt=float(sim.dt), t_end=float(t_end))
    return arrays, meta


def _reporter(case, gust, amplitude, done: int, total: int):
    """``progress`` of ``cfd.unsteady_response`` for the task's line of the runner's progress output (the bar: the
    share of the task's angles done)."""
    rep = piece_reporter(task_key("nonlinear", f"{case.name} {gust.name}"))
    if rep is None:
        return None

    def progress(step, n_steps, t, iterations):
        frac = (done + step / max(n_steps, 1)) / max(total, 1)
        rep.update(f"{amplitude:g} deg ({done + 1}/{total}): step {step}/{n_steps} (s = {t:.2f}, {iterations} "
                   "iterations)", f"{amplitude:g} deg {step}/{n_steps}", frac, force=step == n_steps)

    return progress


def _limit_payload(exc, skipped_after=None) -> tuple:
    """``(arrays, metadata)`` of a march stopped by the solver (the history so far) or skipped after one."""
    from ..gust_rom.pieces import error_text

    if skipped_after is not None:
        return {}, dict(status="failed", limit=True, error=f"not marched: the {skipped_after:g} deg march of the "
                                                            f"same gust stopped ({error_text(exc)[:300]})")
    arrays = {}
    h = getattr(exc, "partial", None)
    if h is not None:
        arrays = {"t": h.t, "cl": h.cl, "cm": h.cm, "cd": h.cd, "max_mach": h.max_mach}
    return arrays, dict(status="failed", limit=True, error=error_text(exc),
                        step=getattr(exc, "step", None), time=getattr(exc, "time", None))


def nonlinear_task(config, case_name: str, gust_name: str, amplitudes: list, root: str, codes: dict,
                   force: bool = False) -> list:
    """The nonlinear marches of one flow case and gust shape at ``amplitudes`` (its steady flow stored), one
    ``nonlinear`` piece each, by increasing magnitude.

    A march that the solver stops (``cfd.UnsteadyStepError``: a step that does not converge, a local Mach
    number beyond the limit, a non-physical state) is stored with ``limit = True`` and its history so far, and
    the larger angles of the same gust are stored as skipped (``limit = True``): neither is marched again
    unless the run is forced. Another error is stored as an ordinary failure (retried by the next run).

    Parameters
    ----------
    config : studies.config.schema.StudyConfig
    case_name, gust_name : str
    amplitudes : list of float
        Gust angles (deg).
    root : str
        The store's folder.
    codes : dict
        Piece -> code version pinned by the main process.
    force : bool
        March even where a piece is stored (else a piece stored meanwhile, e.g. by another run, is kept).

    Returns
    -------
    list of dict
        One report per piece stored (as the other tasks).
    """
    from cfd.unsteady import UnsteadyStepError

    store = pinned_store(root, codes)
    case = config.case(case_name).case
    gust = next(g for g in config.gusts if g.name == gust_name)
    state: dict = {}
    reports = []
    amps = sorted(amplitudes, key=lambda a: (abs(a), a))
    n = int(round(march_end(config.nonlinear, gust, config.simulation) / config.simulation.dt))
    for i, a in enumerate(amps):
        key = nonlinear_piece(config, case, gust, a)
        e = store.get("nonlinear", key)
        if e is not None and not is_failed(e) and not force:
            continue  # stored meanwhile (e.g. by another run)

        def compute(a=a, i=i):
            if "stopped" in state:
                return _limit_payload(state["stopped"][1], skipped_after=state["stopped"][0])
            if "sol" not in state:
                state["sol"] = load_steady_solution(store, case)
            try:
                return _march(config, case, gust, a, state["sol"], _reporter(case, gust, a, i, len(amps)))
            except UnsteadyStepError as exc:
                state["stopped"] = (a, exc)
                return _limit_payload(exc)

        entry, seconds = compute_piece(store, "nonlinear", key, compute)
        report = piece_report("nonlinear", f"nonlinear {case.name} {gust.name} {a:g} deg ({n} steps)", entry, seconds)
        if is_limit(entry):
            report["status"] = "stopped"
        reports.append(report)
    return reports


# ---------------------------------------------------------------------------------------------
# Reading back and comparing
# ---------------------------------------------------------------------------------------------

def compare_histories(nonlinear: dict, linear: dict, scale: float) -> dict:
    """Peak ratios and history errors of a nonlinear history against a linear one.

    Parameters
    ----------
    nonlinear : dict of str -> ndarray, shape (n + 1,)
        ``{"Cl": ..., "Cm": ...}`` at the march's amplitude.
    linear : dict of str -> ndarray, shape (m + 1,), m >= n
        The linear model's histories at the gust's own amplitude, on the same time grid from 0 (only the first
        ``n + 1`` samples are compared).
    scale : float
        ``tan(march angle) / tan(gust's angle)``: the linear history at the march's amplitude is ``scale *
        linear``.

    Returns
    -------
    dict
        ``ratio_X`` (peak ratio) and ``error_X`` (history error) per output ``X`` in both; NaN where the linear
        history is zero throughout.
    """
    out = {}
    for name in OUTPUTS:
        if name not in nonlinear or name not in linear:
            continue
        y = np.asarray(nonlinear[name], dtype=float)
        yl = scale * np.asarray(linear[name], dtype=float)[:y.size]
        if yl.size < y.size:
            raise ValueError(f"the linear {name} history has {yl.size} samples, the nonlinear one {y.size}")
        peak = float(np.max(np.abs(yl)))
        if not peak > 0.0 or not np.all(np.isfinite(yl)):
            out[f"ratio_{name}"] = out[f"error_{name}"] = math.nan
            continue
        out[f"ratio_{name}"] = float(np.max(np.abs(y)) / peak)
        out[f"error_{name}"] = float(np.max(np.abs(y - yl)) / peak)
    return out


@dataclass(frozen=True, eq=False)
class LinearityRecord:
    """One nonlinear march of the study against the linear models of the same gust shape.

    Attributes
    ----------
    case : str
    gust : str
        The gusts of this shape (``"G2/G3"``: :func:`studies.sections.nonlinear.schema.gust_shapes`).
    amplitude_deg : float
        The march's gust angle.
    gust_angle_deg : float
        The angle of the shape's first gust (the amplitude of the LTD and ROM histories compared).
    status : str
        ``"ok"``; ``"stopped"``: the solver stopped the march (the flow left what it resolves: a local Mach
        number beyond its limit, a non-physical state, a step that did not converge) or it was skipped after a
        smaller angle of its gust stopped; ``"failed"``: any other error (retried by the next run).
    error : str or None
        The solver's message of a march that did not end.
    t, cl, cm, cd : ndarray, shape (n + 1,)
        Nonlinear history (perturbations at the march's amplitude); the part before the stop of a stopped march;
        empty when skipped or failed.
    ltd : dict
        :func:`compare_histories` against the LTD (``ratio_Cl``, ``error_Cl``, ``ratio_Cm``, ``error_Cm``); empty
        when the LTD history is not stored.
    roms : dict of str -> dict
        The same against each ROM of the case (label ``"N_r=25 dc_stable T=11.14 M=256"`` -> measures), the
        ROM whose history of this gust is closest to the LTD's (smallest Cl envelope error) first.
    ltd_cl, ltd_cm : ndarray, shape (n + 1,) or (0,)
        The LTD history scaled to the march's amplitude (for plots).
    rom_cl, rom_cm : ndarray, shape (n + 1,) or (0,)
        The first ROM's history scaled likewise.
    metadata : dict
        The piece's metadata (iterations, factorisations, local Mach numbers, seconds, warnings).
    """

    case: str
    gust: str
    amplitude_deg: float
    gust_angle_deg: float
    status: str
    error: Optional[str] = None
    t: np.ndarray = field(default_factory=lambda: np.zeros(0))
    cl: np.ndarray = field(default_factory=lambda: np.zeros(0))
    cm: np.ndarray = field(default_factory=lambda: np.zeros(0))
    cd: np.ndarray = field(default_factory=lambda: np.zeros(0))
    ltd: dict = field(default_factory=dict)
    roms: dict = field(default_factory=dict)
    ltd_cl: np.ndarray = field(default_factory=lambda: np.zeros(0))
    ltd_cm: np.ndarray = field(default_factory=lambda: np.zeros(0))
    rom_cl: np.ndarray = field(default_factory=lambda: np.zeros(0))
    rom_cm: np.ndarray = field(default_factory=lambda: np.zeros(0))
    metadata: dict = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        return self.status == "ok"

    def rom(self) -> dict:
        """The measures against the case's ROM closest to the LTD (empty when there is none)."""
        return next(iter(self.roms.values()), {})


def _rank(value) -> float:
    return math.inf if value is None or not np.isfinite(value) else float(value)


def rom_label(sim) -> str:
    """The label of a ROM history in :attr:`LinearityRecord.roms`."""
    return f"N_r={sim.order} {sim.method} T={sim.T:.6g} M={sim.M}"


def load_linearity(results) -> list:
    """The stored nonlinear marches of a study against its linear models.

    Parameters
    ----------
    results : studies.store.results.StudyResults
        The study's results (its LTD and ROM histories are the linear models).

    Returns
    -------
    list of LinearityRecord
        In case, gust, amplitude order; marches not stored are left out.
    """
    from ..gust_rom.pieces import open_store

    config = results.config
    if getattr(config, "nonlinear", None) is None:
        return []
    store = open_store(config)
    records = []
    for case, gust, a, label in _marches(config):
        e = store.get("nonlinear", nonlinear_piece(config, case, gust, a))
        if e is None:
            continue
        base = dict(case=case.name, gust=label, amplitude_deg=float(a), gust_angle_deg=float(gust.angle_deg))
        if is_failed(e):
            partial = {k: e[k] for k in ("t", "cl", "cm", "cd") if k in e.arrays}
            records.append(LinearityRecord(status="stopped" if is_limit(e) else "failed",
                                           error=str(e.metadata.get("error")), metadata=dict(e.metadata),
                                           **partial, **base))
            continue
        scale = math.tan(math.radians(a)) / math.tan(math.radians(gust.angle_deg))
        nl = {"Cl": e["cl"], "Cm": e["cm"]}
        n = e["t"].size
        kw = {}
        ltd = results.ltd.get((case.name, gust.name))
        if ltd is not None and ltd.t.size >= n:
            kw["ltd"] = compare_histories(nl, {"Cl": ltd.cl, "Cm": ltd.cm}, scale)
            kw["ltd_cl"], kw["ltd_cm"] = scale * ltd.cl[:n], scale * ltd.cm[:n]
        roms = {}
        sims = [s for s in results.sims if s.case == case.name and s.gust == gust.name and s.t.size >= n]
        sims.sort(key=lambda s: _rank(s.metrics.get("peak_err_Cl")))  # the ROM closest to the LTD first
        for s in sims:
            if not roms:
                kw["rom_cl"], kw["rom_cm"] = scale * s.cl[:n], scale * s.cm[:n]
            roms[rom_label(s)] = compare_histories(nl, {"Cl": s.cl, "Cm": s.cm}, scale)
        records.append(LinearityRecord(status="ok", t=e["t"], cl=e["cl"], cm=e["cm"], cd=e["cd"], roms=roms,
                                       metadata=dict(e.metadata), **base, **kw))
    return records
