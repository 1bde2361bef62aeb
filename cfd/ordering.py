"""Fill-reducing orderings of the structured cell stencil, for sparse direct solvers.

Geometric nested dissection on the cell indices ``(ic, jc)``: a set of cells is split along its longer
index extent by a separator two cells thick (the residual stencil is a cross of radius 2, so two
lines disconnect it); the halves are ordered first, recursively, then the separator. The wake cut
couples cell ``(ic, jc)``, ``jc < 2``, to ``(ni-2-ic, jc')``: the first separator holds, besides the
middle lines, the lower-wake cells of the rows ``jc = 0, 1``, so that the two halves of the C are
independent.
"""

import numpy as np

__all__ = ["nested_dissection", "unknown_permutation"]


def nested_dissection(grid, leaf=48):
    """Cell permutation (flat C-order indices) for a sparse LU with little fill.

    Parameters
    ----------
    grid : Grid
    leaf : int
        Sets of at most this many cells are left in natural order.

    Returns
    -------
    ndarray of int, shape (N,)
        ``perm[k]`` is the flat cell index placed at position ``k``.
    """
    NI, NJ = grid.cell_shape
    ic, jc = np.divmod(np.arange(NI * NJ), NJ)
    mid = NI // 2
    top_sep = ((ic >= mid - 1) & (ic <= mid)) | ((ic < grid.n_wake) & (jc < 2))
    out = []

    def recurse(cells):
        if cells.size <= leaf:
            out.append(cells)
            return
        a, b = ic[cells], jc[cells]
        if a.max() - a.min() >= b.max() - b.min():
            coord = a
        else:
            coord = b
        lo, hi = coord.min(), coord.max()
        if hi - lo < 4:
            out.append(cells)
            return
        m = (lo + hi + 1) // 2
        recurse(cells[coord < m - 1])
        recurse(cells[coord > m])
        out.append(cells[(coord >= m - 1) & (coord <= m)])

    allc = np.arange(NI * NJ)
    rest = allc[~top_sep]
    recurse(rest[ic[rest] < mid - 1])
    recurse(rest[ic[rest] > mid])
    out.append(allc[top_sep])
    perm = np.concatenate(out)
    assert perm.size == NI * NJ
    return perm


def unknown_permutation(cell_perm, nvar=4):
    """Expand a cell permutation to the interleaved unknowns ``nvar * cell + k``."""
    return (nvar * cell_perm[:, None] + np.arange(nvar)[None, :]).ravel()
