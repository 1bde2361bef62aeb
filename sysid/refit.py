"""Convex refits of the input/output matrices of a discrete state-space model.

Given the state matrix ``A`` and one of the output/input matrices (``C`` or ``B``) of

    G(z) = C (z I - A)^-1 B + D,

the remaining matrices enter ``G`` linearly, so fitting them to frequency-response samples
``G_k = G(z_k)``, ``z_k = exp(1j omega_d_k)``, is a (weighted) linear least-squares problem in real
unknowns (step 6 of McKelvey's algorithms; real and imaginary parts are stacked). Two exact linear
equality constraints can be added, which is what makes the refit more than least squares:

- DC gain (``dc_gain``, ``z = 1``):          C (I - A)^-1 B + D = G_0,
- Nyquist value (``feedthrough``, ``z = -1``): C (-I - A)^-1 B + D = D_c, the continuous feedthrough under
  the bilinear map (``omega = infinity``); 0 for the aerofoil-gust systems. It is supplied, never solved for.

Numerics
--------
For every input column ``j`` the unknowns are ``theta_j = [B[:, j]; D[:, j]]`` (``n + p`` reals) and
the weighted regression matrix ``Phi_j`` (``2 K p`` rows) is column-equilibrated and factorised by a thin
SVD, ``Phi_j = U S V^T``. In the reduced coordinates ``y = S~ V^T theta`` (``S~ = sqrt(S^2 + eps^2)``,
``eps = 1e-13 S_max`` -- an invisible ridge that only matters when ``Phi`` is numerically rank deficient)
the cost is ``||y - h||^2 + const`` with an identity regression matrix, and the constraints become
``Q_e^T y = f^`` with orthonormal ``Q_e``. Both are perfectly conditioned, whatever the scaling of ``A``.

Two solvers, same problem:

- ``solver="clarabel"`` (default; what :func:`sysid.identify` uses for constrained refits): a cvxpy
  problem solved by Clarabel. It is built ONCE per shape (``n, m, p, K``, constraint set, weight shape)
  with cvxpy Parameters (``h``, ``Q_e``, ``f^``), so it is DPP and a re-solve only assigns Parameter values
  (no recompilation). After the solve the constraint residual is measured in the original units; if it
  exceeds ``tol`` (1e-10 by default) the solution is polished by the exact orthogonal projection onto the
  constraint set in the reduced coordinates (the minimum-cost correction), reported as ``polished=True``.
  Without constraints the minimiser is ``y = h`` in closed form and no solver is called
  (``solver="closed-form"`` in the result).
- ``solver="numpy"``: closed-form null-space method in the original coordinates (particular solution of
  the constraints plus a least-squares fit in the null space of the constraint matrix). It shares no code
  with the reduced-coordinate path and serves as the oracle in the tests.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from .arrays import freeze_array_fields
from .data_checks import check_constraint, check_tolerance, check_weights
from .errors import ConstraintError, FrequencyDataError, FrequencyGridError, OptionError
from .refit_solvers import clear_refit_cache, null_space_solve, reduce_regression, solve_compiled  # noqa: F401
from .state_space import evaluate_ss, modal_form, resolvent_C

__all__ = [
    "BDFit",
    "CDFit",
    "AlternatingFit",
    "fit_bd",
    "fit_cd",
    "fit_alternating",
    "frequency_response",
    "clear_refit_cache",
]

#: Distance of an eigenvalue of ``A`` to ``z = +-1`` below which a constraint there is refused.
POLE_TOL = 1e-8
#: Largest ``| |z| - 1 |`` of a sample point ``z = exp(1j omega_d)`` (round-off of the exponential is 1e-16).
UNIT_CIRCLE_TOL = 1e-9


# --------------------------------------------------------------------------------------------- results
@dataclass(frozen=True)
class BDFit:
    """Result of :func:`fit_bd`.

    Attributes
    ----------
    B : ndarray, shape (n, m), real
    D : ndarray, shape (p, m), real
    residual : float
        Weighted least-squares cost ``sum w |G_k - G_model(z_k)|^2`` (weights as given; 1 if none).
    status : str
        Solver status (``"optimal"``, ``"optimal_inaccurate"``, ...).
    solver : str
        ``"clarabel"``, ``"numpy"`` or ``"closed-form"`` (no constraints: exact minimiser, no solver call).
    constraint_residual : float
        Max abs violation of the imposed equalities after polishing (0.0 when none are imposed).
    solver_constraint_residual : float
        The same, straight from the solver, before any polishing.
    polished : bool
        True when the solver's answer was projected onto the constraint set to reach ``tol``.
    reused_problem : bool
        True when a cached, already compiled cvxpy problem was re-solved with new Parameter values.
    solve_time : float
        Wall time of the call in seconds.
    """

    B: np.ndarray
    D: np.ndarray
    residual: float
    status: str
    solver: str = "closed-form"
    constraint_residual: float = 0.0
    solver_constraint_residual: float = 0.0
    polished: bool = False
    reused_problem: bool = False
    solve_time: float = 0.0

    def __post_init__(self):
        freeze_array_fields(self)   # the arrays of a frozen result are read-only too


@dataclass(frozen=True)
class CDFit:
    """Result of :func:`fit_cd`: ``C`` (p, n) and ``D`` (p, m), real; other fields as in :class:`BDFit`."""

    C: np.ndarray
    D: np.ndarray
    residual: float
    status: str
    solver: str = "closed-form"
    constraint_residual: float = 0.0
    solver_constraint_residual: float = 0.0
    polished: bool = False
    reused_problem: bool = False
    solve_time: float = 0.0

    def __post_init__(self):
        freeze_array_fields(self)   # the arrays of a frozen result are read-only too


@dataclass(frozen=True)
class AlternatingFit:
    """Result of :func:`fit_alternating`.

    Attributes
    ----------
    B, C, D : ndarray, shapes (n, m), (p, n), (p, m)
    residual : float
        Final weighted least-squares cost.
    history : tuple of float
        Cost after every half step (B/D, C/D, B/D, ...); non-increasing up to solver accuracy.
    iterations : int
        Number of full (B/D then C/D) iterations done.
    status : str
        Status of the last solve.
    constraint_residual : float
        Max abs violation of the imposed equalities at the returned (B, C, D).
    """

    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    residual: float
    history: tuple = field(default_factory=tuple)
    iterations: int = 0
    status: str = "optimal"
    constraint_residual: float = 0.0

    def __post_init__(self):
        freeze_array_fields(self)   # the arrays of a frozen result are read-only too


# --------------------------------------------------------------------------------------------- helpers
def _as_real_matrix(X, name: str, shape=None) -> np.ndarray:
    X = np.asarray(X)
    if np.iscomplexobj(X):
        if np.abs(X.imag).max(initial=0.0) > 0:
            raise FrequencyDataError(f"{name} must be real; got complex entries. Pass a real state-space matrix.")
        X = X.real
    X = np.asarray(X, dtype=float)
    if X.ndim != 2:
        raise FrequencyDataError(f"{name} must be a 2-D array; got shape {X.shape}.")
    if shape is not None:
        for got, want, axis in zip(X.shape, shape, ("rows", "columns")):
            if want is not None and got != want:
                raise FrequencyDataError(f"{name} has shape {X.shape}; expected {axis} = {want}.")
    if not np.all(np.isfinite(X)):
        raise FrequencyDataError(f"{name} contains NaN or inf; identify again or clean the data.")
    return X


def _validate(A, C, z, G, weights, dc_gain, feedthrough):
    A = _as_real_matrix(A, "A")
    n = A.shape[0]
    if A.shape != (n, n) or n == 0:
        raise FrequencyDataError(f"A must be square and non-empty; got shape {A.shape}.")
    C = _as_real_matrix(C, "C (or B^T)", (None, n))
    p = C.shape[0]
    z = np.asarray(z, dtype=complex).ravel()
    K = z.size
    if K == 0:
        raise FrequencyDataError("no frequencies (z is empty); give the data's points z = exp(1j omega_d).")
    G = np.asarray(G)
    if G.ndim == 1 and p == 1:
        G = G.reshape(1, 1, -1)
    if G.ndim != 3 or G.shape[0] != p or G.shape[2] != K:
        raise FrequencyDataError(
            f"G must have shape (p, m, K) = ({p}, m, {K}) to match C and z; got {G.shape}."
        )
    G = G.astype(complex)
    if not (np.all(np.isfinite(G)) and np.all(np.isfinite(z))):
        raise FrequencyDataError("G or z contains NaN or inf; remove or repair those frequency samples.")
    off = np.abs(np.abs(z) - 1.0)
    if off.max() > UNIT_CIRCLE_TOL:
        k = int(np.argmax(off))
        raise FrequencyGridError(f"z[{k}] = {z[k]:.6g} is off the unit circle by {abs(z[k]) - 1.0:+.3g} (|z| - 1; at most "
                                 f"{UNIT_CIRCLE_TOL:g}): the sample points are z = exp(1j omega_d) for discrete "
                                 "frequencies omega_d in rad/sample, in double precision (single precision is off "
                                 "by 6e-8)")
    m = G.shape[1]
    weights = check_weights(weights, p, m, K)
    cons = []
    for name, val, z0 in (("dc_gain", dc_gain, 1.0), ("feedthrough", feedthrough, -1.0)):
        if val is None:
            continue
        cons.append((name, z0, check_constraint(val, name, p, m, z0)))
    return A, C, z, G, weights, cons, n, p, m, K


# ``frequency_response(A, B, C, D, z)`` -> (p, m, K): the one state-space evaluator of the package.
frequency_response = evaluate_ss


def _constraint_rows(A, C, cons, lam=None):
    """Constraint matrix E (c, n+p) and right-hand sides F (c, m) for the imposed equalities (``lam``: the
    eigenvalues of ``A`` when known)."""
    n = A.shape[0]
    p = C.shape[0]
    eig = (np.linalg.eigvals(A) if lam is None else lam) if cons else np.array([])
    E_blocks, F_blocks = [], []
    for name, z0, val in cons:
        dist = float(np.min(np.abs(eig - z0)))
        if dist < POLE_TOL:
            where = "z = 1 (DC, omega = 0)" if z0 > 0 else "z = -1 (Nyquist, omega = infinity)"
            fix = (
                "drop dc_gain, or identify with stable=True (poles pulled inside radius 1 - margin) or at a lower order"
                if z0 > 0
                else "drop feedthrough, or identify with stable=True or at a lower order"
            )
            raise ConstraintError(
                f"{name} cannot be imposed: A has an eigenvalue at {where} (distance {dist:.2e} < {POLE_TOL:g}), "
                f"so C (zI - A)^-1 is undefined there. Fix: {fix}."
            )
        F0 = np.linalg.solve((z0 * np.eye(n) - A).T, C.T).T  # C (z0 I - A)^-1, (p, n)
        E_blocks.append(np.hstack([F0, np.eye(p)]))
        F_blocks.append(val)
    if not cons:
        return np.zeros((0, n + p)), np.zeros((0, 0))
    return np.vstack(E_blocks), np.vstack(F_blocks)


def _regressions(F, G, weights, m):
    """Per input column j: weighted real regression (Phi_j, g_j), stacked Re then Im.

    Rows are ordered (part, k, i) with part in (Re, Im). Returns lists of length m; the Phi_j are the
    same object when the weights do not depend on the channel.
    """
    K, p, n = F.shape
    base = np.concatenate([F, np.broadcast_to(np.eye(p), (K, p, p))], axis=2).reshape(K * p, n + p)
    Phis, gs = [], []
    shared = None
    for j in range(m):
        gj = G[:, j, :].T.reshape(K * p)  # row k*p + i holds G[i, j, k]
        if weights is None:
            sw = None
        elif weights.ndim == 1:
            sw = np.repeat(np.sqrt(weights), p)
        else:
            sw = np.sqrt(weights[:, j, :]).T.reshape(K * p)
        if sw is None or weights.ndim == 1:
            if shared is None:
                Pc = base if sw is None else base * sw[:, None]
                shared = np.vstack([Pc.real, Pc.imag])
            Phi = shared
        else:
            Pc = base * sw[:, None]
            Phi = np.vstack([Pc.real, Pc.imag])
        if sw is not None:
            gj = gj * sw
        Phis.append(Phi)
        gs.append(np.concatenate([gj.real, gj.imag]))
    return Phis, gs


# --------------------------------------------------------------------------------------------- public API
def fit_bd(A, C, z, G, *, weights=None, dc_gain=None, feedthrough=None, solver: str = "clarabel", tol: float = 1e-10,
           eig=None) -> BDFit:
    """Fit ``B`` and ``D`` of ``G(z) = C (zI - A)^-1 B + D`` to samples, optionally with exact constraints.

    Parameters
    ----------
    A : ndarray, shape (n, n), real
        Discrete state matrix (kept fixed).
    C : ndarray, shape (p, n), real
        Output matrix (kept fixed).
    z : ndarray, shape (K,), complex
        Sample points, ``z = exp(1j omega_d)`` with ``omega_d`` in rad/sample.
    G : ndarray, shape (p, m, K), complex
        Frequency-response samples (``(K,)`` accepted for SISO).
    weights : ndarray, shape (K,) or (p, m, K), nonnegative, optional
        Weights of the squared residuals: the cost is ``sum w |G_k - G(z_k)|^2`` (use ``1/sigma^2`` for
        noise of standard deviation ``sigma``).
    dc_gain : ndarray, shape (p, m), real, optional
        Imposes ``C (I - A)^-1 B + D = dc_gain`` exactly (to ``tol``).
    feedthrough : ndarray, shape (p, m), real, optional
        Imposes ``C (-I - A)^-1 B + D = feedthrough`` exactly (the ``omega_d = pi`` sample, i.e. the
        continuous feedthrough under the bilinear map; 0 for the aerofoil).
    solver : {"clarabel", "numpy"}
        ``"clarabel"``: cached DPP cvxpy problem + exact polishing (default, used by ``identify``);
        ``"numpy"``: closed-form null-space solution (the test oracle). Unconstrained fits never call a
        solver (closed-form minimiser).
    tol : float
        Accepted max abs constraint violation (absolute, in the units of ``G``); beyond it the solver's
        solution is polished by projection onto the constraint set.
    eig : tuple, optional
        :func:`sysid.state_space.eigen_parts` of ``A``: the regression rows ``C (z_k I - A)^-1`` are then
        formed in the modal form (``O(K p n^2)`` instead of ``K`` LU factorisations; accuracy ``cond(V) eps``,
        ``cond(V) <= 1e6`` by construction).

    Returns
    -------
    BDFit

    Raises
    ------
    ConstraintError
        A constraint at ``z = +-1`` where ``A`` has an eigenvalue (within 1e-8), a malformed constraint, or
        more independent constraints than unknowns.
    SolverError
        Clarabel failed.
    FrequencyDataError
        Malformed arrays, or an eigenvalue of ``A`` on a sample point (an infinite response there).
    FrequencyGridError
        A sample point off the unit circle.
    OptionError
        ``solver`` is not ``"clarabel"`` or ``"numpy"``; ``tol`` not a finite number > 0.
    """
    t0 = time.perf_counter()
    A, C, z, G, weights, cons, n, p, m, K = _validate(A, C, z, G, weights, dc_gain, feedthrough)
    if solver not in ("clarabel", "numpy"):
        raise OptionError(f"solver must be 'clarabel' or 'numpy'; got {solver!r}.")
    tol = check_tolerance(tol, "tol")
    lam = eig[0] if eig else np.linalg.eigvals(A)
    E, Fr = _constraint_rows(A, C, cons, lam)   # first: a constraint at a pole gets its own advice
    if np.min(np.abs(z[:, None] - lam[None, :])) < POLE_TOL:
        # (the resolvent is then huge but may be finite: B came out near 0 with status "optimal")
        raise FrequencyDataError(
            "A has an eigenvalue at (or numerically at) one of the sample points z_k on the unit circle, so the "
            "model response C (z_k I - A)^-1 is infinite there; identify with stable=True or at another order."
        )
    c = E.shape[0]
    N = n + p
    if c > N:
        raise ConstraintError(
            f"{c} equality constraints but only {N} unknowns per input (n + p = {n} + {p}); "
            "impose only one of dc_gain/feedthrough or raise the order."
        )
    F = resolvent_C(A, C, z, modal_form(A, C, eig) if eig else False)  # (K, p, n): C (z_k I - A)^-1
    if not np.all(np.isfinite(F)):
        raise FrequencyDataError(
            "A has an eigenvalue at (or numerically at) one of the sample points z_k on the unit circle, so the "
            "model response C (z_k I - A)^-1 is infinite there; identify with stable=True or at another order."
        )
    Phis, gs = _regressions(F, G, weights, m)
    scale = 1.0  # tol is absolute, in the units of G

    thetas = [None] * m
    status, used, polished, reused = "optimal", "closed-form", False, False
    solver_res = 0.0
    if solver == "numpy":
        used = "numpy"
        for j in range(m):
            thetas[j] = null_space_solve(Phis[j], gs[j], E, Fr[:, j] if c else None)
        if c:
            solver_res = max(float(np.abs(E @ th - Fr[:, j]).max()) for j, th in enumerate(thetas))
    else:
        reds = {}
        hs, Qs, fs, Ms = [], [], [], []
        for j in range(m):
            key_id = id(Phis[j])
            if key_id not in reds:
                reds[key_id] = reduce_regression(Phis[j])
            U, S, St, M = reds[key_id]
            hs.append(S * (U[1].T @ (U[0].T @ gs[j])) / St)
            Ms.append(M)
            if c:
                Eh = E @ M  # (c, N)
                Qe, Re = np.linalg.qr(Eh.T)  # Eh = Re^T Qe^T
                d = np.abs(np.diag(Re))
                if d.min() <= 1e-12 * d.max():
                    raise ConstraintError(
                        "the imposed constraints are linearly dependent at this order (dc_gain and feedthrough "
                        "rows coincide); impose only one of them or change the order."
                    )
                Qs.append(Qe)
                fs.append(np.linalg.solve(Re.T, Fr[:, j]))
        if c:
            used = "clarabel"
            wshape = None if weights is None else weights.shape
            key = (n, m, p, K, tuple(name for name, _, _ in cons), wshape)
            ys, status, reused = solve_compiled(key, hs, Qs, fs, m, N, c)
            for j in range(m):
                thetas[j] = Ms[j] @ ys[j]
            res = [np.abs(E @ thetas[j] - Fr[:, j]).max() for j in range(m)]
            solver_res = float(max(res))
            for j in range(m):
                if res[j] > tol * scale:
                    y = ys[j] - Qs[j] @ (Qs[j].T @ ys[j] - fs[j])
                    thetas[j] = Ms[j] @ y
                    polished = True
                    r = E @ thetas[j] - Fr[:, j]
                    if np.abs(r).max() > tol * scale:  # last resort: min-norm correction in theta space
                        thetas[j] = thetas[j] - np.linalg.lstsq(E, r, rcond=None)[0]
        else:
            for j in range(m):
                thetas[j] = Ms[j] @ hs[j]
    Theta = np.column_stack(thetas)  # (N, m)
    B = Theta[:n, :].copy()
    D = Theta[n:, :].copy()
    residual = float(sum(np.sum((Phis[j] @ thetas[j] - gs[j]) ** 2) for j in range(m)))
    cres = float(np.abs(E @ Theta - Fr).max()) if c else 0.0
    return BDFit(
        B=B,
        D=D,
        residual=residual,
        status=status,
        solver=used,
        constraint_residual=cres,
        solver_constraint_residual=solver_res,
        polished=polished,
        reused_problem=reused,
        solve_time=time.perf_counter() - t0,
    )


def fit_cd(A, B, z, G, *, weights=None, dc_gain=None, feedthrough=None, solver: str = "clarabel", tol: float = 1e-10,
           eig=None) -> CDFit:
    """Fit ``C`` and ``D`` of ``G(z) = C (zI - A)^-1 B + D`` given ``A`` (n, n) and ``B`` (n, m).

    Solved as the B/D refit (:func:`fit_bd`) of the transposed system
    ``G(z)^T = B^T (zI - A^T)^-1 C^T + D^T``.

    Parameters
    ----------
    A : ndarray, shape (n, n), real
        Discrete state matrix (kept fixed).
    B : ndarray, shape (n, m), real
        Input matrix (kept fixed).
    z : ndarray, shape (K,), complex
        Sample points, ``z = exp(1j omega_d)`` with ``omega_d`` in rad/sample.
    G : ndarray, shape (p, m, K), complex
        Frequency-response samples (``(K,)`` accepted when ``B`` has one column and there is one output).
    weights : ndarray, shape (K,) or (p, m, K), nonnegative, optional
        Weights of the squared residuals, as in :func:`fit_bd`.
    dc_gain : ndarray, shape (p, m), real, optional
        Imposes ``C (I - A)^-1 B + D = dc_gain`` exactly (to ``tol``).
    feedthrough : ndarray, shape (p, m), real, optional
        Imposes ``C (-I - A)^-1 B + D = feedthrough`` exactly (the ``omega_d = pi`` sample).
    solver : {"clarabel", "numpy"}
        As in :func:`fit_bd`.
    tol : float
        Accepted max abs constraint violation, as in :func:`fit_bd` (default 1e-10).
    eig : tuple, optional
        :func:`sysid.state_space.eigen_parts` of ``A`` (as in :func:`fit_bd`).

    Returns
    -------
    CDFit
        ``C`` (p, n) and ``D`` (p, m), real; the other fields are those of the transposed B/D fit.

    Raises
    ------
    OptionError
        ``solver`` is not ``"clarabel"`` or ``"numpy"``; ``tol`` not a finite number > 0.
    ConstraintError, SolverError
        As in :func:`fit_bd`.
    FrequencyDataError
        Malformed arrays (e.g. ``G`` not of shape (p, m, K), ``B`` without ``n`` rows).
    """
    A = _as_real_matrix(A, "A")
    B = _as_real_matrix(B, "B", (A.shape[0], None))
    G = np.asarray(G)
    if G.ndim == 1 and B.shape[1] == 1:
        G = G.reshape(1, 1, -1)
    if G.ndim != 3:
        raise FrequencyDataError(f"G must have shape (p, m, K); got {G.shape}.")
    w = None if weights is None else np.asarray(weights, dtype=float)
    if w is not None and w.ndim == 3:
        w = np.swapaxes(w, 0, 1)
    tr = lambda X: None if X is None else np.asarray(X).T  # noqa: E731
    eig_t = (eig[0], eig[2].T, eig[1].T) if eig else None  # A^T = V^-T diag(lam) V^T
    r = fit_bd(A.T, B.T, z, np.swapaxes(G, 0, 1), weights=w, dc_gain=tr(dc_gain), feedthrough=tr(feedthrough),
               solver=solver, tol=tol, eig=eig_t)
    return CDFit(
        C=r.B.T.copy(),
        D=r.D.T.copy(),
        residual=r.residual,
        status=r.status,
        solver=r.solver,
        constraint_residual=r.constraint_residual,
        solver_constraint_residual=r.solver_constraint_residual,
        polished=r.polished,
        reused_problem=r.reused_problem,
        solve_time=r.solve_time,
    )


def fit_alternating(A, C, z, G, *, iterations: int = 10, rtol: float = 1e-9, weights=None, dc_gain=None,
                    feedthrough=None, solver: str = "clarabel", tol: float = 1e-10) -> AlternatingFit:
    """Alternate B/D and C/D refits with ``A`` fixed (block-coordinate descent on a biconvex cost).

    Each half step is the exact constrained minimiser over its block and the current iterate is feasible
    for it, so the cost never increases. Stops after ``iterations`` full steps or when the relative
    decrease of one full step falls below ``rtol``.

    Parameters
    ----------
    A : ndarray, shape (n, n), real
        Discrete state matrix (kept fixed).
    C : ndarray, shape (p, n), real
        Starting output matrix (refitted in the C/D half steps).
    z, G, weights, dc_gain, feedthrough, solver, tol
        As in :func:`fit_bd`: ``z`` shape (K,), ``G`` shape (p, m, K), ``weights`` shape (K,) or (p, m, K),
        ``dc_gain`` and ``feedthrough`` shape (p, m); each half step imposes the same constraints.
    iterations : int
        Maximum number of full (B/D then C/D) steps, >= 1 (default 10).
    rtol : float
        Relative tolerance of the stopping test (default 1e-9): from the second full step on, the iteration
        stops when the cost decreased by at most ``rtol`` times the cost after the previous full step.

    Returns
    -------
    sysid.refit.AlternatingFit
        ``B`` (n, m), ``C`` (p, n), ``D`` (p, m) of the last C/D half step (``B`` from the B/D half step
        before it), the final cost and the cost history.

    Raises
    ------
    OptionError
        ``iterations`` is not an integer >= 1, ``rtol`` not a finite number >= 0, or ``solver`` is not
        ``"clarabel"`` or ``"numpy"``.
    ConstraintError, SolverError, FrequencyDataError
        As raised by :func:`fit_bd` and :func:`fit_cd`.
    """
    if isinstance(iterations, bool) or not isinstance(iterations, (int, np.integer)) or iterations < 1:
        raise OptionError(f"iterations must be an integer >= 1; got {iterations!r}.")
    rtol = check_tolerance(rtol, "rtol", positive=False)
    history = []
    C = np.asarray(C, dtype=float)
    bd = cd = None
    done = 0
    for it in range(iterations):
        bd = fit_bd(A, C, z, G, weights=weights, dc_gain=dc_gain, feedthrough=feedthrough, solver=solver, tol=tol)
        history.append(bd.residual)
        cd = fit_cd(A, bd.B, z, G, weights=weights, dc_gain=dc_gain, feedthrough=feedthrough, solver=solver, tol=tol)
        history.append(cd.residual)
        C = cd.C
        done = it + 1
        if it > 0 and history[-3] - history[-1] <= rtol * max(history[-3], np.finfo(float).tiny):
            break
    return AlternatingFit(
        B=bd.B, C=cd.C, D=cd.D, residual=cd.residual, history=tuple(history), iterations=done,
        status=cd.status, constraint_residual=cd.constraint_residual,
    )
