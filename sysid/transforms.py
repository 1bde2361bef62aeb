"""Discrete <-> continuous conversions of state-space models (paper Eqs. 26, 31, 32).

All functions take and return :class:`control.StateSpace`; discrete models carry ``dt = T``. Channel
names are kept.

- :func:`d2c_bilinear`: discrete -> continuous, inverse Tustin with the paper's balanced ``2/sqrt(T)``
  split of the input and output matrices (Eq. 26).
- :func:`c2d_bilinear`: continuous -> discrete, Tustin (Eq. 31), the exact inverse of Eq. 26.
- :func:`c2d_zoh`: continuous -> discrete, zero-order hold (Eq. 32), computed from the matrix exponential
  of the augmented matrix ``[[A, B], [0, 0]] T`` so that a singular ``A`` (an integrator) is fine.

The bilinear transforms give the same transfer function as ``control.c2d(sys, T, 'tustin')`` (in a
different state basis). Both Tustin and ZOH preserve the DC gain.
"""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np
import scipy.linalg

from .errors import ArgumentTypeError, FrequencyGridError, ModelError
from .grids import check_period

__all__ = ["d2c_bilinear", "c2d_bilinear", "c2d_zoh"]

# Reciprocal condition number below which (I + A) or (2/T I - A) is treated as singular.
_RCOND_SINGULAR = 1e3 * np.finfo(float).eps
# ... and below which the conversion warns that it loses about log10(1/rcond) digits.
_RCOND_WARN = 1e-8


def _check_model(model: Any, *, discrete: bool, func: str):
    import control

    if not isinstance(model, control.StateSpace):
        if isinstance(model, control.LTI):
            model = control.ss(model)
        else:
            raise ArgumentTypeError(f"{func}() expects a control.StateSpace, got {type(model).__name__}")
    if discrete:
        if not model.isdtime(strict=True):
            raise ModelError(
                f"{func}() expects a discrete-time model (dt = T > 0); this one is continuous (dt = 0). "
                "Use c2d_bilinear(model, T) or c2d_zoh(model, T) to discretise it"
            )
        if model.dt is True:
            raise FrequencyGridError(
                f"{func}() needs the sampling period: the model has dt=True (unspecified); build it with "
                "dt=T, e.g. control.ss(A, B, C, D, T)"
            )
    elif not model.isctime(strict=True):
        raise ModelError(
            f"{func}() expects a continuous-time model (dt = 0); this one is discrete (dt = {model.dt}). "
            "Use d2c_bilinear(model) first"
        )
    for name in "ABCD":
        if not np.all(np.isfinite(np.asarray(getattr(model, name), dtype=float))):
            raise ModelError(f"{func}(): the model's {name} contains NaN or inf; repair the model first")
    return model


def _check_stable_poles_kept(A_c: np.ndarray, A_d: np.ndarray, T: float, margin_sq, func: str) -> None:
    """Refuse a period at which a stable continuous pole lands on or outside the unit circle, and warn when its
    distance to the circle keeps fewer than 8 digits.

    ``margin_sq(s)`` is ``1 - |z|^2`` of the discrete image ``z`` of each continuous pole ``s``, computed without
    cancellation (Tustin: ``-2 Re(s) T / |1 - s T / 2|^2``; ZOH: ``-expm1(2 Re(s) T)``); the discrete matrix
    holds it to about ``eps`` (its norm is about 1), so ``log10(margin / eps)`` digits of the pole's decay rate
    survive, and none when the computed discrete pole is not inside the circle.
    """
    if A_c.size == 0:
        return
    s = np.linalg.eigvals(A_c)
    stable = s.real < 0
    if not stable.any():
        return
    z = np.linalg.eigvals(A_d)
    with np.errstate(all="ignore"):
        margin = margin_sq(s[stable])
    mags = np.abs(s[stable])
    lo, hi = float(mags.min()), float(mags.max())
    eps = np.finfo(float).eps
    # a stable pole is lost when more discrete poles lie on or outside the circle than the model has unstable
    # continuous ones (an unstable model's own poles stay outside, as they should: the paper's plain ROMs)
    lost = (int(np.count_nonzero(np.abs(z) >= 1.0)) > int(np.count_nonzero(~stable))) or (margin.min() <= 4 * eps)
    i = int(np.argmin(margin))
    pole = s[stable][i]
    side = "small" if abs(pole) * T < 2.0 else "large"
    advice = (f"choose T with 2/T among the model's pole magnitudes ({lo:.3g} .. {hi:.3g}), e.g. "
              f"T = {2.0 / np.sqrt(lo * hi):.3g}" if lo > 0 else "choose a larger T")
    pole_txt = f"{pole.real:.6g}" + (f" {'+' if pole.imag >= 0 else '-'} {abs(pole.imag):.6g}j" if pole.imag else "")
    if lost:
        raise ModelError(
            f"{func}(): at T = {T:.6g} the stable pole s = {pole_txt} lands on the unit circle (1 - |z|^2 = "
            f"{margin[i]:.3g}, below round-off): T is too {side} for this model, and the discrete model would not "
            f"decay; {advice}")
    digits = np.log10(margin[i] / eps)
    if digits < 8:
        warnings.warn(
            f"{func}(): at T = {T:.6g} the discrete model keeps about {digits:.0f} digits of the decay of the pole "
            f"s = {pole_txt} (1 - |z|^2 = {margin[i]:.3g}): T is too {side} for it; {advice}",
            RuntimeWarning, stacklevel=3)


def _matrices(model) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    return (np.asarray(model.A, dtype=float), np.asarray(model.B, dtype=float),
            np.asarray(model.C, dtype=float), np.asarray(model.D, dtype=float))


def _lu_or_raise(Mtx: np.ndarray, message: str, warn_message: str | None = None):
    """LU factors of ``Mtx``; ``ModelError(message)`` when it is (numerically) singular, a RuntimeWarning
    (``warn_message``) when it is merely ill-conditioned."""
    n = Mtx.shape[0]
    if n == 0:
        return None
    rc = 1.0 / np.linalg.cond(Mtx) if np.all(np.isfinite(Mtx)) else 0.0
    if not np.isfinite(rc) or rc < _RCOND_SINGULAR:
        raise ModelError(message + f" (reciprocal condition number {rc:.2e})")
    if warn_message and rc < _RCOND_WARN:
        warnings.warn(warn_message + f" (reciprocal condition number {rc:.2e}: about {-np.log10(rc):.0f} digits "
                      "lost)", RuntimeWarning, stacklevel=3)
    return scipy.linalg.lu_factor(Mtx)


def _solve(lu, rhs: np.ndarray, trans: int = 0) -> np.ndarray:
    if lu is None:
        return rhs
    return scipy.linalg.lu_solve(lu, rhs, trans=trans)


def _build(A, B, C, D, dt, model):
    import control

    return control.ss(A, B, C, D, dt, inputs=list(model.input_labels), outputs=list(model.output_labels))


def d2c_bilinear(model):
    """Discrete -> continuous by the inverse bilinear (Tustin) map, paper Eq. 26.

    With ``Ahat, Bhat, Chat, Dhat`` the discrete matrices and ``T = model.dt``::

        A = (2/T) (I + Ahat)^-1 (Ahat - I)
        B = (2/sqrt(T)) (I + Ahat)^-1 Bhat
        C = (2/sqrt(T)) Chat (I + Ahat)^-1
        D = Dhat - Chat (I + Ahat)^-1 Bhat

    so that ``G_c(s) = G_d(z)`` with ``s = (2/T)(z - 1)/(z + 1)``; in particular
    ``G_c(j omega) = G_d(exp(j omega_d))`` with ``omega = (2/T) tan(omega_d / 2)``.

    Parameters
    ----------
    model : control.StateSpace
        Discrete model with ``dt = T > 0``.

    Returns
    -------
    control.StateSpace
        Continuous model (``dt = 0``), time in the same units as ``T``.

    Raises
    ------
    TypeError
        ``model`` is not a python-control LTI model.
    ModelError
        Continuous model given, NaN or inf in its matrices, or ``I + Ahat`` singular (a pole at ``z = -1``,
        which maps to ``s = inf``).
        A merely ill-conditioned ``I + Ahat`` (reciprocal condition number below 1e-8) gives a
        ``RuntimeWarning``.
    FrequencyGridError
        ``dt = True`` (sampling period unspecified).
    """
    model = _check_model(model, discrete=True, func="d2c_bilinear")
    T = check_period(model.dt)
    Ad, Bd, Cd, Dd = _matrices(model)
    n = Ad.shape[0]
    I = np.eye(n)
    lu = _lu_or_raise(
        I + Ad,
        "d2c_bilinear(): I + A is singular, the discrete model has a pole at z = -1 (omega = infinity) that the "
        "bilinear map cannot take to a finite continuous pole; move or remove that pole (e.g. refit with a "
        "different order)",
        "d2c_bilinear(): I + A is ill-conditioned: a pole near z = -1 maps to a very fast continuous pole and the "
        "continuous matrices (D = Dhat - C (I + A)^-1 B in particular) are inaccurate",
    )
    A = (2.0 / T) * _solve(lu, Ad - I)
    B = (2.0 / math.sqrt(T)) * _solve(lu, Bd)
    CinvT = _solve(lu, Cd.T, trans=1).T if n else Cd  # Chat (I + Ahat)^-1
    C = (2.0 / math.sqrt(T)) * CinvT
    D = Dd - CinvT @ Bd
    return _build(A, B, C, D, 0, model)


def c2d_bilinear(model, T: float):
    """Continuous -> discrete by the bilinear (Tustin) map, paper Eq. 31 (the inverse of Eq. 26)::

        Ahat = (2/T I + A) (2/T I - A)^-1
        Bhat = (2/sqrt(T)) (2/T I - A)^-1 B
        Chat = (2/sqrt(T)) C (2/T I - A)^-1
        Dhat = D + C (2/T I - A)^-1 B

    Parameters
    ----------
    model : control.StateSpace
        Continuous model (``dt = 0``).
    T : float
        Sampling period, ``> 0``, in the time units of the continuous model (convective time c / U_inf for the
        project's aerodynamic models).

    Returns
    -------
    control.StateSpace
        Discrete model with ``dt = T``.

    Raises
    ------
    TypeError
        ``model`` is not a python-control LTI model.
    ModelError
        Discrete model given, NaN or inf in its matrices, ``2/T I - A`` singular (a continuous pole at
        ``s = 2/T``, which maps to ``z = inf``), or a ``T`` so small or large that a stable continuous pole lands
        on the unit circle (``T = 1e-300`` sent ``s = -1`` to ``z = 1`` silently); change ``T``.
    FrequencyGridError
        ``T <= 0`` or not finite.

    Warns
    -----
    RuntimeWarning
        The discrete model keeps fewer than 8 digits of a stable pole's decay (``1 - |z|^2`` below
        ``1e8`` machine epsilons).
    """
    model = _check_model(model, discrete=False, func="c2d_bilinear")
    T = check_period(T)
    A, B, C, D = _matrices(model)
    n = A.shape[0]
    I = np.eye(n)
    W = (2.0 / T) * I - A
    lu = _lu_or_raise(
        W,
        f"c2d_bilinear(): 2/T I - A is singular, the model has a pole at s = 2/T = {2.0 / T:.6g} that the "
        "bilinear map sends to z = infinity; choose a different T",
    )
    Ad = _solve(lu, ((2.0 / T) * I + A).T, trans=1).T if n else A  # (2/T I + A)(2/T I - A)^-1
    Bd = (2.0 / math.sqrt(T)) * _solve(lu, B)
    CW = _solve(lu, C.T, trans=1).T if n else C  # C (2/T I - A)^-1
    Cd = (2.0 / math.sqrt(T)) * CW
    Dd = D + CW @ B
    _check_stable_poles_kept(A, Ad, T, lambda s: -2.0 * s.real * T / np.abs(1.0 - s * T / 2.0) ** 2,
                             "c2d_bilinear")
    return _build(Ad, Bd, Cd, Dd, T, model)


def c2d_zoh(model, T: float):
    """Continuous -> discrete by zero-order hold, paper Eq. 32::

        Ahat = exp(A T),  Bhat = int_0^T exp(A tau) d tau B,  Chat = C,  Dhat = D

    ``Ahat`` and ``Bhat`` are read from ``expm([[A, B], [0, 0]] T) = [[Ahat, Bhat], [0, I]]``; ``A`` is never
    inverted, so integrators (singular ``A``) are handled.

    Parameters
    ----------
    model : control.StateSpace
        Continuous model (``dt = 0``).
    T : float
        Sampling period, ``> 0``, in the time units of the continuous model (convective time c / U_inf for the
        project's aerodynamic models).

    Returns
    -------
    control.StateSpace
        Discrete model with ``dt = T``.

    Raises
    ------
    TypeError
        ``model`` is not a python-control LTI model.
    ModelError
        Discrete model given, NaN or inf in its matrices, a ``T`` so small that a stable continuous pole
        lands on the unit circle (``exp(s T)`` rounds to modulus 1), or so large that ``exp(A T)`` overflows.
    FrequencyGridError
        ``T <= 0`` or not finite.

    Warns
    -----
    RuntimeWarning
        The discrete model keeps fewer than 8 digits of a stable pole's decay.
    """
    model = _check_model(model, discrete=False, func="c2d_zoh")
    T = check_period(T)
    A, B, C, D = _matrices(model)
    n, m = B.shape
    aug = np.zeros((n + m, n + m))
    aug[:n, :n] = A * T
    aug[:n, n:] = B * T
    with np.errstate(over="ignore", invalid="ignore"):
        E = scipy.linalg.expm(aug)
    if not np.all(np.isfinite(E)):   # exp(1000) for s = +1 at T = 1e3: numpy's overflow warning before
        raise ModelError(f"c2d_zoh(): exp(A T) overflows at T = {T:.6g} (the model's fastest growth rate times T "
                         "exceeds about 700); the discrete model is not representable: choose a smaller T")
    _check_stable_poles_kept(A, E[:n, :n], T, lambda s: -np.expm1(2.0 * s.real * T), "c2d_zoh")
    return _build(E[:n, :n], E[:n, n:], C, D, T, model)
