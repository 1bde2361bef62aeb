"""Linear time-domain (LTD) gust response: BDF2 time marching with one factorisation.

The linearised equations (``cfd.linear``) ``V dq/dt + J q + b(t) = 0`` in solver time
``t = s / mach`` are marched with the second-order backward difference formula

    (3 V / (2 dt) + J) q^{n+1} = V (4 q^n - q^{n-1}) / (2 dt) - b(t^{n+1})

whose matrix does not change: it is factorised once and every step is one back-substitution (plus
the forcing: face averages of the gust and two sparse products). :func:`ltd_responses` marches several
gusts at once: one factorisation, and one back-substitution of a block of right-hand sides per step
(cheaper than one solve per gust: SuperLU reads its factors once per block). Start-up: the system is at rest
before ``s = 0`` (``q^{-1} = q^0 = 0``), so BDF2 applies from the first step and no second matrix
(BDF1) is needed. BDF2 is A-stable; its error for a harmonic of frequency ``omega`` is mainly a
phase error: the discrete derivative is ``i omega (1 + (omega dt)^2 / 3 + ...)``. ``ltd_response``
warns (RuntimeWarning) when ``(omega_g dt)^2 / 3`` exceeds 1 % for the gust's characteristic
frequency ``omega_g`` (the sine's frequency, ``2 pi / length`` for the 1-cosine gust, and ``2 pi``, one
chord, for the sharp-edged gust).

Prescribed motion (:func:`ltd_response` with ``plunge`` and/or ``pitch``): the forcing of ``cfd.motion``,
``b0 x + b1 x'`` per motion input ``x`` (``h`` in chords, ``alpha`` in radians about ``pivot``), and the output
adds ``d x`` (the wind axes turning with the pitch). The rate ``x'`` is the BDF2 difference of the samples,
``(3 x^{n+1} - 4 x^n + x^{n-1}) / (2 dt)`` with ``x = 0`` before ``s = 0``: the same formula as the state's, so
the march is exactly BDF2 applied to the system written for ``q + V^-1 b1 x`` (no separate error from the
rate). A history should start from rest (``x(0) = 0``, and smoothly) for a clean start: a jump at ``s = 0`` is
an impulsive start, as for the sharp-edged gust. No phase-error warning is given for a motion (no frequency
scale is known); the BDF2 phase-rate error at a frequency ``omega`` is ``(omega dt)^2 / 3``.
"""

import dataclasses
import logging
import math
import time
import warnings
from dataclasses import dataclass

import numpy as np

from .gust import OneMinusCosine, SharpEdged, SineGust, face_gust
from .frequencies import check_pivot
from .linear import LinearError, check_gust_method
from .motion import motion_forcing

__all__ = ["LTDHistory", "ltd_response", "ltd_responses", "phase_error_estimate", "check_march"]

log = logging.getLogger(__name__)


@dataclass(frozen=True, eq=False)
class LTDHistory:
    """Time history of a linear gust response (perturbations about the steady loads).

    Attributes
    ----------
    t : ndarray, shape (n + 1,)
        Convective time ``s = t U / c``, from 0 to ``t_end``.
    u : ndarray, shape (n + 1,)
        Gust input ``v_g(x_ref, s) / U`` (zeros without a gust).
    cl, cm, cd : ndarray, shape (n + 1,)
        Load coefficient perturbations (``cm`` about the quarter chord, nose up positive).
    method : str
        ``"svm"`` or ``"fvm"``.
    dt : float
        Convective time step.
    q : ndarray, shape (4N,)
        Final state (solver units).
    h, alpha : ndarray, shape (n + 1,)
        Prescribed plunge (chords, up) and pitch (radians, nose up about ``pivot``); zeros when not given.
    pivot : float or None
        Pitch axis (chords from the leading edge) when a pitch was prescribed.
    """

    t: np.ndarray
    u: np.ndarray
    cl: np.ndarray
    cm: np.ndarray
    cd: np.ndarray
    method: str
    dt: float
    q: np.ndarray
    h: np.ndarray = None
    alpha: np.ndarray = None
    pivot: float = None


def phase_error_estimate(gust, dt):
    """Relative BDF2 frequency (phase-rate) error ``(omega_g dt)^2 / 3`` at the gust's frequency scale."""
    if isinstance(gust, SineGust):
        wg = gust.omega
    elif isinstance(gust, OneMinusCosine):
        wg = 2.0 * math.pi / gust.length
    else:
        wg = 2.0 * math.pi
    return (wg * dt) ** 2 / 3.0


def _check_gust(gust):
    if not isinstance(gust, (SineGust, OneMinusCosine, SharpEdged)):
        raise LinearError(f"gust must be a cfd.SineGust, OneMinusCosine or SharpEdged; got {type(gust).__name__}")


def _check_times(dt, t_end):
    try:
        dt = float(dt)
        t_end = float(t_end)
    except (TypeError, ValueError):
        raise LinearError("dt and t_end must be real numbers (convective time)") from None
    if not (math.isfinite(dt) and dt > 0.0):
        raise LinearError(f"dt = {dt} must be positive and finite (convective time, e.g. 0.02)")
    if not (math.isfinite(t_end) and t_end >= dt):
        raise LinearError(f"t_end = {t_end} must be finite and at least one time step (dt = {dt})")
    return dt, t_end


def _warn_phase(gust, dt, max_phase_error):
    err = phase_error_estimate(gust, dt)
    if err > max_phase_error:
        warnings.warn(
            f"dt = {dt} gives an estimated BDF2 phase-rate error of {100 * err:.2g} % at the gust's frequency "
            f"scale (limit {100 * max_phase_error:.2g} %); reduce dt by {math.sqrt(err / max_phase_error):.2g}x",
            RuntimeWarning,
            stacklevel=3,
        )


def check_march(gust, dt, t_end, max_phase_error=0.01):
    """The checks of :func:`ltd_response` for a march of ``gust`` built elsewhere (``cfd.coupled``).

    Returns the checked ``(dt, t_end)`` (floats); raises :class:`LinearError` for a gust of the wrong type or bad
    times, and warns (``RuntimeWarning``) when :func:`phase_error_estimate` exceeds ``max_phase_error``.
    """
    _check_gust(gust)
    dt, t_end = _check_times(dt, t_end)
    _warn_phase(gust, dt, max_phase_error)
    return dt, t_end


def _motion_samples(name, history, t):
    """Samples of a prescribed motion at the times ``t`` (array of n + 1 values, or a callable of ``s``)."""
    x = history(t) if callable(history) else history
    try:
        x = np.array(np.broadcast_to(np.asarray(x, dtype=float), t.shape) if np.ndim(x) == 0 else x, dtype=float)
    except (TypeError, ValueError):
        raise LinearError(f"{name} must be an array of {t.size} samples or a callable of s; got {history!r}") from None
    if x.shape != t.shape:
        raise LinearError(f"{name} has shape {x.shape}; the march needs {t.size} samples, at s = 0, dt, ..., t_end "
                          "(or give a callable of s)")
    if not np.all(np.isfinite(x)):
        raise LinearError(f"{name} holds NaN or infinite values")
    return x


def _motions(lin, t, plunge, pitch, pivot):
    """``[(MotionForcing, x, x')]`` for the prescribed motions; ``x'`` the BDF2 difference with rest before 0."""
    out = []
    for name, history in (("plunge", plunge), ("pitch", pitch)):
        if history is None:
            continue
        x = _motion_samples(name, history, t)
        xp = np.concatenate([[0.0, 0.0], x])
        rate = (3.0 * xp[2:] - 4.0 * xp[1:-1] + xp[:-2]) / (2.0 * (t[1] - t[0]))
        out.append((motion_forcing(lin, name, pivot), x, rate))
    return out


def _march(lin, gusts, dt, t_end, method, x_ref, initial, motion=None, progress=None, log_interval=60.0):
    """BDF2 for a list of gusts at once (or one column of motion alone); returns a list of :class:`LTDHistory`.

    ``motion``: None or ``(plunge, pitch, pivot)`` (see :func:`_motions`), forcing every column. ``progress`` and
    ``log_interval``: see :func:`ltd_response`.
    """
    t_start = t_log = time.perf_counter()
    n = int(round(t_end / dt))
    t = dt * np.arange(n + 1)
    h = lin.to_solver_time(dt)
    V = lin.V[:, None]
    solve = lin.solver(1.5 * lin.V / h)
    moves = [] if motion is None else _motions(lin, t, *motion)
    g = max(len(gusts), 1)
    if initial is None:
        q_prev = np.zeros((lin.n, g))
        q = np.zeros((lin.n, g))
    else:
        q_prev, q = (np.asarray(a, dtype=float).reshape(lin.n, 1).copy() for a in initial)
    Y = np.zeros((n + 1, 3, g))
    Y[0] = lin.C @ q
    for k in range(1, n + 1):  # time steps: each one back-substitution of g right-hand sides
        b = np.zeros((lin.n, g))
        if gusts:
            faces = [face_gust(lin.grid, gust, t[k]) for gust in gusts]
            b = lin.forcing(np.stack([f[0] for f in faces]), np.stack([f[1] for f in faces]), method).T  # (4N, g)
        for f, x, rate in moves:
            b = b + (f.b0 * x[k] + f.b1 * rate[k])[:, None]
        q_prev, q = q, solve(V * (4.0 * q - q_prev) / (2.0 * h) - b)
        Y[k] = lin.C @ q
        if progress is not None:
            progress(k, n, float(t[k]))
        now = time.perf_counter()
        if now - t_log >= log_interval:
            t_log = now
            log.info("ltd %s: step %d / %d (s = %.3f), %d column(s), %.0f s", method, k, n, t[k], g,
                     now - t_start)
    for f, x, _ in moves:
        Y += np.multiply.outer(x, f.d)[:, :, None]       # the explicit load term d x
    x_of = {f.name: x for f, x, _ in moves}
    pivot = next((f.pivot for f, _, _ in moves if f.name == "pitch"), None)
    zero = np.zeros(n + 1)
    out = []
    for j in range(g):
        u = gusts[j].input(t, x_ref) if gusts else zero
        arrays = [np.ascontiguousarray(a) for a in (t, u, Y[:, 0, j], Y[:, 1, j], Y[:, 2, j], q[:, j],
                                                    x_of.get("plunge", zero), x_of.get("pitch", zero))]
        for a in arrays:
            a.setflags(write=False)
        out.append(LTDHistory(t=arrays[0], u=arrays[1], cl=arrays[2], cm=arrays[3], cd=arrays[4], method=method,
                              dt=dt, q=arrays[5], h=arrays[6], alpha=arrays[7], pivot=pivot))
    return out


def _shape_groups(gusts):
    """Gusts that differ only in angle share a shape: ``(representatives, [(index, factor)] per gust)``.

    The representative of a shape is its gust of largest ``|amplitude|``; a gust's history is its
    representative's times ``factor = amplitude / representative's amplitude`` (0 for a zero-amplitude shape).
    """
    def shape(g):
        return (type(g),) + tuple(getattr(g, f.name) for f in dataclasses.fields(g) if f.name != "angle_deg")

    keys = [shape(g) for g in gusts]
    best = {}                                           # shape -> its gust of largest |amplitude|, first-seen order
    for key, g in zip(keys, gusts):
        if key not in best or abs(g.amplitude) > abs(best[key].amplitude):
            best[key] = g
    index = {key: i for i, key in enumerate(best)}
    reps = list(best.values())
    maps = [(index[key], g.amplitude / best[key].amplitude if best[key].amplitude != 0.0 else 0.0)
            for key, g in zip(keys, gusts)]
    return reps, maps


def _scaled(hist, gust, factor, t, x_ref):
    """``hist`` (of a gust of the same shape) times ``factor``, with ``gust``'s input signal."""
    def frozen(a):
        a = np.ascontiguousarray(a)
        a.setflags(write=False)
        return a

    return dataclasses.replace(hist, u=frozen(gust.input(t, x_ref)), cl=frozen(factor * hist.cl),
                               cm=frozen(factor * hist.cm), cd=frozen(factor * hist.cd), q=frozen(factor * hist.q))


def ltd_responses(lin, gusts, dt, t_end, method="svm", x_ref=0.0, max_phase_error=0.01, *, progress=None,
                  log_interval=60.0):
    """Linear responses to several gusts, marched together (one factorisation, one block solve per step).

    The same as ``[ltd_response(lin, g, dt, t_end, ...) for g in gusts]`` (to round-off), from the rest state,
    for about the cost of one march and a half for two gusts (see ``bench/ltd_bench.py``). Gusts that differ
    only in angle (the paper's G2 and G3) share one column of the march, their histories scaled by the ratio of
    their amplitudes (the system is linear and starts from rest, so this is exact to round-off).

    Parameters
    ----------
    lin : LinearSystem
    gusts : sequence of SineGust, OneMinusCosine or SharpEdged
        At least one.
    dt, t_end, method, x_ref, max_phase_error, progress, log_interval
        As :func:`ltd_response` (shared by all gusts; ``progress`` is called once per step of the march).

    Returns
    -------
    list of LTDHistory
        One per gust, in order.

    Raises
    ------
    LinearError
        As :func:`ltd_response`, or an empty list of gusts.
    """
    check_gust_method(method)
    gusts = list(gusts)
    if not gusts:
        raise LinearError("gusts is empty: give at least one cfd.SineGust, OneMinusCosine or SharpEdged")
    for gust in gusts:
        _check_gust(gust)
    dt, t_end = _check_times(dt, t_end)
    for gust in gusts:
        _warn_phase(gust, dt, max_phase_error)
    reps, maps = _shape_groups(gusts)
    marched = _march(lin, reps, dt, t_end, method, x_ref, None, progress=progress, log_interval=log_interval)
    return [marched[i] if gust is reps[i] else _scaled(marched[i], gust, factor, marched[i].t, x_ref)
            for gust, (i, factor) in zip(gusts, maps)]


def ltd_response(lin, gust, dt, t_end, method="svm", x_ref=0.0, initial=None, max_phase_error=0.01, *,
                 plunge=None, pitch=None, pivot=0.25, progress=None, log_interval=60.0):
    """Linear response to a gust and/or a prescribed rigid motion by BDF2 time marching (one factorisation).

    Parameters
    ----------
    lin : LinearSystem
        From ``cfd.linearise``.
    gust : SineGust, OneMinusCosine, SharpEdged or None
        None: no gust (then give ``plunge`` or ``pitch``).
    dt : float
        Convective time step (chords / U), ``> 0``.
    t_end : float
        Final convective time, ``>= dt``.
    method : {"svm", "fvm"}
    x_ref : float
        Where the gust input signal is measured (chords).
    initial : tuple (q_prev, q_now) of ndarray, shape (4N,), optional
        State at ``s = -dt`` and ``s = 0`` (solver units); default at rest (zeros).
    max_phase_error : float
        Warn when :func:`phase_error_estimate` of the gust exceeds this.
    plunge : ndarray, shape (n + 1,), or callable, optional
        Prescribed plunge ``h(s)`` in chords, positive up, at ``s = 0, dt, ..., t_end`` (``n = round(t_end /
        dt)``), or a callable ``h(s)`` of an array of times. Zero before ``s = 0``.
    pitch : ndarray, shape (n + 1,), or callable, optional
        Prescribed pitch ``alpha(s)`` in radians, nose up about ``(pivot, 0)``; as ``plunge``.
    pivot : float
        Pitch axis, chords from the leading edge.
    progress : callable, optional
        ``progress(step, n_steps, t)`` after every time step (``step = 1 ... n_steps``, ``t`` its convective
        time); its return value is ignored. It does not change the result.
    log_interval : float
        Seconds between progress lines on the ``cfd.ltd`` logger (level INFO).

    Returns
    -------
    LTDHistory
        Loads of the gust and the motion together (the system is linear: marched once); ``h`` and ``alpha`` hold
        the prescribed samples.

    Raises
    ------
    LinearError
        Non-positive or non-finite ``dt``, ``t_end < dt``, unknown method, not a gust, neither a gust nor a
        motion, a motion history of the wrong length or with non-finite values, a non-finite pivot.
    """
    check_gust_method(method)
    if gust is None and plunge is None and pitch is None:
        raise LinearError("nothing to march: give a gust, or a plunge or pitch history (ltd_response(lin, None, dt, "
                          "t_end, pitch=...))")
    if gust is not None:
        _check_gust(gust)
    dt, t_end = _check_times(dt, t_end)
    pivot = check_pivot(pivot)
    if gust is not None:
        _warn_phase(gust, dt, max_phase_error)
    motion = None if plunge is None and pitch is None else (plunge, pitch, pivot)
    return _march(lin, [] if gust is None else [gust], dt, t_end, method, x_ref, initial, motion,
                  progress=progress, log_interval=log_interval)[0]
