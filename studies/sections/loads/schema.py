"""The ``[loads]`` section of a study file: its schema, parsing and store keys (tasks and reader:
:mod:`studies.sections.loads.study`; report: :mod:`studies.sections.loads.report`).

A study may ask for the certification gust loads of CS-25.341 (:mod:`loads`: tuned discrete 1-cosine gusts and
continuous von Karman turbulence) of its rigid aerofoil and of flexible sections at flight points, from one of its
own gust ROMs per case::

    [loads]
    order = 10                        # the ROM (default: the case's highest order of the sweep)
    method = "dc_stable"              # a [methods] variant (default: the first with dc_gain = "match", stable = true)
    T = "70/(2*pi)"                   # default: the case's first T of the sweep
    M = 64                            # default: M_base
    outputs = ["Cl", "Cm"]            # default: the study's [cfd] outputs
    moment_axes = [0.4]               # extra moments about these axes (chords from the leading edge)
    H_range_m = [9.144, 106.68]       # gust gradients H (m); default the rule's 30 to 350 ft
    outside_rule = false              # needed for an H_range_m outside 30 - 350 ft
    n_grid = 24                       # first, geometric grid of H of the search (loads.tuned_gust)
    h_rtol = 1e-4                     # relative width of the final bracket of the critical H
    f_max_hz = 50.0                   # optional cut-off of the N0 integral (a ROM with a feedthrough)
    rigid = true                      # false: flexible sections only
    flexible_outputs = ["Cl", "load_factor", "plunge_spring", "pitch_spring"]   # default DEFAULT_FLEXIBLE_OUTPUTS

    [[loads.sections]]                # optional: flexible sections (loads.FlexibleSection), dimensional
    name = "wing"
    mass_kg_m = 800.0                 # mass per unit span (kg/m)
    a = -0.2                          # elastic axis, centre of mass, radius of gyration squared (semichords),
    x_alpha = 0.1                     # as aeroelastic.TypicalSection
    r_alpha2 = 0.24
    f_h_hz = 2.0                      # uncoupled plunge and pitch frequencies (Hz)
    f_alpha_hz = 6.0
    damping = 0.02                    # modal damping ratio(s) (default 0.02)

    [[loads.points]]                  # one or more; each case fixes the aerofoil and the Mach number
    case = "M0.5"
    altitude_m = [0, 4000, 8000]      # one flight point per altitude (m, geopotential)
    chord_m = 3.0
    F_g = 1.0                         # or z_mo_m, mlw_mtow, mzfw_mtow (loads.alleviation_factor at each altitude)
    design_speed = "VC"               # or "VD" (half the gust velocities)
    name = "cruise"                   # optional (one altitude only); default "<case>@<altitude>m"
    sections = ["wing"]               # its flexible sections (default: all; [] for rigid loads only)

Every flight point is built at parse time (:class:`loads.FlightPoint`), so that a Mach number, altitude, chord
or ``F_g`` outside the rule's or the atmosphere's range is refused before any CFD. A flexible section's
aerodynamics are the case's motion FRF of the ``[aeroelastic]`` section (its ``motion_frf`` piece, fitted with its
``lags``) and the case's gust ROM: a flexible point whose case is not among ``[aeroelastic] cases`` is refused at
parse time (the section reads the ``[aeroelastic]`` options from
:attr:`studies.sections.protocol.StudyTables.sections`), and so are section parameters that
:class:`aeroelastic.TypicalSection` refuses.

Piece (kept in the study's :class:`studies.store.cache.ResultStore` like the others)
-------------------------------------------------------------------------------
====== ================================================= =================================================
piece  arrays                                            metadata
====== ================================================= =================================================
loads  ``peak``, ``critical_H``, ``gust_sign``,          ``outputs``, ``all_outputs``, ``units``,
       ``peak_time``, ``dimensional``, ``H_tolerance``,  ``point`` (rho, TAS, EAS, q, c/U, U_ref, U_sigma,
       ``a_bar``, ``n0``, ``design``,                    F_g), ``n_gradients``, ``u_sigma``,
       ``design_dimensional``, ``quadrature_error``,     ``rom`` (its order, T, M, method), ``seconds``
       ``truncation_error`` (p,); ``correlated`` (p, q);
       ``correlation`` (p, p); ``H_grid`` (K,),
       ``peak_vs_H`` (p, K); ``Omega`` (J,), ``psd``
       (p, J); per output i: ``h<i>_t``, ``h<i>_gust``
       (N,), ``h<i>_y`` (q, N)
====== ================================================= =================================================

``p`` outputs searched, ``q`` all outputs of the gust system (the searched ones and the extra moments). The key
holds the ROM piece's key (:func:`studies.sections.gust_rom.pieces.rom_piece`: steady flow, FRF grid, order, M,
method), the flight point (Mach, altitude, chord, ``F_g``, design speed: not its name), the outputs, moment axes and
the search settings (:func:`loads_piece`). A flexible section's piece (:func:`flexible_piece`) has the same arrays,
and in its metadata ``section``, ``mu``, ``speed_index``, ``elastic_axis``, ``flutter`` (the section's flutter or
divergence at the point: ``found``, ``kind``, ``speed_index``, ``tas``, ``frequency_hz``) and ``fit`` (the motion
fit's errors and lag roots); its key holds the ROM piece's key, the ``motion_frf`` piece's key
(:func:`motion_key`) and the lag count, the point, the section's parameters (not its name), the flexible outputs,
moment axes and the search settings. The code version covers ``sysid``, ``loads``, ``aeroelastic`` and this
section's modules (:data:`LOADS_DEPENDENCIES`). A failed piece is stored as such and computed again by the next run.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable, Optional

from ...config.numbers import normalise_float, parse_number
from ...config.reader import did_you_mean, table_array

__all__ = [
    "LoadsOptions",
    "PointSpec",
    "FlexibleSpec",
    "LOADS_KEYS",
    "POINT_KEYS",
    "SECTION_KEYS",
    "FLEXIBLE_OUTPUTS",
    "DEFAULT_FLEXIBLE_OUTPUTS",
    "LOADS_PIECES",
    "LOADS_DEPENDENCIES",
    "LOADS_ARRAYS",
    "parse_loads",
    "describe",
    "rom_point",
    "loads_piece",
    "flexible_piece",
    "motion_key",
]

LOADS_KEYS = ("order", "method", "T", "M", "outputs", "moment_axes", "H_range_m", "outside_rule", "n_grid", "h_rtol",
              "f_max_hz", "rigid", "flexible_outputs", "sections", "points")
POINT_KEYS = ("case", "altitude_m", "chord_m", "F_g", "z_mo_m", "mlw_mtow", "mzfw_mtow", "design_speed", "name",
              "sections")
SECTION_KEYS = ("name", "mass_kg_m", "a", "x_alpha", "r_alpha2", "f_h_hz", "f_alpha_hz", "damping")
"""Keys of a ``[[loads.sections]]`` table (a flexible section, :class:`loads.FlexibleSection`)."""

FLEXIBLE_OUTPUTS = ("Cl", "Cm", "load_factor", "plunge", "pitch", "plunge_rate", "pitch_rate", "plunge_acc",
                    "pitch_acc", "plunge_spring", "pitch_spring")
"""Outputs of a flexible section's gust system (:mod:`loads.flexible`; ``Cm`` about the elastic axis)."""

DEFAULT_FLEXIBLE_OUTPUTS = ("Cl", "Cm", "load_factor", "plunge", "pitch", "pitch_acc", "plunge_spring", "pitch_spring")
"""The flexible outputs searched by default: the plunge acceleration as the load factor (in g), ``Cm`` about the
elastic axis; moments about ``moment_axes`` (``Cm@x``) and the rates when listed in ``flexible_outputs``."""

DEFAULT_DAMPING = 0.02
"""Modal damping ratio of a flexible section when none is given (:class:`loads.FlexibleSection`'s default)."""
FG_INPUTS = ("z_mo_m", "mlw_mtow", "mzfw_mtow")

LOADS_PIECES = ("loads",)
"""The store pieces of the ``[loads]`` section."""

LOADS_DEPENDENCIES = {"loads": ("sysid", "loads", "aeroelastic", "studies.sections.loads.schema",
                                "studies.sections.loads.study")}
"""Packages and modules whose sources enter the keys of the loads pieces."""

LOADS_ARRAYS = ("peak", "critical_H", "a_bar", "n0", "design", "correlation", "H_grid", "peak_vs_H")
"""Arrays a stored loads piece must hold."""

MAX_POINTS = 500
MAX_AXES = 8
MAX_SECTIONS = 20


@dataclass(frozen=True)
class PointSpec:
    """A flight point of the study.

    Attributes
    ----------
    name : str
    case : str
        The study's case (aerofoil, Mach number, incidence, grid).
    mach : float
        The case's Mach number.
    altitude_m, chord_m : float
    F_g : float
        Flight profile alleviation factor in (0, 1] (given, or from ``fg_inputs`` at the altitude).
    design_speed : {"VC", "VD"}
    fg_inputs : tuple or None
        ``(z_mo_m, mlw_mtow, mzfw_mtow)`` when ``F_g`` was computed from them.
    sections : tuple of str
        The flexible sections (names of :attr:`LoadsOptions.sections`) whose loads are computed at this point.
    """

    name: str
    case: str
    mach: float
    altitude_m: float
    chord_m: float
    F_g: float = 1.0
    design_speed: str = "VC"
    fg_inputs: Optional[tuple] = None
    sections: tuple = ()

    def flight_point(self):
        """The :class:`loads.FlightPoint`."""
        from loads import FlightPoint

        return FlightPoint(mach=self.mach, altitude_m=self.altitude_m, chord_m=self.chord_m, F_g=self.F_g,
                           design_speed=self.design_speed)

    def canonical(self) -> dict:
        """What changes the results (not the name)."""
        return dict(mach=self.mach, altitude_m=self.altitude_m, chord_m=self.chord_m, F_g=self.F_g,
                    design_speed=self.design_speed)


@dataclass(frozen=True)
class FlexibleSpec:
    """A flexible section of the study (dimensional, as :class:`loads.FlexibleSection` takes it).

    Attributes
    ----------
    name : str
    mass_kg_m : float
        Mass per unit span (kg/m).
    a, x_alpha, r_alpha2 : float
        Elastic axis aft of mid-chord, centre of mass aft of it (semichords), radius of gyration squared about it
        (semichords^2), as :class:`aeroelastic.TypicalSection`.
    f_h_hz, f_alpha_hz : float
        Uncoupled plunge and pitch frequencies (Hz).
    damping : tuple of float
        Modal damping ratios of the two in-vacuo modes (ascending frequency).
    """

    name: str
    mass_kg_m: float
    a: float
    x_alpha: float
    r_alpha2: float
    f_h_hz: float
    f_alpha_hz: float
    damping: tuple = (DEFAULT_DAMPING, DEFAULT_DAMPING)

    @property
    def elastic_axis(self) -> float:
        """Chords from the leading edge, ``(1 + a) / 2``."""
        return 0.5 * (1.0 + self.a)

    def typical_section(self, mu: float = 1.0):
        """The :class:`aeroelastic.TypicalSection` with mass ratio ``mu`` (the axes and damping are the section's)."""
        from aeroelastic import TypicalSection

        return TypicalSection(mu=mu, a=self.a, x_alpha=self.x_alpha, r_alpha2=self.r_alpha2,
                              omega_ratio=self.f_h_hz / self.f_alpha_hz, damping=self.damping)

    def flexible_section(self, aero):
        """The :class:`loads.FlexibleSection` with the motion and gust model ``aero`` (about the elastic axis)."""
        from loads import FlexibleSection

        return FlexibleSection(aero, mass=self.mass_kg_m, a=self.a, x_alpha=self.x_alpha, r_alpha2=self.r_alpha2,
                               omega_h=2.0 * math.pi * self.f_h_hz, omega_alpha=2.0 * math.pi * self.f_alpha_hz,
                               damping=self.damping)

    def canonical(self) -> dict:
        """What changes the results (not the name)."""
        return dict(mass_kg_m=self.mass_kg_m, a=self.a, x_alpha=self.x_alpha, r_alpha2=self.r_alpha2,
                    f_h_hz=self.f_h_hz, f_alpha_hz=self.f_alpha_hz, damping=list(self.damping))


@dataclass(frozen=True)
class LoadsOptions:
    """The validated ``[loads]`` section.

    Attributes
    ----------
    rom : dict
        Case name -> ``(T, M, order, method name)`` of the ROM each case's points use.
    outputs : tuple of str
        Outputs searched (the ROM's outputs and the extra moments).
    moment_axes : tuple of float
    H_range_m : tuple of float or None
        None: the rule's 30 - 350 ft.
    outside_rule : bool
    n_grid : int
    h_rtol : float
    f_max_hz : float or None
    points : tuple of PointSpec
    rigid : bool
        Compute the rigid aerofoil's loads at every point (the ROM alone).
    sections : tuple of FlexibleSpec
        The flexible sections (each point names those it has: :attr:`PointSpec.sections`).
    flexible_outputs : tuple of str
        Outputs searched for the flexible sections (:data:`FLEXIBLE_OUTPUTS` and the extra moments).
    motion_omega : tuple of float
        Frequencies (U/c) of the ``[aeroelastic]`` section's motion FRF the flexible sections use (empty without
        flexible sections).
    lags : int
        Lag roots of the motion fit (:func:`aeroelastic.fit_motion`), the ``[aeroelastic]`` section's.
    """

    rom: tuple
    outputs: tuple
    moment_axes: tuple = ()
    H_range_m: Optional[tuple] = None
    outside_rule: bool = False
    n_grid: int = 24
    h_rtol: float = 1e-4
    f_max_hz: Optional[float] = None
    points: tuple = ()
    rigid: bool = True
    sections: tuple = ()
    flexible_outputs: tuple = ()
    motion_omega: tuple = ()
    lags: int = 4

    @property
    def cases(self) -> tuple:
        """The cases of the flight points, in the order they first appear."""
        return tuple(dict.fromkeys(p.case for p in self.points))

    @property
    def flexible_cases(self) -> tuple:
        """The cases with flexible sections at some point, in the order they first appear."""
        return tuple(dict.fromkeys(p.case for p in self.points if p.sections))

    def section(self, name: str) -> FlexibleSpec:
        """The flexible section called ``name``."""
        return next(s for s in self.sections if s.name == name)

    def rom_of(self, case: str) -> tuple:
        """``(T, M, order, method name)`` of the ROM of ``case``."""
        return dict(self.rom)[case]

    def search(self, flexible: bool = False) -> dict:
        """The search settings of every piece's key (``flexible``: with the flexible sections' outputs)."""
        return dict(outputs=list(self.flexible_outputs if flexible else self.outputs),
                    moment_axes=list(self.moment_axes),
                    H_range_m=None if self.H_range_m is None else list(self.H_range_m),
                    outside_rule=self.outside_rule, n_grid=self.n_grid, h_rtol=self.h_rtol, f_max_hz=self.f_max_hz)

    def canonical(self) -> dict:
        """The hashable content (for :meth:`studies.config.schema.StudyConfig.canonical`)."""
        out = dict(rom={c: list(v) for c, v in self.rom}, **self.search(),
                   points=[dict(p.canonical(), name=p.name, case=p.case, **({"sections": list(p.sections)}
                                                                           if p.sections else {}))
                           for p in self.points])
        if not self.rigid:      # only what differs from a rigid-only section (whose hash stays as it was)
            out["rigid"] = False
        if self.sections:
            out.update(sections=[dict(s.canonical(), name=s.name) for s in self.sections],
                       flexible_outputs=list(self.flexible_outputs), motion_omega=list(self.motion_omega),
                       lags=self.lags)
        return out


# ---------------------------------------------------------------------------------------------
# Parsing
# ---------------------------------------------------------------------------------------------

def _hint(word, options) -> str:
    return did_you_mean(word, options) if isinstance(word, str) else ""


def _check_keys(error, table, allowed, prefix):
    for k in table:
        if k not in allowed:
            raise error(f"{prefix}.{k}", f"unknown key{_hint(k, allowed)}; allowed here: {', '.join(allowed)}")


def _number(error, value, key, *, positive=False) -> float:
    if isinstance(value, bool):
        raise error(key, f"must be a number, got {value!r}")
    try:
        v = parse_number(value)
    except ValueError as e:
        raise error(key, str(e)) from None
    if not math.isfinite(v):
        raise error(key, f"must be finite, got {v!r}")
    if positive and v <= 0.0:
        raise error(key, f"must be positive, got {v!r}")
    return normalise_float(v)


def _integer(error, value, key, lo, hi) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        raise error(key, f"must be an integer, got {value!r}")
    if not lo <= value <= hi:
        raise error(key, f"must be between {lo} and {hi}, got {value}")
    return int(value)


def _pick(error, key, value, options, what, fmt=str):
    """The element of ``options`` that ``value`` names (numbers to 1e-9 relative)."""
    for o in options:
        if isinstance(o, float) and not isinstance(value, bool):
            try:
                v = parse_number(value)
            except ValueError as e:
                raise error(key, str(e)) from None
            if abs(v - o) <= 1e-9 * abs(o):
                return o
        elif value == o:
            return o
    raise error(key, f"{value!r} is not {what}{_hint(value, [str(o) for o in options])}; "
                     f"the sweep has {', '.join(fmt(o) for o in options)}")


def _default_method(error, methods) -> str:
    names = [m.name for m in methods]
    good = [m.name for m in methods if m.dc_gain == "match" and m.stable]
    if good:
        return good[0]
    if len(names) == 1:
        raise error("loads.method", f"the study's only method {names[0]!r} does not impose the DC gain and "
                    "stability; give method = \"" + names[0] + "\" to use it anyway, or add a variant "
                    "[methods.dc_stable] dc_gain = \"match\", stable = true (a ROM that may be unstable cannot "
                    "give gust loads)")
    raise error("loads.method", f"none of the study's methods ({', '.join(names)}) has dc_gain = \"match\" and "
                "stable = true; name the one to use (method = \"...\")")


def parse_loads(table: Any, error: Callable[[str, str], Exception], study) -> LoadsOptions:
    """Validate the ``[loads]`` table of a study file.

    Parameters
    ----------
    table : dict
        The parsed TOML table.
    error : callable
        ``error(dotted_key, problem) -> Exception`` (a :class:`studies.config.StudyConfigError` naming the file).
    study : studies.sections.protocol.StudyTables
        The study's cases (with their sweeps), methods, ``M_base`` and ``[cfd]`` outputs.

    Returns
    -------
    LoadsOptions

    Raises
    ------
    studies.config.StudyConfigError
        Naming the dotted key (``loads.points[0].altitude_m``) and what to do: an unknown key or case, a ROM the
        sweep does not identify, an output the ROMs do not have, a flight point :class:`loads.FlightPoint`
        refuses (Mach, altitude, chord, ``F_g``), an H range outside the rule's without ``outside_rule``.
    """
    from loads import FlightPointError, alleviation_factor
    from loads.atmosphere import FT, H_RANGE_FT, RULE_MAX_ALTITUDE

    if not isinstance(table, dict):
        raise error("loads", f"must be a table, got {type(table).__name__} {table!r}")
    _check_keys(error, table, LOADS_KEYS, "loads")
    sweeps = {c.case.name: c for c in study.cases}
    names = list(sweeps)
    rigid = table.get("rigid", True)
    if not isinstance(rigid, bool):
        raise error("loads.rigid", f"must be true or false, got {rigid!r}")
    flex = _parse_sections(error, table.get("sections"))
    flex_names = [f.name for f in flex]

    # --- the flight points
    raw = table.get("points")
    if raw is None:
        raise error("loads.points", "missing: give at least one [[loads.points]] with case, altitude_m, chord_m")
    raw = table_array(error, raw, "loads.points")
    points, origins = [], []          # origins: the [[loads.points]] entry of each point (for messages)
    for i, entry in enumerate(raw):
        key = f"loads.points[{i}]"
        _check_keys(error, entry, POINT_KEYS, key)
        for req in ("case", "altitude_m", "chord_m"):
            if req not in entry:
                raise error(f"{key}.{req}", "missing: a flight point needs case, altitude_m and chord_m")
        w = entry["case"]
        match = [n for n in names if isinstance(w, str) and n.casefold() == w.casefold()]
        if not match:
            raise error(f"{key}.case", f"{w!r} is not a case of this study{_hint(w, names)}; its cases: "
                                       f"{', '.join(names)}")
        case = match[0]
        mach = float(sweeps[case].case.mach)
        alts = entry["altitude_m"]
        listed = isinstance(alts, list)
        alts = alts if listed else [alts]
        if not alts:
            raise error(f"{key}.altitude_m", "give an altitude (m) or a non-empty list of them")
        chord = _number(error, entry["chord_m"], f"{key}.chord_m")
        design_speed = entry.get("design_speed", "VC")
        if design_speed not in ("VC", "VD"):
            raise error(f"{key}.design_speed", f"must be \"VC\" (V_B to V_C) or \"VD\"{_hint(design_speed, ['VC', 'VD'])}, "
                                               f"got {design_speed!r}")
        given = [k for k in FG_INPUTS if k in entry]
        if "F_g" in entry and given:
            raise error(f"{key}.F_g", f"give F_g or its inputs {', '.join(FG_INPUTS)}, not both")
        if given and len(given) < 3:
            missing = [k for k in FG_INPUTS if k not in entry]
            raise error(f"{key}.{missing[0]}", f"missing: F_g from the rule needs {', '.join(FG_INPUTS)} "
                                                "(loads.alleviation_factor)")
        fg_inputs = tuple(_number(error, entry[k], f"{key}.{k}") for k in FG_INPUTS) if given else None
        fg = _number(error, entry["F_g"], f"{key}.F_g") if "F_g" in entry else 1.0
        wanted = _point_sections(error, entry, key, flex_names)
        if not rigid and not wanted:
            raise error(f"{key}.sections", "this point would have no loads: rigid = false and no flexible section; "
                                           "name one of " + (", ".join(flex_names) or "the [[loads.sections]]")
                        + " or set rigid = true")
        if "name" in entry and (listed and len(alts) > 1):
            raise error(f"{key}.name", "a name is for one flight point: give one altitude_m, or leave name out "
                                       "(the points are called <case>@<altitude>m)")
        for j, a in enumerate(alts):
            akey = f"{key}.altitude_m" + (f"[{j}]" if listed else "")
            alt = _number(error, a, akey)
            if alt > RULE_MAX_ALTITUDE:
                raise error(akey, f"{alt:g} m is above 60 000 ft ({RULE_MAX_ALTITUDE:g} m), where CS-25.341(a) "
                                  "gives no discrete-gust velocity")
            if fg_inputs is not None:
                try:
                    fg = normalise_float(alleviation_factor(alt, *fg_inputs))
                except FlightPointError as e:
                    msg = str(e).replace("mlw_over_mtow", "mlw_mtow").replace("mzfw_over_mtow", "mzfw_mtow")
                    field = next((k for k in FG_INPUTS if msg.startswith(k)), FG_INPUTS[0])
                    raise error(f"{key}.{field}", msg) from None
            name = entry["name"] if "name" in entry else f"{case}@{alt:g}m"
            if not isinstance(name, str) or not name.strip() or not all(c.isalnum() or c in "-_.@" for c in name):
                raise error(f"{key}.name", f"{name!r} must be a non-empty name of letters, digits, '-', '_', '.', '@'")
            spec = PointSpec(name=name, case=case, mach=mach, altitude_m=alt, chord_m=chord, F_g=fg,
                             design_speed=design_speed, fg_inputs=fg_inputs, sections=wanted)
            try:
                spec.flight_point()
            except FlightPointError as e:
                msg = str(e)
                field = ("F_g" if msg.startswith("F_g") else "chord_m" if msg.startswith("chord") else
                         "altitude_m" if msg.startswith("altitude") else "case" if msg.startswith("mach") else None)
                where = akey if field == "altitude_m" else f"{key}.{field}" if field else key
                if field == "case":
                    msg = f"case {case!r} has Mach {mach:g}: {msg}"
                raise error(where, msg) from None
            points.append(spec)
            origins.append(i)
    if len(points) > MAX_POINTS:
        raise error("loads.points", f"{len(points)} flight points: at most {MAX_POINTS} per study")
    seen = [p.name.casefold() for p in points]
    for i, n in enumerate(seen):
        if seen.index(n) != i:
            raise error("loads.points", f"flight point {points[i].name!r} appears twice; give each its own name "
                                        "or altitude")
    used = tuple(dict.fromkeys(p.case for p in points))

    # --- the ROM of each case
    methods = list(study.methods)
    mnames = [m.name for m in methods]
    motion_omega, lags = _motion_data(error, study, points, origins)
    if "method" in table:
        method = table["method"]
        if method not in mnames:
            raise error("loads.method", f"{method!r} is not a method of this study{_hint(method, mnames)}; its "
                                        f"methods: {', '.join(mnames)}")
    else:
        method = _default_method(error, methods)
    rom = []
    for case in used:
        sw = sweeps[case]
        order = (_pick(error, "loads.order", table["order"], tuple(sw.orders), f"an order of case {case}'s sweep")
                 if "order" in table else max(sw.orders))
        T = (_pick(error, "loads.T", table["T"], tuple(float(t) for t in sw.T), f"a T of case {case}'s sweep",
                   lambda t: f"{t:.6g}") if "T" in table else float(sw.T[0]))
        M = (_pick(error, "loads.M", table["M"], tuple(sw.M), f"an M of case {case}'s sweep")
             if "M" in table else (study.M_base if study.M_base in sw.M else max(sw.M)))
        rom.append((case, (float(T), int(M), int(order), method)))

    # --- outputs and moment axes
    have = list(study.cfd.outputs)
    axes_raw = table.get("moment_axes", [])
    if not isinstance(axes_raw, list) or len(axes_raw) > MAX_AXES:
        raise error("loads.moment_axes", f"must be a list of at most {MAX_AXES} axes (chords from the leading edge)")
    axes = tuple(_number(error, a, f"loads.moment_axes[{i}]") for i, a in enumerate(axes_raw))
    if axes and not {"Cl", "Cm"} <= set(have):
        raise error("loads.moment_axes", "moments about other axes need the outputs Cl and Cm in [cfd] outputs")
    from loads.system import moment_output_name

    extra = [moment_output_name(a) for a in axes]
    available = have + extra
    outs = table.get("outputs", available)
    if isinstance(outs, str):
        outs = [outs]
    if not isinstance(outs, list) or not outs:
        raise error("loads.outputs", f"must be a non-empty list of outputs, got {outs!r}")
    for i, o in enumerate(outs):
        if o not in available:
            raise error(f"loads.outputs[{i}]", f"{o!r} is not an output of the ROMs{_hint(o, available)}; they have "
                                               f"{', '.join(available)} (moments about moment_axes as Cm@x.xxx)")
    if len(set(outs)) != len(outs):
        raise error("loads.outputs", "an output appears twice")
    flex_outs = ()
    if flex:
        if not {"Cl", "Cm"} <= set(have):
            raise error("loads.sections", "flexible sections need the ROMs' outputs Cl and Cm (add them to [cfd] "
                                          "outputs): the gust ROM drives the section")
        flex_avail = list(FLEXIBLE_OUTPUTS) + extra
        fo = table.get("flexible_outputs", list(DEFAULT_FLEXIBLE_OUTPUTS))
        if isinstance(fo, str):
            fo = [fo]
        if not isinstance(fo, list) or not fo:
            raise error("loads.flexible_outputs", f"must be a non-empty list of outputs, got {fo!r}")
        for i, o in enumerate(fo):
            if o not in flex_avail:
                raise error(f"loads.flexible_outputs[{i}]", f"{o!r} is not an output of a flexible section"
                                                            f"{_hint(o, flex_avail)}; they are {', '.join(flex_avail)}")
        if len(set(fo)) != len(fo):
            raise error("loads.flexible_outputs", "an output appears twice")
        flex_outs = tuple(fo)
    elif "flexible_outputs" in table:
        raise error("loads.flexible_outputs", "there is no flexible section: add [[loads.sections]] or leave "
                                              "flexible_outputs out")

    # --- the H search
    lo_r, hi_r = H_RANGE_FT[0] * FT, H_RANGE_FT[1] * FT
    outside = table.get("outside_rule", False)
    if not isinstance(outside, bool):
        raise error("loads.outside_rule", f"must be true or false, got {outside!r}")
    H_range = None
    if "H_range_m" in table:
        hr = table["H_range_m"]
        if not isinstance(hr, list) or len(hr) != 2:
            raise error("loads.H_range_m", f"must be [H_min, H_max] in metres, got {hr!r}")
        lo, hi = (_number(error, v, f"loads.H_range_m[{i}]", positive=True) for i, v in enumerate(hr))
        if hi < lo:
            raise error("loads.H_range_m", f"H_max ({hi:g} m) must not be below H_min ({lo:g} m)")
        if not outside and (lo < lo_r * (1 - 1e-9) or hi > hi_r * (1 + 1e-9)):
            raise error("loads.H_range_m", f"[{lo:g}, {hi:g}] m is outside the rule's 30 - 350 ft ({lo_r:g} - "
                                           f"{hi_r:g} m); set outside_rule = true to search it anyway")
        H_range = (lo, hi)
    n_grid = _integer(error, table.get("n_grid", 24), "loads.n_grid", 3, 2000)
    h_rtol = _number(error, table.get("h_rtol", 1e-4), "loads.h_rtol", positive=True)
    if not h_rtol < 0.5:
        raise error("loads.h_rtol", f"must be below 0.5 (a relative bracket width), got {h_rtol:g}")
    f_max = _number(error, table["f_max_hz"], "loads.f_max_hz", positive=True) if "f_max_hz" in table else None
    return LoadsOptions(rom=tuple(rom), outputs=tuple(outs), moment_axes=axes, H_range_m=H_range,
                        outside_rule=outside, n_grid=n_grid, h_rtol=h_rtol, f_max_hz=f_max, points=tuple(points),
                        rigid=rigid, sections=flex, flexible_outputs=flex_outs, motion_omega=motion_omega, lags=lags)


def _parse_sections(error, raw) -> tuple:
    """The ``[[loads.sections]]`` tables as :class:`FlexibleSpec` (empty when none)."""
    from aeroelastic import SectionError

    if raw is None:
        return ()
    raw = table_array(error, raw, "loads.sections", most=MAX_SECTIONS)
    out = []
    for i, entry in enumerate(raw):
        key = f"loads.sections[{i}]"
        _check_keys(error, entry, SECTION_KEYS, key)
        for req in SECTION_KEYS[:-1]:
            if req not in entry:
                raise error(f"{key}.{req}", "missing: a flexible section needs name, mass_kg_m (kg/m), a, x_alpha, "
                                            "r_alpha2 (Theodorsen's notation, semichords), f_h_hz and f_alpha_hz "
                                            "(uncoupled plunge and pitch frequencies, Hz); damping is optional")
        name = entry["name"]
        if not isinstance(name, str) or not name.strip() or not all(c.isalnum() or c in "-_." for c in name):
            raise error(f"{key}.name", f"{name!r} must be a non-empty name of letters, digits, '-', '_', '.'")
        if name.casefold() == "rigid" or name.casefold() in [s.name.casefold() for s in out]:
            raise error(f"{key}.name", f"section name {name!r} is taken; give each section its own name (not "
                                       "'rigid')")
        vals = {k: _number(error, entry[k], f"{key}.{k}", positive=k in ("mass_kg_m", "f_h_hz", "f_alpha_hz"))
                for k in SECTION_KEYS[1:-1]}
        damp = entry.get("damping", DEFAULT_DAMPING)
        damp = ([_number(error, d, f"{key}.damping[{j}]") for j, d in enumerate(damp)] if isinstance(damp, list)
                else _number(error, damp, f"{key}.damping"))
        try:
            spec = FlexibleSpec(name=name, damping=damp, **vals)
            section = spec.typical_section()
        except SectionError as e:
            msg = str(e)
            bad = next((k for k in ("a", "x_alpha", "r_alpha2", "damping") if msg.startswith(k)), None)
            if msg.startswith("omega_ratio"):
                bad = "f_h_hz"
            raise error(f"{key}.{bad}" if bad else key, msg) from None
        out.append(FlexibleSpec(name=name, damping=tuple(float(d) for d in section.damping), **vals))
    return tuple(out)


def _point_sections(error, entry, key, flex_names) -> tuple:
    """The flexible sections of one ``[[loads.points]]`` (default: all of them)."""
    if "sections" not in entry:
        return tuple(flex_names)
    raw = entry["sections"]
    raw = [raw] if isinstance(raw, str) else raw
    if not isinstance(raw, list):
        raise error(f"{key}.sections", f"must be a list of flexible section names, got {raw!r}")
    out = []
    for j, n in enumerate(raw):
        if n not in flex_names:
            have = f"the study's flexible sections: {', '.join(flex_names)}" if flex_names else \
                "the study has no [[loads.sections]]"
            raise error(f"{key}.sections[{j}]", f"{n!r} is not a flexible section{_hint(n, flex_names)}; {have}")
        if n in out:
            raise error(f"{key}.sections[{j}]", f"section {n!r} appears twice")
        out.append(n)
    return tuple(out)


def _motion_data(error, study, points, origins) -> tuple:
    """``(omega, lags)`` of the ``[aeroelastic]`` section's motion FRF that the flexible points use (``((), 4)``
    without flexible points); :class:`studies.config.StudyConfigError` when a flexible point's case has none."""
    flexible = [p for p in points if p.sections]
    if not flexible:
        return (), 4
    aero = study.section("aeroelastic")
    if aero is None:
        raise error("loads.sections", "a flexible section needs its case's motion frequency response (inputs "
                                      "plunge and pitch), which the [aeroelastic] section computes: add "
                                      "[aeroelastic] with the cases of the flexible points (" +
                    ", ".join(dict.fromkeys(p.case for p in flexible)) + "), or leave the sections out")
    for p, i in zip(points, origins):
        if p.sections and p.case not in aero.cases:
            raise error(f"loads.points[{i}].case", f"case {p.case!r} has no motion data for the flexible sections "
                                                   f"({', '.join(p.sections)}): add it to [aeroelastic] cases (now "
                                                   f"{', '.join(aero.cases)}), or give this point sections = [] "
                                                   "(rigid loads only)")
    return tuple(aero.omega), int(aero.lags)


def describe(options: LoadsOptions) -> str:
    """Lines for ``lfdrom run --dry-run``: the ROMs, outputs, search and flight points."""
    roms = "; ".join(f"{c}: order {o}, T {T:.6g}, M {M}, {m}" for c, (T, M, o, m) in options.rom)
    hr = ("30 - 350 ft" if options.H_range_m is None else
          f"{options.H_range_m[0]:g} - {options.H_range_m[1]:g} m")
    pts = ", ".join(p.name for p in options.points)
    line = (f"  loads: {len(options.points)} flight point(s) ({pts}); "
            + (f"outputs {', '.join(options.outputs)}" if options.rigid else "no rigid loads")
            + f"; H {hr}, n_grid {options.n_grid}, h_rtol {options.h_rtol:g}; ROMs {roms}")
    if options.sections:
        secs = "; ".join(f"{s.name} ({s.mass_kg_m:g} kg/m, a {s.a:g}, x_alpha {s.x_alpha:g}, r_alpha2 "
                         f"{s.r_alpha2:g}, {s.f_h_hz:g} / {s.f_alpha_hz:g} Hz, damping "
                         f"{'/'.join(f'{d:g}' for d in s.damping)}: "
                         f"{sum(s.name in p.sections for p in options.points)} point(s))" for s in options.sections)
        line += (f"\n  loads, flexible sections: {secs}; outputs {', '.join(options.flexible_outputs)}; motion fit "
                 f"with {options.lags} lag roots on the [aeroelastic] motion FRF ({len(options.motion_omega)} "
                 "frequencies)")
    return line


# ---------------------------------------------------------------------------------------------
# Piece keys
# ---------------------------------------------------------------------------------------------

def rom_point(config, case_name: str):
    """The :class:`studies.config.schema.SweepPoint` whose ROM the flight points of ``case_name`` use."""
    from ...config.schema import SweepPoint

    T, M, order, method = config.loads.rom_of(case_name)
    variant = next(m for m in config.methods if m.name == method)
    return SweepPoint(config.case(case_name).case, T, M, order, variant)


def loads_piece(config, spec: PointSpec) -> dict:
    """Key of the loads piece of one flight point: the ROM piece's key, the point, the outputs and the search."""
    from ..gust_rom.pieces import rom_piece

    return dict(rom=rom_piece(rom_point(config, spec.case), config.M_base, config.cfd), point=spec.canonical(),
                **config.loads.search())


def motion_key(config, case_name: str) -> dict:
    """Key of the ``[aeroelastic]`` section's motion FRF piece of ``case_name`` that the flexible sections use
    (:func:`studies.sections.aeroelastic.schema.motion_frf_piece`)."""
    from ..aeroelastic.schema import motion_frf_piece

    return motion_frf_piece(config.case(case_name).case, config.loads.motion_omega, config.cfd)


def flexible_piece(config, spec: PointSpec, section: FlexibleSpec) -> dict:
    """Key of the loads piece of one flight point and flexible section: the ROM piece's key, the motion FRF
    piece's key and the lag count of its fit, the point, the section (not its name), the outputs and the search."""
    from ..gust_rom.pieces import rom_piece

    opts = config.loads
    return dict(rom=rom_piece(rom_point(config, spec.case), config.M_base, config.cfd),
                motion=motion_key(config, spec.case), lags=opts.lags, point=spec.canonical(),
                section=section.canonical(), **opts.search(flexible=True))
