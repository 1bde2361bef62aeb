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

from dataclasses import dataclass

import numpy as np

from .errors import MeshError

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
