"""Exact Jacobian of the Euler residual by coloured complex-step differentiation.

``R`` (``cfd.euler.residual``) is complex-safe, so ``Im R(q + i h e) / h`` with ``h = 1e-30`` is the
directional derivative ``(dR/dq) e`` to machine precision (no subtractive cancellation). Columns whose
stencils do not overlap share a colour and are perturbed together; the state of all colours is
evaluated as one batch (a leading axis of the residual), chunked to bound memory.

Piecewise parts of the scheme (the ``abs`` of the spectral radius and of the sensor, the ``max`` of
the sensor pair and ``max(0, k4 - eps2)``, the inflow/outflow switch of the far field) are
differentiated on their active branch (chosen on the real part). At a tie the derivative is that of
the branch taken by the real residual: a one-sided derivative, exact almost everywhere.

The residual at a cell depends on the 9-cell cross of radius 2 around it (across the wake cut where it
applies, and through the wall ghosts, which copy cells ``jc = 0, 1``), so the Jacobian is block sparse
with 4 x 4 blocks and at most 9 blocks per block row (11 at wake cells).

The machinery is generic: ``coloured_complex_step`` differentiates any complex-safe function given a
sparsity pattern, so derivatives with respect to ``face_velocity`` or ``source`` reuse the same
residual (see ``residual_derivative``).
"""

from functools import lru_cache

import numpy as np
import scipy.sparse as sp

from .checks import kind_of, real_array, whole_number
from .errors import FlowConditionError, MeshError
from .euler import DEFAULT_SCHEME, check_input, lift_coefficient, residual

__all__ = ["jacobian", "cell_stencil", "greedy_colouring", "coloured_complex_step", "residual_derivative"]

H_STEP = 1e-30


@lru_cache(maxsize=16)
def cell_stencil(grid):
    """Cell-level dependency pattern of the residual.

    Parameters
    ----------
    grid : Grid

    Returns
    -------
    scipy.sparse.csr_matrix, shape (N, N), bool, N = (ni-1)(nj-1)
        Entry (r, c) is set if the residual of cell r depends on the state of cell c (flat C order
        ``ic * (nj-1) + jc``).
    """
    NI, NJ = grid.cell_shape
    ic, jc = np.meshgrid(np.arange(NI), np.arange(NJ), indexing="ij")
    rows, cols = [], []

    def add(mask, i2, j2):
        rows.append((ic * NJ + jc)[mask])
        cols.append((i2 * NJ + j2)[mask])

    add(np.ones_like(ic, bool), ic, jc)
    for d in (-2, -1, 1, 2):
        add((ic + d >= 0) & (ic + d < NI), ic + d, jc)
        add((jc + d >= 0) & (jc + d < NJ), ic, jc + d)
    nw = grid.n_wake
    wake = (ic < nw) | (ic >= NI - nw)
    m = NI - 1 - ic
    add(wake & (jc == 0), m, np.zeros_like(jc))
    add(wake & (jc == 0), m, np.ones_like(jc))
    add(wake & (jc == 1), m, np.zeros_like(jc))
    r = np.concatenate(rows)
    c = np.concatenate(cols)
    S = sp.csr_matrix((np.ones(r.size, bool), (r, c)), shape=(NI * NJ, NI * NJ))
    S.sum_duplicates()
    S.sort_indices()
    return S


def greedy_colouring(pattern, preferred=None):
    """Colour the columns of a sparsity pattern so that no row meets two columns of one colour.

    Parameters
    ----------
    pattern : scipy.sparse matrix, shape (m, n)
    preferred : ndarray of int, shape (n,), optional
        A colouring to keep where it is valid (e.g. a lattice colouring of a structured stencil); a
        column whose preferred colour is taken by a conflicting, already coloured column gets the
        smallest free colour above the preferred ones.

    Returns
    -------
    colours : ndarray of int, shape (n,)
        Colours ``0 .. n_colours - 1``.
    """
    P = sp.csr_matrix(pattern, dtype=bool)
    C = (P.T @ P).tocsr()
    n = C.shape[0]
    colours = np.full(n, -1)
    indptr, indices = C.indptr, C.indices
    base = 0 if preferred is None else int(preferred.max()) + 1
    for k in range(n):
        used = colours[indices[indptr[k]:indptr[k + 1]]]
        used = used[used >= 0]
        if preferred is not None and not np.any(used == preferred[k]):
            colours[k] = preferred[k]
            continue
        if preferred is not None:
            used = used[used >= base] - base
            if used.size == 0:
                colours[k] = base
                continue
            free = np.ones(used.max() + 2, bool)
            free[used] = False
            colours[k] = base + np.argmax(free)
            continue
        if used.size == 0:
            colours[k] = 0
            continue
        free = np.ones(used.max() + 2, bool)
        free[used] = False
        colours[k] = np.argmax(free)
    return colours


@lru_cache(maxsize=16)
def state_pattern(grid):
    """Scalar pattern (4N x 4N) and column colours of dR/dq for this grid."""
    S = cell_stencil(grid)
    # (ic + 3 jc) mod 10 colours the radius-2 cross without conflicts on a lattice; the greedy pass
    # keeps it away from the wake cut and mends it near the cut with a few extra colours.
    NI, NJ = grid.cell_shape
    ic, jc = np.divmod(np.arange(NI * NJ), NJ)
    cell_colours = greedy_colouring(S, preferred=(ic + 3 * jc) % 10)
    cell_colours = np.unique(cell_colours, return_inverse=True)[1]
    P = sp.kron(S, np.ones((4, 4), bool), format="csr")
    P.sort_indices()
    colours = (4 * cell_colours[:, None] + np.arange(4)[None, :]).ravel()
    return P, colours


def coloured_complex_step(func, x0, pattern, colours, *, chunk=8, h=H_STEP):
    """Sparse Jacobian of a complex-safe function by coloured complex step.

    Parameters
    ----------
    func : callable
        ``func(X)`` with ``X`` complex, shape (b, n) -> shape (b, m); must act row by row.
    x0 : ndarray, shape (n,), real
        Point of linearisation.
    pattern : scipy.sparse.csr_matrix, shape (m, n)
        Structural nonzeros of the Jacobian (sorted indices).
    colours : ndarray of int, shape (n,)
        Column colouring of ``pattern`` (``greedy_colouring``).
    chunk : int
        Colours evaluated per batch.

    Returns
    -------
    scipy.sparse.csr_matrix, shape (m, n)
    """
    n_col = int(colours.max()) + 1
    m = pattern.shape[0]
    Y = np.empty((n_col, m))
    for start in range(0, n_col, chunk):
        ids = np.arange(start, min(start + chunk, n_col))
        X = np.tile(x0.astype(complex), (ids.size, 1))
        X += 1j * h * (colours[None, :] == ids[:, None])
        Y[ids] = func(X).imag / h
    rows = np.repeat(np.arange(m), np.diff(pattern.indptr))
    data = Y[colours[pattern.indices], rows]
    return sp.csr_matrix((data, pattern.indices.copy(), pattern.indptr.copy()), shape=pattern.shape)


def jacobian(grid, q, flow, *, face_velocity=None, source=None, scheme=None, chunk=8):
    """Exact Jacobian ``dR/dq`` of ``cfd.euler.residual``.

    Parameters
    ----------
    grid : Grid
    q : ndarray, shape (ni-1, nj-1, 4), real
    flow : FlowCondition
    face_velocity, source, scheme
        As for ``residual`` (``source`` does not depend on ``q`` and drops out).
    chunk : int
        Colours per batched residual evaluation (memory against speed).

    Returns
    -------
    scipy.sparse.csr_matrix, shape (4N, 4N)
        Flat ordering of ``q.ravel()``: ``4 * (ic * (nj-1) + jc) + k``. With ``scheme.vortex`` the
        circulation of the far-field vortex is held at its value for ``q`` (its rank-one term is left
        out, so the matrix is then not exact in the far-field rows).

    Raises
    ------
    FlowConditionError
        ``chunk`` not a whole number >= 1; ``q`` not real or holding NaN or inf; as :func:`cfd.residual`.
    MeshError
        As :func:`cfd.residual` (``q`` or ``face_velocity`` of the wrong shape, ``grid`` not a grid), checked by the
        same function (:func:`cfd.euler.check_input`); ``q`` a batch of states (one state only).
    """
    scheme = DEFAULT_SCHEME if scheme is None else scheme
    n = whole_number(chunk)
    if n is None or n < 1:
        raise FlowConditionError(f"chunk must be a whole number >= 1 (colours per batched residual, default 8); got "
                                 f"{chunk!r}")
    chunk = n
    q_given, q = q, real_array(q)   # None for text, and for complex (it lost its imaginary part, a ComplexWarning)
    if q is None:
        raise FlowConditionError(f"q must be an array of real conserved states; got {kind_of(q_given)}")
    check_input(grid, q, flow, scheme, face_velocity, None)   # residual's checks: the types and the shapes
    if q.shape != grid.cell_shape + (4,):   # a batch of states: residual takes it, the Jacobian is of one state
        raise MeshError(f"q has shape {q.shape}; the Jacobian is of one state: this grid needs "
                        f"{grid.cell_shape + (4,)}")
    if not np.all(np.isfinite(q)):
        raise FlowConditionError("q contains NaN or inf: the Jacobian of such a state is NaN (with NumPy's warnings); "
                                 "linearise about a converged, finite steady state (cfd.solve_steady)")
    shape = q.shape
    circulation = None
    if scheme.vortex:
        g = flow.gamma
        p = (g - 1.0) * (q[..., 3] - 0.5 * (q[..., 1] ** 2 + q[..., 2] ** 2) / q[..., 0])
        circulation = lift_coefficient(grid, p, flow)
    P, colours = state_pattern(grid)

    def func(X):
        R = residual(grid, X.reshape((-1,) + shape), flow, face_velocity=face_velocity, scheme=scheme,
                     circulation=circulation)
        return R.reshape(X.shape[0], -1)

    return coloured_complex_step(func, q.ravel(), P, colours, chunk=chunk)


def residual_derivative(grid, q, flow, direction, *, face_velocity=None, scheme=None, h=H_STEP):
    """Directional derivative of ``R`` with respect to the face velocities, by complex step.

    Parameters
    ----------
    grid, q, flow, scheme
        As for ``residual``.
    direction : tuple (dwi, dwj)
        Perturbation of the face velocities, shapes (..., 2, ni, nj-1) and (..., 2, ni-1, nj); leading
        axes are a batch (several directions at once).
    face_velocity : tuple (wi, wj) or None
        Point of linearisation (zero if None).

    Returns
    -------
    ndarray, shape (..., ni-1, nj-1, 4)
        ``dR/dw . direction``. (``dR/dsource`` is minus the identity.)
    """
    dwi, dwj = (np.asarray(d) for d in direction)
    ni, nj = grid.shape
    wi0 = np.zeros((2, ni, nj - 1)) if face_velocity is None else np.asarray(face_velocity[0])
    wj0 = np.zeros((2, ni - 1, nj)) if face_velocity is None else np.asarray(face_velocity[1])
    wi = wi0 + 1j * h * dwi
    wj = wj0 + 1j * h * dwj
    batch = np.broadcast_shapes(wi.shape[:-3], wj.shape[:-3])
    qc = np.broadcast_to(np.asarray(q, dtype=complex), batch + q.shape)
    return residual(grid, qc, flow, face_velocity=(wi, wj), scheme=scheme).imag / h
