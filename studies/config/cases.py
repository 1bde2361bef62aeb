"""The case catalogue: the paper's test cases T1-T6 and gust cases G1-G6, and user-defined cases.

Test cases (Bagheri, Jones & Gaitonde 2016, Table 1), all at zero incidence on the paper's
181 x 60 C-grid with 100 cells on the aerofoil:

====  ========  =====
Case  Aerofoil  Mach
====  ========  =====
T1    NACA0006  0.85
T2    NACA0010  0.735
T3    NACA0010  0.85
T4    NACA0018  0.25
T5    NACA2410  0.25
T6    NACA2410  0.735
====  ========  =====

Gust cases (Table 2); ``angle_deg`` is the peak effective gust angle ``delta_alpha_eff``
(paper Eq. 18, ``v_max = U tan(delta_alpha_eff)``):

====  ================  ==============  =========
Case  Kind              Length (c)      Angle
====  ================  ==============  =========
G1    one_minus_cosine  0.5             2 deg
G2    one_minus_cosine  1               2 deg
G3    one_minus_cosine  1               5 deg
G4    one_minus_cosine  10              5 deg
G5    one_minus_cosine  25              1 deg
G6    sharp_edged       --              45 deg (``v_gmax = 1``, see below)
====  ================  ==============  =========

G6 and "v_gmax = 1"
-------------------
The paper gives G6 as a step (sharp-edged gust, its Eq. 33) of amplitude ``v_gmax = 1`` in its
non-dimensional velocity, i.e. ``v_gmax / U_inf = 1``: a unit step of the input. In our convention
(docs/conventions.md) the input of every linear model is ``u = v_g(x_ref, t) / U_inf`` and the loads
are per unit of it, so G6 is the unit step ``u = 1`` and its responses are the indicial (sharp-edged
gust) responses per radian of gust angle, the same numbers that the Kussner function scales. The cfd
gust objects are parametrised by the gust angle with amplitude ``tan(angle_deg)``, so G6 is stored
as ``angle_deg = 45`` (``tan 45 deg = 1`` to round-off, 1e-16). The linear responses scale with the
amplitude; this is not a claim that a 45 deg gust is in the linear range, only the normalisation the
paper plots.

Lookup is case-insensitive (``flow_case("t2")``); an unknown name raises :class:`UnknownCaseError`
(a ``KeyError``) listing the known names. User cases are built with :func:`user_case` or the
:class:`FlowCase` and :class:`GustCase` constructors, which validate their fields.
"""

from __future__ import annotations

from types import MappingProxyType
from typing import Mapping, Optional

from .case_fields import CaseError, UnknownCaseError, check_name, check_real, naca_code
from .case_types import GUST_KINDS, FlowCase, GustCase, to_gust
from .grid_spec import MAX_CELLS, MAX_FARFIELD, PAPER_GRID, WALL_SPACING, GridSpec, worker_memory_bytes

__all__ = [
    "CaseError",
    "UnknownCaseError",
    "GridSpec",
    "FlowCase",
    "GustCase",
    "GUST_KINDS",
    "TEST_CASES",
    "GUST_CASES",
    "PAPER_GRID",
    "flow_case",
    "gust_case",
    "user_case",
    "check_name",
    "naca_code",
    "to_gust",
    "case_table",
    "WALL_SPACING",
    "MAX_CELLS",
    "MAX_FARFIELD",
    "worker_memory_bytes",
]
# The names above that this module does not define are re-exported from their homes: studies.config.case_fields
# (errors and field checks), studies.config.grid_spec (grid sizes and their limits) and studies.config.case_types (the case
# types and to_gust).


TEST_CASES: Mapping[str, FlowCase] = MappingProxyType({
    c.name: c for c in (
        FlowCase("T1", "0006", 0.85),
        FlowCase("T2", "0010", 0.735),
        FlowCase("T3", "0010", 0.85),
        FlowCase("T4", "0018", 0.25),
        FlowCase("T5", "2410", 0.25),
        FlowCase("T6", "2410", 0.735),
    )
})
"""The paper's Table 1 (zero incidence, paper grid), by name."""

GUST_CASES: Mapping[str, GustCase] = MappingProxyType({
    g.name: g for g in (
        GustCase("G1", "one_minus_cosine", 0.5, 2.0),
        GustCase("G2", "one_minus_cosine", 1.0, 2.0),
        GustCase("G3", "one_minus_cosine", 1.0, 5.0),
        GustCase("G4", "one_minus_cosine", 10.0, 5.0),
        GustCase("G5", "one_minus_cosine", 25.0, 1.0),
        GustCase("G6", "sharp_edged", None, 45.0),  # v_gmax / U = 1: the unit step (module docstring)
    )
})
"""The paper's Table 2, by name."""


def _lookup(kind: str, table: Mapping, name):
    if isinstance(name, str):
        for key, value in table.items():
            if key.casefold() == name.strip().casefold():
                return value
    raise UnknownCaseError(kind, name, table)


def flow_case(name: str) -> FlowCase:
    """The paper's test case ``name`` (``"T1"`` .. ``"T6"``, case-insensitive).

    Raises
    ------
    UnknownCaseError
        A ``KeyError`` listing the known names.
    """
    return _lookup("test case", TEST_CASES, name)


def gust_case(name: str) -> GustCase:
    """The paper's gust case ``name`` (``"G1"`` .. ``"G6"``, case-insensitive).

    Raises
    ------
    UnknownCaseError
        A ``KeyError`` listing the known names.
    """
    return _lookup("gust case", GUST_CASES, name)


def _default_name(code: str, mach: float, alpha_deg: float) -> str:
    name = f"NACA{code}-M{mach:g}"
    if alpha_deg:
        name += f"-a{alpha_deg:g}"
    return name


def user_case(naca, mach, alpha_deg: float = 0.0, name: Optional[str] = None,
              grid: Optional[GridSpec | Mapping] = None) -> FlowCase:
    """A user-defined test case (any NACA 4-digit aerofoil, Mach number, incidence, grid).

    Parameters
    ----------
    naca : str or int
        NACA 4-digit code.
    mach : float
        ``0.01 <= mach < 1`` (the solver's floor, ``cfd.flow.MIN_MACH``).
    alpha_deg : float
        Incidence (degrees).
    name : str, optional
        Label; default ``"NACA<code>-M<mach>[-a<alpha>]"``.
    grid : GridSpec or mapping, optional
        Grid sizes; a mapping overrides the paper grid's sizes.

    Returns
    -------
    FlowCase

    Raises
    ------
    CaseError
    """
    if grid is None:
        grid = GridSpec()
    elif not isinstance(grid, GridSpec):
        try:
            grid = GridSpec(**dict(grid))
        except TypeError as e:
            raise CaseError(f"grid: {e}; grid sizes are ni, nj, n_surface, farfield") from None
    if name is None:
        code = naca_code("case", naca)
        name = _default_name(code, check_real("case", "mach", mach), check_real("case", "alpha_deg", alpha_deg))
    return FlowCase(name, naca, mach, alpha_deg, grid)


def case_table() -> tuple[list[dict], list[dict]]:
    """Rows describing T1-T6 and G1-G6 (for ``lfdrom cases`` and reports).

    Returns
    -------
    (flow_rows, gust_rows) : tuple of lists of dict
    """
    flows = [dict(name=c.name, aerofoil=c.aerofoil, mach=c.mach, alpha_deg=c.alpha_deg,
                  grid=f"{c.grid.ni} x {c.grid.nj}, {c.grid.n_surface} on the wall, R = {c.grid.farfield:g} c")
             for c in TEST_CASES.values()]
    gusts = [dict(name=g.name, kind=g.kind, length="-" if g.length is None else f"{g.length:g}",
                  angle_deg=g.angle_deg, amplitude=g.amplitude) for g in GUST_CASES.values()]
    return flows, gusts
