"""Synthetic test systems for the sysid tests (independent of the code under test).

Random real discrete systems are built from chosen poles (so the true poles are known), and their
frequency responses are evaluated by a plain per-frequency linear solve.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import linear_sum_assignment


#: A lightly damped continuous system (zeta 0.5 %): two resonant pairs and two real poles.
LIGHT = [-0.004 + 0.8j, -0.004 - 0.8j, -0.01 + 2.1j, -0.01 - 2.1j, -0.3, -1.5]


def random_poles(n: int, rng: np.random.Generator, rho: float = 0.95, rmin: float = 0.2) -> np.ndarray:
    """``n`` poles of a real system: conjugate pairs and real poles, moduli in ``[rmin, rho]``, distinct."""
    poles: list[complex] = []
    while len(poles) < n:
        r = rng.uniform(rmin, rho)
        if n - len(poles) >= 2 and rng.random() < 0.7:
            th = rng.uniform(0.15, np.pi - 0.15)
            cand = [r * np.exp(1j * th), r * np.exp(-1j * th)]
        else:
            cand = [r * rng.choice([-1.0, 1.0])]
        if all(min(abs(c - p) for p in poles) > 0.05 for c in cand) if poles else True:
            poles.extend(cand)
    return np.array(poles)


def real_matrix_from_poles(poles: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Real matrix with the given eigenvalues (real blocks), in a random basis."""
    blocks = []
    i = 0
    while i < len(poles):
        lam = poles[i]
        if abs(lam.imag) > 0:
            a, b = lam.real, lam.imag
            blocks.append(np.array([[a, b], [-b, a]]))
            i += 2
        else:
            blocks.append(np.array([[lam.real]]))
            i += 1
    n = len(poles)
    A0 = np.zeros((n, n))
    k = 0
    for blk in blocks:
        s = blk.shape[0]
        A0[k:k + s, k:k + s] = blk
        k += s
    S = rng.standard_normal((n, n)) + 2 * np.eye(n)
    return S @ A0 @ np.linalg.inv(S)


def random_system(n: int, p: int, m: int, seed: int, rho: float = 0.95):
    """``(A, B, C, D, poles)`` of a random stable discrete MIMO system with poles inside ``rho``."""
    rng = np.random.default_rng(seed)
    poles = random_poles(n, rng, rho=rho)
    A = real_matrix_from_poles(poles, rng)
    B = rng.standard_normal((n, m))
    C = rng.standard_normal((p, n))
    D = rng.standard_normal((p, m))
    return A, B, C, D, poles


def freqresp(A, B, C, D, z) -> np.ndarray:
    """``C (zI - A)^-1 B + D`` at each ``z``, by one linear solve per point: shape (p, m, K)."""
    A, B, C, D = (np.asarray(x, dtype=float) for x in (A, B, C, D))
    n = A.shape[0]
    out = np.empty((C.shape[0], B.shape[1], len(z)), dtype=complex)
    for k, zk in enumerate(np.atleast_1d(z)):
        out[:, :, k] = C @ np.linalg.solve(zk * np.eye(n) - A, B) + D
    return out


def pole_mismatch(est: np.ndarray, true: np.ndarray) -> float:
    """Largest distance between matched poles (optimal assignment)."""
    cost = np.abs(np.asarray(est)[:, None] - np.asarray(true)[None, :])
    r, c = linear_sum_assignment(cost)
    return float(cost[r, c].max())


def noisy_resonant_system(omega, omega_truth, seed: int = 13, noise: float = 0.003):
    """A continuous 12-state system (six resonances at 0.2 - 3, damping ratios 2 - 10 %, random residues, no
    feedthrough) sampled at ``omega`` (``inf`` allowed: exactly 0 there) with ``noise`` times the peak of complex
    Gaussian noise (the ``omega = 0`` sample kept real); returns ``(samples (K,), exact response at omega_truth)``."""
    rng = np.random.default_rng(seed)
    wn, zeta = np.sort(rng.uniform(0.2, 3.0, 6)), rng.uniform(0.02, 0.1, 6)
    up = -zeta * wn + 1j * wn * np.sqrt(1 - zeta**2)
    poles = np.concatenate([up, np.conj(up)])
    r = rng.standard_normal(6) + 1j * rng.standard_normal(6)
    res = np.concatenate([r, np.conj(r)])

    def H(om):
        om = np.asarray(om, dtype=float)
        s = 1j * np.where(np.isinf(om), 0.0, om)
        return np.where(np.isinf(om), 0.0, (res[None, :] / (s[:, None] - poles[None, :])).sum(axis=1))

    G = H(omega)
    G = G + noise * np.abs(G).max() * (rng.standard_normal(G.size) + 1j * rng.standard_normal(G.size)) / np.sqrt(2)
    G[np.asarray(omega) == 0] = G[np.asarray(omega) == 0].real
    G[np.isinf(omega)] = 0.0   # the feedthrough, exact
    return G, H(omega_truth)
