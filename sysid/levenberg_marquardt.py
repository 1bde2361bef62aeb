"""A small bounded Levenberg-Marquardt solver for the pole refinement (:mod:`sysid.pole_refinement`).

The refinement minimises ``||r(x)||^2`` over a few dozen parameters with an analytic (Kaufman) Jacobian and a box
``lower <= x <= upper``. This solver does what that needs and no more, in NumPy alone (no ``scipy.optimize``, whose
import is about half of a first identification's import time):

- the Levenberg-Marquardt step in its trust-region form (Moré 1978, "The Levenberg-Marquardt algorithm:
  implementation and theory", Lecture Notes in Mathematics 630, 105-116): ``min |J dx + r|`` with
  ``|D dx| <= radius``, ``D`` the largest column norms of ``J`` seen so far (the step does not depend on the
  parameters' units), solved from the SVD of the triangular factor of ``J`` (``n_par`` rows, one QR of ``[J r]``
  per accepted point) by Hebden's iteration for the damping (Nocedal & Wright 2006, "Numerical Optimization",
  Algorithm 4.3);
- the radius update of Nocedal & Wright's Algorithm 4.1 (a quarter of the step after a poor gain ratio, double
  after a good one that reached the boundary);
- bounds by projection: a trial point is clipped to the box, short of each bound by :data:`_TO_BOUND` of the
  distance left (and at least one ulp), and its gain ratio uses the clipped step's own predicted reduction
  ``-(2 g . dx + |J dx|^2)``, so a step that the box shortens is judged by what it can do. A parameter held on its
  bound (no room left and the step pushes it out) is fixed and the others' step solved again without it; one
  that is only approaching a bound keeps the clipped joint step. So an active bound is approached geometrically
  and its bounded minimum reached slowly (cost 4e-7 - 1.4e-5 above it after 19 - 200 evaluations on the tests'
  problems): re-solving at every clipped step reaches it to 1e-12 but drove the pole refinement's poles onto the
  stability region's edges (tests/sysid/test_levenberg_marquardt.py says how much).

A residual that returns non-finite values, or the caller's sentinel of a rejected point (any residual of a cost
above the current one), is a rejected step.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["LMResult", "bounded_levenberg_marquardt"]

#: A trial point stops short of a bound by this fraction of the distance left (the iterates stay strictly inside
#: the box, as in interior methods: a pole parameter clipped onto its bound put a real pole on the stability
#: margin at omega = 0).
_TO_BOUND = 0.1


@dataclass(frozen=True)
class LMResult:
    """Result of :func:`bounded_levenberg_marquardt`.

    Attributes
    ----------
    x : ndarray, shape (n_par,)
        The best point found (within the bounds).
    fun : ndarray, shape (rows,)
        The residual there.
    cost : float
        ``||fun||^2``.
    nfev, njev : int
        Residual and Jacobian evaluations.
    status : str
        Why it stopped: ``"max_nfev"``, ``"ftol"`` (relative decrease of the cost below ``ftol``), ``"xtol"``
        (scaled step below ``xtol``), ``"gtol"`` (scaled gradient below ``gtol``) or ``"damping"`` (no step
        reduced the cost even with the largest damping).
    """

    x: np.ndarray
    fun: np.ndarray
    cost: float
    nfev: int
    njev: int
    status: str


def bounded_levenberg_marquardt(residual, jacobian, x0, lower=None, upper=None, *, max_nfev: int = 100,
                                ftol: float = 1e-12, xtol: float = 1e-12, gtol: float = 1e-12) -> LMResult:
    """Minimise ``||residual(x)||^2`` with ``lower <= x <= upper`` by Levenberg-Marquardt (module docstring).

    Parameters
    ----------
    residual : callable
        ``residual(x) -> ndarray (rows,)``.
    jacobian : callable
        ``jacobian(x) -> ndarray (rows, n_par)``; called only at accepted points, after ``residual`` at the same
        ``x`` (a caller may reuse that evaluation's factorisation).
    x0 : array_like, shape (n_par,)
        Start; clipped into the box.
    lower, upper : array_like, shape (n_par,), optional
        Bounds (``-inf`` / ``inf`` allowed); default unbounded.
    max_nfev : int
        Cap on residual evaluations (the start's included).
    ftol, xtol, gtol : float
        Stop when an accepted step lowers the cost by less than ``ftol`` times it, when the scaled step
        ``|D dx|`` is below ``xtol (xtol + |D x|)``, or when the scaled gradient ``max |g / D|`` is below ``gtol``
        times the cost.

    Returns
    -------
    LMResult
    """
    x = np.asarray(x0, dtype=float).copy()
    n_par = x.size
    lo = np.full(n_par, -np.inf) if lower is None else np.broadcast_to(np.asarray(lower, dtype=float), (n_par,))
    hi = np.full(n_par, np.inf) if upper is None else np.broadcast_to(np.asarray(upper, dtype=float), (n_par,))
    x = np.clip(x, lo, hi)
    # a start on a bound is moved just inside it (1e-9 of the bound's scale, at most half the box): the trial
    # points stop short of a bound by a fraction of the distance left, so a parameter on its bound could not move
    both = np.isfinite(lo) & np.isfinite(hi)
    nudge = np.minimum(1e-9 * np.maximum(1.0, np.maximum(np.abs(np.where(np.isfinite(lo), lo, 0.0)),
                                                         np.abs(np.where(np.isfinite(hi), hi, 0.0)))),
                       np.where(both, 0.5 * (hi - lo), np.inf))
    x = np.where(x <= lo, lo + nudge, np.where(x >= hi, hi - nudge, x))
    r = np.asarray(residual(x), dtype=float)
    cost = float(r @ r)
    nfev, njev = 1, 0
    if not np.isfinite(cost):
        return LMResult(x, r, cost, nfev, njev, "damping")
    scale = np.zeros(n_par)
    radius = None
    status = "max_nfev"
    while nfev < max_nfev:
        J = np.asarray(jacobian(x), dtype=float)
        njev += 1
        scale = np.maximum(scale, np.linalg.norm(J, axis=0))
        d = np.where(scale > 0, scale, 1.0)
        # R and Q^T r from one QR of [J r] (Q^T r is the top of its last column): Householder QR scales with the
        # columns, so the step does not depend on the parameters' units to round-off (Q^T r solved from
        # R^T (Q^T r) = J^T r loses digits in proportion to cond(R), which a units change multiplies)
        Rr = np.linalg.qr(np.column_stack([J, r]), mode="r")
        k = min(J.shape[0], n_par)
        R, qtr = Rr[:k, :n_par], Rr[:k, n_par]
        g = J.T @ r
        if np.max(np.abs(g) / d, initial=0.0) <= gtol * max(cost, np.finfo(float).tiny):
            status = "gtol"
            break
        # the subproblem in the scaled variable p = D dx: min |R D^-1 p + Q^T r| with |p| <= radius, from the SVD
        # of the small triangular factor (n_par x n_par)
        U, sv, Vt = np.linalg.svd(R / d, full_matrices=False)
        uf = U.T @ qtr
        if radius is None:
            radius = float(np.linalg.norm(d * x)) or 1.0
        # a trial point stops short of each bound by _TO_BOUND of the distance left, and at least one ulp (else
        # x + 0.9 (hi - x) rounds onto hi once hi - x is below an ulp of hi); an infinite bound stays put
        lo_t = np.maximum(lo + _TO_BOUND * np.where(np.isfinite(lo), x - lo, 0.0), np.nextafter(lo, np.inf))
        hi_t = np.minimum(hi - _TO_BOUND * np.where(np.isfinite(hi), hi - x, 0.0), np.nextafter(hi, -np.inf))
        lo_t, hi_t = np.minimum(lo_t, x), np.maximum(hi_t, x)   # (a start on a bound stays where it is)
        accepted = False
        while nfev < max_nfev:
            p = _trust_step(sv, uf, Vt, radius)
            xt = np.clip(x + p / d, lo_t, hi_t)
            pinned = (xt != x + p / d) & (np.abs(xt - x) <= 1e-12 * np.maximum(1.0, np.abs(x)))
            if pinned.any() and not pinned.all():
                # parameters held on their bound (the step pushes them out, and they have no room left): the other
                # parameters' best step with those held, else the coupled step of a held one keeps the others off
                # the bounded minimum (a start on x1 = hi of Rosenbrock's box never moved). Parameters merely
                # approaching a bound keep the clipped joint step (see _TO_BOUND)
                free = ~pinned
                U2, sv2, Vt2 = np.linalg.svd(R[:, free] / d[free], full_matrices=False)
                q = _trust_step(sv2, U2.T @ (qtr + R[:, pinned] @ (xt - x)[pinned]), Vt2, radius)
                xt[free] = np.clip(x[free] + q / d[free], lo_t[free], hi_t[free])
            step = xt - x
            p_len = float(np.linalg.norm(d * step))
            if p_len <= xtol * (xtol + float(np.linalg.norm(d * x))):
                status = "xtol"
                break
            Js = R @ step
            predicted = -(2.0 * float(qtr @ Js) + float(Js @ Js))   # the model's decrease: |Q^T r|^2 - |R dx + Q^T r|^2
            rt = np.asarray(residual(xt), dtype=float)
            nfev += 1
            cost_t = float(rt @ rt) if np.all(np.isfinite(rt)) else np.inf
            actual = cost - cost_t
            rho = actual / predicted if predicted > 0 else -1.0
            # radius update (Nocedal & Wright 2006, Algorithm 4.1)
            if rho < 0.25:
                radius = 0.25 * p_len
            elif rho > 0.75 and p_len >= 0.95 * radius:
                radius = 2.0 * radius
            if rho > 1e-4:
                x, r, cost_prev, cost = xt, rt, cost, cost_t
                accepted = True
                if actual <= ftol * cost_prev:
                    status = "ftol"
                break
            if radius <= np.finfo(float).eps * (1.0 + float(np.linalg.norm(d * x))):
                status = "damping"
                break
        if status in ("xtol", "ftol", "damping") or not accepted:
            break
    return LMResult(x, r, cost, nfev, njev, status)


def _trust_step(sv, uf, Vt, radius):
    """The minimiser ``p`` of ``|S p + f|`` (``S = U diag(sv) Vt``, ``uf = U^T f``) with ``|p| <= radius``.

    The Gauss-Newton step when it lies in the ball, else ``p(lam) = -Vt^T (sv / (sv^2 + lam)) uf`` with ``lam > 0``
    such that ``|p(lam)| = radius``, found by Newton's method on ``1 / |p(lam)| - 1 / radius`` (Hebden; Nocedal &
    Wright 2006, Algorithm 4.3), which converges from the left in a few iterations.
    """
    tiny = np.finfo(float).eps * (sv[0] if sv.size else 1.0)
    if sv.size and sv[-1] > tiny:
        p = -(uf / sv) @ Vt
        if np.linalg.norm(p) <= radius:
            return p
    lam = 0.0
    phi_hi = None
    for _ in range(30):
        den = sv ** 2 + lam
        with np.errstate(divide="ignore", invalid="ignore"):
            c = np.where(den > 0, sv * uf / den, 0.0)
        norm = float(np.linalg.norm(c))
        if norm == 0.0:
            return np.zeros(Vt.shape[1])
        if abs(norm - radius) <= 1e-3 * radius and lam > 0:
            break
        # d|p|/dlam = -sum c^2 / den / |p|; Newton on phi = 1/|p| - 1/radius
        with np.errstate(divide="ignore", invalid="ignore"):
            dnorm = -float(np.sum(np.where(den > 0, c ** 2 / den, 0.0))) / norm
        phi = 1.0 / norm - 1.0 / radius
        dphi = -dnorm / norm ** 2
        lam_new = lam - phi / dphi if dphi > 0 else 2.0 * lam + tiny
        if phi_hi is not None and lam_new <= lam:
            break
        lam = max(lam_new, 0.0) if lam_new > 0 else (lam * 0.5 if lam > 0 else tiny)
        phi_hi = phi
    p = -c @ Vt
    norm = float(np.linalg.norm(p))
    return p if norm <= radius or norm == 0.0 else p * (radius / norm)
