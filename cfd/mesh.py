"""Structured C-grids: the ``Grid`` container, its finite-volume metrics and the wake cut.

Index conventions (fixed: the flow solver, the loads and the linear operators rely on them)
--------------------------------------------------------------------------------------------
Nodes are ``x[i, j], y[i, j]`` with ``i = 0 .. ni-1`` running around the C and ``j = 0 .. nj-1``
running outward:

* ``i = 0`` is the downstream end of the lower wake branch; ``i`` increases along the lower wake
  towards the trailing edge, then along the lower surface to the leading edge, along the upper
  surface back to the trailing edge and out along the upper wake branch to ``i = ni-1``.
* ``j = 0`` is the aerofoil surface and the wake cut; ``j = nj-1`` is the far-field boundary.
* The ``(i, j)`` frame is right-handed, so cell areas are positive.

Cells are ``(ic, jc)`` with ``ic = 0 .. ni-2`` and ``jc = 0 .. nj-2``; cell ``(ic, jc)`` has the nodes
``(ic, jc), (ic+1, jc), (ic+1, jc+1), (ic, jc+1)``. With ``n_wake`` cells on each wake branch, the wall
cells are ``ic = n_wake .. ni-2-n_wake`` in the row ``jc = 0``, and across the wake cut cell
``(ic, 0)`` (``ic < n_wake``) neighbours cell ``(ni-2-ic, 0)``.

Face vectors are normals scaled by the face length (units: chords):

* ``si[:, i, jc]``, shape ``(2, ni, nj-1)``: the i-face between cells ``(i-1, jc)`` and ``(i, jc)``
  (the edge from node ``(i, jc)`` to node ``(i, jc+1)``), pointing towards increasing ``i``.
* ``sj[:, ic, j]``, shape ``(2, ni-1, nj)``: the j-face between cells ``(ic, j-1)`` and ``(ic, j)``
  (the edge from node ``(ic, j)`` to node ``(ic+1, j)``), pointing towards increasing ``j``.
"""

import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from .errors import MeshError

__all__ = ["Grid", "grid_from_nodes", "c_grid", "grid_quality", "GridQuality"]


@dataclass(frozen=True, eq=False)
class Grid:
    """A structured C-grid with its finite-volume metrics.

    Attributes
    ----------
    x, y : ndarray, shape (ni, nj)
        Node coordinates in chords.
    n_wake : int
        Number of cells on each wake branch along ``j = 0``.
    xc, yc : ndarray, shape (ni-1, nj-1)
        Cell centroids.
    area : ndarray, shape (ni-1, nj-1)
        Cell areas (positive).
    si : ndarray, shape (2, ni, nj-1)
        i-face normals scaled by face length, pointing towards increasing ``i``.
    sj : ndarray, shape (2, ni-1, nj)
        j-face normals scaled by face length, pointing towards increasing ``j``.
    """

    x: np.ndarray
    y: np.ndarray
    n_wake: int
    xc: np.ndarray
    yc: np.ndarray
    area: np.ndarray
    si: np.ndarray
    sj: np.ndarray

    @property
    def shape(self):
        """Node counts ``(ni, nj)``."""
        return self.x.shape

    @property
    def cell_shape(self):
        """Cell counts ``(ni-1, nj-1)``."""
        return self.area.shape

    @property
    def n_cells(self):
        """Total number of cells."""
        return self.area.size

    @property
    def n_surface(self):
        """Number of wall cells (faces on the aerofoil)."""
        return self.cell_shape[0] - 2 * self.n_wake

    @property
    def wall(self):
        """Slice of cell indices ``ic`` that touch the aerofoil in the row ``jc = 0``."""
        return slice(self.n_wake, self.cell_shape[0] - self.n_wake)


def grid_from_nodes(x, y, n_wake):
    """Build a ``Grid`` (metrics included) from node coordinates.

    Parameters
    ----------
    x, y : array_like, shape (ni, nj)
        Node coordinates in chords, ordered as described in the module docstring.
    n_wake : int
        Number of cells on each wake branch.

    Returns
    -------
    Grid

    Raises
    ------
    MeshError
        If the arrays disagree in shape, are too small for the two-layer JST stencil, contain
        non-finite values, if the wake branches do not fit, or if any cell is inverted or degenerate.
    """
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    if x.ndim != 2 or x.shape != y.shape:
        raise MeshError(f"x and y must be 2-D arrays of one shape (ni, nj); got {x.shape} and {y.shape}")
    ni, nj = x.shape
    if ni < 8 or nj < 5:
        raise MeshError(
            f"grid of {ni} x {nj} nodes is too small for the JST stencil (two ghost layers); "
            "use at least 8 x 5 nodes"
        )
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
        raise MeshError("node coordinates contain NaN or inf")
    n_wake = int(n_wake)
    if n_wake < 0 or ni - 1 - 2 * n_wake < 4:
        raise MeshError(
            f"n_wake = {n_wake} leaves {ni - 1 - 2 * n_wake} wall cells out of {ni - 1}; "
            "need 0 <= n_wake and at least 4 cells on the aerofoil"
        )

    # Cell corners: 1 = (i, j), 2 = (i+1, j), 3 = (i+1, j+1), 4 = (i, j+1).
    x1, x2, x3, x4 = x[:-1, :-1], x[1:, :-1], x[1:, 1:], x[:-1, 1:]
    y1, y2, y3, y4 = y[:-1, :-1], y[1:, :-1], y[1:, 1:], y[:-1, 1:]
    area = 0.5 * ((x3 - x1) * (y4 - y2) - (x4 - x2) * (y3 - y1))
    if np.any(area <= 0.0):
        bad = np.argwhere(area <= 0.0)
        raise MeshError(
            f"{len(bad)} inverted or degenerate cells (area <= 0), first at cell {tuple(bad[0])}; "
            "check the node ordering (right-handed i, j) or smooth the grid"
        )
    # Centroid of a quadrilateral from its two triangles (1, 2, 3) and (1, 3, 4).
    a123 = 0.5 * ((x2 - x1) * (y3 - y1) - (x3 - x1) * (y2 - y1))
    a134 = 0.5 * ((x3 - x1) * (y4 - y1) - (x4 - x1) * (y3 - y1))
    xc = (a123 * (x1 + x2 + x3) + a134 * (x1 + x3 + x4)) / (3.0 * area)
    yc = (a123 * (y1 + y2 + y3) + a134 * (y1 + y3 + y4)) / (3.0 * area)

    # i-faces: edge (i, j) -> (i, j+1); normal (dy, -dx) points to +i.
    dx_i = x[:, 1:] - x[:, :-1]
    dy_i = y[:, 1:] - y[:, :-1]
    si = np.stack([dy_i, -dx_i])
    # j-faces: edge (i, j) -> (i+1, j); normal (-dy, dx) points to +j.
    dx_j = x[1:, :] - x[:-1, :]
    dy_j = y[1:, :] - y[:-1, :]
    sj = np.stack([-dy_j, dx_j])

    return Grid(x=x, y=y, n_wake=n_wake, xc=xc, yc=yc, area=area, si=si, sj=sj)


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


def _solve_monotone(f, target, lo, hi, n_iter=100):
    """Vectorised bisection for ``f(r) = target`` with ``f`` increasing on ``[lo, hi]``."""
    target = np.asarray(target, dtype=float)
    lo = np.full(target.shape, float(lo))
    hi = np.full(target.shape, float(hi))
    for _ in range(n_iter):  # iterations of the root finder, not a loop over cells
        mid = 0.5 * (lo + hi)
        below = f(mid) < target
        lo = np.where(below, mid, lo)
        hi = np.where(below, hi, mid)
    return 0.5 * (lo + hi)


def _geometric_sum(r, n):
    """``1 + r + ... + r^(n-1)`` (vectorised, safe at r = 1)."""
    r = np.asarray(r, dtype=float)
    near = np.abs(r - 1.0) < 1e-9
    return np.where(near, np.asarray(n, dtype=float), (r**n - 1.0) / np.where(near, 2.0, r - 1.0))


def _geometric(n, first, length):
    """Cumulative geometric distribution: ``n + 1`` points from 0 to ``length`` (last axis).

    ``first`` and ``length`` broadcast; the ratio is found by bisection.
    """
    first = np.asarray(first, dtype=float)
    length = np.asarray(length, dtype=float)
    ratio = _solve_monotone(lambda r: first * _geometric_sum(r, n), length, 0.2, 5.0)
    k = np.arange(n + 1)
    frac = _geometric_sum(ratio[..., None], k) / _geometric_sum(ratio[..., None], n)
    return length[..., None] * frac, ratio


def _vinokur(n, ds0, ds1):
    """Two-sided tanh stretching (Vinokur 1983): ``n + 1`` points on [0, 1].

    Parameters
    ----------
    n : int
        Number of intervals.
    ds0, ds1 : float
        First and last intervals as fractions of the length.

    Returns
    -------
    ndarray, shape (n + 1,)
        Increasing from 0 to 1.
    """
    xi = np.arange(n + 1) / n
    b = 1.0 / (n * math.sqrt(ds0 * ds1))
    if abs(b - 1.0) < 1e-8:
        u = xi
    elif b > 1.0:
        d = float(_solve_monotone(lambda d: np.sinh(d) / d, b, 1e-8, 60.0))
        u = 0.5 * (1.0 + np.tanh(d * (xi - 0.5)) / math.tanh(0.5 * d))
    else:
        # Spacings larger than uniform at both ends: the tangent form (sin(d)/d = b, d < pi).
        d = float(_solve_monotone(lambda d: -np.sin(d) / d, -b, 1e-8, math.pi - 1e-8))
        u = 0.5 * (1.0 + np.tan(d * (xi - 0.5)) / math.tan(0.5 * d))
    a = math.sqrt(ds1 / ds0)
    s = u / (a + (1.0 - a) * u)
    s[0], s[-1] = 0.0, 1.0
    return s


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
    if farfield < 3.0:
        raise MeshError(f"farfield = {farfield} chords is too close; use at least 3 (default 25)")
    return n_wake2 // 2


def _boundaries(foil, ni, nj, n_surface, n_wake, farfield, le_spacing, te_spacing, wall_spacing, outer_blend):
    """Inner (wall + cut) and outer boundary nodes and the first-cell heights along ``j = 0``."""
    half = n_surface // 2
    # Wall: lower surface TE -> LE, upper surface LE -> TE (arc length from the lower TE).
    arc_le = foil.s_leading_edge_arc
    arc_up = foil.perimeter - arc_le
    low = arc_le * _vinokur(half, te_spacing / arc_le, le_spacing / arc_le)
    up = arc_le + arc_up * _vinokur(half, le_spacing / arc_up, te_spacing / arc_up)
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
    dist, _ = _geometric(n_wake, te_spacing, length)
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
    dist, ratio = _geometric(nj - 1, h, length)
    f = dist / length[:, None]
    x = x_in[:, None] + f * (x_o - x_in)[:, None]
    y = y_in[:, None] + f * (y_o - y_in)[:, None]
    x[:, -1], y[:, -1] = x_o, y_o  # exactly, not x_in + (x_o - x_in)
    return x, y, f


def _d_i(a):
    """Central first difference along axis 0 on interior nodes: shape (ni-2, nj-2)."""
    return 0.5 * (a[2:, 1:-1] - a[:-2, 1:-1])


def _d_j(a):
    """Central first difference along axis 1 on interior nodes: shape (ni-2, nj-2)."""
    return 0.5 * (a[1:-1, 2:] - a[1:-1, :-2])


def _elliptic(x, y, f, n_iter, tol):
    """Picard iterations of the Thompson equations with spacing-control functions.

    Solves ``alpha (r_ii + phi r_i) - 2 beta r_ij + gamma (r_jj + psi r_j) = 0`` on interior nodes
    (``r = (x, y)``, unit index spacing) with the boundary nodes fixed.

    * ``phi`` is the Thomas-Middlecoff i-spacing control of the inner boundary (wall and cut),
      blended towards that of the outer boundary with the arc fraction ``f`` of the initial grid.
    * ``psi = -ln(ratio)`` keeps the geometric j-distribution of each initial i-line.

    Each iteration freezes the coefficients and solves the 9-point system for ``x`` and ``y``
    with one sparse LU factorisation.

    Returns the smoothed ``x, y`` (shape (ni, nj)) and the number of iterations.
    """
    ni, nj = x.shape
    n = ni * nj
    idx = np.arange(n).reshape(ni, nj)
    inner = idx[1:-1, 1:-1].ravel()
    bnd = np.setdiff1d(idx.ravel(), inner, assume_unique=True)

    def boundary_phi(xb, yb):
        xd, yd = 0.5 * (xb[2:] - xb[:-2]), 0.5 * (yb[2:] - yb[:-2])
        xdd, ydd = xb[2:] - 2 * xb[1:-1] + xb[:-2], yb[2:] - 2 * yb[1:-1] + yb[:-2]
        return -(xd * xdd + yd * ydd) / (xd**2 + yd**2)

    w_in = 1.0 - f[1:-1, 1:-1]
    phi = np.clip(
        w_in * boundary_phi(x[:, 0], y[:, 0])[:, None] + (1.0 - w_in) * boundary_phi(x[:, -1], y[:, -1])[:, None],
        -1.0,
        1.0,
    )

    # ln(s_{j+1/2} / s_{j-1/2}) along the initial i-lines (interior nodes): the wanted growth.
    log_s = np.log(np.hypot(np.diff(x[1:-1], axis=1), np.diff(y[1:-1], axis=1)))
    psi = np.clip(log_s[:, :-1] - log_s[:, 1:], -1.0, 1.0)

    offsets = [(0, 0), (1, 0), (-1, 0), (0, 1), (0, -1), (1, 1), (-1, -1), (1, -1), (-1, 1)]
    cols = np.concatenate([idx[1 + di : ni - 1 + di, 1 + dj : nj - 1 + dj].ravel() for di, dj in offsets] + [bnd])
    rows = np.concatenate([inner] * len(offsets) + [bnd])
    rhs = np.zeros((n, 2))
    rhs[bnd, 0] = x.ravel()[bnd]
    rhs[bnd, 1] = y.ravel()[bnd]
    scale = np.min(np.hypot(x[:, 1] - x[:, 0], y[:, 1] - y[:, 0]))
    it = 0
    for it in range(1, n_iter + 1):  # Picard iterations; each one is a single sparse solve
        xi_, yi_, xj_, yj_ = _d_i(x), _d_i(y), _d_j(x), _d_j(y)
        al = xj_**2 + yj_**2
        be = xi_ * xj_ + yi_ * yj_
        ga = xi_**2 + yi_**2
        vals = [
            -2.0 * (al + ga),
            al * (1.0 + 0.5 * phi),
            al * (1.0 - 0.5 * phi),
            ga * (1.0 + 0.5 * psi),
            ga * (1.0 - 0.5 * psi),
            -0.5 * be,
            -0.5 * be,
            0.5 * be,
            0.5 * be,
        ]
        data = np.concatenate([v.ravel() for v in vals] + [np.ones(bnd.size)])
        A = sp.csc_matrix((data, (rows, cols)), shape=(n, n))
        sol = spla.splu(A).solve(rhs)
        x_new, y_new = sol[:, 0].reshape(ni, nj), sol[:, 1].reshape(ni, nj)
        change = np.max(np.hypot(x_new - x, y_new - y)) / scale
        x, y = x_new, y_new
        if change < tol:
            break
    return x, y, it


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
       spacing, elliptic smoothing (``_elliptic``), then nodes moved along each i-line back to the
       geometric distribution (the smoother shifts them slightly).
    3. The ``n_layers`` j-lines above layer ``k`` are blended towards straight extrusions along
       the last marching direction, so the i-lines cross the interface without a kink.
    """
    ni = x_in.size
    length = np.hypot(x_o - x_in, y_o - y_in)
    dist, _ = _geometric(nj - 1, h, length)
    k = int(np.clip(np.argmax(dist.min(axis=0) >= march_distance), 2, nj // 2))
    xm, ym = _march(x_in, y_in, dist[:, : k + 1], spread=0.5)
    # Outer block from layer k: first spacing continues the marched geometric growth.
    first = dist[:, k + 1] - dist[:, k]
    x0, y0, f0 = _transfinite(xm[:, k], ym[:, k], x_o, y_o, first, nj - k)
    xe, ye, _ = _elliptic(x0, y0, f0, max_iter, tol)
    for a, a0 in ((xe, x0), (ye, y0)):
        a[:, 0], a[:, -1], a[0, :], a[-1, :] = a0[:, 0], a0[:, -1], a0[0, :], a0[-1, :]
    seg = np.hypot(np.diff(xe, axis=1), np.diff(ye, axis=1))
    lo = seg.sum(axis=1)
    do, _ = _geometric(nj - 1 - k, first, lo)
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
        Thickness (chords) of the marched near-wall block, at most ``nj // 2`` layers.

    Returns
    -------
    Grid
        With ``n_wake = (ni - 1 - n_surface) / 2``; node ``(i, 0)`` and ``(ni-1-i, 0)`` coincide for
        ``i <= n_wake``.

    Raises
    ------
    MeshError
        If the sizes do not fit the stencil or each other, the far field is too close, the spacings
        are not positive and small enough, or the grid folds (inverted cells).
    """
    if not all(hasattr(foil, a) for a in ("at_arc", "perimeter", "s_leading_edge_arc", "t")):
        raise MeshError(f"foil must be an aerofoil from cfd.naca (e.g. cfd.naca('0012')); got {type(foil).__name__}")
    n_wake = _check_sizes(ni, nj, n_surface, farfield)
    if le_spacing is None:
        le_spacing = float(np.clip(0.25 * 1.1019 * foil.t**2, 0.001, 0.005))
    half_len = min(foil.s_leading_edge_arc, foil.perimeter - foil.s_leading_edge_arc)
    for name, v, hi in (
        ("wall_spacing", wall_spacing, farfield / (nj - 1)),
        ("le_spacing", le_spacing, half_len / (n_surface // 2)),
        ("te_spacing", te_spacing, half_len / (n_surface // 2)),
    ):
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
    return grid_from_nodes(x, y, n_wake)


@dataclass(frozen=True)
class GridQuality:
    """Quality figures of a structured grid (angles in degrees, lengths in chords).

    Attributes
    ----------
    shape : tuple of int
        Node counts ``(ni, nj)``.
    n_cells : int
        Number of cells.
    min_area : float
        Smallest cell area (chords^2).
    min_wall_height, max_wall_height : float
        Extreme first-cell heights on the aerofoil (length of the first j-edge).
    max_wall_nonorthogonality : float
        Largest deviation from 90 deg of a cell corner angle on the wall (aerofoil only).
    max_cut_nonorthogonality : float
        The same on the wake cut.
    min_angle, max_angle : float
        Extreme cell corner angles over the whole grid.
    max_skewness : float
        ``max |angle - 90| / 90`` over all cell corners (0 for rectangles, 1 for degenerate).
    max_stretch_i, max_stretch_j : float
        Largest ratio (>= 1) of the sizes of neighbouring cells along i and along j.
    max_aspect_ratio : float
        Largest ratio of a cell's i-size to its j-size or vice versa.
    """

    shape: tuple
    n_cells: int
    min_area: float
    min_wall_height: float
    max_wall_height: float
    max_wall_nonorthogonality: float
    max_cut_nonorthogonality: float
    min_angle: float
    max_angle: float
    max_skewness: float
    max_stretch_i: float
    max_stretch_j: float
    max_aspect_ratio: float

    def as_dict(self):
        """The figures as a plain dict (for tables and reports)."""
        return {k: getattr(self, k) for k in self.__dataclass_fields__}

    def __str__(self):
        rows = [f"{k:28s} {v:.4g}" if isinstance(v, float) else f"{k:28s} {v}" for k, v in self.as_dict().items()]
        return "\n".join(rows)


def _corner_angles(x, y):
    """Interior angles (deg) of every cell at its four corners, shape (4, ni-1, nj-1).

    Corners in the order (i, j), (i+1, j), (i+1, j+1), (i, j+1).
    """
    px = np.stack([x[:-1, :-1], x[1:, :-1], x[1:, 1:], x[:-1, 1:]])
    py = np.stack([y[:-1, :-1], y[1:, :-1], y[1:, 1:], y[:-1, 1:]])
    ax, ay = np.roll(px, -1, axis=0) - px, np.roll(py, -1, axis=0) - py  # to the next corner
    bx, by = np.roll(px, 1, axis=0) - px, np.roll(py, 1, axis=0) - py  # to the previous corner
    cos = (ax * bx + ay * by) / (np.hypot(ax, ay) * np.hypot(bx, by))
    return np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))


def grid_quality(grid):
    """Quality figures of a C-grid.

    Parameters
    ----------
    grid : Grid

    Returns
    -------
    GridQuality
    """
    x, y = grid.x, grid.y
    ang = _corner_angles(x, y)
    wall = grid.wall
    # Corners on j = 0 are corners 0 and 1 of the cells in the row jc = 0.
    dev0 = np.abs(ang[:2, :, 0] - 90.0)
    cut = np.r_[0 : grid.n_wake, grid.cell_shape[0] - grid.n_wake : grid.cell_shape[0]]
    # Cell sizes: distance between the midpoints of opposite faces.
    li = np.hypot(0.5 * (x[1:, :-1] + x[1:, 1:] - x[:-1, :-1] - x[:-1, 1:]),
                  0.5 * (y[1:, :-1] + y[1:, 1:] - y[:-1, :-1] - y[:-1, 1:]))
    lj = np.hypot(0.5 * (x[:-1, 1:] + x[1:, 1:] - x[:-1, :-1] - x[1:, :-1]),
                  0.5 * (y[:-1, 1:] + y[1:, 1:] - y[:-1, :-1] - y[1:, :-1]))
    ri = li[1:, :] / li[:-1, :]
    rj = lj[:, 1:] / lj[:, :-1]
    h = np.hypot(x[:, 1] - x[:, 0], y[:, 1] - y[:, 0])[grid.n_wake : grid.shape[0] - grid.n_wake]
    return GridQuality(
        shape=tuple(int(v) for v in grid.shape),
        n_cells=int(grid.n_cells),
        min_area=float(grid.area.min()),
        min_wall_height=float(h.min()),
        max_wall_height=float(h.max()),
        max_wall_nonorthogonality=float(dev0[:, wall].max()),
        max_cut_nonorthogonality=float(dev0[:, cut].max()) if cut.size else 0.0,
        min_angle=float(ang.min()),
        max_angle=float(ang.max()),
        max_skewness=float(np.abs(ang - 90.0).max() / 90.0),
        max_stretch_i=float(np.maximum(ri, 1.0 / ri).max()),
        max_stretch_j=float(np.maximum(rj, 1.0 / rj).max()),
        max_aspect_ratio=float(np.maximum(li / lj, lj / li).max()),
    )
