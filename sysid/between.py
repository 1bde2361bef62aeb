"""An estimate of a fitted model's error between the data's samples.

A fit that matches every sample can still be far off between two of them (a resonance narrower than the
spacing, or a model that nearly interpolates the data). The samples alone cannot say what the truth does there,
but they say what simple functions through them do: :func:`between_error` compares the model, at the midpoint of
every data interval and at the peaks of its own resonances that fall inside an interval
(:func:`sysid.residues.resonance_points`), with local readings of the samples around that interval
(:func:`sample_readings`), and charges it with its distance from the nearest reading less the readings' spread.

The readings come in three families, the simplest that explains the neighbouring samples:

- **cubic** (where the samples resolve the response): four local cubics in ``omega_d`` (real and imaginary parts
  through the two samples on either side, the same stencil moved one sample left and right, and magnitude with
  unwrapped phase). Their error is fourth order in the spacing, and where they disagree (a phase that turns fast)
  the model is charged only beyond their spread, so the estimate is then a lower bound;
- **one local resonance**: a rational function of type (2, 1) in ``omega_d``, least squares on the six samples
  around the interval (:func:`rational_interpolant`), and the same moved one sample either way;
- **two local resonances**: type (3, 2) on eight samples.

A rational family replaces the simpler one where the simpler one misses the samples next to its stencil by more
than :data:`READING_GAIN` times what the rational one leaves, and by more than what noise and a resolved
response can explain (:data:`READING_FLOOR` of the output's peak, and :data:`CUBIC_NOISE_MULT` /
:data:`RATIONAL_NOISE_MULT` times the noise of :func:`sysid.noise.noise_level`). That happens at resonances
narrower than the spacing, which no polynomial through the samples follows (a cubic through them misses the next
sample by 0.3 - 9 times the peak on the noisy 12-state systems of ``bench/sysid_truth_between_bench.py``) but
whose tails on the neighbouring samples pin down a local pole: a model that has the resonance is then not charged
for it, and a model that lacks it is.

Measured on 2026-12-04 (``bench/sysid_truth_between_bench.py --estimate``: the default fits of the 42 noisy
12-state systems at orders 8, 12 and 16, estimate against the true max error between the samples): within a
factor 2 of the truth at 98 of 126 fits (with the cubic readings alone: 62), more than 2 times above it at 3 (44),
more than 2 times below at 25 (20); at the true order 12 the cubic readings alone overestimated up to 44 times
(1.12 of the peak against a true 0.026). The Sears function and the 1 % noisy 4-state system (no resonance
narrower than the spacing) are read by the cubic family alone, as before: 1 % noisy order-4 data fitted at order 8
0.193 / 0.203 (estimate / truth; the model then had a resonance that follows the noise, which the relocation now
avoids: 0.0154 / 0.0142), at order 6 0.0176 / 0.0142; the Sears function with a delay at order 6
0.0074 / 0.0123. The estimate is a lower bound where the readings disagree; :func:`between_uncertainty` says how far
they do (what the samples leave open between them).
"""

from __future__ import annotations

import numpy as np

from .errors import OptionError
from .noise import noise_level
from .residues import resonance_points
from .state_space import evaluate_ss

__all__ = ["BETWEEN_RATIO", "BETWEEN_MIN_ERROR", "READING_GAIN", "READING_FLOOR", "CUBIC_NOISE_MULT",
           "RATIONAL_NOISE_MULT", "between_error", "between_uncertainty", "between_estimate", "between_deviation",
           "between_points", "cubic_interpolant", "polar_interpolant", "cubic_misfit", "rational_interpolant",
           "sample_readings"]


BETWEEN_RATIO = 3.0
"""Ratio of the estimated error between the samples (:attr:`IdentificationResult.between_error_per_output`) to the
error on them above which :func:`sysid.identify` warns that the samples do not pin the model down between them (with a
resonance narrower than ``2 UNRESOLVED_WIDTH`` sample spacings as the likely cause, or the model nearly
interpolating the data)."""

BETWEEN_MIN_ERROR = 1e-3
"""Estimated error between the samples (fraction of the peak) below which :func:`sysid.identify` does not warn about it,
whatever the ratio: 0.1 % of the peak is within what a smooth interpolant of the samples can tell."""

READING_GAIN = 4.0
"""How many times better a rational family of readings (:func:`sample_readings`) must explain the samples around an
interval than the simpler family it replaces (misfits: :func:`cubic_misfit`, :func:`rational_interpolant`)."""

READING_FLOOR = 0.05
"""Misfit of a family of readings, as a fraction of the output's peak, below which it is kept whatever a rational
family does better: where a cubic through the samples misses the next one by less than 5 % of the peak, the
samples resolve the response (the Sears function and the noisy 4-state system keep the cubic family everywhere),
while a resonance narrower than the spacing makes it miss by 0.3 - 9 times the peak (the 12-state systems of
``bench/sysid_truth_between_bench.py``), and so does Cm's fast phase above k = 2 on the paper's grid (eight samples
there), where the rational readings bring the estimate closer to an LFD eight times denser (docs/sysid.md)."""

CUBIC_NOISE_MULT = 25.0
"""A cubic family misfit within this many times the noise's standard deviation (:func:`sysid.noise.noise_level`) is
what noise alone gives: on an equispaced grid a cubic through four samples misses the next one by the fourth
difference, whose noise is ``sqrt(70) ~ 8.4`` times the samples' (:mod:`sysid.noise`), and the larger of two such
complex Gaussian values stays below three of their deviations but for a few in ten thousand."""

RATIONAL_NOISE_MULT = 5.0
"""The same for a rational reading's least-squares misfit (two complex samples more than unknowns: the residuals
are at most a few deviations)."""

#: Shifts of the stencils whose spread is the uncertainty of a rational reading.
_SHIFTS = (0, -1, 1)
#: Sanathanan-Koerner reweightings of a local rational least-squares fit.
_SK_ITERATIONS = 4
#: Largest magnitude of a rational reading, in units of the largest sample of its window (a resonance between two
#: samples peaks at (spacing / half-width) times its tails; a reading beyond 100 sits on its own pole).
_MAX_READING = 100.0


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
    return np.einsum("pmjk,jk->pmj", H[:, :, nodes], _lagrange_weights(w[nodes], at))


def _lagrange_weights(x: np.ndarray, at: np.ndarray) -> np.ndarray:
    """Lagrange weights of the four nodes ``x`` (J, 4) at the points ``at`` (J,): shape (J, 4)."""
    L = np.ones_like(x)
    for a in range(4):
        for b in range(4):
            if a != b:
                L[:, a] *= (at - x[:, b]) / (x[:, a] - x[:, b])
    return L


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


def _intervals(w: np.ndarray, at: np.ndarray):
    """The data interval of each point (``w`` sorted): index ``k`` of its left sample, its centre and width."""
    k = np.clip(np.searchsorted(w, at) - 1, 0, w.size - 2)
    return k, 0.5 * (w[k] + w[k + 1]), w[k + 1] - w[k]


def cubic_misfit(omega_d: np.ndarray, H: np.ndarray, at: np.ndarray) -> np.ndarray:
    """How far the centred cubic reading of each point (:func:`cubic_interpolant`, through the two samples on
    either side of its interval) misses the samples just outside its four: the larger miss of the sample before
    and the one after the stencil (on an equispaced grid, the fourth differences there).

    Parameters
    ----------
    omega_d : ndarray, shape (K,), K >= 4, distinct
    H : ndarray, shape (p, m, K), complex
    at : ndarray, shape (J,), within ``[min omega_d, max omega_d]``

    Returns
    -------
    ndarray, shape (p, m, J)
        Absolute misfit (units of ``H``); 0 where the stencil has no sample outside it (fewer than five samples).
    """
    order = np.argsort(omega_d)
    w = np.asarray(omega_d, dtype=float)[order]
    H = np.asarray(H)[:, :, order]
    K = w.size
    k, _, _ = _intervals(w, np.asarray(at, dtype=float))
    first = np.clip(k - 1, 0, K - 4)
    nodes = first[:, None] + np.arange(4)[None, :]
    out = np.zeros(H.shape[:2] + k.shape)
    for o in (first - 1, first + 4):
        inside = (o >= 0) & (o < K)
        oc = np.clip(o, 0, K - 1)
        pred = np.einsum("pmjk,jk->pmj", H[:, :, nodes], _lagrange_weights(w[nodes], w[oc]))
        out = np.maximum(out, np.where(inside, np.abs(pred - H[:, :, oc]), 0.0))
    return out


def _rational_fits(w: np.ndarray, H: np.ndarray, row: np.ndarray, k: np.ndarray, poles: int, shift):
    """Local rational fits (:func:`rational_interpolant`) of the rows ``row`` (N,) of ``H`` (R, K) around the intervals
    ``k`` (N,) of the sorted grid ``w``, each window moved by ``shift`` (an integer, or one per fit):
    ``(num (N, poles + 2), den (N, poles), centre (N,), width (N,), scale (N,), misfit (N,))``, the coefficients in
    the local variable and for the data divided by ``scale`` (the largest magnitude in the window)."""
    K = w.size
    L = 2 * poles + 4
    centre, width = 0.5 * (w[k] + w[k + 1]), w[k + 1] - w[k]
    first = np.clip(np.clip(k - (L // 2 - 1), 0, K - L) + shift, 0, K - L)
    idx = first[:, None] + np.arange(L)[None, :]                       # (N, L)
    t = ((w[idx] - centre[:, None]) / width[:, None]).astype(complex)
    Hw = H[row[:, None], idx]                                          # (N, L): only the windows are gathered
    scale = np.maximum(np.abs(Hw).max(axis=1), np.finfo(float).tiny)
    Hs = Hw / scale[:, None]
    powers = [t ** j for j in range(poles + 2)]
    M = np.stack(powers + [-Hs * powers[j] for j in range(poles)], axis=-1)   # (N, L, q), q = 2 poles + 2
    q = M.shape[-1]
    rhs = Hs * t ** poles
    # a ridge row per unknown, 1e-10 of its column's norm: a window that sees a function of lower type (a pole far
    # away, zeros) has a rank-deficient matrix, whose least-squares solution is then the small-norm one
    ridge = 1e-10 * np.sqrt(np.sum(np.abs(M) ** 2, axis=1)) + np.finfo(float).tiny   # (N, q)
    weight = np.ones(Hs.shape)
    for _ in range(_SK_ITERATIONS):
        Mw = np.concatenate([M * weight[..., None], ridge[:, None, :] * np.eye(q)[None]], axis=1)
        bw = np.concatenate([rhs * weight, np.zeros((rhs.shape[0], q))], axis=1)
        Q, R = np.linalg.qr(Mw)
        x = np.linalg.solve(R, np.einsum("nlq,nl->nq", Q.conj(), bw)[..., None])[..., 0]
        num, den = x[:, :poles + 2], x[:, poles + 2:]
        D_window = t ** poles + sum(den[:, j, None] * t ** j for j in range(poles))
        weight = 1.0 / np.maximum(np.abs(D_window), 1e-6)
    N_window = sum(num[:, j, None] * t ** j for j in range(poles + 2))
    with np.errstate(all="ignore"):
        misfit = np.abs(N_window / D_window - Hs).max(axis=1) * scale
    return num, den, centre, width, scale, np.where(np.isfinite(misfit), misfit, np.inf)


def _pair_fits(w: np.ndarray, rows: np.ndarray, pairs: np.ndarray, poles: int, cache: dict | None):
    """:func:`_rational_fits` of the (row, interval) ``pairs`` (2, N) for every window shift of :data:`_SHIFTS`: the
    fit's arrays with leading axes (len(_SHIFTS), N). With ``cache`` (a dict the caller keeps across calls on the
    same ``w`` and ``rows``, e.g. :func:`sysid.order_sweep` over its orders) each pair is fitted once."""
    n_shifts, N = len(_SHIFTS), pairs.shape[1]

    def fit(p):
        f = _rational_fits(w, rows, np.tile(p[0], n_shifts), np.tile(p[1], n_shifts), poles,
                           np.repeat(np.array(_SHIFTS), p.shape[1]))
        return tuple(a.reshape((n_shifts, p.shape[1]) + a.shape[1:]) for a in f)

    if cache is None:
        return fit(pairs)
    key = (w.tobytes(), rows.tobytes())
    if cache.get("data") != key:   # another data set: start afresh
        cache.clear()
        cache["data"] = key
    store = cache.get(poles)
    if store is None:
        shape = (n_shifts,) + rows.shape[:1] + (w.size - 1,)
        store = cache[poles] = {"done": np.zeros(shape[1:], dtype=bool), "fit": None, "shape": shape}
    missing = ~store["done"][pairs[0], pairs[1]]
    if missing.any():
        new_pairs = np.unique(pairs[:, missing], axis=1)
        new = fit(new_pairs)
        if store["fit"] is None:
            store["fit"] = tuple(np.full(store["shape"] + a.shape[2:], np.nan, dtype=a.dtype) for a in new)
        for full, a in zip(store["fit"], new):
            full[:, new_pairs[0], new_pairs[1]] = a
        store["done"][new_pairs[0], new_pairs[1]] = True
    return tuple(full[:, pairs[0], pairs[1]] for full in store["fit"])


def _rational_values(fit, at: np.ndarray) -> np.ndarray:
    """The readings of :func:`_rational_fits` at the points ``at`` (any shape ``S`` that the fit's leading axes,
    ``S`` too, broadcast with)."""
    num, den, centre, width, scale, _ = fit
    t = (at - centre) / width
    with np.errstate(all="ignore"):
        return (sum(num[..., j] * t ** j for j in range(num.shape[-1]))
                / (t ** den.shape[-1] + sum(den[..., j] * t ** j for j in range(den.shape[-1])))) * scale


def rational_interpolant(omega_d: np.ndarray, H: np.ndarray, at: np.ndarray, poles: int = 1,
                         shift: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Local rational reading of samples: at each point, ``N(t) / D(t)`` with ``deg N = poles + 1`` and ``D`` monic of
    degree ``poles``, fitted by least squares to the ``2 poles + 4`` samples around the point's interval (``t``:
    ``omega_d`` from the interval's centre in units of its width).

    The fit is linear in the coefficients of ``N`` and ``D`` once the residual ``N - D H`` is divided by ``D``
    (Sanathanan-Koerner iterations, ``D`` of the previous one: :data:`_SK_ITERATIONS`), each solved by a QR
    factorisation with a small ridge, so rank-deficient windows (a function of lower type there) give a finite
    reading.

    Parameters
    ----------
    omega_d : ndarray, shape (K,), distinct
    H : ndarray, shape (p, m, K), complex
    at : ndarray, shape (J,), within ``[min omega_d, max omega_d]``
    poles : int
        1 (one local resonance, six samples) or more.
    shift : int
        Moves the window by ``shift`` samples, within the data.

    Raises
    ------
    OptionError
        ``poles`` not a whole number >= 1, ``shift`` not a whole number.

    Returns
    -------
    values : ndarray, shape (p, m, J), complex
        The readings at ``at`` (NaN where the data have fewer samples than the window).
    misfit : ndarray, shape (p, m, J)
        Largest absolute residual over the window's samples.
    """
    for name, v in (("poles", poles), ("shift", shift)):
        if isinstance(v, (bool, np.bool_)) or not isinstance(v, (int, np.integer)) or (name == "poles" and v < 1):
            raise OptionError(f"{name} must be a whole number{' >= 1' if name == 'poles' else ''}; got {v!r}")
    order = np.argsort(omega_d)
    w = np.asarray(omega_d, dtype=float)[order]
    H = np.asarray(H, dtype=complex)[:, :, order]
    at = np.asarray(at, dtype=float)
    p, m, K = H.shape
    if K < 2 * poles + 4:
        nan = np.full((p, m, at.size), np.nan)
        return nan + 0j, nan
    k, _, _ = _intervals(w, at)
    fit = _rational_fits(w, H.reshape(p * m, K), np.repeat(np.arange(p * m), at.size), np.tile(k, p * m), poles,
                         shift)
    values = _rational_values(fit, np.tile(at, p * m))
    return values.reshape(p, m, at.size), fit[-1].reshape(p, m, at.size)


def sample_readings(omega_d: np.ndarray, H: np.ndarray, at: np.ndarray,
                    cache: dict | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Readings of the samples at the points ``at`` and their spread: per output, input and point, the simplest
    family of the module docstring that explains the samples around the point's interval.

    Parameters
    ----------
    omega_d : ndarray, shape (K,), K >= 4, distinct (rad/sample)
    H : ndarray, shape (p, m, K), complex
    at : ndarray, shape (J,), within ``[min omega_d, max omega_d]``
    cache : dict, optional
        Kept by the caller across calls on the same data (any points): the local rational fits are then made once
        per output, input, interval and window (:func:`sysid.order_sweep` estimates every order on one data set).

    Returns
    -------
    readings : ndarray, shape (4, p, m, J), complex
        The family's readings (a rational family's three fill the first three rows and repeat its centred one).
    spread : ndarray, shape (p, m, J)
        Largest distance of a reading from the family's first (centred) one.
    family : ndarray, shape (p, m, J), int
        0: cubic; 1, 2: local rational with that many poles.
    """
    wd = np.asarray(omega_d, dtype=float)
    H = np.asarray(H)
    at = np.asarray(at, dtype=float)
    I0 = cubic_interpolant(wd, H, at)
    readings = np.stack([I0, polar_interpolant(wd, H, at), cubic_interpolant(wd, H, at, -1),
                         cubic_interpolant(wd, H, at, 1)])
    family = np.zeros(I0.shape, dtype=int)
    misfit = cubic_misfit(wd, H, at)
    peak = np.abs(H).max(axis=(1, 2))[:, None, None]
    order = np.argsort(wd)
    w, Hs = wd[order], H[:, :, order]
    rows = Hs.reshape(-1, wd.size)                                    # (p m, K)
    sigma = noise_level(Hs, np.where(w >= np.pi, np.inf, w))[:, None, None] * peak   # (along the sorted grid)
    floor = np.broadcast_to(np.maximum(CUBIC_NOISE_MULT * sigma, READING_FLOOR * peak), misfit.shape).copy()
    k, _, _ = _intervals(w, at)
    for poles in (1, 2):
        if w.size < 2 * poles + 6:   # a window and a sample either side to shift it to
            break
        todo = misfit > floor   # the family so far misses the samples around the interval by more than it may
        if not todo.any():
            break
        ch, pt = np.nonzero(todo.reshape(rows.shape[0], at.size))    # the (output x input, point) pairs to read
        # one fit per (output x input, interval) and window shift, all in one batch
        pairs, inverse = np.unique(np.stack([ch, k[pt]]), axis=1, return_inverse=True)
        fit = _pair_fits(w, rows, pairs, poles, cache)                  # (3, pairs, ...)
        inverse = inverse.reshape(-1)
        R = _rational_values(tuple(f[:, inverse] for f in fit), at[pt][None, :])             # (3, pairs to read)
        miss = fit[-1][0, inverse]
        # a reading on (or next to) its own pole - a jump in the samples, or a pole-zero pair that nearly cancels
        # in a window of lower type - is no reading of the samples: at most _MAX_READING times their largest value
        bounded = np.abs(R).max(axis=0) <= _MAX_READING * fit[4][:, inverse].max(axis=0)
        ok = bounded & np.all(np.isfinite(R), axis=0) & (misfit.reshape(-1, at.size)[ch, pt] > READING_GAIN * miss)
        if not ok.any():
            continue
        ch, pt, R, miss = ch[ok], pt[ok], R[:, ok], miss[ok]
        i, j = np.unravel_index(ch, misfit.shape[:2])
        readings[:, i, j, pt] = np.concatenate([R, R[:1]])          # four rows, as the cubic family's
        family[i, j, pt] = poles
        misfit[i, j, pt] = miss
        floor[i, j, pt] = np.maximum(RATIONAL_NOISE_MULT * sigma, READING_FLOOR * peak)[i, 0, 0]
    spread = np.max(np.abs(readings[1:] - readings[:1]), axis=0)
    return readings, spread, family


def _deviation_and_spread(A, B, C, D, omega_d, H, cache=None):
    """:func:`between_deviation`'s points and departures, and the readings' spread there (p, m, J)."""
    H = np.asarray(H)
    wd = np.asarray(omega_d, dtype=float)
    lam = np.linalg.eigvals(np.asarray(A, dtype=float)) if np.size(A) else None
    pts = between_points(wd, lam)
    with np.errstate(all="ignore"):
        Gm = evaluate_ss(A, B, C, D, np.exp(1j * pts))
    # where the readings disagree the samples do not pin the response down (a fast phase, an uncertain local
    # resonance), and the model is charged only with its departure beyond that spread
    readings, spread, _ = sample_readings(wd, H, pts, cache)
    dev = np.maximum(np.min(np.abs(Gm[None] - readings), axis=0) - spread, 0.0)
    return pts, np.where(np.isfinite(dev), dev, np.inf), spread


def between_deviation(A, B, C, D, omega_d, H) -> tuple[np.ndarray, np.ndarray]:
    """The points between the samples and the model's departure there, beyond the spread of the readings of
    the samples (:func:`sample_readings`; see :func:`between_error`).

    Returns
    -------
    pts : ndarray, shape (J,)
        :func:`between_points` (``omega_d``, rad/sample).
    dev : ndarray, shape (p, m, J)
        Absolute departure (units of ``H``); inf where the model is not finite; NaN when the data have fewer than
        four distinct frequencies.
    """
    wd = np.asarray(omega_d, dtype=float)
    if np.unique(wd).size < 4:   # no cubic through the samples: nothing to read between them
        pts = between_points(wd)
        return pts, np.full(np.shape(H)[:2] + pts.shape, np.nan)
    pts, dev, _ = _deviation_and_spread(A, B, C, D, omega_d, H)
    return pts, dev


def between_estimate(A, B, C, D, omega_d, H, cache: dict | None = None) -> tuple[np.ndarray, np.ndarray]:
    """:func:`between_error` and :func:`between_uncertainty` from one set of readings: ``(error (p,), uncertainty
    (p,))``, fractions of each output's data peak (NaN with fewer than four distinct frequencies). ``cache``: see
    :func:`sample_readings`."""
    H = np.asarray(H)
    if np.unique(np.asarray(omega_d, dtype=float)).size < 4:
        return np.full(H.shape[0], np.nan), np.full(H.shape[0], np.nan)
    _, dev, spread = _deviation_and_spread(A, B, C, D, omega_d, H, cache)
    peak = np.maximum(np.abs(H).max(axis=(1, 2)), np.finfo(float).tiny)
    return dev.max(axis=(1, 2)) / peak, spread.max(axis=(1, 2)) / peak


def between_uncertainty(A, B, C, D, omega_d, H) -> np.ndarray:
    """How far the samples leave the response open between them, per output: the largest spread of the local
    readings of the samples (:func:`sample_readings`) at the points :func:`between_error` looks at, as a fraction of
    the output's data peak. Where it is larger than :func:`between_error`, that estimate is a lower bound: the
    samples do not say which of their readings the truth follows. On the paper's LFD data (McKelvey's grid, M = 256,
    eight samples above k = 2) it is 0.54 - 0.68 of the peak for Cm of T4 and T5 at every order, where the fits are
    0.36 - 0.77 off between the samples against an LFD eight times denser (bench/sysid_between_bench.py; their
    estimates 0.007 - 0.57); on the 12-state systems with 0.3 % - 1 % noise about 0.02, on the Sears function
    0.01 (measured 2026-12-04).

    Same parameters as :func:`between_error`; returns ndarray, shape (p,).
    """
    return between_estimate(A, B, C, D, omega_d, H)[1]


def between_error(A, B, C, D, omega_d, H, cache: dict | None = None) -> np.ndarray:
    """Estimated error per output of the discrete model ``(A, B, C, D)`` between the samples ``H`` at
    ``omega_d``: ``max_j d_j / max_k |H_k|`` over the :func:`between_points` ``z_j`` (interval midpoints and the
    model's resonance peaks inside intervals), where ``d_j`` is the model's distance from the nearest local reading
    of the samples (:func:`sample_readings`: four cubics, or local rational functions where a resonance narrower
    than the spacing defeats the cubics) less the readings' spread (:func:`between_deviation`).

    Parameters
    ----------
    A : ndarray, shape (n, n); B : ndarray, shape (n, m); C : ndarray, shape (p, n); D : ndarray, shape (p, m)
    omega_d : ndarray, shape (K,)
        Data frequencies in ``[0, pi]`` (rad/sample).
    H : ndarray, shape (p, m, K), complex
    cache : dict, optional
        See :func:`sample_readings` (estimates of several models of the same data).

    Returns
    -------
    ndarray, shape (p,)
        Fractions of each output's data peak (over inputs and samples); NaN when the data have fewer than four
        distinct frequencies (no cubic through them), inf when the model is not finite there.
    """
    return between_estimate(A, B, C, D, omega_d, H, cache)[0]
