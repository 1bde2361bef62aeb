"""Exact response of a modal gust system to the 1-cosine gust, at any times, vectorised over gusts.

For the gust ``u(s) = (A / 2)(1 - cos(omega s))``, ``omega = pi / H`` (``H`` in chords), ``0 <= s <= 2 H``, zero
after, each mode ``z' = lambda z + b u`` from rest has the closed form (no time stepping, no sampling error)::

    z(s) = b (A / 2) [E(0, s) - (E(i omega, s) + E(-i omega, s)) / 2]      (s <= 2 H)
    E(mu, s) = int_0^s exp(lambda (s - sigma)) exp(mu sigma) d sigma = exp(mu s) s phi1((lambda - mu) s)
    z(s) = exp(lambda (s - 2 H)) z(2 H)                                    (s > 2 H)

with ``phi1(x) = (exp(x) - 1) / x`` (a 5-term series for ``|x| < 1e-3``, truncation below ``1e-18``; the direct
form loses at most ``eps / |x| < 3e-13``). ``Re lambda <= 0`` (stable models only, checked by
:func:`loads.system.gust_system`), so nothing overflows; ``lambda = 0`` (a free plunge) and ``lambda = i omega``
(an undamped mode in resonance with the gust) are regular points of ``phi1``. The outputs are then
``y = Re(C z) + d u``: the response of the continuous model to the continuous gust, exact to round-off times the
eigenvector matrix's condition number (:attr:`loads.system.GustSystem.condition`).
"""

from __future__ import annotations

import numpy as np

__all__ = ["phi1", "gust_input", "modal_states", "outputs_at"]


def phi1(x: np.ndarray) -> np.ndarray:
    """``(exp(x) - 1) / x`` elementwise for complex ``x`` (1 at 0), any shape."""
    x = np.asarray(x, dtype=complex)
    out = np.empty_like(x)
    small = np.abs(x) < 1e-3
    xs = x[small]
    out[small] = 1.0 + xs / 2.0 * (1.0 + xs / 3.0 * (1.0 + xs / 4.0 * (1.0 + xs / 5.0)))
    xl = x[~small]
    out[~small] = (np.exp(xl) - 1.0) / xl
    return out


def gust_input(H: np.ndarray, s: np.ndarray) -> np.ndarray:
    """Unit 1-cosine ``(1 - cos(pi s / H)) / 2`` on ``0 <= s <= 2 H``, 0 elsewhere; ``H``, ``s`` broadcast (chords)."""
    H, s = np.broadcast_arrays(np.asarray(H, float), np.asarray(s, float))
    on = (s >= 0.0) & (s <= 2.0 * H)
    return np.where(on, 0.5 * (1.0 - np.cos(np.pi * s / H)), 0.0)


def modal_states(lam: np.ndarray, b: np.ndarray, H: np.ndarray, s: np.ndarray) -> np.ndarray:
    """Modal states from rest for a unit-amplitude 1-cosine gust.

    Parameters
    ----------
    lam, b : ndarray, complex, shape (n,)
        Eigenvalues (``Re <= 0``) and modal input.
    H : ndarray, shape (m,)
        Gust gradient of each query (convective lengths, chords), > 0.
    s : ndarray, shape (m,)
        Time of each query (convective, ``>= 0``).

    Returns
    -------
    ndarray, complex, shape (m, n)
    """
    H = np.asarray(H, dtype=float)[:, None]
    s = np.asarray(s, dtype=float)[:, None]
    se = np.minimum(s, 2.0 * H)                         # time within the gust
    w = np.pi / H
    L = lam[None, :]
    iw = 1j * w
    E0 = se * phi1(L * se)
    Ep = np.exp(iw * se) * se * phi1((L - iw) * se)
    Em = np.exp(-iw * se) * se * phi1((L + iw) * se)
    z = 0.5 * b[None, :] * (E0 - 0.5 * (Ep + Em))
    after = s > 2.0 * H
    if np.any(after):
        z = np.where(after, z * np.exp(L * np.maximum(s - 2.0 * H, 0.0)), z)
    return z


def outputs_at(system, H: np.ndarray, s: np.ndarray, rows=None) -> np.ndarray:
    """Outputs per unit gust angle at the queries ``(H, s)``: shape (m, p) (or (m, len(rows)))."""
    z = modal_states(system.lam, system.b, H, s)
    C = system.C if rows is None else system.C[rows]
    d = system.d if rows is None else system.d[rows]
    return (z @ C.T).real + gust_input(H, s)[:, None] * d[None, :]
