"""Residues for fixed poles by convex programmes: the minimax fit of ``C`` and ``D`` under exact DC and
feedthrough equalities, optionally with gain bounds between the samples (steps 4 and 5 of
:mod:`sysid.relocation`)."""

import numpy as np

from .errors import SolverError
from .minimax_socp import minimax_socp
from .state_space import shifted_solve

__all__ = ["socp_minimax", "gap_bounds", "minimax_cd", "resonance_points", "bounds_at", "GAP_REFINE", "GAP_SLACK",
           "GAP_FLOOR", "GAP_NOISE", "RESONANCE_OFFSETS"]

#: Points per data interval, slack over the larger neighbouring sample and floor (fraction of the peak) of
#: the gain bound between samples (:func:`gap_bounds`).
GAP_REFINE, GAP_SLACK, GAP_FLOOR = 8, 1.25, 0.05
#: Noise standard deviations added to the larger neighbouring sample's magnitude in the gain bound between
#: samples (:func:`gap_bounds` with ``noise``): a noisy sample's magnitude is below the true one by up to about
#: three of them (the smallest of a few hundred Rayleigh-distributed deviations is not the concern; the largest
#: deficit of the two neighbours of a resonance is), so a bound built from noisy samples without them rejects the
#: true response.
GAP_NOISE = 3.0

#: First stage of :func:`socp_minimax` by the dedicated interior-point method of :mod:`sysid.minimax_socp`
#: (Clarabel only when it does not converge, and for the ``within`` second stage); False: Clarabel always.
#: Only from :data:`DEDICATED_MIN_UNKNOWNS` unknowns on: below, its NumPy call overhead per iteration makes
#: it less than 1.5 times faster than Clarabel (captured T1-T6 programmes, median Clarabel / dedicated time per
#: programme: N = 11 1.18, 16 1.33, 21 1.48, 26 1.62, 41 2.31, 56 2.71; ``python bench/minimax_socp_bench.py
#: --orders 10,15,20,25,40,55``, 2026-12-04, loaded 2-core machine).
DEDICATED_SOLVER = True
DEDICATED_MIN_UNKNOWNS = 24

#: Where a pole's resonance is looked for (:func:`resonance_points`): offsets from the pole's angle, in units of
#: its distance ``|1 - r|`` from the unit circle (the half width of the resonance peak).
RESONANCE_OFFSETS = np.array([-2.0, -1.0, -0.5, 0.0, 0.5, 1.0, 2.0])


# --------------------------------------------------------------------------------------------- minimax
def socp_minimax(Q, g, E, f, tol=1e-9, Qb=None, ub=None, within=None):
    """Solve ``min_y max_k |Q_k y - g_k|`` s.t. ``E y = f`` (and ``|Qb_j y| <= ub_j``) with the dedicated
    interior-point method or Clarabel (conic form, one 3-cone per row).

    ``Q`` (K, N) complex, ``g`` (K,) complex, ``E`` (c, N) real, ``f`` (c,); optional bounds ``Qb`` (J, N)
    complex, ``ub`` (J,) positive. Variables ``x = [y; t]``; Clarabel's form ``A x + s = b``, ``s`` in the
    cones: zero cone for ``E y = f``, for each ``k`` the cone ``s = (t, Re(Q_k y - g_k), Im(Q_k y - g_k))``,
    and for each bound ``s = (ub_j, Re(Qb_j y), Im(Qb_j y))``.

    With ``within = eps`` (lexicographic second stage), the minimax level ``t*`` found first becomes a bound:
    the answer minimises ``sum_k |Q_k y - g_k|^2`` subject to ``|Q_k y - g_k| <= (1 + eps) t*`` and the same
    equalities and bounds (the minimax solution is flat over the samples - equioscillation - and leaves the
    low-error region unused; the second stage spends that freedom on the least-squares error without giving up
    more than ``eps`` of the max error). When the second stage fails, the minimax answer is returned.

    The first stage is solved by :func:`sysid.minimax_socp.minimax_socp` when :data:`DEDICATED_SOLVER` is set
    and ``N >= DEDICATED_MIN_UNKNOWNS`` (the same tolerance); when that method does not converge (iteration
    cap, lost definiteness: e.g. an infeasible bounded programme), Clarabel solves the programme and reports its
    status.

    Returns ``(y, status)``; ``y`` is None when the solver did not succeed.
    """
    if DEDICATED_SOLVER and within is None and Q.shape[1] >= DEDICATED_MIN_UNKNOWNS:
        y, _ = minimax_socp(Q, g, E, f, Qb=Qb, ub=ub, tol=tol)
        if y is not None:
            return y, "optimal"
    return _socp_clarabel(Q, g, E, f, tol, Qb, ub, within)


def _socp_clarabel(Q, g, E, f, tol=1e-9, Qb=None, ub=None, within=None):
    """:func:`socp_minimax` by Clarabel (conic form, one 3-cone per row)."""
    import clarabel
    import scipy.sparse as sp

    K, N = Q.shape
    c = E.shape[0]
    rows = []
    b = []
    if c:
        rows.append(np.hstack([E, np.zeros((c, 1))]))
        b.append(f)
    blk = np.zeros((3 * K, N + 1))
    blk[0::3, N] = -1.0  # s_t = t
    blk[1::3, :N] = -Q.real  # s = b - A x = Q y - g  ->  A = -Q, b = -g
    blk[2::3, :N] = -Q.imag
    bb = np.zeros(3 * K)
    bb[1::3] = -g.real
    bb[2::3] = -g.imag
    rows.append(blk)
    b.append(bb)
    J = 0 if Qb is None else Qb.shape[0]
    if J:
        blk = np.zeros((3 * J, N + 1))
        blk[1::3, :N] = -Qb.real
        blk[2::3, :N] = -Qb.imag
        bb = np.zeros(3 * J)
        bb[0::3] = ub
        rows.append(blk)
        b.append(bb)
    Am = sp.csc_matrix(np.vstack(rows))
    bv = np.concatenate(b)
    Pm = sp.csc_matrix((N + 1, N + 1))
    q = np.zeros(N + 1)
    q[N] = 1.0
    cones = ([clarabel.ZeroConeT(c)] if c else []) + [clarabel.SecondOrderConeT(3)] * (K + J)
    st = clarabel.DefaultSettings()
    st.verbose = False
    st.tol_gap_abs = st.tol_gap_rel = st.tol_feas = tol  # relative to the unit-scaled data
    st.max_iter = 200
    # no iterative refinement of each KKT solve: it took 40 % of the solve time on these small dense
    # programmes (T4, N_r = 25: 0.196 -> 0.116 s for the fit's eight programmes, objectives equal to 2e-10,
    # the iteration counts equal to +-1; measured 2026-12-03); the equalities are projected exactly afterwards
    st.iterative_refinement_enable = False
    y, status = _clarabel(Pm, q, Am, bv, cones, st, N)
    if y is None or within is None:
        return y, status
    # second stage: t fixed at (1 + within) t*, least squares of the residuals; x = y, A from the rows above
    # without the t column, the cone heads move into b
    t_star = float(np.max(np.abs(Q @ y - g)))
    A2 = Am.tocsc()[:, :N]
    b2 = bv.copy()
    b2[c:c + 3 * K:3] = (1.0 + within) * t_star
    # sum |Q y - g|^2 = y^T Re(Q^H Q) y - 2 Re(Q^H g)^T y + const (Clarabel: 1/2 x^T P x + q^T x)
    P2 = sp.csc_matrix(np.triu(2.0 * (Q.conj().T @ Q).real))
    q2 = -2.0 * (Q.conj().T @ g).real
    y2, status2 = _clarabel(P2, q2, A2, b2, cones, st, N)
    if y2 is None or np.max(np.abs(Q @ y2 - g)) > (1.0 + 2.0 * within) * t_star:
        return y, status
    return y2, status2


def _clarabel(P, q, A, b, cones, settings, N):
    """Run Clarabel; ``(x[:N], status)``, ``x`` None when it did not succeed."""
    import clarabel

    try:
        sol = clarabel.DefaultSolver(P, q, A, b, cones, settings).solve()
    except Exception as exc:  # pragma: no cover - solver internals
        return None, f"solver_error: {exc}"
    status = str(sol.status)
    ok = status in ("Solved", "AlmostSolved", "SolveStatus.Solved", "SolveStatus.AlmostSolved")
    if not ok:
        return None, status
    return np.array(sol.x[:N]), "optimal" if "Almost" not in status else "optimal_inaccurate"


def gap_bounds(z: np.ndarray, G: np.ndarray, refine: int = GAP_REFINE, slack: float = GAP_SLACK,
               floor: float = GAP_FLOOR, noise=None) -> tuple[np.ndarray, np.ndarray]:
    """Points between the data frequencies and the gain a model may reach there.

    Between two neighbouring samples a model has no data to follow; on the bilinear grid the top intervals
    are wide (``omega`` 14.6 to 29.2 on the paper's grid), and a fit that matches every sample can resonate
    inside them. The bound at a point between samples ``k`` and ``k + 1`` (in ``omega_d``) is
    ``slack * (max(|G_k|, |G_k+1|) + GAP_NOISE * sigma * peak_out) + floor * peak`` per channel (``peak``: the
    channel's, ``peak_out``: its output's over all inputs, ``sigma``: the output's noise level relative to
    ``peak_out``, 0 without ``noise``); the interval above the highest sample, up to
    ``omega_d = pi``, takes the highest sample alone.

    Parameters
    ----------
    z : ndarray, shape (K,), complex
        Data points ``exp(1j omega_d)``, ``0 <= omega_d <= pi``.
    G : ndarray, shape (p, m, K), complex
    refine : int
        Points per interval (``refine - 1`` strictly inside each).
    slack, floor : float
        Relative to the larger neighbouring sample and to the channel's peak.
    noise : array_like, shape (p,), optional
        Noise standard deviation of each output relative to its peak (:func:`sysid.noise.noise_level`); the
        samples' magnitudes are taken :data:`GAP_NOISE` of them higher. Measured on the 12-state systems of
        ``bench/sysid_truth_between_bench.py`` with 0.3 - 1 % noise: the true response breaks the bounds of the
        noisy samples by 2 - 5 %, and a fit at the noise level with it.

    Returns
    -------
    z_b : ndarray, shape (J,), complex
    u_b : ndarray, shape (p, m, J), positive
    """
    wd = np.abs(np.angle(np.asarray(z, dtype=complex)))
    order = np.argsort(wd)
    wd = wd[order]
    mag = np.abs(np.asarray(G))[:, :, order]
    peak = np.maximum(mag.max(axis=2, keepdims=True), np.finfo(float).tiny)
    ends = np.append(wd, np.pi)
    env = np.concatenate([np.maximum(mag[:, :, :-1], mag[:, :, 1:]), mag[:, :, -1:]], axis=2)  # (p, m, K)
    if noise is not None:
        out_peak = mag.max(axis=(1, 2), keepdims=True)   # each output's peak over its inputs, as noise_level's
        env = env + GAP_NOISE * np.asarray(noise, dtype=float).reshape(-1, 1, 1) * out_peak
    t = np.arange(1, refine) / refine
    pts = ends[:-1, None] + (ends[1:] - ends[:-1])[:, None] * t[None, :]  # (K, refine - 1)
    wide = (ends[1:] - ends[:-1]) > 1e-12
    pts = pts[wide].reshape(-1)
    u = np.repeat(env[:, :, wide], refine - 1, axis=2)
    return np.exp(1j * pts), slack * u + floor * peak


def resonance_points(lam, offsets=RESONANCE_OFFSETS) -> np.ndarray:
    """Points of the unit circle where the resonances of the discrete poles ``lam`` peak.

    A fixed grid between the samples misses a resonance narrower than its spacing (a pole at radius
    ``1 - 1e-3`` peaks over ``1e-3`` rad of ``omega_d``; eight points per interval of McKelvey's 64-interval grid
    are ``6e-3`` apart). For each pole ``r exp(i theta)`` with ``|1 - r| < 0.5`` these are the angles
    ``theta + k |1 - r|`` for ``k`` in ``offsets``, clipped to ``[0, pi]`` (the peak and its flanks).

    Parameters
    ----------
    lam : array_like, shape (n,), complex
        Discrete poles (eigenvalues of ``A``).
    offsets : array_like, shape (k,)

    Returns
    -------
    ndarray, shape (J,), complex
        ``exp(1j omega_d)`` at the distinct angles, ``0 <= omega_d <= pi`` (empty when no pole is near the
        circle).
    """
    lam = np.asarray(lam, dtype=complex).reshape(-1)
    near = np.isfinite(lam) & (np.abs(1.0 - np.abs(lam)) < 0.5)
    r, theta = np.abs(lam[near]), np.abs(np.angle(lam[near]))
    wd = np.clip(theta[:, None] + np.abs(1.0 - r)[:, None] * np.asarray(offsets)[None, :], 0.0, np.pi)
    return np.exp(1j * np.unique(wd))


def bounds_at(z, zb, ub) -> np.ndarray:
    """The :func:`gap_bounds` at other points ``z`` of the circle: the larger bound of the two points of ``zb``
    on either side of each (in ``omega_d``).

    The bounds are constant across each data interval, and the two neighbouring points belong to the interval
    that holds ``z`` or to the one next to it (when a sample lies between them), so the larger one is never tighter
    than the bound of ``z``'s own interval; a point beyond the first or last point of ``zb`` takes that point's.

    Parameters
    ----------
    z : ndarray, shape (J,), complex
    zb : ndarray, shape (L,), complex; ub : ndarray, shape (p, m, L)
        From :func:`gap_bounds` (``L >= 1``).

    Returns
    -------
    ndarray, shape (p, m, J)
    """
    wb = np.abs(np.angle(zb))
    order = np.argsort(wb)
    wb, ub = wb[order], np.asarray(ub)[:, :, order]
    w = np.abs(np.angle(np.asarray(z, dtype=complex)))
    i = np.searchsorted(wb, w)
    left, right = np.clip(i - 1, 0, wb.size - 1), np.clip(i, 0, wb.size - 1)
    return np.maximum(ub[:, :, left], ub[:, :, right])


def basis_response(A, B, z, eig=None):
    """``(z_k I - A)^-1 B`` for all k, shape (K, n, m), complex: the Schur form
    (:func:`sysid.state_space.shifted_solve`), or with ``eig``
    (:func:`sysid.state_space.eigen_parts` of ``A``: ``(lam, V, V^-1)``) ``V diag(1 / (z_k - lam)) (V^-1 B)``."""
    z = np.asarray(z, dtype=complex).reshape(-1)
    if eig:
        lam, V, Vinv = eig
        return V[None] @ ((Vinv @ B)[None] / (z[:, None, None] - lam[None, :, None]))
    return shifted_solve(A, B, z)


def minimax_cd(A, B, z, G, *, dc_gain=None, feedthrough=None, weights=None, start=None, bound=None,
               within=None, eig=None):
    """Minimax fit of ``C`` and ``D`` with ``A``, ``B`` fixed, under exact DC / feedthrough equalities.

    For each output ``i`` (the rows of ``C`` and ``D`` decouple):

        min_{C_i, D_i}  max_{j, k} w_ijk |C_i (z_k I - A)^-1 B_j + D_ij - G_ijk|
        s.t.  C_i (I - A)^-1 B + D_i = dc_gain_i,   C_i (-I - A)^-1 B + D_i = feedthrough_i,

    a second-order cone programme (one cone per sample), solved by Clarabel (its conic form is built
    directly: a cvxpy compile per problem size cost about 2 s, the solve milliseconds). The unknowns are
    expressed in an orthonormal basis of the column space of the regression matrix (thin QR after column
    equilibration), so the problem is well conditioned whatever the realisation.

    Parameters
    ----------
    A : ndarray, shape (n, n); B : ndarray, shape (n, m)
    z : ndarray, shape (K,), complex
        ``exp(1j omega_d)``.
    G : ndarray, shape (p, m, K), complex
    dc_gain, feedthrough : ndarray, shape (p, m), real, optional
    weights : ndarray, shape (p, m, K), nonnegative, optional
        Multiply the absolute errors (default 1).
    start : tuple (C, D), optional
        A feasible fit (e.g. least squares); the answer is never worse than it in the weighted max error
        (when the solver does worse, e.g. inaccurate, the start is returned for that output). With ``bound``,
        a start that breaks the bound is not returned: the output gets NaN and the status says why.
    bound : tuple (z_b, u_b), optional
        Gain bounds at further points: ``|G_ij(z_b[l])| <= u_b[i, j, l]``, ``z_b`` shape (J,) on the unit
        circle, ``u_b`` shape (p, m, J) positive (e.g. :func:`gap_bounds`); more cones of the same programme.
    within : float, optional
        Lexicographic second stage of :func:`socp_minimax`: least-squares residues among those within
        ``1 + within`` of the minimax level (per output).
    eig : tuple, optional
        :func:`sysid.state_space.eigen_parts` of ``A``: the basis responses ``(z_k I - A)^-1 B`` at the samples
        and bound points are formed in the modal form (``O(K n^2 m)`` instead of ``K`` LU factorisations).

    Returns
    -------
    C : ndarray, shape (p, n); D : ndarray, shape (p, m); status : str
    """
    A = np.asarray(A, dtype=float)
    B = np.asarray(B, dtype=float)
    G = np.asarray(G, dtype=complex)
    p, m, K = G.shape
    n = A.shape[0]
    X = basis_response(A, B, z, eig)  # (K, n, m)
    if bound is not None:
        zb = np.asarray(bound[0], dtype=complex)
        ub = np.broadcast_to(np.asarray(bound[1], dtype=float), (p, m, zb.size))
        Xb = basis_response(A, B, zb, eig)
    W = np.ones((p, m, K)) if weights is None else np.broadcast_to(np.asarray(weights, dtype=float), (p, m, K))
    cons_pts = []
    if dc_gain is not None:
        cons_pts.append((np.linalg.solve(np.eye(n) - A, B), np.asarray(dc_gain, dtype=float)))
    if feedthrough is not None:
        cons_pts.append((np.linalg.solve(-np.eye(n) - A, B), np.asarray(feedthrough, dtype=float)))
    C = np.zeros((p, n))
    D = np.zeros((p, m))
    statuses = []
    N = n + m
    for i in range(p):
        # rows (j, k): [X[k, :, j], e_j] . [C_i, D_i] ~= G[i, j, k]
        Phi = np.zeros((m * K, N), dtype=complex)
        g = np.zeros(m * K, dtype=complex)
        w = np.zeros(m * K)
        for j in range(m):
            Phi[j * K:(j + 1) * K, :n] = X[:, :, j]
            Phi[j * K:(j + 1) * K, n + j] = 1.0
            g[j * K:(j + 1) * K] = G[i, j]
            w[j * K:(j + 1) * K] = W[i, j]
        Phi = Phi * w[:, None]
        g = g * w
        E = np.vstack([np.hstack([Xc.T, np.eye(m)]) for Xc, _ in cons_pts]) if cons_pts else np.zeros((0, N))
        f = np.concatenate([v[i] for _, v in cons_pts]) if cons_pts else np.zeros(0)
        col = np.linalg.norm(np.vstack([Phi.real, Phi.imag]), axis=0)
        col[col == 0] = 1.0
        Qf, R = np.linalg.qr(np.vstack([Phi.real, Phi.imag]) / col)
        d = np.abs(np.diag(R))
        keep = d > 1e-12 * d.max()
        if not keep.all():  # rank deficient (should not happen for distinct poles): fall back to the start
            statuses.append("rank-deficient")
            if start is None:
                raise SolverError("minimax residue fit: rank-deficient regression matrix; give a start")
            C[i], D[i] = start[0][i], start[1][i]
            continue
        Mt = np.linalg.inv(R) / col[:, None]  # theta = Mt @ y
        Q = Qf[:m * K] + 1j * Qf[m * K:]
        gs = float(np.abs(g).max()) or 1.0
        Ey = E @ Mt
        ce = np.linalg.norm(Ey, axis=1, keepdims=True) if E.shape[0] else None
        E_y = Ey / ce if E.shape[0] else Ey
        f_y = f / gs / ce[:, 0] if E.shape[0] else f
        Qb = ubs = None
        start_ok = start is not None
        if bound is not None:
            Phib = np.zeros((m * zb.size, N), dtype=complex)
            for j in range(m):
                Phib[j * zb.size:(j + 1) * zb.size, :n] = Xb[:, :, j]
                Phib[j * zb.size:(j + 1) * zb.size, n + j] = 1.0
            Qb = Phib @ Mt
            ubs = ub[i].reshape(-1) / gs
            if start_ok:
                start_ok = bool(np.all(np.abs(Phib @ np.concatenate([start[0][i], start[1][i]])) <= ub[i].reshape(-1)))
        y, status = socp_minimax(Q, g / gs, E_y, f_y, Qb=Qb, ub=ubs, within=within)
        y = None if y is None else y * gs
        statuses.append(status)
        if y is None or status not in ("optimal", "optimal_inaccurate"):
            if start is None:
                raise SolverError(f"minimax residue fit failed (status {status!r}); use the least-squares fit")
            C[i], D[i] = (start[0][i], start[1][i]) if start_ok else (np.nan, np.nan)
            continue
        theta = Mt @ y
        if E.shape[0]:  # exact projection onto the equalities (minimum-norm correction in theta)
            r = E @ theta - f
            theta = theta - np.linalg.lstsq(E, r, rcond=None)[0]
        C[i], D[i] = theta[:n], theta[n:]
        if start_ok:
            e_new = np.max(np.abs(Phi @ theta - g))
            e_old = np.max(np.abs(Phi @ np.concatenate([start[0][i], start[1][i]]) - g))
            if not e_new <= e_old:
                C[i], D[i] = start[0][i], start[1][i]
    status = "optimal" if all(s == "optimal" for s in statuses) else ",".join(sorted(set(statuses)))
    return C, D, status
