"""Coupling the typical section with the fitted aerodynamic model: one LTI system per speed.

Time scaling. The aerodynamic model lives in convective time ``s = t U / c``; the structure in
``tau = omega_alpha t``. With the speed index ``V = U / (b omega_alpha)`` and ``c = 2 b``::

    s = (V / 2) tau,    d/ds = (2 / V) d/dtau

so a continuous aerodynamic state-space ``(A, B, C, D)`` in ``s`` is ``((V/2) A, (V/2) B, C, D)`` in ``tau``,
and the polynomial part reads ``M0 q + (2/V) M1 q' + (4/V^2) M2 q''`` (``'`` = d/dtau).

Blocks (python-control):

- structure ``S``: inputs ``[Cl, Cm]``, states ``[h, alpha, h', alpha']``, outputs
  ``[h, alpha, h', alpha', h'', alpha'', Cl, Cm]`` with
  ``q'' = Ms^-1 (V^2 diag(1, 2) / (pi mu) [Cl, Cm] - Ks q - Ds q')`` (``Ds`` the structural damping,
  :attr:`TypicalSection.damping_matrix`, zero by default)
  (see :mod:`aeroelastic.section`) and the loads passed through;
- motion aerodynamics ``Am``: inputs ``[h, alpha, h', alpha', h'', alpha'']`` (and zero columns for the loads),
  outputs ``[Cl, Cm]``;
- optional gust aerodynamics ``Ag``: input ``gust``, outputs ``[Cl, Cm]``.

``control.feedback(S, Am, sign=+1)`` closes the loop (the apparent-mass feedthrough makes it an algebraic loop,
which ``feedback`` solves exactly; ``control.interconnect`` refuses algebraic loops), and
``control.series(Ag, closed)`` adds the gust.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .errors import AeroModelError, SpeedError
from .fit import MotionModel, fit_motion
from .section import TypicalSection, check_section

__all__ = ["coupled_model", "state_matrix", "as_motion_model", "check_speed", "check_axis", "data_axis", "STATE_OUTPUTS",
           "FIT_OPTIONS", "MAX_SPEED"]

STATE_OUTPUTS = ["plunge", "pitch", "plunge_rate", "pitch_rate", "plunge_acc", "pitch_acc"]
FIT_OPTIONS = ("gust_order", "T", "optimise", "poles")
"""Keyword options of :func:`aeroelastic.fit_motion` that :func:`as_motion_model` (``flutter``, ``gust_response``)
passes on."""


MAX_SPEED = 1e6
"""Largest speed index ``U / (b omega_alpha)`` :func:`check_speed` accepts: far above any section's flutter speed
(of the order of ``sqrt(mu)``); at 1e200 the state matrix overflowed (Python's OverflowError)."""


def check_speed(speed: Any) -> float:
    """A speed index checked: a positive, finite number.

    Parameters
    ----------
    speed : any
        The speed index ``U / (b omega_alpha)`` (dimensionless).

    Returns
    -------
    float

    Raises
    ------
    SpeedError
        Not a number (a bool included), not finite, not positive, or above :data:`MAX_SPEED`.
    """
    try:
        if isinstance(speed, (bool, np.bool_)):
            raise TypeError
        V = float(speed)
    except (TypeError, ValueError):
        raise SpeedError(f"speed index U/(b omega_alpha) must be a number, got {speed!r}") from None
    if V > MAX_SPEED:
        raise SpeedError(f"speed index U/(b omega_alpha) = {V:g} is above MAX_SPEED = {MAX_SPEED:g}: flutter speed "
                         "indices are of the order of sqrt(mu) (mu = 1e4 gives about 100); check the units (U / (b "
                         "omega_alpha), b the semichord)")
    if not math.isfinite(V) or V <= 0:
        raise SpeedError(
            f"speed index U/(b omega_alpha) must be positive and finite, got {speed!r} (the aerodynamic "
            "coefficients are per dynamic pressure, undefined at zero speed; use a small speed for the still-air limit)"
        )
    return V


def data_axis(aero: Any) -> float | None:
    """The pitch pivot and moment axis (chords from the leading edge) that data say they are about, or None.

    Read from ``aero.metadata``: ``"axis"`` (set by :func:`aeroelastic.change_axes`) or ``"a"`` (semichords aft of
    mid-chord, set by :mod:`aeroelastic.theodorsen`'s data). A :class:`MotionModel` carries no axis: None.
    """
    from collections.abc import Mapping

    md = getattr(aero, "metadata", None)
    if not isinstance(md, Mapping):
        return None
    try:
        if "axis" in md:
            return float(md["axis"])
        if "a" in md:
            return 0.5 * (1.0 + float(md["a"]))
    except (TypeError, ValueError):
        return None
    return None


def check_axis(aero: Any, section: TypicalSection) -> None:
    """:class:`AeroModelError` when data say they are about another axis than ``section.elastic_axis``.

    The coupled equations take pitch and ``Cm`` about the elastic axis; data about another axis (e.g. the
    quarter chord while ``a = -0.2``) would give a wrong flutter speed without a word.
    """
    x = data_axis(aero)
    if x is not None and abs(x - section.elastic_axis) > 1e-9:
        raise AeroModelError(
            f"the data are about the axis {x:.6g} chords from the leading edge but the section's elastic axis is at "
            f"{section.elastic_axis:.6g} (a = {section.a:g}); bring the data to it with "
            "aeroelastic.to_elastic_axis(frf, section) (or change_axes) first")


def as_motion_model(aero: Any, order: int = 4, **fit_kw) -> MotionModel:
    """Return ``aero`` if it is a :class:`MotionModel`, else fit it with :func:`fit_motion`.

    Raises :class:`AeroModelError` for ``aero`` of another type, or a keyword option not in :data:`FIT_OPTIONS`
    (whatever ``aero`` is, so that a misspelled option is never silently ignored).
    """
    unknown = sorted(set(fit_kw) - set(FIT_OPTIONS))
    if unknown:
        raise AeroModelError(f"unknown option(s) {unknown}: the fit options (aeroelastic.fit_motion, used when aero "
                             f"is frequency-response data) are {FIT_OPTIONS}; check the spelling")
    if isinstance(aero, MotionModel):
        return aero
    import sysid

    if isinstance(aero, sysid.FrequencyResponse):
        return fit_motion(aero, order, **fit_kw)
    raise AeroModelError(
        f"aero must be a sysid.FrequencyResponse (inputs plunge, pitch[, gust]; outputs Cl, Cm about the elastic "
        f"axis) or an aeroelastic.MotionModel, got {type(aero).__name__}"
    )


def coupled_model(aero: Any, section: TypicalSection, speed: float, *, gust: bool | None = None):
    """The aeroelastic section at one speed as one continuous state-space model.

    Parameters
    ----------
    aero : MotionModel or sysid.FrequencyResponse
        Aerodynamic model (fitted with :func:`fit_motion` if data are given).
    section : TypicalSection
    speed : float
        Speed index ``V = U / (b omega_alpha) > 0``.
    gust : bool, optional
        Include the gust input (default: when the model has one).

    Returns
    -------
    control.StateSpace
        Continuous, time ``tau = omega_alpha t`` (eigenvalues in units of ``omega_alpha``). Inputs ``["gust"]``
        (or none); outputs ``["plunge", "pitch", "plunge_rate", "pitch_rate", "plunge_acc", "pitch_acc", "Cl",
        "Cm"]`` (``h / c`` up, rad, their ``tau`` derivatives, coefficients with ``Cm`` about the elastic axis).
        States: structure ``[h, alpha, h', alpha']``, then the lag states, then the gust states.

    Raises
    ------
    SpeedError
        ``speed`` not positive and finite.
    AeroModelError
        ``gust=True`` for a model without gust input, or ``gust`` not a bool or None.
    SectionError
        ``section`` not a :class:`TypicalSection`.
    """
    import control

    check_section(section)
    check_axis(aero, section)
    if not isinstance(gust, (bool, np.bool_, type(None))):
        raise AeroModelError(f"gust must be True, False or None (default: when the model has a gust input); got "
                             f"{gust!r}")
    V = check_speed(speed)
    model = as_motion_model(aero)
    if gust is None:
        gust = model.has_gust
    if gust and not model.has_gust:
        raise AeroModelError("gust=True but the aerodynamic model has no gust input; fit data with a 'gust' input")

    Ms, Ks, Lm, Ds = section.mass_matrix, section.stiffness_matrix, section.load_matrix, section.damping_matrix
    Mi = np.linalg.inv(Ms)
    Z2, I2 = np.zeros((2, 2)), np.eye(2)
    # structure: states [q, q'], inputs [Cl, Cm]
    A_s = np.block([[Z2, I2], [-Mi @ Ks, -Mi @ Ds]])
    B_s = np.vstack([Z2, V**2 * Mi @ Lm])
    C_s = np.vstack([np.hstack([I2, Z2]), np.hstack([Z2, I2]), np.hstack([-Mi @ Ks, -Mi @ Ds]), np.zeros((2, 4))])
    D_s = np.vstack([Z2, Z2, V**2 * Mi @ Lm, I2])
    S = control.ss(A_s, B_s, C_s, D_s, inputs=["Cl", "Cm"], outputs=STATE_OUTPUTS + ["Cl", "Cm"],
                   states=["h", "alpha", "h'", "alpha'"])

    # motion aerodynamics in tau: lag part time-scaled, polynomial part as feedthrough on q, q', q''
    lag = model.lag_model()
    nl = lag.nstates
    A_a = 0.5 * V * np.asarray(lag.A)
    B_a = np.hstack([0.5 * V * np.asarray(lag.B), np.zeros((nl, 6))])
    C_a = np.asarray(lag.C)
    D_a = np.hstack([model.M0 + np.asarray(lag.D), (2.0 / V) * model.M1, (4.0 / V**2) * model.M2, Z2])
    Am = control.ss(A_a, B_a, C_a, D_a, inputs=STATE_OUTPUTS + ["Cl_in", "Cm_in"], outputs=["Cl", "Cm"],
                    states=[f"lag{j // 2}_{'ha'[j % 2]}" for j in range(nl)])
    closed = control.feedback(S, Am, sign=+1)
    names = STATE_OUTPUTS + ["Cl", "Cm"]
    if not gust:
        return control.ss(closed.A, np.zeros((closed.nstates, 0)), closed.C, np.zeros((8, 0)), outputs=names)
    g = model.gust
    Ag = control.ss(0.5 * V * np.asarray(g.A), 0.5 * V * np.asarray(g.B), np.asarray(g.C), np.asarray(g.D),
                    inputs=["gust"], outputs=["Cl", "Cm"])
    sys = control.series(Ag, closed)
    return control.ss(sys.A, sys.B, sys.C, sys.D, inputs=["gust"], outputs=names)


def state_matrix(aero: Any, section: TypicalSection, speed: float) -> np.ndarray:
    """State matrix of the gust-free coupled model in closed form (numpy only), for fast speed sweeps.

    Eliminating the algebraic loop by hand: with ``M0e = M0 + sum_j A_j`` and the lag part ``(A_l, B_l, C_l)``,

    ``(Ms - 4 Lm M2) q'' = (V^2 Lm M0e - Ks) q + (2 V Lm M1 - Ds) q' + V^2 Lm C_l x_l``,
    ``x_l' = (V / 2)(A_l x_l + B_l q)``,

    with ``Lm = diag(1, 2) / (pi mu)`` (:attr:`TypicalSection.load_matrix`). ``Ms - 4 Lm M2`` is the mass matrix
    with the apparent mass. Same states and eigenvalues as :func:`coupled_model` with ``gust=False`` (tested).

    Returns
    -------
    ndarray, shape (4 + 2 n_lags, 4 + 2 n_lags)
    """
    V = check_speed(speed)
    model = as_motion_model(aero)
    lag = model.lag_model()
    Al, Bl, Cl, Dl = (np.asarray(x) for x in (lag.A, lag.B, lag.C, lag.D))
    nl = Al.shape[0]
    Ms, Ks, Lm, Ds = section.mass_matrix, section.stiffness_matrix, section.load_matrix, section.damping_matrix
    Mt = Ms - 4.0 * Lm @ model.M2
    rhs = np.hstack([V**2 * Lm @ (model.M0 + Dl) - Ks, 2.0 * V * Lm @ model.M1 - Ds, V**2 * Lm @ Cl])
    A = np.zeros((4 + nl, 4 + nl))
    A[0:2, 2:4] = np.eye(2)
    A[2:4] = np.linalg.solve(Mt, rhs)
    A[4:, 0:2] = 0.5 * V * Bl
    A[4:, 4:] = 0.5 * V * Al
    return A
