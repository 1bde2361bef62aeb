"""One-dimensional point distributions of the C-grid: geometric growth and two-sided Vinokur (tanh) stretching."""

import math

import numpy as np

from ..checks import kind_of, real_array, real_number, whole_number
from ..errors import MeshError

__all__ = ["geometric_distribution", "vinokur_distribution"]


def _solve_monotone(f, target, lo, hi, n_iter=100):
    """Vectorised bisection for ``f(r) = target`` with ``f`` increasing on ``[lo, hi]``."""
    target = np.asarray(target, dtype=float)
    lo = np.full(target.shape, float(lo))
    hi = np.full(target.shape, float(hi))
    for _ in range(n_iter):  # iterations of the root finder, not a loop over cells
        mid = 0.5 * (lo + hi)
        below = f(mid) < target
        lo = np.where(below, mid, lo)
        hi = np.where(below, hi, mid)
    return 0.5 * (lo + hi)


def _intervals(n):
    """``n`` as an int if it is a whole number >= 1, else :class:`MeshError` (a numpy complex ``n`` lost its
    imaginary part with only a ``ComplexWarning``, ``2.5`` gave points that miss the end, 0 NaN or a division by
    zero, text a bare TypeError)."""
    v = whole_number(n)
    if v is None or v < 1:
        raise MeshError(f"n must be a whole number of intervals >= 1; got {kind_of(n)} {n!r:.80}")
    return v


def _lengths(name, value, what):
    """``value`` as a float array, or :class:`MeshError` naming ``name`` unless it holds real numbers (a complex
    value lost its imaginary part with only a ``ComplexWarning``, None became NaN, text failed in NumPy)."""
    v = real_array(value)
    if v is None:
        raise MeshError(f"{name} must be a real number or an array of real numbers ({what}); got "
                        f"{kind_of(value)} {value!r:.80}")
    return v


def _positive(v, name, what):
    """The float array ``v`` if every value is positive and finite, else :class:`MeshError` naming ``name`` (a
    ``first`` of 0 or below, or NaN, gave the ratio 5 or 0.2 of the bisection's bounds without a word; a ``length``
    of 0 or below gave points that do not increase; an infinite one NaN)."""
    bad = v[~(np.isfinite(v) & (v > 0.0))]
    if bad.size:
        raise MeshError(f"{name} must be positive and finite ({what}); got {bad.ravel()[:5].tolist()}")
    return v


def _fraction(name, value, what):
    """``value`` as a float if it is a positive finite real number, else :class:`MeshError` naming ``name`` (a
    numpy complex lost its imaginary part with only a ``ComplexWarning``; a Python complex, text, None, 0 or a
    negative number raised a bare TypeError, ZeroDivisionError or math domain error)."""
    v = real_number(value)
    if v is None or not (math.isfinite(v) and v > 0.0):
        raise MeshError(f"{name} must be a positive finite real number ({what}); got {kind_of(value)} "
                        f"{value!r:.80}")
    return v


def _geometric_sum(r, n):
    """``1 + r + ... + r^(n-1)`` (vectorised, safe at r = 1)."""
    r = np.asarray(r, dtype=float)
    near = np.abs(r - 1.0) < 1e-9
    return np.where(near, np.asarray(n, dtype=float), (r**n - 1.0) / np.where(near, 2.0, r - 1.0))


def geometric_distribution(n, first, length):
    """Cumulative geometric distribution: ``n + 1`` points from 0 to ``length`` (last axis).

    ``first`` and ``length`` broadcast; the ratio is found by bisection.

    Parameters
    ----------
    n : int
        Number of intervals.
    first : float or ndarray
        First interval (chords).
    length : float or ndarray, broadcasting with ``first``
        Total length (chords).

    Returns
    -------
    points : ndarray, shape (..., n + 1)
        Increasing from 0 to ``length``.
    ratio : ndarray, shape (...)
        The growth ratio of neighbouring intervals (in ``[0.2, 5]``).

    Raises
    ------
    MeshError
        If ``n`` is not a whole number >= 1, or ``first`` or ``length`` is not real numbers (complex, text,
        None) or holds a value that is not positive and finite.
    """
    n = _intervals(n)
    first = _positive(_lengths("first", first, "first interval, chords"), "first", "first interval, chords")
    length = _positive(_lengths("length", length, "total length, chords"), "length", "total length, chords")
    ratio = _solve_monotone(lambda r: first * _geometric_sum(r, n), length, 0.2, 5.0)
    k = np.arange(n + 1)
    frac = _geometric_sum(ratio[..., None], k) / _geometric_sum(ratio[..., None], n)
    return length[..., None] * frac, ratio


def vinokur_distribution(n, ds0, ds1):
    """Two-sided tanh stretching (Vinokur 1983): ``n + 1`` points on [0, 1].

    Parameters
    ----------
    n : int
        Number of intervals.
    ds0, ds1 : float
        First and last intervals as fractions of the length.

    Returns
    -------
    ndarray, shape (n + 1,)
        Increasing from 0 to 1.

    Raises
    ------
    MeshError
        If ``n`` is not a whole number >= 1, or ``ds0`` or ``ds1`` is not a positive finite real number
        (complex, text, None, 0).
    """
    n = _intervals(n)
    ds0 = _fraction("ds0", ds0, "first interval as a fraction of the length")
    ds1 = _fraction("ds1", ds1, "last interval as a fraction of the length")
    xi = np.arange(n + 1) / n
    b = 1.0 / (n * math.sqrt(ds0 * ds1))
    if abs(b - 1.0) < 1e-8:
        u = xi
    elif b > 1.0:
        d = float(_solve_monotone(lambda d: np.sinh(d) / d, b, 1e-8, 60.0))
        u = 0.5 * (1.0 + np.tanh(d * (xi - 0.5)) / math.tanh(0.5 * d))
    else:
        # Spacings larger than uniform at both ends: the tangent form (sin(d)/d = b, d < pi).
        d = float(_solve_monotone(lambda d: -np.sin(d) / d, -b, 1e-8, math.pi - 1e-8))
        u = 0.5 * (1.0 + np.tan(d * (xi - 0.5)) / math.tan(0.5 * d))
    a = math.sqrt(ds1 / ds0)
    s = u / (a + (1.0 - a) * u)
    s[0], s[-1] = 0.0, 1.0
    return s
