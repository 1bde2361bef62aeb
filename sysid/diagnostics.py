"""Data diagnostics: are frequency-response data consistent with a causal, stable, real LTI system?

:func:`diagnose` looks at each output/input channel of a :class:`sysid.FrequencyResponse` before it is
fitted, and says by how much the data depart from what any causal, stable, real state-space model can
represent. Three checks:

**(a) Negative-time energy** (equispaced McKelvey grid ``omega_d = pi k / M``, ``k = 0..M`` only). The
samples are extended by conjugate symmetry to the full circle (``2M`` points, ``H(2 pi - omega_d) =
conj H(omega_d)``, as in McKelvey's Algorithm 1) and inverse-FFT'd into the periodised discrete impulse
response ``h[t]``, ``t = -M..M-1`` (NumPy's ``fftfreq`` order: the ambiguous sample ``t = +-M`` counts as
negative). The diagnostic is ``E_neg = sum_{t<0} h[t]^2 / sum_t h[t]^2``. For a causal system whose
impulse response has decayed within ``M`` samples it is the aliased tail, ``~ rho^(2M)`` for spectral radius
``rho``; measured data that respond before the input reaches the reference point have ``E_neg > 0``. By
Parseval, a model whose impulse response has decayed within ``M`` samples cannot fit the data with a relative
RMS error (RMS over the conjugate-extended grid) below ``sqrt(E_neg)``: ``E_neg = 1e-4`` is a 1 % floor.

**(b) Kramers-Kronig residual** (any grid; needs a sampling period ``T``, else a default one, below). A
causal stable real system's response on the unit circle ``H(theta) = sum_{n>=0} h[n] exp(-1j theta n)``
has ``Im H = -Hilb[Re H]``, the periodic Hilbert transform (conjugate function)::

    Im H(theta) = -1/(2 pi) P.V. int_{-pi}^{pi} Re H(phi) cot((theta - phi) / 2) dphi
                = -1/(2 pi) int_{-pi}^{pi} (Re H(phi) - Re H(theta)) cot((theta - phi) / 2) dphi

(the second form subtracts the singularity: the principal value of ``int cot`` over a period is 0, and the
integrand is now bounded, ``-> -2 d Re H / d theta`` at ``phi = theta``). Because the bilinear map
``omega_d = 2 arctan(omega T / 2)`` maps the right half ``s``-plane onto the outside of the unit disc, this is
exactly the continuous Kramers-Kronig relation of ``H(i omega)``, written on a finite interval, for any
``T``; ``T`` only changes the discretisation. The integral is evaluated with the periodic trapezoid rule on
the data's own frequencies, extended by the even symmetry of ``Re H`` to ``[-pi, pi)`` (gaps, e.g. missing
``omega = 0`` or ``omega = inf`` samples, are spanned linearly); the derivative at ``phi = theta`` is the
three-point nonuniform difference. The residual per channel is ``max_k |Im H_KK - Im H| / max_k |H|``.

*Threshold from the data's resolution.* The rule's error is not a fixed number: it is third order in the
spacing for smooth data on McKelvey's grid, but of order one or below next to a branch point at ``omega = 0``
(Theodorsen's and Sears' functions, ``1 / (1 + sqrt(s))``: order 1/2), and largest next to that point. It is
estimated from the data (:func:`kk_discretisation`): the rule on every second and every fourth sample, whose
largest differences ``d2``, ``d1`` on their own samples give the observed order ``2^q = d1 / d2`` and the full
rule's error ``d2 / r``, ``r = d1 / d2`` clipped to ``[1, 3]``. A channel is flagged where its residual exceeds
``max(kk_tol, 3 x`` that estimate``)`` (``kk_tol = 1e-2``: differences below 1 % of the peak are not worth a
flag) plus the band-limited bound below, at the samples where that bound is below the threshold.

*Unsampled ends (band-limited data).* Without ``omega = 0`` (or ``inf``) the real part between 0 and the lowest
sample (the highest and pi) is unknown and the rule bridges it with a straight line. If the truth differs from
that line by at most ``delta``, the imaginary part at ``theta`` moves by at most ``delta / (2 pi) int_gap
|cot((theta - phi)/2)| dphi`` (closed form, :func:`kk_truncation_bound`); ``delta`` is the data's largest slope
of ``Re H`` times the gap's width (the response assumed to vary in the gap no faster than between the samples),
at most twice the peak. The bound is infinite next to a gap and small far from it. Where it leaves fewer than
a quarter of the samples checkable (data measured in a band far from 0 and inf, e.g. 75 - 110 GHz) the check
says it does not apply: no verdict either way.

*Improper responses.* Data without an ``omega = inf`` sample whose ``|H|`` grows at the top of the band (log-log
slope above 0.5, :func:`high_frequency_slope`; ``k^2`` for an apparent-mass load) are named improper: no proper
state-space model follows them outside the band, and the plain KK relation (which needs a decaying response)
is skipped for them.

**(a') Negative-time energy on a finer grid.** A causal response's negative-time energy on McKelvey's grid is its
aliased tail and falls as ``M`` grows (slowly next to a branch point: 5.6e-4 at ``M = 32`` and 3.8e-5 at 128 for
``1 / (1 + sqrt(s))``); an advance or noise keep it. The flag uses the energy extrapolated from the subgrids
``M / 2`` and ``M / 4`` (:func:`negative_time_limit`).

**(c) The DC and infinite-frequency samples.** A real system's ``H(omega = 0)`` is real: its imaginary part
relative to the channel's peak is reported and flagged above ``dc_imag_tol`` (``dc_gain="match"`` uses only
the real part). Whether the data contain ``omega = 0`` and ``omega = inf`` (the continuous feedthrough,
imposed by :func:`sysid.identify` as ``G(z = -1)``) is reported too.

Default ``T`` for data on continuous frequencies without one: ``T = 2 / sqrt(omega_lo omega_hi)`` with the
smallest positive and the largest finite ``omega``, which puts their geometric mean at ``omega_d = pi / 2``
(:func:`default_T`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Sequence

import numpy as np

from .arrays import freeze_array_fields
from .data_checks import check_nonzero_outputs
from .errors import ArgumentTypeError, FrequencyGridError, OptionError
from .frd import FrequencyResponse, continuous_to_discrete
from .grids import check_period

__all__ = ["diagnose", "DataDiagnostics", "default_T", "negative_time_energy", "negative_time_limit",
           "kramers_kronig_imag", "kk_discretisation", "kk_truncation_bound", "high_frequency_slope", "delayed"]

NEG_TIME_TOL = 1e-4
KK_TOL = 1e-2
DC_IMAG_TOL = 1e-6
KK_SAFETY = 3.0
"""The KK residual must exceed this many times its estimated quadrature error (:func:`kk_discretisation`, an
asymptotic estimate) before it counts."""
KK_MIN_SAMPLES = 12
"""Fewest samples for the KK check: its error estimate needs three nested grids of at least three samples."""
KK_MIN_CHECKED = 0.25
"""Least fraction of the samples at which the band-limited bound (:func:`kk_truncation_bound`) leaves the check
meaningful; below it the check does not apply (e.g. data measured in a band far from 0 and inf)."""
IMPROPER_SLOPE = 0.5
"""A log-log slope of ``|H|`` above this at the top of the band (no ``omega = inf`` sample) names the response
improper (:func:`high_frequency_slope`)."""
_TINY = np.finfo(float).tiny


def default_T(omega: np.ndarray) -> float:
    """Sampling period that spreads continuous frequencies over ``(0, pi)``: ``2 / sqrt(omega_lo omega_hi)``.

    Parameters
    ----------
    omega : array_like, shape (K,)
        Continuous frequencies (U_inf / c units); zero and ``inf`` samples are ignored.

    Returns
    -------
    float
        ``T`` such that the bilinear map sends the geometric mean of the smallest positive and the largest
        finite frequency to ``omega_d = pi / 2``.

    Raises
    ------
    FrequencyGridError
        No positive finite frequency, or frequencies so small (subnormal) that ``T`` would overflow.
    """
    w = np.asarray(omega, dtype=float)
    w = w[np.isfinite(w) & (w > 0)]
    if w.size == 0:
        raise FrequencyGridError("no positive finite frequency to choose T from; give T explicitly")
    T = 2.0 / (math.sqrt(float(w.min())) * math.sqrt(float(w.max())))   # a product of two roots: no underflow
    if not math.isfinite(T):
        raise FrequencyGridError(
            f"the frequencies ({float(w.min()):.3g} .. {float(w.max()):.3g}) are too small to choose a sampling period "
            "from (T would overflow); express them in other units (e.g. rad/s or U_inf / c) or give T explicitly")
    return T


def negative_time_energy(H: np.ndarray) -> np.ndarray:
    """Fraction of the periodised impulse response's energy at negative discrete time.

    Parameters
    ----------
    H : array_like, complex, shape (p, m, M + 1)
        Samples on McKelvey's equispaced grid ``omega_d = pi k / M``, ``k = 0..M``.

    Returns
    -------
    ndarray, shape (p, m)
        ``sum_{t=-M..-1} h[t]^2 / sum_t h[t]^2`` (module docstring); 0 for an all-zero channel.
    """
    H = np.asarray(H, dtype=complex)
    M = H.shape[-1] - 1
    ext = np.concatenate([H, np.conj(H[..., -2:0:-1])], axis=-1)  # 2M points around the circle
    ext[..., 0] = ext[..., 0].real  # a real sequence: the DC and Nyquist samples of the DFT are real
    ext[..., M] = ext[..., M].real
    h = np.fft.ifft(ext, axis=-1).real
    e = h**2
    total = e.sum(axis=-1)
    neg = e[..., M:].sum(axis=-1)
    return np.where(total > 0, neg / np.maximum(total, _TINY), 0.0)


def _periodic_grid(theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Even extension of sorted ``theta`` in ``[0, pi]`` to ``[-pi, pi)``: ``(phi, src)`` with ``src`` the index
    of the data sample each point of ``phi`` takes its value from."""
    K = theta.size
    idx = np.arange(K)
    pos = idx[(theta > 0) & (theta < np.pi)]  # mirrored: everything strictly inside (0, pi)
    at_pi = idx[theta >= np.pi]
    phi = np.concatenate([-theta[at_pi], -theta[pos[::-1]], theta[idx[(theta < np.pi)]]])
    src = np.concatenate([at_pi, pos[::-1], idx[theta < np.pi]])
    # theta == 0 appears once (in the last block); theta == pi once, as -pi
    return phi, src


def kramers_kronig_imag(re_H: np.ndarray, omega_d: np.ndarray) -> np.ndarray:
    """Imaginary part that causality implies from the real part, on the data's own discrete frequencies.

    Parameters
    ----------
    re_H : array_like, shape (..., K)
        Real part of the response at ``omega_d``.
    omega_d : array_like, shape (K,)
        Discrete frequencies in ``[0, pi]``, distinct (any order, any spacing).

    Returns
    -------
    ndarray, shape (..., K)
        ``-1/(2 pi) int (Re H(phi) - Re H(theta)) cot((theta - phi)/2) dphi`` by the periodic trapezoid rule
        (module docstring, with its discretisation error).
    """
    wd = np.asarray(omega_d, dtype=float)
    f = np.asarray(re_H, dtype=float)
    order = np.argsort(wd, kind="stable")
    theta = wd[order]
    fs = f[..., order]
    phi, src = _periodic_grid(theta)
    n = phi.size
    nxt = np.roll(phi, -1)
    nxt[-1] += 2 * np.pi
    prv = np.roll(phi, 1)
    prv[0] -= 2 * np.pi
    h_plus, h_minus = nxt - phi, phi - prv
    w = (h_plus + h_minus) / 2.0  # periodic trapezoid weights
    F = fs[..., src]  # (..., n)
    Fp, Fm = np.roll(F, -1, axis=-1), np.roll(F, 1, axis=-1)
    dF = (h_minus**2 * Fp - h_plus**2 * Fm + (h_plus**2 - h_minus**2) * F) / (h_minus * h_plus * (h_minus + h_plus))
    # evaluation points: the position of each sorted data sample in phi (the last block holds theta < pi,
    # theta == pi sits at phi[0] = -pi)
    pos_in_phi = np.empty(theta.size, dtype=int)
    for j in range(n):
        if phi[j] >= 0 or (phi[j] == -np.pi):
            pos_in_phi[src[j]] = j
    d = theta[:, None] - phi[None, :]
    d = (d + np.pi) % (2 * np.pi) - np.pi  # wrap into [-pi, pi)
    self_pt = np.zeros((theta.size, n), dtype=bool)
    self_pt[np.arange(theta.size), pos_in_phi] = True
    with np.errstate(divide="ignore", invalid="ignore"):
        cot = np.where(self_pt, 0.0, 1.0 / np.tan(np.where(self_pt, 1.0, d / 2.0)))
    Wk = w[None, :] * cot  # (K, n)
    fi = fs  # value at the evaluation points, (..., K)
    integral = F @ Wk.T - fi * Wk.sum(axis=1)  # sum_j w_j (F_j - f_i) cot_ij, j != i
    integral = integral + w[pos_in_phi] * (-2.0 * dF[..., pos_in_phi])
    out_sorted = -integral / (2.0 * np.pi)
    out = np.empty_like(out_sorted)
    out[..., order] = out_sorted
    return out


def _subgrid(order: np.ndarray, step: int) -> np.ndarray:
    """Every ``step``-th of the sorted sample indices ``order``, the last one always kept."""
    sub = order[::step]
    return sub if sub[-1] == order[-1] else np.append(sub, order[-1])


def kk_discretisation(re_H: np.ndarray, omega_d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The causal imaginary part and the estimated error of its quadrature, from the data's own resolution.

    The rule of :func:`kramers_kronig_imag` is applied on all samples (spacing ``h``), on every second and on
    every fourth (``2h``, ``4h``). Its largest error sits next to where the response is least smooth (a branch
    point at ``omega = 0`` as in Theodorsen's function, a sharp resonance), and moves with the grid, so the
    estimate works with the largest differences of each coarse rule on its own samples: ``d2 = max |I(2h) -
    I(h)|`` over the samples of the ``2h`` grid (about the ``2h`` rule's largest error) and ``d1 = max |I(4h) -
    I(2h)|`` over those of the ``4h`` grid. For an error ``c h^q`` their ratio is ``r = d1 / d2 = 2^q`` whatever
    the order ``q`` (three for smooth data on McKelvey's grid, below one next to a branch point, ``1/2`` for
    ``1 / (1 + sqrt(s))``), and the full rule's largest error is about ``d2 / r``. ``r`` is clipped to ``[1, 3]``:
    below 1 the rule does not converge (the samples do not resolve the response) and the estimate is ``d2``; above
    3 (second order or better) the estimate stays ``d2 / 3``, because a coarse grid that misses a feature makes
    ``d1`` large without the rule converging faster. :func:`diagnose` flags only a residual above three times
    the estimate. Measured on exact data (tests/sysid/test_diagnostics.py): the residual is 0.6 - 2 times the
    estimate for Theodorsen's function and ``1 / (1 + sqrt(s))`` at ``M = 32 .. 512``.

    Parameters
    ----------
    re_H : array_like, shape (..., K)
    omega_d : array_like, shape (K,)
        Distinct discrete frequencies in ``[0, pi]``.

    Returns
    -------
    im_kk : ndarray, shape (..., K)
        :func:`kramers_kronig_imag` on all samples.
    error : ndarray, shape (...)
        Its estimated error (max over the frequencies, in the units of ``re_H``), NaN for fewer than
        :data:`KK_MIN_SAMPLES` samples.
    """
    wd = np.asarray(omega_d, dtype=float)
    f = np.asarray(re_H, dtype=float)
    im_kk = kramers_kronig_imag(f, wd)
    if wd.size < KK_MIN_SAMPLES:
        return im_kk, np.full(f.shape[:-1], np.nan)
    order = np.argsort(wd, kind="stable")
    half, quarter = _subgrid(order, 2), _subgrid(order, 4)
    im2 = kramers_kronig_imag(f[..., half], wd[half])
    im4 = kramers_kronig_imag(f[..., quarter], wd[quarter])
    pos_in_half = {int(k): i for i, k in enumerate(half)}
    q_in_half = np.array([pos_in_half[int(k)] for k in quarter])
    d2 = np.abs(im2 - im_kk[..., half]).max(axis=-1)
    d1 = np.abs(im4 - im2[..., q_in_half]).max(axis=-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.clip(d1 / d2, 1.0, 3.0)
    return im_kk, np.where(d2 > 0, d2 / r, d1)


def kk_truncation_bound(omega_d: np.ndarray, re_H: np.ndarray, peak: np.ndarray) -> np.ndarray:
    """Bound of what the unsampled ends of ``[0, pi]`` can change in the causal imaginary part, per sample,
    relative to the peak (the band-limited form of the check).

    Without an ``omega = 0`` sample the even real part is unknown on ``(-a, a)``, ``a`` the lowest sampled
    ``omega_d``; without ``omega = inf`` on ``(b, 2 pi - b)``, ``b`` the highest. The rule bridges each gap with a
    straight line, so if the true ``Re H`` differs from that line by at most ``delta`` there, the imaginary part at
    ``theta`` changes by at most ``delta / (2 pi) int_gap |cot((theta - phi) / 2)| dphi``, integrated in closed form
    (``int cot(x / 2) dx = 2 ln sin(x / 2)``). ``delta`` follows from the data, assuming the response varies in
    the gap no faster than between the samples: the largest slope ``L`` of ``Re H`` between neighbouring samples
    times the gap's width, and never more than ``2 max |H|``. The bound is infinite at the sample next to a gap.

    Parameters
    ----------
    omega_d : array_like, shape (K,)
        Distinct discrete frequencies in ``[0, pi]``.
    re_H : array_like, shape (p, m, K)
    peak : array_like, shape (p, m)
        ``max |H|`` per channel.

    Returns
    -------
    ndarray, shape (p, m, K)
        The bound divided by the channel's peak (0 with both end samples).
    """
    wd = np.asarray(omega_d, dtype=float)
    f = np.asarray(re_H, dtype=float)
    tol = 1e-9 * np.pi
    order = np.argsort(wd, kind="stable")
    th, fs = wd[order], f[..., order]
    with np.errstate(divide="ignore", invalid="ignore"):
        slope = np.abs(np.diff(fs, axis=-1) / np.diff(th)).max(axis=-1) if th.size > 1 else np.zeros(f.shape[:-1])

    def F(x):   # 2 ln sin(x / 2), x in [0, 2 pi]
        with np.errstate(divide="ignore"):
            return 2.0 * np.log(np.abs(np.sin(x / 2.0)))

    def abs_cot_integral(x1, x2):   # int_{x1}^{x2} |cot(x/2)| dx, 0 <= x1 <= x2 <= 2 pi
        return np.where(x2 <= np.pi, F(x2) - F(x1), np.where(x1 >= np.pi, F(x1) - F(x2), -F(x1) - F(x2)))

    bound = np.zeros(f.shape)
    pk = np.asarray(peak, dtype=float)[..., None]
    if th[0] > tol:   # no omega = 0 sample: the gap (-a, a)
        a = th[0]
        delta = np.minimum(slope * a, 2.0 * np.asarray(peak))[..., None]
        bound = bound + delta / (2.0 * np.pi) * abs_cot_integral(th - a, th + a)[order.argsort()] / pk
    if th[-1] < np.pi - tol:   # no omega = inf sample: the gap (b, 2 pi - b)
        b = th[-1]
        delta = np.minimum(slope * (np.pi - b), 2.0 * np.asarray(peak))[..., None]
        bound = bound + delta / (2.0 * np.pi) * abs_cot_integral(b - th, 2.0 * np.pi - b - th)[order.argsort()] / pk
    return np.where(np.isnan(bound), np.inf, bound)


def high_frequency_slope(omega: np.ndarray, H: np.ndarray) -> np.ndarray | None:
    """Log-log slope of ``|H|`` over the top of the sampled band, per channel; None when it cannot be measured.

    Least squares of ``log |H|`` on ``log omega`` over the samples in the highest quarter of the positive finite
    frequencies on a log scale (at least 6 samples, a band of at least a factor 2); a proper response tends to
    its finite feedthrough (slope 0 or negative), ``k^2`` growth has slope 2. Growth counts only when the lower
    and upper halves of that window agree on it (within a factor 1.5): the flank of a resonance just above the
    band steepens towards it and is reported as slope 0, not as improper.

    Parameters
    ----------
    omega : array_like, shape (K,) or None
    H : array_like, complex, shape (p, m, K)

    Returns
    -------
    ndarray, shape (p, m), or None
        None without continuous frequencies, with an ``omega = inf`` sample (the data say the response is finite
        there), or with too few samples at the top; 0 where the growth is not a steady power law.
    """
    if omega is None:
        return None
    w = np.asarray(omega, dtype=float)
    if np.isinf(w).any():
        return None
    pos = np.flatnonzero(np.isfinite(w) & (w > 0))
    if pos.size < 3:
        return None
    lw = np.log(w[pos])
    top = pos[lw >= lw.max() - 0.25 * (lw.max() - lw.min())]
    if top.size < 3 or w[top].max() < 2.0 * w[top].min():
        return None
    mag = np.abs(np.asarray(H))[..., top]
    if np.any(mag <= 0) or top.size < 6:
        return None

    def fit(idx):
        x = np.log(w[top][idx]) - np.log(w[top][idx]).mean()
        y = np.log(mag[..., idx])
        return (y - y.mean(axis=-1, keepdims=True)) @ x / (x @ x)

    order = np.argsort(w[top])
    lower, upper = fit(order[: order.size // 2]), fit(order[order.size // 2:])
    whole = fit(order)
    # a power law has one slope over the window; the flank of a resonance just above the band steepens
    steady = (np.minimum(lower, upper) > 0) & (np.maximum(lower, upper) <= 1.5 * np.minimum(lower, upper))
    return np.where(steady, whole, np.minimum(whole, 0.0))


@dataclass(frozen=True)
class DataDiagnostics:
    """Result of :func:`diagnose`. Arrays are indexed ``[output, input]``.

    Attributes
    ----------
    outputs, inputs : tuple of str
    negative_time_energy : ndarray (p, m) or None
        ``E_neg`` of each channel (module docstring); ``None`` unless the grid is McKelvey's equispaced one.
    rms_floor : ndarray (p, m) or None
        ``sqrt(E_neg)``: the relative RMS error below which no model with a decayed impulse response fits.
    kk_residual : ndarray (p, m)
        Kramers-Kronig residual ``max |Im H_KK - Im H| / max |H|`` over the samples where the band-limited bound
        is below the threshold; NaN where the check does not apply (``kk_applies``).
    kk_discretisation : ndarray (p, m)
        Estimated quadrature error of the causal imaginary part, from the data's resolution
        (:func:`kk_discretisation`; NaN for fewer than 12 samples).
    dc_imag : ndarray (p, m) or None
        ``|Im H(omega = 0)| / max |H|``; ``None`` when the data have no ``omega = 0`` sample.
    has_dc, has_inf : bool
        Whether the data contain ``omega = 0`` and ``omega = inf`` (``omega_d = pi``).
    feedthrough : ndarray (p, m) or None
        Real part of the ``omega = inf`` sample.
    T : float
        Sampling period used for the KK check (the data's, or :func:`default_T`).
    T_is_default : bool
    equispaced : bool
    flagged : ndarray of bool (p, m)
        Channels that fail any check.
    warnings : tuple of str
        Plain-language findings with what to do; empty when the data look consistent.
    thresholds : dict
        ``neg_time``, ``kk``, ``dc_imag``, ``kk_safety`` used.
    negative_time_limit : ndarray (p, m) or None
        The negative-time energy extrapolated to a fine grid (:func:`negative_time_limit`), which the flag uses;
        None off McKelvey's grid or when ``M`` is not a multiple of 4 of at least 16.
    kk_threshold : ndarray (p, m) or None
        ``max(kk_tol, 3 x kk_discretisation)``.
    kk_applies : ndarray of bool (p, m) or None
        Whether the KK check applies (enough samples, and the unsampled ends leave a quarter of them checkable).
    high_frequency_slope : ndarray (p, m) or None
        Log-log slope of ``|H|`` at the top of the band (:func:`high_frequency_slope`); above 0.5 the channel is
        named improper.
    notes : tuple of str
        Findings that are not inconsistencies (a grid too coarse for a causal response's slowly decaying tail);
        they do not change :attr:`ok`.
    """

    outputs: tuple
    inputs: tuple
    negative_time_energy: np.ndarray | None = field(repr=False)
    rms_floor: np.ndarray | None = field(repr=False)
    kk_residual: np.ndarray = field(repr=False)
    kk_discretisation: np.ndarray = field(repr=False)
    dc_imag: np.ndarray | None = field(repr=False)
    has_dc: bool
    has_inf: bool
    feedthrough: np.ndarray | None = field(repr=False)
    T: float
    T_is_default: bool
    equispaced: bool
    flagged: np.ndarray = field(repr=False)
    warnings: tuple = ()
    thresholds: dict = field(default_factory=dict, repr=False)
    negative_time_limit: np.ndarray | None = field(default=None, repr=False)
    kk_threshold: np.ndarray | None = field(default=None, repr=False)
    kk_applies: np.ndarray | None = field(default=None, repr=False)
    high_frequency_slope: np.ndarray | None = field(default=None, repr=False)
    notes: tuple = ()

    def __post_init__(self):
        freeze_array_fields(self)   # the arrays of a frozen result are read-only too

    @property
    def ok(self) -> bool:
        """True when no channel is flagged, every check applied and was computed, and nothing else was found."""
        return not self.warnings and not self.flagged.any() and self._all_computed()

    def _all_computed(self) -> bool:
        nums = [self.kk_residual] + ([] if self.negative_time_energy is None else [self.negative_time_energy])
        return all(np.isfinite(np.asarray(a, dtype=float)).all() for a in nums)

    def _status(self, i: int, j: int) -> str:
        if self.flagged[i, j]:
            return "FLAG"
        if self.kk_applies is not None and not self.kk_applies[i, j]:
            return "KK n/a"
        if not np.isfinite(self.kk_residual[i, j]) or (self.negative_time_energy is not None
                                                       and not np.isfinite(self.negative_time_energy[i, j])):
            return "not computed"
        return "ok"

    def channels(self) -> list[dict]:
        """One dict per channel: ``output, input, neg_time_energy, kk_residual, kk_discretisation, dc_imag,
        flagged, status`` (None where a check does not apply; ``status`` is ``"FLAG"``, ``"KK n/a"``,
        ``"not computed"`` or ``"ok"``)."""
        rows = []
        for i, o in enumerate(self.outputs):
            for j, u in enumerate(self.inputs):
                rows.append(dict(
                    output=o, input=u,
                    neg_time_energy=None if self.negative_time_energy is None else float(self.negative_time_energy[i, j]),
                    kk_residual=float(self.kk_residual[i, j]),
                    kk_discretisation=float(self.kk_discretisation[i, j]),
                    dc_imag=None if self.dc_imag is None else float(self.dc_imag[i, j]),
                    flagged=bool(self.flagged[i, j]),
                    status=self._status(i, j),
                ))
        return rows

    def _table(self, markdown: bool) -> list[str]:
        head = ["channel", "neg.-time energy", "KK residual", "(discr. est.)", "Im H(0)/peak", "flag"]
        rows = []
        for c in self.channels():
            rows.append([
                f"{c['output']}/{c['input']}",
                "n/a" if c["neg_time_energy"] is None else f"{c['neg_time_energy']:.2e}",
                "n/a" if math.isnan(c["kk_residual"]) else f"{c['kk_residual']:.2e}",
                "n/a" if math.isnan(c["kk_discretisation"]) else f"{c['kk_discretisation']:.1e}",
                "no sample" if c["dc_imag"] is None else f"{c['dc_imag']:.1e}",
                c["status"],
            ])
        if markdown:
            out = ["| " + " | ".join(head) + " |", "|" + "|".join(" --- " for _ in head) + "|"]
            out += ["| " + " | ".join(r) + " |" for r in rows]
            return out
        widths = [max(len(x) for x in col) for col in zip(head, *rows)]
        out = ["  ".join(v.ljust(w) for v, w in zip(head, widths)).rstrip()]
        out += ["  ".join(v.ljust(w) for v, w in zip(r, widths)).rstrip() for r in rows]
        return out

    def _header(self) -> str:
        grid = ("equispaced McKelvey grid" if self.equispaced else
                "non-equispaced grid: negative-time energy needs McKelvey's grid, the KK residual applies")
        tnote = ("no T (discrete frequencies only)" if math.isnan(self.T) else f"T = {self.T:.6g}") + (" (default 2/sqrt(omega_lo omega_hi), for the KK check only)"
                                       if self.T_is_default else "")
        samples = (f"omega = 0 sample: {'yes' if self.has_dc else 'no'}; "
                   f"omega = inf sample: {'yes' if self.has_inf else 'no'}")
        return f"data diagnostics ({grid}, {tnote}); {samples}"

    def summary(self) -> str:
        """Plain-text report: one line per channel, then the warnings (or that the data look consistent)."""
        lines = [self._header()] + ["  " + s for s in self._table(False)] + ["note: " + n for n in self.notes]
        if self.warnings or not self.ok:
            lines += ["warning: " + w for w in self.warnings]
        else:
            lines.append("the data are consistent with a causal, stable, real LTI system within the thresholds "
                         f"(negative-time energy <= {self.thresholds['neg_time']:g}, KK residual <= "
                         f"max({self.thresholds['kk']:g}, 3 x its quadrature error estimated from the data's "
                         f"resolution), Im H(0)/peak <= {self.thresholds['dc_imag']:g})")
        return "\n".join(lines)

    def markdown(self) -> str:
        """The same report as Markdown (a table and a bullet list)."""
        lines = [self._header() + ".", ""] + self._table(True) + [""] + [f"- Note: {n}" for n in self.notes]
        if self.warnings or not self.ok:
            lines += [f"- {w}" for w in self.warnings]
        else:
            lines.append("- The data are consistent with a causal, stable, real LTI system within the thresholds "
                         f"(negative-time energy <= {self.thresholds['neg_time']:g}, KK residual <= "
                         f"max({self.thresholds['kk']:g}, 3 x its quadrature error estimated from the data's "
                         f"resolution), Im H(0)/peak <= {self.thresholds['dc_imag']:g}).")
        return "\n".join(lines)


def negative_time_limit(H: np.ndarray) -> np.ndarray | None:
    """The negative-time energy the equispaced data tend to as the grid is refined, per channel.

    A causal response's negative-time energy on McKelvey's grid is the aliased tail of its impulse response, which
    falls as ``M`` grows (geometrically for rational systems, algebraically next to a branch point at
    ``omega = 0``: ``1 / (1 + sqrt(s))`` gives 5.6e-4 at ``M = 32`` and 3.8e-5 at 128); a response before the input
    (a time advance) or noise keep it. From the grids ``M``, ``M / 2`` and ``M / 4`` (subsamples of the data):
    ``E(M) - d2 / (r - 1)`` with ``d2 = E(M/2) - E(M)``, ``r = (E(M/4) - E(M/2)) / d2`` when the energy falls
    with ``r > 1.5``, else ``E(M)`` itself.

    Parameters
    ----------
    H : array_like, complex, shape (p, m, M + 1)
        Samples on McKelvey's grid.

    Returns
    -------
    ndarray, shape (p, m), or None
        None when ``M`` is not a multiple of 4 of at least 16 (then only ``E(M)`` is known).
    """
    H = np.asarray(H, dtype=complex)
    M = H.shape[-1] - 1
    if M % 4 or M < 16:
        return None
    e1 = negative_time_energy(H)
    e2 = negative_time_energy(H[..., ::2])
    e4 = negative_time_energy(H[..., ::4])
    d2, d1 = e2 - e1, e4 - e2
    with np.errstate(divide="ignore", invalid="ignore"):
        r = d1 / d2
        lim = np.where((d2 > 0) & (d1 > 0) & (r > 1.5), e1 - d2 / (r - 1.0), e1)
    return np.maximum(lim, 0.0)


def _names(ch: Sequence[tuple[int, int]], frf: FrequencyResponse) -> str:
    return ", ".join(f"{frf.outputs[i]}/{frf.inputs[j]}" for i, j in ch)


def _kk_grid(frf: FrequencyResponse, T: float | None) -> tuple[np.ndarray, float, bool, str]:
    """``(omega_d, T_used, T_is_default, note)`` for the KK check: the data's own ``omega_d`` when their ``T``
    resolves their frequencies, else the map with :func:`default_T` (the continuous KK relation is the same for
    every ``T``; only the quadrature changes)."""
    from .grids import PERIOD_MAX_FACTOR, period_factor

    if frf.omega is None:   # discrete data without T: their own unit circle
        return np.asarray(frf.omega_d, dtype=float), float("nan"), False, ""
    if frf.omega_d is not None and period_factor(frf.T, frf.omega) <= PERIOD_MAX_FACTOR:
        return np.asarray(frf.omega_d, dtype=float), float(frf.T), False, ""
    note = ""
    if frf.omega_d is not None:
        note = (f"the data's T = {frf.T:.6g} does not resolve their frequencies (sysid.grids.check_period_resolves; "
                "identify refuses it), so the KK check maps them with the default T")
    T_used = check_period(T) if (T is not None and frf.omega_d is None) else default_T(frf.omega)
    return continuous_to_discrete(frf.omega, T_used), T_used, T is None or frf.omega_d is not None, note


def diagnose(
    frf: FrequencyResponse,
    *,
    neg_time_tol: float = NEG_TIME_TOL,
    kk_tol: float = KK_TOL,
    dc_imag_tol: float = DC_IMAG_TOL,
    T: float | None = None,
) -> DataDiagnostics:
    """Check frequency-response data for consistency with a causal, stable, real LTI system.

    Parameters
    ----------
    frf : FrequencyResponse
        Data on a discrete grid (with or without ``T``) or on continuous frequencies.
    neg_time_tol : float
        Flag a channel whose negative-time energy fraction, extrapolated to a fine grid
        (:func:`negative_time_limit`), exceeds this (default 1e-4: a 1 % RMS floor).
    kk_tol : float
        The smallest Kramers-Kronig residual (peak-normalised) worth reporting (default 1e-2). A channel is
        flagged where its residual exceeds ``max(kk_tol, 3 x`` the quadrature error estimated from the data's
        resolution, :func:`kk_discretisation`) plus the band-limited bound of the unsampled ends
        (:func:`kk_truncation_bound`), at the samples where that bound is below the threshold; when those are
        fewer than a quarter of the samples, or fewer than 12 samples in all, the check does not apply.
    dc_imag_tol : float
        Flag ``|Im H(0)| / max |H|`` above this (default 1e-6, as :attr:`FrequencyResponse.dc_gain`).
    T : float, optional
        Sampling period for the KK check of data on continuous frequencies without one (default
        :func:`default_T`); ignored when the data have ``omega_d``. Data whose own ``T`` does not resolve their
        frequencies (:func:`sysid.grids.check_period_resolves`) are checked with :func:`default_T`.

    Returns
    -------
    DataDiagnostics
        Per-channel numbers, flags, plain-language ``warnings`` and :meth:`DataDiagnostics.summary`. A check
        that could not be computed (a NaN) is reported as such and never as consistent.

    Raises
    ------
    TypeError
        ``frf`` is not a :class:`FrequencyResponse`.
    OptionError
        A tolerance that is not a nonnegative number.
    FrequencyGridError
        A frequency appears twice; ``T`` given and not positive and finite; or, for data on continuous
        frequencies only, no ``T`` given and no positive finite frequency to choose the default from.
    FrequencyDataError
        An output that is zero at every frequency (nothing to check).

    Notes
    -----
    The formulas, the tolerances' meaning and the error estimates are in the module docstring of
    :mod:`sysid.diagnostics`.
    """
    if not isinstance(frf, FrequencyResponse):
        raise ArgumentTypeError(f"diagnose() expects a sysid.FrequencyResponse, got {type(frf).__name__}")
    for name, value in (("neg_time_tol", neg_time_tol), ("kk_tol", kk_tol), ("dc_imag_tol", dc_imag_tol)):
        if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)) \
                or not (np.isfinite(value) and value >= 0):
            raise OptionError(f"{name} must be a nonnegative number, got {value!r}")
    if T is not None:
        check_period(T)
    H = np.asarray(frf.H)
    check_nonzero_outputs(H, frf.outputs)   # (all-zero data passed every check)
    p, m, K = H.shape
    peak = np.maximum(np.abs(H).max(axis=-1), _TINY)

    wd, T_used, T_is_default, t_note = _kk_grid(frf, T)
    if np.unique(wd).size != wd.size:
        raise FrequencyGridError("diagnose() needs distinct frequencies; the data repeat a frequency, "
                                 "average or drop the repeated samples")

    equi = frf.is_equispaced
    neg = negative_time_energy(H) if equi else None
    neg_lim = negative_time_limit(H) if equi else None
    floor = None if neg is None else np.sqrt(neg)

    im_kk, kk_disc = kk_discretisation(H.real, wd)
    kk_disc = kk_disc / peak
    kk_lim = np.maximum(kk_tol, KK_SAFETY * np.nan_to_num(kk_disc, nan=np.inf))   # (p, m)
    bound = kk_truncation_bound(wd, H.real, peak)   # (p, m, K)
    res_k = np.abs(im_kk - H.imag) / peak[..., None]
    checked = bound < kk_lim[..., None]
    kk_applies = (K >= KK_MIN_SAMPLES) & (checked.mean(axis=-1) >= KK_MIN_CHECKED) & np.isfinite(kk_lim)
    with np.errstate(invalid="ignore"):
        kk_res = np.where(checked, res_k, -np.inf).max(axis=-1)
    kk_res = np.where(kk_applies & np.isfinite(kk_res), kk_res, np.nan)
    kk_computed = ~kk_applies | np.isfinite(kk_res)   # not applicable is not "not computed"

    slope = high_frequency_slope(frf.omega, H)
    improper = np.zeros((p, m), bool) if slope is None else slope > IMPROPER_SLOPE

    tol = 1e-9 * np.pi
    k_dc = np.flatnonzero(np.abs(wd) <= tol)
    k_inf = np.flatnonzero(np.abs(wd - np.pi) <= tol)
    has_dc, has_inf = bool(k_dc.size), bool(k_inf.size)
    dc_imag = np.abs(H[:, :, k_dc[0]].imag) / peak if has_dc else None
    ft = np.array(H[:, :, k_inf[0]].real) if has_inf else None

    neg_judged = neg if neg_lim is None else neg_lim
    flag_neg = np.zeros((p, m), bool) if neg is None else ~(neg_judged <= neg_time_tol)   # NaN flags
    with np.errstate(invalid="ignore"):
        flag_kk = kk_applies & ~improper & np.any(checked & (res_k > kk_lim[..., None] + bound), axis=-1)
    flag_dc = np.zeros((p, m), bool) if dc_imag is None else dc_imag > dc_imag_tol
    flagged = flag_neg | flag_kk | flag_dc | improper
    chans = lambda mask: [tuple(ij) for ij in np.argwhere(mask)]  # noqa: E731

    msgs: list[str] = []
    if t_note:
        msgs.append(t_note)
    if flag_neg.any():
        ch = chans(flag_neg)
        worst = max(ch, key=lambda ij: np.nan_to_num(neg_judged[ij], nan=np.inf))
        lim_txt = "" if neg_lim is None else (f", {neg_lim[worst]:.2g} extrapolated to a fine grid from the grids M, "
                                              "M/2 and M/4: a causal response's aliased tail would fall")
        msgs.append(
            f"{_names(ch, frf)}: {neg[worst]:.2g} of the impulse response's energy is at negative time{lim_txt} "
            f"(threshold {neg_time_tol:g}), so no causal model whose impulse response decays within the grid's "
            f"{K - 1} samples fits these data better than about {np.sqrt(neg[worst]):.1%} RMS: accurate fits need "
            "poles outside the unit circle, or stable poles so close to it (|z|^M not small, often near z = -1) that "
            "the impulse response wraps around the grid: artefacts of the fit. If the output responds before the "
            "input reaches its reference point (e.g. loads that feel a gust ahead of the leading edge while the gust "
            "is referenced at x_ref = 0), move the reference upstream by d: the response is then later, H exp(-i "
            "omega d) (sysid.diagnostics.delayed(frf, d)), the ROM is driven by the input at the new reference, and "
            "diagnose() tells whether the negative-time content went; if it does not fall, it is in the data (e.g. "
            "an under-resolved fast phase roll near omega_d = pi: try a smaller T or a larger M), or it is noise "
            "(white noise puts half its energy at negative time: about half the noise-to-signal power ratio)")
    if improper.any():
        ch = chans(improper)
        worst = max(ch, key=lambda ij: slope[ij])
        msgs.append(
            f"{_names(ch, frf)}: |H| grows like omega^{slope[worst]:.2g} at the top of the band (no omega = inf "
            "sample): the response is improper (e.g. an apparent-mass load growing like k^2). No proper state-space "
            "model follows it outside the band: a fit matches the band only and levels off to its feedthrough D "
            "beyond, so do not use the model above the highest frequency; or fit the strictly proper part, e.g. "
            "H / (1 + i omega / omega_c)^2 with omega_c above the band, and add the polynomial back. The "
            "Kramers-Kronig check is skipped for it (a growing response needs subtractions)")
    if flag_kk.any():
        ch = chans(flag_kk)
        worst = max(ch, key=lambda ij: np.nan_to_num(kk_res[ij], nan=np.inf))
        msgs.append(
            f"{_names(ch, frf)}: the imaginary part differs from the one causality implies from the real part "
            f"(Kramers-Kronig) by {kk_res[worst]:.2g} of the peak (threshold {kk_lim[worst]:.2g}: max({kk_tol:g}, "
            f"{KK_SAFETY:g} x the quadrature error {kk_disc[worst]:.1g} estimated from the data's resolution)): the "
            "data are not those of a causal, stable, real system, or they are noisy (noise has no causal structure: "
            "a residual about twice the relative noise level is expected); check the sign convention (responses per "
            "exp(+i omega t)), the phase reference (a time advance e^{+i omega tau} is non-causal), and add "
            "frequencies where the response varies fast")
    notes: list[str] = []
    coarse = np.zeros((p, m), bool) if neg is None else (neg > neg_time_tol) & ~flag_neg
    if coarse.any():
        ch = chans(coarse)
        worst = max(ch, key=lambda ij: neg[ij])
        notes.append(
            f"{_names(ch, frf)}: {neg[worst]:.2g} of the impulse response's energy is at negative time on this grid, "
            f"but it falls on the grids M/4 and M/2 as a causal response's aliased tail does (extrapolated "
            f"{neg_lim[worst]:.2g}): consistent with causality; the grid's {K - 1} intervals are coarse for its "
            f"slowly decaying impulse response, so a model that decays within them cannot fit better than about "
            f"{np.sqrt(neg[worst]):.1%} RMS (a larger M or smaller T resolves it)")
    if flag_dc.any():
        ch = chans(flag_dc)
        worst = max(ch, key=lambda ij: dc_imag[ij])
        msgs.append(
            f"{_names(ch, frf)}: the omega = 0 sample has an imaginary part of {dc_imag[worst]:.2g} of the peak "
            f"(threshold {dc_imag_tol:g}); a real system's DC gain is real: the 'DC' sample is probably at a small "
            "nonzero frequency or carries a phase error; dc_gain='match' uses its real part only")
    not_applicable = ~kk_applies & ~improper
    if not_applicable.any():
        ch = chans(not_applicable)
        why = (f"only {K} samples (at least {KK_MIN_SAMPLES} are needed)" if K < KK_MIN_SAMPLES else
               f"the data cover omega_d = {wd.min():.3g} .. {wd.max():.3g} of [0, pi] (T = {T_used:.6g}), and what the "
               "response does in the unsampled band could change the causal imaginary part by more than the "
               "threshold at most samples")
        msgs.append(f"{_names(ch, frf)}: the Kramers-Kronig check does not apply: {why}; it says nothing about "
                    "causality here (a band-limited check needs the response near omega = 0 and inf, or a model)")
    not_computed = ~kk_computed | (np.zeros((p, m), bool) if neg is None else ~np.isfinite(neg))
    if not_computed.any():
        msgs.append(f"{_names(chans(not_computed), frf)}: a consistency check could not be computed (NaN): the "
                    "data are not judged consistent; check the frequencies and T")
    if not has_dc:
        msgs.append("no omega = 0 sample: the DC gain cannot be matched (dc_gain='match' needs it); add the steady "
                    "response or pass the DC gain as an array")
    return DataDiagnostics(
        outputs=tuple(frf.outputs), inputs=tuple(frf.inputs), negative_time_energy=neg, rms_floor=floor,
        kk_residual=kk_res, kk_discretisation=kk_disc, dc_imag=dc_imag, has_dc=has_dc,
        has_inf=has_inf, feedthrough=ft, T=float(T_used), T_is_default=T_is_default, equispaced=equi,
        flagged=flagged, warnings=tuple(msgs),
        thresholds={"neg_time": neg_time_tol, "kk": kk_tol, "dc_imag": dc_imag_tol, "kk_safety": KK_SAFETY},
        negative_time_limit=neg_lim, kk_threshold=kk_lim, kk_applies=kk_applies, high_frequency_slope=slope,
        notes=tuple(notes),
    )


def delayed(frf: FrequencyResponse, d: float) -> FrequencyResponse:
    """The response delayed by ``d`` convective time units: ``H(omega) exp(-1j omega d)``.

    For a gust input this is the response to the gust at a reference point ``d`` chords further upstream
    (``x_ref -> x_ref - d``); ``d < 0`` advances it. The ``omega = inf`` sample is kept as is (a delay has no
    limit there; the aerofoil's feedthrough is 0 anyway).

    Parameters
    ----------
    frf : FrequencyResponse
        Data with continuous frequencies ``omega``.
    d : float
        Delay (convective time, chords / U_inf).

    Returns
    -------
    FrequencyResponse

    Raises
    ------
    OptionError
        ``d`` not a finite number.
    FrequencyGridError
        No continuous frequencies.
    """
    if isinstance(d, (bool, np.bool_)) or not isinstance(d, (int, float, np.integer, np.floating)) \
            or not np.isfinite(d):
        raise OptionError(f"d must be a finite delay (convective time), got {d!r}")
    if frf.omega is None:
        raise FrequencyGridError("delayed() needs the continuous frequencies omega: give the data a T")
    w = np.asarray(frf.omega, dtype=float)
    fin = np.isfinite(w)
    factor = np.where(fin, np.exp(-1j * np.where(fin, w, 0.0) * float(d)), 1.0)
    return frf.replace(H=np.asarray(frf.H) * factor)
