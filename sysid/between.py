"""An estimate of a fitted model's error between the data's samples.

A fit that matches every sample can still be far off between two of them (a resonance narrower than the
spacing, or a model that nearly interpolates the data). The samples alone cannot say what the truth does there,
but they say what smooth functions through them do: :func:`between_error` compares the model, at the midpoint of
every data interval and at the peaks of its own resonances that fall inside an interval
(:func:`sysid.residues.resonance_points`), with four local cubic readings of the samples (in ``omega_d``: real and
imaginary parts through the two samples on either side, the same stencil moved one sample left and right, and
magnitude with unwrapped phase), and charges it with its distance from the nearest reading less the readings'
spread. Where the samples resolve the response the readings agree (their error is fourth order in the spacing)
and the estimate is the model's error there; where they disagree (a resonance of the data narrower than the
spacing, a phase that turns fast) the model is charged only beyond them, so the estimate is then a lower bound.

Measured on 2026-12-03 (tests/sysid/test_identify.py, tests/sysid/test_between.py, bench/sysid_truth_between_bench.py;
estimate / true max error between the samples, fractions of the peak): 1 % noisy order-4 data fitted at order 8
0.333 / 0.347 and at order 6 0.0148 / 0.0171; the Sears function with a delay at order 6 0.0069 / 0.011; a
12-state system with 1 % noise at order 8 0.0346 / 0.0345. It overestimates where the data's own resonances are
narrower than the spacing (the same 12-state system with 0.3 % noise at its true order 12: 0.037 / 0.008), and
on the paper's aerofoil data it sees what the dense LFD shows (docs/sysid.md): T4 at N_r = 25, 9.1 % / 27 % (Cl /
Cm) between the samples against 1.8 % / 1.2 % on them.
"""

from __future__ import annotations

import numpy as np

from .residues import resonance_points
from .state_space import evaluate_ss

__all__ = ["BETWEEN_RATIO", "BETWEEN_MIN_ERROR", "between_error", "between_deviation", "between_points",
           "cubic_interpolant", "polar_interpolant"]


BETWEEN_RATIO = 3.0
"""Ratio of the estimated error between the samples (:attr:`IdentificationResult.between_error_per_output`) to the
error on them above which :func:`sysid.identify` warns that the samples do not pin the model down between them (with a
resonance narrower than ``2 UNRESOLVED_WIDTH`` sample spacings as the likely cause, or the model nearly
interpolating the data)."""

BETWEEN_MIN_ERROR = 1e-3
"""Estimated error between the samples (fraction of the peak) below which :func:`sysid.identify` does not warn about it,
whatever the ratio: 0.1 % of the peak is within what a smooth interpolant of the samples can tell."""


def between_points(omega_d: np.ndarray, lam: np.ndarray | None = None) -> np.ndarray:
    """The midpoints of the data intervals in ``omega_d`` and, with the discrete poles ``lam``, the points where
    their resonances peak (:func:`sysid.residues.resonance_points`) that lie strictly inside an interval.

    Parameters
    ----------
    omega_d : ndarray, shape (K,)
        Data frequencies in ``[0, pi]`` (rad/sample), any order.
    lam : ndarray, shape (n,), complex, optional
        Eigenvalues of the model's ``A``.

    Returns
    -------
    ndarray, shape (J,)
        Sorted, distinct, none equal to a sample.
    """
    w = np.unique(np.asarray(omega_d, dtype=float))
    pts = 0.5 * (w[1:] + w[:-1])
    if lam is not None and w.size > 1:
        wr = np.abs(np.angle(resonance_points(lam)))
        inside = (wr > w[0]) & (wr < w[-1])
        i = np.searchsorted(w, wr)
        gap = np.minimum(np.abs(wr - w[np.clip(i - 1, 0, w.size - 1)]), np.abs(w[np.clip(i, 0, w.size - 1)] - wr))
        pts = np.concatenate([pts, wr[inside & (gap > 1e-9 * np.pi)]])
    return np.unique(pts)


def cubic_interpolant(omega_d: np.ndarray, H: np.ndarray, at: np.ndarray, shift: int = 0) -> np.ndarray:
    """Local cubic interpolation of samples: through four neighbouring samples of each point (in ``omega_d``;
    by default the two on either side where there are two), in real and imaginary parts.

    Parameters
    ----------
    omega_d : ndarray, shape (K,), K >= 4, distinct
    H : ndarray, shape (p, m, K), complex
    at : ndarray, shape (J,), within ``[min omega_d, max omega_d]``
    shift : int
        Moves the four samples by ``shift`` places (``-1``: three on the left, one on the right), within the data.

    Returns
    -------
    ndarray, shape (p, m, J), complex
    """
    order = np.argsort(omega_d)
    w = np.asarray(omega_d, dtype=float)[order]
    H = np.asarray(H)[:, :, order]
    at = np.asarray(at, dtype=float)
    i = np.clip(np.searchsorted(w, at) - 2 + shift, 0, w.size - 4)   # first of the four nodes
    nodes = i[:, None] + np.arange(4)[None, :]                 # (J, 4)
    x = w[nodes]
    # Lagrange weights of the four nodes at each point, (J, 4)
    L = np.ones_like(x)
    for a in range(4):
        for b in range(4):
            if a != b:
                L[:, a] *= (at - x[:, b]) / (x[:, a] - x[:, b])
    return np.einsum("pmjk,jk->pmj", H[:, :, nodes], L)


def polar_interpolant(omega_d: np.ndarray, H: np.ndarray, at: np.ndarray) -> np.ndarray:
    """:func:`cubic_interpolant` of the magnitude and of the unwrapped phase (along ``omega_d``): the smooth
    reading of samples whose phase turns fast (a delay), where real and imaginary parts oscillate between them.

    Same parameters and shape as :func:`cubic_interpolant`.
    """
    order = np.argsort(omega_d)
    w = np.asarray(omega_d, dtype=float)[order]
    H = np.asarray(H)[:, :, order]
    mag = cubic_interpolant(w, np.abs(H).astype(complex), at).real
    ph = cubic_interpolant(w, np.unwrap(np.angle(H), axis=2).astype(complex), at).real
    return mag * np.exp(1j * ph)


def between_deviation(A, B, C, D, omega_d, H) -> tuple[np.ndarray, np.ndarray]:
    """The points between the samples and the model's departure there, beyond the spread of smooth readings of
    the samples (see :func:`between_error`).

    Returns
    -------
    pts : ndarray, shape (J,)
        :func:`between_points` (``omega_d``, rad/sample).
    dev : ndarray, shape (p, m, J)
        Absolute departure (units of ``H``); inf where the model is not finite.
    """
    H = np.asarray(H)
    wd = np.asarray(omega_d, dtype=float)
    lam = np.linalg.eigvals(np.asarray(A, dtype=float)) if np.size(A) else None
    pts = between_points(wd, lam)
    with np.errstate(all="ignore"):
        Gm = evaluate_ss(A, B, C, D, np.exp(1j * pts))
    # smooth readings of the samples: the centred cubic in real and imaginary parts, and the spread of three others
    # (magnitude and phase; the stencils moved one sample left and right) as its uncertainty. Where they disagree
    # the samples do not resolve the response (a resonance of the data themselves, a fast phase), and the model is
    # charged only with its departure beyond that spread
    I0 = cubic_interpolant(wd, H, pts)
    others = [polar_interpolant(wd, H, pts), cubic_interpolant(wd, H, pts, -1), cubic_interpolant(wd, H, pts, 1)]
    spread = np.max([np.abs(I - I0) for I in others], axis=0)
    dev = np.maximum(np.min([np.abs(Gm - I) for I in [I0] + others], axis=0) - spread, 0.0)
    return pts, np.where(np.isfinite(dev), dev, np.inf)


def between_error(A, B, C, D, omega_d, H) -> np.ndarray:
    """Estimated error per output of the discrete model ``(A, B, C, D)`` between the samples ``H`` at
    ``omega_d``: ``max_j d_j / max_k |H_k|`` over the :func:`between_points` ``z_j`` (interval midpoints and the
    model's resonance peaks inside intervals), where ``d_j`` is the model's distance from the nearest of four local
    cubic readings of the samples (:func:`cubic_interpolant` centred and moved one sample either way,
    :func:`polar_interpolant`) less their spread (:func:`between_deviation`).

    Parameters
    ----------
    A : ndarray, shape (n, n); B : ndarray, shape (n, m); C : ndarray, shape (p, n); D : ndarray, shape (p, m)
    omega_d : ndarray, shape (K,)
        Data frequencies in ``[0, pi]`` (rad/sample).
    H : ndarray, shape (p, m, K), complex

    Returns
    -------
    ndarray, shape (p,)
        Fractions of each output's data peak (over inputs and samples); NaN when the data have fewer than four
        distinct frequencies (no cubic through them), inf when the model is not finite there.
    """
    H = np.asarray(H)
    if np.unique(np.asarray(omega_d, dtype=float)).size < 4:
        return np.full(H.shape[0], np.nan)
    _, dev = between_deviation(A, B, C, D, omega_d, H)
    peak = np.maximum(np.abs(H).max(axis=(1, 2)), np.finfo(float).tiny)
    return dev.max(axis=(1, 2)) / peak
