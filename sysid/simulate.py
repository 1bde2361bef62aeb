"""Time simulation of a discrete ROM: Markov parameters, FFT convolution, python-control fallback.

A ROM identified at sampling period ``T`` (dt = T) is simulated at another step ``dt`` by mapping it to
continuous time (inverse bilinear map, paper Eq. 26) and re-discretising it at ``dt`` by Tustin (Eq. 31) or
zero-order hold (Eq. 32). The discrete model is then driven from rest by an FFT convolution of its impulse
response (:func:`markov_parameters`), or by ``control.forced_response`` when it is unstable.

As in python-control, :func:`rom_response` returns the data (a ``control.TimeResponseData``); plotting is
left to the caller. :func:`rom_simulation` is the same computation on bare matrices, returning the outputs.
Time is convective (s = t U / c); inputs and outputs are in the model's units (gust angle in radians, load
coefficients per radian for the gust ROMs).
"""

from __future__ import annotations

import numpy as np

from .errors import ArgumentTypeError, ModelError, OptionError, TimeDataError
from .grids import check_period
from .transforms import c2d_bilinear, c2d_zoh, d2c_bilinear

__all__ = ["markov_parameters", "simulate_discrete", "rediscretise", "rom_simulation", "rom_response",
           "first_uneven_step", "check_matrices", "DISCRETISATIONS", "SIMULATION_METHODS", "MAX_SIMULATION_VALUES"]

MAX_SIMULATION_VALUES = 10**7 * 8
"""Largest ``n x m x N`` (states x inputs x time steps) :func:`rom_simulation` takes: the FFT convolution holds
the first ``N`` Markov parameters of every state, ``16 n m N`` bytes while doubling (1.3 GB here), and
python-control's march as much; an order-55 ROM over 2000 steps needs 1.1e5."""

DISCRETISATIONS = ("tustin", "zoh")
"""Re-discretisations of a ROM at the simulation step: Tustin (paper Eq. 31) or zero-order hold (Eq. 32)."""

SIMULATION_METHODS = ("auto", "convolution", "control")
"""How :func:`simulate_discrete` drives a discrete model (see there)."""


def markov_parameters(A, B, C, N):
    """The first ``N`` Markov parameters ``C A^k B``, ``k = 0 .. N - 1``, by doubling.

    ``[B, AB, ..., A^(2L-1) B] = [X, A^L X]`` with ``X = [B, ..., A^(L-1) B]``: ``log2 N`` matrix products
    instead of ``N`` matrix-vector products in Python.

    Parameters
    ----------
    A, B, C : ndarray, shapes (n, n), (n, m), (p, n)
    N : int

    Returns
    -------
    ndarray, shape (p, m, N)

    Raises
    ------
    ModelError
        Matrices of the wrong shapes (named) or not finite.
    OptionError
        ``N`` not a positive whole number.
    TimeDataError
        ``n m N`` above :data:`MAX_SIMULATION_VALUES`.
    """
    B = np.asarray(B, dtype=float)
    C = np.asarray(C, dtype=float)
    A, B, C, _ = check_matrices(A, B, C, np.zeros((np.shape(C)[0] if np.ndim(C) == 2 else 0,
                                                   np.shape(B)[1] if np.ndim(B) == 2 else 0)))
    if isinstance(N, (bool, np.bool_)) or not isinstance(N, (int, np.integer)) or N < 1:
        raise OptionError(f"N must be a positive whole number of Markov parameters, got {N!r}")
    _check_size(A.shape[0], B.shape[1], N)
    n, m = B.shape
    X = B.T.reshape(m, n, 1)  # per input: columns A^k b
    P = A
    while X.shape[2] < N:
        X = np.concatenate([X, np.einsum("ij,mjk->mik", P, X)], axis=2)
        P = P @ P
    return np.einsum("pi,mik->pmk", C, X[:, :, :N])


def simulate_discrete(A, B, C, D, u, method="auto"):
    """Response of ``x[k+1] = A x[k] + B u[k], y[k] = C x[k] + D u[k]`` from rest, as python-control's
    ``forced_response`` gives it.

    ``"convolution"``: ``y = D u + g * u`` with the impulse response ``g[0] = 0``, ``g[k] = C A^(k-1) B``
    (:func:`markov_parameters`) and an FFT convolution: the same numbers to round-off, 13x (order 9) to 2.9x
    (order 55) faster than the step-by-step recursion of ``control.forced_response`` for 2000 steps
    (``bench/rom_simulation_bench.py``, re-discretisation included). ``"control"``:
    ``control.forced_response``. ``"auto"``: the convolution when ``A`` is stable (spectral radius
    ``< 1``), else python-control (the impulse response of an unstable model grows without bound and its
    FFT would lose the small early values).

    Parameters
    ----------
    A, B, C, D : ndarray, shapes (n, n), (n, m), (p, n), (p, m)
    u : ndarray, shape (N,) or (m, N)
        Input samples, one per step.
    method : {"auto", "convolution", "control"}

    Returns
    -------
    ndarray, shape (p, N)
        Output samples.

    Raises
    ------
    OptionError
        Unknown ``method``.
    ModelError
        Matrices of the wrong shapes (named) or not finite.
    TimeDataError
        ``u`` with another number of channels than ``B`` has columns, not finite, or too long
        (:data:`MAX_SIMULATION_VALUES`).
    """
    import control
    from scipy.signal import fftconvolve

    if not isinstance(method, str) or method not in SIMULATION_METHODS:
        raise OptionError(f"method must be 'auto', 'convolution' or 'control', got {method!r}")
    A, B, C, D = check_matrices(*(np.atleast_2d(np.asarray(x, dtype=float)) for x in (A, B, C, D)))
    U = _check_input(u, B.shape[1])
    N = U.shape[1]
    _check_size(A.shape[0], B.shape[1], N)
    if method == "auto":
        rho = float(np.max(np.abs(np.linalg.eigvals(A)))) if A.size else 0.0
        method = "convolution" if rho < 1.0 else "control"
    if method == "control":
        out = control.forced_response(control.ss(A, B, C, D, True), U=U)
        return np.atleast_2d(np.asarray(out.outputs))
    G = markov_parameters(A, B, C, max(N - 1, 1))  # (p, m, N - 1): g[1:]
    Y = D @ U
    for j in range(U.shape[0]):
        Y[:, 1:] += fftconvolve(G[:, j, :], U[j][None, :], axes=1)[:, :N - 1]
    return Y


def rediscretise(model, dt: float, discretisation: str = "tustin"):
    """A discrete model at another sampling period: inverse bilinear map (Eq. 26), then Tustin or ZOH at ``dt``.

    Parameters
    ----------
    model : control.StateSpace
        Discrete, ``model.dt`` its sampling period ``T`` (convective time).
    dt : float
        The new sampling period (convective time).
    discretisation : {"tustin", "zoh"}

    Returns
    -------
    control.StateSpace
        Discrete, ``dt``.

    Raises
    ------
    OptionError
        Unknown ``discretisation``.
    ModelError
        The continuous form has a pole at ``s = 2 / dt`` (Tustin cannot map it).
    """
    import control

    if not isinstance(discretisation, str) or discretisation not in DISCRETISATIONS:
        raise OptionError(f"discretisation must be 'tustin' or 'zoh', got {discretisation!r}")
    if not isinstance(model, control.StateSpace):
        raise ArgumentTypeError(f"rediscretise() expects a discrete control.StateSpace, got {type(model).__name__}")
    continuous = d2c_bilinear(model)
    try:
        return c2d_bilinear(continuous, dt) if discretisation == "tustin" else c2d_zoh(continuous, dt)
    except ModelError as e:  # name the simulation step, not the identification's T
        raise ModelError(
            f"the ROM identified with T = {model.dt:g} cannot be re-discretised at the simulation step dt = "
            f"{dt:g} ({discretisation}): its continuous form has a pole at s = 2/dt = {2.0 / dt:g} ({e}); "
            "change simulation.dt (or the identification's T)") from None


def first_uneven_step(t) -> int | None:
    """Index ``k`` of the first step ``t[k+1] - t[k]`` that differs from ``t[1] - t[0]``, or None when the times
    are equispaced.

    Equispaced means to ``1e-6`` of the step and of the times' size (times printed with six significant digits
    pass), beyond the rounding of their type (float32); a dropped or doubled sample is off by a whole step.

    Parameters
    ----------
    t : array_like, shape (N,)
        Times, ``N >= 2``.

    Returns
    -------
    int or None
    """
    t_in = np.asarray(t)
    t = t_in.astype(float).reshape(-1)
    steps = np.diff(t)
    eps = np.finfo(t_in.dtype).eps if np.issubdtype(t_in.dtype, np.floating) else np.finfo(float).eps
    span = np.abs(t).max()
    bad = np.flatnonzero(~(np.abs(steps - steps[0]) <= 1e-6 * (steps[0] + span) + 8 * eps * span))
    return int(bad[0]) if bad.size else None


def _check_input(u, m: int, t=None) -> np.ndarray:
    """``u`` as a finite float array of shape ``(m, N)``; :class:`TimeDataError` naming the first bad sample."""
    if np.iscomplexobj(u):
        raise TimeDataError("u must be real (an input history); got complex values, whose imaginary part would be "
                            "dropped: pass u.real, or simulate the real and imaginary parts apart")
    try:
        U = np.atleast_2d(np.asarray(u, dtype=float))
    except (TypeError, ValueError):
        raise TimeDataError(f"u must be an array of numbers, shape (N,) or (m, N), got {u!r}"[:200]) from None
    if U.ndim != 2:
        raise TimeDataError(f"u must have shape (N,) or (m, N), got {np.shape(u)}")
    if U.shape[0] != m:
        raise TimeDataError(f"u has {U.shape[0]} input channels but the model has m = {m} (B's columns)")
    if U.shape[1] == 0:
        raise TimeDataError("u has no samples; give at least one time step")
    bad = np.argwhere(~np.isfinite(U))
    if bad.size:
        k = int(bad[0][1])
        at = f" (t = {t[k]:g})" if t is not None else ""
        raise TimeDataError(f"u contains NaN or inf at sample {k}{at}; every output from there on would be NaN: "
                            "repair or drop that sample")
    return U


def _check_size(n: int, m: int, N: int) -> None:
    size = max(n, 1) * m * N
    if size > MAX_SIMULATION_VALUES:
        raise TimeDataError(
            f"n x m x N = {n} x {m} x {N} = {size:.3g} values, above sysid.simulate.MAX_SIMULATION_VALUES = "
            f"{MAX_SIMULATION_VALUES:.3g} (about {16 * size / 2**30:.2g} GiB of Markov parameters): use a larger "
            "time step or fewer times, or a lower-order ROM")


def check_matrices(A, B, C, D) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``A, B, C, D`` as float arrays of shapes ``(n, n), (n, m), (p, n), (p, m)``, finite.

    Raises
    ------
    ModelError
        A matrix that is not 2-D, not real numbers, NaN or inf, or whose shape does not fit the others (the
        message names it, as python-control does: ``B has shape (2, 1) but A is 1 x 1``).
    """
    mats = {}
    for name, x in zip("ABCD", (A, B, C, D)):
        try:
            a = np.asarray(x, dtype=float)
        except (TypeError, ValueError):
            raise ModelError(f"{name} must be a matrix of real numbers, got {x!r}") from None
        if a.ndim != 2:
            raise ModelError(f"{name} must be a 2-D matrix, got shape {a.shape}")
        if not np.all(np.isfinite(a)):
            raise ModelError(f"{name} contains NaN or inf; repair the model")
        mats[name] = a
    A, B, C, D = (mats[k] for k in "ABCD")
    if A.shape[0] != A.shape[1]:
        raise ModelError(f"A must be square (n, n), got shape {A.shape}")
    n = A.shape[0]
    if B.shape[0] != n:
        raise ModelError(f"B has shape {B.shape} but A is {n} x {n}: B must be (n, m) = ({n}, m)")
    if C.shape[1] != n:
        raise ModelError(f"C has shape {C.shape} but A is {n} x {n}: C must be (p, n) = (p, {n})")
    if D.shape != (C.shape[0], B.shape[1]):
        raise ModelError(f"D has shape {D.shape} but C and B give (p, m) = ({C.shape[0]}, {B.shape[1]})")
    return A, B, C, D


def rom_simulation(A, B, C, D, T, t, u, discretisation="tustin", method="auto"):
    """Simulate a discrete ROM (sampling period ``T``) at the time step of ``t``.

    The ROM is re-discretised at ``dt = t[1] - t[0]`` (:func:`rediscretise`: paper Eqs. 26 then 31 or 32),
    then driven by ``u`` from rest (:func:`simulate_discrete`: an FFT convolution with its impulse response,
    or ``control.forced_response`` for an unstable model).

    Parameters
    ----------
    A, B, C, D : ndarray, shapes (n, n), (n, 1), (p, n), (p, 1)
    T : float
        Sampling period of the ROM (convective time).
    t : ndarray, shape (N,)
        Equispaced times from 0 (convective time).
    u : ndarray, shape (N,)
        Input (gust angle ``v_g / U`` at the reference point, radians).
    discretisation : {"tustin", "zoh"}
    method : {"auto", "convolution", "control"}
        See :func:`simulate_discrete`.

    Returns
    -------
    ndarray, shape (p, N)
        Outputs.

    Raises
    ------
    TimeDataError
        ``t`` not equispaced (to ``1e-6`` of its step and size, beyond its rounding), not increasing or not
        finite; ``u`` of another length, with another number of channels than ``B`` has columns, or not finite (a
        NaN made every later output NaN); fewer than two time points; ``n m N`` above
        :data:`MAX_SIMULATION_VALUES`.
    OptionError
        An unknown discretisation or method (checked first).
    FrequencyGridError
        ``T`` not positive and finite (python-control's "invalid timebase" before).
    ModelError
        A matrix of the wrong shape (named), not finite; the ROM cannot be re-discretised at that step.
    """
    import control

    if not isinstance(discretisation, str) or discretisation not in DISCRETISATIONS:
        raise OptionError(f"discretisation must be 'tustin' or 'zoh', got {discretisation!r}")
    if not isinstance(method, str) or method not in SIMULATION_METHODS:
        raise OptionError(f"method must be 'auto', 'convolution' or 'control', got {method!r}")
    A, B, C, D = check_matrices(A, B, C, D)
    T = check_period(T)
    t_in = np.asarray(t)
    try:
        t = t_in.astype(float).reshape(-1)
    except (TypeError, ValueError):
        raise TimeDataError(f"t must be an array of times (numbers), got {t!r}") from None
    bad = np.flatnonzero(~np.isfinite(t))
    if bad.size:
        raise TimeDataError(f"t contains NaN or inf at index {int(bad[0])}; give finite equispaced times")
    if t.size < 2:
        raise TimeDataError(f"need at least two time points, got {t.size}")
    dt = float(t[1] - t[0])
    steps = np.diff(t)
    if not (np.isfinite(dt) and dt > 0):
        raise TimeDataError(f"times must increase: t[1] - t[0] = {dt!r}; give equispaced increasing times")
    k = first_uneven_step(t_in)
    if k is not None:
        raise TimeDataError(f"times must be equispaced (the ROM is re-discretised at one step): t[{k + 1}] - t[{k}] "
                            f"= {float(steps[k])!r} but t[1] - t[0] = {dt!r}; resample the input on an equispaced grid")
    N_u = np.atleast_2d(np.asarray(u)).shape[-1]
    if N_u != t.size:
        raise TimeDataError(f"u has {N_u} samples but t has {t.size} times; give one input sample per time")
    U = _check_input(u, B.shape[1], t)
    _check_size(A.shape[0], B.shape[1], t.size)
    discrete = rediscretise(control.ss(A, B, C, D, T), dt, discretisation)
    return simulate_discrete(discrete.A, discrete.B, discrete.C, discrete.D, U if np.ndim(u) == 2 else U[0], method)


def rom_response(model, t, u, *, discretisation: str = "tustin", method: str = "auto"):
    """Response of a discrete ROM from rest to the input ``u`` sampled at the times ``t``.

    Parameters
    ----------
    model : control.StateSpace
        Discrete ROM, ``model.dt = T`` (convective time), ``m`` inputs and ``p`` outputs.
    t : array_like, shape (N,)
        Equispaced times from 0 (convective time); the model is re-discretised at their step.
    u : array_like, shape (N,) or (m, N)
        Input samples.
    discretisation : {"tustin", "zoh"}
    method : {"auto", "convolution", "control"}
        See :func:`simulate_discrete`.

    Returns
    -------
    control.TimeResponseData
        ``time`` (N,), ``outputs`` (p, N), ``inputs`` (m, N), with the model's signal names.

    Raises
    ------
    TimeDataError
        ``t`` not equispaced (to ``1e-6`` of its step and size, beyond its rounding) or not increasing, or ``u`` of
        another length, or fewer than two time points.
    OptionError
        An unknown discretisation or method.
    ModelError
        ``model`` is continuous, or the ROM cannot be re-discretised at that step; otherwise as
        :func:`rom_simulation`.
    TypeError
        ``model`` is not a ``control.StateSpace``.
    """
    import control

    if not isinstance(model, control.StateSpace):
        raise ArgumentTypeError(f"rom_response() expects a control.StateSpace (a discrete ROM), got {type(model).__name__}")
    if not model.isdtime(strict=True) or model.dt is True:
        raise ModelError(f"rom_response() expects a discrete model with dt = T > 0 (the ROM's sampling period); "
                         f"this one has dt = {model.dt!r}: discretise it first (sysid.c2d_bilinear(model, T))")
    try:
        U = np.atleast_2d(np.asarray(u, dtype=float))
    except (TypeError, ValueError):
        raise TimeDataError(f"u must be an array of numbers, shape (N,) or (m, N), got {u!r}") from None
    Y = rom_simulation(model.A, model.B, model.C, model.D, model.dt, t, U, discretisation, method)  # t as given:
    t = np.asarray(t, dtype=float)                                   # its rounding sets the equispacing check
    return control.TimeResponseData(t, Y, inputs=U, output_labels=list(model.output_labels),
                                    input_labels=list(model.input_labels), sysname=model.name, issiso=False,
                                    plot_inputs=True)
