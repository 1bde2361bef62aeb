"""C-grid generation around an aerofoil (:func:`c_grid`): boundary nodes, a marched near-wall block, an
elliptically smoothed outer block and the blend between them. The method is summarised below and in docs/mesh.md."""

import numpy as np

from ..errors import MeshError
from .elliptic import elliptic_smooth
from .metrics import grid_from_nodes, inverted_cells
from .spacing import geometric_distribution, vinokur_distribution

__all__ = ["c_grid"]

# ---------------------------------------------------------------------------------------------
# C-grid generation
# ---------------------------------------------------------------------------------------------
#
# Method (details in docs/mesh.md):
#   1. Boundary nodes. Wall: two-sided Vinokur (tanh) distribution of arc length on each surface,
#      with given spacings at the leading and trailing edges. Wake cut: a straight line along the
#      trailing-edge bisector, geometric cells starting from the trailing-edge spacing. Far field:
#      a semicircle of radius R about mid-chord, straight lines y = +-R and the outflow plane
#      x = 0.5 + R.
#   2. Near-wall block (about 0.3 chord): explicit hyperbolic-type marching along normals that are
#      smoothed over a width growing with the distance from the wall; orthogonal at the wall,
#      fold-free at the concave corners either side of the trailing edge.
#   3. Outer block: transfinite initial grid from the last marched layer to the far field, then
#      elliptic smoothing (Thompson equations, Thomas-Middlecoff-type control functions; each Picard
#      step freezes the coefficients and solves the 9-point system with one sparse LU), nodes moved
#      back along the i-lines to the geometric j-spacing, and a blend across the interface.
#   The j-spacing is geometric along every i-line, from the first-cell height to the far field.


MIN_FARFIELD = 3.0
"""Smallest far-field distance (chords from mid-chord) of a C-grid: the characteristic far-field condition takes
the free stream there (:func:`c_grid` refuses less; :func:`cfd.solve_steady` warns for a grid of other origin)."""


MAX_FARFIELD = 1e4
"""Largest far-field distance (chords) of a C-grid: 400 times the paper's 25. Already at 1e3 the default 60 nodes
outward fold the grid (a typed MeshError); at 1e300 the spacing overflowed (SuperLU's 'Factor is exactly
singular')."""

MAX_NODES = 4_000_000
"""Most nodes ``ni * nj`` of a C-grid: 370 times the paper's 181 x 60 (10 860). The grid itself would fit, but no
solver of this package would: the sparse LU of its Jacobian fills in faster than the node count grows."""


def _check_sizes(ni, nj, n_surface, farfield):
    for name, v in (("ni", ni), ("nj", nj), ("n_surface", n_surface)):
        if not isinstance(v, (int, np.integer)) or isinstance(v, bool):
            raise MeshError(f"{name} must be an integer, got {v!r}")
    if n_surface < 8 or n_surface % 2:
        raise MeshError(
            f"n_surface = {n_surface} must be even (one half per surface) and at least 8; "
            "e.g. n_surface=100 as in the paper"
        )
    n_wake2 = ni - 1 - n_surface
    if n_wake2 < 2 or n_wake2 % 2:
        raise MeshError(
            f"ni - 1 - n_surface = {n_wake2} cells are left for the two wake branches; it must be even and "
            f"at least 2 (one cell per branch): use ni = n_surface + 1 + 2 * n_wake, e.g. ni={n_surface + 81} "
            f"for 40 wake cells per branch"
        )
    if nj < 16:
        raise MeshError(
            f"nj = {nj} nodes across the domain is too few to reach the far field with a smooth spacing; "
            "use nj >= 16 (the paper uses 60)"
        )
    if not isinstance(farfield, (int, float, np.integer, np.floating)) or not np.isfinite(farfield):
        raise MeshError(f"farfield = {farfield!r} must be a finite number of chords, e.g. 25 (the default)")
    if farfield < MIN_FARFIELD:
        raise MeshError(f"farfield = {farfield} chords is too close; use at least {MIN_FARFIELD:g} (default 25)")
    if farfield > MAX_FARFIELD:
        raise MeshError(f"farfield = {farfield:g} chords is beyond cfd.mesh.generation.MAX_FARFIELD = "
                        f"{MAX_FARFIELD:g}; the far field is in chords (the paper's: 25)")
    if ni * nj > MAX_NODES:
        raise MeshError(f"ni * nj = {ni} * {nj} = {ni * nj} nodes is more than cfd.mesh.generation.MAX_NODES = "
                        f"{MAX_NODES:.0e}: no solver here could factorise its Jacobian (the paper's grid: 181 x 60)")
    return n_wake2 // 2


def _check_smoothing(max_iter, tol, n_layers, march_distance, farfield):
    """The smoother's settings of :func:`c_grid`, checked (:class:`MeshError` naming the argument); ``farfield``
    already checked."""
    for name, v, default in (("max_iter", max_iter, 100), ("n_layers", n_layers, 16)):
        if not isinstance(v, (int, np.integer)) or isinstance(v, bool) or v < 0:
            raise MeshError(f"{name} must be a whole number >= 0 (default {default}); got {v!r}")

    def real(v):
        return isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, bool) and np.isfinite(v)

    if not (real(tol) and tol > 0.0):
        raise MeshError(f"tol must be a positive finite number (the smoother's node-move tolerance, default 1e-3); "
                        f"got {tol!r}")
    if not (real(march_distance) and 0.0 <= march_distance < farfield):
        # beyond the reach of every i-line (100 with the far field at 25) it fell back to two layers and failed as a
        # fold "around strongly cambered sections"; 0 marches the least, two layers (valid at the default size; a
        # coarse grid may fold, and the fold's message names march_distance)
        raise MeshError(f"march_distance must be a number of chords with 0 <= march_distance < farfield = {farfield:g} "
                        f"(the thickness of the marched near-wall block, default 0.3; at most nj // 2 layers are "
                        f"marched, so a larger value adds nothing); got {march_distance!r}")


def _boundaries(foil, ni, nj, n_surface, n_wake, farfield, le_spacing, te_spacing, wall_spacing, outer_blend):
    """Inner (wall + cut) and outer boundary nodes and the first-cell heights along ``j = 0``."""
    half = n_surface // 2
    # Wall: lower surface TE -> LE, upper surface LE -> TE (arc length from the lower TE).
    arc_le = foil.s_leading_edge_arc
    arc_up = foil.perimeter - arc_le
    low = arc_le * vinokur_distribution(half, te_spacing / arc_le, le_spacing / arc_le)
    up = arc_le + arc_up * vinokur_distribution(half, le_spacing / arc_up, te_spacing / arc_up)
    arc = np.concatenate([low, up[1:]])
    xw, yw = foil.at_arc(arc)
    xw[0] = xw[-1] = 1.0  # the sharp trailing edge (1, y_c(1) = 0), exactly
    yw[0] = yw[-1] = 0.0

    # Wake cut: bisector of the trailing-edge wedge (surface tangents at the TE), pointing downstream.
    xt, yt = foil.surface(np.array([0.0, 1e-6, 1.0 - 1e-6, 1.0]))
    t_low = np.array([xt[0] - xt[1], yt[0] - yt[1]])
    t_up = np.array([xt[3] - xt[2], yt[3] - yt[2]])
    bis = t_low / np.hypot(*t_low) + t_up / np.hypot(*t_up)
    bis /= np.hypot(*bis)
    x_out = 0.5 + farfield
    length = (x_out - xw[0]) / bis[0]
    dist, _ = geometric_distribution(n_wake, te_spacing, length)
    xk = xw[0] + dist * bis[0]
    yk = yw[0] + dist * bis[1]
    xk[-1] = x_out
    x_in = np.concatenate([xk[::-1], xw[1:-1], xk])
    y_in = np.concatenate([yk[::-1], yw[1:-1], yk])

    # First-cell height: constant on the wall, growing along the cut (1 + d / 2 chords).
    d = np.concatenate([dist[::-1], np.zeros(n_surface - 1), dist])
    h = wall_spacing * (1.0 + 0.5 * d)

    # Outer boundary. Straight parts follow the wake nodes blended with a uniform distribution;
    # the semicircle follows the wall's arc position blended with uniform angle.
    g = outer_blend
    wfrac = dist / dist[-1]
    sfrac = (1.0 - g) * wfrac + g * np.linspace(0.0, 1.0, n_wake + 1)
    xs = 0.5 + (x_out - 0.5) * sfrac  # x along the straight part, from x = 0.5 outward
    afrac = (1.0 - g) * (arc - arc[0]) / (arc[-1] - arc[0]) + g * np.linspace(0.0, 1.0, n_surface + 1)
    ang = -0.5 * np.pi - np.pi * afrac  # from the bottom (-90 deg) round the front to the top (-270 deg)
    xa = 0.5 + farfield * np.cos(ang)
    ya = farfield * np.sin(ang)
    xa[[0, -1]] = 0.5
    ya[0], ya[-1] = -farfield, farfield
    x_o = np.concatenate([xs[::-1], xa[1:-1], xs])
    y_o = np.concatenate([np.full(n_wake + 1, -farfield), ya[1:-1], np.full(n_wake + 1, farfield)])
    return x_in, y_in, x_o, y_o, h


def _transfinite(x_in, y_in, x_o, y_o, h, nj):
    """Straight i-lines from inner to outer boundary with geometric spacing from height ``h``."""
    length = np.hypot(x_o - x_in, y_o - y_in)
    dist, ratio = geometric_distribution(nj - 1, h, length)
    f = dist / length[:, None]
    x = x_in[:, None] + f * (x_o - x_in)[:, None]
    y = y_in[:, None] + f * (y_o - y_in)[:, None]
    x[:, -1], y[:, -1] = x_o, y_o  # exactly, not x_in + (x_o - x_in)
    return x, y, f


def _redistribute(x, y, frac):
    """Move the nodes along each i-line to the arc-length fractions ``frac`` (shape (ni, nj))."""
    seg = np.hypot(np.diff(x, axis=1), np.diff(y, axis=1))
    arc = np.concatenate([np.zeros((x.shape[0], 1)), np.cumsum(seg, axis=1)], axis=1)
    target = frac * arc[:, -1:]
    # Segment k of each line with arc[k] <= target < arc[k+1] (vectorised over all lines).
    k = np.clip(np.sum(arc[:, None, :] <= target[:, :, None], axis=2) - 1, 0, x.shape[1] - 2)
    rows = np.arange(x.shape[0])[:, None]
    a0, a1 = arc[rows, k], arc[rows, k + 1]
    w = (target - a0) / (a1 - a0)
    xr = (1 - w) * x[rows, k] + w * x[rows, k + 1]
    yr = (1 - w) * y[rows, k] + w * y[rows, k + 1]
    xr[:, [0, -1]], yr[:, [0, -1]] = x[:, [0, -1]], y[:, [0, -1]]
    return xr, yr


def _march(x0, y0, dist, spread=0.5):
    """March layers of nodes from the line ``(x0, y0)`` along smoothed normals.

    An explicit hyperbolic-type marching: layer ``j + 1`` is layer ``j`` moved by
    ``dist[:, j + 1] - dist[:, j]`` along its normals. From the second layer on, the unit normals
    (tangent turned +90 deg) are averaged along the layer with a Gaussian of width
    ``spread * dist[i, j]`` in arc length: the width grows with the distance from the wall, so the
    lines leaving a concave corner (each side of the sharp trailing edge, seen from the fluid)
    converge by at most a fraction of their spacing and never cross, while the first layer is
    exactly normal to the wall and cut. The end lines ``i = 0`` and ``i = ni-1`` march straight
    down and up.

    Parameters
    ----------
    x0, y0 : ndarray, shape (ni,)
        The wall and wake cut.
    dist : ndarray, shape (ni, k + 1)
        Distance of each layer from the start line along the i-lines (``dist[:, 0] = 0``).
    spread : float
        Smoothing width over distance from the wall.

    Returns
    -------
    x, y : ndarray, shape (ni, k + 1)
    """
    ni, k1 = dist.shape
    x = np.empty((ni, k1))
    y = np.empty((ni, k1))
    x[:, 0], y[:, 0] = x0, y0
    for j in range(k1 - 1):  # loop over layers; each layer is one vectorised step
        tx, ty = np.gradient(x[:, j]), np.gradient(y[:, j])
        nrm = np.hypot(tx, ty)
        nx, ny = -ty / nrm, tx / nrm
        if j > 0:
            arc = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(x[:, j]), np.diff(y[:, j])))])
            sigma = spread * dist[:, j]
            kern = np.exp(-0.5 * ((arc[:, None] - arc[None, :]) / sigma[:, None]) ** 2)
            nx, ny = kern @ nx, kern @ ny
            nrm = np.hypot(nx, ny)
            nx, ny = nx / nrm, ny / nrm
        nx[0], ny[0], nx[-1], ny[-1] = 0.0, -1.0, 0.0, 1.0
        step = dist[:, j + 1] - dist[:, j]
        x[:, j + 1], y[:, j + 1] = x[:, j] + step * nx, y[:, j] + step * ny
    return x, y


def _smooth(x_in, y_in, x_o, y_o, h, nj, max_iter, tol, n_layers, march_distance=0.3):
    """Near-wall marched layers, an elliptic outer block, and a blend across their interface.

    1. March the layers ``j = 0 .. k`` from the wall and cut along smoothed normals (``_march``),
       with the geometric j-spacing of first height ``h``; ``k`` is the first layer at least
       ``march_distance`` chords from the wall (at most ``nj // 2``).
    2. Between layer ``k`` and the far field: transfinite initial grid continuing the geometric
       spacing, elliptic smoothing (``elliptic_smooth``), then nodes moved along each i-line back to the
       geometric distribution (the smoother shifts them slightly).
    3. The ``n_layers`` j-lines above layer ``k`` are blended towards straight extrusions along
       the last marching direction, so the i-lines cross the interface without a kink.
    """
    ni = x_in.size
    length = np.hypot(x_o - x_in, y_o - y_in)
    dist, _ = geometric_distribution(nj - 1, h, length)
    reach = dist.min(axis=0) >= march_distance
    k = int(np.clip(np.argmax(reach) if reach.any() else nj // 2, 2, nj // 2))   # beyond every line: the most
    xm, ym = _march(x_in, y_in, dist[:, : k + 1], spread=0.5)
    # Outer block from layer k: first spacing continues the marched geometric growth.
    first = dist[:, k + 1] - dist[:, k]
    x0, y0, f0 = _transfinite(xm[:, k], ym[:, k], x_o, y_o, first, nj - k)
    xe, ye, _ = elliptic_smooth(x0, y0, f0, max_iter, tol)
    for a, a0 in ((xe, x0), (ye, y0)):
        a[:, 0], a[:, -1], a[0, :], a[-1, :] = a0[:, 0], a0[:, -1], a0[0, :], a0[-1, :]
    seg = np.hypot(np.diff(xe, axis=1), np.diff(ye, axis=1))
    lo = seg.sum(axis=1)
    do, _ = geometric_distribution(nj - 1 - k, first, lo)
    xe, ye = _redistribute(xe, ye, do / lo[:, None])
    # Blend the outer block towards the extrusion of layer k along the last marching direction.
    dx, dy = xm[:, k] - xm[:, k - 1], ym[:, k] - ym[:, k - 1]
    dn = np.hypot(dx, dy)
    jj = np.arange(nj - k)
    nl = max(1, min(n_layers, nj - k - 1))  # the far-field row keeps weight 0
    w = np.where(jj < nl, 0.5 * (1.0 + np.cos(np.pi * jj / nl)), 0.0)[None, :]
    w = np.broadcast_to(w, xe.shape).copy()
    w[[0, -1], :] = 0.0
    xe = (1 - w) * xe + w * (xm[:, k : k + 1] + do * (dx / dn)[:, None])
    ye = (1 - w) * ye + w * (ym[:, k : k + 1] + do * (dy / dn)[:, None])
    return np.concatenate([xm[:, :k], xe], axis=1), np.concatenate([ym[:, :k], ye], axis=1)


def c_grid(
    foil,
    ni=181,
    nj=60,
    n_surface=100,
    farfield=25.0,
    wall_spacing=0.004,
    le_spacing=None,
    te_spacing=0.006,
    smooth=True,
    max_iter=100,
    tol=1e-3,
    n_layers=16,
    march_distance=0.3,
):
    """A structured C-grid around an aerofoil (the paper's 181 x 60 grid by default).

    Parameters
    ----------
    foil : Aerofoil
        From ``cfd.naca``; needs ``at_arc``, ``perimeter`` and ``s_leading_edge_arc``.
    ni, nj : int
        Nodes around the C and outward (``ni - 1`` by ``nj - 1`` cells).
    n_surface : int
        Cells on the aerofoil, even; the two wake branches get ``(ni - 1 - n_surface) / 2``
        cells each (40 for the defaults).
    farfield : float
        Far-field radius R in chords: a semicircle of radius R about mid-chord ``(0.5, 0)``,
        joined by straight lines ``y = -R`` and ``y = +R`` to the outflow plane ``x = 0.5 + R``.
    wall_spacing : float
        Height of the first cell on the wall (chords). It grows along the wake cut as
        ``wall_spacing * (1 + d / 2)`` with ``d`` the distance from the trailing edge.
    le_spacing : float, optional
        Surface spacing at the leading edge (chords, arc length). Default
        ``clip(0.25 r_LE, 0.001, 0.005)`` with the leading-edge radius ``r_LE = 1.1019 t^2``:
        about four cells per radian of nose curvature.
    te_spacing : float
        Surface spacing at the trailing edge and first wake cell (chords).
    smooth : bool
        Build the marched and elliptic grid (True) or return the transfinite initial grid, with
        straight i-lines from the wall to the far field (False; not orthogonal at the wall).
    max_iter : int
        Maximum Picard iterations of the elliptic smoother of the outer block.
    tol : float
        Stop the smoother when no node moves by more than ``tol`` times the smallest first-cell
        height of the block in one iteration.
    n_layers : int
        j-lines above the marched block blended towards its last marching direction.
    march_distance : float
        Thickness (chords) of the marched near-wall block, at least 2 and at most ``nj // 2`` layers;
        ``0 <= march_distance < farfield`` (0: the least, two layers).

    Returns
    -------
    Grid
        With ``n_wake = (ni - 1 - n_surface) / 2``; node ``(i, 0)`` and ``(ni-1-i, 0)`` coincide for
        ``i <= n_wake``.

    Raises
    ------
    MeshError
        If the sizes do not fit the stencil or each other, the far field is too close, the spacings
        are not positive and small enough, a smoother setting is out of range (``max_iter``, ``n_layers`` not
        whole numbers >= 0, ``tol`` not positive, ``march_distance`` outside ``(0, farfield)``, any of them
        non-finite), ``smooth``
        not a bool, ``farfield`` above :data:`MAX_FARFIELD`, more than :data:`MAX_NODES` nodes, or the grid folds
        (inverted cells).
    """
    if not all(hasattr(foil, a) for a in ("at_arc", "perimeter", "s_leading_edge_arc", "t")):
        raise MeshError(f"foil must be an aerofoil from cfd.naca (e.g. cfd.naca('0012')); got {type(foil).__name__}")
    n_wake = _check_sizes(ni, nj, n_surface, farfield)
    _check_smoothing(max_iter, tol, n_layers, march_distance, farfield)
    if not isinstance(smooth, (bool, np.bool_)):
        raise MeshError(f"smooth must be True or False; got {smooth!r}")
    if le_spacing is None:
        le_spacing = float(np.clip(0.25 * 1.1019 * foil.t**2, 0.001, 0.005))
    half_len = min(foil.s_leading_edge_arc, foil.perimeter - foil.s_leading_edge_arc)
    for name, v, hi in (
        ("wall_spacing", wall_spacing, farfield / (nj - 1)),
        ("le_spacing", le_spacing, half_len / (n_surface // 2)),
        ("te_spacing", te_spacing, half_len / (n_surface // 2)),
    ):
        if not isinstance(v, (int, float, np.integer, np.floating)) or isinstance(v, bool):
            raise MeshError(f"{name} must be a number of chords; got {v!r}")
        if not (np.isfinite(v) and 0.0 < v < hi):
            raise MeshError(
                f"{name} = {v} must be positive and below the uniform spacing {hi:.4g} chords; "
                f"reduce it (defaults: wall 0.004, trailing edge 0.006) or add nodes"
            )
    x_in, y_in, x_o, y_o, h = _boundaries(
        foil, ni, nj, n_surface, n_wake, float(farfield), le_spacing, te_spacing, wall_spacing, 0.5
    )
    if not smooth:
        x, y, _ = _transfinite(x_in, y_in, x_o, y_o, h, nj)
    else:
        x, y = _smooth(x_in, y_in, x_o, y_o, h, nj, max_iter, tol, n_layers, march_distance)
        # Cut nodes are boundary nodes: keep the two branches bit-identical.
        x[ni - 1 - n_wake :, 0] = x[n_wake::-1, 0]
        y[ni - 1 - n_wake :, 0] = y[n_wake::-1, 0]
    folded = inverted_cells(x, y)
    if folded.size:   # said here, for the generator's user (grid_from_nodes speaks to whoever built the nodes)
        thin = (f"; march_distance = {march_distance:g} chords is below the default 0.3: a thinner marched block "
                "folds coarse grids of any section" if smooth and march_distance < 0.3 else "")
        raise MeshError(
            f"c_grid folded the grid around {getattr(foil, 'name', 'this section')}: {len(folded)} inverted cells, "
            f"first at cell {tuple(int(k) for k in folded[0])}. The generator folds around strongly cambered "
            "sections on coarse grids: use more nodes (ni, nj, n_surface; the paper's 181 x 60 meshes NACA 4912, "
            "which 81 x 16 folds); some sections (NACA 9912) fold at every setting: build the nodes yourself and "
            f"pass them to cfd.grid_from_nodes{thin}")
    return grid_from_nodes(x, y, n_wake)
