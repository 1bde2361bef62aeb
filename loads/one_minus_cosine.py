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
    small = np.abs(x) < 1e-3
    series = 1.0 + x / 2.0 * (1.0 + x / 3.0 * (1.0 + x / 4.0 * (1.0 + x / 5.0)))
    safe = np.where(small, 1.0, x)
    return np.where(small, series, (np.exp(safe) - 1.0) / safe)


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


def _half_modes(system):
    """Modes with ``Im lambda >= 0`` and their weighted output residues ``w C_i b_i`` (``w = 2`` for a complex
    mode, standing for its conjugate partner; 1 for a real one), cached on the system."""
    cache = system.__dict__.get("_half")
    if cache is None:
        lam = system.lam
        keep = lam.imag >= 0.0
        w = np.where(lam.imag[keep] > 0.0, 2.0, 1.0)
        cache = (lam[keep], system.C[:, keep] * (system.b[keep] * w)[None, :])
        object.__setattr__(system, "_half", cache)
    return cache


def outputs_at(system, H: np.ndarray, s: np.ndarray, rows=None) -> np.ndarray:
    """Outputs per unit gust angle at the queries ``(H, s)``: shape (m, p) (or (m, len(rows))).

    Uses the real system's symmetry: the modes come in conjugate pairs (``lambda``, ``C b`` conjugated) whose
    contributions to ``y`` are conjugate, so each pair is twice the real part of one mode:
    ``y = Re sum_{Im lambda >= 0} w C_i z_i + d u`` (half the work of :func:`modal_states`, which the tests check
    it against).
    """
    lam, R = _half_modes(system)
    if rows is not None:
        R = R[rows]
        d = system.d[rows]
    else:
        d = system.d
    return (_g(lam, H, s) @ R.T).real + gust_input(H, s)[:, None] * d[None, :]


def outputs_rowwise(system, H: np.ndarray, s: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """Output ``rows[k]`` at query ``(H[k], s[k])``, shape (m,)."""
    lam, R = _half_modes(system)
    g = _g(lam, H, s)
    return np.einsum("mn,mn->m", g, R[rows]).real + gust_input(H, s) * system.d[rows]


def slopes_rowwise(system, H: np.ndarray, s: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """``dy/ds`` of output ``rows[k]`` at query ``(H[k], s[k])``, shape (m,): ``z' = lambda z + b u``, so
    ``y' = Re sum w C b (lambda z / b + u) + d u'``."""
    lam, R = _half_modes(system)
    g = _g(lam, H, s)
    u = gust_input(H, s)
    Hs = np.asarray(H, dtype=float)
    ss = np.asarray(s, dtype=float)
    du = np.where((ss >= 0) & (ss <= 2 * Hs), 0.5 * np.pi / Hs * np.sin(np.pi * ss / Hs), 0.0)
    return np.einsum("mn,mn->m", g * lam[None, :] + u[:, None], R[rows]).real + du * system.d[rows]


def _g(lam, H, s):
    """``z / b`` per query and mode (unit gust), continued by the free decay after the gust; shape (m, n).

    Written with one exponential per entry, ``E(mu, s) = (exp(lambda s) - exp(mu s)) / (lambda - mu)``, and the
    ``phi1`` form (no cancellation) for the entries where ``|(lambda - mu) s| < 1e-3``.
    """
    H = np.asarray(H, dtype=float)[:, None]
    s = np.asarray(s, dtype=float)[:, None]
    se = np.minimum(s, 2.0 * H)
    iw = 1j * np.pi / H
    L = lam[None, :]
    eL = np.exp(L * se)
    ep, em = np.exp(iw * se), np.exp(-iw * se)
    terms = []
    for mu, emu in ((0.0, 1.0), (iw, ep), (-iw, em)):
        dl = L - mu
        x = dl * se
        small = np.abs(x) < 1e-3
        with np.errstate(divide="ignore", invalid="ignore"):
            E = (eL - emu) / dl
        if np.any(small):
            E = np.where(small, np.broadcast_to(emu, x.shape) * se * phi1(np.where(small, x, 0.0)), E)
        terms.append(E)
    g = 0.5 * (terms[0] - 0.5 * (terms[1] + terms[2]))
    after = s > 2.0 * H
    if np.any(after):
        g = np.where(after, g * np.exp(L * np.maximum(s - 2.0 * H, 0.0)), g)
    return g
