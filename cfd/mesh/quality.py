"""Quality figures of a structured C-grid (:func:`grid_quality`): angles, wall heights, stretching, aspect ratios."""

from dataclasses import dataclass

import numpy as np

from ..checks import not_a_grid
from ..errors import MeshError
from .metrics import Grid

__all__ = ["grid_quality", "GridQuality"]


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

    Raises
    ------
    MeshError
        ``grid`` is not a :class:`cfd.Grid`.
    """
    if not isinstance(grid, Grid):
        raise MeshError(not_a_grid(grid))
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
