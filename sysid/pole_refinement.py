"""Gauss-Newton refinement of stable poles by variable projection (step 2 of :mod:`sysid.relocation`)."""

import warnings

import numpy as np

from .levenberg_marquardt import bounded_levenberg_marquardt
from .poles import floor_at, pair_poles, partial_fraction_basis, pole_groups

__all__ = ["refine_poles", "stable_params", "params_to_poles", "derivative_columns", "derivative_factors"]


# --------------------------------------------------------------------------------------------- refinement
def stable_params(poles: np.ndarray, floor=None) -> np.ndarray:
    """Poles (canonical order) -> real parameters: ``log(-Re)`` for every real pole, ``log(-Re - f(Im))`` and
    ``Im`` per pair (``f``: the :func:`resolution_floor`, 0 without one)."""
    out = []
    i = 0
    while i < poles.size:
        a = poles[i]
        if a.imag != 0:
            f = float(floor_at(np.array([a.imag]), floor)[0][0])
            out.append(np.log(max(-a.real - f, 1e-9 * -a.real)))
            out.append(a.imag)
            i += 2
        else:
            out.append(np.log(-a.real))
            i += 1
    return np.array(out)


def _imag_param_mask(poles: np.ndarray) -> np.ndarray:
    """True for the parameters of :func:`stable_params` that are imaginary parts."""
    mask = []
    i = 0
    while i < poles.size:
        if poles[i].imag != 0:
            mask += [False, True]
            i += 2
        else:
            mask.append(False)
            i += 1
    return np.array(mask, dtype=bool)


def params_to_poles(x: np.ndarray, template: np.ndarray, floor=None) -> np.ndarray:
    """Poles from the stable parameters ``x`` (:func:`stable_params`), in the order of ``template``.

    A real pole is ``-exp(u)``; a pair ``-(f(|v|) + exp(u)) +- i |v|`` with ``f`` the :func:`resolution_floor`
    (0 without one). ``template`` (shape (n,), canonical order) only says which poles are real and which pairs.
    """
    idx, pair = pole_groups(template)
    width = np.where(pair, 2, 1)
    pos = np.cumsum(width) - width  # each group's first parameter
    x = np.asarray(x, dtype=float)
    u = np.exp(x[pos])
    im = np.where(pair, np.abs(x[np.minimum(pos + 1, x.size - 1)]), 0.0)
    im = np.where(pair & (im == 0), 1e-300, im)
    a = -(u + np.where(pair, floor_at(im, floor)[0], 0.0)) + 1j * im
    out = np.empty(template.size, dtype=complex)
    out[idx] = a
    out[idx[pair] + 1] = np.conj(a[pair])
    return out


def derivative_columns(s, poles, theta, floor=None, factors=None):
    """``(dPhi / dx_q) theta`` for every stable parameter ``x_q`` (:func:`stable_params`): shape (K, n_par).

    Vectorised form of :func:`_basis_derivatives` contracted with the coefficients ``theta`` (length >= n;
    entries beyond ``n``, e.g. the constant, do not depend on the poles). With a :func:`resolution_floor`
    ``f``, a pair's real part is ``-(f(Im) + exp(u))``: ``dRe/du = Re + f`` and ``dRe/dIm = -f'(Im)``.
    ``factors``: :func:`derivative_factors` of ``(s, poles, floor)`` precomputed (they do not depend on
    ``theta``; the same arithmetic).
    """
    if factors is None:
        factors = derivative_factors(s, poles, floor)
    q1, q2, idx, pair, a, f, slope, pos_u, n_par = factors
    n = poles.size
    t1 = theta[idx]
    t2 = np.where(pair, theta[np.minimum(idx + 1, n - 1)], 0.0)
    d_re = np.where(pair, (q1 + q2) * t1 + 1j * (q1 - q2) * t2, q1 * t1)  # d(contribution)/d(Re a)
    du = (a.real + f) * d_re
    dv = 1j * (q1 - q2) * t1 - (q1 + q2) * t2 - slope * d_re
    out = np.empty((s.size, n_par), dtype=complex)
    out[:, pos_u] = du
    out[:, pos_u[pair] + 1] = dv[:, pair]
    return out


def derivative_factors(s, poles, floor=None):
    """The parts of :func:`derivative_columns` that depend on the poles only.

    Returns
    -------
    tuple
        ``(q1, q2, idx, pair, a, f, slope, pos_u, n_par)``: ``1 / (s - a)^2`` and ``1 / (s - conj a)^2``
        (K, g) per group ``a`` (:func:`pole_groups` ``idx``, ``pair``), the floor ``f`` and its slope (g,), each
        group's first parameter ``pos_u`` (g,) and the number of parameters.
    """
    fin = np.isfinite(s)
    idx, pair = pole_groups(poles)
    a = poles[idx]
    q1 = np.zeros((s.size, idx.size), dtype=complex)
    q2 = np.zeros((s.size, idx.size), dtype=complex)
    q1[fin] = 1.0 / (s[fin, None] - a[None, :]) ** 2
    q2[fin] = 1.0 / (s[fin, None] - np.conj(a)[None, :]) ** 2
    f, slope = floor_at(a.imag, floor)
    # parameter order: per real pole u; per pair (u, v)
    width = np.where(pair, 2, 1)
    pos_u = np.cumsum(width) - width
    return q1, q2, idx, pair, a, f, slope, pos_u, int(np.sum(width))


def _bad_step(P, K, dc, n_coef):
    """A residual that makes :func:`sysid.levenberg_marquardt.bounded_levenberg_marquardt` reject a step."""
    return np.full(P * (2 * K + (1 if dc is not None else 0) + n_coef), 1e10)


class _Projection:
    """The variable-projection problem of :func:`refine_poles`: its residual and Kaufman Jacobian at the stable
    parameters ``x``, computed apart.

    :func:`sysid.levenberg_marquardt.bounded_levenberg_marquardt` asks for the residual at every trial step and
    for the Jacobian only at the accepted ones, so a rejected step costs the least-squares coefficients alone (the derivative columns
    and their projection are about half an evaluation). The residual's factorisation is kept for the Jacobian
    at the same ``x``; the arithmetic is that of one joint evaluation.
    """

    def __init__(self, s, Hs, W, common_w, fixed_d, dc, ft, mu, ridge, template, floor):
        self.Hs, self.W, self.common_w, self.fixed_d = Hs, W, common_w, fixed_d
        self.dc, self.ft, self.mu, self.ridge, self.template, self.floor = dc, ft, mu, ridge, template, floor
        self.s_all = np.concatenate([s, [0.0 + 0j]])   # the samples, then s = 0 (the DC penalty's row)
        self._hr = None
        from scipy.linalg import solve_triangular

        self._solve_triangular = solve_triangular
        self._key = None
        self._r = None
        self._state = None   # (poles, [(Ar, Q, theta) per channel]) at self._key; None after a rejected step
        self._prev = (None, None, None)   # (key, r, state) of the point before, while it was good

    def residual(self, x: np.ndarray) -> np.ndarray:
        """Weighted residuals of all channels (real and imaginary parts, DC penalty, ridge rows), stacked."""
        key = x.tobytes()
        if key == self._key:
            return self._r
        if key == self._prev[0]:   # back at the last point after a rejected trial (the Jacobian is wanted there)
            self._prev, (self._key, self._r, self._state) = (self._key, self._r, self._state), self._prev
            return self._r
        W, P, K = self.W, self.Hs.shape[0], self.Hs.shape[1]
        pl = params_to_poles(x, self.template, self.floor)
        basis = partial_fraction_basis(self.s_all, pl)   # the samples and s = 0 in one evaluation
        Phi, b0 = basis[:K], basis[K].real
        if not self.fixed_d:
            Phi = np.hstack([Phi, np.ones((K, 1))])
            b0 = np.concatenate([b0, [1.0]])
        HR = self._data_rows(Phi.shape[1])   # (rows, P)
        mats = []
        for c in range(P if not self.common_w else 1):   # the regression matrix is shared when the weights are
            Ac = W[c][:, None] * Phi
            rows = [Ac.real, Ac.imag] + ([self.mu * b0[None, :]] if self.dc is not None else []) + [self.ridge]
            Ar = np.vstack(rows)
            Q, R = np.linalg.qr(Ar)
            dR = np.abs(np.diag(R))
            if not dR.min() > 1e-14 * dR.max():  # coincident poles: reject this step
                return self._remember(key, _bad_step(P, K, self.dc, Phi.shape[1]), None)
            mats.append((Ar, Q, R))
        if self.common_w:   # every channel's coefficients from one triangular solve
            Ar, Q, R = mats[0]
            TH = self._solve_triangular(R, Q.T @ HR)   # (N, P)
            res = Ar @ TH - HR
            parts = [(Ar, Q, TH[:, c]) for c in range(P)]
        else:
            parts, cols = [], []
            for c, (Ar, Q, R) in enumerate(mats):
                th = self._solve_triangular(R, Q.T @ HR[:, c])
                cols.append(Ar @ th - HR[:, c])
                parts.append((Ar, Q, th))
            res = np.stack(cols, axis=1)
        r = res.T.reshape(-1)   # channel by channel, as the Jacobian's rows
        if not np.all(np.isfinite(r)):
            return self._remember(key, np.full(r.shape, 1e10), None)
        return self._remember(key, r, (pl, parts))

    def _data_rows(self, n_cols: int) -> np.ndarray:
        """The weighted data of every channel as the regression's right-hand sides, shape (rows, P) (cached)."""
        if self._hr is None or self._hr.shape[0] != 2 * self.Hs.shape[1] + (self.dc is not None) + n_cols:
            cols = []
            for c in range(self.Hs.shape[0]):
                hc = [self.W[c] * self.Hs[c].real, self.W[c] * self.Hs[c].imag]
                if self.dc is not None:
                    hc.append(np.array([self.mu * (self.dc[c] - (self.ft[c] if self.fixed_d else 0.0))]))
                hc.append(np.zeros(n_cols))
                cols.append(np.concatenate(hc))
            self._hr = np.stack(cols, axis=1)
        return self._hr

    def jacobian(self, x: np.ndarray, *_) -> np.ndarray:
        """Kaufman's Jacobian ``P_perp (dPhi / dx) theta`` of :meth:`residual` at ``x``, shape (rows, n_par)."""
        r = self.residual(x)
        if self._state is None:   # a rejected point: the residual says so, the Jacobian is zero
            return np.zeros((r.size, x.size))
        pl, parts = self._state
        W, K = self.W, self.Hs.shape[1]
        fac = derivative_factors(self.s_all, pl, self.floor)   # the samples and s = 0 together
        Vs = []
        for c, (Ar, Q, th) in enumerate(parts):
            D = derivative_columns(self.s_all, pl, th, self.floor, fac)  # (K + 1, n_par): (dPhi/dx_q) theta
            V = W[c][:, None] * D[:K]
            rows = [V.real, V.imag]
            if self.dc is not None:
                rows.append(self.mu * D[K:].real)
            rows.append(np.zeros((Ar.shape[1], V.shape[1])))  # the ridge rows do not depend on the poles
            Vs.append(np.vstack(rows))
        if self.common_w:   # one projection for every channel (Kaufman: onto the complement of range(Ar))
            Q = parts[0][1]
            V = np.hstack(Vs)
            V = V - Q @ (Q.T @ V)
            J = np.vstack(np.hsplit(V, len(parts)))
        else:
            J = np.vstack([V - Q @ (Q.T @ V) for V, (_, Q, _) in zip(Vs, parts)])
        if not np.all(np.isfinite(J)):   # (not seen: the residual at x was finite) a zero Jacobian ends the run here
            return np.zeros(J.shape)
        return J

    def _remember(self, key, r, state):
        if self._state is not None:   # keep the last good point: the solver returns to it after a rejected trial
            self._prev = (self._key, self._r, self._state)
        self._key, self._r, self._state = key, r, state
        return r


def refine_poles(s, H, poles, *, weights=None, dc=None, ft=None, max_nfev: int = 60, region=None,
                 ridge_weight: float = 1e-4, min_real: float | None = None):
    """Gauss-Newton refinement of stable poles by variable projection.

    Minimises over the poles ``sum_c ||W_c (f_c(s_k) - H_c(s_k))||^2 + mu^2 sum_c (f_c(0) - dc_c)^2``, where
    ``f_c = sum_l theta_cl phi_l + d_c`` (:func:`partial_fraction_basis`) has the least-squares coefficients ``theta_c`` for
    the current poles (variable projection, Golub & Pereyra 1973, with Kaufman's Jacobian, BIT 15 (1975)
    49-57: ``J = P_perp (dPhi/dx) theta``). The derivative columns are :func:`derivative_columns`. The poles are parametrised as ``Re a = -exp(u)``, so every
    iterate is stable; ``d_c = ft_c`` is fixed when the feedthrough is given and the DC equality enters as a
    heavy penalty row (the caller's final convex refit imposes both exactly). The solver is the bounded
    Levenberg-Marquardt of :mod:`sysid.levenberg_marquardt` (scaled by the Jacobian's column norms).

    Parameters
    ----------
    s : ndarray, shape (K,), complex
        ``1j omega`` (``inf`` allowed).
    H : ndarray, shape (P, K), complex
        Channels.
    poles : ndarray, shape (n,), complex
        Start (canonical order, ``Re < 0``).
    weights : ndarray, shape (P, K), optional
        Multiply the residuals.
    dc, ft : ndarray, shape (P,), optional
        Values at ``s = 0`` and ``s = inf``.
    max_nfev : int
        Cap on residual evaluations.
    region : (float, float, float), optional
        ``(centre, radius, smax)`` as in :func:`relocate_poles`; the result is projected into it.
    ridge_weight : float
        Tikhonov term ``ridge_weight * ||phi_l|| * theta_cl`` per coefficient (column norms at the start),
        which keeps poles from merging with huge cancelling residues.
    min_real : float, optional
        Smallest ``|a|`` of a real pole (with ``region``): a real pole much slower than the first nonzero sample
        frequency changes the response between ``omega = 0`` and that sample, where nothing was measured (the
        refinement put one on the stability margin, ``|a| = 9e-5`` against a first sample at ``1.1e-3``, which
        matched the DC gain and left the response between those two samples free). Default: the region's floor
        at ``omega = 0`` when it has one, else none.

    Returns
    -------
    ndarray, shape (n,), complex
        Refined poles, ``Re < 0`` (the start when the cost did not fall).
    """
    s = np.asarray(s, dtype=complex)
    P, K = H.shape
    W = np.ones((P, K)) if weights is None else np.broadcast_to(np.asarray(weights, dtype=float), (P, K))
    common_w = bool(np.all(W == W[:1]))
    fixed_d = ft is not None
    Hs = H - (np.asarray(ft, dtype=float)[:, None] if fixed_d else 0.0)
    mu = 10.0 * np.sqrt(K)
    # ridge on each coefficient times its basis column's norm at the start: without it the refinement could
    # merge two poles at the edge of the stability region and fit with huge cancelling residues (|C| ~ 1e10
    # for a DC gain of 7 on T4 at N_r = 25), which the evaluated model then loses to round-off (8 digits of
    # the DC equality). ``ridge_weight`` times the data norm is what such a contribution costs.
    Phi_start = partial_fraction_basis(s, poles)
    cn = np.linalg.norm(np.vstack([Phi_start.real, Phi_start.imag]), axis=0)
    if not fixed_d:
        cn = np.concatenate([cn, [0.0]])
    ridge = np.diag(ridge_weight * cn)
    floor = region[3] if region is not None and len(region) > 3 else None
    problem = _Projection(s, Hs, W, common_w, fixed_d, dc, ft, mu, ridge, poles, floor)

    x0 = stable_params(poles, floor)
    bounds = (-np.inf, np.inf)
    if region is not None:  # box bounds from the region: |Re a| between its right and left edges, |Im a| <= smax
        c0, r0, smax = region[:3]
        lo = np.full(x0.size, np.log(max(-(c0 + r0), 1e-300)))
        hi = np.full(x0.size, np.log(min(-(c0 - r0), smax)))
        is_im = _imag_param_mask(poles)
        lo[is_im], hi[is_im] = -smax, smax
        f0_real = max(float(np.interp(0.0, *floor)) if floor is not None else 0.0, min_real or 0.0)
        if f0_real > 0:   # a real pole is no narrower than a pair at omega = 0 may be
            is_real = np.ones(x0.size, dtype=bool)
            is_real[is_im] = False
            is_real[np.flatnonzero(is_im) - 1] = False
            lo[is_real] = np.maximum(lo[is_real], np.log(f0_real))
        x0 = np.clip(x0, lo + 1e-9 * np.abs(lo), hi - 1e-9 * np.abs(hi))
        bounds = (lo, hi)
    f0 = problem.residual(x0)
    if f0[0] == 1e10:
        return poles
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore")
        try:
            sol = bounded_levenberg_marquardt(problem.residual, problem.jacobian, x0, bounds[0], bounds[1],
                                              max_nfev=max_nfev, xtol=1e-12, ftol=1e-12, gtol=1e-12)
        except np.linalg.LinAlgError:
            return poles
    if not np.all(np.isfinite(sol.x)) or not np.sum(sol.fun ** 2) < np.sum(f0 ** 2):
        return poles
    scale = float(np.abs(s[np.isfinite(s)]).max()) if np.isfinite(s).any() else 1.0
    return pair_poles(params_to_poles(sol.x, poles, floor), scale, region)
