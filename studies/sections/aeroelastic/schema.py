"""The ``[aeroelastic]`` section of a study file: its schema, parsing and store keys (tasks and reader:
:mod:`studies.sections.aeroelastic.study`).

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

Pieces (kept in the study's :class:`studies.store.cache.ResultStore` like the others)
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
``aeroelastic``, this module and :mod:`studies.sections.aeroelastic.study` (:data:`AEROELASTIC_DEPENDENCIES`). A failed
piece is stored as such and computed again by the next run.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import Any, Callable, Optional

import numpy as np

from sysid.order_limits import max_order

from ...config.reader import did_you_mean, table_array
from ...config.numbers import normalise_float, parse_number
from ...config.schema import case_canonical

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
    "describe",
    "motion_frf_piece",
    "flutter_piece",
]

AEROELASTIC_KEYS = ("cases", "omega", "lags", "gust_order", "speeds", "sections")
SECTION_KEYS = ("name", "mu", "a", "x_alpha", "r_alpha2", "omega_ratio", "gust_speed")
RANGE_KEYS = ("min", "max", "n")

AEROELASTIC_PIECES = ("motion_frf", "flutter")
"""The store pieces of the ``[aeroelastic]`` section, in the order a case computes them."""

AEROELASTIC_DEPENDENCIES = {
    "motion_frf": ("cfd",),
    "flutter": ("cfd", "sysid", "aeroelastic", "studies.sections.aeroelastic.schema",
                "studies.sections.aeroelastic.study"),
}
"""Packages and modules whose sources enter the keys of the aeroelastic pieces (merged into
:data:`studies.store.cache.PIECE_DEPENDENCIES`)."""

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
        """The hashable content (for :meth:`studies.config.schema.StudyConfig.canonical`)."""
        return dict(cases=list(self.cases), omega=list(self.omega), lags=self.lags,
                    gust_order=self.gust_order, speeds=None if self.speeds is None else list(self.speeds),
                    sections=[dict(s.canonical(), name=s.name, gust_speed=s.gust_speed) for s in self.sections])


def _error(source, key, problem):
    return source(key, problem)


def _check_keys(source, table, allowed, prefix):
    for k in table:
        if k not in allowed:
            raise _error(source, f"{prefix}.{k}", f"unknown key{_did_you_mean(k, allowed)}; allowed here: "
                                                   f"{', '.join(allowed)}")



def _did_you_mean(word, options) -> str:
    """:func:`studies.config.reader.did_you_mean` for a name from the file (not always a string)."""
    return did_you_mean(word, options) if isinstance(word, str) else ""


def _number(source, value, key, *, positive=False) -> float:
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


def parse_aeroelastic(table: Any, source: Callable[[str, str], Exception], cases: tuple,
                      gusts: tuple) -> AeroelasticOptions:
    """Validate the ``[aeroelastic]`` table of a study file.

    Parameters
    ----------
    table : dict
        The parsed TOML table.
    source : callable
        ``source(dotted_key, problem) -> Exception``: the study file's error (``studies.config`` passes one that
        makes a :class:`studies.config.StudyConfigError` naming the file).
    cases : tuple of studies.config.schema.CaseSweep
        The study's cases.
    gusts : tuple of studies.config.cases.GustCase
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
                         f"{w!r} is not a case of this study{_did_you_mean(w, names)}; its cases: {', '.join(names)}")
        if match[0] in chosen:
            raise _error(source, f"aeroelastic.cases[{i}]", f"case {match[0]!r} appears twice")
        chosen.append(match[0])
    omega = (_range_or_list(source, table["omega"], "aeroelastic.omega", zero=True, max_n=MAX_OMEGA_POINTS,
                            what="frequencies") if "omega" in table else DEFAULT_OMEGA)
    lags = _integer(source, table.get("lags", 4), "aeroelastic.lags", 0, MAX_LAGS)
    gust_order = _integer(source, table.get("gust_order", 8), "aeroelastic.gust_order", 1, 40)
    # what the fits can take from len(omega) frequencies (omega = 0 among them), checked before any CFD
    n_freq = len(omega)
    if 2 * n_freq < lags + 3:  # Roger's fit: lags + 2 real coefficients per entry besides the static one
        raise _error(source, "aeroelastic.lags", f"{lags} lag roots need at least {-(-(lags + 3) // 2)} "
                     f"frequencies; aeroelastic.omega has {n_freq}: add frequencies or use fewer lags")
    gust_limit = max_order(n_freq - 1, "mckelvey2", p=2, m=1)
    if gust_order > gust_limit:
        raise _error(source, "aeroelastic.gust_order", f"gust_order = {gust_order} is beyond what {n_freq} "
                     f"frequencies support (at most {gust_limit}: sysid's limit for the gust column); add "
                     "frequencies to aeroelastic.omega or lower gust_order")
    speeds = (_range_or_list(source, table["speeds"], "aeroelastic.speeds", zero=False, max_n=MAX_SPEEDS,
                             what="speed indices") if "speeds" in table else None)
    raw = table.get("sections")
    if raw is None:
        raise _error(source, "aeroelastic.sections", "missing: give at least one [[aeroelastic.sections]] with "
                                                     "name, mu, a, x_alpha, r_alpha2, omega_ratio")
    raw = table_array(source, raw, "aeroelastic.sections")
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
        # TypicalSection names the parameter it refuses first ("r_alpha2 = 0.001 must exceed x_alpha^2 ..."); a
        # name further on is context (" mu" matched that message's " must", so the key said mu)
        first = re.match(r"[A-Za-z_]\w*", msg)
        bad = first.group() if first and first.group() in SECTION_KEYS[1:-1] else None
        raise _error(source, f"{key}.{bad}" if bad else key, msg) from None
    return spec


def describe(options: AeroelasticOptions) -> str:
    """One line for ``lfdrom run --dry-run``: the cases, frequencies, lags, speeds and sections."""
    w = np.asarray(options.omega)
    speeds = ("default" if options.speeds is None else
              f"{len(options.speeds)} from {options.speeds[0]:g} to {options.speeds[-1]:g}")
    secs = "; ".join(f"{s.name} (mu {s.mu:g}, a {s.a:g}, x_alpha {s.x_alpha:g}, r_alpha2 {s.r_alpha2:g}, "
                     f"omega_ratio {s.omega_ratio:g}" + ("" if s.gust_speed is None else f", gusts at V {s.gust_speed:g}")
                     + ")" for s in options.sections)
    return (f"  aeroelastic: cases {', '.join(options.cases)}; {w.size} motion frequencies (0 .. {w.max():g} U/c); "
            f"{options.lags} lags; speeds {speeds}; sections {secs}")


# ---------------------------------------------------------------------------------------------
# Piece keys
# ---------------------------------------------------------------------------------------------

def motion_frf_piece(case, omega, cfd_options) -> dict:
    """Key of the motion FRF of a flow case: its steady flow, the frequencies, pivot, inputs and gust method.

    Parameters
    ----------
    case : studies.config.cases.FlowCase
    omega : sequence of float
        Frequencies (U/c).
    cfd_options : studies.config.schema.CFDOptions
    """
    return dict(steady=case_canonical(case), omega=[float(w) for w in omega], inputs=list(MOTION_INPUTS),
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
