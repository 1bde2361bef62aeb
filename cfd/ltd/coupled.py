"""Coupled linear time marching: the linearised Euler equations and a two-degree-of-freedom structure in one
implicit BDF2 step (monolithic, no sub-iteration).

The structure moves the whole grid rigidly (``cfd.motion``): plunge ``h`` (chords, up) of the point
``(pivot, 0)`` and pitch ``alpha`` (radians, nose up) about it. Its equations, in convective time ``s = t U / c``
(``' = d/ds``), with nondimensional matrices given by the caller::

    M x'' + D x' + K x = L y,      x = [h, alpha],      y = [Cl, Cm_pivot]

``Cm_pivot = Cm + (pivot - 1/4) Cl`` is the moment about the pivot (the solver's ``Cm`` is about the quarter
chord). The fluid is the linear system of ``cfd.ltd`` with the motion's forcing (``cfd.motion``)::

    V dq/dt + J q + b_gust(t) + B0 x + B1 x' = 0,      [Cl, Cm, Cd] = C q + Dx x     (t solver time, s / mach)

Typical section (``aeroelastic.section``: ``Ms q_tt + Ks q = (V^2 / (pi mu)) diag(1, 2) y`` in
``tau = omega_alpha t``, speed index ``V = U / (b omega_alpha)``): since ``s = (V / 2) tau``,

    M = Ms = [[2, -x_alpha], [-2 x_alpha, r_alpha2]],   K = (4 / V^2) Ks = (4 / V^2) diag(2 omega_ratio^2, r_alpha2),
    L = (4 / (pi mu)) diag(1, 2),   pivot = (1 + a) / 2,

so the speed index enters through ``K`` only (the Mach number stays that of the linearisation: a change of
``omega_alpha`` or of the air density at fixed flow, as in the frequency-domain coupling of ``aeroelastic``).

The step
--------
BDF2 for the fluid (as ``cfd.ltd``) and for the first-order structural system ``x' = v``,
``M v' + D v + K x = L y``, all at the new time level ``n + 1``::

    (3 V / (2 h) + J) q = V (4 q^n - q^{n-1}) / (2 h) - b_gust^{n+1} - B0 x - B1 v
    3 x / (2 dt) - v = (4 x^n - x^{n-1}) / (2 dt)
    (3 M / (2 dt) + D) v + K x - L P (C q + Dx x) = M (4 v^n - v^{n-1}) / (2 dt)

(``h = dt / mach``; ``P`` picks ``[Cl, Cm_pivot]`` from ``[Cl, Cm, Cd]``). The structural rate ``v`` is therefore the
BDF2 difference of ``x``, the same formula by which ``cfd.ltd_response`` differentiates a prescribed motion: the
fluid side of this march is exactly ``cfd.ltd_response`` driven by the computed ``x`` (tested to round-off).
The coupled step is solved exactly by block elimination: with the factorised fluid matrix ``A`` and the four
columns ``Z = A^-1 [B0, B1]`` (computed once), ``q = q* - Z z`` where ``q* = A^-1 (rhs without the motion)``
and ``z = [x, v]`` solves a constant 4 x 4 system (the structure plus the instantaneous aerodynamic response
``-C Z + [Dx, 0]``, which holds the apparent mass). Each step costs one fluid back-substitution, as a rigid
march. No sub-iterations and no added-mass instability: the scheme is the fully implicit BDF2 of the coupled
system (A-stable for the coupled linear system).

Start: everything at rest before ``s = 0`` (``q = 0``, ``x = v = 0`` at ``s = -dt`` and ``0``), as ``cfd.ltd``.
"""

from dataclasses import dataclass

import numpy as np

from ..checks import real_array
from ..gust import face_gust
from ..frequencies import check_pivot, check_x_ref
from ..linear import LinearError, check_gust_method, check_linear_system
from . import check_march
from ..motion import motion_forcing

__all__ = ["CoupledHistory", "coupled_ltd", "pivot_load_matrix"]


@dataclass(frozen=True, eq=False)
class CoupledHistory:
    """Time history of the coupled march (perturbations about the steady state; arrays read-only).

    Attributes
    ----------
    t : ndarray, shape (n + 1,)
        Convective time ``s = t U / c``, ``0, dt, ..., t_end``.
    u : ndarray, shape (n + 1,)
        Gust input ``v_g(x_ref, s) / U`` (dimensionless: the tangent of the local gust angle).
    h : ndarray, shape (n + 1,)
        Plunge of the pivot, chords, up.
    alpha : ndarray, shape (n + 1,)
        Pitch about the pivot, rad, nose up.
    h_rate, alpha_rate : ndarray, shape (n + 1,)
        ``dh/ds`` and ``d alpha/ds`` (per convective time unit): the BDF2 differences of ``h`` and ``alpha``.
    cl : ndarray, shape (n + 1,)
        Lift coefficient (up, normal to the undisturbed free stream).
    cm : ndarray, shape (n + 1,)
        Moment coefficient about the pivot, nose up (``cm_quarter + (pivot - 1/4) cl``).
    cm_quarter : ndarray, shape (n + 1,)
        Moment coefficient about the quarter chord (the solver's ``Cm``).
    cd : ndarray, shape (n + 1,)
        Pressure drag coefficient.
    method : str
        Gust method, ``"svm"`` or ``"fvm"``.
    dt : float
        Convective time step.
    pivot : float
        Elastic axis, chords from the leading edge.
    q : ndarray, shape (4N,)
        Final fluid state (solver units).
    """

    t: np.ndarray
    u: np.ndarray
    h: np.ndarray
    alpha: np.ndarray
    h_rate: np.ndarray
    alpha_rate: np.ndarray
    cl: np.ndarray
    cm: np.ndarray
    cm_quarter: np.ndarray
    cd: np.ndarray
    method: str
    dt: float
    pivot: float
    q: np.ndarray


def pivot_load_matrix(pivot):
    """``P`` with ``[Cl, Cm_pivot] = P [Cl, Cm, Cd]`` (``Cm`` about the quarter chord), shape (2, 3).

    ``Cm_pivot = Cm + (pivot - 1/4) Cl``: a lift ``L`` (up) at ``x`` gives the nose-up moment ``-L (x - x_0)``
    about ``x_0`` (``aeroelastic.axes`` derives the same identity).
    """
    pivot = check_pivot(pivot)
    return np.array([[1.0, 0.0, 0.0], [pivot - 0.25, 1.0, 0.0]])


def _matrix(name, a, required=True):
    """A real, finite (2, 2) matrix, or zeros when ``a`` is None and not required."""
    if a is None:
        if required:
            raise LinearError(f"{name} is required: a (2, 2) array for x = [h, alpha] (nondimensional, see "
                              "cfd.ltd.coupled)")
        return np.zeros((2, 2))
    m = real_array(a)   # None for text, and for complex (it lost its imaginary part with only a ComplexWarning)
    if m is None:
        raise LinearError(f"{name} must be a real (2, 2) array for x = [h, alpha]; got {a!r}")
    if m.shape != (2, 2):
        raise LinearError(f"{name} has shape {m.shape}; it must be (2, 2), rows and columns [h, alpha]")
    if not np.all(np.isfinite(m)):
        raise LinearError(f"{name} holds NaN or infinite values; for the rigid (infinite mass) limit give load=0")
    return m


def _mass(a):
    """The mass matrix, checked by :func:`_matrix` and positive definite: its eigenvalues of positive real part
    (``trace > 0`` and ``det > 0`` for a 2 x 2; for a symmetric matrix exactly the Cholesky test). The typical
    section's ``[[2, -x_alpha], [-2 x_alpha, r_alpha2]]`` is not symmetric (rows scaled by ``diag(1, 2)``) and passes
    exactly when ``r_alpha2 > x_alpha^2``, ``aeroelastic.TypicalSection``'s condition."""
    m = _matrix("mass", a)
    if not (np.trace(m) > 0.0 and np.linalg.det(m) > 0.0):   # a negative or zero mass or inertia marched as given
        ev = ", ".join(f"{v:.3g}" for v in np.linalg.eigvals(m))
        raise LinearError(f"mass must be positive definite (positive mass and inertia: eigenvalues of positive real "
                          f"part, e.g. the typical section's [[2, -x_alpha], [-2 x_alpha, r_alpha2]] with r_alpha2 > "
                          f"x_alpha^2); got eigenvalues {ev}. For the rigid (infinite mass) limit give load=0")
    return m


def coupled_ltd(lin, gust, dt, t_end, *, mass, stiffness, load, pivot, damping=None, method="svm", x_ref=0.0,
                max_phase_error=0.01):
    """Gust response of a section on springs: the linear CFD and the structure marched together (BDF2).

    Parameters
    ----------
    lin : LinearSystem
        From ``cfd.linearise``.
    gust : SineGust, OneMinusCosine or SharpEdged
        The gust (as ``cfd.ltd_response``).
    dt : float
        Convective time step (chords / U), ``> 0``.
    t_end : float
        Final convective time, ``>= dt``.
    mass : array_like, shape (2, 2)
        ``M`` of ``M x'' + D x' + K x = L y`` (see the module docstring), ``x = [h / c, alpha]``, ``'`` = d/ds;
        positive definite (eigenvalues of positive real part: a symmetric ``M`` must be SPD; the typical section's
        is not symmetric).
    stiffness : array_like, shape (2, 2)
        ``K``, per convective time squared relative to ``M`` (for the typical section ``(4 / V^2) Ks``).
    load : array_like, shape (2, 2)
        ``L``: generalised forces per unit ``[Cl, Cm_pivot]`` (for the typical section ``(4 / (pi mu)) diag(1, 2)``;
        zeros: the structure does not feel the air, the rigid limit).
    pivot : float
        Elastic axis, chords from the leading edge: ``h`` is the plunge of ``(pivot, 0)``, ``alpha`` the pitch about
        it, and the moment fed to the structure is about it.
    damping : array_like, shape (2, 2), optional
        ``D`` (structural damping), per convective time relative to ``M``; default zero.
    method : {"svm", "fvm"}
    x_ref : float
        Where the gust input ``u`` is measured (chords).
    max_phase_error : float
        Warn when the BDF2 phase-rate error at the gust's frequency scale exceeds this (``cfd.ltd``).

    Returns
    -------
    CoupledHistory

    Raises
    ------
    LinearError
        Not a gust, bad ``dt`` or ``t_end`` (more than ``cfd.ltd.MAX_STEPS`` steps or beyond ``cfd.ltd.MAX_TIME``
        included), a gust that passes in fewer than ``cfd.gust.MIN_GUST_STEPS`` steps, unknown method, a matrix that is
        not a finite (2, 2) array, a ``mass`` that is not positive definite (negative or zero), a non-finite pivot or
        ``x_ref``, a singular coupled step (e.g. a damping of ``-1.5 mass / dt`` with ``stiffness`` and ``load`` zero),
        or ``lin`` not a ``LinearSystem``.

    Notes
    -----
    Cost: one factorisation and four back-substitutions to set up, then one back-substitution, a gust forcing
    and a 4 x 4 product per step (as ``cfd.ltd_response``).
    """
    check_linear_system(lin)
    check_gust_method(method)
    x_ref = check_x_ref(x_ref)
    dt, t_end = check_march(gust, dt, t_end, max_phase_error, x_ref)
    pivot = check_pivot(pivot)
    M = _mass(mass)
    K = _matrix("stiffness", stiffness)
    L = _matrix("load", load)
    D = _matrix("damping", damping, required=False)

    n = int(round(t_end / dt))
    t = dt * np.arange(n + 1)
    hs = lin.to_solver_time(dt)
    V = lin.V
    solve = lin.solver(1.5 * V / hs)
    forcings = [motion_forcing(lin, "plunge"), motion_forcing(lin, "pitch", pivot)]
    Z = solve(np.stack([f.b0 for f in forcings] + [f.b1 for f in forcings], axis=1))   # (4N, 4): A^-1 [B0, B1]
    Dx = np.stack([f.d for f in forcings], axis=1)                                       # (3, 2)
    E = -lin.C @ Z                                                                        # (3, 4) loads per z
    E[:, :2] += Dx
    P = pivot_load_matrix(pivot)
    I2 = np.eye(2)
    S = np.block([[1.5 / dt * I2, -I2], [K, 1.5 / dt * M + D]])
    S[2:] -= L @ P @ E
    if not np.all(np.isfinite(S)) or np.linalg.cond(S) > 1e14:
        raise LinearError("the coupled step matrix is singular: check that mass (with the apparent mass of the air) "
                          "is invertible, or give load=0 for the rigid limit with an invertible mass")
    S_inv = np.linalg.inv(S)
    LPC = L @ P @ lin.C                                                                  # (2, 4N)

    q_prev = np.zeros(lin.n)
    q = np.zeros(lin.n)
    z_prev = np.zeros(4)
    z = np.zeros(4)
    Zs = np.zeros((n + 1, 4))
    Y = np.zeros((n + 1, 3))
    for k in range(1, n + 1):   # one back-substitution and a 4 x 4 product per step
        gi, gj = face_gust(lin.grid, gust, t[k])
        q_star = solve(V * (4.0 * q - q_prev) / (2.0 * hs) - lin.forcing(gi, gj, method))
        r = np.concatenate([(4.0 * z[:2] - z_prev[:2]) / (2.0 * dt),
                            M @ (4.0 * z[2:] - z_prev[2:]) / (2.0 * dt) + LPC @ q_star])
        z_prev, z = z, S_inv @ r
        q_prev, q = q, q_star - Z @ z
        Zs[k] = z
        Y[k] = lin.C @ q + Dx @ z[:2]
    cm_pivot = Y[:, 1] + (pivot - 0.25) * Y[:, 0]
    arrays = [t, gust.input(t, x_ref), Zs[:, 0], Zs[:, 1], Zs[:, 2], Zs[:, 3], Y[:, 0], cm_pivot, Y[:, 1], Y[:, 2], q]
    arrays = [np.ascontiguousarray(a, dtype=float) for a in arrays]
    for a in arrays:
        a.setflags(write=False)
    return CoupledHistory(t=arrays[0], u=arrays[1], h=arrays[2], alpha=arrays[3], h_rate=arrays[4],
                          alpha_rate=arrays[5], cl=arrays[6], cm=arrays[7], cm_quarter=arrays[8], cd=arrays[9],
                          method=method, dt=dt, pivot=pivot, q=arrays[10])
