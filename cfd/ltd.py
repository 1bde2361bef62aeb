"""Linear time-domain (LTD) gust response: BDF2 time marching with one factorisation.

The linearised equations (``cfd.linear``) ``V dq/dt + J q + b(t) = 0`` in solver time
``t = s / mach`` are marched with the second-order backward difference formula

    (3 V / (2 dt) + J) q^{n+1} = V (4 q^n - q^{n-1}) / (2 dt) - b(t^{n+1})

whose matrix does not change: it is factorised once and every step is one back-substitution (plus
the forcing: face averages of the gust and two sparse products). Start-up: the system is at rest
before ``s = 0`` (``q^{-1} = q^0 = 0``), so BDF2 applies from the first step and no second matrix
(BDF1) is needed. BDF2 is A-stable; its error for a harmonic of frequency ``omega`` is mainly a
phase error: the discrete derivative is ``i omega (1 + (omega dt)^2 / 3 + ...)``. ``ltd_response``
warns (RuntimeWarning) when ``(omega_g dt)^2 / 3`` exceeds 1 % for the gust's characteristic
frequency ``omega_g`` (the sine's frequency, ``2 pi / length`` for the 1-cosine gust, and ``2 pi``, one
chord, for the sharp-edged gust).
"""

import math
import warnings
from dataclasses import dataclass

import numpy as np

from .gust import OneMinusCosine, SharpEdged, SineGust, face_gust
from .linear import LinearError, _check_method

__all__ = ["LTDHistory", "ltd_response", "phase_error_estimate"]


@dataclass(frozen=True, eq=False)
class LTDHistory:
    """Time history of a linear gust response (perturbations about the steady loads).

    Attributes
    ----------
    t : ndarray, shape (n + 1,)
        Convective time ``s = t U / c``, from 0 to ``t_end``.
    u : ndarray, shape (n + 1,)
        Gust input ``v_g(x_ref, s) / U``.
    cl, cm, cd : ndarray, shape (n + 1,)
        Load coefficient perturbations (``cm`` about the quarter chord, nose up positive).
    method : str
        ``"svm"`` or ``"fvm"``.
    dt : float
        Convective time step.
    q : ndarray, shape (4N,)
        Final state (solver units).
    """

    t: np.ndarray
    u: np.ndarray
    cl: np.ndarray
    cm: np.ndarray
    cd: np.ndarray
    method: str
    dt: float
    q: np.ndarray


def phase_error_estimate(gust, dt):
    """Relative BDF2 frequency (phase-rate) error ``(omega_g dt)^2 / 3`` at the gust's frequency scale."""
    if isinstance(gust, SineGust):
        wg = gust.omega
    elif isinstance(gust, OneMinusCosine):
        wg = 2.0 * math.pi / gust.length
    else:
        wg = 2.0 * math.pi
    return (wg * dt) ** 2 / 3.0


def ltd_response(lin, gust, dt, t_end, method="svm", x_ref=0.0, initial=None, max_phase_error=0.01):
    """Linear response to a gust by BDF2 time marching (one factorisation).

    Parameters
    ----------
    lin : LinearSystem
        From ``cfd.linearise``.
    gust : SineGust, OneMinusCosine or SharpEdged
    dt : float
        Convective time step (chords / U), ``> 0``.
    t_end : float
        Final convective time, ``>= dt``.
    method : {"svm", "fvm"}
    x_ref : float
        Where the input signal is measured (chords).
    initial : tuple (q_prev, q_now) of ndarray, shape (4N,), optional
        State at ``s = -dt`` and ``s = 0`` (solver units); default at rest (zeros).
    max_phase_error : float
        Warn when :func:`phase_error_estimate` exceeds this.

    Returns
    -------
    LTDHistory

    Raises
    ------
    LinearError
        Non-positive or non-finite ``dt``, ``t_end < dt``, unknown method, not a gust.
    """
    _check_method(method)
    if not isinstance(gust, (SineGust, OneMinusCosine, SharpEdged)):
        raise LinearError(f"gust must be a cfd.SineGust, OneMinusCosine or SharpEdged; got {type(gust).__name__}")
    try:
        dt = float(dt)
        t_end = float(t_end)
    except (TypeError, ValueError):
        raise LinearError("dt and t_end must be real numbers (convective time)") from None
    if not (math.isfinite(dt) and dt > 0.0):
        raise LinearError(f"dt = {dt} must be positive and finite (convective time, e.g. 0.02)")
    if not (math.isfinite(t_end) and t_end >= dt):
        raise LinearError(f"t_end = {t_end} must be finite and at least one time step (dt = {dt})")
    err = phase_error_estimate(gust, dt)
    if err > max_phase_error:
        warnings.warn(
            f"dt = {dt} gives an estimated BDF2 phase-rate error of {100 * err:.2g} % at the gust's frequency "
            f"scale (limit {100 * max_phase_error:.2g} %); reduce dt by {math.sqrt(err / max_phase_error):.2g}x",
            RuntimeWarning,
            stacklevel=2,
        )
    n = int(round(t_end / dt))
    t = dt * np.arange(n + 1)
    h = lin.to_solver_time(dt)
    V = lin.V
    solve = lin.solver(1.5 * V / h)
    if initial is None:
        q_prev = np.zeros(lin.n)
        q = np.zeros(lin.n)
    else:
        q_prev, q = (np.asarray(a, dtype=float).copy() for a in initial)
    Y = np.zeros((n + 1, 3))
    Y[0] = lin.C @ q
    for k in range(1, n + 1):  # time steps: each one back-substitution
        gi, gj = face_gust(lin.grid, gust, t[k])
        rhs = V * (4.0 * q - q_prev) / (2.0 * h) - lin.forcing(gi, gj, method)
        q_prev, q = q, solve(rhs)
        Y[k] = lin.C @ q
    u = gust.input(t, x_ref)
    out = [np.ascontiguousarray(a) for a in (t, u, Y[:, 0], Y[:, 1], Y[:, 2], q)]
    for a in out:
        a.setflags(write=False)
    return LTDHistory(t=out[0], u=out[1], cl=out[2], cm=out[3], cd=out[4], method=method, dt=dt, q=out[5])
