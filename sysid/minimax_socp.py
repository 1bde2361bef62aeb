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
scalings vectorised over the cones and solved by Cholesky.

The solver never guesses: it returns ``None`` when it has not met its tolerances within :data:`MAX_ITER`
iterations, when the normal equations lose positive definiteness or when the iterates stop being finite
(e.g. an infeasible bounded programme), and the caller falls back to a general-purpose conic solver.
"""

import numpy as np

__all__ = ["minimax_socp", "MAX_ITER", "STEP_FRACTION"]

#: Iteration cap (the programmes of :func:`sysid.residues.minimax_cd` take 10-25).
MAX_ITER = 60

#: Fraction of the distance to the cone boundary taken by each step.
STEP_FRACTION = 0.99

_J = np.array([1.0, -1.0, -1.0])  # the hyperbolic reflection diag(1, -1, -1)


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
        ``dual_residual`` (relative, as in the stopping rule), ``reason``.
    """
    Q = np.asarray(Q, dtype=complex)
    g = np.asarray(g, dtype=complex)
    E = np.asarray(E, dtype=float).reshape(-1, Q.shape[1])
    f = np.asarray(f, dtype=float).reshape(-1)
    K, N = Q.shape
    c = E.shape[0]
    # null space of E: E^T = [U1 U2] [R; 0]  ->  y0 = U1 R^-T f (least norm), Z = U2
    if c:
        U, R = np.linalg.qr(E.T, mode="complete")
        d = np.abs(np.diag(R[:c]))
        if d.min() <= 1e-12 * max(d.max(), 1e-300):
            return None, {"iterations": 0, "level": np.nan, "gap": np.nan, "reason": "rank-deficient E"}
        y0 = U[:, :c] @ np.linalg.solve(R[:c].T, f)
        Z = U[:, c:]
    else:
        y0 = np.zeros(N)
        Z = np.eye(N)
    n = Z.shape[1]
    n1 = n + 1
    J = 0 if Qb is None else Qb.shape[0]
    M = K + J
    # G (M, 3, n1), h (M, 3): s = h - G x
    QZ = Q @ Z
    r0 = Q @ y0 - g
    G = np.zeros((M, 3, n1))
    h = np.zeros((M, 3))
    G[:K, 0, n] = -1.0
    G[:K, 1, :n] = -QZ.real
    G[:K, 2, :n] = -QZ.imag
    h[:K, 1] = r0.real
    h[:K, 2] = r0.imag
    if J:
        QbZ = Qb @ Z
        b0 = Qb @ y0
        G[K:, 1, :n] = -QbZ.real
        G[K:, 2, :n] = -QbZ.imag
        h[K:, 0] = ub
        h[K:, 1] = b0.real
        h[K:, 2] = b0.imag
    cvec = np.zeros(n1)
    cvec[n] = 1.0
    Gf = G.reshape(3 * M, n1)
    hf = h.reshape(-1)
    hnorm = max(1.0, float(np.abs(hf).max()))
    absG = np.abs(G)
    JG = _J[None, :, None] * G

    # starting point: x least squares of G x ~ h, z least norm with G^T z = -c, both shifted into the cones
    try:
        L0 = np.linalg.cholesky(Gf.T @ Gf)
    except np.linalg.LinAlgError:
        return None, {"iterations": 0, "level": np.nan, "gap": np.nan, "reason": "singular G"}
    x = _chol_solve(L0, Gf.T @ hf)
    s = hf - Gf @ x
    z = -(Gf @ _chol_solve(L0, cvec))
    s = _shift_into_cone(s.reshape(M, 3))
    z = _shift_into_cone(z.reshape(M, 3))

    info = {"iterations": 0, "level": np.nan, "gap": np.nan, "reason": "iteration cap"}
    for it in range(MAX_ITER):
        rx = np.einsum("mik,mi->k", G, z) + cvec  # dual residual G^T z + c
        rz = s + (Gf @ x).reshape(M, 3) - h  # primal residual
        gap = float(np.einsum("mi,mi->", s, z))
        pcost = x[n]
        pres = float(np.abs(rz).max()) / hnorm
        # relative to the size of the terms summed in G^T z (bound rows of large gain, e.g. near a resonance,
        # carry large multipliers whose sum cancels to round-off of that size, not of 1)
        dres = float(np.abs(rx).max()) / max(1.0, float(np.einsum("mik,mi->k", absG, np.abs(z)).max()))
        info.update(iterations=it, gap=gap, primal_residual=pres, dual_residual=dres)
        if not (np.isfinite(gap) and np.isfinite(pres) and np.isfinite(dres)):
            info["reason"] = "not finite"
            return None, info
        if pres <= tol and dres <= tol and (gap <= tol * abs(pcost) or gap <= 1e-2 * tol):
            y = y0 + Z @ x[:n]
            info.update(level=float(np.abs(Q @ y - g).max()), reason="converged")
            return y, info
        mu = gap / M
        # Nesterov-Todd scaling W = beta (2 v v^T - J) per cone, W z = W^-1 s = lam
        ds = _det(s)
        dz = _det(z)
        if np.any(ds <= 0) or np.any(dz <= 0):
            info["reason"] = "left the cone"
            return None, info
        sb = s / np.sqrt(ds)[:, None]
        zb = z / np.sqrt(dz)[:, None]
        gam = np.sqrt(0.5 * (1.0 + np.einsum("mi,mi->m", sb, zb)))
        wb = (sb + _J * zb) / (2.0 * gam)[:, None]
        beta = (ds / dz) ** 0.25
        v = wb.copy()
        v[:, 0] += 1.0
        v /= np.sqrt(2.0 * (wb[:, 0] + 1.0))[:, None]
        u = _J * v  # W^-1 = (2 u u^T - J) / beta
        lam = _apply(v, beta, z, inverse=False)
        # W^-1 G and the normal equations
        uG = np.einsum("mi,mik->mk", u, G)
        ib = 1.0 / beta
        Gt = (2.0 * (u * ib[:, None])[:, :, None]) * uG[:, None, :] - JG * ib[:, None, None]
        Gtf = Gt.reshape(3 * M, n1)
        Ri = _inverse_factor(Gtf)  # H^-1 = Gt^T Gt = Ri Ri^T
        if Ri is None:
            info["reason"] = "normal equations singular"
            return None, info
        Winv_rz = _apply(u, beta, rz, inverse=True)

        def newton(bs):
            # G^T dz = -rx, G dx + ds = -rz, lam o (W dz + W^-1 ds) = bs  ->  (dx, W^-1 ds, W dz)
            d = _jordan_div(lam, bs)
            rhs = -rx + np.einsum("mik,mi->k", Gt, -Winv_rz - d)
            dx = Ri @ (Ri.T @ rhs)
            wdz = (Gtf @ dx).reshape(M, 3) + d + Winv_rz
            return dx, d - wdz, wdz

        lamsq = _jordan(lam, lam)
        lam2 = np.concatenate([lam, lam])
        qc = np.concatenate([_det(lam)] * 2)
        dxa, dsa, dza = newton(-lamsq)
        alpha_a = min(1.0, _max_step(lam2, np.concatenate([dsa, dza]), qc))
        sigma = (1.0 - alpha_a) ** 3
        bs = -lamsq - _jordan(dsa, dza)
        bs[:, 0] += sigma * mu
        dx, dst, dzt = newton(bs)
        alpha = min(1.0, STEP_FRACTION * _max_step(lam2, np.concatenate([dst, dzt]), qc))
        x = x + alpha * dx
        s = s + alpha * _apply(v, beta, dst, inverse=False)
        z = z + alpha * _apply(u, beta, dzt, inverse=True)
    info["iterations"] = MAX_ITER
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
    """``u0^2 - |u1|^2`` per cone, (M,), as a product of two sums (less cancellation near the boundary)."""
    r = np.hypot(u[:, 1], u[:, 2])
    return (u[:, 0] - r) * (u[:, 0] + r)


def _shift_into_cone(u):
    """``u + a e`` with ``a = 1 + max(0, max_k (|u_k1| - u_k0))`` when some ``u_k`` is not strictly inside."""
    a = float(np.max(np.hypot(u[:, 1], u[:, 2]) - u[:, 0]))
    if a >= 0.0:
        u = u.copy()
        u[:, 0] += 1.0 + a
    return u


def _apply(p, beta, a, inverse):
    """``W a`` (``p = v``) or ``W^-1 a`` (``p = J v``) per cone: ``(2 p (p^T a) - J a) * beta^(+-1)``."""
    out = (2.0 * np.einsum("mi,mi->m", p, a))[:, None] * p - _J * a
    return out / beta[:, None] if inverse else out * beta[:, None]


def _jordan(a, b):
    """Jordan product per cone: ``(a^T b, a0 b1 + b0 a1)``."""
    out = a[:, 0:1] * b + b[:, 0:1] * a
    out[:, 0] = np.einsum("mi,mi->m", a, b)
    return out


def _jordan_div(lam, b):
    """``d`` with ``lam o d = b`` per cone (``lam`` strictly inside)."""
    l0 = lam[:, 0]
    d0 = (l0 * b[:, 0] - lam[:, 1] * b[:, 1] - lam[:, 2] * b[:, 2]) / _det(lam)
    out = (b - d0[:, None] * lam) / l0[:, None]
    out[:, 0] = d0
    return out


def _max_step(u, d, qc):
    """Largest ``a >= 0`` with ``u + a d`` in every cone (``inf`` when unbounded); ``u`` strictly inside.

    The first positive root of ``det(u + a d) = qa a^2 + qb a + qc`` (``qc > 0``): a path that leaves the cone
    crosses ``det = 0`` first. Roots by the cancellation-free pair ``q / qa``, ``qc / q``; ``qc = det(u)``."""
    qa = _det(d)
    qb = 2.0 * np.einsum("mi,mi->m", u * _J, d)
    with np.errstate(divide="ignore", invalid="ignore"):
        q = -0.5 * (qb + np.copysign(np.sqrt(qb * qb - 4.0 * qa * qc), qb))  # nan: no real root
        r = np.concatenate([q / qa, qc / q])
    r = r[r > 0.0]  # nan (no root, 0 / 0) drops out, inf (linear case) stays
    return float(r.min()) if r.size else np.inf
