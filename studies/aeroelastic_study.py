"""The ``[aeroelastic]`` section of a study file: its schema, parsing, store pieces and tasks.

A study may ask for the flutter of typical sections and their gust response, with the aerodynamics of its own
flow cases (``cfd.lfd_response`` with motion inputs, fitted by :func:`aeroelastic.fit_motion`)::

    [aeroelastic]
    cases = ["M02"]                                # flow cases of the study (default: all)
    omega = { min = 0.02, max = 2.0, n = 24 }      # motion FRF frequencies (U/c); 0 is added; or a list
    lags = 4                                       # lag roots of aeroelastic.fit_motion
    gust_order = 8                                 # states of the gust model (sysid.identify inside fit_motion)
    speeds = { min = 0.05, max = 3.0, n = 300 }    # speed indices U/(b omega_alpha) of the root locus; or a list

    [[aeroelastic.sections]]                       # one or more typical sections (Theodorsen's notation)
    name = "HP"
    mu = 20
    a = -0.2
    x_alpha = 0.1
    r_alpha2 = 0.24
    omega_ratio = 0.4
    gust_speed = 1.5                               # optional: gust histories of the study's gusts at this speed

Pieces (kept in the study's :class:`studies.cache.ResultStore` like the others)
-------------------------------------------------------------------------------
=========== ======================================= ===================================================
piece       arrays                                  metadata
=========== ======================================= ===================================================
motion_frf  ``H`` (2, 3, K) complex, ``omega``      ``inputs`` (gust, plunge, pitch), ``outputs``
            (K,) in U/c                             (Cl, Cm about the quarter chord), ``pivot``,
                                                    ``method``, ``seconds``, ``lfd``
flutter     ``speeds`` (N,), ``eigenvalues`` (N, n) ``speed_index``, ``flutter_speed_index``,
            complex, ``modes`` (2,), per gust i:    ``frequency_ratio``, ``reduced_frequency``, ``kind``,
            ``g<i>_t``, ``g<i>_u``, ``g<i>_plunge``, ``found``, ``section``, ``gusts``, ``gust_speed``,
            ``g<i>_pitch``, ``g<i>_Cl``, ``g<i>_Cm``  ``fit`` (fit errors, lag roots), ``seconds``
            (n + 1,)
=========== ======================================= ===================================================

The motion FRF's key holds the steady flow's key (aerofoil, Mach, incidence, grid), the frequencies, the
pivot, the gust method and the code version of ``cfd`` (as the other CFD pieces); the flutter piece's key holds
the motion FRF's key, the section (not its name), the lag count, the speed grid, and for the gust histories the
gusts, the speed and the study's ``dt``, ``t_end``, ``x0``; its code version covers ``cfd``, ``sysid``,
``aeroelastic`` and this module (:data:`AEROELASTIC_DEPENDENCIES`). A failed piece is stored as such and
computed again by the next run.
"""

from __future__ import annotations

import difflib
import math
import time
from dataclasses import dataclass
from typing import Any, Mapping, Optional

import numpy as np

__all__ = [
    "AeroelasticOptions",
    "SectionSpec",
    "AEROELASTIC_KEYS",
    "SECTION_KEYS",
    "AEROELASTIC_PIECES",
    "AEROELASTIC_DEPENDENCIES",
    "DEFAULT_OMEGA",
    "MOTION_INPUTS",
    "MOTION_OUTPUTS",
    "PIVOT",
    "parse_aeroelastic",
    "motion_frf_piece",
    "flutter_piece",
    "gust_time",
    "aeroelastic_plan",
    "aeroelastic_status",
    "motion_frf_task",
    "flutter_task",
    "FlutterRecord",
    "load_flutter",
]

AEROELASTIC_KEYS = ("cases", "omega", "lags", "gust_order", "speeds", "sections")
SECTION_KEYS = ("name", "mu", "a", "x_alpha", "r_alpha2", "omega_ratio", "gust_speed")
RANGE_KEYS = ("min", "max", "n")

AEROELASTIC_PIECES = ("motion_frf", "flutter")
"""The store pieces of the ``[aeroelastic]`` section, in the order a case computes them."""

AEROELASTIC_DEPENDENCIES = {
    "motion_frf": ("cfd",),
    "flutter": ("cfd", "sysid", "aeroelastic", "studies.aeroelastic_study"),
}
"""Packages and modules whose sources enter the keys of the aeroelastic pieces (merged into
:data:`studies.cache.PIECE_DEPENDENCIES`)."""

DEFAULT_OMEGA = (0.0,) + tuple(float(w) for w in np.geomspace(0.02, 2.0, 24))
"""Default motion frequencies (U/c): 0 (the static derivatives, kept exactly by the fit) and 24 log-spaced
from 0.02 to 2 (``k`` up to 1; flutter of the usual sections is near ``k = 0.3``, and above ``k ~ 1`` the
compressible loads leave Roger's polynomial asymptote: docs/aeroelastic.md section 4)."""

MOTION_INPUTS = ("gust", "plunge", "pitch")
MOTION_OUTPUTS = ("Cl", "Cm")
PIVOT = 0.25
"""Pitch axis of the motion FRF (chords from the leading edge); ``Cm`` is about the quarter chord too."""

MAX_OMEGA_POINTS = 400
MAX_SPEEDS = 20000
MAX_LAGS = 12


# ---------------------------------------------------------------------------------------------
# Schema
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class SectionSpec:
    """A typical section of the study (Theodorsen's notation, see docs/aeroelastic.md).

    Attributes
    ----------
    name : str
    mu : float
        Mass ratio ``m / (pi rho b^2)``.
    a : float
        Elastic axis aft of mid-chord (semichords).
    x_alpha : float
        Centre of mass aft of the elastic axis (semichords).
    r_alpha2 : float
        Radius of gyration squared about the elastic axis (semichords squared).
    omega_ratio : float
        ``omega_h / omega_alpha``.
    gust_speed : float or None
        Speed index ``U / (b omega_alpha)`` of the flexible section's gust histories; None: none.
    """

    name: str
    mu: float
    a: float
    x_alpha: float
    r_alpha2: float
    omega_ratio: float
    gust_speed: Optional[float] = None

    def section(self):
        """The :class:`aeroelastic.TypicalSection`."""
        from aeroelastic import TypicalSection

        return TypicalSection(mu=self.mu, a=self.a, x_alpha=self.x_alpha, r_alpha2=self.r_alpha2,
                              omega_ratio=self.omega_ratio)

    def canonical(self) -> dict:
        """Everything that changes the results (not the name)."""
        return dict(mu=self.mu, a=self.a, x_alpha=self.x_alpha, r_alpha2=self.r_alpha2,
                    omega_ratio=self.omega_ratio)


@dataclass(frozen=True)
class AeroelasticOptions:
    """The validated ``[aeroelastic]`` section.

    Attributes
    ----------
    cases : tuple of str
        Names of the study's flow cases whose aerodynamics are used.
    omega : tuple of float
        Motion FRF frequencies (U/c), increasing, finite, the first 0.
    lags : int
        Lag roots of :func:`aeroelastic.fit_motion`.
    gust_order : int
        States of the gust column's model (``fit_motion(..., gust_order=)``); the subspace step needs about
        ``1.5 gust_order`` frequencies or more.
    speeds : tuple of float or None
        Speed indices of the root locus, increasing; None: :func:`aeroelastic.flutter`'s default
        (``V_f`` from 0.02 to 3 for each section).
    sections : tuple of SectionSpec
    """

    cases: tuple
    omega: tuple = DEFAULT_OMEGA
    lags: int = 4
    gust_order: int = 8
    speeds: Optional[tuple] = None
    sections: tuple = ()

    def canonical(self) -> dict:
        """The hashable content (for :meth:`studies.schema.StudyConfig.canonical`)."""
        return dict(cases=list(self.cases), omega=list(self.omega), lags=self.lags,
                    gust_order=self.gust_order, speeds=None if self.speeds is None else list(self.speeds),
                    sections=[dict(s.canonical(), name=s.name, gust_speed=s.gust_speed) for s in self.sections])


def _error(source, key, problem):
    from .config import StudyConfigError

    return StudyConfigError(source, key, problem)


def _suggest(word, options) -> str:
    if not isinstance(word, str):
        return ""
    low = {o.lower(): o for o in options}
    if word.lower() in low:
        return f" (did you mean {low[word.lower()]!r}?)"
    close = difflib.get_close_matches(word, list(options), n=1, cutoff=0.6)
    return f" (did you mean {close[0]!r}?)" if close else ""


def _check_keys(source, table, allowed, prefix):
    for k in table:
        if k not in allowed:
            raise _error(source, f"{prefix}.{k}", f"unknown key{_suggest(k, allowed)}; allowed here: "
                                                   f"{', '.join(allowed)}")


def _number(source, value, key, *, positive=False) -> float:
    from .numbers import normalise_float, parse_number

    try:
        v = parse_number(value)
    except ValueError as e:
        raise _error(source, key, str(e)) from None
    if not math.isfinite(v):
        raise _error(source, key, f"must be finite, got {v!r}")
    if positive and v <= 0.0:
        raise _error(source, key, f"must be positive, got {v!r}")
    return normalise_float(v)


def _integer(source, value, key, lo, hi) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        raise _error(source, key, f"must be an integer, got {value!r}")
    if not lo <= value <= hi:
        raise _error(source, key, f"must be between {lo} and {hi}, got {value}")
    return int(value)


def _range_or_list(source, value, key, *, zero: bool, max_n: int, what: str) -> tuple:
    """A grid given as ``{min, max, n}`` (log-spaced for frequencies, linear for speeds) or as a list."""
    if isinstance(value, dict):
        _check_keys(source, value, RANGE_KEYS, key)
        for req in RANGE_KEYS:
            if req not in value:
                raise _error(source, f"{key}.{req}", f"missing: give min, max and n (or a list of {what})")
        lo = _number(source, value["min"], f"{key}.min", positive=True)
        hi = _number(source, value["max"], f"{key}.max", positive=True)
        n = _integer(source, value["n"], f"{key}.n", 2, max_n)
        if hi <= lo:
            raise _error(source, key, f"max ({hi:g}) must be above min ({lo:g})")
        grid = np.geomspace(lo, hi, n) if zero else np.linspace(lo, hi, n)
        vals = ([0.0] if zero else []) + [float(v) for v in grid]
    elif isinstance(value, list):
        if not 2 <= len(value) <= max_n:
            raise _error(source, key, f"give 2 to {max_n} {what}, got {len(value)}")
        vals = [_number(source, v, f"{key}[{i}]") for i, v in enumerate(value)]
        if any(v < 0 for v in vals) or (not zero and vals[0] <= 0):
            raise _error(source, key, f"{what} must be {'>= 0' if zero else 'positive'}")
        if any(b <= a for a, b in zip(vals, vals[1:])):
            raise _error(source, key, f"{what} must be strictly increasing")
        if zero and vals[0] != 0.0:
            vals = [0.0] + vals  # the fit keeps the static derivatives exactly from omega = 0
    else:
        raise _error(source, key, f"must be a table {{ min = ..., max = ..., n = ... }} or a list of {what}, got "
                                  f"{value!r}")
    return tuple(vals)


def parse_aeroelastic(table: Any, source: str, cases: tuple, gusts: tuple) -> AeroelasticOptions:
    """Validate the ``[aeroelastic]`` table of a study file.

    Parameters
    ----------
    table : dict
        The parsed TOML table.
    source : str
        The study file (for the messages).
    cases : tuple of studies.schema.CaseSweep
        The study's cases.
    gusts : tuple of studies.cases.GustCase
        The study's gusts (the flexible section's gust histories use them all).

    Returns
    -------
    AeroelasticOptions

    Raises
    ------
    studies.config.StudyConfigError
        Naming the dotted key (``aeroelastic.sections[0].mu``) and what to do.
    """
    if not isinstance(table, dict):
        raise _error(source, "aeroelastic", f"must be a table, got {type(table).__name__} {table!r}")
    _check_keys(source, table, AEROELASTIC_KEYS, "aeroelastic")
    names = [c.case.name for c in cases]
    wanted = table.get("cases", names)
    if isinstance(wanted, str):
        wanted = [wanted]
    if not isinstance(wanted, list) or not wanted:
        raise _error(source, "aeroelastic.cases", f"must be a non-empty list of case names, got {wanted!r}")
    chosen = []
    for i, w in enumerate(wanted):
        match = [n for n in names if isinstance(w, str) and n.casefold() == w.casefold()]
        if not match:
            raise _error(source, f"aeroelastic.cases[{i}]",
                         f"{w!r} is not a case of this study{_suggest(w, names)}; its cases: {', '.join(names)}")
        if match[0] in chosen:
            raise _error(source, f"aeroelastic.cases[{i}]", f"case {match[0]!r} appears twice")
        chosen.append(match[0])
    omega = (_range_or_list(source, table["omega"], "aeroelastic.omega", zero=True, max_n=MAX_OMEGA_POINTS,
                            what="frequencies") if "omega" in table else DEFAULT_OMEGA)
    lags = _integer(source, table.get("lags", 4), "aeroelastic.lags", 0, MAX_LAGS)
    gust_order = _integer(source, table.get("gust_order", 8), "aeroelastic.gust_order", 1, 40)
    speeds = (_range_or_list(source, table["speeds"], "aeroelastic.speeds", zero=False, max_n=MAX_SPEEDS,
                             what="speed indices") if "speeds" in table else None)
    raw = table.get("sections")
    if raw is None:
        raise _error(source, "aeroelastic.sections", "missing: give at least one [[aeroelastic.sections]] with "
                                                     "name, mu, a, x_alpha, r_alpha2, omega_ratio")
    if isinstance(raw, dict):
        raw = [raw]
    if not isinstance(raw, list) or not raw:
        raise _error(source, "aeroelastic.sections", "must be a list of tables ([[aeroelastic.sections]])")
    sections = []
    for i, entry in enumerate(raw):
        sections.append(_parse_section(source, entry, f"aeroelastic.sections[{i}]", gusts))
    seen = [s.name.casefold() for s in sections]
    for i, n in enumerate(seen):
        if seen.index(n) != i:
            raise _error(source, f"aeroelastic.sections[{i}].name",
                         f"section {sections[i].name!r} appears twice; give each section its own name")
    return AeroelasticOptions(cases=tuple(chosen), omega=omega, lags=lags, gust_order=gust_order, speeds=speeds, sections=tuple(sections))


def _parse_section(source, entry, key, gusts) -> SectionSpec:
    from aeroelastic import SectionError

    if not isinstance(entry, dict):
        raise _error(source, key, f"must be a table, got {entry!r}")
    _check_keys(source, entry, SECTION_KEYS, key)
    for req in SECTION_KEYS[:-1]:
        if req not in entry:
            raise _error(source, f"{key}.{req}", "missing: a section needs name, mu, a, x_alpha, r_alpha2, "
                                                 "omega_ratio (Theodorsen's notation, docs/aeroelastic.md)")
    name = entry["name"]
    if not isinstance(name, str) or not name.strip() or not all(c.isalnum() or c in "-_." for c in name):
        raise _error(source, f"{key}.name", f"{name!r} must be a non-empty name of letters, digits, '-', '_', '.'")
    vals = {k: _number(source, entry[k], f"{key}.{k}") for k in SECTION_KEYS[1:-1]}
    gust_speed = None
    if "gust_speed" in entry:
        gust_speed = _number(source, entry["gust_speed"], f"{key}.gust_speed", positive=True)
        if not gusts:
            raise _error(source, f"{key}.gust_speed", "the study has no gusts: add gusts = [...] or leave "
                                                      "gust_speed out")
    spec = SectionSpec(name=name, gust_speed=gust_speed, **vals)
    try:
        spec.section()
    except SectionError as e:
        msg = str(e)
        bad = next((k for k in SECTION_KEYS[1:-1] if msg.startswith(k) or f" {k}" in msg.split(":")[0]), None)
        raise _error(source, f"{key}.{bad}" if bad else key, msg) from None
    return spec


# ---------------------------------------------------------------------------------------------
# Piece keys
# ---------------------------------------------------------------------------------------------

def motion_frf_piece(case, omega, cfd_options) -> dict:
    """Key of the motion FRF of a flow case: its steady flow, the frequencies, pivot, inputs and gust method.

    Parameters
    ----------
    case : studies.cases.FlowCase
    omega : sequence of float
        Frequencies (U/c).
    cfd_options : studies.schema.CFDOptions
    """
    from .pieces import steady_piece

    return dict(steady=steady_piece(case), omega=[float(w) for w in omega], inputs=list(MOTION_INPUTS),
                outputs=list(MOTION_OUTPUTS), pivot=PIVOT, gust_method=cfd_options.gust_method)


def flutter_piece(config, case, spec: SectionSpec) -> dict:
    """Key of the flutter piece of one flow case and section (with its gust histories when asked for)."""
    opts = config.aeroelastic
    key = dict(motion=motion_frf_piece(case, opts.omega, config.cfd), section=spec.canonical(), lags=opts.lags,
               gust_order=opts.gust_order,
               speeds=None if opts.speeds is None else list(opts.speeds))
    if spec.gust_speed is not None:
        sim = config.simulation
        key["gust"] = dict(speed=spec.gust_speed, dt=sim.dt, t_end=sim.t_end, x0=sim.x0,
                           gusts=[dict(kind=g.kind, length=g.length, angle_deg=g.angle_deg) for g in config.gusts])
    return key


def _case(config, name):
    return config.case(name).case


def aeroelastic_plan(config, store, force: bool) -> dict:
    """What the store lacks: case name -> ``{"motion": bool, "flutter": int}`` (empty without the section)."""
    from .tasks import needs_compute

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
    """``(missing, failed)`` lists of the aeroelastic pieces (for :func:`studies.results.load_results`)."""
    from .pieces import is_failed

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

    from .cases import to_gust

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
    fit = dict(max_error=float(model.max_error), rms_error=float(model.rms_error),
               gust_max_error=float(model.gust_max_error), poles=[float(p) for p in model.poles])
    meta = dict(status="ok", speed_index=float(res.speed_index), flutter_speed_index=float(res.flutter_speed_index),
                frequency_ratio=float(res.frequency_ratio), reduced_frequency=float(res.reduced_frequency),
                kind=str(res.kind), found=bool(res.found), section=spec.name, gusts=gusts,
                gust_speed=spec.gust_speed, fit=fit, seconds=time.perf_counter() - t0)
    return arrays, meta


def motion_frf_task(config, case_name: str, root: str, codes: dict) -> list:
    """The motion frequency response of one flow case (its steady flow stored): one ``motion_frf`` piece.

    ``cfd.lfd_response(lin, omega, inputs=("gust", "plunge", "pitch"), pivot=0.25)`` on the section's ``omega``;
    ``H`` has shape (2, 3, K): Cl and Cm (quarter chord) per unit gust angle, plunge ``h / c`` (up) and pitch
    (rad, nose up about the quarter chord).

    Parameters
    ----------
    config : studies.schema.StudyConfig
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
    from .progress import piece_reporter, task_key
    from .tasks import compute_piece, load_linear_system, piece_report, pinned_store

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
    from .pieces import is_failed
    from .tasks import compute_piece, needs_compute, piece_report, pinned_store

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
    seconds: float
    motion_seconds: float


def load_flutter(config, store) -> list:
    """The stored flutter pieces of a study, as :class:`FlutterRecord` (case order, then section order)."""
    import aeroelastic as ae

    from .pieces import is_failed

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
                                         fit=dict(md.get("fit", {})), seconds=_f(md.get("seconds")),
                                         motion_seconds=motion_s))
    return records


def _f(v) -> float:
    return float("nan") if v is None else float(v)

