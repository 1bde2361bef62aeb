"""Surface pressure and integrated loads on the aerofoil wall.

Wall pressure: ``cfd.boundary.wall_pressure`` (linear extrapolation from the first two cells, the same
value the wall flux of the residual uses), so that the loads are the momentum the scheme actually puts
through the wall. Forces integrate ``p_w - p_inf`` over the wall faces (``-sum (p_w - p_inf) S``, with
``S = sj[:, wall, 0]`` pointing from the body into the fluid) and are resolved in wind axes; the
moment is about ``(0.25, 0)``, nose-up positive. Reference: dynamic pressure ``0.5 rho_inf U^2`` with
``rho_inf = 1``, ``U = mach`` (units of a_inf), chord 1.
"""

import numpy as np

from .boundary import wall_pressure
from .checks import not_a_grid, real_array
from .errors import FlowConditionError, MeshError
from .euler import check_state
from .flow import NON_PHYSICAL, FlowCondition, is_physical
from .mesh.metrics import Grid

__all__ = ["wall_cp", "force_coefficients"]


def _wall_pressure(grid, q, gamma):
    q0 = q[..., grid.wall, 0, :]
    q1 = q[..., grid.wall, 1, :]
    p0 = (gamma - 1.0) * (q0[..., 3] - 0.5 * (q0[..., 1] ** 2 + q0[..., 2] ** 2) / q0[..., 0])
    p1 = (gamma - 1.0) * (q1[..., 3] - 0.5 * (q1[..., 1] ** 2 + q1[..., 2] ** 2) / q1[..., 0])
    return wall_pressure(p0, p1)


def _check_load_input(grid, q, flow):
    """``q`` as an array after :func:`cfd.euler.check_state` (as :func:`cfd.residual` checks it), the types, and
    the state physical (:func:`cfd.flow.is_physical`, as ``solve_steady`` checks ``q0``)."""
    if not isinstance(grid, Grid):
        raise MeshError(not_a_grid(grid))
    if not isinstance(flow, FlowCondition):
        raise FlowConditionError(f"flow must be a cfd.FlowCondition (e.g. cfd.FlowCondition(mach, alpha_deg)); "
                                 f"got {type(flow).__name__}")
    q = np.asarray(q)
    check_state(grid, q, "q")
    if not is_physical(q, flow.gamma):   # NaN gave NaN loads; a negative density or pressure, loads of no flow
        raise FlowConditionError(f"q {NON_PHYSICAL}: it is not a flow, and its loads would be NaN or meaningless; "
                                 "compute loads of a converged, physical state (cfd.solve_steady reports a diverged "
                                 "solve with ConvergenceError)")
    return q


def wall_cp(grid, q, flow):
    """Pressure coefficient at the wall faces.

    Parameters
    ----------
    grid : Grid
    q : ndarray, shape (..., ni-1, nj-1, 4)
    flow : FlowCondition

    Returns
    -------
    x_wall : ndarray, shape (n_surface,)
        Chordwise position of the wall face centres (chords), ordered as ``i``: lower surface from the
        trailing edge to the leading edge, then the upper surface back.
    cp : ndarray, shape (..., n_surface)
        ``(p_w - p_inf) / (0.5 mach^2)``.

    Raises
    ------
    MeshError
        ``q`` whose last three axes are not ``(ni-1, nj-1, 4)`` (as :func:`cfd.residual`), ``grid`` not a Grid.
    FlowConditionError
        ``flow`` not a FlowCondition; ``q`` holding NaN, inf or a non-positive density or pressure.
    """
    q = _check_load_input(grid, q, flow)
    x = grid.x[:, 0]
    ic = np.arange(grid.wall.start, grid.wall.stop)
    x_wall = 0.5 * (x[ic] + x[ic + 1])
    pw = _wall_pressure(grid, q, flow.gamma)
    return x_wall, (pw - flow.p) / flow.dynamic_pressure


def force_coefficients(grid, q, flow, x_ref=(0.25, 0.0)):
    """Lift, drag and pitching-moment coefficients from the wall pressure.

    Parameters
    ----------
    grid : Grid
    q : ndarray, shape (..., ni-1, nj-1, 4)
    flow : FlowCondition
    x_ref : tuple of float
        Moment reference point (chords); quarter chord by default.

    Returns
    -------
    cl, cd, cm : ndarray, shape (...) (floats for a single state)
        Wind axes (drag along the free stream, lift normal to it); ``cm`` nose up positive.

    Raises
    ------
    MeshError, FlowConditionError
        As :func:`wall_cp`; ``x_ref`` not two finite real numbers (FlowConditionError; ``(nan, 0)`` gave a NaN
        ``cm``, a third coordinate was ignored, a complex point lost its imaginary part).
    """
    ref = real_array(x_ref)   # None for text and complex (a complex point lost its imaginary part)
    if ref is None:
        ref = np.zeros(0)
    if ref.shape != (2,) or not np.all(np.isfinite(ref)):
        raise FlowConditionError(f"x_ref must be a finite point (x, y) in chords, e.g. (0.25, 0.0); got "
                                 f"{x_ref!r}")
    x_ref = ref
    _, cp = wall_cp(grid, q, flow)
    s = grid.sj[:, grid.wall, 0]
    ic = np.arange(grid.wall.start, grid.wall.stop)
    xm = 0.5 * (grid.x[ic, 0] + grid.x[ic + 1, 0]) - x_ref[0]
    ym = 0.5 * (grid.y[ic, 0] + grid.y[ic + 1, 0]) - x_ref[1]
    cx = -(cp * s[0]).sum(-1)
    cy = -(cp * s[1]).sum(-1)
    # z-moment of the face forces; nose up is clockwise (negative z) with x downstream and y up.
    cmz = (xm * (-cp * s[1]) - ym * (-cp * s[0])).sum(-1)
    a = flow.alpha
    cl = -cx * np.sin(a) + cy * np.cos(a)
    cd = cx * np.cos(a) + cy * np.sin(a)
    return cl, cd, -cmz
