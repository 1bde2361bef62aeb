"""The :class:`Grid` container and its finite-volume metrics: cell areas and centroids, face vectors.

Node, cell and face indices follow the conventions in the docstring of :mod:`cfd.mesh`.
"""

from dataclasses import dataclass

import numpy as np

from ..checks import kind_of, real_array, whole_number
from ..errors import MeshError

__all__ = ["Grid", "grid_from_nodes"]


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


#: Nodes of the cut closer than this fraction of the local spacing along ``j = 0`` are one node.
CUT_TOL = 1e-3


def _coincident_pairs(x, y):
    """Length of the leading run of node pairs ``(i, 0)``, ``(ni-1-i, 0)`` (``i < (ni-1)/2``) that coincide, and
    the number of such pairs (the run covers them all for a zero-thickness body)."""
    xw, yw = x[:, 0], y[:, 0]
    ni = xw.size
    seg = np.hypot(np.diff(xw), np.diff(yw))
    local = np.minimum(np.r_[seg[0], seg], np.r_[seg, seg[-1]])  # shortest j = 0 edge at each node
    n_pairs = (ni - 1) // 2 + (ni - 1) % 2  # pairs of distinct nodes
    i = np.arange(n_pairs)
    dist = np.hypot(xw[i] - xw[ni - 1 - i], yw[i] - yw[ni - 1 - i])
    tol = CUT_TOL * np.minimum(local[i], local[ni - 1 - i])
    apart = np.flatnonzero(dist > tol)
    return (int(apart[0]) if apart.size else n_pairs), n_pairs


def _check_wake(x, y, n_wake):
    """``n_wake`` as an int, or :class:`MeshError` unless it is a whole number that fits and matches the cut."""
    ni = x.shape[0]
    n = whole_number(n_wake)
    if n is None:
        raise MeshError(f"n_wake must be a whole number (cells on each wake branch, e.g. grid.n_wake); got {n_wake!r}")
    if n < 0 or ni - 1 - 2 * n < 4:
        raise MeshError(
            f"n_wake = {n} leaves {ni - 1 - 2 * n} wall cells out of {ni - 1}; "
            "need 0 <= n_wake and at least 4 cells on the aerofoil"
        )
    run, n_pairs = _coincident_pairs(x, y)
    # A C-grid's wake branches meet pairwise along j = 0 up to the sharp trailing edge, a node of both
    # branches: run = n_wake + 1. A grid without a cut (n_wake = 0) may also have no common node at all; a
    # zero-thickness body (a flat plate) has every pair coincident, so its n_wake cannot be checked.
    if run == n + 1 or (n == 0 and run == 0) or run == n_pairs:
        return n
    if run == 0:
        raise MeshError(
            f"n_wake = {n} does not match the grid: nodes (0, 0) and ({ni - 1}, 0) do not coincide, so there is "
            "no wake cut; pass n_wake=0 (or check the node ordering of the C-grid)"
        )
    raise MeshError(
        f"n_wake = {n} does not match the grid: the wake-cut nodes (i, 0) and ({ni - 1} - i, 0) coincide for "
        f"i = 0 .. {run - 1} (the last one the trailing edge), so n_wake should be {run - 1}"
    )


def signed_cell_areas(x, y) -> np.ndarray:
    """Signed areas of the quadrilateral cells of the node arrays ``x, y`` (shape (ni, nj)), shape (ni-1, nj-1):
    half the cross product of the diagonals, positive for right-handed ``(i, j)``.

    Parameters
    ----------
    x, y : array_like, shape (ni, nj)
        Node coordinates (chords).

    Returns
    -------
    ndarray, shape (ni-1, nj-1)

    Raises
    ------
    MeshError
        If ``x`` or ``y`` is not an array of real numbers (complex, text, None), or they are not 2-D arrays of
        the same shape.
    """
    x, y = _nodes("x", x), _nodes("y", y)
    if x.ndim != 2 or x.shape != y.shape:   # 1-D or 0-D nodes raised a bare IndexError, 3-D gave (ni-1, nj-1, k)
        raise MeshError(f"x and y must be 2-D arrays of node coordinates of the same shape (ni, nj); got shapes "
                        f"{x.shape} and {y.shape}")
    # corners 1 = (i, j), 2 = (i+1, j), 3 = (i+1, j+1), 4 = (i, j+1): 0.5 (x3 - x1, y3 - y1) x (x4 - x2, y4 - y2)
    return 0.5 * ((x[1:, 1:] - x[:-1, :-1]) * (y[:-1, 1:] - y[1:, :-1])
                  - (x[:-1, 1:] - x[1:, :-1]) * (y[1:, 1:] - y[:-1, :-1]))


def inverted_cells(x, y) -> np.ndarray:
    """Indices ``(i, j)`` of the cells of the node arrays ``x, y`` (shape (ni, nj)) whose signed area is not
    positive (inverted or degenerate), shape (k, 2), in row-major order; :class:`MeshError` as
    :func:`signed_cell_areas` for nodes that are not real numbers or not 2-D arrays of the same shape."""
    return np.argwhere(signed_cell_areas(x, y) <= 0.0)


def _nodes(name, value):
    """Node coordinates as a float array, or :class:`MeshError` naming ``name`` unless they are real numbers
    (``grid_from_nodes("a", "b", 3)`` raised NumPy's "could not convert string to float")."""
    v = real_array(value)
    if v is None:
        raise MeshError(f"{name} must be a 2-D array of real node coordinates (chords), shape (ni, nj); got "
                        f"{kind_of(value)}")
    return v


def grid_from_nodes(x, y, n_wake):
    """Build a ``Grid`` (metrics included) from node coordinates.

    Parameters
    ----------
    x, y : array_like, shape (ni, nj)
        Node coordinates in chords, ordered as described in :mod:`cfd.mesh`.
    n_wake : int
        Number of cells on each wake branch. It must match the nodes: ``(i, 0)`` and ``(ni-1-i, 0)`` coincide
        (to :data:`CUT_TOL` of the local spacing) for ``i = 0 .. n_wake``, the last pair being the sharp
        trailing edge, and differ for ``i = n_wake + 1``; ``n_wake = 0`` also allows a grid without a cut
        (no pair coincides). A zero-thickness body (every pair coincident) is not checked.

    Returns
    -------
    Grid

    Raises
    ------
    MeshError
        If the arrays are not real numbers, disagree in shape, are too small for the two-layer JST stencil, contain
        non-finite values, if ``n_wake`` is not a whole number, leaves fewer than 4 wall cells or does not
        match the wake cut (the message gives the value that does), or if any cell is inverted or degenerate.
    """
    x, y = _nodes("x", x), _nodes("y", y)
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
    n_wake = _check_wake(x, y, n_wake)

    # Cell corners: 1 = (i, j), 2 = (i+1, j), 3 = (i+1, j+1), 4 = (i, j+1).
    x1, x2, x3, x4 = x[:-1, :-1], x[1:, :-1], x[1:, 1:], x[:-1, 1:]
    y1, y2, y3, y4 = y[:-1, :-1], y[1:, :-1], y[1:, 1:], y[:-1, 1:]
    area = signed_cell_areas(x, y)
    if np.any(area <= 0.0):
        bad = np.argwhere(area <= 0.0)
        raise MeshError(
            f"{len(bad)} inverted or degenerate cells (area <= 0), first at cell {tuple(int(k) for k in bad[0])}; "
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
