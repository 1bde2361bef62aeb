"""Elliptic grid smoothing: Picard iterations of the Thompson equations with spacing-control functions."""

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

__all__ = ["elliptic_smooth"]


def _d_i(a):
    """Central first difference along axis 0 on interior nodes: shape (ni-2, nj-2)."""
    return 0.5 * (a[2:, 1:-1] - a[:-2, 1:-1])


def _d_j(a):
    """Central first difference along axis 1 on interior nodes: shape (ni-2, nj-2)."""
    return 0.5 * (a[1:-1, 2:] - a[1:-1, :-2])


def elliptic_smooth(x, y, f, n_iter, tol):
    """Picard iterations of the Thompson equations with spacing-control functions.

    Solves ``alpha (r_ii + phi r_i) - 2 beta r_ij + gamma (r_jj + psi r_j) = 0`` on interior nodes
    (``r = (x, y)``, unit index spacing) with the boundary nodes fixed.

    * ``phi`` is the Thomas-Middlecoff i-spacing control of the inner boundary (wall and cut),
      blended towards that of the outer boundary with the arc fraction ``f`` of the initial grid.
    * ``psi = -ln(ratio)`` keeps the geometric j-distribution of each initial i-line.

    Each iteration freezes the coefficients and solves the 9-point system for ``x`` and ``y``
    with one sparse LU factorisation.

    Parameters
    ----------
    x, y : ndarray, shape (ni, nj)
        The initial grid (chords); its boundary nodes stay where they are.
    f : ndarray, shape (ni, nj)
        Arc fraction of each node along its i-line in the initial grid (0 at the inner boundary, 1 outside).
    n_iter : int
        Most Picard iterations.
    tol : float
        Stop when no node moves by more than ``tol`` times the smallest first-cell height in one iteration.

    Returns
    -------
    x, y : ndarray, shape (ni, nj)
        The smoothed grid.
    iterations : int
        Picard iterations done.
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
