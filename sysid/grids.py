"""Frequency grids and the bilinear frequency map (paper Eq. 28) linking continuous and discrete frequencies.

``omega = (2 / T) tan(omega_d / 2)``: ``omega`` in ``U_inf / c`` (convective), ``omega_d`` in radians per sample
in ``[0, pi]``; ``omega_d = pi`` is ``omega = inf`` (the continuous feedthrough). McKelvey's grid
``omega_d = pi k / M`` is the one the subspace Algorithm 1 needs.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .errors import FrequencyGridError

__all__ = ["check_period", "check_discrete_frequencies", "check_continuous_frequencies", "check_distinct",
           "discrete_to_continuous", "continuous_to_discrete", "mckelvey_grid", "GRID_RTOL"]

#: Relative tolerance (of pi) that decides whether a grid is equispaced / a sample sits on 0 or pi.
GRID_RTOL = 1e-9


def check_period(T: Any) -> float:
    """Return ``T`` as a positive finite float or raise :class:`FrequencyGridError` (``True`` is not a period)."""
    try:
        if isinstance(T, bool):
            raise TypeError
        Tf = float(T)
    except (TypeError, ValueError):
        raise FrequencyGridError(
            f"sampling period T must be a positive finite number, got {T!r}; pass e.g. T=70/(2*pi)"
        ) from None
    if not math.isfinite(Tf) or Tf <= 0.0:
        raise FrequencyGridError(
            f"sampling period T must be positive and finite, got T={T!r}; pass e.g. T=70/(2*pi)"
        )
    return Tf


def check_discrete_frequencies(omega_d: Any) -> np.ndarray:
    """Return ``omega_d`` as a 1-D float array, or raise :class:`FrequencyGridError` naming the first index
    that is NaN, inf or outside ``[0, pi]`` (to ``GRID_RTOL * pi``)."""
    wd = np.asarray(omega_d, dtype=float).reshape(-1)
    tol = GRID_RTOL * np.pi
    bad = np.flatnonzero(~np.isfinite(wd) | (wd < -tol) | (wd > np.pi + tol))
    if bad.size:
        raise FrequencyGridError(f"omega_d[{int(bad[0])}] = {float(wd[bad[0]])!r}; discrete frequencies must be finite "
                                 "and lie in [0, pi] (rad/sample): repair or drop that sample")
    return wd


def check_continuous_frequencies(omega: Any) -> np.ndarray:
    """Return ``omega`` as a 1-D float array, or raise :class:`FrequencyGridError` naming the first index that
    is NaN or negative (``inf``, the feedthrough sample, is allowed)."""
    w = np.asarray(omega, dtype=float).reshape(-1)
    bad = np.flatnonzero(np.isnan(w) | (w < 0))
    if bad.size:
        raise FrequencyGridError(f"omega[{int(bad[0])}] = {float(w[bad[0]])!r}; continuous frequencies must be >= 0 "
                                 "(U_inf/c units, inf allowed) and not NaN: repair or drop that sample")
    return w


def check_distinct(freq: Any, name: str = "omega_d") -> None:
    """Raise :class:`FrequencyGridError` naming the first repeated frequency (both indices and the value)."""
    w = np.asarray(freq, dtype=float).reshape(-1)
    order = np.argsort(w, kind="stable")
    same = np.flatnonzero(w[order][1:] == w[order][:-1])
    if same.size:
        i, j = sorted((int(order[same[0]]), int(order[same[0] + 1])))
        raise FrequencyGridError(f"{name}[{i}] and {name}[{j}] are the same frequency {float(w[i])!r}; the "
                                 "frequencies must be distinct: average or drop the repeated samples")


def discrete_to_continuous(omega_d: np.ndarray, T: float) -> np.ndarray:
    """Bilinear map ``omega = (2/T) tan(omega_d / 2)`` (paper Eq. 28).

    Parameters
    ----------
    omega_d : array_like, shape (K,)
        Discrete frequencies in ``[0, pi]`` (rad/sample).
    T : float
        Sampling period (convective time units, chords / U_inf).

    Returns
    -------
    omega : ndarray, shape (K,)
        Continuous frequencies (U_inf / c units). ``omega_d == pi`` maps to exactly ``np.inf`` (never the
        huge finite number ``tan(pi/2)`` gives in floating point).

    Raises
    ------
    FrequencyGridError
        ``T`` not positive and finite, or an ``omega_d`` outside ``[0, pi]`` (beyond ``pi`` the tangent wraps to
        negative frequencies) or not finite.
    """
    T = check_period(T)
    wd = np.asarray(omega_d, dtype=float)
    check_discrete_frequencies(wd)
    at_pi = np.isclose(wd, np.pi, rtol=0.0, atol=GRID_RTOL * np.pi)
    with np.errstate(over="ignore"):
        omega = (2.0 / T) * np.tan(np.where(at_pi, 0.0, wd) / 2.0)
    return np.where(at_pi, np.inf, omega)


def continuous_to_discrete(omega: np.ndarray, T: float) -> np.ndarray:
    """Inverse bilinear map ``omega_d = 2 arctan(omega T / 2)``; ``inf`` maps to exactly ``pi``.

    Parameters
    ----------
    omega : array_like, shape (K,)
        Continuous frequencies (U_inf / c units), nonnegative, ``inf`` allowed.
    T : float
        Sampling period (convective time units, chords / U_inf).

    Returns
    -------
    omega_d : ndarray, shape (K,)
        Discrete frequencies in ``[0, pi]``.

    Raises
    ------
    FrequencyGridError
        ``T`` not positive and finite, or an ``omega`` negative or NaN.
    """
    T = check_period(T)
    w = np.asarray(omega, dtype=float)
    check_continuous_frequencies(w)
    return np.where(np.isinf(w), np.pi, 2.0 * np.arctan(np.where(np.isinf(w), 0.0, w) * T / 2.0))


def mckelvey_grid(M: int, T: float) -> tuple[np.ndarray, np.ndarray]:
    """McKelvey's equispaced identification grid and its continuous image.

    Parameters
    ----------
    M : int
        Number of intervals; the grid has ``M + 1`` points ``omega_d = pi k / M``, ``k = 0..M``.
        The paper uses ``M = 256`` (257 frequencies).
    T : float
        Sampling period (convective time units); the paper uses ``T = 70 / (2 pi)``.

    Returns
    -------
    omega_d : ndarray, shape (M + 1,)
        Discrete frequencies, ``omega_d[0] = 0`` and ``omega_d[-1] = pi`` exactly.
    omega : ndarray, shape (M + 1,)
        Continuous frequencies (U_inf / c units), ``(2/T) tan(omega_d / 2)``; ``omega[0] = 0`` and
        ``omega[-1] = np.inf`` exactly.
    """
    if isinstance(M, bool) or not isinstance(M, (int, np.integer)) or M < 1:
        raise FrequencyGridError(f"M must be a positive integer (number of grid intervals), got {M!r}")
    T = check_period(T)
    k = np.arange(M + 1)
    omega_d = np.pi * k / M
    omega_d[-1] = np.pi
    omega = discrete_to_continuous(omega_d, T)
    return omega_d, omega
