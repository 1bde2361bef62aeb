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

The sub-package, in the order of the data: :mod:`cfd.mesh.geometry` (the aerofoil: :func:`cfd.naca`,
:class:`cfd.Aerofoil`), :mod:`cfd.mesh.spacing` (point distributions) and :mod:`cfd.mesh.elliptic` (the
smoother), used by :mod:`cfd.mesh.generation` (:func:`c_grid`); :mod:`cfd.mesh.metrics` (:class:`Grid`,
:func:`grid_from_nodes`: the finite-volume metrics); :mod:`cfd.mesh.quality` (:func:`grid_quality`);
:mod:`cfd.mesh.presets` (the named grids of :func:`cfd.preset_grid`). The grid's public names are importable from
here.
"""

from .generation import c_grid
from .metrics import Grid, grid_from_nodes
from .quality import GridQuality, grid_quality

__all__ = ["Grid", "grid_from_nodes", "c_grid", "grid_quality", "GridQuality"]
