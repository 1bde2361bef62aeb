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

*Discretisation error.* The trapezoid rule on the smooth integrand has error ``sum_j h_j^3 / 12 |g''|``,
second order in the largest spacing ``h`` in ``omega_d`` (a gap of width ``g`` contributes ``O(g^3)``); on
the equispaced grid the derivative difference dominates and the error is ``O(h^3)``. It is estimated from
the data: the same rule on every second sample differs from the full one by about ``3x`` (second order)
to ``7x`` (third order) the full rule's error, so ``kk_discretisation = max |Im_KK(half) - Im_KK(full)| / 3
/ max |H|`` over the common samples is a conservative estimate. A channel is flagged only when its residual
exceeds both ``kk_tol`` and ``3 x`` that estimate.

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
from .errors import FrequencyGridError
from .frd import FrequencyResponse, continuous_to_discrete

__all__ = ["diagnose", "DataDiagnostics", "default_T", "negative_time_energy", "kramers_kronig_imag", "delayed"]

NEG_TIME_TOL = 1e-4
KK_TOL = 1e-2
DC_IMAG_TOL = 1e-6
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
        No positive finite frequency.
    """
    w = np.asarray(omega, dtype=float)
    w = w[np.isfinite(w) & (w > 0)]
    if w.size == 0:
        raise FrequencyGridError("no positive finite frequency to choose T from; give T explicitly")
    return 2.0 / math.sqrt(float(w.min()) * float(w.max()))


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
        Kramers-Kronig residual ``max |Im H_KK - Im H| / max |H|``.
    kk_discretisation : ndarray (p, m)
        Estimated discretisation error of that residual (NaN for fewer than 8 samples).
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
        ``neg_time``, ``kk``, ``dc_imag`` used.
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

    def __post_init__(self):
        freeze_array_fields(self)   # the arrays of a frozen result are read-only too

    @property
    def ok(self) -> bool:
        """True when no channel is flagged and nothing else was found."""
        return not self.warnings

    def channels(self) -> list[dict]:
        """One dict per channel: ``output, input, neg_time_energy, kk_residual, kk_discretisation, dc_imag,
        flagged`` (None where a check does not apply)."""
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
                ))
        return rows

    def _table(self, markdown: bool) -> list[str]:
        head = ["channel", "neg.-time energy", "KK residual", "(discr. est.)", "Im H(0)/peak", "flag"]
        rows = []
        for c in self.channels():
            rows.append([
                f"{c['output']}/{c['input']}",
                "n/a" if c["neg_time_energy"] is None else f"{c['neg_time_energy']:.2e}",
                f"{c['kk_residual']:.2e}",
                "n/a" if math.isnan(c["kk_discretisation"]) else f"{c['kk_discretisation']:.1e}",
                "no sample" if c["dc_imag"] is None else f"{c['dc_imag']:.1e}",
                "FLAG" if c["flagged"] else "ok",
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
        lines = [self._header()] + ["  " + s for s in self._table(False)]
        if self.warnings:
            lines += ["warning: " + w for w in self.warnings]
        else:
            lines.append("the data are consistent with a causal, stable, real LTI system within the thresholds "
                         f"(negative-time energy <= {self.thresholds['neg_time']:g}, KK residual <= "
                         f"max({self.thresholds['kk']:g}, 3 x its discretisation estimate), Im H(0)/peak <= {self.thresholds['dc_imag']:g})")
        return "\n".join(lines)

    def markdown(self) -> str:
        """The same report as Markdown (a table and a bullet list)."""
        lines = [self._header() + ".", ""] + self._table(True) + [""]
        if self.warnings:
            lines += [f"- {w}" for w in self.warnings]
        else:
            lines.append("- The data are consistent with a causal, stable, real LTI system within the thresholds "
                         f"(negative-time energy <= {self.thresholds['neg_time']:g}, KK residual <= "
                         f"max({self.thresholds['kk']:g}, 3 x its discretisation estimate), Im H(0)/peak <= {self.thresholds['dc_imag']:g}).")
        return "\n".join(lines)


def _kk(frf_H: np.ndarray, omega_d: np.ndarray, peak: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(residual, discretisation estimate)``, each (p, m)."""
    im_kk = kramers_kronig_imag(frf_H.real, omega_d)
    res = np.abs(im_kk - frf_H.imag).max(axis=-1) / peak
    K = omega_d.size
    if K < 8:
        return res, np.full(res.shape, np.nan)
    order = np.argsort(omega_d, kind="stable")
    half = order[::2]
    if order[-1] not in half:
        half = np.append(half, order[-1])
    im_half = kramers_kronig_imag(frf_H.real[..., half], omega_d[half])
    disc = np.abs(im_half - im_kk[..., half]).max(axis=-1) / 3.0 / peak
    return res, disc


def _names(ch: Sequence[tuple[int, int]], frf: FrequencyResponse) -> str:
    return ", ".join(f"{frf.outputs[i]}/{frf.inputs[j]}" for i, j in ch)


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
        Flag a channel whose negative-time energy fraction exceeds this (default 1e-4: a 1 % RMS floor).
    kk_tol : float
        Flag a channel whose Kramers-Kronig residual (peak-normalised) exceeds this (default 1e-2) and three
        times its discretisation estimate.
    dc_imag_tol : float
        Flag ``|Im H(0)| / max |H|`` above this (default 1e-6, as :attr:`FrequencyResponse.dc_gain`).
    T : float, optional
        Sampling period for the KK check of data on continuous frequencies without one (default
        :func:`default_T`); ignored when the data have ``omega_d``.

    Returns
    -------
    DataDiagnostics
        Per-channel numbers, flags, plain-language ``warnings`` and :meth:`DataDiagnostics.summary`.

    Raises
    ------
    TypeError
        ``frf`` is not a :class:`FrequencyResponse`.
    FrequencyGridError
        A frequency appears twice; or, for data on continuous frequencies only, ``T`` not positive and finite,
        or no ``T`` given and no positive finite frequency to choose the default from.

    Notes
    -----
    The formulas, the tolerances' meaning and the discretisation error are in the module docstring of
    :mod:`sysid.diagnostics`.
    """
    if not isinstance(frf, FrequencyResponse):
        raise TypeError(f"diagnose() expects a sysid.FrequencyResponse, got {type(frf).__name__}")
    H = np.asarray(frf.H)
    p, m, K = H.shape
    peak = np.maximum(np.abs(H).max(axis=-1), _TINY)

    T_is_default = False
    if frf.omega_d is not None:
        wd = np.asarray(frf.omega_d, dtype=float)
        T_used = frf.T if frf.T is not None else float("nan")
    else:
        T_used = T if T is not None else default_T(frf.omega)
        T_is_default = T is None
        wd = continuous_to_discrete(frf.omega, T_used)
    if np.unique(wd).size != wd.size:
        raise FrequencyGridError("diagnose() needs distinct frequencies; the data repeat a frequency, "
                                 "average or drop the repeated samples")

    equi = frf.is_equispaced
    neg = negative_time_energy(H) if equi else None
    floor = None if neg is None else np.sqrt(neg)
    kk_res, kk_disc = _kk(H, wd, peak)

    tol = 1e-9 * np.pi
    k_dc = np.flatnonzero(np.abs(wd) <= tol)
    k_inf = np.flatnonzero(np.abs(wd - np.pi) <= tol)
    has_dc, has_inf = bool(k_dc.size), bool(k_inf.size)
    dc_imag = np.abs(H[:, :, k_dc[0]].imag) / peak if has_dc else None
    ft = np.array(H[:, :, k_inf[0]].real) if has_inf else None

    flag_neg = np.zeros((p, m), bool) if neg is None else neg > neg_time_tol
    kk_lim = np.maximum(kk_tol, 3.0 * np.nan_to_num(kk_disc, nan=0.0))
    flag_kk = kk_res > kk_lim
    flag_dc = np.zeros((p, m), bool) if dc_imag is None else dc_imag > dc_imag_tol
    flagged = flag_neg | flag_kk | flag_dc
    chans = lambda mask: [tuple(ij) for ij in np.argwhere(mask)]  # noqa: E731

    msgs: list[str] = []
    if flag_neg.any():
        ch = chans(flag_neg)
        worst = max(ch, key=lambda ij: neg[ij])
        msgs.append(
            f"{_names(ch, frf)}: {neg[worst]:.2g} of the impulse response's energy is at negative time (threshold "
            f"{neg_time_tol:g}), so no causal model whose impulse response decays within the grid's {K - 1} samples "
            f"fits these data better than about {np.sqrt(neg[worst]):.1%} RMS: accurate fits need poles outside the "
            "unit circle, or stable poles so close to it (|z|^M not small, often near z = -1) that the impulse response "
            "wraps around the grid: artefacts of the fit. If the output responds before the input "
            "reaches its reference point (e.g. loads that feel a gust ahead of the leading edge while the gust is "
            "referenced at x_ref = 0), move the reference upstream by d: the response is then later, H exp(-i omega "
            "d) (sysid.diagnostics.delayed(frf, d)), the ROM is driven by the input at the new reference, and "
            "diagnose() tells whether the negative-time content went; if it does not fall, it is in the data (e.g. "
            "an under-resolved fast phase roll near omega_d = pi: try a smaller T or a larger M)")
    if flag_kk.any():
        ch = chans(flag_kk)
        worst = max(ch, key=lambda ij: kk_res[ij])
        msgs.append(
            f"{_names(ch, frf)}: the imaginary part differs from the one causality implies from the real part "
            f"(Kramers-Kronig) by {kk_res[worst]:.2g} of the peak (threshold {kk_tol:g}, discretisation estimate "
            f"{kk_disc[worst]:.1g}): the data are not those of a causal, stable, real system, or they are noisy "
            "(noise has no causal structure: a residual about twice the relative noise level is expected), or "
            "too sparse in frequency; check the sign convention (responses per exp(+i omega t)), the phase reference "
            "(a time advance e^{+i omega tau} is non-causal), and add frequencies where the response varies fast")
    if flag_dc.any():
        ch = chans(flag_dc)
        worst = max(ch, key=lambda ij: dc_imag[ij])
        msgs.append(
            f"{_names(ch, frf)}: the omega = 0 sample has an imaginary part of {dc_imag[worst]:.2g} of the peak "
            f"(threshold {dc_imag_tol:g}); a real system's DC gain is real: the 'DC' sample is probably at a small "
            "nonzero frequency or carries a phase error; dc_gain='match' uses its real part only")
    if not has_dc:
        msgs.append("no omega = 0 sample: the DC gain cannot be matched (dc_gain='match' needs it); add the steady "
                    "response or pass the DC gain as an array")
    return DataDiagnostics(
        outputs=tuple(frf.outputs), inputs=tuple(frf.inputs), negative_time_energy=neg, rms_floor=floor,
        kk_residual=kk_res, kk_discretisation=kk_disc, dc_imag=dc_imag, has_dc=has_dc,
        has_inf=has_inf, feedthrough=ft, T=float(T_used), T_is_default=T_is_default, equispaced=equi,
        flagged=flagged, warnings=tuple(msgs),
        thresholds={"neg_time": neg_time_tol, "kk": kk_tol, "dc_imag": dc_imag_tol},
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
    """
    if frf.omega is None:
        raise FrequencyGridError("delayed() needs the continuous frequencies omega: give the data a T")
    w = np.asarray(frf.omega, dtype=float)
    fin = np.isfinite(w)
    factor = np.where(fin, np.exp(-1j * np.where(fin, w, 0.0) * float(d)), 1.0)
    return frf.replace(H=np.asarray(frf.H) * factor)
