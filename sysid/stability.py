"""Stabilisation of an identified discrete state matrix.

Two methods, both returning a real matrix with spectral radius below ``1 - margin``:

``"lmi"`` -- Lacy & Bernstein (IEEE TAC 48(7), 2003), a semidefinite program solved by cvxpy + Clarabel.
    Variables ``P = P^T`` (n, n) and ``Q`` (n, n); with ``rho = 1 - margin``::

        minimise    || Gamma1 Q - Gamma2 P ||_F      (shift equation Gamma1 A = Gamma2 given)
                 or || A P - Q ||_F                  (otherwise)
        subject to  [[rho^2 P - delta I, Q], [Q^T, P]] >> 0,   trace(P) = n,

    and ``A_new = Q P^-1``. Convention: ``A`` acts on the right of the extended observability matrix
    (``Gamma1 A = Gamma2``), and ``Q = A_new P``. By a Schur complement (``P >> 0`` from the lower block)
    the LMI is ``rho^2 P - A_new P A_new^T >> delta I``, a Lyapunov inequality for ``A_new^T``: for a left
    eigenvector ``v^H A_new = lambda v^H``, ``(rho^2 - |lambda|^2) v^H P v > 0``, so ``|lambda| < rho``.
    (``P^-1 Q = P^-1 (Q P^-1) P`` is similar to ``Q P^-1``, hence equally stable, but it is the same map in
    another state basis and does not approximate ``A``: the objective ``||(A - Q P^-1) P||_F`` is about
    ``Q P^-1``.)
    ``P`` is defined up to a positive scale; ``trace(P) = n`` fixes it so that ``delta`` (default 1e-6) is a
    relative strictness, and the data of the objective are normalised to unit Frobenius norm. When the
    shift equation is given, the objective is reduced to a ``2n x 2n`` triangular factor ``R`` of
    ``[Gamma1, -Gamma2]`` (``||[Gamma1, -Gamma2] [Q; P]||_F = ||R [Q; P]||_F``), so the SDP size does not
    depend on the number of Hankel rows. A matrix that is already stable with the margin is returned as is
    (no SDP), unless ``force=True``.

    By default (``subspace=True``) the SDP is solved on the invariant subspace of the offending
    eigenvalues only: with the ordered real Schur form ``A = Z [[T11, T12], [0, T22]] Z^T``, ``T11``
    (k x k) holding the eigenvalues of modulus ``>= rho``, the LMI replaces ``T11`` and keeps ``T12``,
    ``T22``. The spectrum of the result is ``eig(T11_new)`` (radius < rho by the LMI) plus the untouched
    ``eig(T22)`` (< rho by construction). In the shift equation ``(Gamma1 Z) T ~= Gamma2 Z`` the first k
    columns involve ``T11`` alone, so the reduced problem is the same SDP with ``Gamma1 Z1`` and
    ``Gamma2 Z1``, and the other columns' residuals do not change. This is a restriction of the full
    SDP (``subspace=False``) at a fraction of the cost: the full SDP has a 2n x 2n PSD cone, Clarabel
    needed 52 s at n = 55 on random data and failed (NumericalError) on lightly damped identified data.
    The full SDP also tends to move every eigenvalue (its objective is weighted by ``P``, which may be
    nearly singular), so it changed A more than reflection did in our tests; the subspace form changed it
    less.

``"reflect"`` -- eigenvalue reflection, the cheap baseline. In the real Schur form ``A = Z T Z^T`` each
    1x1 or 2x2 diagonal block whose eigenvalue has modulus ``r >= rho`` is scaled so that its eigenvalues
    move along their ray to modulus ``rho^2 / r`` (``mode="mirror"``: ``lambda -> rho^2 / conj(lambda)``,
    the inversion in the circle of radius ``rho``) or to ``rho (1 - 1e-9)`` (``mode="circle"``). Scaling a
    diagonal block of a quasi-triangular matrix changes exactly that block's eigenvalues; ``Z T' Z^T``
    stays real.

After either method the input/output matrices should be refitted (``sysid.refit.fit_bd``).
"""

from __future__ import annotations

import time
import warnings
from dataclasses import dataclass
from typing import Mapping

import numpy as np
import scipy.linalg as sla

from .arrays import freeze_array_fields
from .errors import FrequencyDataError, OptionError, SolverError
from .metrics import spectral_radius

__all__ = ["StabiliseResult", "stabilise", "spectral_radius", "is_stable"]


@dataclass(frozen=True)
class StabiliseResult:
    """Result of :func:`stabilise`.

    Attributes
    ----------
    A : ndarray, shape (n, n), real
        Stabilised state matrix (spectral radius < 1 - margin).
    method : str
        ``"lmi"``, ``"reflect"`` or ``"none"`` (input already stable with the margin).
    spectral_radius_before, spectral_radius_after : float
    relative_change : float
        ``||A_new - A||_F / ||A||_F``.
    status : str
        Solver status for ``"lmi"`` (``"optimal"``, ...), ``"reflected"`` or ``"already_stable"``.
    objective : float
        Shift-equation residual ``||Gamma1 A_new - Gamma2||_F`` when gamma1/gamma2 are given, else NaN.
    solve_time : float
        Wall time in seconds.
    """

    A: np.ndarray
    method: str
    spectral_radius_before: float
    spectral_radius_after: float
    relative_change: float
    status: str = ""
    objective: float = float("nan")
    solve_time: float = 0.0

    def __post_init__(self):
        freeze_array_fields(self)   # the arrays of a frozen result are read-only too


def is_stable(A, margin: float = 0.0) -> bool:
    """True when the discrete-time matrix ``A`` has spectral radius strictly below ``1 - margin``."""
    return spectral_radius(A) < 1.0 - margin


def _check(A, margin):
    A = np.asarray(A)
    if np.iscomplexobj(A):
        raise FrequencyDataError("A must be real; got a complex matrix.")
    A = np.asarray(A, dtype=float)
    if A.ndim != 2 or A.shape[0] != A.shape[1] or A.shape[0] == 0:
        raise FrequencyDataError(f"A must be a non-empty square matrix; got shape {A.shape}.")
    if not np.all(np.isfinite(A)):
        raise FrequencyDataError("A contains NaN or inf.")
    if isinstance(margin, (bool, np.bool_)) or np.ndim(margin) != 0 \
            or np.asarray(margin).dtype.kind not in "iuf" or not (0.0 <= float(margin) < 1.0):
        raise OptionError(f"margin must lie in [0, 1); got {margin!r}.")
    return A


def _reflect(A, rho, mode):
    T, Z = sla.schur(A, output="real")
    n = A.shape[0]
    i = 0
    target = rho * (1.0 - 1e-9)
    while i < n:
        two = i + 1 < n and T[i + 1, i] != 0.0
        sl = slice(i, i + 2) if two else slice(i, i + 1)
        blk = T[sl, sl]
        r = float(np.max(np.abs(np.linalg.eigvals(blk))))
        if r >= rho and r > 0:
            new_r = min(rho**2 / r, target) if mode == "mirror" else target
            s = new_r / r
            # eigenvalues of a quasi-triangular T are those of its diagonal blocks: only this one moves
            T[sl, sl] = s * blk
        i += 2 if two else 1
    return Z @ T @ Z.T


def _lmi_sdp(A, rho, G1, G2, delta, solver_opts):
    """Lacy-Bernstein SDP on a k x k problem; returns (A_new, status)."""
    import cvxpy as cp

    n = A.shape[0]
    if G1 is not None:
        R = np.linalg.qr(np.hstack([G1, -G2]), mode="r")  # ||[G1, -G2] X||_F = ||R X||_F
        # ||R X||_F = ||S V^T X||_F; rows with s < 1e-10 s_max (a rank-deficient [G1, -G2], e.g. when the
        # outputs are scaled alike) change the objective by < 1e-10 relative but made Clarabel fail
        _, S, Vt = np.linalg.svd(R, full_matrices=False)
        keep = S > 1e-10 * max(S[0], 1e-300)
        R = S[keep, None] * Vt[keep]
        R = R / max(np.linalg.norm(R), 1e-300)
        R1, R2 = R[:, :n], R[:, n:]
    P = cp.Variable((n, n), symmetric=True)
    Q = cp.Variable((n, n))
    if G1 is not None:
        resid = R1 @ Q + R2 @ P
    else:
        s = max(np.linalg.norm(A, 2), 1e-300)
        resid = (A / s) @ P - Q / s
    lmi = cp.bmat([[rho**2 * P - delta * np.eye(n), Q], [Q.T, P]])
    cons = [0.5 * (lmi + lmi.T) >> 0, cp.trace(P) == n]
    prob = cp.Problem(cp.Minimize(cp.norm(resid, "fro")), cons)
    try:
        with warnings.catch_warnings():
            warnings.filterwarnings("ignore", message="Solution may be inaccurate")
            prob.solve(solver=cp.CLARABEL, **solver_opts)
    except cp.error.SolverError as exc:
        raise SolverError(
            f"Clarabel failed on the stability SDP ({exc}). Try method='reflect' or a lower order."
        ) from exc
    if prob.status not in ("optimal", "optimal_inaccurate") or P.value is None:
        raise SolverError(
            f"stability SDP returned status {prob.status!r}. Try method='reflect', a smaller margin or a lower order."
        )
    if prob.status == "optimal_inaccurate":
        warnings.warn("stability SDP solved inaccurately ('optimal_inaccurate'); the result is checked "
                      "and rescaled if needed.", RuntimeWarning, stacklevel=4)
    Pv = 0.5 * (P.value + P.value.T)
    A_new = np.linalg.solve(Pv.T, Q.value.T).T  # Q P^-1 (P^-1 Q is not certified)
    return A_new, prob.status


def _lmi(A, rho, gamma1, gamma2, delta, solver_opts, subspace):
    n = A.shape[0]
    G1 = G2 = None
    if gamma1 is not None:
        G1 = np.asarray(gamma1, dtype=float)
        G2 = np.asarray(gamma2, dtype=float)
        if G1.ndim != 2 or G1.shape[1] != n or G2.shape != (G1.shape[0], n):
            raise FrequencyDataError(
                f"gamma1 and gamma2 must both have shape (rows, n = {n}); got {G1.shape} and {G2.shape}."
            )
    if not subspace:
        return _lmi_sdp(A, rho, G1, G2, delta, solver_opts)
    # ordered real Schur form: eigenvalues with |lambda| >= rho first (T11, k x k), the rest stay untouched
    T, Z, k = sla.schur(A, output="real", sort=lambda re, im: np.hypot(re, im) >= rho)
    if k == 0:  # nothing outside (only reached with force=True): the full SDP is what was asked for
        return _lmi_sdp(A, rho, G1, G2, delta, solver_opts)
    Z1 = Z[:, :k]
    if G1 is not None:
        # (G1 Z) T ~= G2 Z; its first k columns involve only T11: (G1 Z1) T11 ~= G2 Z1
        T11, status = _lmi_sdp(T[:k, :k], rho, G1 @ Z1, G2 @ Z1, delta, solver_opts)
    else:
        T11, status = _lmi_sdp(T[:k, :k], rho, None, None, delta, solver_opts)
    T = T.copy()
    T[:k, :k] = T11
    return Z @ T @ Z.T, status


def stabilise(A, *, method: str = "lmi", margin: float = 1e-3, gamma1=None, gamma2=None, delta: float = 1e-6,
              mode: str = "mirror", subspace: bool = True, force: bool = False,
              solver_opts: dict | None = None) -> StabiliseResult:
    """Return a state matrix with spectral radius below ``1 - margin``, close to ``A``.

    Parameters
    ----------
    A : ndarray, shape (n, n), real
        Discrete state matrix, typically the least-squares solution of ``gamma1 A = gamma2``.
    method : {"lmi", "reflect"}
        See the module docstring.
    margin : float
        Required stability margin, ``0 <= margin < 1``; the result has radius ``< 1 - margin``.
    gamma1, gamma2 : ndarray, shape (rows, n), optional
        Shift-equation matrices (``gamma1 @ A ~= gamma2``); used by ``"lmi"`` for its objective.
    delta : float
        LMI strictness relative to ``trace(P) = n`` (``"lmi"`` only).
    mode : {"mirror", "circle"}
        Where ``"reflect"`` puts the offending eigenvalues.
    subspace : bool
        ``"lmi"`` only. True (default): solve the SDP on the invariant subspace of the eigenvalues with
        ``|lambda| >= 1 - margin`` only (see the module docstring); False: the full n x n SDP (Clarabel
        took 52 s for a random n = 55 problem, as the 2n x 2n PSD cone makes its KKT system dense; on the
        lightly damped N_r = 55 benchmark data it stopped with NumericalError after about 11 s with the
        shift-equation objective and took 80 s with ``||A P - Q||_F``; use it for small n).
    force : bool
        Run the method even when ``A`` is already stable with the margin.
    solver_opts : dict, optional
        Extra keyword arguments for Clarabel.

    Returns
    -------
    StabiliseResult

    Raises
    ------
    SolverError
        The SDP failed.
    FrequencyDataError
        Malformed ``A`` or gamma matrices.
    OptionError
        ``method``, ``mode``, ``margin`` outside ``[0, 1)``, ``delta`` negative, ``subspace`` / ``force`` not
        booleans.

    Notes
    -----
    If the SDP solution misses the margin by round-off (Clarabel's accuracy is about 1e-8), it is
    shrunk radially by the smallest factor that restores it; this is reported in ``status``.
    """
    t0 = time.perf_counter()
    A = _check(A, margin)
    if isinstance(delta, (bool, np.bool_)) or not isinstance(delta, (int, float, np.integer, np.floating)) \
            or not (np.isfinite(delta) and delta >= 0):
        raise OptionError(f"delta must be a nonnegative number (the LMI's strictness, default 1e-6); got {delta!r}.")
    for name, flag in (("subspace", subspace), ("force", force)):
        if not isinstance(flag, (bool, np.bool_)):
            raise OptionError(f"{name} must be True or False; got {flag!r}.")
    if (gamma1 is None) != (gamma2 is None):
        raise OptionError("give both gamma1 and gamma2, or neither.")
    if method not in ("lmi", "reflect"):   # before the early return for a stable A, which passed any method
        raise OptionError(f"method must be 'lmi' or 'reflect'; got {method!r}.")
    if mode not in ("mirror", "circle"):
        raise OptionError(f"mode must be 'mirror' or 'circle'; got {mode!r}.")
    if solver_opts is not None and not isinstance(solver_opts, Mapping):
        raise OptionError(f"solver_opts must be a dict of Clarabel settings or None; got {solver_opts!r}.")
    rho = 1.0 - margin
    r0 = spectral_radius(A)
    nrm = max(np.linalg.norm(A), 1e-300)
    gam_obj = (lambda An: float(np.linalg.norm(np.asarray(gamma1) @ An - np.asarray(gamma2)))) if gamma1 is not None \
        else (lambda An: float("nan"))
    if r0 < rho and not force:
        return StabiliseResult(A=A.copy(), method="none", spectral_radius_before=r0, spectral_radius_after=r0,
                               relative_change=0.0, status="already_stable", objective=gam_obj(A),
                               solve_time=time.perf_counter() - t0)
    if method == "reflect":
        A_new = _reflect(A, rho, mode)
        status = "reflected"
    else:
        opts = {"tol_gap_abs": 1e-9, "tol_gap_rel": 1e-9, "tol_feas": 1e-9}
        opts.update(solver_opts or {})
        A_new, status = _lmi(A, rho, gamma1, gamma2, delta, opts, subspace)
    r1 = spectral_radius(A_new)
    if r1 >= rho:  # round-off at the boundary: shrink radially, by as little as possible
        A_new = A_new * (rho * (1.0 - 1e-9) / r1)
        r1 = spectral_radius(A_new)
        status += "+rescaled"
    return StabiliseResult(
        A=A_new,
        method=method,
        spectral_radius_before=r0,
        spectral_radius_after=r1,
        relative_change=float(np.linalg.norm(A_new - A) / nrm),
        status=status,
        objective=gam_obj(A_new),
        solve_time=time.perf_counter() - t0,
    )
