"""The level of the measurement noise in frequency-response samples, estimated from the samples alone.

A smooth response sampled densely has tiny fourth differences along the grid; additive white noise of standard
deviation ``sigma`` gives fourth differences of standard deviation ``sqrt(70) sigma`` (the sum of the squared
binomial coefficients 1, 4, 6, 4, 1). The median of their magnitude is robust to the few differences that a
resonance or a sparse stretch of the grid makes large, so

    ``sigma_hat = median |Delta^4 H_k| / (sqrt(70) sqrt(ln 2))``

(``sqrt(ln 2) sigma`` is the median magnitude of complex Gaussian noise whose ``E|n|^2 = sigma^2``). The
estimate is an upper bound of the noise where the grid is too sparse for the response (the differences then
carry the response itself), and about the noise where it is dense. Measured on McKelvey's grid (M = 64, T = 1):
1 % noise on a 4-state system 1.13e-2, on a 12-state system 1.25e-2, 0.3 % on it 4.0e-3; the Sears function
without noise 1.2e-6; the paper's LFD data (docs/data/frf-T1..T6.npz, 256 samples) 1.6e-8 - 5.0e-6 of the
peak, where their fits' errors are 1e-4 - 1e-1 (``tests/sysid/test_noise.py``). On sparse noise-free data it
measures the response's own curvature instead: every eighth of those samples (33) gives 1e-4 - 8e-3, so a fit of
such data whose error is within ten times that takes least-squares residues (e.g. the gust model of
``studies/aeroelastic.toml``'s 33 coarse-grid samples: max error 4.3e-4 -> 5.6e-4 of the peak on them).

:func:`sysid.relocation.fit_relocated` uses it to choose the residue fit: a minimax fit of samples whose
least-squares error is already at the noise level follows the noise (its error between the samples grows),
where least squares averages it.
"""

from __future__ import annotations

import math

import numpy as np

from .errors import FrequencyDataError

__all__ = ["noise_level", "NOISE_MIN_SAMPLES"]

NOISE_MIN_SAMPLES = 9
"""Fewest finite samples for an estimate (five fourth differences); below it :func:`noise_level` returns 0."""

_SCALE = math.sqrt(70.0) * math.sqrt(math.log(2.0))


def noise_level(H, omega) -> np.ndarray:
    """Estimated standard deviation of white noise in each output's samples, relative to that output's peak.

    Parameters
    ----------
    H : array_like, complex, shape (p, K) or (p, m, K)
        Samples on the grid ``omega``.
    omega : array_like, shape (K,)
        Frequencies, in any order (the samples are sorted by frequency before their differences are taken: a
        shuffled grid gave an estimate 18 times too high); samples at infinite ``omega`` are left out.

    Returns
    -------
    ndarray, shape (p,)
        ``sigma_hat / peak`` per output (the largest over the inputs); 0 for an output that is zero or when fewer
        than :data:`NOISE_MIN_SAMPLES` samples are finite.

    Raises
    ------
    FrequencyDataError
        Shapes that do not match, values that are not numbers, NaN or inf in ``H``, NaN in ``omega``.
    """
    try:
        H = np.asarray(H, dtype=complex)
        omega = np.asarray(omega, dtype=float)
    except (TypeError, ValueError):
        raise FrequencyDataError("noise_level needs H, an array of numbers of shape (p, K) or (p, m, K), and omega, "
                                 "an array of real frequencies") from None
    if H.ndim == 2:
        H = H[:, None, :]
    if H.ndim != 3 or omega.shape != (H.shape[-1],):
        raise FrequencyDataError(f"noise_level needs H of shape (p, K) or (p, m, K) and omega of shape (K,); got H "
                                 f"{H.shape}, omega {omega.shape}")
    if not np.all(np.isfinite(H)) or np.any(np.isnan(omega)):
        raise FrequencyDataError("noise_level: H contains NaN or inf, or omega NaN; a noise estimate of them would be "
                                 "meaningless: remove those samples")
    order = np.argsort(omega, kind="stable")   # the differences below run along the frequency axis
    H, omega = H[:, :, order], omega[order]
    fin = np.isfinite(omega)
    Hf = H[:, :, fin]
    p = H.shape[0]
    if Hf.shape[-1] < NOISE_MIN_SAMPLES:
        return np.zeros(p)
    peak = np.abs(Hf).max(axis=(1, 2))
    d4 = np.abs(np.diff(Hf, 4, axis=-1))
    sigma = np.median(d4, axis=-1).max(axis=1) / _SCALE
    return np.divide(sigma, peak, out=np.zeros(p), where=peak > 0)
