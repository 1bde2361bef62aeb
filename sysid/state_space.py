"""State-space models on the unit circle: evaluation of ``G(z) = D + C (zI - A)^-1 B`` and the fast
unconstrained least squares of ``B`` and ``D`` for fixed ``A`` and ``C`` (numpy; used by the order sweep, the
subspace step's plain refit and quick checks; the constrained refits are in :mod:`sysid.refit`)."""

from __future__ import annotations

import numpy as np

__all__ = ["eigen_parts", "modal_form", "shifted_solve", "resolvent_C", "lstsq_bd_phi", "lstsq_bd", "evaluate_ss"]

#: Largest 1-norm condition number of the eigenvector matrix for which the modal (eigenvalue) form is used
#: to evaluate C (zI - A)^-1; beyond it the Schur form is used (:func:`shifted_solve`, backward stable).
_MODAL_COND_MAX = 1e6


def eigen_parts(A: np.ndarray):
    """The eigendecomposition of ``A`` when it is diagonalisable and its eigenvectors well conditioned.

    Parameters
    ----------
    A : ndarray, shape (n, n)

    Returns
    -------
    tuple or None
        ``(lam, V, V^-1)``: eigenvalues (n,), eigenvectors (n, n) and their inverse (n, n), with
        ``A = V diag(lam) V^-1``; None when ``n = 0``, ``V`` is singular or its 1-norm condition number exceeds
        ``_MODAL_COND_MAX``. Depends on ``A`` only: compute it once per state matrix and pass it to
        :func:`modal_form` or :func:`evaluate_ss` (same arithmetic, same results).
    """
    if A.shape[0] == 0:
        return None
    lam, V = np.linalg.eig(A)
    try:
        Vinv = np.linalg.inv(V)
    except np.linalg.LinAlgError:
        return None
    cond = np.linalg.norm(V, 1) * np.linalg.norm(Vinv, 1)
    if not np.isfinite(cond) or cond > _MODAL_COND_MAX:
        return None
    return lam, V, Vinv


def modal_form(A: np.ndarray, C: np.ndarray, eig=None):
    """The modal form of ``(A, C)`` when ``A`` is diagonalisable and its eigenvectors well conditioned.

    Parameters
    ----------
    A : ndarray, shape (n, n)
    C : ndarray, shape (p, n)
    eig : tuple, None or False, optional
        :func:`eigen_parts` of ``A`` precomputed (None: computed here; False: no modal form).

    Returns
    -------
    tuple or None
        ``(lam, C V, V^-1)``: eigenvalues (n,), (p, n) and (n, n) with ``A = V diag(lam) V^-1``; None when
        ``n = 0``, ``V`` is singular or its 1-norm condition number exceeds ``_MODAL_COND_MAX``.
    """
    if eig is None:
        eig = eigen_parts(A)
    if not eig:
        return None
    lam, V, Vinv = eig
    return lam, C @ V, Vinv


def shifted_solve(A: np.ndarray, B: np.ndarray, z: np.ndarray) -> np.ndarray:
    """``(z_k I - A)^-1 B`` for all k through the complex Schur form ``A = U T U^H``.

    One Schur decomposition (``O(n^3)``), then a back substitution in ``z_k I - T`` vectorised over the points
    (``O(K n^2 m)``): backward stable like one LU per point (``O(K n^3)``), which it replaces where the
    eigenvectors are too ill conditioned for the modal form (a 55-state model at 2048 points: about 10 ms
    against 130 ms).

    Parameters
    ----------
    A : ndarray, shape (n, n)
    B : ndarray, shape (n, m)
    z : ndarray, complex, shape (K,)
        Points of the complex plane.

    Returns
    -------
    ndarray, complex, shape (K, n, m)
        Entries are inf or NaN (without a warning) at a point that is an eigenvalue of ``A``: callers check
        ``np.isfinite`` and say what it means for them.
    """
    import scipy.linalg

    z = np.asarray(z, dtype=complex).reshape(-1)
    n, m = B.shape
    K = z.size
    if n == 0:
        return np.zeros((K, 0, m), dtype=complex)
    T, U = scipy.linalg.schur(np.asarray(A, dtype=complex), output="complex")
    Y = U.conj().T @ B  # (n, m)
    X = np.empty((n, K, m), dtype=complex)  # state index first: each step is one matrix-vector product
    Xf = X.reshape(n, K * m)
    with np.errstate(divide="ignore", invalid="ignore"):
        for i in range(n - 1, -1, -1):
            r = Y[i][None, :] + (T[i, i + 1:] @ Xf[i + 1:]).reshape(K, m)  # (z I - T) is -T off the diagonal
            X[i] = r / (z - T[i, i])[:, None]
        return (U @ Xf).reshape(n, K, m).transpose(1, 0, 2)


def resolvent_C(A: np.ndarray, C: np.ndarray, z: np.ndarray, modal=None) -> np.ndarray:
    """``C (z_k I - A)^-1`` for all k.

    Uses the modal form ``(C V) diag(1 / (z - lam)) V^-1`` (``O(K p n^2)``) when the eigenvector matrix is
    well conditioned, else the Schur form (:func:`shifted_solve` of ``A^T``, ``O(K p n^2)``).

    Parameters
    ----------
    A : ndarray, shape (n, n)
    C : ndarray, shape (p, n)
    z : ndarray, complex, shape (K,)
        Points of the z-plane (``exp(i omega_d)`` on the unit circle).
    modal : tuple, None or False
        :func:`modal_form` precomputed; None computes it; False forces the solve.

    Returns
    -------
    ndarray, complex, shape (K, p, n)
    """
    if modal is None:
        modal = modal_form(A, C)
    if modal:
        lam, CV, Vinv = modal
        return (CV[None, :, :] / (z[:, None, None] - lam[None, None, :])) @ Vinv
    # C (zI - A)^-1 = ((zI - A)^-T C^T)^T
    return np.swapaxes(shifted_solve(np.asarray(A).T, np.asarray(C).T, z), 1, 2)


def lstsq_bd_phi(phi: np.ndarray, G: np.ndarray, weights: np.ndarray | None = None):
    """Unconstrained least-squares ``B, D`` with ``C (z_k I - A)^-1 B + D ~ G_k``, from the regressor.

    Parameters
    ----------
    phi : ndarray, complex, shape (K, p, n)
        :func:`resolvent_C` at the data's points.
    G : ndarray, complex, shape (p, m, K)
        The data.
    weights : ndarray, shape (K,), optional
        Per-frequency weights of the squared residuals.

    Returns
    -------
    B : ndarray, shape (n, m)
    D : ndarray, shape (p, m)
    """
    p, m, K = G.shape
    n = phi.shape[2]
    X = np.concatenate([phi, np.broadcast_to(np.eye(p), (K, p, p))], axis=2).reshape(K * p, n + p)
    Y = G.transpose(2, 0, 1).reshape(K * p, m)
    if weights is not None:
        sw = np.sqrt(np.repeat(np.asarray(weights, dtype=float), p))[:, None]
        X, Y = X * sw, Y * sw
    Xr = np.concatenate([X.real, X.imag], axis=0)
    Yr = np.concatenate([Y.real, Y.imag], axis=0)
    theta = np.linalg.lstsq(Xr, Yr, rcond=None)[0]
    return theta[:n], theta[n:]


def lstsq_bd(A: np.ndarray, C: np.ndarray, z: np.ndarray, G: np.ndarray,
             weights: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Unconstrained real least squares for ``B``, ``D`` (McKelvey step 6), closed form in NumPy.

    Minimises ``sum_k w_k ||G_k - D - C (z_k I - A)^-1 B||_F^2`` with real ``B`` (n, m), ``D`` (p, m).
    All input columns share one regressor, so this is a single ``lstsq`` with ``m`` right-hand sides.

    Parameters
    ----------
    A : (n, n), C : (p, n) real
    z : (K,) complex, points on the unit circle
    G : (p, m, K) complex
    weights : (K,) nonnegative, optional

    Returns
    -------
    B : ndarray (n, m), D : ndarray (p, m)
    """
    return lstsq_bd_phi(resolvent_C(np.asarray(A, float), np.asarray(C, float), np.asarray(z, complex)),
                         np.asarray(G, complex), weights)


def evaluate_ss(A: np.ndarray, B: np.ndarray, C: np.ndarray, D: np.ndarray, z: np.ndarray, eig=None) -> np.ndarray:
    """``G(z_k) = C (z_k I - A)^-1 B + D`` for all k: shape (p, m, K).

    In the modal form (:func:`modal_form`) the products are ``(C V) diag(1 / (z_k - lam)) (V^-1 B)``
    (``O(K p n m)``, against ``O(K p n^2)`` for :func:`resolvent_C` then ``B``); else the Schur form
    (:func:`shifted_solve`, ``O(K n^2 m)``).
    ``eig``: :func:`eigen_parts` of ``A`` precomputed (optional).
    """
    z = np.asarray(z, dtype=complex).reshape(-1)
    modal = modal_form(A, C, eig)
    if modal:
        lam, CV, Vinv = modal
        G = (CV[None, :, :] / (z[:, None, None] - lam[None, None, :])) @ (Vinv @ B)  # (K, p, m)
    else:
        G = C[None] @ shifted_solve(A, B, z)
    return (G + D[None]).transpose(1, 2, 0)
