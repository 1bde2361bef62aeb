"""The case types of a study: :class:`FlowCase` (aerofoil, flight condition, grid) and :class:`GustCase`
(a gust per unit gust angle), and :func:`to_gust`, the ``cfd`` gust object of a gust case."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field, replace
from typing import Optional

from .case_fields import CaseError, check_name, check_real, naca_code
from .grid_spec import GridSpec

MIN_MACH = 0.01
"""The solver's lowest free-stream Mach number, ``cfd.flow.MIN_MACH`` (restated, not imported: importing cfd would
make ``lfdrom cases`` load SciPy; a test checks the two agree), so that a study file is refused when it is read,
not when its steady piece runs."""

__all__ = ["FlowCase", "GustCase", "GUST_KINDS", "to_gust"]

GUST_KINDS = ("one_minus_cosine", "sharp_edged")


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
        Free-stream Mach number, ``0.01 <= mach < 1`` (:data:`MIN_MACH`).
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
        mach = check_real(owner, "mach", self.mach)
        if not MIN_MACH <= mach < 1.0:
            raise CaseError(f"{owner}: mach = {mach} is out of range; the solver handles {MIN_MACH} <= mach < 1 "
                            "(below 0.01 its low-Mach dissipation spoils the pressure field, docs/validation.md)")
        object.__setattr__(self, "mach", mach)
        alpha = check_real(owner, "alpha_deg", self.alpha_deg)
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
        from cfd.mesh.geometry import naca

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
    """A gust of the study, in the per-unit-gust-angle convention of docs/conventions.md.

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
            raise CaseError(f"{owner}: kind {self.kind!r} is unknown; use one of {', '.join(GUST_KINDS)}", "kind")
        if self.kind == "sharp_edged":
            if self.length is not None:
                raise CaseError(f"{owner}: a sharp-edged gust has no length; leave length out (None)", "length")
        else:
            if self.length is None:
                raise CaseError(f"{owner}: a one_minus_cosine gust needs a length in chords, e.g. 1.0", "length")
            length = check_real(owner, "length", self.length)
            if length <= 0.0:
                raise CaseError(f"{owner}: length = {length} must be positive (chords)", "length")
            object.__setattr__(self, "length", length)
        angle = check_real(owner, "angle_deg", self.angle_deg)
        if not 0.0 < abs(angle) < 90.0:
            raise CaseError(f"{owner}: angle_deg = {angle} must satisfy 0 < |angle_deg| < 90 (e.g. 1 to 5 deg)",
                            "angle_deg")
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
        raise TypeError(f"to_gust() expects a studies.config.cases.GustCase, got {type(gust_case).__name__}")
    if gust_case.kind == "one_minus_cosine":
        return OneMinusCosine(length=gust_case.length, angle_deg=gust_case.angle_deg, x0=x0)
    return SharpEdged(angle_deg=gust_case.angle_deg, x0=x0)
