"""One-dimensional point distributions of the C-grid: geometric growth and two-sided Vinokur (tanh) stretching."""

import math

import numpy as np

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
    """
    first = np.asarray(first, dtype=float)
    length = np.asarray(length, dtype=float)
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
    """
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
