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

__all__ = ["check_period", "real_frequencies", "check_discrete_frequencies", "check_continuous_frequencies", "check_distinct",
           "discrete_to_continuous", "continuous_to_discrete", "mckelvey_grid", "GRID_RTOL", "MAX_GRID_M",
           "period_factor", "period_range", "check_period_resolves", "PERIOD_WARN_FACTOR", "PERIOD_MAX_FACTOR"]

#: Relative tolerance (of pi) that decides whether a grid is equispaced / a sample sits on 0 or pi.
GRID_RTOL = 1e-9

MAX_GRID_M = 2**16
"""Largest ``M`` of :func:`mckelvey_grid` (65 537 frequencies). Not the grid's own memory (1 MB) but what any
use of it costs: McKelvey's Algorithm 1 builds Hankel matrices of ``q p`` rows and about ``2 M m`` columns, so
at order 50 with two outputs a grid of ``2**16`` intervals already needs 0.4 GB of complex numbers, and
``10**8`` asked 1.6 GB for the grid alone (``10**9`` did not return). The paper uses ``M = 256``; the study
runner allows at most 4096."""

PERIOD_WARN_FACTOR = 10.0
""":func:`check_period_resolves` warns when the centre frequency ``2 / T`` of the bilinear map lies more than
this factor outside the data's positive finite frequencies (see there for the measurements)."""

PERIOD_MAX_FACTOR = 100.0
""":func:`check_period_resolves` refuses ``T`` when ``2 / T`` lies more than this factor outside the data's
positive finite frequencies."""


def check_period(T: Any) -> float:
    """Return ``T`` as a positive finite float or raise :class:`FrequencyGridError` (``True`` and the string
    ``"1"`` are not periods)."""
    try:
        if isinstance(T, (bool, np.bool_, str, bytes)):
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


def real_frequencies(freq: Any, name: str, *, allow_nan: bool = False) -> np.ndarray:
    """``freq`` as a 1-D float array, or :class:`FrequencyGridError` naming ``name`` when it is not an array of
    real numbers (text, None, complex values: NumPy dropped their imaginary part with only a warning) or holds NaN
    (unless ``allow_nan``: the caller reports it). ``inf`` is left to the caller."""
    if freq is None or isinstance(freq, (str, bytes)) or np.iscomplexobj(freq):
        raise FrequencyGridError(f"{name} must be real frequencies (an array of real numbers), got {freq!r}: pass "
                                 "the frequencies themselves, not s = i omega or z = exp(i omega_d)")
    try:
        w = np.asarray(freq, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise FrequencyGridError(f"{name} must be an array of real frequencies, got {freq!r}") from None
    if not allow_nan and np.isnan(w).any():
        raise FrequencyGridError(f"{name}[{int(np.flatnonzero(np.isnan(w))[0])}] = nan; frequencies must be numbers: "
                                 "repair or drop that sample")
    return w


def check_discrete_frequencies(omega_d: Any) -> np.ndarray:
    """Return ``omega_d`` as a 1-D float array, or raise :class:`FrequencyGridError` naming the first index
    that is NaN, inf or outside ``[0, pi]`` (to ``GRID_RTOL * pi``), or when it is not real numbers."""
    wd = real_frequencies(omega_d, "omega_d", allow_nan=True)
    tol = GRID_RTOL * np.pi
    bad = np.flatnonzero(~np.isfinite(wd) | (wd < -tol) | (wd > np.pi + tol))
    if bad.size:
        raise FrequencyGridError(f"omega_d[{int(bad[0])}] = {float(wd[bad[0]])!r}; discrete frequencies must be finite "
                                 "and lie in [0, pi] (rad/sample): repair or drop that sample")
    return wd


def check_continuous_frequencies(omega: Any) -> np.ndarray:
    """Return ``omega`` as a 1-D float array, or raise :class:`FrequencyGridError` naming the first index that
    is NaN or negative (``inf``, the feedthrough sample, is allowed), or when it is not real numbers."""
    w = real_frequencies(omega, "omega", allow_nan=True)
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
    wd = _real_array(omega_d, "omega_d")
    check_discrete_frequencies(wd)
    at_pi = np.isclose(wd, np.pi, rtol=0.0, atol=GRID_RTOL * np.pi)
    with np.errstate(over="ignore"):
        omega = (2.0 / T) * np.tan(np.where(at_pi, 0.0, wd) / 2.0)
    return np.where(at_pi, np.inf, omega)


def _real_array(x: Any, name: str) -> np.ndarray:
    """``x`` as a float array; :class:`FrequencyGridError` for text, objects or complex values."""
    if np.iscomplexobj(x):
        raise FrequencyGridError(f"{name} must be real frequencies; got complex values")
    try:
        return np.asarray(x, dtype=float)
    except (TypeError, ValueError):
        raise FrequencyGridError(f"{name} must be an array of real frequencies, got {x!r}"[:200]) from None


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
    w = _real_array(omega, "omega")
    check_continuous_frequencies(w)
    return np.where(np.isinf(w), np.pi, 2.0 * np.arctan(np.where(np.isinf(w), 0.0, w) * T / 2.0))


def _band(omega: Any) -> tuple[float, float] | None:
    """``(omega_lo, omega_hi)``: the smallest and largest positive finite frequency, or None without any."""
    w = np.asarray(omega, dtype=float).reshape(-1)
    w = w[np.isfinite(w) & (w > 0)]
    return (float(w.min()), float(w.max())) if w.size else None


def period_factor(T: float, omega: Any) -> float:
    """How far the bilinear map's centre frequency ``2 / T`` lies outside the data's frequencies.

    The map ``omega_d = 2 arctan(omega T / 2)`` sends ``omega = 2 / T`` to ``omega_d = pi / 2``; frequencies far
    below it crowd at ``omega_d = 0`` (``z = 1``) and far above it at ``omega_d = pi`` (``z = -1``), where a
    discrete model holds their dynamics in ever fewer digits (``z - 1 ~ i omega T``).

    Parameters
    ----------
    T : float
        Sampling period (the time unit of ``1 / omega``), positive and finite.
    omega : array_like, shape (K,)
        Continuous frequencies; zero and ``inf`` samples are ignored.

    Returns
    -------
    float
        ``(2 / T) / omega_hi`` when ``2 / T`` is above the largest positive finite frequency ``omega_hi``,
        ``omega_lo / (2 / T)`` when it is below the smallest ``omega_lo``, else 1 (also 1 when the data have no
        positive finite frequency).
    """
    T = check_period(T)
    band = _band(omega)
    if band is None:
        return 1.0
    lo, hi = band
    with np.errstate(over="ignore"):
        centre = 2.0 / T
        return float(max(centre / hi, lo / centre, 1.0)) if np.isfinite(centre) else float("inf")


def period_range(omega: Any, factor: float = PERIOD_MAX_FACTOR) -> tuple[float, float]:
    """The sampling periods ``T`` whose centre frequency ``2 / T`` lies within ``factor`` of the frequencies
    ``omega``: ``(2 / (factor omega_hi), 2 factor / omega_lo)``.

    The one rule of the project for a period against a frequency band: :func:`check_period_resolves` applies
    it to the data's own frequencies with :data:`PERIOD_MAX_FACTOR`; the study runner's ``T_RANGE``
    (0.02 .. 200) is this range for the aerofoil's gust response, ``omega = 0.01 .. 100``, with ``factor = 1``.

    Parameters
    ----------
    omega : array_like
        Frequencies (zero and ``inf`` ignored); at least one positive finite one.
    factor : float
        ``>= 1``.

    Returns
    -------
    (float, float)
        ``(T_min, T_max)``.

    Raises
    ------
    FrequencyGridError
        No positive finite frequency, or ``factor`` below 1 or not finite.
    """
    band = _band(omega)
    if band is None:
        raise FrequencyGridError("no positive finite frequency: the period cannot be checked against the data")
    if not (isinstance(factor, (int, float, np.floating)) and math.isfinite(factor) and factor >= 1.0):
        raise FrequencyGridError(f"factor must be a finite number >= 1, got {factor!r}")
    lo, hi = band
    return 2.0 / (factor * hi), 2.0 * factor / lo


def check_period_resolves(T: float, omega: Any, *, what: str = "T") -> float:
    """Check that the bilinear map with period ``T`` resolves the data's frequencies ``omega``.

    The rule (:func:`period_factor`, :func:`period_range`): the map's centre frequency ``2 / T`` must lie within
    :data:`PERIOD_MAX_FACTOR` (100) of the data's positive finite frequencies, and a ``RuntimeWarning`` says so
    beyond :data:`PERIOD_WARN_FACTOR` (10). Measured on a four-pole system sampled at 60 frequencies from 0.1 to
    10 (plus 0 and inf), order 4, exact data, the max errors of ``identify`` (subspace / relocation with
    ``stable=True, dc_gain="match"``) are 4e-10 / 7e-14 with ``2 / T`` 10 times above the data, 2e-8 / 5e-4 at
    20, 7e-7 / 0.27 at 50, 6e-6 / 0.53 at 100; 1.5e-9 / 1e-13 at 10 times below, 6e-9 / 0.055 at 25 below
    (docs/sysid.md, "Input checks", has the script); ``T = 1e-300`` (a factor of 2e299) returned a model 119 % off
    (every sample mapped to ``z = 1``).

    Parameters
    ----------
    T : float
        Sampling period, positive and finite.
    omega : array_like, shape (K,)
        The data's continuous frequencies (zero and ``inf`` ignored).
    what : str
        The name of the period in messages.

    Returns
    -------
    float
        :func:`period_factor` (1 when ``2 / T`` lies among the data's frequencies).

    Raises
    ------
    FrequencyGridError
        ``T`` not positive and finite, or the factor above :data:`PERIOD_MAX_FACTOR`.

    Warns
    -----
    RuntimeWarning
        The factor above :data:`PERIOD_WARN_FACTOR`.
    """
    T = check_period(T)
    factor = period_factor(T, omega)
    if factor <= PERIOD_WARN_FACTOR:
        return factor
    lo, hi = _band(omega)
    T_lo, T_hi = period_range(omega)
    with np.errstate(over="ignore"):
        centre = 2.0 / T
    side = ("0 (z = 1): T is too small" if centre > hi else "pi (z = -1): T is too large")
    text = (f"{what} = {T:.6g} puts the bilinear map's centre frequency 2/T = {centre:.6g} {factor:.3g} times "
            f"{'above' if centre > hi else 'below'} the data's frequencies ({lo:.6g} .. {hi:.6g}), so the samples "
            f"crowd near omega_d = {side}")
    if factor > PERIOD_MAX_FACTOR:
        raise FrequencyGridError(f"{text}, and the discrete model cannot resolve them; use {T_lo:.6g} <= T <= "
                                 f"{T_hi:.6g} (2/T within {PERIOD_MAX_FACTOR:g} times the data's frequencies), "
                                 f"e.g. T = {2.0 / math.sqrt(lo * hi):.6g} (2/T at their geometric mean)")
    import warnings

    warnings.warn(f"{text}, where the fit loses accuracy (sysid.grids.check_period_resolves); prefer T = "
                  f"{2.0 / math.sqrt(lo * hi):.6g} (2/T at the geometric mean of the data's frequencies)",
                  RuntimeWarning, stacklevel=3)
    return factor


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

    Raises
    ------
    FrequencyGridError
        ``M`` not a positive integer or above :data:`MAX_GRID_M`; ``T`` not positive and finite.
    """
    if isinstance(M, bool) or not isinstance(M, (int, np.integer)) or M < 1:
        raise FrequencyGridError(f"M must be a positive integer (number of grid intervals), got {M!r}")
    if M > MAX_GRID_M:
        raise FrequencyGridError(
            f"M = {M} intervals: at most M = {MAX_GRID_M} (sysid.grids.MAX_GRID_M): the identification's Hankel "
            f"matrices hold about 2 M samples per output row, 0.4 GB at order 50 already at M = {MAX_GRID_M}; the "
            "paper uses M = 256. Use fewer intervals, or sample the band you need with FrequencyResponse.take")
    T = check_period(T)
    k = np.arange(M + 1)
    omega_d = np.pi * k / M
    omega_d[-1] = np.pi
    omega = discrete_to_continuous(omega_d, T)
    return omega_d, omega
