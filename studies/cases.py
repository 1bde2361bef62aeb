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
(shared/DESIGN.md) the input of every linear model is ``u = v_g(x_ref, t) / U_inf`` and the loads
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

import math
import numbers
import re
from dataclasses import asdict, dataclass, field, replace
from types import MappingProxyType
from typing import Mapping, Optional

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
]

GUST_KINDS = ("one_minus_cosine", "sharp_edged")


class CaseError(ValueError):
    """A test or gust case definition is invalid (bad NACA code, Mach out of range, bad gust...)."""


class UnknownCaseError(CaseError, KeyError):
    """A case name is not in the catalogue. Subclasses ``KeyError`` (and ``ValueError``).

    Attributes
    ----------
    name : str
        The name that was looked up.
    known : tuple of str
        The names in the catalogue.
    """

    def __init__(self, kind: str, name: object, known):
        self.name = name
        self.known = tuple(known)
        msg = (f"unknown {kind} {name!r}; known {kind}s: {', '.join(self.known)} "
               "(names are case-insensitive)")
        super().__init__(msg)
        self.message = msg

    def __str__(self) -> str:  # KeyError would otherwise quote the message
        return self.message


def _real(owner: str, name: str, value) -> float:
    if isinstance(value, bool):
        raise CaseError(f"{owner}: {name} must be a real number, got {value!r}")
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise CaseError(f"{owner}: {name} must be a real number, got {value!r}") from None
    if not math.isfinite(v):
        raise CaseError(f"{owner}: {name} must be finite, got {value!r}")
    return v


def _integer(owner: str, name: str, value) -> int:
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise CaseError(f"{owner}: {name} must be an integer, got {value!r}")
    return int(value)


WALL_SPACING = 0.004
"""First cell height at the wall of ``cfd.c_grid`` (its ``wall_spacing`` default, chords)."""

MAX_CELLS = 2_000_000
"""Most cells ``(ni - 1) (nj - 1)`` of a study grid on any machine (memory of the exact Jacobian's LU); a grid
whose estimated worker memory (:func:`worker_memory_bytes`) exceeds twice the machine's is refused too."""

MAX_FARFIELD = 200.0
"""Farthest far field (chords) a study grid may ask of ``cfd.c_grid``."""


def worker_memory_bytes(cells: int) -> float:
    """Estimated peak memory of one study worker on a grid of ``cells`` cells (bytes).

    Anchored on the paper grid (10,620 cells: about 1.5 GB at the peak of the fast sweep, measured, see
    ``studies.runner.auto_workers``) and scaled as ``cells^1.2``, the growth of a nested-dissection LU's fill
    on 2-D grids over this range (``N log N``). Right to a factor of two; used to refuse grids that cannot fit.
    """
    return 1.5e9 * (max(int(cells), 1) / 10_620) ** 1.2


def _physical_memory_bytes():
    import os

    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):  # pragma: no cover - not POSIX
        return None


@dataclass(frozen=True)
class GridSpec:
    """Sizes of the C-grid (``cfd.c_grid`` arguments); the paper's 181 x 60 grid by default.

    Parameters
    ----------
    ni, nj : int
        Nodes around the C and outward.
    n_surface : int
        Cells on the aerofoil (even); ``ni - 1 - n_surface`` must be even and >= 2 (the wake cells).
    farfield : float
        Far-field radius in chords (>= 3).

    Raises
    ------
    CaseError
        Sizes that ``cfd.c_grid`` would reject (checked here, before any grid is built).
    """

    ni: int = 181
    nj: int = 60
    n_surface: int = 100
    farfield: float = 25.0

    def __post_init__(self):
        for name in ("ni", "nj", "n_surface"):
            object.__setattr__(self, name, _integer("grid", name, getattr(self, name)))
        object.__setattr__(self, "farfield", _real("grid", "farfield", self.farfield))
        if self.n_surface < 8 or self.n_surface % 2:
            raise CaseError(f"grid: n_surface = {self.n_surface} must be even and at least 8 (paper: 100)")
        wake = self.ni - 1 - self.n_surface
        if wake < 2 or wake % 2:
            raise CaseError(
                f"grid: ni - 1 - n_surface = {wake} wake cells must be even and >= 2; use ni = n_surface + 1 "
                f"+ 2 * n_wake, e.g. ni = {self.n_surface + 81} for 40 wake cells per branch")
        if self.nj < 16:
            raise CaseError(f"grid: nj = {self.nj} is too few; use nj >= 16 (paper: 60)")
        if self.farfield < 3.0:
            raise CaseError(f"grid: farfield = {self.farfield} chords is too close; use at least 3 (default 25)")
        if self.farfield > MAX_FARFIELD:
            raise CaseError(f"grid: farfield = {self.farfield:g} chords is farther than the grid can reach from the wall "
                            f"spacing {WALL_SPACING} without folding (1000 chords on 16 nodes did); use at most "
                            f"{MAX_FARFIELD:g} (the far-field vortex correction makes 20 - 50 enough; paper: 25)")
        if self.farfield / (self.nj - 1) <= WALL_SPACING:
            raise CaseError(
                f"grid: nj = {self.nj} nodes outward over {self.farfield:g} chords leaves a uniform spacing below the "
                f"wall spacing {WALL_SPACING} that cfd.c_grid grows from; use nj < {int(self.farfield / WALL_SPACING) + 1} "
                "(paper: 60)")
        cells = (self.ni - 1) * (self.nj - 1)
        need = worker_memory_bytes(cells)
        have = _physical_memory_bytes()
        if cells > MAX_CELLS or (have is not None and need > 2 * have):
            raise CaseError(
                f"grid: {self.ni} x {self.nj} has {cells:,} cells: a worker would need about {need / 2**30:.3g} GiB "
                f"for the exact Jacobian's sparse LU (1.5 GB for the paper grid's 10,620 cells, growing as cells^1.2)"
                + (f", more than twice this machine's {have / 2**30:.3g} GiB" if have is not None else "")
                + f" (at most {MAX_CELLS:,} cells in any case); use a coarser grid, e.g. 361 x 120")

    def kwargs(self) -> dict:
        """Keyword arguments of ``cfd.c_grid``."""
        return asdict(self)


PAPER_GRID = GridSpec()

_NAME_RE = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.+\-]*$")


def check_name(owner: str, name) -> str:
    """A case, gust or method name checked: letters, digits and ``_ . + -`` (it names files and table rows).

    Parameters
    ----------
    owner : str
        What is named (``"case"``, ``"gust"``, ``"method"``), for the error message.
    name : any

    Returns
    -------
    str
        ``name``.

    Raises
    ------
    CaseError
        Not such a string.
    """
    if not isinstance(name, str) or not _NAME_RE.match(name):
        raise CaseError(
            f"{owner} name {name!r} must be a non-empty string of letters, digits and _ . + - "
            "(it names files and table rows), e.g. 'naca0012-m05'")
    return name


def naca_code(owner: str, code) -> str:
    """A NACA 4-digit code checked by ``cfd.naca``.

    Parameters
    ----------
    owner : str
        What it belongs to (e.g. ``"case 'mine'"``), for the error message.
    code : str or int
        ``"0012"``, ``"NACA 0012"`` or ``12``.

    Returns
    -------
    str
        The four digits, e.g. ``"0012"``.

    Raises
    ------
    CaseError
        Not a valid code.
    """
    from cfd.geometry import naca  # the submodule: works even where the cfd package namespace is bare

    try:
        naca(code)
    except ValueError as e:  # cfd.GeometryError
        raise CaseError(f"{owner}: {e}") from None
    if isinstance(code, int):
        return f"{code:04d}"
    return str(code).strip().upper().removeprefix("NACA").strip()


@dataclass(frozen=True)
class FlowCase:
    """An aerofoil and flight condition: a test case of the study.

    Parameters
    ----------
    name : str
        Label (letters, digits, ``_ . + -``), e.g. ``"T2"``.
    naca : str
        NACA 4-digit code (``"0010"``, ``"NACA2410"`` or an int); stored as the four digits.
    mach : float
        Free-stream Mach number, ``0 < mach < 1``.
    alpha_deg : float
        Incidence (degrees), finite, ``|alpha_deg| < 90``.
    grid : GridSpec
        C-grid sizes (the paper's 181 x 60 grid by default).

    Raises
    ------
    CaseError
    """

    name: str
    naca: str
    mach: float
    alpha_deg: float = 0.0
    grid: GridSpec = field(default_factory=GridSpec)

    def __post_init__(self):
        name = check_name("case", self.name)
        owner = f"case {name!r}"
        object.__setattr__(self, "naca", naca_code(owner, self.naca))
        mach = _real(owner, "mach", self.mach)
        if not 0.0 < mach < 1.0:
            raise CaseError(f"{owner}: mach = {mach} is out of range; the solver handles 0 < mach < 1")
        object.__setattr__(self, "mach", mach)
        alpha = _real(owner, "alpha_deg", self.alpha_deg)
        if abs(alpha) >= 90.0:
            raise CaseError(f"{owner}: alpha_deg = {alpha} is not an incidence; use |alpha_deg| < 90")
        object.__setattr__(self, "alpha_deg", alpha)
        if not isinstance(self.grid, GridSpec):
            raise CaseError(f"{owner}: grid must be a GridSpec, got {type(self.grid).__name__}")

    @property
    def aerofoil(self) -> str:
        """``"NACA0010"`` etc."""
        return f"NACA{self.naca}"

    def foil(self):
        """The ``cfd.Aerofoil``."""
        from cfd.geometry import naca

        return naca(self.naca)

    def with_grid(self, **sizes) -> "FlowCase":
        """A copy with some grid sizes replaced (``ni``, ``nj``, ``n_surface``, ``farfield``)."""
        try:
            grid = replace(self.grid, **sizes)
        except TypeError as e:
            raise CaseError(f"case {self.name!r}: {e}; grid sizes are ni, nj, n_surface, farfield") from None
        return replace(self, grid=grid)

    def to_dict(self) -> dict:
        """Plain dictionary (JSON-ready)."""
        return asdict(self)


@dataclass(frozen=True)
class GustCase:
    """A gust of the study, in the per-unit-gust-angle convention of shared/DESIGN.md.

    Parameters
    ----------
    name : str
        Label, e.g. ``"G3"``.
    kind : {"one_minus_cosine", "sharp_edged"}
    length : float or None
        Gust length in chords (``> 0``) for the 1-cosine gust; None for the sharp-edged gust.
    angle_deg : float
        Peak effective gust angle (degrees), ``0 < |angle_deg| < 90``; amplitude ``tan(angle_deg)``.

    Raises
    ------
    CaseError
    """

    name: str
    kind: str
    length: Optional[float]
    angle_deg: float

    def __post_init__(self):
        name = check_name("gust", self.name)
        owner = f"gust {name!r}"
        if self.kind not in GUST_KINDS:
            raise CaseError(f"{owner}: kind {self.kind!r} is unknown; use one of {', '.join(GUST_KINDS)}")
        if self.kind == "sharp_edged":
            if self.length is not None:
                raise CaseError(f"{owner}: a sharp-edged gust has no length; leave length out (None)")
        else:
            if self.length is None:
                raise CaseError(f"{owner}: a one_minus_cosine gust needs a length in chords, e.g. 1.0")
            length = _real(owner, "length", self.length)
            if length <= 0.0:
                raise CaseError(f"{owner}: length = {length} must be positive (chords)")
            object.__setattr__(self, "length", length)
        angle = _real(owner, "angle_deg", self.angle_deg)
        if not 0.0 < abs(angle) < 90.0:
            raise CaseError(f"{owner}: angle_deg = {angle} must satisfy 0 < |angle_deg| < 90 (e.g. 1 to 5 deg)")
        object.__setattr__(self, "angle_deg", angle)

    @property
    def amplitude(self) -> float:
        """Peak input ``v_max / U = tan(angle_deg)`` (1 for G6, to round-off)."""
        return math.tan(math.radians(self.angle_deg))

    def to_dict(self) -> dict:
        """Plain dictionary (JSON-ready)."""
        return asdict(self)


def to_gust(gust_case: GustCase, x0: float = -2.0):
    """The ``cfd`` gust object of a gust case, its front at ``x0`` (chords) at ``s = 0``.

    Parameters
    ----------
    gust_case : GustCase
    x0 : float
        Front position at ``s = 0``, upstream (``x0 <= cfd.gust.X0_MAX``); the gust reaches
        ``x_ref = 0`` at ``s = -x0``.

    Returns
    -------
    cfd.OneMinusCosine or cfd.SharpEdged

    Raises
    ------
    TypeError
        ``gust_case`` is not a :class:`GustCase`.
    cfd.GustError
        ``x0`` is too close to the aerofoil (``cfd.GustPositionError``) or not finite.
    """
    from cfd.gust import OneMinusCosine, SharpEdged

    if not isinstance(gust_case, GustCase):
        raise TypeError(f"to_gust() expects a studies.cases.GustCase, got {type(gust_case).__name__}")
    if gust_case.kind == "one_minus_cosine":
        return OneMinusCosine(length=gust_case.length, angle_deg=gust_case.angle_deg, x0=x0)
    return SharpEdged(angle_deg=gust_case.angle_deg, x0=x0)


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
        ``0 < mach < 1``.
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
        name = _default_name(code, _real("case", "mach", mach), _real("case", "alpha_deg", alpha_deg))
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
