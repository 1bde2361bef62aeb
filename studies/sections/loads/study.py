"""The ``[loads]`` section's tasks, run plan and reader (schema, parsing and keys:
:mod:`studies.sections.loads.schema`).

:func:`loads_task` computes the rigid loads of every flight point of one case whose piece the store lacks, once
the case's ROMs are stored (the gust-ROM section's ``roms`` task): the stored ROM as a discrete
:class:`control.StateSpace` (``dt = T``, convective), one :func:`loads.gust_system` per flight point shared by
:func:`loads.tuned_gust` and :func:`loads.continuous_turbulence`. :func:`flexible_task` computes the flexible
sections' loads of the case's points once its ROM and the ``[aeroelastic]`` section's motion FRF are stored
(:func:`flexible_aero`: the motion FRF about the elastic axis fitted by :func:`aeroelastic.fit_motion`, the gust
ROM as the gust model, so that rigid and flexible rows share one gust aerodynamics), refusing a point at or above
the section's flutter or divergence speed there. Each piece is stored through
:func:`studies.run.compute.compute_piece` (a point that raises is stored as a failure with its error), so an
interrupted run keeps what it stored and a second run computes nothing. :func:`load_loads` reads the pieces back as
:class:`LoadsRecord`.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ...run.compute import compute_piece, needs_compute, piece_report, pinned_store
from ...run.progress import piece_reporter, task_key
from ...store.entries import is_failed
from ..gust_rom.pieces import rom_piece
from .schema import FlexibleSpec, PointSpec, flexible_piece, loads_piece, motion_key, rom_point

__all__ = ["loads_plan", "flexible_plan", "loads_status", "loads_task", "flexible_task", "loads_payload",
           "flexible_payload", "flexible_aero", "rom_model", "LoadsRecord", "load_loads", "FLUTTER_GRID"]

FLUTTER_GRID = (0.01, 3.0, 300)
"""Speed indices of the flutter check at a flexible point: ``np.linspace(0.01, 3, 300)`` times the point's own
(the flutter or divergence speed found up to three times the flight speed; above it, "none below 3 V")."""


def _points_of(config, case_name):
    return [p for p in config.loads.points if p.case == case_name]


def loads_plan(config, store, force: bool) -> dict:
    """What the store lacks: case name -> number of rigid loads pieces to compute (empty without the section)."""
    opts = config.loads
    if opts is None:
        return {}
    if not opts.rigid:
        return {case: 0 for case in opts.cases}
    return {case: sum(needs_compute(store, "loads", loads_piece(config, p), force) for p in _points_of(config, case))
            for case in opts.cases}


def flexible_plan(config, store, force: bool) -> dict:
    """What the store lacks: case name -> number of flexible loads pieces to compute (cases with flexible points)."""
    opts = config.loads
    if opts is None:
        return {}
    return {case: sum(needs_compute(store, "loads", flexible_piece(config, p, opts.section(n)), force)
                      for p in _points_of(config, case) for n in p.sections)
            for case in opts.flexible_cases}


def _rom_entry(config, store, case_name):
    return store.get("rom", rom_piece(rom_point(config, case_name), config.M_base, config.cfd))


def loads_status(config, store) -> tuple:
    """``(missing, failed)`` lists of the loads pieces (for :func:`studies.store.results.load_results`); a point
    whose ROM failed is listed as failed with the ROM's error (it cannot be computed)."""
    opts = config.loads
    missing, failed = [], []
    if opts is None:
        return missing, failed
    for case in opts.cases:
        rom = _rom_entry(config, store, case)
        motion = store.get("motion_frf", motion_key(config, case)) if case in opts.flexible_cases else None
        for p in _points_of(config, case):
            for sec in ((None,) if opts.rigid else ()) + p.sections:
                what = f"loads of {p.name}" + ("" if sec is None else f", flexible section {sec},")
                key = loads_piece(config, p) if sec is None else flexible_piece(config, p, opts.section(sec))
                e = store.get("loads", key)
                if e is None:
                    if rom is not None and is_failed(rom):
                        failed.append(f"{what} its ROM ({case}) failed: {rom.metadata.get('error')}")
                    elif sec is not None and motion is not None and is_failed(motion):
                        failed.append(f"{what} its motion FRF ({case}) failed: {motion.metadata.get('error')}")
                    else:
                        missing.append(f"loads {case} {p.name}" + ("" if sec is None else f" {sec}"))
                elif is_failed(e):
                    failed.append(f"{what} failed: {e.metadata.get('error')}")
    return missing, failed


def rom_model(entry, T: float):
    """The stored ROM piece as a discrete :class:`control.StateSpace` (``dt = T``, input ``gust``, its outputs)."""
    import control

    return control.StateSpace(entry["A"], entry["B"], entry["C"], entry["D"], float(T), inputs=["gust"],
                              outputs=list(entry.metadata.get("outputs", ["Cl", "Cm"])))


def loads_payload(model, spec: PointSpec, opts, rom_info: dict) -> tuple:
    """``(arrays, metadata)`` of the loads piece of one flight point (see the schema's module docstring).

    Parameters
    ----------
    model : control.StateSpace
        The case's gust ROM.
    spec : PointSpec
    opts : LoadsOptions
    rom_info : dict
        Order, T, M and method of the ROM (stored in the metadata).
    """
    import loads

    t0 = time.process_time()
    point = spec.flight_point()
    system = loads.gust_system(model, point, moment_axes=opts.moment_axes)
    arrays, meta = _search(system, point, spec, opts, opts.outputs)
    return arrays, dict(meta, rom=dict(rom_info), seconds=time.process_time() - t0)


def _search(system, point, spec: PointSpec, opts, outputs) -> tuple:
    """The tuned gusts and turbulence of ``system`` at ``point``: ``(arrays, metadata)`` of a loads piece."""
    import loads

    tg = loads.tuned_gust(system, point, outputs=outputs, H_range=opts.H_range_m,
                          outside_rule=opts.outside_rule, n_grid=opts.n_grid, h_rtol=opts.h_rtol)
    ct = loads.continuous_turbulence(system, point, outputs=outputs, f_max_hz=opts.f_max_hz)
    outs, every = list(tg.outputs), list(tg.all_outputs)

    def vec(d):
        return np.array([float(d[o]) for o in outs])

    arrays = {"peak": vec(tg.peak), "critical_H": vec(tg.critical_H), "gust_sign": vec(tg.gust_sign),
              "peak_time": vec(tg.peak_time), "dimensional": vec(tg.dimensional), "H_tolerance": vec(tg.H_tolerance),
              "correlated": np.array([[float(tg.correlated[x][y]) for y in every] for x in outs]),
              "H_grid": np.asarray(tg.H_grid, dtype=float), "peak_vs_H": np.asarray(tg.peak_vs_H, dtype=float),
              "a_bar": vec(ct.a_bar), "n0": vec(ct.n0), "design": vec(ct.design),
              "design_dimensional": vec(ct.dimensional), "quadrature_error": vec(ct.quadrature_error),
              "truncation_error": vec(ct.truncation_error), "correlation": np.asarray(ct.correlation, dtype=float),
              "Omega": np.asarray(ct.Omega, dtype=float), "psd": np.asarray(ct.psd, dtype=float)}
    for i, o in enumerate(outs):
        arrays[f"h{i}_t"] = np.asarray(tg.times[o], dtype=float)
        arrays[f"h{i}_y"] = np.asarray(tg.histories[o], dtype=float)
        arrays[f"h{i}_gust"] = np.asarray(tg.gust[o], dtype=float)
    scale = dict(zip(system.outputs, (float(s) for s in system.scale)))
    meta = dict(status="ok", point=spec.name, case=spec.case, outputs=outs, all_outputs=every,
                units=[tg.units[o] for o in outs], all_units=list(system.units),
                all_scales=[scale[o] for o in every], n_gradients=int(tg.n_gradients), u_sigma=float(ct.u_sigma),
                atmosphere=dict(rho=point.rho, tas=point.tas, eas=point.eas, q=point.q, time_scale=point.time_scale,
                                speed_of_sound=point.speed_of_sound, u_ref=point.reference_gust_velocity(),
                                F_g=point.F_g),
                source=ct.source)
    return arrays, meta


def flexible_aero(motion_entry, rom, section: FlexibleSpec, lags: int):
    """The motion and gust model of a flexible section, about its elastic axis (:class:`aeroelastic.MotionModel`).

    The motion columns (plunge, pitch) of the stored motion FRF are moved to the elastic axis
    (:func:`aeroelastic.to_elastic_axis`) and fitted in Roger's form (:func:`aeroelastic.fit_motion`, ``lags`` lag
    roots); the gust model is the case's gust ROM (continuous by the inverse bilinear map, which keeps its frequency
    response), its moment moved to the elastic axis, ``Cm_e = Cm_{1/4} + (x_e - 1/4) Cl``.

    Parameters
    ----------
    motion_entry : studies.store.cache entry
        The ``motion_frf`` piece (``H`` (2, 3, K), ``omega`` (K,) in U/c; Cl, Cm and pitch about its ``pivot``).
    rom : control.StateSpace
        The gust ROM (:func:`rom_model`), outputs containing ``Cl`` and ``Cm`` (quarter chord).
    section : FlexibleSpec
    lags : int

    Returns
    -------
    aeroelastic.MotionModel
    """
    import dataclasses

    import aeroelastic as ae
    import control
    import sysid

    from ..aeroelastic.schema import MOTION_INPUTS, MOTION_OUTPUTS, PIVOT

    md = motion_entry.metadata
    inputs = list(md.get("inputs", MOTION_INPUTS))
    frf = sysid.FrequencyResponse.from_continuous(motion_entry["H"], motion_entry["omega"], inputs=inputs,
                                                  outputs=list(md.get("outputs", MOTION_OUTPUTS)))
    ea = ae.to_elastic_axis(frf, section.typical_section(), pivot=float(md.get("pivot", PIVOT)), moment_axis=PIVOT)
    cols = [inputs.index("plunge"), inputs.index("pitch")]
    motion = sysid.FrequencyResponse.from_continuous(np.asarray(ea.H)[:, cols, :], ea.omega,
                                                     inputs=["plunge", "pitch"], outputs=list(ea.outputs))
    model = ae.fit_motion(motion, lags)
    g = sysid.d2c_bilinear(rom) if rom.dt else rom
    outs = list(g.output_labels)
    C, D = np.asarray(g.C, dtype=float), np.asarray(g.D, dtype=float)
    il, im = outs.index("Cl"), outs.index("Cm")
    shift = section.elastic_axis - PIVOT
    C2 = np.vstack([C[il], C[im] + shift * C[il]])
    D2 = np.vstack([D[il], D[im] + shift * D[il]])
    gust = control.ss(np.asarray(g.A, dtype=float), np.asarray(g.B, dtype=float), C2, D2, inputs=["gust"],
                      outputs=["Cl", "Cm"])
    return dataclasses.replace(model, gust=gust, gust_identification=None, gust_max_error=float("nan"))


def flexible_payload(aero, spec: PointSpec, section: FlexibleSpec, opts, rom_info: dict) -> tuple:
    """``(arrays, metadata)`` of the loads piece of one flight point and flexible section.

    The flutter (or divergence) speed of the section at the point's density (``mu = m / (pi rho b^2)``) is found
    first on :data:`FLUTTER_GRID` (:func:`aeroelastic.flutter`); a point at or above it is refused with a
    :class:`loads.LoadsModelError` saying both speeds (stored as the piece's failure).

    Parameters
    ----------
    aero : aeroelastic.MotionModel
        :func:`flexible_aero`.
    spec : PointSpec
    section : FlexibleSpec
    opts : LoadsOptions
    rom_info : dict
        Order, T, M and method of the gust ROM (stored in the metadata).
    """
    import warnings

    import aeroelastic as ae
    import loads

    t0 = time.process_time()
    point = spec.flight_point()
    fs = section.flexible_section(aero)
    sec = fs.typical_section(point)
    V = fs.speed_index(point)
    to_tas = 0.5 * point.chord_m * fs.omega_alpha           # m/s per unit speed index
    lo, hi, n = FLUTTER_GRID
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)     # "stable over the whole grid" is an answer here
        fl = ae.flutter(aero, sec, np.linspace(lo, hi, n) * V)
    flutter = dict(found=bool(fl.found), kind=str(fl.kind), speed_index=float(fl.speed_index),
                   tas=float(fl.speed_index) * to_tas if fl.found else math.nan,
                   frequency_hz=float(fl.frequency_ratio) * fs.omega_alpha / (2 * math.pi) if fl.found else math.nan)
    if fl.found and fl.speed_index <= V:
        raise loads.LoadsModelError(
            f"flexible section {section.name} reaches {fl.kind} at {flutter['tas']:.4g} m/s TAS at {spec.altitude_m:g} m "
            f"(speed index {fl.speed_index:.4g}, mu {sec.mu:.4g}), at or below the flight point's {point.tas:.4g} m/s "
            f"(speed index {V:.4g}): its gust response grows without bound; stiffen the section (f_alpha_hz, "
            "f_h_hz), or leave the point out of it (sections = [...] in its [[loads.points]])")
    system = loads.gust_system(fs, point, moment_axes=opts.moment_axes)
    arrays, meta = _search(system, point, spec, opts, opts.flexible_outputs)
    fit = dict(max_error=float(aero.max_error), rms_error=float(aero.rms_error), poles=[float(p) for p in aero.poles])
    meta = dict(meta, rom=dict(rom_info), section=section.name, mu=float(sec.mu), speed_index=float(V),
                elastic_axis=float(fs.elastic_axis), flutter=flutter, fit=fit, seconds=time.process_time() - t0)
    return arrays, meta


def loads_task(config, case_name: str, root: str, codes: dict, force: bool) -> list:
    """The loads of every flight point of one case that the store lacks (its ROM stored): one piece each.

    Parameters
    ----------
    config : studies.config.schema.StudyConfig
    case_name : str
    root : str
        The store's folder.
    codes : dict
        Piece -> code version pinned by the main process.
    force : bool
        Recompute pieces even when stored.

    Returns
    -------
    list of dict
        One report per piece stored (none when the ROM is missing or failed: the reader says so).
    """
    store = pinned_store(root, codes)
    rom = _rom_entry(config, store, case_name)
    if rom is None or is_failed(rom) or not config.loads.rigid:
        return []
    T, M, order, method = config.loads.rom_of(case_name)
    model = rom_model(rom, T)
    info = dict(order=order, T=T, M=M, method=method)
    points = _points_of(config, case_name)
    reporter = piece_reporter(task_key("loads", case_name))
    reports = []
    for i, spec in enumerate(points):
        key = loads_piece(config, spec)
        if not needs_compute(store, "loads", key, force):
            continue
        if reporter is not None:
            reporter.update(f"flight point {i + 1}/{len(points)}: {spec.name}", f"point {i + 1}/{len(points)}",
                            i / len(points))
        entry, seconds = compute_piece(store, "loads", key,
                                       lambda spec=spec: loads_payload(model, spec, config.loads, info))
        reports.append(piece_report("loads", f"loads {spec.name} (M {spec.mach:g}, {spec.altitude_m:g} m, "
                                             f"c {spec.chord_m:g} m)", entry, seconds))
    return reports


def flexible_task(config, case_name: str, root: str, codes: dict, force: bool) -> list:
    """The flexible sections' loads of every flight point of one case that the store lacks (its ROM and the
    ``[aeroelastic]`` section's motion FRF stored): one piece per point and section.

    Parameters
    ----------
    config, case_name, root, codes, force
        As for :func:`loads_task`.

    Returns
    -------
    list of dict
        One report per piece stored (none when the ROM or the motion FRF is missing or failed: the reader says so).
    """
    store = pinned_store(root, codes)
    rom = _rom_entry(config, store, case_name)
    motion = store.get("motion_frf", motion_key(config, case_name))
    if rom is None or is_failed(rom) or motion is None or is_failed(motion):
        return []
    opts = config.loads
    T, M, order, method = opts.rom_of(case_name)
    model = rom_model(rom, T)
    info = dict(order=order, T=T, M=M, method=method)
    todo = [(p, opts.section(n)) for p in _points_of(config, case_name) for n in p.sections]
    todo = [(p, s) for p, s in todo if needs_compute(store, "loads", flexible_piece(config, p, s), force)]
    reporter = piece_reporter(task_key("flexible loads", case_name))
    fits = {}       # one motion fit per elastic axis (the fit does not depend on mass, frequencies or the point)

    def aero_of(section):
        if section.a not in fits:
            try:
                fits[section.a] = flexible_aero(motion, model, section, opts.lags)
            except Exception as e:  # noqa: BLE001 - raised again inside each piece's compute: stored as its failure
                fits[section.a] = e
        return fits[section.a]

    def compute(spec, section):
        aero = aero_of(section)
        if isinstance(aero, Exception):
            raise aero
        return flexible_payload(aero, spec, section, opts, info)

    reports = []
    for i, (spec, section) in enumerate(todo):
        if reporter is not None:
            reporter.update(f"{spec.name}, section {section.name} ({i + 1}/{len(todo)})", f"{i + 1}/{len(todo)}",
                            i / len(todo))
        entry, seconds = compute_piece(store, "loads", flexible_piece(config, spec, section),
                                       lambda spec=spec, section=section: compute(spec, section))
        reports.append(piece_report("loads", f"loads {spec.name} flexible {section.name} (M {spec.mach:g}, "
                                             f"{spec.altitude_m:g} m, c {spec.chord_m:g} m)", entry, seconds))
    return reports


# ---------------------------------------------------------------------------------------------
# Reading back
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class LoadsRecord:
    """A stored loads piece (arrays as stored; dicts keyed by output).

    Attributes
    ----------
    spec : PointSpec
    outputs : tuple of str
        The outputs searched.
    all_outputs : tuple of str
        Every output of the gust system (columns of ``correlated``, rows of the histories).
    units : dict
        SI unit of each searched output's dimensional load.
    peak, critical_H, gust_sign, peak_time, dimensional, H_tolerance : dict
        The tuned gust (:class:`loads.TunedGustResult`; ``critical_H`` in m, ``peak_time`` in s).
    correlated : dict of dict
        ``correlated[x][y]``: ``y`` at the time of ``x``'s peak (model units).
    a_bar, n0, design, design_dimensional, quadrature_error, truncation_error : dict
        Continuous turbulence (:class:`loads.TurbulenceResult`; ``A_bar`` per m/s TAS, ``N0`` in 1/s).
    correlation : ndarray, shape (p, p)
    u_sigma : float
        ``U_sigma`` (m/s TAS, with ``F_g``).
    atmosphere : dict
        ``rho``, ``tas``, ``eas``, ``q``, ``time_scale``, ``speed_of_sound``, ``u_ref``, ``F_g`` at the point.
    scales : dict
        Factor from model units to SI of every output.
    H_grid, peak_vs_H, Omega, psd : ndarray
    histories : dict
        Output -> ``(t, y, gust)``: times (s), all outputs (q, N) and the gust velocity (m/s) of its critical gust.
    rom : dict
        Order, T, M, method of the ROM.
    n_gradients : int
    seconds : float
        CPU time of the piece (s).
    all_units : tuple of str
        SI unit of every output.
    section : str or None
        The flexible section's name; None for the rigid aerofoil.
    flexible : dict
        For a flexible section: ``mu``, ``speed_index`` (``U / (b omega_alpha)``) at the point, ``elastic_axis``
        (chords), ``flutter`` (``found``, ``kind``, ``speed_index``, ``tas`` in m/s, ``frequency_hz``: the section's
        flutter or divergence at the point's density, up to three times its speed) and ``fit`` (the motion fit's
        ``max_error``, ``rms_error``, lag ``poles``); empty for the rigid aerofoil.
    """

    spec: PointSpec
    outputs: tuple
    all_outputs: tuple
    units: dict
    peak: dict
    critical_H: dict
    gust_sign: dict
    peak_time: dict
    dimensional: dict
    H_tolerance: dict
    correlated: dict
    a_bar: dict
    n0: dict
    design: dict
    design_dimensional: dict
    quadrature_error: dict
    truncation_error: dict
    correlation: Any = field(repr=False)
    u_sigma: float = math.nan
    atmosphere: dict = field(default_factory=dict)
    scales: dict = field(default_factory=dict)
    H_grid: Any = field(default=None, repr=False)
    peak_vs_H: Any = field(default=None, repr=False)
    Omega: Any = field(default=None, repr=False)
    psd: Any = field(default=None, repr=False)
    histories: dict = field(default_factory=dict, repr=False)
    rom: dict = field(default_factory=dict)
    n_gradients: int = 0
    seconds: float = math.nan

    all_units: tuple = ()
    section: Any = None
    flexible: dict = field(default_factory=dict)

    @property
    def model(self) -> str:
        """``"rigid"`` or the flexible section's name."""
        return "rigid" if self.section is None else self.section

    def rho(self, x: str, y: str) -> float:
        """Continuous-turbulence correlation coefficient of outputs ``x`` and ``y``."""
        o = list(self.outputs)
        return float(self.correlation[o.index(x), o.index(y)])

    def results(self) -> tuple:
        """``(loads.TunedGustResult, loads.TurbulenceResult)`` rebuilt from the store, for the ``loads.*_plot``
        functions (their ``system`` holds the outputs' SI factors and units only: no modes)."""
        import loads

        point = self.spec.flight_point()
        q = len(self.all_outputs)
        system = loads.GustSystem(np.zeros(0, complex), np.zeros(0, complex), np.zeros((q, 0), complex),
                                  np.zeros(q), tuple(self.all_outputs),
                                  np.array([self.scales[o] for o in self.all_outputs]), tuple(self.all_units), point)
        tg = loads.TunedGustResult(self.outputs, self.peak, self.critical_H, self.gust_sign, self.peak_time,
                                   self.correlated, self.dimensional, self.units, self.H_tolerance, self.H_grid,
                                   self.peak_vs_H, {o: h[0] for o, h in self.histories.items()},
                                   {o: h[1] for o, h in self.histories.items()},
                                   {o: h[2] for o, h in self.histories.items()}, self.all_outputs, self.n_gradients,
                                   None, point, system)
        ct = loads.TurbulenceResult(self.outputs, self.a_bar, self.n0, self.correlation, self.design,
                                    self.design_dimensional, self.units, self.u_sigma, self.quadrature_error,
                                    self.truncation_error, {}, {}, self.Omega, self.psd, "model", None, point)
        return tg, ct


def _record(spec: PointSpec, e) -> LoadsRecord:
    md = e.metadata
    outs, every = tuple(md["outputs"]), tuple(md["all_outputs"])

    def d(name):
        return {o: float(v) for o, v in zip(outs, e[name])}

    corr = {x: {y: float(v) for y, v in zip(every, row)} for x, row in zip(outs, e["correlated"])}
    hist = {o: (e[f"h{i}_t"], e[f"h{i}_y"], e[f"h{i}_gust"]) for i, o in enumerate(outs)}
    return LoadsRecord(spec=spec, outputs=outs, all_outputs=every, units=dict(zip(outs, md["units"])),
                       peak=d("peak"), critical_H=d("critical_H"), gust_sign=d("gust_sign"), peak_time=d("peak_time"),
                       dimensional=d("dimensional"), H_tolerance=d("H_tolerance"), correlated=corr, a_bar=d("a_bar"),
                       n0=d("n0"), design=d("design"), design_dimensional=d("design_dimensional"),
                       quadrature_error=d("quadrature_error"), truncation_error=d("truncation_error"),
                       correlation=e["correlation"], u_sigma=float(md["u_sigma"]), atmosphere=dict(md["atmosphere"]),
                       scales=dict(zip(every, md["all_scales"])), H_grid=e["H_grid"], peak_vs_H=e["peak_vs_H"],
                       Omega=e["Omega"], psd=e["psd"], histories=hist, rom=dict(md["rom"]),
                       n_gradients=int(md["n_gradients"]), seconds=float(md.get("seconds", math.nan)),
                       all_units=tuple(md["all_units"]), section=md.get("section"),
                       flexible={k: md[k] for k in ("mu", "speed_index", "elastic_axis", "flutter", "fit") if k in md})


def load_loads(config, store) -> list:
    """The stored loads pieces of a study, as :class:`LoadsRecord` (in the order of the flight points; at each, the
    rigid aerofoil first, then its flexible sections in the order of ``[[loads.sections]]``)."""
    opts = config.loads
    if opts is None:
        return []
    records = []
    for spec in opts.points:
        keys = [loads_piece(config, spec)] if opts.rigid else []
        keys += [flexible_piece(config, spec, s) for s in opts.sections if s.name in spec.sections]
        for key in keys:
            e = store.get("loads", key)
            if e is not None and not is_failed(e):
                records.append(_record(spec, e))
    return records
