"""The typical section (pitch and plunge on springs) in Theodorsen's notation.

Equations of motion (``h`` plunge UP in chords, ``alpha`` nose up about the elastic axis, centre of mass
``x_alpha b`` aft of it), from Lagrange's equations with the centre of mass moving ``h c - x_alpha b alpha``::

    m (c h'' - b x_alpha alpha'') + k_h c h = L = q c Cl
    I_ea alpha'' - m b x_alpha c h'' + k_alpha alpha = M = q c^2 Cm

With ``b = c / 2``, ``m = mu pi rho b^2``, ``I_ea = m b^2 r_alpha2``, ``omega_h^2 = k_h / m``,
``omega_alpha^2 = k_alpha / I_ea``, time ``tau = omega_alpha t`` and the speed index ``V = U / (b omega_alpha)``
they read, for ``q = [h, alpha]`` (``'`` = d/d tau)::

    Ms q'' + Ks q = (V^2 / (pi mu)) diag(1, 2) [Cl, Cm]
    Ms = [[2, -x_alpha], [-2 x_alpha, r_alpha2]],   Ks = diag(2 omega_ratio^2, r_alpha2)

(the first row divided by ``m b omega_alpha^2``, the second by ``m b^2 omega_alpha^2``).

Structural damping (optional, default none as in the classical flutter examples this package is checked
against): modal damping ratios ``zeta_1``, ``zeta_2`` of the two in-vacuo modes (ascending frequency), added as
the classical (Caughey) damping matrix ``Ds`` that leaves those modes uncoupled, each decaying with its ratio::

    Ms q'' + Ds q' + Ks q = (V^2 / (pi mu)) diag(1, 2) [Cl, Cm]
    R Ds = (R Ms) Phi diag(2 zeta_i w_i) Phi^T (R Ms),   R = diag(1, 1/2),   Phi^T (R Ms) Phi = I

(``R`` makes ``R Ms`` and ``R Ks`` symmetric: the second row of the equations was divided by ``b`` more than the
first). An undamped section's flutter speed is a conservative bound for a damped one.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .errors import SectionError

__all__ = ["TypicalSection", "check_section", "A_RANGE"]


def _num(name: str, v, *, positive: bool = False) -> float:
    """``v`` as a finite float (> 0 with ``positive``), else :class:`SectionError` naming ``name``; a bool or a string
    is refused, not converted (as :class:`cfd.FlowCondition` does: ``mu="20"`` was parsed)."""
    if isinstance(v, (bool, np.bool_, str, bytes)):
        raise SectionError(f"{name} must be a real number, got {v!r}")
    try:
        f = float(v)
    except (TypeError, ValueError):
        raise SectionError(f"{name} must be a real number, got {v!r}") from None
    if not math.isfinite(f):
        raise SectionError(f"{name} must be finite, got {v!r}")
    if positive and f <= 0:
        raise SectionError(f"{name} must be > 0, got {v!r}")
    return f


@dataclass(frozen=True)
class TypicalSection:
    """Two-degree-of-freedom typical section (Theodorsen's notation).

    Parameters
    ----------
    mu : float
        Mass ratio ``m / (pi rho b^2)`` (> 0).
    a : float
        Elastic axis aft of mid-chord, in semichords: ``-1 <= a <= 1`` on the chord; ahead of the leading edge down
        to ``a = -3`` (a chord ahead; Isogai's swept-wing section has ``a = -2``); behind the trailing edge
        (``a > 1``) is refused.
    x_alpha : float
        Centre of mass aft of the elastic axis, in semichords.
    r_alpha2 : float
        Radius of gyration squared about the elastic axis, in semichords squared; must exceed ``x_alpha^2``
        (the moment of inertia about the centre of mass is positive).
    omega_ratio : float
        ``omega_h / omega_alpha`` (uncoupled plunge over pitch frequency, > 0).
    damping : float or (float, float)
        Modal (structural) damping ratios of the two in-vacuo modes, ascending frequency, each in ``[0, 1)``; one
        number applies to both. Default 0 (undamped). Stored as a tuple of two floats.

    Raises
    ------
    SectionError
        A parameter is not a finite real number (a string such as ``"20"`` or a bool is refused, not converted),
        ``mu``, ``r_alpha2`` or ``omega_ratio`` is not positive, ``r_alpha2 <= x_alpha^2``, the elastic axis lies
        outside ``-3 <= a <= 1`` (behind the trailing edge, or more than a chord ahead of the leading edge), or a
        damping ratio outside ``[0, 1)``.

    Examples
    --------
    Hodges & Pierce's example section:

    >>> sec = TypicalSection(mu=20, a=-0.2, x_alpha=0.1, r_alpha2=0.24, omega_ratio=0.4)
    >>> round(sec.elastic_axis, 3)
    0.4
    """

    mu: float
    a: float
    x_alpha: float
    r_alpha2: float
    omega_ratio: float
    damping: Any = 0.0

    def __post_init__(self) -> None:
        sa = object.__setattr__
        sa(self, "mu", _num("mu", self.mu, positive=True))
        sa(self, "a", _num("a", self.a))
        if not A_RANGE[0] <= self.a <= A_RANGE[1]:
            raise SectionError(
                f"a = {self.a!r} puts the elastic axis {'behind the trailing edge' if self.a > 1 else 'more than a chord ahead of the leading edge'}"
                f" (a is in semichords aft of mid-chord: -1 is the leading edge, 1 the trailing edge); allowed "
                f"{A_RANGE[0]:g} <= a <= {A_RANGE[1]:g}; check the units (semichords, not chords or percent)")
        sa(self, "damping", _damping(self.damping))
        sa(self, "x_alpha", _num("x_alpha", self.x_alpha))
        sa(self, "r_alpha2", _num("r_alpha2", self.r_alpha2, positive=True))
        sa(self, "omega_ratio", _num("omega_ratio", self.omega_ratio, positive=True))
        if self.r_alpha2 <= self.x_alpha**2:
            raise SectionError(
                f"r_alpha2 = {self.r_alpha2} must exceed x_alpha^2 = {self.x_alpha**2} (the inertia about the centre "
                "of mass, m b^2 (r_alpha2 - x_alpha^2), must be positive); check the radius of gyration is about the "
                "elastic axis and squared"
            )

    @property
    def elastic_axis(self) -> float:
        """Elastic axis in chords from the leading edge, ``(1 + a) / 2``."""
        return 0.5 * (1.0 + self.a)

    @property
    def mass_matrix(self) -> np.ndarray:
        """``Ms``, shape (2, 2), for ``q = [h/c, alpha]`` in ``tau = omega_alpha t`` (see the module notes)."""
        return np.array([[2.0, -self.x_alpha], [-2.0 * self.x_alpha, self.r_alpha2]])

    @property
    def stiffness_matrix(self) -> np.ndarray:
        """``Ks = diag(2 omega_ratio^2, r_alpha2)``, shape (2, 2)."""
        return np.diag([2.0 * self.omega_ratio**2, self.r_alpha2])

    @property
    def damping_matrix(self) -> np.ndarray:
        """``Ds``, shape (2, 2): modal damping of the in-vacuo modes (see the module notes); zeros when undamped."""
        if self.damping == (0.0, 0.0):
            return np.zeros((2, 2))
        R = np.diag([1.0, 0.5])
        M, K = R @ self.mass_matrix, R @ self.stiffness_matrix
        from scipy.linalg import eigh

        w2, Phi = eigh(K, M)                      # ascending, Phi^T M Phi = I
        w = np.sqrt(np.maximum(w2, 0.0))
        Dm = M @ Phi @ np.diag(2.0 * np.asarray(self.damping) * w) @ Phi.T @ M
        return np.linalg.solve(R, Dm)

    @property
    def load_matrix(self) -> np.ndarray:
        """``diag(1, 2) / (pi mu)``: generalised forces per ``V^2 [Cl, Cm]``, shape (2, 2)."""
        return np.diag([1.0, 2.0]) / (np.pi * self.mu)

    def natural_frequencies(self) -> np.ndarray:
        """In-vacuo coupled frequencies ``omega / omega_alpha`` (ascending), shape (2,).

        Roots of ``det(Ks - w^2 Ms) = 0``:
        ``(r2 - x_a^2) w^4 - r2 (1 + s^2) w^2 + r2 s^2 = 0`` with ``s = omega_ratio``.
        """
        r2, xa, s2 = self.r_alpha2, self.x_alpha, self.omega_ratio**2
        w2 = np.roots([r2 - xa**2, -r2 * (1 + s2), r2 * s2])
        return np.sort(np.sqrt(w2.real))


A_RANGE = (-3.0, 1.0)
"""Elastic-axis positions :class:`TypicalSection` takes, semichords aft of mid-chord (trailing edge at 1)."""


def _damping(v) -> tuple:
    """``v`` (a number or a pair) as two damping ratios in ``[0, 1)``, or :class:`SectionError`."""
    vals = np.atleast_1d(np.asarray(v, dtype=object)).ravel().tolist() if not isinstance(v, (int, float)) else [v]
    if len(vals) == 1:
        vals = vals * 2
    if len(vals) != 2:
        raise SectionError(f"damping must be one ratio or two (one per in-vacuo mode, ascending frequency), got {v!r}")
    out = tuple(_num("damping", x) for x in vals)
    if any(not 0.0 <= z < 1.0 for z in out):
        raise SectionError(f"damping ratios must lie in [0, 1) (fractions of critical: 0.02 is 2 %), got {v!r}")
    return out


def check_section(section) -> TypicalSection:
    """``section`` itself if it is a :class:`TypicalSection`, else :class:`SectionError` naming what it got.

    Parameters
    ----------
    section : TypicalSection

    Returns
    -------
    TypicalSection
    """
    if not isinstance(section, TypicalSection):
        raise SectionError(f"section must be an aeroelastic.TypicalSection(mu, a, x_alpha, r_alpha2, omega_ratio), "
                           f"got {type(section).__name__}")
    return section
