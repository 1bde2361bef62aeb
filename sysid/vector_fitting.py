"""Relaxed vector fitting (Sanathanan-Koerner iterations in ``s``) with every iterate kept stable: step 1 of
:mod:`sysid.relocation`."""

import numpy as np

from .poles import modal_realisation, pair_poles, partial_fraction_basis, pole_distance

__all__ = ["relocate_poles"]


def relocate_poles(s, H, poles, *, weights=None, iterations: int = 30, tol: float = 1e-10,
                   lawson: int = 0, region=None) -> tuple[np.ndarray, int]:
    """Relaxed vector fitting: relocate common poles of all channels, keeping every iterate stable.

    Each iteration solves the linearised (Sanathanan-Koerner) problem

        sigma(s_k) H_c(s_k) ~= f_c(s_k),   sigma(s) = sum_l c_l phi_l(s) + d_sigma,
        f_c(s) = sum_l r_cl phi_l(s) + d_c,

    for every channel ``c`` (real unknowns; the ``phi_l`` of :func:`partial_fraction_basis` on the current poles), with the
    relaxation row ``Re sum_k sigma(s_k) = K`` (Gustavsen 2006, Eq. 9) instead of ``d_sigma = 1``. The
    channel unknowns ``r_c, d_c`` are eliminated by a QR factorisation per channel (Deschrijver et al. 2008,
    "fast VF"), so the cost is linear in the number of channels. The new poles are the zeros of ``sigma``:
    the eigenvalues of ``A_c - b c^T / d_sigma`` (:func:`modal_realisation`), reflected to ``Re < 0``.

    Parameters
    ----------
    s : ndarray, shape (K,), complex
        ``1j * omega`` (``inf`` allowed: that row only sees the constants).
    H : ndarray, shape (P, K), complex
        Channels to fit (outputs x inputs flattened), each already scaled as it should count.
    poles : ndarray, shape (n,), complex
        Starting poles in canonical order (:func:`initial_poles`).
    weights : ndarray, shape (K,) or (P, K), optional
        Nonnegative frequency weights of the linearised residuals (multiplying the residual, not its square).
    iterations : int
        Maximum number of relocations.
    tol : float
        Stop when no pole moves by more than ``tol`` times the largest pole magnitude.
    lawson : int
        Extra iterations after convergence with Lawson weights ``w_k <- w_k |e_k| / mean`` from the
        residual of the least-squares channel fit on the current poles (towards the minimax fit).
    region : (float, float, float), optional
        ``(centre, radius, smax)``: relocated poles are kept in the :func:`stability_region` disc and within
        ``|s| <= smax``.

    Returns
    -------
    poles : ndarray, shape (n,), complex, all ``Re < 0``
    iterations : int
        Relocations run.
    """
    s = np.asarray(s, dtype=complex).reshape(-1)
    H = np.asarray(H, dtype=complex)
    P, K = H.shape
    n = poles.size
    scale = float(np.abs(s[np.isfinite(s)]).max()) if np.isfinite(s).any() else 1.0
    W = np.ones((P, K)) if weights is None else np.broadcast_to(np.asarray(weights, dtype=float), (P, K)).copy()
    poles = pair_poles(poles, scale, region)
    it_done = 0
    law_left = lawson
    it = 0
    while it < iterations + lawson:
        it += 1
        Phi = partial_fraction_basis(s, poles)
        Phi1 = np.hstack([Phi, np.ones((K, 1))])  # (K, n+1): basis of f_c and of sigma
        rows = []
        Q1 = None
        for c in range(P):
            w = W[c][:, None]
            if Q1 is None or weights is not None and np.ndim(weights) == 2:
                Q1 = np.linalg.qr(np.vstack([(w * Phi1).real, (w * Phi1).imag]))[0]
            X = -(w * H[c][:, None]) * Phi1
            X = np.vstack([X.real, X.imag])
            X = X - Q1 @ (Q1.T @ X)  # the part of the sigma block that the channel's own unknowns cannot fit
            rows.append(np.linalg.qr(X, mode="r"))
        Rs = np.vstack(rows)
        # relaxation: Re sum_k sigma(s_k) = K, weighted like one channel's typical row
        fin = np.isfinite(s)
        relax = np.concatenate([Phi1[fin].real.sum(axis=0)])
        wr = np.linalg.norm(Rs) / (K * max(P, 1))
        A_ls = np.vstack([Rs, wr * relax[None, :]])
        b_ls = np.zeros(A_ls.shape[0])
        b_ls[-1] = wr * K
        col = np.linalg.norm(A_ls, axis=0)
        col[col == 0] = 1.0
        x = np.linalg.lstsq(A_ls / col, b_ls, rcond=None)[0] / col
        cs, ds = x[:n], x[n]
        if abs(ds) < 1e-8 * max(np.abs(cs).max(initial=0.0), 1.0):  # relaxed problem degenerate: fix d_sigma = 1
            x = np.linalg.lstsq(Rs[:, :n], -Rs[:, n], rcond=None)[0]
            cs, ds = x, 1.0
        Ac_, bc = modal_realisation(poles)
        Z = Ac_ - np.outer(bc, cs) / ds
        if not np.all(np.isfinite(Z)):
            break
        new = pair_poles(np.linalg.eigvals(Z), scale, region)
        it_done = it
        moved = pole_distance(new, poles) / max(np.abs(new).max(), 1e-300)
        poles = new
        if it > iterations or (moved < tol and it <= iterations):
            if law_left <= 0:
                break
            # Lawson step: reweight by the current least-squares channel residual
            Phi1 = np.hstack([partial_fraction_basis(s, poles), np.ones((K, 1))])
            for c in range(P):
                Ar = np.vstack([(W[c][:, None] * Phi1).real, (W[c][:, None] * Phi1).imag])
                br = np.concatenate([(W[c] * H[c]).real, (W[c] * H[c]).imag])
                th = np.linalg.lstsq(Ar, br, rcond=None)[0]
                e = np.abs(Phi1 @ th - H[c])
                W[c] = W[c] * e / max(e.mean(), 1e-300)
            law_left -= 1
            if it <= iterations:
                it = iterations  # jump to the Lawson phase
    return poles, it_done
