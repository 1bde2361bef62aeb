"""The ``[aeroelastic]`` section's tasks, run plan and reader (schema, parsing and keys:
:mod:`studies.sections.aeroelastic.schema`).

:func:`motion_frf_task` computes a flow case's motion frequency response (``cfd.lfd_response`` with inputs gust,
plunge and pitch) once its steady flow is stored; :func:`flutter_task` then the flutter of every section with
it (``aeroelastic.to_elastic_axis``, ``fit_motion``, ``flutter``, and ``gust_response`` for the study's gusts at
the section's ``gust_speed``). Both store their pieces through :func:`studies.run.compute.compute_piece` (a piece that
raises is stored as a failure), so an interrupted run keeps what it stored and a second run computes nothing.
:func:`load_flutter` reads the flutter pieces back as :class:`FlutterRecord`.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from .schema import MOTION_INPUTS, MOTION_OUTPUTS, PIVOT, SectionSpec, flutter_piece, motion_frf_piece
from ..gust_rom.pieces import is_failed
from ...run.progress import piece_reporter, task_key
from ..gust_rom.tasks import compute_piece, load_linear_system, needs_compute, piece_report, pinned_store

__all__ = [
    "gust_time",
    "aeroelastic_plan",
    "aeroelastic_status",
    "motion_frf_task",
    "flutter_task",
    "FlutterRecord",
    "load_flutter",
]


def _case(config, name):
    return config.case(name).case


def aeroelastic_plan(config, store, force: bool) -> dict:
    """What the store lacks: case name -> ``{"motion": bool, "flutter": int}`` (empty without the section)."""
    opts = getattr(config, "aeroelastic", None)
    if opts is None:
        return {}
    plan = {}
    for name in opts.cases:
        case = _case(config, name)
        motion = needs_compute(store, "motion_frf", motion_frf_piece(case, opts.omega, config.cfd), force)
        n = sum(needs_compute(store, "flutter", flutter_piece(config, case, s), force) for s in opts.sections)
        plan[name] = dict(motion=bool(motion), flutter=int(n))
    return plan


def aeroelastic_status(config, store) -> tuple:
    """``(missing, failed)`` lists of the aeroelastic pieces (for :func:`studies.store.results.load_results`)."""
    opts = getattr(config, "aeroelastic", None)
    missing, failed = [], []
    if opts is None:
        return missing, failed
    for name in opts.cases:
        case = _case(config, name)
        e = store.get("motion_frf", motion_frf_piece(case, opts.omega, config.cfd))
        if e is None:
            missing.append(f"motion_frf {name}")
        elif is_failed(e):
            failed.append(f"motion frequency response of {name} failed: {e.metadata.get('error')}")
        for s in opts.sections:
            f = store.get("flutter", flutter_piece(config, case, s))
            if f is None:
                missing.append(f"flutter {name} {s.name}")
            elif is_failed(f):
                failed.append(f"flutter of {name} with section {s.name} failed: {f.metadata.get('error')}")
    return missing, failed




# ---------------------------------------------------------------------------------------------
# Computations
# ---------------------------------------------------------------------------------------------

def gust_time(simulation) -> np.ndarray:
    """The convective time grid of the flexible section's gust histories, shape (n + 1,):
    ``0, dt, ..., t_end`` of the study's ``[simulation]`` (as the LTD histories)."""
    n = int(round(simulation.t_end / simulation.dt))
    return np.linspace(0.0, n * simulation.dt, n + 1)


def _motion_frf(lin, omega, cfd_options, progress=None):
    import cfd
    from cfd.lfd import AUTO_FAST_ABOVE

    omega = np.asarray(omega, dtype=float)
    kw = {}
    if progress is not None and omega.size > AUTO_FAST_ABOVE:
        import inspect

        kw["progress"] = progress.sweep(int(omega.size), inspect.signature(cfd.lfd_response).parameters["tol"].default)
    return cfd.lfd_response(lin, omega, gust=cfd_options.gust_method, outputs=MOTION_OUTPUTS, inputs=MOTION_INPUTS,
                            pivot=PIVOT, method="auto", **kw)


def _flutter_payload(config, case_frf_entry, spec: SectionSpec) -> tuple:
    """``(arrays, metadata)`` of the flutter piece from a stored motion FRF entry."""
    import aeroelastic as ae
    from sysid import FrequencyResponse

    from ...config.cases import to_gust

    t0 = time.perf_counter()
    md = case_frf_entry.metadata
    frf = FrequencyResponse.from_continuous(case_frf_entry["H"], case_frf_entry["omega"],
                                            inputs=md.get("inputs", list(MOTION_INPUTS)),
                                            outputs=md.get("outputs", list(MOTION_OUTPUTS)))
    sec = spec.section()
    ea = ae.to_elastic_axis(frf, sec, pivot=float(md.get("pivot", PIVOT)), moment_axis=0.25)
    opts = config.aeroelastic
    model = ae.fit_motion(ea, opts.lags, gust_order=opts.gust_order)
    res = ae.flutter(model, sec, None if opts.speeds is None else np.asarray(opts.speeds))
    arrays = {"speeds": np.asarray(res.speeds, dtype=float), "eigenvalues": np.asarray(res.eigenvalues, dtype=complex),
              "modes": np.asarray(res.modes, dtype=int)}
    gusts = []
    if spec.gust_speed is not None:
        t = gust_time(config.simulation)
        for i, g in enumerate(config.gusts):
            u = np.asarray(to_gust(g, x0=config.simulation.x0).input(t), dtype=float)
            r = ae.gust_response(model, sec, spec.gust_speed, (t, u))
            for name in ("t", "u", "plunge", "pitch", "Cl", "Cm"):
                arrays[f"g{i}_{name}"] = np.asarray(getattr(r, name), dtype=float)
            gusts.append(g.name)
    try:  # the incompressible flat plate's flutter of the same section (k-method determinant, exact C(k))
        ref = ae.theodorsen.flutter_determinant(sec)
        theodorsen = dict(speed_index=float(ref.speed_index), frequency_ratio=float(ref.frequency_ratio))
    except Exception as e:  # noqa: BLE001 - a reference only: recorded, not fatal
        theodorsen = dict(speed_index=math.nan, frequency_ratio=math.nan, error=f"{type(e).__name__}: {e}"[:300])
    fit = dict(max_error=float(model.max_error), rms_error=float(model.rms_error),
               gust_max_error=float(model.gust_max_error), poles=[float(p) for p in model.poles])
    meta = dict(status="ok", speed_index=float(res.speed_index), flutter_speed_index=float(res.flutter_speed_index),
                frequency_ratio=float(res.frequency_ratio), reduced_frequency=float(res.reduced_frequency),
                kind=str(res.kind), found=bool(res.found), section=spec.name, gusts=gusts,
                gust_speed=spec.gust_speed, fit=fit, theodorsen=theodorsen, seconds=time.perf_counter() - t0)
    return arrays, meta


def motion_frf_task(config, case_name: str, root: str, codes: dict) -> list:
    """The motion frequency response of one flow case (its steady flow stored): one ``motion_frf`` piece.

    ``cfd.lfd_response(lin, omega, inputs=("gust", "plunge", "pitch"), pivot=0.25)`` on the section's ``omega``;
    ``H`` has shape (2, 3, K): Cl and Cm (quarter chord) per unit gust angle, plunge ``h / c`` (up) and pitch
    (rad, nose up about the quarter chord).

    Parameters
    ----------
    config : studies.config.schema.StudyConfig
    case_name : str
    root : str
        The store's folder.
    codes : dict
        Piece -> code version pinned by the main process.

    Returns
    -------
    list of dict
        One report per piece stored (as the other tasks).
    """
    store = pinned_store(root, codes)
    case = _case(config, case_name)
    opts = config.aeroelastic

    def compute():
        lin = load_linear_system(store, case)
        t0 = time.perf_counter()
        frf = _motion_frf(lin, opts.omega, config.cfd, piece_reporter(task_key("motion", case.name)))
        seconds = time.perf_counter() - t0
        return ({"H": np.asarray(frf.H), "omega": np.asarray(frf.omega, dtype=float)},
                dict(status="ok", inputs=list(frf.inputs), outputs=list(frf.outputs), pivot=PIVOT,
                     method=str(frf.metadata.get("method", "auto")), seconds=seconds,
                     lfd={k: v for k, v in frf.metadata.items() if isinstance(v, (int, float, str, bool))}))

    entry, seconds = compute_piece(store, "motion_frf", motion_frf_piece(case, opts.omega, config.cfd), compute)
    return [piece_report("motion_frf", f"motion_frf {case.name} ({len(opts.omega)} frequencies, gust + plunge + "
                                       "pitch)", entry, seconds)]


def flutter_task(config, case_name: str, root: str, codes: dict, force: bool) -> list:
    """Flutter (and gust histories) of every section of the study for one flow case (its motion FRF stored).

    Parameters
    ----------
    config, case_name, root, codes
        As for :func:`motion_frf_task`.
    force : bool
        Recompute pieces even when stored.

    Returns
    -------
    list of dict
        One report per piece stored.
    """
    store = pinned_store(root, codes)
    case = _case(config, case_name)
    opts = config.aeroelastic
    frf_entry = store.get("motion_frf", motion_frf_piece(case, opts.omega, config.cfd))
    if frf_entry is None or is_failed(frf_entry):
        return []
    reports = []
    for spec in opts.sections:
        key = flutter_piece(config, case, spec)
        if not needs_compute(store, "flutter", key, force):
            continue
        entry, seconds = compute_piece(store, "flutter", key, lambda spec=spec: _flutter_payload(config, frf_entry,
                                                                                                   spec))
        reports.append(piece_report("flutter", f"flutter {case.name} {spec.name}", entry, seconds))
    return reports


# ---------------------------------------------------------------------------------------------
# Reading back
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class FlutterRecord:
    """A stored flutter piece.

    Attributes
    ----------
    case, section : str
    spec : SectionSpec
    result : aeroelastic.FlutterResult
        Rebuilt from the store (``model`` is None: the fit is not stored, its errors are in ``fit``).
    gusts : dict of str -> aeroelastic.GustResponse
        The flexible section's gust histories at ``spec.gust_speed`` (empty when not asked for).
    fit : dict
        ``max_error``, ``rms_error``, ``gust_max_error`` of the motion fit and its lag ``poles`` (U/c).
    theodorsen : dict
        ``speed_index`` and ``frequency_ratio`` of the same section on Theodorsen's incompressible flat plate
        (``aeroelastic.theodorsen.flutter_determinant``), the reference the CFD's numbers are read against.
    seconds : float
        Compute time of the piece (s).
    motion_seconds : float
        Compute time of the case's motion FRF (s).
    """

    case: str
    section: str
    spec: SectionSpec
    result: Any
    gusts: dict
    fit: dict
    theodorsen: dict
    seconds: float
    motion_seconds: float


def load_flutter(config, store) -> list:
    """The stored flutter pieces of a study, as :class:`FlutterRecord` (case order, then section order)."""
    import aeroelastic as ae

    opts = getattr(config, "aeroelastic", None)
    records = []
    if opts is None:
        return records
    for name in opts.cases:
        case = _case(config, name)
        m = store.get("motion_frf", motion_frf_piece(case, opts.omega, config.cfd))
        motion_s = float(m.metadata.get("seconds", float("nan"))) if m is not None and not is_failed(m) else math.nan
        for spec in opts.sections:
            e = store.get("flutter", flutter_piece(config, case, spec))
            if e is None or is_failed(e):
                continue
            md = e.metadata
            res = ae.FlutterResult(
                speed_index=_f(md.get("speed_index")), flutter_speed_index=_f(md.get("flutter_speed_index")),
                frequency_ratio=_f(md.get("frequency_ratio")), kind=str(md.get("kind")), found=bool(md.get("found")),
                reduced_frequency=_f(md.get("reduced_frequency")), speeds=e["speeds"], eigenvalues=e["eigenvalues"],
                modes=e["modes"], section=spec.section(), model=None)
            gusts = {}
            for i, g in enumerate(md.get("gusts", [])):
                gusts[g] = ae.GustResponse(e[f"g{i}_t"], 2.0 * e[f"g{i}_t"] / spec.gust_speed, e[f"g{i}_u"],
                                           e[f"g{i}_plunge"], e[f"g{i}_pitch"], e[f"g{i}_Cl"], e[f"g{i}_Cm"],
                                           float(spec.gust_speed))
            records.append(FlutterRecord(case=name, section=spec.name, spec=spec, result=res, gusts=gusts,
                                         fit=dict(md.get("fit", {})),
                                         theodorsen=dict(md.get("theodorsen", {})), seconds=_f(md.get("seconds")),
                                         motion_seconds=motion_s))
    return records


def _f(v) -> float:
    return float("nan") if v is None else float(v)

