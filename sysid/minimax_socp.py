"""A dedicated interior-point solver for the complex minimax programme of :func:`sysid.residues.socp_minimax`:

    min_y max_k |Q_k y - g_k|   s.t.  E y = f,  |Qb_j y| <= ub_j,

with every cone three-dimensional (one per complex residual). The equalities are eliminated by a null-space
basis (``y = y0 + Z w``, ``E Z = 0``), leaving the standard-form cone programme in ``x = (w, t)``

    min t   s.t.  G x + s = h,  s in K = SOC(3)^M

(one cone ``s_k = (t, Re r_k, Im r_k)`` per sample, ``r_k = Q_k y - g_k``, and ``s_j = (ub_j, Re Qb_j y,
Im Qb_j y)`` per bound). It is solved by a primal-dual path-following method with Nesterov-Todd scaling and
Mehrotra's predictor-corrector (the algorithm of L. Vandenberghe, "The CVXOPT linear and quadratic cone program
solvers", 2010, sections 3-5, specialised to a linear objective, no equality rows and 3-cones): each Newton
system is reduced to the ``(N - c + 1)``-square normal equations ``G^T W^-2 G dx = r``, formed with the
scalings vectorised over the cones and solved by Cholesky (by the triangular factor of a QR factorisation of
``W^-1 G`` when they are too ill-conditioned to be formed, near the optimum of bounded programmes).

The solver never guesses: it returns ``None`` when it has not met its tolerances within :data:`MAX_ITER`
iterations, when the normal equations become singular, or when an iterate leaves the cones or stops being
finite (an infeasible bounded programme does within 5-7 iterations), and the caller falls back to a
general-purpose conic solver.
"""

import math

import numpy as np

from .refit_solvers import equality_null_space

__all__ = ["minimax_socp", "MAX_ITER", "STEP_FRACTION"]

#: Iteration cap (the programmes of :func:`sysid.residues.minimax_cd` on the paper data take 15-27).
MAX_ITER = 60

#: Fraction of the distance to the cone boundary taken by each step.
STEP_FRACTION = 0.99

_J = np.array([1.0, -1.0, -1.0])  # the hyperbolic reflection diag(1, -1, -1)
_Jc = _J[:, None]


def minimax_socp(Q, g, E, f, Qb=None, ub=None, tol=1e-9):
    """Solve ``min_y max_k |Q_k y - g_k|`` s.t. ``E y = f`` and ``|Qb_j y| <= ub_j``.

    Parameters
    ----------
    Q : ndarray, shape (K, N), complex
    g : ndarray, shape (K,), complex
    E : ndarray, shape (c, N), real, full row rank
    f : ndarray, shape (c,), real
    Qb : ndarray, shape (J, N), complex, optional
    ub : ndarray, shape (J,), positive, optional
    tol : float
        Relative tolerance of the duality gap (``s^T z <= tol * t`` or ``<= 1e-2 tol``) and of the primal and
        dual residuals (infinity norms, relative to ``max(1, |h|_inf)`` and to ``max(1, | |G|^T |z| |_inf)``,
        the size of the terms whose sum is ``G^T z``), for data scaled to unit size (``|g|_inf = 1`` and ``Q``
        with orthonormal columns, as :func:`sysid.residues.minimax_cd` builds them). Stricter in the gap than
        Clarabel's ``tol_gap_abs`` for small levels, so the level is known to ``tol`` relative.

    Returns
    -------
    y : ndarray, shape (N,), real, or None
        None when the method did not converge (see the module docstring); ``E y = f`` to round-off otherwise.
    info : dict
        ``iterations``, ``level`` (``max_k |Q_k y - g_k|``), ``gap`` (``s^T z``), ``primal_residual``,
        ``dual_residual`` (relative, as in the stopping rule; only computed once the other two are met),
        ``reason``.
    """
    Q = np.asarray(Q, dtype=complex)
    g = np.asarray(g, dtype=complex)
    E = np.asarray(E, dtype=float).reshape(-1, Q.shape[1])
    f = np.asarray(f, dtype=float).reshape(-1)
    K, N = Q.shape
    c = E.shape[0]
    if c:   # the equalities' solutions y0 + Z w (sysid.refit_solvers.equality_null_space)
        try:
            y0, Z, d = equality_null_space(E, f)
        except np.linalg.LinAlgError:   # exactly singular R
            d = np.zeros(1)
        if d.min() <= 1e-12 * max(d.max(), 1e-300):
            return None, {"iterations": 0, "level": np.nan, "gap": np.nan, "reason": "rank-deficient E"}
    else:
        y0 = np.zeros(N)
        Z = np.eye(N)
    n = Z.shape[1]
    n1 = n + 1
    J = 0 if Qb is None else Qb.shape[0]
    M = K + J
    # cone components first: G (3, M, n1), h (3, M), s = h - G x; row 0 the cones' heads
    QZ = Q @ Z
    r0 = Q @ y0 - g
    G = np.zeros((3, M, n1))
    h = np.zeros((3, M))
    G[0, :K, n] = -1.0
    G[1, :K, :n] = -QZ.real
    G[2, :K, :n] = -QZ.imag
    h[1, :K] = r0.real
    h[2, :K] = r0.imag
    if J:
        QbZ = Qb @ Z
        b0 = Qb @ y0
        G[1, K:, :n] = -QbZ.real
        G[2, K:, :n] = -QbZ.imag
        h[0, K:] = ub
        h[1, K:] = b0.real
        h[2, K:] = b0.imag
    cvec = np.zeros(n1)
    cvec[n] = 1.0
    Gf = G.reshape(3 * M, n1)
    hnorm = max(1.0, float(np.abs(h).max()))
    absG = np.abs(G)
    JG = _J[:, None, None] * G

    # starting point: x least squares of G x ~ h, z least norm with G^T z = -c, both shifted into the cones
    try:
        L0 = np.linalg.cholesky(Gf.T @ Gf)
    except np.linalg.LinAlgError:
        return None, {"iterations": 0, "level": np.nan, "gap": np.nan, "reason": "singular G"}
    x = _chol_solve(L0, Gf.T @ h.reshape(-1))
    s = _shift_into_cone(h - (Gf @ x).reshape(3, M))
    z = _shift_into_cone(-(Gf @ _chol_solve(L0, cvec)).reshape(3, M))

    info = {"iterations": 0, "level": np.nan, "gap": np.nan, "reason": "iteration cap"}
    gap = pres = np.nan
    for it in range(MAX_ITER):
        rx = np.einsum("imk,im->k", G, z)  # dual residual G^T z + c
        rx[n] += 1.0
        rz = s + (Gf @ x).reshape(3, M) - h  # primal residual
        gap = float(np.vdot(s, z))
        pcost = x[n]
        pres = float(np.abs(rz).max()) / hnorm
        if not math.isfinite(gap + pres):
            info.update(iterations=it, gap=gap, primal_residual=pres, reason="not finite")
            return None, info
        if pres <= tol and (gap <= tol * abs(pcost) or gap <= 1e-2 * tol):
            # relative to the size of the terms summed in G^T z (bound rows of large gain, e.g. near a
            # resonance, carry large multipliers whose sum cancels to round-off of that size, not of 1)
            dres = float(np.abs(rx).max()) / max(1.0, float(np.einsum("imk,im->k", absG, np.abs(z)).max()))
            if dres <= tol:
                y = y0 + Z @ x[:n]
                info.update(iterations=it, gap=gap, primal_residual=pres, dual_residual=dres,
                            level=float(np.abs(Q @ y - g).max()), reason="converged")
                return y, info
        mu = gap / M
        # Nesterov-Todd scaling W = beta (2 v v^T - J) per cone, W z = W^-1 s = lam
        ds = _det(s)
        dz = _det(z)
        if not (ds.min() > 0.0 and dz.min() > 0.0):
            info.update(iterations=it, gap=gap, primal_residual=pres, reason="left the cone")
            return None, info
        sb = s / np.sqrt(ds)
        zb = z / np.sqrt(dz)
        wb = (sb + _Jc * zb) / np.sqrt(2.0 * (1.0 + np.einsum("im,im->m", sb, zb)))  # / (2 gamma)
        beta = np.sqrt(np.sqrt(ds / dz))
        v = wb
        v[0] += 1.0
        v /= np.sqrt(2.0 * v[0])
        u = _Jc * v  # W^-1 = (2 u u^T - J) / beta
        ib = 1.0 / beta
        lam = _apply(v, beta, z)
        # W^-1 G and the normal equations
        Gt = (2.0 * u * ib)[:, :, None] * np.einsum("im,imk->mk", u, G)[None] - JG * ib[None, :, None]
        Gtf = Gt.reshape(3 * M, n1)
        Ri = _inverse_factor(Gtf)  # H^-1 = (Gt^T Gt)^-1 = Ri Ri^T
        if Ri is None:
            info.update(iterations=it, gap=gap, primal_residual=pres, reason="normal equations singular")
            return None, info
        Winv_rz = _apply(u, ib, rz)

        def newton(bs):
            # G^T dz = -rx, G dx + ds = -rz, lam o (W dz + W^-1 ds) = bs  ->  (dx, W^-1 ds, W dz)
            d = _jordan_div(lam, bs)
            e = -Winv_rz - d
            dx = Ri @ (Ri.T @ (Gtf.T @ e.reshape(-1) - rx))
            wdz = (Gtf @ dx).reshape(3, M) - e
            return dx, d - wdz, wdz

        lamsq = _jordan(lam, lam)
        lam2 = np.concatenate([lam, lam], axis=1)
        qc = np.concatenate([_det(lam)] * 2)
        dxa, dsa, dza = newton(-lamsq)
        alpha_a = min(1.0, _max_step(lam2, np.concatenate([dsa, dza], axis=1), qc))
        sigma = (1.0 - alpha_a) ** 3
        bs = -lamsq - _jordan(dsa, dza)
        bs[0] += sigma * mu
        dx, dst, dzt = newton(bs)
        alpha = min(1.0, STEP_FRACTION * _max_step(lam2, np.concatenate([dst, dzt], axis=1), qc))
        x = x + alpha * dx
        s = s + alpha * _apply(v, beta, dst)
        z = z + alpha * _apply(u, ib, dzt)
    info.update(iterations=MAX_ITER, gap=gap, primal_residual=pres)
    return None, info


def _inverse_factor(Gt):
    """``Ri`` with ``(Gt^T Gt)^-1 = Ri Ri^T``: the inverse transposed Cholesky factor of the normal equations,
    or from the QR factorisation of ``Gt`` when they are not numerically positive definite (forming
    ``Gt^T Gt`` squares the condition number: the bounded programmes lost definiteness near the optimum);
    None when ``Gt`` is numerically rank deficient."""
    try:
        L = np.linalg.cholesky(Gt.T @ Gt)
        dL = np.diag(L)
        if dL.min() > 1e-4 * dL.max():  # cond(H) below about 1e8: the squared form loses at most 1e-8
            return np.linalg.inv(L).T
    except np.linalg.LinAlgError:
        pass
    R = np.linalg.qr(Gt, mode="r")
    dR = np.abs(np.diag(R))
    if not dR.min() > 1e-14 * dR.max():
        return None
    return np.linalg.inv(R)


def _chol_solve(L, b):
    """``(L L^T)^-1 b``."""
    return np.linalg.solve(L.T, np.linalg.solve(L, b))


def _det(u):
    """``u0^2 - |u1|^2`` per cone, (M,), for ``u`` (3, M), as a product of two sums (less cancellation near
    the boundary)."""
    r = np.hypot(u[1], u[2])
    return (u[0] - r) * (u[0] + r)


def _shift_into_cone(u):
    """``u + a e`` with ``a = 1 + max(0, max_k (|u_k1| - u_k0))`` when some ``u_k`` is not strictly inside."""
    a = float(np.max(np.hypot(u[1], u[2]) - u[0]))
    if a >= 0.0:
        u = u.copy()
        u[0] += 1.0 + a
    return u


def _apply(p, scale, a):
    """``W a`` (``p = v``, ``scale = beta``) or ``W^-1 a`` (``p = J v``, ``scale = 1 / beta``) per cone:
    ``(2 p (p^T a) - J a) * scale``."""
    return ((2.0 * np.einsum("im,im->m", p, a)) * p - _Jc * a) * scale


def _jordan(a, b):
    """Jordan product per cone: ``(a^T b, a0 b1 + b0 a1)``."""
    out = a[0] * b + b[0] * a
    out[0] = np.einsum("im,im->m", a, b)
    return out


def _jordan_div(lam, b):
    """``d`` with ``lam o d = b`` per cone (``lam`` strictly inside)."""
    d0 = np.einsum("im,im->m", _Jc * lam, b) / _det(lam)
    out = (b - d0 * lam) / lam[0]
    out[0] = d0
    return out


def _max_step(u, d, qc):
    """Largest ``a >= 0`` with ``u + a d`` in every cone (``inf`` when unbounded); ``u`` strictly inside.

    The first positive root of ``det(u + a d) = qa a^2 + qb a + qc`` (``qc > 0``): a path that leaves the cone
    crosses ``det = 0`` first. Roots by the cancellation-free pair ``q / qa``, ``qc / q``; ``qc = det(u)``."""
    qa = _det(d)
    qb = 2.0 * np.einsum("im,im->m", _Jc * u, d)
    with np.errstate(divide="ignore", invalid="ignore"):
        q = -0.5 * (qb + np.copysign(np.sqrt(qb * qb - 4.0 * qa * qc), qb))  # nan: no real root
        r = np.concatenate([q / qa, qc / q])
    r = r[r > 0.0]  # nan (no root, 0 / 0) drops out, inf (linear case) stays
    return float(r.min()) if r.size else np.inf
