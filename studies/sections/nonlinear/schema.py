"""The ``[nonlinear]`` section of a study file: its schema, parsing and store keys (tasks and reader:
:mod:`studies.sections.nonlinear.study`; report: :mod:`studies.sections.nonlinear.report`).

A study may ask where its linear models hold: the nonlinear Euler response (``cfd.unsteady_response``) of its
cases to its gusts at several amplitudes, compared with the LTD and the ROMs of the same gust shape::

    [nonlinear]
    cases = ["T2", "T3"]            # flow cases of the study (default: all)
    gusts = ["G1", "G3"]            # gusts of the study (default: all that have an amplitude to march)
    amplitudes = [0.5, 1, 2, 5]     # gust angles (deg) of every gust shape; default: none besides gust_angle
    gust_angle = true               # also each gust's own angle (default true) where it is <= max_angle
    max_angle = 15                  # (deg) gust angles above are not marched (default 15; G6's 45 deg is the
                                    # normalisation of the indicial response, not a gust anyone flies)
    tail = 8                        # chords marched after the gust has passed the trailing edge (default 8)

The march uses the study's ``[simulation]`` ``dt`` and ``x0`` (the LTD's, so that the difference from the LTD is
the nonlinearity alone, not the time step) and the ``[cfd]`` gust method. It ends at :func:`march_end`: for a
1-cosine gust of length ``L`` from ``x0``, ``-x0 + L + 1 + tail`` (the gust has left the trailing edge), for the
sharp-edged gust ``-x0 + 1 + 2 tail`` (the indicial response has settled to within a few per cent), never past the
study's ``t_end``.

Piece (kept in the study's :class:`studies.store.cache.ResultStore` like the others)
-------------------------------------------------------------------------------
========== ============================================ ============================================
piece      arrays                                       metadata
========== ============================================ ============================================
nonlinear  ``t``, ``u``, ``cl``, ``cm``, ``cd``,        ``amplitude_deg``, ``steady_loads``,
           ``iterations``, ``max_mach`` (n + 1,)        ``n_factorisations``, ``iterations_per_step``,
                                                        ``max_local_mach``, ``steady_max_mach``, ``seconds``
========== ============================================ ============================================

``cl``, ``cm``, ``cd`` are perturbations about the steady loads at the gust's amplitude (as
``cfd.unsteady_response`` returns them). The key holds the steady flow's key (aerofoil, Mach, incidence, grid), the
gust shape and angle, ``dt``, the end time, ``x0``, the gust method and the code version of ``cfd``. A march that
fails (a step that does not converge, a local Mach number beyond the solver's limit, a non-physical state) is
stored as a failure with the solver's message, which the report shows: the linear model cannot be judged there.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any, Callable

from ...config.reader import did_you_mean
from ...config.numbers import normalise_float, parse_number

__all__ = [
    "NonlinearOptions",
    "NONLINEAR_KEYS",
    "NONLINEAR_PIECES",
    "NONLINEAR_DEPENDENCIES",
    "MAX_AMPLITUDES",
    "parse_nonlinear",
    "describe",
    "march_amplitudes",
    "gust_shapes",
    "march_end",
    "nonlinear_piece",
]

NONLINEAR_KEYS = ("cases", "gusts", "amplitudes", "gust_angle", "max_angle", "tail")

NONLINEAR_PIECES = ("nonlinear",)
"""The store pieces of the ``[nonlinear]`` section."""

NONLINEAR_DEPENDENCIES = {"nonlinear": ("cfd",)}
"""Packages whose sources enter the key of the nonlinear piece (merged into
:data:`studies.store.cache.PIECE_DEPENDENCIES`): ``cfd`` only, as the other CFD pieces (the task is a thin wrapper)."""

MAX_AMPLITUDES = 20
MAX_ANGLE_LIMIT = 45.0


@dataclass(frozen=True)
class NonlinearOptions:
    """The validated ``[nonlinear]`` section.

    Attributes
    ----------
    cases : tuple of str
        Names of the study's flow cases to march.
    gusts : tuple of str
        Names of the study's gusts to march.
    amplitudes : tuple of float
        Gust angles (deg, positive, increasing) marched for every gust shape.
    gust_angle : bool
        Also march each gust at its own angle (when it is at most ``max_angle``).
    max_angle : float
        Largest gust angle marched (deg).
    tail : float
        Chords marched after a 1-cosine gust has left the trailing edge (see :func:`march_end`).
    """

    cases: tuple
    gusts: tuple
    amplitudes: tuple = ()
    gust_angle: bool = True
    max_angle: float = 15.0
    tail: float = 8.0

    def canonical(self) -> dict:
        """The hashable content (for :meth:`studies.config.schema.StudyConfig.canonical`)."""
        return dict(cases=list(self.cases), gusts=list(self.gusts), amplitudes=list(self.amplitudes),
                    gust_angle=self.gust_angle, max_angle=self.max_angle, tail=self.tail)



def _did_you_mean(word, options) -> str:
    """:func:`studies.config.reader.did_you_mean` for a name from the file (not always a string)."""
    return did_you_mean(word, options) if isinstance(word, str) else ""


def _number(source, value, key, *, lo=None, hi=None) -> float:
    try:
        v = parse_number(value)
    except ValueError as e:
        raise source(key, str(e)) from None
    if not math.isfinite(v):
        raise source(key, f"must be finite, got {v!r}")
    if (lo is not None and v <= lo) or (hi is not None and v > hi):
        raise source(key, f"must be in ({lo:g}, {hi:g}], got {v!r}")
    return normalise_float(v)


def _names(source, table, key, known, what) -> tuple:
    wanted = table.get(key, list(known))
    if isinstance(wanted, str):
        wanted = [wanted]
    if not isinstance(wanted, list) or not wanted:
        raise source(f"nonlinear.{key}", f"must be a non-empty list of {what} names, got {wanted!r}")
    chosen = []
    for i, w in enumerate(wanted):
        match = [n for n in known if isinstance(w, str) and n.casefold() == w.casefold()]
        if not match:
            raise source(f"nonlinear.{key}[{i}]", f"{w!r} is not a {what} of this study{_did_you_mean(w, known)}; "
                                                  f"its {what}s: {', '.join(known) or 'none'}")
        if match[0] in chosen:
            raise source(f"nonlinear.{key}[{i}]", f"{what} {match[0]!r} appears twice")
        chosen.append(match[0])
    return tuple(chosen)


def parse_nonlinear(table: Any, source: Callable[[str, str], Exception], cases: tuple,
                    gusts: tuple, simulation=None) -> NonlinearOptions:
    """Validate the ``[nonlinear]`` table of a study file.

    Parameters
    ----------
    table : dict
        The parsed TOML table.
    source : callable
        ``source(dotted_key, problem) -> Exception`` (``studies.config`` passes one that makes a
        :class:`studies.config.StudyConfigError` naming the file).
    cases : tuple of studies.config.schema.CaseSweep
        The study's cases.
    gusts : tuple of studies.config.cases.GustCase
        The study's gusts.
    simulation : studies.config.schema.SimulationOptions, optional
        The study's ``[simulation]``: a gust that has not left the trailing edge by its ``t_end`` is refused.

    Returns
    -------
    NonlinearOptions

    Raises
    ------
    studies.config.StudyConfigError
        Naming the dotted key (``nonlinear.amplitudes[2]``) and what to do.
    """
    if not isinstance(table, dict):
        raise source("nonlinear", f"must be a table, got {type(table).__name__} {table!r}")
    for k in table:
        if k not in NONLINEAR_KEYS:
            raise source(f"nonlinear.{k}", f"unknown key{_did_you_mean(k, NONLINEAR_KEYS)}; allowed here: "
                                           f"{', '.join(NONLINEAR_KEYS)}")
    if not gusts:
        raise source("nonlinear", "the study has no gusts: add gusts = [...] (the nonlinear march needs a gust)")
    case_names = _names(source, table, "cases", [c.case.name for c in cases], "case")
    gust_names = _names(source, table, "gusts", [g.name for g in gusts], "gust")
    max_angle = _number(source, table.get("max_angle", 15.0), "nonlinear.max_angle", lo=0.0, hi=MAX_ANGLE_LIMIT)
    raw = table.get("amplitudes", [])
    if not isinstance(raw, list) or len(raw) > MAX_AMPLITUDES:
        raise source("nonlinear.amplitudes", f"must be a list of at most {MAX_AMPLITUDES} gust angles (deg), got "
                                             f"{raw!r}")
    amps = [_number(source, a, f"nonlinear.amplitudes[{i}]", lo=0.0, hi=max_angle) for i, a in enumerate(raw)]
    if any(b <= a for a, b in zip(amps, amps[1:])):
        raise source("nonlinear.amplitudes", f"must be strictly increasing, got {amps}")
    gust_angle = table.get("gust_angle", True)
    if not isinstance(gust_angle, bool):
        raise source("nonlinear.gust_angle", f"must be true or false, got {gust_angle!r}")
    if not amps and not gust_angle:
        raise source("nonlinear.amplitudes", "nothing to march: give amplitudes or leave gust_angle = true")
    tail = _number(source, table.get("tail", 8.0), "nonlinear.tail", lo=0.0, hi=1000.0)
    opts = NonlinearOptions(cases=case_names, gusts=gust_names, amplitudes=tuple(amps), gust_angle=gust_angle,
                            max_angle=max_angle, tail=tail)
    by_name = {g.name: g for g in gusts}
    if simulation is not None:
        for i, name in enumerate(gust_names):
            g = by_name[name]
            passed = -simulation.x0 + (float(g.length) if g.kind == "one_minus_cosine" else 0.0) + 1.0
            if passed > simulation.t_end:
                where = f"nonlinear.gusts[{i}]" if "gusts" in table else "nonlinear"
                raise source(where, f"gust {name} has not left the trailing edge at [simulation] t_end = "
                                    f"{simulation.t_end:g} (it does at s = {passed:g} from x0 = {simulation.x0:g}): "
                                    "raise t_end or leave the gust out of [nonlinear]")
    empty = [g for g in gust_names if not march_amplitudes(opts, by_name[g])]
    if empty and "gusts" not in table and len(empty) < len(gust_names):  # default: the gusts with an amplitude
        return replace(opts, gusts=tuple(g for g in gust_names if g not in empty))
    if empty:
        raise source("nonlinear.max_angle", f"no amplitude of gust(s) {', '.join(empty)} is at most {max_angle:g} "
                                            "deg: give amplitudes or raise max_angle")
    return opts


def march_amplitudes(options: NonlinearOptions, gust) -> tuple:
    """The gust angles (deg) marched for the study gust ``gust`` (a :class:`studies.config.cases.GustCase`): the
    section's ``amplitudes`` with the sign of the gust's angle, and the gust's own angle when ``gust_angle`` and
    ``|angle|`` is at most ``max_angle``; by increasing magnitude."""
    sign = -1.0 if gust.angle_deg < 0 else 1.0
    amps = {sign * a for a in options.amplitudes}
    if options.gust_angle and abs(gust.angle_deg) <= options.max_angle:
        amps.add(float(gust.angle_deg))
    return tuple(sorted(amps, key=lambda a: (abs(a), a)))


def gust_shapes(options: NonlinearOptions, gusts) -> list:
    """The section's gusts grouped by shape: gusts of the same kind and length (G2 and G3 of the paper differ
    only in angle) share their marches, which are keyed by shape and angle.

    Parameters
    ----------
    options : NonlinearOptions
    gusts : sequence of studies.config.cases.GustCase
        The study's gusts.

    Returns
    -------
    list of (str, GustCase, tuple of float)
        ``(label, gust, angles)`` per shape, in the section's order: the label joins the names (``"G2/G3"``),
        ``gust`` is the first of them (its LTD and ROM histories are the linear models of the shape), ``angles``
        the union of their :func:`march_amplitudes`, by increasing magnitude.
    """
    by_name = {g.name: g for g in gusts}
    groups: dict = {}
    for name in options.gusts:
        g = by_name[name]
        groups.setdefault((g.kind, g.length), []).append(g)
    out = []
    for members in groups.values():
        angles = {a for g in members for a in march_amplitudes(options, g)}
        out.append(("/".join(g.name for g in members), members[0],
                    tuple(sorted(angles, key=lambda a: (abs(a), a)))))
    return out


def march_end(options: NonlinearOptions, gust, simulation) -> float:
    """Convective end time of the march of ``gust`` (a :class:`studies.config.cases.GustCase`): ``-x0 + L + 1 + tail`` for
    a 1-cosine gust of length ``L`` (its back has left the trailing edge ``tail`` chords before), ``-x0 + 1 +
    2 tail`` for the sharp-edged gust; at most the study's ``t_end``, and a whole number of ``dt``."""
    x0 = simulation.x0
    if gust.kind == "one_minus_cosine":
        end = -x0 + float(gust.length) + 1.0 + options.tail
    else:
        end = -x0 + 1.0 + 2.0 * options.tail
    n = min(int(math.ceil(end / simulation.dt - 1e-9)), int(round(simulation.t_end / simulation.dt)))
    return normalise_float(n * simulation.dt)


def describe(options: NonlinearOptions) -> str:
    """One line for ``lfdrom run --dry-run``."""
    amps = ", ".join(f"{a:g}" for a in options.amplitudes) or "none"
    own = f" and each gust's own angle up to {options.max_angle:g} deg" if options.gust_angle else ""
    return (f"  nonlinear: cases {', '.join(options.cases)}; gusts {', '.join(options.gusts)}; amplitudes {amps} "
            f"deg{own}; {options.tail:g} chords after each gust")


def nonlinear_piece(config, case, gust, amplitude_deg: float) -> dict:
    """Key of the nonlinear march of one flow case, gust shape and amplitude.

    Parameters
    ----------
    config : studies.config.schema.StudyConfig
    case : studies.config.cases.FlowCase
    gust : studies.config.cases.GustCase
        The shape (its own angle is replaced by ``amplitude_deg``).
    amplitude_deg : float
    """
    from ...config.schema import case_canonical

    sim = config.simulation
    return dict(steady=case_canonical(case), gust=dict(kind=gust.kind, length=gust.length),
                angle_deg=float(amplitude_deg), dt=sim.dt, t_end=march_end(config.nonlinear, gust, sim), x0=sim.x0,
                gust_method=config.cfd.gust_method)
