"""Flow condition, nondimensionalisation and perfect-gas relations.

Nondimensionalisation (fixed; the linearised solvers rely on it)
----------------------------------------------------------------
Free-stream density ``rho_inf = 1``, free-stream speed of sound ``a_inf = 1``, so ``p_inf = 1/gamma``;
lengths in chords; free-stream speed ``|u_inf| = mach``; time in chords / a_inf. At incidence
``alpha`` the free stream is ``u = M cos(alpha)``, ``v = M sin(alpha)``.

Conserved variables ``q = (rho, rho u, rho v, rho E)`` with ``p = (gamma - 1)(rho E - rho |u|^2 / 2)``.
Every helper here takes the variable axis *last* (shape ``(..., 4)``) and is complex-safe (no
``abs``, no comparisons), so that complex-step differentiation goes through it.
"""

from dataclasses import dataclass

import numpy as np

from .checks import real_number
from .errors import FlowConditionError, MeshError

__all__ = ["FlowCondition", "conserved", "primitive", "pressure", "check_gamma", "is_physical", "NON_PHYSICAL",
           "MIN_MACH", "LOW_MACH"]

MIN_MACH = 0.01
"""Lowest free-stream Mach number accepted. The JST dissipation of a compressible scheme scales like ``1 / M`` at
low Mach number; measured on 2026-12-03 on the paper's 181 x 60 grid, NACA 0012 at 2 deg
(``cfd.solve_steady(cfd.c_grid(cfd.naca("0012")), M, 2.0)``): the stagnation Cp (isentropic 1.000) is 1.013,
1.069, 1.241, 1.521 and 2.167 at M = 0.1, 0.05, 0.02, 0.01 and 0.005, the spurious drag 1.7, 6.8, 22, 48 and
97 counts; Cl stays within 1.5 % of its M = 0.1 value. Below 0.01 the pressure field is no longer a solution
of the flow asked for (at M = 0.001 on a coarse grid: Cl 20 % off, stagnation Cp 8.7)."""

LOW_MACH = 0.1
"""Below this Mach number :func:`cfd.solve_steady` warns that the pressure near stagnation and the drag carry
the low-Mach error of :data:`MIN_MACH` (lift and moment are still within about 1 %)."""


@dataclass(frozen=True)
class FlowCondition:
    """A subsonic free stream.

    Parameters
    ----------
    mach : float
        Free-stream Mach number, ``MIN_MACH <= mach < 1`` (:data:`MIN_MACH` = 0.01).
    alpha_deg : float
        Incidence in degrees (finite).
    gamma : float
        Ratio of specific heats, ``> 1``.

    Raises
    ------
    FlowConditionError
        If a value is NaN, infinite or out of range.
    """

    mach: float
    alpha_deg: float = 0.0
    gamma: float = 1.4

    def __post_init__(self):
        for name in ("mach", "alpha_deg", "gamma"):
            given = getattr(self, name)
            value = real_number(given)   # None for a bool, text ("0.5" was parsed), a complex number
            if value is None:
                raise FlowConditionError(f"{name} must be a real number; got {given!r}")
            if not np.isfinite(value):
                raise FlowConditionError(f"{name} must be finite; got {given!r}")
            object.__setattr__(self, name, value)
        if not 0.0 < self.mach < 1.0:
            raise FlowConditionError(
                f"mach = {self.mach} is out of range: the solver handles subsonic free streams, "
                f"{MIN_MACH} <= mach < 1"
            )
        if self.mach < MIN_MACH:
            raise FlowConditionError(
                f"mach = {self.mach} is below {MIN_MACH}, where this compressible scheme's dissipation (which grows "
                "like 1/M) spoils the pressure field (cfd.flow.MIN_MACH); for a nearly incompressible flow use "
                "M = 0.1 - 0.2 and the Prandtl-Glauert factor"
            )
        if not 1.0 < self.gamma < 3.0:
            raise FlowConditionError(f"gamma = {self.gamma} is out of range; use 1 < gamma < 3 (air: 1.4)")
        if abs(self.alpha_deg) >= 90.0:
            raise FlowConditionError(f"alpha_deg = {self.alpha_deg} is not an incidence; use |alpha| < 90 deg")

    @property
    def alpha(self):
        """Incidence in radians."""
        return np.deg2rad(self.alpha_deg)

    @property
    def velocity(self):
        """Free-stream velocity ``(u, v)``, shape (2,), units of a_inf."""
        return self.mach * np.array([np.cos(self.alpha), np.sin(self.alpha)])

    @property
    def rho(self):
        """Free-stream density (1)."""
        return 1.0

    @property
    def p(self):
        """Free-stream pressure ``1 / gamma``."""
        return 1.0 / self.gamma

    @property
    def q(self):
        """Free-stream conserved state, shape (4,)."""
        u, v = self.velocity
        return conserved(1.0, u, v, self.p, self.gamma)

    @property
    def dynamic_pressure(self):
        """``0.5 rho_inf U^2 = 0.5 mach^2``."""
        return 0.5 * self.mach**2


def check_gamma(gamma):
    """Refuse (:class:`FlowConditionError`) a ratio of specific heats that is not a real number in ``(1, 3)``
    (``gamma = 0`` gave a pressure of -0 silently)."""
    if isinstance(gamma, (bool, np.bool_)) or not isinstance(gamma, (int, float, np.integer, np.floating)) \
            or not 1.0 < gamma < 3.0:
        raise FlowConditionError(f"gamma must be a real number in (1, 3) (air: 1.4); got {gamma!r}")


def conserved(rho, u, v, p, gamma=1.4):
    """Conserved variables from primitive ones.

    Parameters
    ----------
    rho, u, v, p : array_like, broadcastable, shape (...)
    gamma : float

    Returns
    -------
    ndarray, shape (..., 4)
        ``(rho, rho u, rho v, rho E)``.

    Raises
    ------
    MeshError
        Arrays that do not broadcast.
    FlowConditionError
        ``gamma`` not a real number in ``(1, 3)``.

    Notes
    -----
    An elementwise conversion: NaN or a non-physical value in gives the same out, as NumPy's arithmetic (the
    solvers check their own states).
    """
    check_gamma(gamma)
    try:
        rho, u, v, p = np.broadcast_arrays(rho, u, v, p)
    except ValueError:
        raise MeshError(f"rho, u, v and p must broadcast to one shape; got shapes {np.shape(rho)}, {np.shape(u)}, "
                        f"{np.shape(v)} and {np.shape(p)}") from None
    rho_e = p / (gamma - 1.0) + 0.5 * rho * (u * u + v * v)
    return np.stack([rho, rho * u, rho * v, rho_e], axis=-1)


def primitive(q, gamma=1.4):
    """Primitive variables from conserved ones.

    Parameters
    ----------
    q : ndarray, shape (..., 4)
    gamma : float

    Returns
    -------
    rho, u, v, p : ndarray, shape (...)

    Raises
    ------
    MeshError
        ``q``'s last axis is not the 4 conserved variables.
    FlowConditionError
        ``gamma`` not a real number in ``(1, 3)``.

    Notes
    -----
    Elementwise, as :func:`conserved`: NaN in gives NaN out.
    """
    check_gamma(gamma)
    if np.shape(q)[-1:] != (4,):
        raise MeshError(f"q has shape {np.shape(q)}; conserved states need a last axis of 4 "
                        "(rho, rho u, rho v, rho E)")
    rho = q[..., 0]
    u = q[..., 1] / rho
    v = q[..., 2] / rho
    p = (gamma - 1.0) * (q[..., 3] - 0.5 * rho * (u * u + v * v))
    return rho, u, v, p


def pressure(q, gamma=1.4):
    """Static pressure of conserved states ``q`` (shape (..., 4)) -> shape (...)."""
    return primitive(q, gamma)[3]


NON_PHYSICAL = "contains NaN, inf or non-positive density or pressure"
"""What :func:`is_physical` refuses, for the messages of the functions that check a state with it."""


def is_physical(q, gamma=1.4):
    """Whether every state of ``q`` (shape (..., 4)) is finite with positive density and pressure: the states the
    solvers (``solve_steady``'s ``q0``), the loads and the linearisation accept.

    Parameters
    ----------
    q : ndarray, shape (..., 4)
    gamma : float

    Returns
    -------
    bool
    """
    q = np.asarray(q)
    if not (np.all(np.isfinite(q)) and np.all(q[..., 0] > 0.0)):
        return False
    return bool(np.all(pressure(q, gamma) > 0.0))
