"""The solvers behind :mod:`sysid.refit`: the column-equilibrated reduction of a regression matrix, the DPP
cvxpy problem compiled once per shape and re-solved by Clarabel (an LRU cache of compiled problems), and the
closed-form null-space method that serves as the oracle (see :mod:`sysid.refit`'s Numerics)."""

from __future__ import annotations

import threading
import warnings
from collections import OrderedDict

import numpy as np

from .errors import SolverError

__all__ = ["reduce_regression", "solve_compiled", "null_space_solve", "equality_null_space", "clear_refit_cache"]

#: Relative singular-value floor of the (column-scaled) regression matrix (invisible ridge).
_RCOND = 1e-13
#: Maximum number of compiled cvxpy problems kept (least recently used are dropped).
_CACHE_SIZE = 64
_PROBLEM_CACHE: "OrderedDict[tuple, _CompiledRefit]" = OrderedDict()
_CACHE_LOCK = threading.Lock()


def reduce_regression(Phi):
    """Column-equilibrated SVD of Phi = (Qr Ur) S V^T: returns ((Qr, Ur), S, S~, M), theta = M @ y."""
    s = np.linalg.norm(Phi, axis=0)
    s[s == 0] = 1.0
    Qr, R = np.linalg.qr(Phi / s)  # tall-skinny: QR first, then the SVD of the small triangle
    Ur, S, Vt = np.linalg.svd(R)
    eps = _RCOND * (S[0] if S.size else 1.0)
    St = np.sqrt(S**2 + eps**2)
    M = (Vt.T / St) / s[:, None]
    return (Qr, Ur), S, St, M


class _CompiledRefit:
    """A DPP cvxpy problem ``min sum_j ||y_j - h_j||^2 s.t. Q_j^T y_j = f_j`` built once per shape."""

    def __init__(self, N: int, c: int, m: int):
        import cvxpy as cp

        self.y = [cp.Variable(N, name=f"y{j}") for j in range(m)]
        self.h = [cp.Parameter(N, name=f"h{j}") for j in range(m)]
        self.Q = [cp.Parameter((N, c), name=f"Q{j}") for j in range(m)]
        self.f = [cp.Parameter(c, name=f"f{j}") for j in range(m)]
        obj = cp.Minimize(sum(cp.sum_squares(self.y[j] - self.h[j]) for j in range(m)))
        cons = [self.Q[j].T @ self.y[j] == self.f[j] for j in range(m)]
        self.problem = cp.Problem(obj, cons)
        assert self.problem.is_dpp()
        self.n_solves = 0
        self.lock = threading.Lock()  # Parameter values are shared state: one solve at a time


def clear_refit_cache() -> None:
    """Forget all compiled refit problems (the next constrained refit compiles again)."""
    with _CACHE_LOCK:
        _PROBLEM_CACHE.clear()


def _get_compiled(key, N, c, m):
    prob = _PROBLEM_CACHE.get(key)
    reused = prob is not None
    if prob is None:
        prob = _CompiledRefit(N, c, m)
        _PROBLEM_CACHE[key] = prob
        while len(_PROBLEM_CACHE) > _CACHE_SIZE:
            _PROBLEM_CACHE.popitem(last=False)
    else:
        _PROBLEM_CACHE.move_to_end(key)
    return prob, reused


def solve_compiled(key, hs, Qs, fs, m, N, c):
    """Solve the cached DPP problem of shape ``key`` with Clarabel: ``ys`` (m arrays (N,)), status, reused.

    The problem is homogeneous in ``(h, f)``, so it is solved for ``h / s`` and ``f / s`` with ``s`` their largest
    magnitude and the answer scaled back: Clarabel's tolerances are absolute, and data in other units than
    order one (1e12: "constraints may be inconsistent"; 1e-9: errors of 5e-9 instead of round-off, measured)
    would otherwise meet them differently."""
    import cvxpy as cp

    s = max([float(np.abs(v).max()) for v in list(hs) + list(fs) if np.size(v)] + [0.0])
    s = s if np.isfinite(s) and s > 0 else 1.0
    with _CACHE_LOCK:
        comp, reused = _get_compiled(key, N, c, m)
    with comp.lock:
        for j in range(m):
            comp.h[j].value = hs[j] / s
            comp.Q[j].value = Qs[j]
            comp.f[j].value = fs[j] / s
        try:
            comp.problem.solve(
                solver=cp.CLARABEL, tol_gap_abs=1e-12, tol_gap_rel=1e-12, tol_feas=1e-12, max_iter=200
            )
        except cp.error.SolverError as exc:  # pragma: no cover - depends on solver internals
            raise SolverError(
                f"Clarabel failed on the B/D refit ({exc}). Try solver='numpy', fewer constraints or a lower order."
            ) from exc
        status = comp.problem.status
        ys = [None if y.value is None else s * np.array(y.value, dtype=float) for y in comp.y]
        comp.n_solves += 1
    if status not in ("optimal", "optimal_inaccurate") or any(y is None for y in ys):
        raise SolverError(
            f"Clarabel returned status {status!r} on the B/D refit. The constraints may be inconsistent; "
            "try solver='numpy', drop a constraint or lower the order."
        )
    if status == "optimal_inaccurate":
        warnings.warn(
            "Clarabel reported 'optimal_inaccurate' on the B/D refit; the result is polished onto the "
            "constraints but its cost may be slightly above optimal.",
            RuntimeWarning,
            stacklevel=4,
        )
    return ys, status, reused


def equality_null_space(E, f):
    """The solutions of ``E y = f`` as ``y0 + Z w``: ``E^T = [U1 U2] [R; 0]`` (complete QR), ``y0 = U1 R^-T f``
    (the least-norm solution), ``Z = U2`` (orthonormal, ``E Z = 0``).

    Parameters
    ----------
    E : ndarray, shape (c, N), real, ``c >= 1``; f : ndarray, shape (c,)

    Returns
    -------
    y0 : ndarray, shape (N,); Z : ndarray, shape (N, N - c); r_diag : ndarray, shape (c,)
        ``|diag R|``: a rank test for ``E`` (a value near 0 relative to the largest: ``E`` rank deficient).
    """
    c = E.shape[0]
    U, R = np.linalg.qr(E.T, mode="complete")
    R = R[:c, :c]
    return U[:, :c] @ np.linalg.solve(R.T, f), U[:, c:], np.abs(np.diag(R))


def null_space_solve(Phi, g, E, f):
    """Closed-form constrained LS: theta = theta_p + Z w, E theta_p = f, E Z = 0 (the oracle)."""
    if E.shape[0] == 0:
        return np.linalg.lstsq(Phi, g, rcond=None)[0]
    theta_p, Z, _ = equality_null_space(E, f)
    if Z.shape[1] == 0:
        return theta_p
    w = np.linalg.lstsq(Phi @ Z, g - Phi @ theta_p, rcond=None)[0]
    return theta_p + Z @ w
