"""NACA 4-digit aerofoils with a sharp (closed) trailing edge, and the tabulated NACA 64A010.

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

from ..checks import kind_of, real_array
from ..errors import GeometryError

__all__ = ["Aerofoil", "TabulatedAerofoil", "naca", "naca64a010", "MAX_PANELS", "MAX_CAMBER"]

MAX_PANELS = 1_000_000
"""Most surface panels of an aerofoil's ``coordinates`` (``n``): 16 MB of points. The paper's grid has 100 wall
cells; ``n = 1e8`` would ask for 1.6 GB at the first call of ``coordinates()`` (``cfd.naca`` only stored it)."""


def _check_panels(n):
    """Refuse a panel count that is not a whole number in ``[4, MAX_PANELS]`` (:class:`GeometryError`)."""
    if not isinstance(n, (int, np.integer)) or isinstance(n, bool) or n < 4:
        raise GeometryError(f"n = {n!r} surface panels is invalid; give an integer >= 4, e.g. n=200")
    if n > MAX_PANELS:
        raise GeometryError(f"n = {n} surface panels is more than cfd.mesh.geometry.MAX_PANELS = {MAX_PANELS:.0e} "
                            f"({16 * n / 2**30:.3g} GiB of coordinates); the default n=200 resolves the section, and "
                            "c_grid takes its own n_surface")

MAX_CAMBER = 0.1
"""Bound (excluded) on the maximum camber ``m`` of an :class:`Aerofoil`, fraction of chord: the NACA 4-digit family's
first digit gives 0 - 9 % (``"9912"`` is the most cambered code)."""


def _real(name, value, what):
    """``value`` as a float if it is a finite real number (not a bool or a string), else :class:`GeometryError`."""
    if isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, (bool, np.bool_)):
        if np.isfinite(value):
            return float(value)
    raise GeometryError(f"{name} must be a finite real number ({what}); got {value!r}")


def _points(name, value, what):
    """``value`` as a float array of real numbers without NaN, else :class:`GeometryError` (None and NaN gave
    ``(nan, nan)``, a complex value lost its imaginary part, text failed in NumPy)."""
    v = real_array(value)
    if v is None:
        raise GeometryError(f"{name} must be a real number or an array of real numbers ({what}); got "
                            f"{kind_of(value)} {value!r:.80}")
    if np.any(np.isnan(v)):
        raise GeometryError(f"{name} contains NaN; give real numbers ({what})")
    return v


def _stations(value):
    """Chordwise stations ``x`` as a float array, or :class:`GeometryError` unless they are real numbers (a
    complex value lost its imaginary part with only a ``ComplexWarning``, None became NaN, text failed in
    NumPy). NaN itself passes, and gives NaN, as before."""
    v = real_array(value)
    if v is None:
        raise GeometryError(f"x must be a real number or an array of real chordwise stations (chords, in [0, 1]); "
                            f"got {kind_of(value)} {value!r:.80}")
    return v


def _check_section(m, p, t):
    """Refuse (:class:`GeometryError`) a NACA 4-digit section outside the family's definition: ``0 <= m <
    MAX_CAMBER``, ``0 < p < 1`` when ``m > 0`` (the camber line divides by ``p`` and ``1 - p``; any finite ``p``
    when ``m = 0``, where it is unused), ``0 < t < 1``; all finite (a NaN ``m`` reached the grid generator)."""
    m = _real("m", m, "maximum camber, fraction of chord, e.g. 0.02")
    p = _real("p", p, "position of maximum camber, fraction of chord, e.g. 0.4")
    t = _real("t", t, "maximum thickness, fraction of chord, e.g. 0.12")
    if not 0.0 <= m < MAX_CAMBER:
        raise GeometryError(f"m = {m!r} is outside the NACA 4-digit camber range 0 <= m < {MAX_CAMBER:g} (fraction of "
                            "chord: 2 % camber is m = 0.02; use m = 0 for a symmetric section)")
    if m > 0.0 and not 0.0 < p < 1.0:
        raise GeometryError(f"p = {p!r}: a cambered section (m = {m:g}) needs the position of maximum camber inside "
                            "the chord, 0 < p < 1 (fraction of chord, e.g. 0.4)")
    if not 0.0 < t < 1.0:
        raise GeometryError(f"t = {t!r} is not a thickness: give 0 < t < 1 (fraction of chord, e.g. 0.12 for 12 %)")


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

    Raises
    ------
    GeometryError
        ``m``, ``p`` or ``t`` not a finite real number; ``m`` outside ``[0, MAX_CAMBER)``; ``p`` outside ``(0, 1)``
        when ``m > 0``; ``t`` outside ``(0, 1)``; ``n`` not an integer in ``[4, MAX_PANELS]``.
    """

    code: str
    m: float
    p: float
    t: float
    n: int = 200
    _table: tuple = field(default=None, repr=False, compare=False)

    def __post_init__(self):
        _check_section(self.m, self.p, self.t)
        _check_panels(self.n)
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

        Raises
        ------
        GeometryError
            ``x`` not real numbers (complex, text, None).
        """
        x = _stations(x)
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

        Raises
        ------
        GeometryError
            ``x`` not real numbers (complex, text, None).
        """
        x = _stations(x)
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

        Raises
        ------
        GeometryError
            ``s`` not real numbers (None, text, complex), NaN, or outside ``[0, 1]``.
        """
        s = _points("surface parameter s", s, "in [0, 1]: 0 lower TE, 0.5 LE, 1 upper TE")
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
        _check_panels(n)
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

        Raises
        ------
        GeometryError
            ``arc`` not real numbers (None, text, complex), NaN, or outside ``[0, perimeter]``.
        """
        s_tab, arc_tab = self._table
        arc = _points("arc", arc, f"arc lengths in [0, {arc_tab[-1]:.6f}] chords from the lower trailing edge")
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


# NACA 64A010 half thickness, per cent of chord, at the stations of Abbott & von Doenhoff's Appendix I, as
# tabulated by PDAS ("Appendix I - Profiles", R. Carmichael, Public Domain Aeronautical Software, last updated
# 10 July 2017: the book's tables recomputed with the PDAS program naca456, which implements Ladson, Brooks,
# Hill & Sproles, NASA TM-4741, 1996, whose abstract reports agreement with the previously published ordinates of
# the 6-series and most 6A-series sections "generally within 5e-5"). Leading-edge radius given there: 0.735 %
# chord. Mirrored in github.com/kurtsansom/pdas, docs/source/profiles.rst ("NACA Profile 64A010").
_NACA64A010_X = (0.0, 0.5, 0.75, 1.25, 2.5, 5.0, 7.5, 10.0, 15.0, 20.0, 25.0, 30.0, 35.0, 40.0, 45.0, 50.0, 55.0,
                 60.0, 65.0, 70.0, 75.0, 80.0, 85.0, 90.0, 95.0, 100.0)
_NACA64A010_Y = (0.0, 0.8148, 0.9803, 1.2351, 1.6938, 2.3307, 2.8075, 3.2010, 3.8152, 4.2731, 4.6073, 4.8361,
                 4.9672, 4.9946, 4.8920, 4.6822, 4.3855, 4.0198, 3.5954, 3.1228, 2.6192, 2.1010, 1.5817, 1.0620,
                 0.5393, 0.0)


@dataclass(frozen=True)
class TabulatedAerofoil(Aerofoil):
    """A symmetric section of unit chord given by a table of half-thickness ordinates.

    Same interface as :class:`Aerofoil` (``surface``, ``at_arc``, ``coordinates``, ``perimeter``,
    ``s_leading_edge_arc``, ``thickness``, ``camber``, ``t``), so :func:`cfd.c_grid` takes it unchanged.

    Interpolation. With ``u = sqrt(x)`` signed (``+`` upper, ``-`` lower surface) the surface ordinate is an odd
    function ``y = f(u)`` on ``[-1, 1]``, regular through the leading edge (``y ~ sqrt(2 r_LE) u`` there). The
    table points and their mirror images are interpolated by one cubic spline in ``u`` (not-a-knot ends; the data
    are odd, so the spline is odd and the two surfaces are exact mirror images): ``C2`` everywhere, leading edge
    included, and it passes through every table point. The surface parameter ``s`` is the one of
    :class:`Aerofoil` (``u = sin(pi (2 s - 1) / 2)``, cosine clustering at both edges).

    Trailing edge. The tables used here end at ``y(1) = 0`` (sharp); a table that does not is refused
    (:class:`GeometryError`), so no closure is applied silently.

    Attributes
    ----------
    table_x, table_y : tuple of float
        Stations and half thicknesses of the table (fractions of chord), ``x`` from 0 to 1.
    source : str
        Where the table comes from.
    """

    table_x: tuple = ()
    table_y: tuple = ()
    source: str = ""
    _spline: object = field(default=None, repr=False, compare=False)

    def __post_init__(self):
        from scipy.interpolate import CubicSpline

        x = np.asarray(self.table_x, dtype=float)
        y = np.asarray(self.table_y, dtype=float)
        if x.ndim != 1 or x.shape != y.shape or x.size < 5:
            raise GeometryError("a tabulated section needs at least 5 (x, y) pairs of equal length")
        if x[0] != 0.0 or x[-1] != 1.0 or np.any(np.diff(x) <= 0.0):
            raise GeometryError("table stations must increase strictly from x = 0 to x = 1 (fractions of chord)")
        if y[0] != 0.0 or y[-1] != 0.0 or np.any(y[1:-1] <= 0.0):
            raise GeometryError(
                "table half thicknesses must be positive inside and 0 at both ends (sharp trailing edge for the "
                "C-grid); close a blunt trailing edge explicitly before building the section"
            )
        u = np.sqrt(x)
        spline = CubicSpline(np.concatenate([-u[:0:-1], u]), np.concatenate([-y[:0:-1], y]), bc_type="not-a-knot")
        object.__setattr__(self, "_spline", spline)
        super().__post_init__()

    @property
    def name(self):
        """``"NACA" + code``."""
        return f"NACA{self.code}"

    def _yt(self, sqrt_x, x):
        # Odd spline in u = sqrt(x); evaluated at u >= 0. The clip removes round-off below 0 at the trailing edge.
        return np.maximum(self._spline(np.clip(sqrt_x, 0.0, 1.0)), 0.0)

    def thickness_slope(self, x):
        """Slope ``dy_t/dx`` of the half thickness (dimensionless), for ``0 < x <= 1``.

        Parameters
        ----------
        x : array_like
            Chordwise stations in ``(0, 1]`` (chords).

        Returns
        -------
        ndarray, same shape as ``x``

        Raises
        ------
        GeometryError
            ``x`` not real numbers (complex, text, None).
        """
        x = _stations(x)
        u = np.sqrt(np.clip(x, 1e-300, None))
        return self._spline(u, 1) / (2.0 * u)

    def leading_edge_radius(self):
        """Leading-edge radius (chords) of the interpolated section: ``(dy/du)^2 / 2`` at ``u = 0``."""
        return float(0.5 * self._spline(0.0, 1) ** 2)


def naca64a010(n=200):
    """The NACA 64A010 section (symmetric, 10 % thick at 40 % chord; Isogai's case A, AGARD R-702 CT cases).

    Ordinates: Abbott & von Doenhoff, *Theory of Wing Sections* (Dover, 1959), Appendix I, at the book's 26
    stations, as tabulated (recomputed to 4 decimals with NASA TM-4741's procedure) by PDAS, "Appendix I -
    Profiles", R. L. Carmichael, Public Domain Aeronautical Software (pdas.com/profiles.html, 2017). The table
    ends at ``y = 0`` at ``x = 1``: the trailing edge is sharp as tabulated, no closure is added. Interpolated
    by an odd cubic spline in signed ``sqrt(x)`` (:class:`TabulatedAerofoil`).

    Parameters
    ----------
    n : int
        Default number of cosine-clustered panels of ``coordinates()``.

    Returns
    -------
    TabulatedAerofoil
        ``code = "64A010"``, ``t = 0.10`` (maximum thickness of the table, at ``x = 0.40``).
    """
    _check_panels(n)
    return TabulatedAerofoil(
        code="64A010", m=0.0, p=0.0, t=0.10, n=int(n),
        table_x=tuple(v / 100.0 for v in _NACA64A010_X), table_y=tuple(v / 100.0 for v in _NACA64A010_Y),
        source="Abbott & von Doenhoff (1959) App. I, recomputed by PDAS naca456 (NASA TM-4741)",
    )


def naca(code, n=200):
    """A NACA 4-digit aerofoil of unit chord with a sharp trailing edge (or the tabulated NACA 64A010).

    Parameters
    ----------
    code : str or int
        Four digits ``MPTT``: maximum camber ``M`` % chord at ``P`` tenths of chord, thickness
        ``TT`` % chord, e.g. ``"0012"``, ``"2410"`` (a ``"NACA"`` prefix is accepted). An int is
        zero-padded (``12`` -> ``"0012"``). ``"64A010"`` (also ``"64A-010"``) gives the tabulated
        section of :func:`naca64a010`.
    n : int
        Default number of cosine-clustered panels of ``Aerofoil.coordinates()``.

    Returns
    -------
    Aerofoil
        Frozen (a :class:`TabulatedAerofoil` for ``"64A010"``); ``surface(s)``, ``at_arc(arc)`` and
        ``coordinates(n)`` give points on it.

    Raises
    ------
    GeometryError
        If the code is not four digits (nor ``"64A010"``; other 6A-series codes are refused with a
        message naming the one tabulated), has zero thickness, camber without a position (or a
        position without camber), or ``n`` is not an integer >= 4.
    """
    example = 'use four digits MPTT such as "0012" (symmetric) or "2410" (2 % camber at 0.4 c, 10 % thick)'
    if isinstance(code, (int, np.integer)) and not isinstance(code, bool):
        if not 0 <= int(code) <= 9999:
            raise GeometryError(f"NACA code {code} is not a 4-digit number; {example}")
        code = f"{int(code):04d}"
    if not isinstance(code, str):
        raise GeometryError(f"NACA code must be a string, got {type(code).__name__}; {example}")
    c = code.strip().upper().removeprefix("NACA").strip().replace("-", "")
    if len(c) >= 5 and c[:2].isdigit() and c[2] == "A":
        if c == "64A010":
            return naca64a010(n)
        raise GeometryError(
            f"NACA code {code!r}: of the 6A series only \"64A010\" is tabulated (cfd.naca64a010); "
            f"otherwise {example}"
        )
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
    _check_panels(n)
    return Aerofoil(code=c, m=m, p=p, t=t, n=int(n))
