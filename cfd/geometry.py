"""NACA 4-digit aerofoils with a sharp (closed) trailing edge.

Conventions: chord 1, leading edge of the camber line at ``x = 0``, trailing edge at ``x = 1``.

Thickness distribution (NACA Report 460, with the closed-trailing-edge last coefficient)::

    y_t(x) = 5 t (0.2969 sqrt(x) - 0.1260 x - 0.3516 x^2 + 0.2843 x^3 - 0.1036 x^4)

The original coefficient of ``x^4`` is ``-0.1015``, which leaves a blunt trailing edge of thickness
``2 * 5 t * 0.0021 = 0.021 t`` (0.25 % chord for 12 % thickness). ``-0.1036`` makes the five
coefficients sum to zero, so ``y_t(1) = 0`` (to round-off) and the trailing edge is sharp, as an
inviscid C-grid with a wake cut wants. The change moves the surface by ``0.0105 t x^4``: at most
0.13 % chord for NACA0012, at the trailing edge.

The thickness is applied normal to the camber line::

    x_u = x - y_t sin(theta),  y_u = y_c + y_t cos(theta)
    x_l = x + y_t sin(theta),  y_l = y_c - y_t cos(theta),   theta = atan(dy_c/dx)

so for a cambered section the most forward surface point lies slightly ahead of ``x = 0``.

The surface is parametrised by ``s`` in ``[0, 1]``: ``s = 0`` is the trailing edge on the lower
surface, ``s = 1/2`` the leading edge, ``s = 1`` the trailing edge on the upper surface (the order
of the C-grid's ``i`` index along the wall). The chordwise station is ``x = (1 - cos(phi)) / 2``
with ``phi = pi (2 s - 1)``: uniform ``s`` is cosine clustering at both edges, and the map is smooth
through the leading edge because ``sqrt(x) = |sin(phi / 2)|``.
"""

from dataclasses import dataclass, field

import numpy as np

from .errors import GeometryError

__all__ = ["Aerofoil", "naca"]

# Closed-trailing-edge thickness coefficients: a0 sqrt(x) + a1 x + a2 x^2 + a3 x^3 + a4 x^4.
_A0, _A1, _A2, _A3, _A4 = 0.2969, -0.1260, -0.3516, 0.2843, -0.1036

# Points of the dense table used to invert arc length (the map s -> arc length is smooth).
_N_TABLE = 4001


@dataclass(frozen=True)
class Aerofoil:
    """A NACA 4-digit aerofoil section of unit chord with a sharp trailing edge.

    Attributes
    ----------
    code : str
        The four digits, e.g. ``"2410"``.
    m : float
        Maximum camber, fraction of chord (first digit / 100).
    p : float
        Chordwise position of maximum camber, fraction of chord (second digit / 10).
    t : float
        Maximum thickness, fraction of chord (last two digits / 100).
    n : int
        Default number of panels of ``coordinates()`` (cosine clustered).
    """

    code: str
    m: float
    p: float
    t: float
    n: int = 200
    _table: tuple = field(default=None, repr=False, compare=False)

    def __post_init__(self):
        # Dense table of (s, cumulative arc length) to place points at given arc positions.
        s = np.linspace(0.0, 1.0, _N_TABLE)
        x, y = self.surface(s)
        ds = np.hypot(np.diff(x), np.diff(y))
        arc = np.concatenate([[0.0], np.cumsum(ds)])
        object.__setattr__(self, "_table", (s, arc))

    @property
    def name(self):
        """``"NACA" + code``."""
        return f"NACA{self.code}"

    # ------------------------------------------------------------------ section definition
    def thickness(self, x):
        """Half thickness ``y_t(x)``, measured normal to the camber line.

        Parameters
        ----------
        x : array_like
            Chordwise stations in ``[0, 1]`` (chords).

        Returns
        -------
        ndarray, same shape as ``x``
            Half thickness in chords; zero at ``x = 0`` and (sharp trailing edge) at ``x = 1``.
        """
        x = np.asarray(x, dtype=float)
        return self._yt(np.sqrt(np.clip(x, 0.0, None)), x)

    def _yt(self, sqrt_x, x):
        # Non-negative on [0, 1]; the clip removes the -3e-17 of round-off at the sharp trailing edge.
        return np.maximum(5.0 * self.t * (_A0 * sqrt_x + x * (_A1 + x * (_A2 + x * (_A3 + x * _A4)))), 0.0)

    def camber(self, x):
        """Camber line ``y_c(x)`` and its slope ``dy_c/dx``.

        Parameters
        ----------
        x : array_like
            Chordwise stations in ``[0, 1]`` (chords).

        Returns
        -------
        yc, dyc : ndarray, same shape as ``x``
            Camber ordinate (chords) and slope (dimensionless).
        """
        x = np.asarray(x, dtype=float)
        m, p = self.m, self.p
        if m == 0.0:
            return np.zeros_like(x), np.zeros_like(x)
        front = x < p
        yc = np.where(front, m / p**2 * (2 * p * x - x**2), m / (1 - p) ** 2 * (1 - 2 * p + 2 * p * x - x**2))
        dyc = np.where(front, 2 * m / p**2 * (p - x), 2 * m / (1 - p) ** 2 * (p - x))
        return yc, dyc

    def surface(self, s):
        """Surface points at parameter values ``s``.

        Parameters
        ----------
        s : array_like
            Surface parameter in ``[0, 1]``: 0 lower trailing edge, 1/2 leading edge, 1 upper
            trailing edge. Uniform ``s`` gives cosine clustering at both edges.

        Returns
        -------
        x, y : ndarray, same shape as ``s``
            Surface coordinates in chords.
        """
        s = np.asarray(s, dtype=float)
        if np.any((s < 0.0) | (s > 1.0)):
            raise GeometryError("surface parameter s must lie in [0, 1] (0: lower TE, 0.5: LE, 1: upper TE)")
        phi = np.pi * (2.0 * s - 1.0)
        xc = 0.5 * (1.0 - np.cos(phi))
        half = np.sin(0.5 * phi)  # +sqrt(x) on the upper surface, -sqrt(x) on the lower
        yt_signed = np.sign(half) * self._yt(np.abs(half), xc)  # +y_t upper, -y_t lower
        yc, dyc = self.camber(xc)
        theta = np.arctan(dyc)
        return xc - yt_signed * np.sin(theta), yc + yt_signed * np.cos(theta)

    def coordinates(self, n=None):
        """Cosine-clustered surface points, lower trailing edge -> leading edge -> upper trailing edge.

        Parameters
        ----------
        n : int, optional
            Number of panels (default ``self.n``); ``n + 1`` points, the first and last both at the
            trailing edge ``(1, 0)``.

        Returns
        -------
        x, y : ndarray, shape (n + 1,)
            Coordinates in chords.
        """
        n = self.n if n is None else n
        if not isinstance(n, (int, np.integer)) or isinstance(n, bool) or n < 4:
            raise GeometryError(f"n = {n!r} surface panels is invalid; give an integer >= 4, e.g. n=200")
        return self.surface(np.linspace(0.0, 1.0, int(n) + 1))

    # ------------------------------------------------------------------ arc length
    @property
    def perimeter(self):
        """Surface length (chords), lower trailing edge to upper trailing edge."""
        return float(self._table[1][-1])

    @property
    def s_leading_edge_arc(self):
        """Arc length (chords) from the lower trailing edge to the leading edge ``s = 1/2``."""
        s, arc = self._table
        return float(np.interp(0.5, s, arc))

    def at_arc(self, arc):
        """Surface points at given arc lengths from the lower trailing edge.

        The parameter is found by interpolating a dense arc-length table, then the point is
        evaluated exactly, so the points lie on the aerofoil to round-off.

        Parameters
        ----------
        arc : array_like
            Arc lengths in ``[0, perimeter]`` (chords), measured from the lower trailing edge
            round the leading edge.

        Returns
        -------
        x, y : ndarray, same shape as ``arc``
            Surface coordinates in chords.
        """
        s_tab, arc_tab = self._table
        arc = np.asarray(arc, dtype=float)
        if np.any((arc < -1e-12) | (arc > arc_tab[-1] * (1 + 1e-12))):
            raise GeometryError(f"arc lengths must lie in [0, {arc_tab[-1]:.6f}] (the perimeter)")
        s = np.clip(np.interp(arc, arc_tab, s_tab), 0.0, 1.0)
        return self.surface(s)

    # ------------------------------------------------------------------ derived figures
    def area(self, n=4000):
        """Enclosed area (chords^2) from a polygon of ``n`` cosine-clustered panels.

        For a symmetric section the exact value is the integral of ``2 y_t``:
        ``10 t (2/3 a0 + a1/2 + a2/3 + a3/4 + a4/5) = 0.68088 t`` with the closed trailing edge
        (the often-quoted ``0.685 t`` is the open-trailing-edge value, ``a4 = -0.1015``).
        """
        x, y = self.surface(np.linspace(0.0, 1.0, n + 1))
        # The surface runs clockwise (lower TE -> LE -> upper TE), so the shoelace sum is negative.
        return float(-0.5 * np.sum(x[:-1] * y[1:] - x[1:] * y[:-1]))

    def zero_lift_angle_deg(self, n=2000):
        """Thin-aerofoil-theory zero-lift angle (degrees) from the camber line.

        ``alpha_L0 = -(1/pi) int_0^pi (dy_c/dx)(cos(th) - 1) dth`` with ``x = (1 - cos th) / 2``,
        integrated with the midpoint rule on ``n`` panels (the slope is only piecewise smooth).
        """
        th = (np.arange(n) + 0.5) * np.pi / n
        _, dyc = self.camber(0.5 * (1.0 - np.cos(th)))
        alpha = -np.sum(dyc * (np.cos(th) - 1.0)) * (np.pi / n) / np.pi
        return float(np.degrees(alpha))


def naca(code, n=200):
    """A NACA 4-digit aerofoil of unit chord with a sharp trailing edge.

    Parameters
    ----------
    code : str or int
        Four digits ``MPTT``: maximum camber ``M`` % chord at ``P`` tenths of chord, thickness
        ``TT`` % chord, e.g. ``"0012"``, ``"2410"`` (a ``"NACA"`` prefix is accepted). An int is
        zero-padded (``12`` -> ``"0012"``).
    n : int
        Default number of cosine-clustered panels of ``Aerofoil.coordinates()``.

    Returns
    -------
    Aerofoil
        Frozen; ``surface(s)``, ``at_arc(arc)`` and ``coordinates(n)`` give points on it.

    Raises
    ------
    GeometryError
        If the code is not four digits, has zero thickness, camber without a position (or a
        position without camber), or ``n`` is not an integer >= 4.
    """
    example = 'use four digits MPTT such as "0012" (symmetric) or "2410" (2 % camber at 0.4 c, 10 % thick)'
    if isinstance(code, (int, np.integer)) and not isinstance(code, bool):
        if not 0 <= int(code) <= 9999:
            raise GeometryError(f"NACA code {code} is not a 4-digit number; {example}")
        code = f"{int(code):04d}"
    if not isinstance(code, str):
        raise GeometryError(f"NACA code must be a string, got {type(code).__name__}; {example}")
    c = code.strip().upper().removeprefix("NACA").strip()
    if len(c) != 4:
        raise GeometryError(f"NACA code {code!r} has {len(c)} characters, not 4; {example}")
    if not c.isdigit() or not c.isascii():
        raise GeometryError(f"NACA code {code!r} contains non-digit characters; {example}")
    m, p, t = int(c[0]) / 100.0, int(c[1]) / 10.0, int(c[2:]) / 100.0
    if t == 0.0:
        raise GeometryError(f"NACA code {code!r} has zero thickness; {example}")
    if m > 0.0 and p == 0.0:
        raise GeometryError(
            f"NACA code {code!r} has camber {c[0]} % but no position of maximum camber (second digit 0); "
            "give a position 1-9 tenths of chord, e.g. \"2410\""
        )
    if m == 0.0 and p > 0.0:
        raise GeometryError(
            f"NACA code {code!r} gives a camber position but zero camber; a symmetric section is "
            f"\"00{c[2:]}\", a cambered one e.g. \"2{c[1]}{c[2:]}\""
        )
    if not isinstance(n, (int, np.integer)) or isinstance(n, bool) or n < 4:
        raise GeometryError(f"n = {n!r} surface panels is invalid; give an integer >= 4, e.g. n=200")
    return Aerofoil(code=c, m=m, p=p, t=t, n=int(n))
