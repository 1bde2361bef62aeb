"""Block orthonormalisation for the fast sweep's basis (:mod:`cfd.sweep.basis`): a growable column buffer,
Cholesky QR, block Gram-Schmidt with re-orthogonalisation and rank-revealing deflation, and the nested extension
that keeps the coarse basis a leading subset of the fine one (the error estimate of :mod:`cfd.sweep`)."""

import numpy as np
import scipy.linalg as sla

__all__ = ["ColumnBuffer", "basis_coefficients", "cholesky_qr", "orthonormalise", "nested_extension"]


class ColumnBuffer:
    """The columns of a growing ``(n, m)`` complex matrix, held in one Fortran-ordered buffer.

    Appending copies only the new columns (the buffer doubles when full), and :attr:`cols` is a view, so
    products with the whole basis go straight to BLAS without copying it.
    """

    def __init__(self, n, capacity):
        self._buf = np.zeros((n, max(int(capacity), 1)), complex, order="F")
        self.size = 0

    @property
    def cols(self):
        return self._buf[:, :self.size]

    def extend(self, X):
        k = X.shape[1]
        if self.size + k > self._buf.shape[1]:
            grown = np.zeros((self._buf.shape[0], max(2 * self._buf.shape[1], self.size + k)), complex, order="F")
            grown[:, :self.size] = self.cols
            self._buf = grown
        self._buf[:, self.size:self.size + k] = X
        self.size += k


def basis_coefficients(Q, X):
    """``Q^H X`` without a conjugated copy of the tall ``Q``: ``(X^H Q)^H``, shape (m, k)."""
    return (X.conj().T @ Q).conj().T


def cholesky_qr(X):
    """``X = Q R`` for nearly orthonormal columns (after Gram-Schmidt): two BLAS-3 products instead of
    Householder's column sweeps (``R`` upper triangular, shape (k, k))."""
    R = sla.cholesky(X.conj().T @ X, lower=False)
    return X @ sla.solve_triangular(R, np.eye(R.shape[0]), lower=False), R


def orthonormalise(X, Q=None, tol=1e-12):
    """Orthonormalise the columns of ``X`` against the orthonormal columns ``Q`` and among themselves.

    Block classical Gram-Schmidt twice (a third pass when a kept column lost more than 90 % of its norm to
    ``Q``), then a rank-revealing QR that drops the directions already in the span.

    Parameters
    ----------
    X : ndarray, shape (n, k)
    Q : ndarray, shape (n, m), optional
    tol : float
        Columns whose norm falls below ``tol`` times their original norm are dropped (already in span).

    Returns
    -------
    Qx : ndarray, shape (n, k') with k' <= k
        Orthonormal new columns, orthogonal to ``Q``.
    coeff : ndarray, shape (m, k)
        ``X = Q coeff + Qx Rx`` (to the dropped parts).
    Rx : ndarray, shape (k', k)
    """
    norm0 = np.linalg.norm(X, axis=0)
    norm0 = np.where(norm0 > 0.0, norm0, 1.0)
    X = np.array(X, dtype=complex) / norm0            # unit columns: the deflation test is relative to each
    m = 0 if Q is None else Q.shape[1]
    coeff = np.zeros((m, X.shape[1]), complex)

    def project(Y):                                   # Y -= Q Q^H Y in place; returns Q^H Y
        c = basis_coefficients(Q, Y)
        Y -= Q @ c
        return c

    for _ in range(2 if m else 0):
        coeff += project(X)
    Qx, Rx, piv = sla.qr(X, mode="economic", pivoting=True)
    r = int(np.sum(np.abs(np.diag(Rx)) > tol))
    Qx, Rx = Qx[:, :r], Rx[:r][:, np.argsort(piv)]
    if m and r and abs(Rx[r - 1, piv[r - 1]]) < 0.1:  # small kept directions: one more pass
        c = project(Qx)
        Qx, Rk = cholesky_qr(Qx)
        coeff += c @ Rx
        Rx = Rk @ Rx
    return Qx, coeff * norm0, Rx * norm0


def nested_extension(P, sizes, Q, tol=1e-12):
    """New basis columns from one shift's Krylov blocks ``P``, block by block in their order (nested).

    Parameters
    ----------
    P : ndarray, shape (n, k)
        The shift's Krylov blocks, orthonormal among themselves.
    sizes : list of int
        Columns per block (``sum(sizes) == k``).
    Q : ndarray, shape (n, m) or None
        The basis so far (orthonormal).
    tol : float
        A column is dropped when less than ``tol`` of its norm lies outside the span of ``Q`` and the
        earlier blocks' new columns.

    Returns
    -------
    Qn : ndarray, shape (n, k')
        Orthonormal, orthogonal to ``Q``. The columns of each block follow those of the earlier blocks, so
        leaving out the last ones gives the basis without the shift's last block.
    kept : list of int
        New columns per block.
    """
    Ps = np.array(P, dtype=complex)
    if Q is not None and Q.shape[1]:
        for _ in range(2):                        # block Gram-Schmidt against the whole basis at once (BLAS-3)
            Ps -= Q @ basis_coefficients(Q, Ps)
    cols, kept, start = [], [], 0
    for size in sizes:                            # then each block against the earlier new columns (small)
        X = Ps[:, start:start + size]
        start += size
        N = np.hstack(cols) if cols else None
        for _ in range(2 if cols else 0):
            X = X - N @ basis_coefficients(N, X)
        Qx, Rx, piv = sla.qr(X, mode="economic", pivoting=True)
        r = int(np.sum(np.abs(np.diag(Rx)) > tol))   # relative to the unit column before any projection
        cols.append(Qx[:, :r])
        kept.append(r)
    Qn = np.hstack(cols)
    if Qn.shape[1] and Q is not None and Q.shape[1]:
        Qn -= Q @ basis_coefficients(Q, Qn)             # a third pass for directions that were mostly in span Q
        Qn, _ = cholesky_qr(Qn)                   # unpivoted: keeps the block order
    return Qn, kept
