"""Gust response of the flexible typical section (time histories from the coupled state-space model)."""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from sysid.arrays import read_only
from sysid.simulate import first_uneven_step

from .coupling import check_axis, check_speed, as_motion_model, coupled_model
from .errors import AeroModelError
from .fit import real_array
from .section import TypicalSection

__all__ = ["GustResponse", "gust_response", "simulate"]


@dataclass(frozen=True)
class GustResponse:
    """Time histories of the flexible section in a gust (all arrays shape (N,), read-only).

    Attributes
    ----------
    t : ndarray
        Convective time ``s = t U / c`` (the gust's time base).
    tau : ndarray
        Structural time ``omega_alpha t = 2 s / V``.
    u : ndarray
        Gust angle at the leading edge, ``v_g / U`` (rad).
    plunge : ndarray
        ``h / c``, positive up.
    pitch : ndarray
        ``alpha`` (rad), nose up about the elastic axis.
    Cl, Cm : ndarray
        Lift and moment coefficients (``Cm`` about the elastic axis, nose up), perturbations about the steady state.
    speed : float
        Speed index ``U / (b omega_alpha)``.
    """

    t: np.ndarray = field(repr=False)
    tau: np.ndarray = field(repr=False)
    u: np.ndarray = field(repr=False)
    plunge: np.ndarray = field(repr=False)
    pitch: np.ndarray = field(repr=False)
    Cl: np.ndarray = field(repr=False)
    Cm: np.ndarray = field(repr=False)
    speed: float = float("nan")



def _gust_history(gust: Any, t: Any):
    if t is None:
        if isinstance(gust, tuple) and len(gust) == 2:
            t, u = gust
        elif hasattr(gust, "t") and hasattr(gust, "u"):
            t, u = gust.t, gust.u
        else:
            raise AeroModelError(
                "give the gust history as (t, u), an object with .t and .u (e.g. a cfd.ltd_response history), or "
                "u with t= (convective time s = t U / c, gust angle in rad)"
            )
    else:
        u = gust
    arrays = []
    for name, a in (("t", t), ("u", u)):
        a = real_array(name, a)
        if a.ndim != 1:
            raise AeroModelError(f"{name} must be 1-D (one gust history), got shape {a.shape}; give one history per "
                                 "call (or ravel it yourself if that is what you mean)")
        arrays.append(a)
    t, u = arrays
    if t.size != u.size or t.size < 2:
        raise AeroModelError(f"t and u must be 1-D of the same length >= 2, got {t.size} and {u.size}")
    if np.any(~np.isfinite(t)) or np.any(~np.isfinite(u)) or np.any(np.diff(t) <= 0):
        raise AeroModelError("t must be finite and strictly increasing, u finite")
    k = first_uneven_step(t)
    if k is not None:   # python-control's forced_response integrates on one step
        steps = np.diff(t)
        raise AeroModelError(f"t must be equispaced: t[{k + 1}] - t[{k}] = {steps[k]:.6g} but t[1] - t[0] = "
                             f"{steps[0]:.6g}; resample the gust on an equispaced grid (np.interp)")
    if not np.any(u):
        raise AeroModelError(f"the gust history u is zero at all {u.size} samples: there is nothing to respond to. A "
                             "gust shorter than the time step falls between the samples (cfd.ltd_response refuses "
                             "one shorter than cfd.gust.MIN_GUST_STEPS steps); sample it more finely")
    _warn_coarse_gust(t, u)
    return t, u


MIN_PEAK_SAMPLES = 3
"""Fewest samples at or above half the gust's peak ``|u|`` below which :func:`gust_response` warns: the input is
linear between samples, so a gust resolved by one or two samples is a triangle whose height and timing depend on
where the samples fall (a 1-cosine gust sampled four times per length has three)."""


def _warn_coarse_gust(t: np.ndarray, u: np.ndarray) -> None:
    """Warn when the gust's peak is resolved by fewer than :data:`MIN_PEAK_SAMPLES` samples."""
    a = np.abs(u)
    n = int(np.count_nonzero(a >= 0.5 * a.max()))
    if n < MIN_PEAK_SAMPLES:
        warnings.warn(f"the gust history reaches half its peak at {n} sample(s) only (step {t[1] - t[0]:.3g}): the "
                      "input is linear between samples, so the gust's shape and peak are lost; sample at least four "
                      "times per gust length", RuntimeWarning, stacklevel=4)


def simulate(sys, section: TypicalSection, speed: float, t: np.ndarray, u: np.ndarray) -> GustResponse:
    """Simulate a coupled model in ``tau`` (input ``gust``, outputs containing plunge, pitch, Cl, Cm) on
    convective ``t``.

    Zero initial state; the input is linear between samples (python-control's ``forced_response``).
    """
    import control

    V = check_speed(speed)
    tau = 2.0 * (t - t[0]) / V
    r = control.forced_response(sys, T=tau, U=u[None, :])
    names = list(sys.output_labels)
    y = np.asarray(r.outputs).reshape(len(names), -1)
    get = {n: y[names.index(n)] for n in ("plunge", "pitch", "Cl", "Cm")}
    return GustResponse(read_only(t), read_only(tau + 2.0 * t[0] / V), read_only(u), read_only(get["plunge"]),
                        read_only(get["pitch"]), read_only(get["Cl"]), read_only(get["Cm"]), float(V))


def gust_response(aero: Any, section: TypicalSection, speed: float, gust: Any, t: Any = None, *, order: int = 4,
                  **fit_kw) -> GustResponse:
    """Plunge, pitch, Cl and Cm histories of the flexible section in a gust.

    Parameters
    ----------
    aero : sysid.FrequencyResponse or MotionModel
        Inputs ``["gust", "plunge", "pitch"]``, outputs ``["Cl", "Cm"]`` (``Cm`` about the elastic axis), as for
        :func:`aeroelastic.flutter`; data are fitted with :func:`aeroelastic.fit_motion`.
    section : TypicalSection
    speed : float
        Speed index ``U / (b omega_alpha)`` (below flutter for a bounded response).
    gust : (t, u), object with ``.t`` and ``.u``, or array ``u``
        Gust angle ``u = v_g(x = 0) / U`` (rad), 1-D of shape (N,), at convective times ``t`` (``s = t U / c``),
        1-D of shape (N,), finite, increasing and equispaced, ``N >= 2``; the section starts at rest in its
        steady state at ``t[0]``.
    t : array_like, shape (N,), optional
        Convective times (``s = t U / c``) when ``gust`` is the array ``u``; then required.
    order : int
        Lag roots of the motion fit when ``aero`` is data (default 4).
    **fit_kw
        Options of :func:`aeroelastic.fit_motion` (``gust_order``, ``T``, ``optimise``, ``poles``: the names in
        :data:`aeroelastic.coupling.FIT_OPTIONS`), used when ``aero`` is data; checked against those names even
        when ``aero`` is a :class:`MotionModel` (then they are otherwise ignored).

    Returns
    -------
    GustResponse
        Histories of shape (N,) on the times ``t``.

    Raises
    ------
    AeroModelError
        ``aero`` neither a model nor data, the model has no gust input, the history is malformed or zero at every
        sample (a gust between the samples), or a fit option is not in :data:`aeroelastic.coupling.FIT_OPTIONS`.
    FitError
        Data that cannot be fitted (see :func:`aeroelastic.fit_motion`).
    SectionError
        ``section`` not a :class:`TypicalSection`.
    SpeedError
        ``speed`` not positive and finite.

    Warns
    -----
    RuntimeWarning
        The coupled section is unstable at ``speed`` (above its flutter or divergence speed): the history grows
        without bound, and the warning gives the growth rate. The gust reaches half its peak at fewer than
        :data:`MIN_PEAK_SAMPLES` samples. The step samples the section's fastest oscillation fewer than
        :data:`POINTS_PER_PERIOD` times.
    """
    check_axis(aero, section)
    model = as_motion_model(aero, order, **fit_kw)
    if not model.has_gust:
        raise AeroModelError("the aerodynamic model has no 'gust' input; give data with inputs ['gust', 'plunge', 'pitch']")
    tt, u = _gust_history(gust, t)
    sys = coupled_model(model, section, speed, gust=True)
    eig = np.linalg.eigvals(np.asarray(sys.A))
    growth = float(eig.real.max()) if eig.size else 0.0
    if growth > 1e-9 * max(1.0, float(np.abs(eig).max())):
        warnings.warn(f"the coupled section is unstable at speed {float(speed):g} (growth rate {growth:.3g} per unit "
                      "omega_alpha t): above its flutter or divergence speed, the gust response grows without bound",
                      RuntimeWarning, stacklevel=2)
    _warn_coarse_step(eig, float(speed), tt)
    return simulate(sys, section, speed, tt, u)


POINTS_PER_PERIOD = 10
"""Fewest samples per period of the section's fastest oscillation below which :func:`gust_response` warns: the
histories are its values at the samples only (a step of 2.5 chords, two per period at V = 1.5, missed the
pitch peak of a 10-chord gust by 23 %; a 20-chord step never sampled that gust)."""


def _warn_coarse_step(eig, speed: float, t: np.ndarray) -> None:
    """Warn when the time step samples the fastest oscillatory mode of the coupled system (eigenvalues ``eig`` in
    units of ``omega_alpha``) at fewer than :data:`POINTS_PER_PERIOD` points per period."""
    w = np.abs(np.asarray(eig).imag)
    w = w[w > 1e-9]
    if not w.size:
        return
    period = 2.0 * np.pi / w.max() * speed / 2.0   # convective time: s = tau V / 2
    dt = float(t[1] - t[0])
    if dt > period / POINTS_PER_PERIOD:
        warnings.warn(f"the time step {dt:.3g} (convective time) samples the section's fastest oscillation "
                      f"(period {period:.3g}) {period / dt:.2g} times per period; the histories hold their values at "
                      f"the samples only: use a step of at most {period / POINTS_PER_PERIOD:.3g}, and sample the gust "
                      "finely enough to resolve it", RuntimeWarning, stacklevel=3)
