"""Linear time-domain (LTD) gust response: BDF2 or Radau IIA time marching, factorised once.

Two schemes (``scheme=``): BDF2 (below; the default, and the nonlinear solver's scheme) and the three-stage
Radau IIA of order 5 (``"radau5"``, :mod:`cfd.ltd.radau`): steps of 0.14 (the largest multiple of ``dt`` not above
:data:`RADAU_STEP`), one real and one complex back-substitution each, the loads written on the ``dt`` grid by
the collocation polynomial. On the paper's T2 against the LFD at sine gusts (``bench/ltd_radau_bench.py``) its
amplitude errors are 7 - 17x (omega = 4 pi) and 140 - 180x (2 pi) smaller than BDF2's at ``dt = 0.02``, for
less than half the work (docs/performance.md).

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

The sub-package: this module marches the linear system alone (:func:`ltd_response`, :func:`ltd_responses`) and
holds the checks every march shares (:func:`check_march`, :func:`check_times`); :mod:`cfd.ltd.radau` is the
Radau IIA tableau and its dense output; :mod:`cfd.ltd.coupled` marches the linear system with a two-degree-of-freedom
structure (:func:`cfd.coupled_ltd`).
"""

import dataclasses
import logging
import math
import time
import warnings
from dataclasses import dataclass

import numpy as np
from threadpoolctl import threadpool_limits

from ..checks import callback, kind_of, log_interval as check_log_interval, real_array, real_number
from ..errors import MarchInterrupted
from ..gust import OneMinusCosine, SharpEdged, SineGust, check_gust_step, face_gust, warn_unseen
from ..frequencies import check_pivot, check_x_ref
from ..linear import LinearError, check_gust_method, check_linear_system
from ..motion import motion_forcing
from .radau import RADAU_C, dense_weights, radau_transform, stability_function

__all__ = ["LTDHistory", "ltd_response", "ltd_responses", "phase_error_estimate", "check_march", "SCHEMES",
           "RADAU_STEP", "radau_substeps", "radau_steps", "gust_frequency", "check_scheme", "MAX_STEPS", "MAX_TIME",
           "check_times"]

log = logging.getLogger(__name__)


@dataclass(frozen=True, eq=False)
class LTDHistory:
    """Time history of a linear gust response (perturbations about the steady loads).

    Attributes
    ----------
    t : ndarray, shape (n + 1,)
        Convective time ``s = t U / c``, from 0 to ``t_end``.
    u : ndarray, shape (n + 1,)
        Gust input ``v_g(x_ref, s) / U`` (dimensionless: the tangent of the local gust angle; zeros without a
        gust).
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


SCHEMES = ("bdf2", "radau5")
"""Time schemes of the LTD: BDF2 (one real factorisation, one solve per step) and the three-stage Radau IIA
(order 5; one real and one complex factorisation, one solve of each per step of :data:`RADAU_STEP`)."""


def gust_frequency(gust):
    """The gust's frequency scale (U/c): the sine's frequency, ``2 pi / length`` for the 1-cosine gust, and
    ``2 pi`` (one chord) for the sharp-edged gust."""
    if isinstance(gust, SineGust):
        return gust.omega
    if isinstance(gust, OneMinusCosine):
        return 2.0 * math.pi / gust.length
    return 2.0 * math.pi


def phase_error_estimate(gust, dt, scheme="bdf2", step=None):
    """Relative phase-rate error of the scheme at the gust's frequency scale :func:`gust_frequency`.

    BDF2 with step ``dt``: its phase-rate error ``(omega dt)^2 / 3`` (it dominates BDF2's error). Radau IIA with
    the step ``h = m dt`` of :func:`radau_substeps`: ``|log(R(i omega h)) / (i omega h) - 1|``, the relative
    error of the growth rate, phase and amplitude together, with its stability function ``R``: about
    ``(omega h)^5 / 7200`` of damping and ``(omega h)^6 / 42 000`` of phase rate (damping dominates).
    """
    check_scheme(scheme)
    w = gust_frequency(gust)
    if scheme == "bdf2":
        wdt = w * dt
        return wdt * wdt / 3.0   # inf, not OverflowError, for an absurd dt (``** 2`` of a float raised one at 1e300)
    wh = w * radau_substeps(dt, step) * dt
    R = stability_function(1j * wh)
    with np.errstate(divide="ignore"):   # R = 0 (L-stable) at an absurd step: an error of inf, without a warning
        return abs(complex(np.log(abs(R)), float(np.angle(R))) / (1j * wh) - 1.0)


def check_scheme(scheme, dt=None, step=None):
    """Raise :class:`LinearError` unless ``scheme`` is one of :data:`SCHEMES` and, with ``dt``, ``step`` suits it
    (None for BDF2; for Radau IIA a positive whole multiple of ``dt``, :func:`radau_substeps`)."""
    if scheme not in SCHEMES:
        raise LinearError(f"scheme must be one of {SCHEMES}; got {scheme!r}")
    if dt is None:
        return
    if scheme == "bdf2" and step is not None:
        raise LinearError(f"step = {step!r} applies to scheme='radau5' only (BDF2 steps at dt = {dt})")
    if scheme == "radau5":
        radau_substeps(dt, step)


def _check_gust(gust):
    if not isinstance(gust, (SineGust, OneMinusCosine, SharpEdged)):
        raise LinearError(f"gust must be a cfd.SineGust, OneMinusCosine or SharpEdged; got {type(gust).__name__}")


def _check_initial(lin, initial, scheme):
    """``initial`` as ``(q_prev, q_now)``, real finite arrays of shape ``(lin.n,)`` (``q_prev`` may be None for
    Radau IIA, which does not use it), or None; else :class:`LinearError`."""
    if initial is None:
        return None
    what = f"initial must be a pair (q_prev, q_now) of states of shape ({lin.n},) (4N, solver units)"
    if isinstance(initial, np.ndarray) and initial.ndim == 2 and initial.shape[0] == 2:
        initial = (initial[0], initial[1])  # a (2, 4N) array: its rows are the pair
    if isinstance(initial, np.ndarray) or not isinstance(initial, (tuple, list)) or len(initial) != 2:
        raise LinearError(f"{what}; got {type(initial).__name__}" + (
            f" of shape {np.shape(initial)}" if isinstance(initial, np.ndarray) else ""))
    out = []
    for name, a in zip(("q_prev", "q_now"), initial):
        if a is None and name == "q_prev" and scheme == "radau5":
            out.append(None)                            # a one-step method: q_now only
            continue
        v = real_array(a)
        if v is None:
            raise LinearError(f"{what}; its {name} is not an array of real numbers: {kind_of(a)}")
        if v.shape != (lin.n,):
            raise LinearError(f"{what}; its {name} has shape {v.shape}")
        if not np.all(np.isfinite(v)):
            raise LinearError(f"{what}; its {name} contains NaN or inf")
        out.append(v)
    return tuple(out)


MAX_STEPS = 1_000_000
"""Most time steps one march takes (``round(t_end / dt)``): the paper's march is 2000 steps (dt 0.02, t_end 40);
a million BDF2 steps of the paper grid (one back-substitution each, about 0.03 s) are some 8 hours. Longer
histories are marched in pieces, each from the last state of the one before (``initial=``). The study files'
limit, ``studies.schema.MAX_STEPS``, is the same number (a test checks it)."""


MAX_TIME = 1e6
"""Latest convective time one march reaches (``t_end``): the gust's face averages are differences of its
antiderivative at ``x - x0 - s``, which keep fewer of the grid's digits as ``s`` grows (a sharp-edged gust on the
test grid: the loads off by 5e-9 at ``s = 1e6``, 7 % at 1e15, zero at 1e18 and beyond, all without a word). The
paper's march ends at 40; a gust has long passed the aerofoil after a few hundred chords."""


def check_times(dt, t_end, error=LinearError):
    """``(dt, t_end)`` as floats, checked for every time march (LTD, coupled, nonlinear) before any work: ``dt``
    positive and finite, ``t_end`` finite, at least ``dt`` and at most :data:`MAX_TIME`, at most :data:`MAX_STEPS`
    steps; else ``error``."""
    dt, t_end = real_number(dt), real_number(t_end)   # None for a bool and for text (dt="0.1" was parsed)
    if dt is None or t_end is None:
        raise error("dt and t_end must be real numbers (convective time)")
    if not (math.isfinite(dt) and dt > 0.0):
        raise error(f"dt = {dt} must be positive and finite (convective time, e.g. 0.02)")
    if not (math.isfinite(t_end) and t_end >= dt):
        raise error(f"t_end = {t_end} must be finite and at least one time step (dt = {dt})")
    if round(t_end / dt) > MAX_STEPS:
        raise error(f"t_end / dt = {t_end:g} / {dt:g} = {t_end / dt:.3g} steps, more than cfd.ltd.MAX_STEPS = "
                          f"{MAX_STEPS:.0e}: check dt (convective time, c / U; the paper's step is 0.02), or march a "
                          "longer history in pieces, each from the state the last one ended in (initial=)")
    if t_end > MAX_TIME:   # an absurd dt (1e300) marched a sharp-edged gust to zero loads without a word
        raise error(f"t_end = {t_end:g} (convective time) is beyond cfd.ltd.MAX_TIME = {MAX_TIME:.0e}: there the "
                    f"gust's position x - x0 - s keeps too few of the grid's digits for its face averages; check dt "
                    f"(= {dt:g}; convective time, c / U; the paper's step is 0.02) and t_end (the paper's is 40)")
    return dt, t_end


def _warn_phase(gust, dt, max_phase_error, scheme="bdf2", step=None):
    if isinstance(max_phase_error, bool) or not isinstance(max_phase_error, (int, float, np.integer, np.floating)) \
            or not max_phase_error > 0.0:
        raise LinearError(f"max_phase_error must be a positive number (relative phase-rate error that warns, default "
                          f"0.01; inf never warns); got {max_phase_error!r}")
    err = phase_error_estimate(gust, dt, scheme, step)
    if err > max_phase_error:
        if scheme == "bdf2":
            what, power = f"dt = {dt} gives an estimated BDF2 phase-rate", 2.0
        else:
            what, power = (f"the Radau IIA step {radau_substeps(dt, step) * dt:g} gives an estimated growth-rate "
                           "(phase and amplitude)"), 5.0
        knob = "dt" if scheme == "bdf2" or radau_substeps(dt, step) == 1 else "the step"
        warnings.warn(
            f"{what} error of {100 * err:.2g} % at the gust's frequency scale (limit "
            f"{100 * max_phase_error:.2g} %); reduce {knob} by "
            f"{(err / max_phase_error) ** (1.0 / power):.2g}x",
            RuntimeWarning,
            stacklevel=3,
        )


def check_march(gust, dt, t_end, max_phase_error=0.01, x_ref=0.0):
    """The checks of :func:`ltd_response` for a march of ``gust`` built elsewhere (``cfd.ltd.coupled``).

    Returns the checked ``(dt, t_end)`` (floats); raises :class:`LinearError` for a gust of the wrong type, bad
    times or a gust shorter than :data:`cfd.gust.MIN_GUST_STEPS` steps, and warns (``RuntimeWarning``) when
    :func:`phase_error_estimate` exceeds ``max_phase_error`` or the march ends before the gust reaches ``x_ref``.
    """
    _check_gust(gust)
    dt, t_end = check_times(dt, t_end)
    check_gust_step(gust, dt, LinearError)
    _warn_phase(gust, dt, max_phase_error)
    warn_unseen(gust, t_end, check_x_ref(x_ref), stacklevel=4)
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


class _Clock:
    """Progress of a march: the caller's ``progress(step, n_steps, t)`` and a log line every ``interval`` s."""

    def __init__(self, method, columns, progress, interval):
        self.method, self.columns, self.progress, self.interval = method, columns, progress, interval
        self.start = self.last = time.perf_counter()

    def __call__(self, k, n, t):
        if self.progress is not None:
            self.progress(k, n, float(t))
        now = time.perf_counter()
        if now - self.last >= self.interval:
            self.last = now
            log.info("ltd %s: step %d / %d (s = %.3f), %d column(s), %.0f s", self.method, k, n, t, self.columns,
                     now - self.start)


class _Stopped(KeyboardInterrupt):
    """An interrupt of a march's loop after output step ``k``: the loads ``Y[:k + 1]`` and the state there (as the
    loop would return them had it ended at ``k``); :func:`_march` turns it into :class:`MarchInterrupted`."""

    def __init__(self, k, Y, q):
        super().__init__(k)
        self.k, self.Y, self.q = k, Y, q


def _bdf2(lin, gusts, t, method, initial, moves, clock):
    """BDF2 on the grid ``t``: the loads ``Y`` (n + 1, 3, g) (without the motions' ``d x``) and the final state;
    :class:`_Stopped` on an interrupt."""
    n = t.size - 1
    dt = t[1] - t[0]
    h = lin.to_solver_time(dt)
    V = lin.V[:, None]
    solve = lin.solver(1.5 * lin.V / h)
    g = max(len(gusts), 1)
    if initial is None:
        q_prev = np.zeros((lin.n, g))
        q = np.zeros((lin.n, g))
    else:
        q_prev, q = (np.asarray(a, dtype=float).reshape(lin.n, 1).copy() for a in initial)
    Y = np.zeros((n + 1, 3, g))
    Y[0] = lin.C @ q
    done = (0, q)   # the last completed step and its state: what an interrupt keeps
    try:
        for k in range(1, n + 1):  # time steps: each one back-substitution of g right-hand sides
            b = _gust_forcing(lin, gusts, t[k], method) if gusts else np.zeros((lin.n, g))
            for f, x, rate in moves:
                b = b + (f.b0 * x[k] + f.b1 * rate[k])[:, None]
            q_prev, q = q, solve(V * (4.0 * q - q_prev) / (2.0 * h) - b)
            Y[k] = lin.C @ q
            done = (k, q)
            clock(k, n, t[k])
    except KeyboardInterrupt as e:
        k, q = done
        raise _Stopped(k, Y[:k + 1], q) from e
    return Y, q


RADAU_STEP = 0.14
"""Default Radau IIA step (convective time): the largest whole multiple of the output ``dt`` not above it."""


def radau_substeps(dt, step=None):
    """Output steps ``dt`` per Radau IIA step: ``round(step / dt)`` (at least 1); ``step=None``: the largest
    multiple of ``dt`` not above :data:`RADAU_STEP`."""
    if step is None:
        return max(1, int(math.floor(RADAU_STEP / dt + 1e-9)))
    try:
        step = float(step)
    except (TypeError, ValueError):
        raise LinearError(f"step must be a number (convective time) or None; got {step!r}") from None
    if not (math.isfinite(step) and step > 0.0):
        raise LinearError(f"step = {step} must be positive and finite (convective time, e.g. 0.14)")
    m = int(round(step / dt))
    if m < 1 or abs(m * dt - step) > 1e-9 * max(step, dt):
        raise LinearError(f"the Radau step {step} must be a whole multiple of dt = {dt} (the output grid); "
                          f"e.g. step = {max(m, 1) * dt:g}")
    return m


def radau_steps(n, m):
    """Radau IIA steps that cover ``n`` output intervals, ``m`` to a step (the last may end past ``t_end``)."""
    return -(-n // m)


def _stage_times(t, m):
    """Convective times of the stages of every Radau IIA step over the output grid ``t``: (n_steps, 3)."""
    H = m * (t[1] - t[0])
    return t[0] + H * (np.arange(radau_steps(t.size - 1, m))[:, None] + RADAU_C[None, :])


def _radau_motions(lin, t, plunge, pitch, pivot, stage_times):
    """``[(MotionForcing, x, x_stages)]`` for the Radau march: the samples at ``t`` and the values at the stage
    times (array, shape of ``stage_times``), from the history's own callable (one call with the array) or a cubic
    spline through the samples (extrapolated over the last step's part past ``t_end``)."""
    from scipy.interpolate import CubicSpline

    out = []
    for name, history in (("plunge", plunge), ("pitch", pitch)):
        if history is None:
            continue
        x = _motion_samples(name, history, t)
        flat = stage_times.ravel()
        xs = (_motion_samples(name, history, flat) if callable(history) else CubicSpline(t, x)(flat))
        xs = xs.reshape(stage_times.shape)
        out.append((motion_forcing(lin, name, pivot), x, xs))
    return out


def _radau(lin, gusts, t, method, initial, moves, m, stage_times, clock):
    """Radau IIA (:mod:`cfd.ltd.radau`) with steps of ``m`` output intervals, dense output on the grid ``t``;
    ``stage_times`` (n_steps, 3): the convective times of every step's stages (:func:`_stage_times`).

    A motion ``x`` (input of ``b0 x + b1 x'``) is marched in the variable ``p = q + V^-1 b1 x / mach``, which
    removes the rate: ``V p' + J p + (b0 - J V^-1 b1 / mach) x = 0``, ``y = C p + (d - C V^-1 b1 / mach) x``.

    Returns
    -------
    Y : ndarray, shape (n + 1, 3, g)
        Loads, motions' terms included.
    q : ndarray, shape (4N, g)
        State at ``t[-1]``.

    Raises
    ------
    _Stopped
        On an interrupt, with the loads and state up to the last completed step.
    """
    n = t.size - 1
    dt = t[1] - t[0]
    H = m * dt                                         # convective step
    h = float(lin.to_solver_time(H))
    lam, P, Pinv = radau_transform()
    e = Pinv @ np.ones(3)                              # P^-1 1
    solve_r = lin.solver((lam[0].real / h) * lin.V)
    solve_c = lin.solver((lam[1] / h) * lin.V, native_complex=True)
    V = lin.V[:, None]
    g = max(len(gusts), 1)
    # motions in p: forcing (b0 - J V^-1 b1 / mach) x, output (d - C V^-1 b1 / mach) x, p = q + V^-1 b1 x / mach
    shifts = [f.b1 / (lin.V * lin.mach) for f, _, _ in moves]
    forces = [f.b0 - lin.apply_jacobian(s) for (f, _, _), s in zip(moves, shifts)]
    # at rest before s = 0 (x = 0 there): p starts at q, and a jump of x at s = 0 is an impulsive start
    q = np.zeros((lin.n, g)) if initial is None else np.asarray(initial[-1], dtype=float).reshape(lin.n, 1).copy()
    # (min(m, n), 4): the output points inside a step that the march uses (all m of them built before: a dt of
    # 1e-300 asked for 1e299 rows, a bare ValueError "Maximum allowed size exceeded")
    W = dense_weights(np.arange(1, min(m, n) + 1) / m)
    Y = np.zeros((n + 1, 3, g))
    Y[0] = lin.C @ q
    y_n = Y[0]
    done = (0, q)   # the last completed output step and the state there: what an interrupt keeps
    try:
        for k, times in enumerate(stage_times):
            b = np.zeros((3, lin.n, g))
            for i, s_i in enumerate(times):
                if gusts:
                    b[i] = _gust_forcing(lin, gusts, s_i, method)
                for fb, (_, _, xs) in zip(forces, moves):
                    b[i] += (fb * xs[k, i])[:, None]
            Vq = V * q
            r = np.tensordot(Pinv[:2], b, axes=(1, 0))     # (2, 4N, g): (P^-1 b)_k for the real and complex rows
            w_r = solve_r((lam[0].real / h) * e[0].real * Vq - r[0].real)
            w_c = solve_c((lam[1] / h) * e[1] * Vq - r[1])
            stages = [P[i, 0].real * w_r + 2.0 * (P[i, 1] * w_c).real for i in range(3)]
            y_stages = np.stack([y_n] + [lin.C @ Q for Q in stages])          # (4, 3, g)
            lo = k * m
            hi = min(lo + m, n)
            Y[lo + 1:hi + 1] = np.tensordot(W[:hi - lo], y_stages, axes=(1, 0))
            if hi < lo + m:                                # the last step ends past t_end: the state there
                q = np.tensordot(dense_weights([(hi - lo) / m])[0], np.stack([q] + stages), axes=(0, 0))
            else:
                q = stages[-1]
            y_n = y_stages[-1]
            done = (hi, q)
            clock(hi, n, t[hi])
    except KeyboardInterrupt as e:
        hi, q = done
        raise _Stopped(hi, *_radau_motion_terms(lin, Y[:hi + 1], q, shifts, moves, hi)) from e
    return _radau_motion_terms(lin, Y, q, shifts, moves, n)


def _radau_motion_terms(lin, Y, q, shifts, moves, k):
    """The loads ``Y[:k + 1]`` and the state at output step ``k`` of :func:`_radau` back in ``q`` from ``p``: the
    motions' terms ``(d - C V^-1 b1 / mach) x`` added to ``Y`` (in place) and ``V^-1 b1 x / mach`` taken from ``q``."""
    for s, (f, x, _) in zip(shifts, moves):
        Y += np.multiply.outer(x[:k + 1], f.d - lin.C @ s)[:, :, None]
    q = q - sum((s * x[k] for s, (_, x, _) in zip(shifts, moves)), np.zeros(lin.n))[:, None]
    return Y, q


def _gust_forcing(lin, gusts, s, method):
    """Forcing ``b`` (4N, g) of the gusts at convective time ``s``."""
    faces = [face_gust(lin.grid, gust, s) for gust in gusts]
    return lin.forcing(np.stack([f[0] for f in faces]), np.stack([f[1] for f in faces]), method).T


def _march(lin, gusts, dt, t_end, method, x_ref, initial, motion=None, progress=None, log_interval=60.0,
           scheme="bdf2", step=None):
    """March a list of gusts at once (or one column of motion alone); returns a list of :class:`LTDHistory`.

    ``motion``: None or ``(plunge, pitch, pivot)`` (see :func:`_motions`), forcing every column. ``progress`` and
    ``log_interval``: see :func:`ltd_response`; ``scheme`` and ``step``: see :func:`ltd_responses`.
    """
    n_steps = n = int(round(t_end / dt))
    t = dt * np.arange(n + 1)
    g = max(len(gusts), 1)
    clock = _Clock(method, g, progress, log_interval)
    stopped = None
    # one BLAS thread: the steps' small dense products would otherwise leave BLAS threads spinning on the other
    # core while SuperLU back-substitutes (measured on the 2-core machine: Radau's complex solve 55 ms instead
    # of 25 ms on a 91 x 30 grid)
    with threadpool_limits(limits=1, user_api="blas"):
        try:
            if scheme == "bdf2":
                moves = [] if motion is None else _motions(lin, t, *motion)
                Y, q = _bdf2(lin, gusts, t, method, initial, moves, clock)
            else:
                m = radau_substeps(dt, step)
                stage_times = _stage_times(t, m)
                moves = [] if motion is None else _radau_motions(lin, t, *motion, stage_times)
                Y, q = _radau(lin, gusts, t, method, initial, moves, m, stage_times, clock)
        except _Stopped as e:                                  # interrupted: the history so far, then re-raise
            stopped, Y, q = e, e.Y, e.q
        if scheme == "bdf2":
            for f, x, _ in moves:
                Y += np.multiply.outer(x[:Y.shape[0]], f.d)[:, :, None]   # the explicit load term d x
    if stopped is not None:
        n = stopped.k
        t = t[:n + 1]
    moves = [(f, x[:n + 1]) for f, x, _ in moves]
    if stopped is None and not np.all(np.isfinite(Y)):
        raise LinearError("the march's loads overflowed to inf or NaN: the inputs are too large for floating point "
                          "(the system is linear: march a unit input and scale the loads)")
    x_of = {f.name: x for f, x in moves}
    pivot = next((f.pivot for f, _ in moves if f.name == "pitch"), None)
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
    if stopped is not None:
        raise MarchInterrupted(f"the {method} march was interrupted; the history up to step {n} of {n_steps} "
                               f"(s = {t[n]:.4g}) is in .partial", partial=out, step=n, time=float(t[n])) from stopped
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
                  log_interval=60.0, scheme="bdf2", step=None):
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
    dt, t_end, method, x_ref, max_phase_error, progress, log_interval, scheme, step
        As :func:`ltd_response` (shared by all gusts; ``progress`` is called once per step of the march).

    Returns
    -------
    list of LTDHistory
        One per gust, in order.

    Raises
    ------
    LinearError
        As :func:`ltd_response`, or ``gusts`` empty or not a sequence (a single gust).
    MarchInterrupted
        As :func:`ltd_response`; ``.partial`` is the list of histories so far, one per gust.
    """
    check_linear_system(lin)
    check_gust_method(method)
    if isinstance(gusts, (SineGust, OneMinusCosine, SharpEdged)):
        raise LinearError("gusts must be a sequence of gusts; for one gust pass [gust] or use ltd_response")
    try:
        gusts = list(gusts)
    except TypeError:
        raise LinearError(f"gusts must be a sequence of cfd.SineGust, OneMinusCosine or SharpEdged; got "
                          f"{type(gusts).__name__}") from None
    if not gusts:
        raise LinearError("gusts is empty: give at least one cfd.SineGust, OneMinusCosine or SharpEdged")
    for gust in gusts:
        _check_gust(gust)
    dt, t_end = check_times(dt, t_end)
    x_ref = check_x_ref(x_ref)
    check_scheme(scheme, dt, step)
    progress = callback("progress", progress, LinearError)
    log_interval = check_log_interval(log_interval, LinearError)
    for gust in gusts:
        check_gust_step(gust, dt, LinearError)
    for gust in gusts:
        _warn_phase(gust, dt, max_phase_error, scheme, step)
        warn_unseen(gust, t_end, x_ref)
    reps, maps = _shape_groups(gusts)

    def per_gust(marched):
        return [marched[i] if gust is reps[i] else _scaled(marched[i], gust, factor, marched[i].t, x_ref)
                for gust, (i, factor) in zip(gusts, maps)]

    try:
        marched = _march(lin, reps, dt, t_end, method, x_ref, None, progress=progress, log_interval=log_interval,
                         scheme=scheme, step=step)
    except MarchInterrupted as e:
        e.partial = per_gust(e.partial)
        raise
    return per_gust(marched)


def ltd_response(lin, gust, dt, t_end, method="svm", x_ref=0.0, initial=None, max_phase_error=0.01, *,
                 plunge=None, pitch=None, pivot=0.25, progress=None, log_interval=60.0, scheme="bdf2", step=None):
    """Linear response to a gust and/or a prescribed rigid motion by time marching (BDF2 or Radau IIA).

    Parameters
    ----------
    lin : LinearSystem
        From ``cfd.linearise``.
    gust : SineGust, OneMinusCosine, SharpEdged or None
        None: no gust (then give ``plunge`` or ``pitch``).
    dt : float
        Convective time step (chords / U), ``> 0``: BDF2's step, and the output grid of both schemes.
    t_end : float
        Final convective time, ``>= dt``.
    method : {"svm", "fvm"}
    x_ref : float
        Where the gust input signal is measured (chords).
    initial : tuple (q_prev, q_now) of ndarray, shape (4N,), optional
        State at ``s = -dt`` and ``s = 0`` (solver units); default at rest (zeros). Radau IIA (a one-step
        method) uses ``q_now`` only (``q_prev`` may be None).
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
        ``progress(step, n_steps, t)`` after every time step (``step = 1 ... n_steps`` of the ``dt`` grid, ``t``
        its convective time; Radau IIA calls it after each of its steps, with the last output step it reached);
        its return value is ignored. It does not change the result.
    log_interval : float
        Seconds between progress lines on the ``cfd.ltd`` logger (level INFO).
    scheme : {"bdf2", "radau5"}
        ``"bdf2"`` (default): BDF2 with step ``dt`` (one real factorisation, one solve per step).
        ``"radau5"``: three-stage Radau IIA (order 5, L-stable, :mod:`cfd.ltd.radau`) with steps of ``step``, one
        real and one complex solve per step (two factorisations), the loads on the ``dt`` grid from its
        collocation polynomial (dense output, ``O(step^4)``). Measured on the paper's gusts
        (``bench/ltd_radau_bench.py``): more accurate than BDF2 at ``dt = 0.02`` for less work
        (docs/performance.md).
    step : float, optional
        Radau IIA only: its step (convective time), a whole multiple of ``dt``; default the largest multiple
        of ``dt`` not above :data:`RADAU_STEP` (:func:`radau_substeps`). A motion given as samples is
        interpolated by a cubic spline at the stage times (give a callable for its exact values; it is called
        once with the flat array of all stage times, those of the last step past ``t_end`` included).

    Returns
    -------
    LTDHistory
        Loads of the gust and the motion together (the system is linear: marched once); ``h`` and ``alpha`` hold
        the prescribed samples.

    Raises
    ------
    LinearError
        Non-positive or non-finite ``dt``, ``t_end < dt`` or beyond :data:`MAX_TIME`, more than :data:`MAX_STEPS` steps,
        a gust that passes in fewer than :data:`cfd.gust.MIN_GUST_STEPS` steps (its samples could all miss it), unknown
        method or scheme, not a gust, neither a gust nor a motion, a ``progress`` that is not callable, a negative
        ``log_interval``, a motion history of the wrong length or with non-finite values, a non-finite pivot or
        ``x_ref``, a ``max_phase_error`` that is not a positive number, a Radau step that is not a positive whole
        multiple of ``dt``, an ``initial`` that is not a pair of finite real states of shape (4N,), ``lin`` not a
        ``LinearSystem``; loads that overflow to inf or NaN (inputs too large for floating point).
    MarchInterrupted
        A ``KeyboardInterrupt`` (Ctrl-C, or raised by ``progress``) during the march: re-raised as this subclass of
        ``KeyboardInterrupt``, with the history up to the last completed output step in ``.partial``.

    Warns
    -----
    RuntimeWarning
        :func:`phase_error_estimate` above ``max_phase_error``; a march from rest that ends before the gust's front
        reaches ``x_ref`` (loads of about zero).
    """
    check_linear_system(lin)
    check_gust_method(method)
    if gust is None and plunge is None and pitch is None:
        raise LinearError("nothing to march: give a gust, or a plunge or pitch history (ltd_response(lin, None, dt, "
                          "t_end, pitch=...))")
    if gust is not None:
        _check_gust(gust)
    dt, t_end = check_times(dt, t_end)
    x_ref = check_x_ref(x_ref)
    pivot = check_pivot(pivot)
    check_scheme(scheme, dt, step)
    initial = _check_initial(lin, initial, scheme)
    progress = callback("progress", progress, LinearError)
    log_interval = check_log_interval(log_interval, LinearError)
    if gust is not None:
        check_gust_step(gust, dt, LinearError)
        _warn_phase(gust, dt, max_phase_error, scheme, step)
        if initial is None:
            warn_unseen(gust, t_end, x_ref)
    motion = None if plunge is None and pitch is None else (plunge, pitch, pivot)
    try:
        return _march(lin, [] if gust is None else [gust], dt, t_end, method, x_ref, initial, motion,
                      progress=progress, log_interval=log_interval, scheme=scheme, step=step)[0]
    except MarchInterrupted as e:
        e.partial = e.partial[0]
        raise
