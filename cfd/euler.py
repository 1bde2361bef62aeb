"""Residual of the 2-D Euler equations: cell-centred finite volumes with JST dissipation.

Semi-discrete form (per cell, ``area`` from ``cfd.mesh``)::

    area * dq/dt + R(q) = 0,   R = sum over faces of (F.S - d) - source

Convective flux
    Averaged fluxes, ``(F(q_L) + F(q_R)) / 2 . S``, in the moving-grid form of the paper (Eq. 3): mass,
    momentum and energy are convected with the relative normal velocity ``(u - w).S`` and the energy
    flux adds ``p u.S``; ``w`` is the face grid velocity (``face_velocity``; zero by default). At the
    wall the flux is pressure only: ``(0, p_w S, p_w w.S)`` with ``p_w`` from ``boundary.wall_pressure``.
JST dissipation (Jameson, Schmidt & Turkel 1981)
    ``d = lambda (eps2 (w_R - w_L) - eps4 (w_{R+1} - 3 w_R + 3 w_L - w_{L-1}))`` on
    ``w = (rho, rho u, rho v, rho H)`` (energy dissipated on rho H, which keeps total enthalpy
    constant in steady flow), with the pressure sensor
    ``nu = |p_+ - 2 p + p_-| / (p_+ + 2 p + p_-)`` per cell and direction,
    ``eps2 = k2 max(nu_L, nu_R)`` (the two cells of the face) and ``eps4 = max(0, k4 - eps2)``;
    ``lambda = (lambda_L + lambda_R) / 2``, ``lambda_X = |(u_X - w).S| + c_X |S|`` (scalar dissipation,
    no directional scaling). No dissipation crosses the wall. The stencil of ``R`` at a cell is the
    9-cell cross of radius 2 (through the wake cut where it applies).

Every operation is vectorised on the state padded with two ghost layers (``cfd.boundary``), and the
whole residual is complex-safe (``abs`` and ``max`` follow the real part) so that ``cfd.jacobian``
differentiates it by complex step; the state may carry leading batch axes.
"""

from dataclasses import dataclass

import numpy as np

from . import boundary as bc
from .checks import not_a_grid
from .errors import FlowConditionError, MeshError

__all__ = ["Scheme", "residual", "spectral_radius_sum", "check_state", "check_input"]


@dataclass(frozen=True)
class Scheme:
    """Numerical constants of the spatial scheme.

    Parameters
    ----------
    k2 : float
        Second-difference (shock) coefficient.
    k4 : float
        Fourth-difference (background) coefficient.
    vortex : bool
        Point-vortex far-field correction (Thomas & Salas). The circulation comes from the lift of the
        current state; ``cfd.jacobian`` holds it frozen (the far-field rows then miss a rank-one term).
    """

    k2: float = 0.5
    k4: float = 1.0 / 64.0
    vortex: bool = False

    def __post_init__(self):
        for name in ("k2", "k4"):
            k = getattr(self, name)
            if isinstance(k, (bool, np.bool_)) or not isinstance(k, (int, float, np.integer, np.floating)) or not (
                    np.isfinite(k) and k >= 0.0):
                raise FlowConditionError(f"Scheme.{name} must be a finite number >= 0 (default "
                                         f"{getattr(Scheme, name):g}); got {k!r}")
        if not isinstance(self.vortex, (bool, np.bool_)):
            raise FlowConditionError(f"Scheme.vortex must be True or False; got {self.vortex!r}")


DEFAULT_SCHEME = Scheme()


def check_state(grid, q, name="state"):
    """Raise :class:`MeshError` unless the last three axes of ``q`` are the grid's cells and 4 variables."""
    shape = grid.cell_shape + (4,)
    if np.shape(q)[-3:] != shape:
        raise MeshError(f"{name} has shape {np.shape(q)}; this grid needs (..., {shape[0]}, {shape[1]}, 4)")


def check_input(grid, q, flow, scheme, face_velocity, source):
    """The argument checks of :func:`residual` (shared by :func:`cfd.jacobian`): ``grid``, ``flow`` and ``scheme``
    of their types, ``q``, ``face_velocity`` and ``source`` of the grid's shapes (leading batch axes allowed);
    :class:`MeshError` or :class:`FlowConditionError` naming the argument."""
    if not hasattr(grid, "cell_shape") or not hasattr(grid, "si"):
        raise MeshError(not_a_grid(grid))
    if not hasattr(flow, "gamma") or not hasattr(flow, "q"):
        raise FlowConditionError(f"flow must be a cfd.FlowCondition(mach, alpha_deg); got {type(flow).__name__}")
    if not isinstance(scheme, Scheme):
        raise FlowConditionError(f"scheme must be a cfd.Scheme or None; got {type(scheme).__name__}")
    check_state(grid, q, "q")
    shape = grid.cell_shape + (4,)
    if face_velocity is not None:
        wi, wj = face_velocity
        ni, nj = grid.shape
        if np.shape(wi)[-3:] != (2, ni, nj - 1) or np.shape(wj)[-3:] != (2, ni - 1, nj):
            raise MeshError(
                f"face_velocity must be (wi, wj) with shapes (2, {ni}, {nj - 1}) and (2, {ni - 1}, {nj}); "
                f"got {np.shape(wi)} and {np.shape(wj)}"
            )
    if source is not None and np.shape(source)[-3:] != shape:
        raise MeshError(f"source has shape {np.shape(source)}; this grid needs {shape}")


def _flux(rho, u, v, p, rhoe, sx, sy, ws):
    """Moving-grid flux through a face with normal (sx, sy) and normal grid speed ws = w.S."""
    un = u * sx + v * sy
    vr = un - ws
    return rho * vr, rho * u * vr + p * sx, rho * v * vr + p * sy, rhoe * vr + p * un


def _direction_flux(P, p, c, sx, sy, wx, wy, scheme, axis):
    """Convective minus dissipative flux through the faces of one direction.

    ``P`` is the padded state (..., 4, a, b) already cut to the interior of the other direction, with
    the direction of interest on ``axis`` (-2 or -1) carrying two ghost layers at each end; ``p`` and
    ``c`` the matching pressure and speed of sound. Returns (..., 4, faces...) with n+1 faces.
    """
    n = P.shape[axis] - 4

    def sl(a, b):
        idx = [slice(None)] * P.ndim
        idx[axis] = slice(a, b)
        return tuple(idx)

    def sl3(a, b):
        idx = [slice(None)] * p.ndim
        idx[axis] = slice(a, b)
        return tuple(idx)

    rho = P[..., 0, :, :]
    u = P[..., 1, :, :] / rho
    v = P[..., 2, :, :] / rho
    rhoe = P[..., 3, :, :]
    L, R = sl3(1, n + 2), sl3(2, n + 3)
    ws = 0.0 if wx is None else wx * sx + wy * sy
    fl = _flux(rho[L], u[L], v[L], p[L], rhoe[L], sx, sy, ws)
    fr = _flux(rho[R], u[R], v[R], p[R], rhoe[R], sx, sy, ws)
    # Spectral radius of the face.
    smag = np.sqrt(sx * sx + sy * sy)
    lam = 0.5 * (
        bc.cabs(u[L] * sx + v[L] * sy - ws) + c[L] * smag + bc.cabs(u[R] * sx + v[R] * sy - ws) + c[R] * smag
    )
    # Pressure sensor on padded cells 1 .. n+2.
    nu = bc.cabs(p[sl3(2, n + 4)] - 2.0 * p[sl3(1, n + 3)] + p[sl3(0, n + 2)]) / (
        p[sl3(2, n + 4)] + 2.0 * p[sl3(1, n + 3)] + p[sl3(0, n + 2)]
    )
    eps2 = scheme.k2 * bc.cmax(nu[sl3(0, n + 1)], nu[sl3(1, n + 2)])
    eps4 = bc.cmax(np.zeros_like(eps2), scheme.k4 - eps2)
    # Dissipated variables: rho, rho u, rho v, rho H.
    w = [P[..., 0, :, :], P[..., 1, :, :], P[..., 2, :, :], rhoe + p]
    out = []
    for k in range(4):
        wk = w[k]
        d1 = wk[R] - wk[L]
        d3 = wk[sl3(3, n + 4)] - 3.0 * wk[R] + 3.0 * wk[L] - wk[sl3(0, n + 1)]
        out.append(0.5 * (fl[k] + fr[k]) - lam * (eps2 * d1 - eps4 * d3))
    return np.stack(out, axis=-3)


def pad(grid, W, flow, face_velocity=None, scheme=DEFAULT_SCHEME, circulation=None):
    """State padded with two ghost layers on each side.

    Parameters
    ----------
    grid : Grid
    W : ndarray, shape (..., 4, ni-1, nj-1)
        Component-first state.
    flow : FlowCondition
    face_velocity : (wi, wj) or None
    scheme : Scheme
    circulation : float or None
        Lift coefficient used by the vortex correction; computed from ``W`` (real part) if None.

    Returns
    -------
    P : ndarray, shape (..., 4, ni+3, nj+3)
    """
    g = flow.gamma
    NI, NJ = grid.cell_shape
    nw = grid.n_wake
    batch = W.shape[:-3]
    P = np.empty(batch + (4, NI + 4, NJ + 4), dtype=W.dtype)
    P[...] = flow.q[:, None, None]  # corners (never used) hold the free stream
    P[..., 2:-2, 2:-2] = W
    rho, u, v = W[..., 0, :, :], W[..., 1, :, :] / W[..., 0, :, :], W[..., 2, :, :] / W[..., 0, :, :]
    p = (g - 1.0) * (W[..., 3, :, :] - 0.5 * rho * (u * u + v * v))
    wi = wj = None
    if face_velocity is not None:
        wi, wj = face_velocity

    # j-min: wake cut and wall.
    P[..., 2:2 + nw, 1] = W[..., ::-1, 0][..., :nw]
    P[..., 2:2 + nw, 0] = W[..., ::-1, 1][..., :nw]
    P[..., NI + 2 - nw:NI + 2, 1] = W[..., ::-1, 0][..., NI - nw:]
    P[..., NI + 2 - nw:NI + 2, 0] = W[..., ::-1, 1][..., NI - nw:]
    wall = grid.wall
    s = grid.sj[:, wall, 0]
    n = s / np.sqrt((s * s).sum(0))
    wx = wy = 0.0
    if wj is not None:
        wx, wy = wj[..., 0, wall, 0], wj[..., 1, wall, 0]
    for layer, jc in ((1, 0), (0, 1)):
        P[..., 2 + nw:NI + 2 - nw, layer] = bc.wall_mirror(
            rho[..., wall, jc], u[..., wall, jc], v[..., wall, jc], p[..., wall, jc], n[0], n[1], wx, wy, g
        )

    # Far field: j-max, i-min, i-max.
    if scheme.vortex:
        if circulation is None:
            circulation = lift_coefficient(grid, p.real, flow)
    uf, vf = flow.velocity
    sides = (
        ("jmax", grid.sj[:, :, -1], None if wj is None else wj[..., :, :, -1]),
        ("imin", -grid.si[:, 0, :], None if wi is None else wi[..., :, 0, :]),
        ("imax", grid.si[:, -1, :], None if wi is None else wi[..., :, -1, :]),
    )
    for side, s, w in sides:
        n = s / np.sqrt((s * s).sum(0))
        if scheme.vortex:
            free = bc.vortex_free_stream(*_face_centres(grid, side), flow, circulation)
        else:
            free = (1.0, uf, vf, flow.p)
        wn = 0.0 if w is None else w[..., 0, :] * n[0] + w[..., 1, :] * n[1]
        if side == "jmax":
            take = (rho[..., :, -1], u[..., :, -1], v[..., :, -1], p[..., :, -1])
        elif side == "imin":
            take = (rho[..., 0, :], u[..., 0, :], v[..., 0, :], p[..., 0, :])
        else:
            take = (rho[..., -1, :], u[..., -1, :], v[..., -1, :], p[..., -1, :])
        state = bc.farfield_state(*take, n[0], n[1], free, wn, g)
        if side == "jmax":
            P[..., 2:NI + 2, NJ + 2] = state
            P[..., 2:NI + 2, NJ + 3] = state
        elif side == "imin":
            P[..., 0, 2:NJ + 2] = state
            P[..., 1, 2:NJ + 2] = state
        else:
            P[..., NI + 2, 2:NJ + 2] = state
            P[..., NI + 3, 2:NJ + 2] = state
    return P


def _face_centres(grid, side):
    if side == "jmax":
        x, y = grid.x[:, -1], grid.y[:, -1]
    elif side == "imin":
        x, y = grid.x[0, :], grid.y[0, :]
    else:
        x, y = grid.x[-1, :], grid.y[-1, :]
    return 0.5 * (x[1:] + x[:-1]), 0.5 * (y[1:] + y[:-1])


def lift_coefficient(grid, p, flow):
    """Lift coefficient of (real) cell pressures p (..., ni-1, nj-1); batch axes reduce to the first."""
    p = p.reshape((-1,) + p.shape[-2:])[0]
    pw = bc.wall_pressure(p[grid.wall, 0], p[grid.wall, 1])
    s = grid.sj[:, grid.wall, 0]
    fx, fy = -(pw - flow.p) @ s[0], -(pw - flow.p) @ s[1]
    a = flow.alpha
    return (-fx * np.sin(a) + fy * np.cos(a)) / flow.dynamic_pressure


def residual(grid, q, flow, *, face_velocity=None, source=None, scheme=None, circulation=None):
    """Euler residual ``R(q)``: net outward flux (convective + JST + boundary) minus sources.

    Parameters
    ----------
    grid : Grid
    q : ndarray, shape (..., ni-1, nj-1, 4)
        Conserved variables per cell (real or complex; leading axes are a batch).
    flow : FlowCondition
    face_velocity : tuple (wi, wj) or None
        Grid velocities at the faces, ``wi`` shape (..., 2, ni, nj-1), ``wj`` shape (..., 2, ni-1, nj),
        units of a_inf. None for a fixed grid.
    source : ndarray, shape (..., ni-1, nj-1, 4) or None
        Sources integrated over the cells (added to the right-hand side, i.e. subtracted from R).
    scheme : Scheme or None
        Dissipation constants and options; ``Scheme()`` by default.
    circulation : float or None
        Lift coefficient for the vortex far field (``scheme.vortex``); None: from ``q``.

    Returns
    -------
    R : ndarray, shape of ``q``
        Units of flux (a_inf times conserved variable times chord).

    Raises
    ------
    MeshError
        ``grid`` not a grid; ``q``, ``face_velocity`` or ``source`` of the wrong shape.
    FlowConditionError
        ``flow`` not a :class:`cfd.FlowCondition`, ``scheme`` not a :class:`Scheme`.

    Notes
    -----
    A kernel of the solvers, called at every iteration: a NaN in ``q`` gives NaN in ``R`` (the solvers test their
    states; :func:`cfd.jacobian` and :func:`cfd.solve_steady` refuse a non-finite one).
    """
    scheme = DEFAULT_SCHEME if scheme is None else scheme
    q = np.asarray(q)
    check_input(grid, q, flow, scheme, face_velocity, source)
    g = flow.gamma
    NI, NJ = grid.cell_shape
    W = np.moveaxis(q, -1, -3)
    P = pad(grid, W, flow, face_velocity, scheme, circulation)
    rho = P[..., 0, :, :]
    p = (g - 1.0) * (P[..., 3, :, :] - 0.5 * (P[..., 1, :, :] ** 2 + P[..., 2, :, :] ** 2) / rho)
    c = np.sqrt(g * p / rho)
    wi = wj = None
    if face_velocity is not None:
        wi, wj = face_velocity
    # i-direction: faces i = 0 .. ni-1 over interior rows.
    Fi = _direction_flux(
        P[..., :, 2:-2], p[..., :, 2:-2], c[..., :, 2:-2], grid.si[0], grid.si[1],
        None if wi is None else wi[..., 0, :, :], None if wi is None else wi[..., 1, :, :], scheme, -2,
    )
    Fj = _direction_flux(
        P[..., 2:-2, :], p[..., 2:-2, :], c[..., 2:-2, :], grid.sj[0], grid.sj[1],
        None if wj is None else wj[..., 0, :, :], None if wj is None else wj[..., 1, :, :], scheme, -1,
    )
    # Wall faces: pressure only, no dissipation.
    wall = grid.wall
    pw = bc.wall_pressure(p[..., 2:-2, 2][..., wall], p[..., 2:-2, 3][..., wall])
    sx, sy = grid.sj[0, wall, 0], grid.sj[1, wall, 0]
    ws = 0.0 if wj is None else wj[..., 0, wall, 0] * sx + wj[..., 1, wall, 0] * sy
    Fj[..., 0, wall, 0] = 0.0
    Fj[..., 1, wall, 0] = pw * sx
    Fj[..., 2, wall, 0] = pw * sy
    Fj[..., 3, wall, 0] = pw * ws
    Rc = Fi[..., 1:, :] - Fi[..., :-1, :] + Fj[..., :, 1:] - Fj[..., :, :-1]
    Rq = np.moveaxis(Rc, -3, -1)
    if source is not None:
        Rq = Rq - source
    return Rq


def spectral_radius_sum(grid, q, flow):
    """Sum over the four faces of each cell of ``|u.S| + c|S|`` (for local time steps).

    Parameters
    ----------
    grid : Grid
    q : ndarray, shape (ni-1, nj-1, 4), real

    Returns
    -------
    ndarray, shape (ni-1, nj-1)
        ``dt_local = cfl * area / result``.
    """
    g = flow.gamma
    rho = q[..., 0]
    u, v = q[..., 1] / rho, q[..., 2] / rho
    p = (g - 1.0) * (q[..., 3] - 0.5 * rho * (u * u + v * v))
    c = np.sqrt(np.maximum(g * p / rho, 1e-300))
    si = 0.5 * (grid.si[:, 1:, :] + grid.si[:, :-1, :])
    sj = 0.5 * (grid.sj[:, :, 1:] + grid.sj[:, :, :-1])
    li = np.abs(u * si[0] + v * si[1]) + c * np.hypot(si[0], si[1])
    lj = np.abs(u * sj[0] + v * sj[1]) + c * np.hypot(sj[0], sj[1])
    return 2.0 * (li + lj)
