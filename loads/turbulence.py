"""Continuous turbulence of CS-25.341(b): A_bar, N0, correlation coefficients and design loads.

With ``H_y(Omega)`` the load ``y`` per unit gust velocity (m/s TAS) at spatial frequency ``Omega`` (rad/m) and
the von Karman spectrum of unit rms (``L = 2500 ft``)::

    Phi(Omega) = (L / pi) (1 + 8/3 (1.339 L Omega)^2) / (1 + (1.339 L Omega)^2)^(11/6)
    A_bar_y^2 = int_0^inf |H_y|^2 Phi dOmega,    N0_y = (1 / 2 pi) sqrt(int (Omega U)^2 |H_y|^2 Phi / A_bar_y^2)
    rho_xy = int Re(H_x conj(H_y)) Phi dOmega / (A_bar_x A_bar_y),   design load = A_bar U_sigma

A gust-angle model ``G`` (convective ``omega = Omega c``) gives ``H = G(i Omega c) / U``.

- From a model (:class:`loads.system.GustSystem`, any frequency): composite 8-point Gauss-Legendre on uniform
  panels in ``ln Omega`` from ``1e-10`` to ``1e6`` over ``1.339 L`` (and past ``1e4`` times the fastest pole),
  the panels doubled until two successive sums agree to ``rtol``; the quadrature error reported is that last
  difference. Truncation, estimated and reported: below, ``|H(0)|^2 Phi(0) Omega_lo``; above, the spectrum's
  power-law tail times ``|H(Omega_hi)|^2``. ``N0`` diverges for an output with a feedthrough ``d`` (its
  integrand grows like ``Omega^(1/3)``): :class:`SpectrumError`, unless a cut-off ``f_max_hz`` is given, which
  bounds the ``N0`` integral only: ``A_bar`` and the correlations are the rule's integrals to infinity
  (25.341(b)(2)), finite for a proper model.
- From frequency-response data (:class:`sysid.FrequencyResponse` with a ``"gust"`` input): the trapezoidal rule
  on the data's own grid; the quadrature error estimated by Richardson's difference against every second point,
  the truncation below the first and above the last frequency from the end values as above (above: ``|H|``
  held at its last value for ``A_bar`` and decaying like ``1 / Omega``, a proper model's, for ``N0``); an
  ``omega = inf`` sample that is not zero is a feedthrough (``N0`` diverges as above). A ``RuntimeWarning``
  when an estimate exceeds 1 % of the result.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from typing import Any, Sequence

import numpy as np

from .atmosphere import FT, FlightPoint, check_point
from .checks import real_values
from .errors import GustError, LoadsModelError, SpectrumError
from .system import GustSystem, check_distinct_outputs, check_moment_axes, gust_system, moment_outputs

__all__ = ["TurbulenceResult", "continuous_turbulence", "von_karman", "SCALE_LENGTH", "WARN_ERROR"]

SCALE_LENGTH = 2500.0 * FT
"""The rule's turbulence scale ``L = 2500 ft`` (762 m)."""
WARN_ERROR = 0.01
"""Relative quadrature or truncation error of ``A_bar`` or ``N0`` above which a ``RuntimeWarning`` is given."""
_GL_X, _GL_W = np.polynomial.legendre.leggauss(8)


def _check_scale(name: str, L: Any) -> float:
    """``L`` as a positive, finite turbulence scale (m), else :class:`GustError` naming ``name``."""
    try:
        f = math.nan if isinstance(L, (bool, np.bool_, str, bytes)) else float(L)
    except (TypeError, ValueError):
        f = math.nan
    if not (math.isfinite(f) and f > 0):
        raise GustError(f"{name} must be a positive, finite turbulence scale (m; the rule's is 2500 ft = 762 m), "
                        f"got {L!r}")
    return f


def von_karman(Omega: Any, L: float = SCALE_LENGTH) -> np.ndarray:
    """Von Karman vertical-gust spectrum of unit rms, ``Phi(Omega)`` (m/rad), ``Omega`` in rad/m, any shape.

    One-sided: ``int_0^inf Phi dOmega = 1``.

    Parameters
    ----------
    Omega : array_like
        Spatial frequencies (rad/m), real and finite (the spectrum is even in ``Omega``).
    L : float
        Turbulence scale (m), positive and finite; default the rule's 2500 ft.

    Returns
    -------
    ndarray
        ``Phi`` with the shape of ``Omega``.

    Raises
    ------
    GustError
        ``L`` not a positive, finite number (``L < 0`` gave a negative spectrum, ``L = 0`` zero); ``Omega`` not
        real numbers, or NaN or inf (``Phi`` was NaN).
    """
    L = _check_scale("L", L)
    w = real_values(Omega)
    if w is None:
        raise GustError(f"Omega must be real spatial frequencies (rad/m: a number or an array of numbers), got "
                        f"{Omega!r}")
    if not np.all(np.isfinite(w)):
        raise GustError(f"Omega must be finite (rad/m), got {np.count_nonzero(~np.isfinite(w))} NaN or inf value(s) "
                        f"(first {w[~np.isfinite(w)][0]!r}); the spectrum tends to 0 like Omega^(-5/3) at infinity")
    return _phi(w, L)


def _phi(Omega: np.ndarray, L: float) -> np.ndarray:
    """:func:`von_karman` without the checks (the integrals' own, finite frequencies)."""
    x = (1.339 * L * np.asarray(Omega, dtype=float)) ** 2
    return (L / math.pi) * (1.0 + 8.0 / 3.0 * x) / (1.0 + x) ** (11.0 / 6.0)


def _tail_coefficient(L: float) -> float:
    """``Phi ~ K Omega^(-5/3)`` at large ``Omega``: ``K = (L / pi)(8/3)(1.339 L)^(-5/3)``."""
    return (L / math.pi) * (8.0 / 3.0) * (1.339 * L) ** (-5.0 / 3.0)


@dataclass(frozen=True)
class TurbulenceResult:
    """Continuous-turbulence loads of one flight point (dicts keyed by output; model units per m/s TAS).

    Attributes
    ----------
    outputs : tuple of str
    a_bar : dict
        ``A_bar`` per unit rms gust velocity (model units per m/s TAS).
    n0 : dict
        Rice's characteristic frequency ``N0`` (1/s).
    correlation : ndarray, shape (p, p)
        ``rho_xy`` in the order of ``outputs``.
    design : dict
        ``A_bar U_sigma`` (model units): the load increment of the rule.
    dimensional, units : dict
        ``design`` in SI at the point and its unit.
    u_sigma : float
        ``U_sigma`` (m/s TAS, with ``F_g``).
    quadrature_error, truncation_error : dict
        Estimated relative errors of ``A_bar`` (``N0``'s in ``n0_quadrature_error``, ``n0_truncation_error``).
    n0_quadrature_error, n0_truncation_error : dict
    Omega : ndarray, shape (K,)
        Spatial frequencies (rad/m) of the PSD arrays.
    psd : ndarray, shape (p, K)
        ``|H|^2 Phi`` (model units^2 per (m/s)^2 per rad/m).
    source : str
        ``"model"`` or ``"data"``.
    f_max_hz : float or None
        The cut-off of the ``N0`` integral, if any (``A_bar`` and the correlations run to infinity).
    point : FlightPoint
    """

    outputs: tuple
    a_bar: dict
    n0: dict
    correlation: np.ndarray = field(repr=False)
    design: dict = field(default_factory=dict)
    dimensional: dict = field(default_factory=dict)
    units: dict = field(default_factory=dict)
    u_sigma: float = float("nan")
    quadrature_error: dict = field(default_factory=dict)
    truncation_error: dict = field(default_factory=dict)
    n0_quadrature_error: dict = field(default_factory=dict)
    n0_truncation_error: dict = field(default_factory=dict)
    Omega: np.ndarray = field(default=None, repr=False)
    psd: np.ndarray = field(default=None, repr=False)
    source: str = "model"
    f_max_hz: float | None = None
    point: FlightPoint | None = field(default=None, repr=False)

    def rho(self, x: str, y: str) -> float:
        """Correlation coefficient of outputs ``x`` and ``y``.

        Raises
        ------
        LoadsModelError
            ``x`` or ``y`` not one of ``outputs`` (the message lists them).
        """
        o = list(self.outputs)
        for arg, name in (("x", x), ("y", y)):
            if not isinstance(name, str) or name not in o:
                raise LoadsModelError(f"{arg} = {name!r} is not an output of the turbulence result; its outputs are "
                                      f"{o}")
        return float(self.correlation[o.index(x), o.index(y)])

    def summary(self) -> str:
        lines = [f"continuous turbulence ({self.source}) at {self.point.summary()}, U_sigma {self.u_sigma:.4g} m/s"]
        for o in self.outputs:
            lines.append(f"  {o}: A_bar {self.a_bar[o]:.5g} per m/s, N0 {self.n0[o]:.4g} /s, design "
                         f"{self.design[o]:.5g} ({self.dimensional[o]:.5g} {self.units[o]}); errors quadrature "
                         f"{self.quadrature_error[o]:.1e}, truncation {self.truncation_error[o]:.1e}")
        return "\n".join(lines)


def _check_fmax(f_max_hz):
    if f_max_hz is None:
        return None
    try:
        f = float(f_max_hz)
    except (TypeError, ValueError):
        f = math.nan
    if isinstance(f_max_hz, bool) or not (math.isfinite(f) and f > 0):
        raise GustError(f"f_max_hz must be a positive, finite cut-off frequency (Hz) or None, got {f_max_hz!r}")
    return f


def _check_rtol(rtol):
    try:
        f = float(rtol)
    except (TypeError, ValueError):
        f = math.nan
    if isinstance(rtol, bool) or not (math.isfinite(f) and 1e-12 <= f < 0.1):
        raise GustError(f"rtol must lie in [1e-12, 0.1), got {rtol!r}")
    return f


def continuous_turbulence(model_or_frf: Any, point: FlightPoint, *, outputs: Sequence[str] | None = None,
                          L_m: float = SCALE_LENGTH, f_max_hz: float | None = None, rtol: float = 1e-8,
                          moment_axes: Sequence[float] = (), moment_reference: float = 0.25) -> TurbulenceResult:
    """Continuous-turbulence loads of CS-25.341(b) at one flight point.

    Parameters
    ----------
    model_or_frf : model or sysid.FrequencyResponse
        A model as :func:`loads.tuned_gust` takes, or gust frequency-response data (continuous ``omega`` in
        ``U / c``, a ``"gust"`` input, gust angle at the leading edge), integrated on their own grid.
    point : FlightPoint
    outputs : sequence of str, optional
        Default all.
    L_m : float
        Turbulence scale (m), default the rule's 2500 ft.
    f_max_hz : float, optional
        Upper cut-off (Hz) of the ``N0`` integral (default none: to infinity); needed for ``N0`` of an output with
        a feedthrough. ``A_bar`` and the correlations are always integrated to infinity, as the rule defines
        them (with data: over all the data, the tail above estimated as ``truncation_error``).
    rtol : float
        Relative agreement of successive panel doublings (model path; default 1e-8).
    moment_axes, moment_reference
        As for :func:`loads.tuned_gust`.

    Returns
    -------
    TurbulenceResult

    Raises
    ------
    SpectrumError
        ``N0`` diverges (a feedthrough, no cut-off), or the quadrature did not reach ``rtol`` (model path).
    LoadsModelError
        No ``"gust"`` input, an unknown or repeated output, a NaN or inf in the model's matrices, unstable model,
        data without continuous frequencies, a moment axis or ``moment_reference`` that is not a finite number, two
        moment axes that would share an output name.
    GustError
        Bad ``f_max_hz``, ``rtol`` or ``L_m``; a point above 60 000 ft (no turbulence intensity there).
    FlightPointError
        ``point`` not a :class:`FlightPoint` (as for :func:`loads.gust_system`; it was a GustError).
    """
    import sysid

    check_point(point)
    point.turbulence_intensity()   # the rule's U_sigma exists at the point: checked before the integrals
    f_max = _check_fmax(f_max_hz)
    rtol = _check_rtol(rtol)
    L = _check_scale("L_m", L_m)
    if isinstance(model_or_frf, sysid.FrequencyResponse):
        return _from_data(model_or_frf, point, outputs, L, f_max, moment_axes, moment_reference)
    system = gust_system(model_or_frf, point, moment_axes=moment_axes, moment_reference=moment_reference)
    return _from_system(system, point, outputs, L, f_max, rtol)


def _rows(names_all, outputs):
    if outputs is None:
        return list(range(len(names_all)))
    if isinstance(outputs, str):
        outputs = [outputs]
    rows = []
    for o in outputs:
        if o not in names_all:
            raise LoadsModelError(f"no output {o!r}; the outputs are {list(names_all)}")
        rows.append(list(names_all).index(o))
    if not rows:
        raise LoadsModelError("outputs is empty")
    check_distinct_outputs([names_all[r] for r in rows])
    return rows


def _from_system(system: GustSystem, point, outputs, L, f_max, rtol):
    rows = _rows(system.outputs, outputs)
    names = [system.outputs[r] for r in rows]
    U, c = point.tas, point.chord_m
    d = system.d[rows]
    scale = max(1.0, float(np.abs(system.lam).max(initial=0.0)))
    lo = 1e-10 / (1.339 * L)
    hi = max(1e6 / (1.339 * L), 1e4 * scale / c)                        # A_bar and the correlations: to infinity
    hi_n0 = hi if f_max is None else 2.0 * math.pi * f_max / U          # N0: to the cut-off, if any
    at_zero = np.abs(system.lam) <= 1e-12 * scale
    if np.any(at_zero):
        reach = np.abs(system.C[np.ix_(rows, np.flatnonzero(at_zero))] * system.b[at_zero]).max(axis=1)
        bad = [n for n, r in zip(names, reach) if r > 0.0]
        if bad:
            raise SpectrumError(f"A_bar of {bad} diverges at low frequency: the model has a pole at zero (a free "
                                "rigid-body motion, e.g. an unsprung plunge) that these outputs see, so |H|^2 grows "
                                "like 1 / Omega^2; give the section a spring, or ask for outputs it does not reach "
                                "(accelerations, loads)")
    H0 = np.abs(system.frequency_response([lo * c])[rows, 0]) / U     # (at lo: a pole at 0 unseen by an output)
    big = np.abs(system.frequency_response(np.geomspace(lo * c, hi * c, 400))[rows]).max(axis=1) / U
    if f_max is None:
        feed = np.abs(d) / U > 1e-10 * np.maximum(big, 1e-300)
        if np.any(feed):
            bad = [n for n, f in zip(names, feed) if f]
            raise SpectrumError(
                f"N0 of {bad} diverges: the model's feedthrough d = {np.abs(d[feed]) .max():.3g} makes "
                "Omega^2 |H|^2 Phi grow like Omega^(1/3); give f_max_hz (the band N0's crossings are counted in) "
                "or a strictly proper model")

    def panels(n_panels, top):
        """Gauss points ``Omega`` and weights ``w Omega Phi`` on ``n_panels`` panels in ``ln Omega`` up to ``top``, and
        ``H`` there (p, K)."""
        edges = np.linspace(math.log(lo), math.log(top), n_panels + 1)
        mid, half = 0.5 * (edges[1:] + edges[:-1]), 0.5 * (edges[1:] - edges[:-1])
        x = (mid[:, None] + half[:, None] * _GL_X[None, :]).ravel()
        w = (half[:, None] * _GL_W[None, :]).ravel()
        Om = np.exp(x)
        G = system.frequency_response(Om * c)[rows] / U                  # (p, K)
        return Om, w * Om * _phi(Om, L), G                         # dOmega = Omega dx

    def integrals(n_panels):
        """``(cross, mom, var_n0)``: the correlations' integrals to ``hi``; N0's two moments to ``hi_n0``."""
        Om, wt, G = panels(n_panels, hi)
        cross = (G[:, None, :] * G[None, :, :].conj()).real @ wt         # (p, p)
        if hi_n0 != hi:
            Om, wt, G = panels(n_panels, hi_n0)
        G2 = np.abs(G) ** 2
        return cross, (G2 * (Om * U) ** 2) @ wt, G2 @ wt

    n = 64
    prev = integrals(n)
    for _ in range(12):
        n *= 2
        cur = integrals(n)
        err_a = np.abs(np.diag(cur[0]) - np.diag(prev[0])) / np.maximum(np.diag(cur[0]), 1e-300)
        err_m = (np.abs(cur[1] - prev[1]) / np.maximum(cur[1], 1e-300)
                 + np.abs(cur[2] - prev[2]) / np.maximum(cur[2], 1e-300))
        small = np.diag(cur[0]) <= 1e-24 * np.diag(cur[0]).max(initial=0.0)     # unreached outputs
        err_a, err_m = np.where(small, 0.0, err_a), np.where(small, 0.0, err_m)
        prev = cur
        if err_a.max() <= rtol and err_m.max() <= rtol:
            break
    else:
        raise SpectrumError(f"the turbulence integrals did not converge to rtol = {rtol:g} with {n} panels; a pole "
                            "very near the imaginary axis (an undamped mode): add structural damping")
    cross, mom, var_n0 = prev
    var = np.diag(cross).copy()
    Hhi = np.abs(system.frequency_response([hi * c])[rows, 0]) / U
    zero, a_bar, n0, trunc_a, trunc_m = _moments(var, mom, var_n0, names, H0, lo, Hhi, hi, L, U, f_max)
    quad_a = np.where(zero, 0.0, 0.5 * err_a)
    quad_m = np.where(zero, 0.0, 0.5 * (err_m + err_a))
    plotO = np.geomspace(max(lo, 1e-3 / (1.339 * L)), min(hi, 10.0 * max(scale, 1.0) / c), 600)
    psd = np.abs(system.frequency_response(plotO * c)[rows] / U) ** 2 * _phi(plotO, L)
    return _result(names, rows, system.scale, system.units, a_bar, n0, cross, quad_a, trunc_a, quad_m, trunc_m,
                   plotO, psd, "model", f_max, point)


def _moments(var, mom, var_n0, names, H_lo, Om_lo, H_hi, Om_hi, L, U, f_max):
    """``A_bar``, ``N0`` and their truncation estimates from the integrals (both paths), per output.

    ``var`` (the integral of ``|H|^2 Phi`` to infinity), ``mom`` and ``var_n0`` (the two moments of ``N0`` over its
    band, to the cut-off if any), ``|H|`` at the lowest and highest frequency integrated (``Om_lo``, ``Om_hi``, rad/m):
    the truncation below is ``|H(0)|^2 Phi(0) Omega_lo`` (and ``Omega^2`` times it for ``N0``), above the spectrum's
    ``Omega^(-5/3)`` tail times ``|H(Omega_hi)|^2`` (none for ``N0`` with a cut-off, which ends its band).

    Returns
    -------
    zero, a_bar, n0, trunc_a, trunc_m : ndarray, shape (p,)
        Outputs the gust does not reach (:func:`_unreached`; their values 0), ``A_bar``, ``N0`` (Rice's rate of its
        band) and the relative truncation errors of ``A_bar`` and ``N0``.
    """
    K = _tail_coefficient(L)
    low_a = H_lo**2 * (L / math.pi) * Om_lo
    low_m = H_lo**2 * (L / math.pi) * U**2 * Om_lo**3 / 3.0
    high_a = H_hi**2 * K * 1.5 * Om_hi ** (-2.0 / 3.0)
    high_m = H_hi**2 * U**2 * Om_hi**2 * K * 1.5 * Om_hi ** (-2.0 / 3.0) if f_max is None else np.zeros(len(names))
    zero = _unreached(var, names)
    var, mom = np.where(zero, 0.0, var), np.where(zero, 0.0, mom)
    sv, sm = np.where(zero, 1.0, var), np.where(zero | (mom <= 0), 1.0, mom)
    sv0 = np.where(zero | (var_n0 <= 0), 1.0, var_n0)
    a_bar = np.sqrt(var)
    n0 = np.sqrt(mom / sv0) / (2.0 * math.pi)      # Rice's rate of the band N0 is counted in (to the cut-off, if any)
    trunc_a = np.where(zero, 0.0, 0.5 * (low_a + high_a) / sv)     # relative error of sqrt: half the integral's
    high_a0 = high_a if f_max is None else 0.0
    trunc_m = np.where(zero, 0.0, 0.5 * ((low_m + high_m) / sm + (low_a + high_a0) / sv0))
    return zero, a_bar, n0, trunc_a, trunc_m


def _unreached(var: np.ndarray, names) -> np.ndarray:
    """Outputs the gust does not reach (zero variance, to round-off of the largest), with a RuntimeWarning: their
    A_bar is 0 and their N0 and correlations, undefined, are set to 0 (never NaN)."""
    top = float(np.max(var, initial=0.0))
    zero = ~(var > 1e-24 * top) | ~(var > 0.0)
    if np.any(zero):
        warnings.warn(f"output(s) {[n for n, z in zip(names, zero) if z]} are not reached by the gust (zero "
                      "response): A_bar = 0, and N0 and the correlations with them, undefined, are set to 0",
                      RuntimeWarning, stacklevel=5)
    return zero


def _result(names, rows, scales, units, a_bar, n0, cross, quad_a, trunc_a, quad_m, trunc_m, Om, psd, source, f_max,
            point):
    us = point.turbulence_intensity()
    zero = a_bar == 0.0
    safe = np.where(zero, 1.0, a_bar)
    corr = np.where(zero[:, None] | zero[None, :], 0.0, cross / np.outer(safe, safe))
    np.fill_diagonal(corr, 1.0)
    for name, qa, ta, qm, tm in zip(names, quad_a, trunc_a, quad_m, trunc_m):
        if max(qa, ta, qm, tm) > WARN_ERROR:
            warnings.warn(f"continuous turbulence of {name} ({source}): estimated relative errors A_bar quadrature "
                          f"{qa:.2g}, truncation {ta:.2g}; N0 quadrature {qm:.2g}, truncation {tm:.2g} exceed "
                          f"{WARN_ERROR:g}: extend or refine the frequencies", RuntimeWarning, stacklevel=4)
    d = lambda arr: {n: float(v) for n, v in zip(names, arr)}
    design = a_bar * us
    sc = np.asarray(scales)[rows]
    corr = np.array(corr)
    corr.setflags(write=False)
    Om = np.array(Om)
    Om.setflags(write=False)
    psd = np.array(psd)
    psd.setflags(write=False)
    return TurbulenceResult(tuple(names), d(a_bar), d(n0), corr, d(design), d(design * sc),
                            {n: units[r] for n, r in zip(names, rows)}, us, d(quad_a), d(trunc_a), d(quad_m),
                            d(trunc_m), Om, psd, source, f_max, point)


def _from_data(frf, point, outputs, L, f_max, moment_axes, moment_reference):
    if frf.omega is None:
        raise LoadsModelError("the data have no continuous frequencies (omega in U/c); build them with "
                              "sysid.FrequencyResponse.from_continuous or give T")
    if "gust" not in frf.inputs:
        raise LoadsModelError(f"the data have no input named 'gust' (inputs {list(frf.inputs)})")
    H = np.asarray(frf.H)[:, list(frf.inputs).index("gust"), :]
    names_all = list(frf.outputs)
    axes, x_ref = check_moment_axes(moment_axes, moment_reference)
    if axes:
        if "Cl" not in names_all or "Cm" not in names_all:
            raise LoadsModelError(f"moment_axes needs outputs 'Cl' and 'Cm'; the data's outputs are {names_all}")
        il, im = names_all.index("Cl"), names_all.index("Cm")
        extra = [H[im] + (x - x_ref) * H[il] for x in axes]
        H = np.vstack([H] + [e[None] for e in extra])
        names_all += moment_outputs(axes, names_all)
    rows = _rows(names_all, outputs)
    names = [names_all[r] for r in rows]
    w = np.asarray(frf.omega, dtype=float)
    U, c = point.tas, point.chord_m
    finite = np.isfinite(w)
    Hinf = H[rows][:, ~finite]
    order = np.argsort(w[finite])
    w, G = w[finite][order], H[rows][:, finite][:, order] / U
    Om = w / c
    # A_bar and the correlations over all the data (the tail above estimated); N0 up to the cut-off, if any
    keep = np.ones(Om.size, dtype=bool) if f_max is None else Om <= 2.0 * math.pi * f_max / U
    if Om.size < 3 or np.count_nonzero(keep) < 3:
        raise LoadsModelError(f"need at least 3 finite frequencies for the quadrature (below f_max_hz for N0), got "
                              f"{int(np.count_nonzero(keep))}")
    if f_max is None and Hinf.size and np.any(np.abs(Hinf) > 1e-10 * np.abs(G * U).max(axis=1, keepdims=True)):
        raise SpectrumError("N0 diverges: the data's omega = inf sample (the feedthrough) is not zero, so "
                            "Omega^2 |H|^2 Phi grows like Omega^(1/3); give f_max_hz")
    Phi = _phi(Om, L)
    cross_int = (G[:, None, :] * G[None, :, :].conj()).real * Phi
    cross = np.trapezoid(cross_int, Om, axis=-1)
    Om_m = Om[keep]
    G2 = np.abs(G[:, keep]) ** 2
    mom_int = G2 * (Om_m * U) ** 2 * Phi[keep]
    mom = np.trapezoid(mom_int, Om_m, axis=-1)
    var_n0 = np.trapezoid(G2 * Phi[keep], Om_m, axis=-1)   # N0's band
    var = np.diag(cross).copy()
    # Richardson-type estimate: the same rule on every second point
    var2 = np.trapezoid(np.abs(G[:, ::2]) ** 2 * Phi[::2], Om[::2], axis=-1)
    mom2 = np.trapezoid(mom_int[:, ::2], Om_m[::2], axis=-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        quad_a = 0.5 * np.abs(var - var2) / 3.0 / var
        quad_m = 0.5 * (np.abs(mom - mom2) / 3.0 / mom + np.abs(var - var2) / 3.0 / var)
    zero, a_bar, n0, trunc_a, trunc_m = _moments(var, mom, var_n0, names, np.abs(G[:, 0]), Om[0], np.abs(G[:, -1]),
                                                 Om[-1], L, U, f_max)
    quad_a = np.where(zero, 0.0, quad_a)
    quad_m = np.where(zero, 0.0, quad_m)
    q, cc = point.q, point.chord_m
    scales = [q * cc if n == "Cl" else (q * cc * cc if n.startswith("Cm") else 1.0) for n in names_all]
    units = ["N/m" if n == "Cl" else ("N m/m" if n.startswith("Cm") else "-") for n in names_all]
    psd = np.abs(G) ** 2 * Phi
    return _result(names, rows, scales, units, a_bar, n0, cross, quad_a, trunc_a, quad_m, trunc_m, Om, psd, "data",
                   f_max, point)
