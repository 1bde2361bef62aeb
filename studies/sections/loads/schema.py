"""The ``[loads]`` section of a study file: its schema, parsing and store keys (tasks and reader:
:mod:`studies.sections.loads.study`; report: :mod:`studies.sections.loads.report`).

A study may ask for the certification gust loads of CS-25.341 (:mod:`loads`: tuned discrete 1-cosine gusts and
continuous von Karman turbulence) of its rigid aerofoil at flight points, from one of its own gust ROMs per case::

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
    f_max_hz = 50.0                   # optional cut-off of the turbulence integrals (a ROM with a feedthrough)

    [[loads.points]]                  # one or more; each case fixes the aerofoil and the Mach number
    case = "M0.5"
    altitude_m = [0, 4000, 8000]      # one flight point per altitude (m, geopotential)
    chord_m = 3.0
    F_g = 1.0                         # or z_mo_m, mlw_mtow, mzfw_mtow (loads.alleviation_factor at each altitude)
    design_speed = "VC"               # or "VD" (half the gust velocities)
    name = "cruise"                   # optional (one altitude only); default "<case>@<altitude>m"

Every flight point is built at parse time (:class:`loads.FlightPoint`), so that a Mach number, altitude, chord
or ``F_g`` outside the rule's or the atmosphere's range is refused before any CFD. The flexible section
(:class:`loads.FlexibleSection`) is not part of the section yet: it needs the case's motion FRF.

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
the search settings; its code version covers ``sysid``, ``loads``, ``aeroelastic`` and this section's modules
(:data:`LOADS_DEPENDENCIES`). A failed piece is stored as such and computed again by the next run.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable, Optional

from ...config.numbers import normalise_float, parse_number
from ...config.reader import did_you_mean

__all__ = [
    "LoadsOptions",
    "PointSpec",
    "LOADS_KEYS",
    "POINT_KEYS",
    "LOADS_PIECES",
    "LOADS_DEPENDENCIES",
    "LOADS_ARRAYS",
    "parse_loads",
    "describe",
    "rom_point",
    "loads_piece",
]

LOADS_KEYS = ("order", "method", "T", "M", "outputs", "moment_axes", "H_range_m", "outside_rule", "n_grid", "h_rtol",
              "f_max_hz", "points")
POINT_KEYS = ("case", "altitude_m", "chord_m", "F_g", "z_mo_m", "mlw_mtow", "mzfw_mtow", "design_speed", "name")
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
    """

    name: str
    case: str
    mach: float
    altitude_m: float
    chord_m: float
    F_g: float = 1.0
    design_speed: str = "VC"
    fg_inputs: Optional[tuple] = None

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

    @property
    def cases(self) -> tuple:
        """The cases of the flight points, in the order they first appear."""
        return tuple(dict.fromkeys(p.case for p in self.points))

    def rom_of(self, case: str) -> tuple:
        """``(T, M, order, method name)`` of the ROM of ``case``."""
        return dict(self.rom)[case]

    def search(self) -> dict:
        """The search settings of every piece's key."""
        return dict(outputs=list(self.outputs), moment_axes=list(self.moment_axes),
                    H_range_m=None if self.H_range_m is None else list(self.H_range_m),
                    outside_rule=self.outside_rule, n_grid=self.n_grid, h_rtol=self.h_rtol, f_max_hz=self.f_max_hz)

    def canonical(self) -> dict:
        """The hashable content (for :meth:`studies.config.schema.StudyConfig.canonical`)."""
        return dict(rom={c: list(v) for c, v in self.rom}, **self.search(),
                    points=[dict(p.canonical(), name=p.name, case=p.case) for p in self.points])


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

    # --- the flight points
    raw = table.get("points")
    if raw is None:
        raise error("loads.points", "missing: give at least one [[loads.points]] with case, altitude_m, chord_m")
    if isinstance(raw, dict):
        raw = [raw]
    if not isinstance(raw, list) or not raw:
        raise error("loads.points", "must be a list of tables ([[loads.points]])")
    points = []
    for i, entry in enumerate(raw):
        key = f"loads.points[{i}]"
        if not isinstance(entry, dict):
            raise error(key, f"must be a table, got {entry!r}")
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
                             design_speed=design_speed, fg_inputs=fg_inputs)
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
                        outside_rule=outside, n_grid=n_grid, h_rtol=h_rtol, f_max_hz=f_max, points=tuple(points))


def describe(options: LoadsOptions) -> str:
    """Lines for ``lfdrom run --dry-run``: the ROMs, outputs, search and flight points."""
    roms = "; ".join(f"{c}: order {o}, T {T:.6g}, M {M}, {m}" for c, (T, M, o, m) in options.rom)
    hr = ("30 - 350 ft" if options.H_range_m is None else
          f"{options.H_range_m[0]:g} - {options.H_range_m[1]:g} m")
    pts = ", ".join(p.name for p in options.points)
    return (f"  loads: {len(options.points)} flight point(s) ({pts}); outputs {', '.join(options.outputs)}; H {hr}, "
            f"n_grid {options.n_grid}, h_rtol {options.h_rtol:g}; ROMs {roms}")


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
