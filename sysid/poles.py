"""Poles of the relocation method (:mod:`sysid.relocation`): where they may lie, their canonical order, and the
bases they span.

- :func:`stability_region`: the s-plane disc that the bilinear map sends inside ``|z| <= rho``;
- :func:`resolution_floor`: the smallest damping of a resonant pair that the data's frequency spacing resolves;
- :func:`pair_poles`: eigenvalues -> canonical order (real poles, then conjugate pairs), projected into the
  region and onto the floor;
- :func:`partial_fraction_basis`, :func:`modal_realisation`: the real-parameter partial-fraction basis in
  ``s`` and its modal state-space form (Gustavsen & Semlyen 1999, Eq. A.3);
- :func:`discrete_basis`, :func:`input_normal`: the bilinear map of that realisation (paper Eq. 31) in
  input-normal coordinates; :func:`balanced_coordinates` for a fitted model whose evaluation loses digits.
"""

import numpy as np

from .errors import FrequencyDataError, OptionError

__all__ = ["stability_region", "resolution_floor", "floor_at", "pair_poles", "initial_poles", "pole_groups", "partial_fraction_basis",
           "modal_realisation", "pole_distance", "discrete_basis", "input_normal", "balanced_coordinates", "RESOLUTION",
           "MIN_DAMPING", "MIN_SEPARATION"]

#: Smallest |Re s| of a relocated pole, relative to the largest finite data frequency (poles on the imaginary
#: axis would make the model marginally stable; the reflection keeps them strictly inside).
MIN_DAMPING = 1e-6
#: Smallest relative gap between two real poles.
MIN_SEPARATION = 1e-2
#: Smallest damping of a resonant pole pair, in units of the local spacing of the data frequencies at the
#: pole's frequency (:func:`resolution_floor`).
RESOLUTION = 0.5


# --------------------------------------------------------------------------------------------- poles
def stability_region(T: float, rho: float) -> tuple[float, float]:
    """The disc of the s-plane that the bilinear map with period ``T`` sends to ``|z| <= rho < 1``.

    ``z = (1 + s T/2) / (1 - s T/2)``; the circle ``|z| = rho`` is the Apollonius circle with centre
    ``-(2/T) (1 + rho^2) / (1 - rho^2)`` and radius ``(2/T) 2 rho / (1 - rho^2)``, inside the open left
    half plane.

    Returns
    -------
    (centre, radius) : (float, float)
    """
    if not 0.0 < rho < 1.0:
        raise OptionError(f"rho must be in (0, 1); got {rho!r}")
    g = 2.0 / float(T)
    return -g * (1 + rho * rho) / (1 - rho * rho), g * 2 * rho / (1 - rho * rho)


def resolution_floor(omega: np.ndarray, resolution: float = RESOLUTION) -> tuple[np.ndarray, np.ndarray]:
    """Smallest damping ``|Re s|`` that the data can resolve, against the frequency ``Im s`` of a pole pair.

    A pole pair at ``-sigma +/- i omega_p`` has a resonance of half-width ``sigma`` about ``omega_p``. Where the
    data frequencies are ``Delta`` apart, a resonance much narrower than ``Delta`` is invisible at the samples
    and free to take any height between them: the fit places such poles to bend the response at one or two
    samples, and the model then resonates where nothing was measured (on the paper's grid, T = 70 / (2 pi), the
    samples at omega = 14.6 and 29.2 have none between them, and an unconstrained relocation put a resonance of
    28 times Cm's peak at omega = 15.5). Requiring ``sigma >= resolution * Delta(omega_p)`` keeps every
    resonance at least ``2 * resolution`` sample spacings wide, so the samples see its shape; where the data
    are dense (low frequencies on the bilinear grid) the floor is far below any damping a fit needs.

    Parameters
    ----------
    omega : ndarray, shape (K,)
        Data frequencies (U_inf / c units; ``0`` and ``inf`` allowed, duplicates ignored).
    resolution : float
        Smallest half-width of a resonance in local sample spacings (``>= 0``; 0: no floor).

    Returns
    -------
    (xp, fp) : ndarray, shape (J,) each
        Breakpoints of the piecewise-linear floor ``sigma_min(omega_p) = interp(omega_p, xp, fp)``: the local
        spacing at the midpoint of each data interval, constant below the first midpoint, and growing like
        the distance to the highest finite frequency above it (nothing there was measured).
    """
    w = np.asarray(omega, dtype=float)
    w = np.unique(w[np.isfinite(w) & (w >= 0)])
    if w.size < 2 or resolution <= 0:
        return np.array([0.0, 1.0]), np.zeros(2)
    gaps = np.diff(w)
    mids = 0.5 * (w[1:] + w[:-1])
    top, last = float(w[-1]), float(gaps[-1])
    far = top + 1e6 * max(top, 1.0)
    xp = np.concatenate([mids, [top, far]])
    fp = resolution * np.concatenate([gaps, [last, last + (far - top)]])
    return xp, fp


def floor_at(im: np.ndarray, floor) -> tuple[np.ndarray, np.ndarray]:
    """Value and slope of the :func:`resolution_floor` ``(xp, fp)`` at ``|im|`` (0 for real poles)."""
    im = np.abs(np.asarray(im, dtype=float))
    if floor is None:
        return np.zeros_like(im), np.zeros_like(im)
    xp, fp = floor
    val = np.interp(im, xp, fp)
    slopes = np.diff(fp) / np.diff(xp)
    seg = np.clip(np.searchsorted(xp, im, side="right") - 1, 0, slopes.size - 1)
    slope = np.where((im > xp[0]) & (im < xp[-1]), slopes[seg], 0.0)
    return np.where(im > 0, val, 0.0), np.where(im > 0, slope, 0.0)


def pair_poles(lam: np.ndarray, scale: float, region=None) -> np.ndarray:
    """Eigenvalues of a real matrix -> poles in the canonical order: real ones, then pairs (a, conj a),
    Im a > 0; tiny imaginary parts (round-off) are dropped, ``Re >= 0`` is reflected to ``Re < 0``
    (``a -> -conj(a)``), and with ``region = (centre, radius)`` (:func:`stability_region`) poles outside the
    disc are moved radially onto it (so the discrete model keeps its spectral-radius margin), after poles
    beyond ``|s| = smax`` have been scaled back to that magnitude and pairs with less damping than the
    region's :func:`resolution_floor` have been moved left onto it."""
    lam = np.asarray(lam, dtype=complex)
    tol = 1e-10 * max(scale, 1.0)
    re = lam.real.copy()
    re = np.where(re >= -MIN_DAMPING * scale, -np.maximum(np.abs(re), MIN_DAMPING * scale), re)
    if region is not None and len(region) > 3:
        re = np.where(np.abs(lam.imag) > tol, np.minimum(re, -floor_at(lam.imag, region[3])[0]), re)
    lam = re + 1j * lam.imag
    if region is not None:  # (centre, radius, smax[, floor])
        c0, r0, smax = region[:3]
        mag = np.abs(lam)
        lam = np.where(mag > smax, lam * (smax / np.maximum(mag, 1e-300)), lam)
        d = np.abs(lam - c0)
        inner = r0 * (1 - 1e-9)  # strictly inside, so that round-off in the bilinear map keeps |z| < 1 - margin
        out = d > inner
        lam = np.where(out, c0 + (lam - c0) * (inner / np.maximum(d, 1e-300)), lam)
    real = np.sort(lam[np.abs(lam.imag) <= tol].real)
    up = lam[lam.imag > tol]
    # a real matrix gives conjugate pairs; keep the upper ones and pair them with their conjugates
    n_up = np.count_nonzero(lam.imag > tol)
    n_dn = np.count_nonzero(lam.imag < -tol)
    if n_up != n_dn:  # pragma: no cover - round-off broke a pair: treat the odd ones as real
        up = up[np.argsort(-np.abs(up.imag))][: min(n_up, n_dn)]
        rest = lam.size - real.size - 2 * up.size
        real = np.sort(np.concatenate([real, -np.abs(lam[np.abs(lam.imag) > tol].real)[:rest]]))
    up = up[np.argsort(up.imag)]
    # real poles that the projection (or the relocation) made coincide would make the basis degenerate:
    # keep neighbours at least MIN_SEPARATION apart (relative), moving the right one of a pair to the right
    for k in range(real.size - 2, -1, -1):
        gap = MIN_SEPARATION * abs(real[k])
        if real[k + 1] - real[k] < gap:
            real[k + 1] = real[k] + gap
    out = [complex(r) for r in real]
    for a in up:
        out += [a, np.conj(a)]
    return np.array(out, dtype=complex)


def initial_poles(omega: np.ndarray, n: int, spacing: str = "log") -> np.ndarray:
    """Starting poles for :func:`relocate_poles`: ``n // 2`` lightly damped pairs spread over the data band.

    Parameters
    ----------
    omega : ndarray, shape (K,)
        Data frequencies (U_inf / c units; ``0`` and ``inf`` allowed and ignored for the band).
    n : int
        Number of states (``n % 2`` real poles are added at the geometric middle of the band).
    spacing : {"log", "lin"}
        Imaginary parts ``beta`` log- or linearly spaced over ``[omega_min, omega_max]`` of the positive finite
        data frequencies; real parts ``-beta / 100`` (Gustavsen & Semlyen 1999, Sec. IV).

    Returns
    -------
    ndarray, shape (n,), complex
    """
    w = np.asarray(omega, dtype=float)
    w = w[np.isfinite(w) & (w > 0)]
    if w.size == 0:
        raise FrequencyDataError("pole relocation needs at least one positive finite frequency")
    lo, hi = float(w.min()), float(w.max())
    npair = n // 2
    if spacing == "log":
        beta = np.geomspace(lo, hi, npair) if npair > 1 else np.array([np.sqrt(lo * hi)] * npair)
    elif spacing == "lin":
        beta = np.linspace(lo, hi, npair) if npair > 1 else np.array([0.5 * (lo + hi)] * npair)
    else:
        raise OptionError(f"spacing must be 'log' or 'lin'; got {spacing!r}")
    out = [-np.sqrt(lo * hi)] * (n % 2)
    for b in beta:
        out += [complex(-b / 100, b), complex(-b / 100, -b)]
    return np.array(out, dtype=complex)


def pole_groups(poles: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The first column of each real pole or conjugate pair in canonical order.

    Parameters
    ----------
    poles : ndarray, shape (n,), complex
        Canonical order (:func:`pair_poles`): real poles, then pairs ``(a, conj a)``.

    Returns
    -------
    idx : ndarray of int, shape (g,)
        Index of each group's first pole (a pair occupies ``idx`` and ``idx + 1``).
    pair : ndarray of bool, shape (g,)
        True where the group is a pair.
    """
    is_pair = np.abs(poles.imag) > 0
    first = np.ones(poles.size, dtype=bool)
    first[1:] = ~(is_pair[1:] & is_pair[:-1] & (np.conj(poles[1:]) == poles[:-1]))
    idx = np.flatnonzero(first)
    return idx, is_pair[idx]


def partial_fraction_basis(s: np.ndarray, poles: np.ndarray) -> np.ndarray:
    """Real-parameter partial-fraction basis, shape (K, n), complex.

    A real pole ``a`` gives ``1 / (s - a)``; a pair ``(a, conj a)`` gives ``1/(s-a) + 1/(s-conj a)`` and
    ``i/(s-a) - i/(s-conj a)``, so that real coefficients ``(c1, c2)`` are the residue ``c1 + i c2`` at ``a``
    (Gustavsen & Semlyen 1999, Eq. A.3). ``s = inf`` gives a zero row.
    """
    K = s.size
    n = poles.size
    Phi = np.zeros((K, n), dtype=complex)
    fin = np.isfinite(s)
    if n == 0:
        return Phi
    sf = s[fin][:, None]
    idx, pair = pole_groups(poles)
    a = poles[idx]
    t1 = 1.0 / (sf - a[None, :])
    t2 = 1.0 / (sf - np.conj(a)[None, :])
    rows = Phi if fin.all() else np.zeros((int(fin.sum()), n), dtype=complex)  # the finite rows, filled in place
    rows[:, idx[~pair]] = t1[:, ~pair]
    t1p, t2p = t1[:, pair], t2[:, pair]
    rows[:, idx[pair]] = t1p + t2p
    rows[:, idx[pair] + 1] = 1j * (t1p - t2p)
    if rows is not Phi:
        Phi[fin] = rows
    return Phi


def modal_realisation(poles: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Real ``(A_c, b)`` with ``(sI - A_c)^-1 b`` equal to :func:`partial_fraction_basis` (one input).

    Real pole ``a``: ``A_c = [a]``, ``b = [1]``. Pair ``a = x + i y``: ``A_c = [[x, y], [-y, x]]``,
    ``b = [2, 0]`` (Gustavsen & Semlyen 1999, Eq. A.6), for which ``[1, 0] (sI - A_c)^-1 b`` and
    ``[0, 1] (sI - A_c)^-1 b`` are the two basis functions of the pair.

    Returns
    -------
    A_c : ndarray, shape (n, n); b : ndarray, shape (n,)
    """
    n = poles.size
    A = np.zeros((n, n))
    b = np.zeros(n)
    i = 0
    while i < n:
        a = poles[i]
        if a.imag == 0:
            A[i, i] = a.real
            b[i] = 1.0
            i += 1
        else:
            A[i:i + 2, i:i + 2] = [[a.real, a.imag], [-a.imag, a.real]]
            b[i] = 2.0
            i += 2
    return A, b


def pole_distance(a, b) -> float:
    if a.size != b.size:
        return np.inf
    return float(np.abs(np.sort_complex(a) - np.sort_complex(b)).max()) if a.size else 0.0


# --------------------------------------------------------------------------------------------- discrete
def discrete_basis(poles: np.ndarray, T: float, m: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """Discrete ``(A, B)`` of the modal realisation of ``poles`` by the bilinear map (paper Eq. 31).

    Parameters
    ----------
    poles : ndarray, shape (n,), complex
        Continuous poles in canonical order, ``Re < 0``.
    T : float
        Sampling period (convective time units).
    m : int
        Inputs: ``B`` is block diagonal, one copy of the modal input vector per input, so ``A`` is
        ``kron(I_m, A_1)`` with ``n m`` states when ``m > 1``.

    Returns
    -------
    A : ndarray, shape (n m, n m); B : ndarray, shape (n m, m)
        ``(zI - A)^-1 B`` spans, per input, the same functions as the continuous partial fractions plus a
        constant (the bilinear map of ``1 / (s - a)`` is ``c1 + c2 / (z - a_d)``).
    """
    import scipy.linalg

    Ac, b = modal_realisation(poles)
    n = Ac.shape[0]
    A1 = np.kron(np.eye(m), Ac)
    B1 = np.kron(np.eye(m), b.reshape(n, 1))
    # the A and B of sysid.c2d_bilinear, with the same LU solves, without building control.StateSpace objects
    # (python-control's import alone is about 1.5 s; Re a < 0 keeps 2/T I - A1 regular)
    I = np.eye(n * m)
    lu = scipy.linalg.lu_factor((2.0 / T) * I - A1)
    Ad = scipy.linalg.lu_solve(lu, ((2.0 / T) * I + A1).T, trans=1).T
    Bd = (2.0 / np.sqrt(T)) * scipy.linalg.lu_solve(lu, B1)
    return np.asarray(Ad, dtype=float), np.asarray(Bd, dtype=float)


def input_normal(A, B):
    """``(A, B)`` in input-normal coordinates: ``A A^T + B B^T = I`` (controllability Gramian = I).

    The state transformation ``x = L x'`` with ``P = L L^T`` the controllability Gramian
    (``A P A^T - P + B B^T = 0``) leaves the function space of ``C (zI - A)^-1 B + D`` unchanged, and makes
    the map from ``C`` to the impulse response an isometry (``||C (zI - A)^-1 B||_H2 = ||C||_F``), so
    fitted output matrices cannot hold large cancelling entries. The modal form of nearly coincident poles
    did: entries of 1e10 in ``C`` for a DC gain of 7 (T4, N_r = 25), which lost 8 digits of the DC
    equality to round-off when the model was evaluated. Returns the input unchanged when the Gramian is not
    numerically positive definite.
    """
    import scipy.linalg

    try:
        P = scipy.linalg.solve_discrete_lyapunov(A, B @ B.T)
        P = 0.5 * (P + P.T)
        w, V = np.linalg.eigh(P)
    except (np.linalg.LinAlgError, ValueError):
        return A, B
    if not (np.all(np.isfinite(w)) and w.min() > 1e-13 * w.max()):
        return A, B
    L = V * np.sqrt(w)  # P = L L^T
    Li = (V / np.sqrt(w)).T  # L^-1
    return Li @ A @ L, Li @ B


def balanced_coordinates(A, B, C):
    """``(A, B, C)`` in balanced coordinates: both Gramians equal ``diag(hsv)``, the Hankel singular values.

    Used where a realisation's evaluation loses digits: in input-normal coordinates the fitted ``C`` of nearly
    coincident poles still cancels against ``(I - A)^-1 B`` (``sum_j |C_ij x_j|`` up to 6e5 times the peak
    on T5 at N_r = 55, i.e. 1e-10 of the peak of possible round-off in a double-precision DC gain); balanced,
    the same model's terms sum to a few times the peak. The square roots of the Gramians come from symmetric
    eigendecompositions, with eigenvalues below ``1e-14`` of the largest raised to it (nearly unobservable
    directions keep a bounded scaling).

    Parameters
    ----------
    A : ndarray, shape (n, n); B : ndarray, shape (n, m); C : ndarray, shape (p, n)
        A stable discrete realisation.

    Returns
    -------
    tuple or None
        ``(A_b, B_b, C_b, T, T_inv)``: the balanced matrices (the input's shapes) and the transformation
        ``x = T x_b`` (n, n) with its inverse; ``None`` when the Gramians cannot be computed or are not finite.
    """
    import scipy.linalg

    def root(M):
        w, V = np.linalg.eigh(0.5 * (M + M.T))
        w = np.maximum(w, 1e-14 * max(float(w.max()), np.finfo(float).tiny))
        return V * np.sqrt(w)

    try:
        Lp = root(scipy.linalg.solve_discrete_lyapunov(A, B @ B.T))
        Lq = root(scipy.linalg.solve_discrete_lyapunov(A.T, C.T @ C))
        U, hsv, Vt = np.linalg.svd(Lq.T @ Lp)
    except (np.linalg.LinAlgError, ValueError):
        return None
    if not (np.all(np.isfinite(hsv)) and hsv.min() > 0):
        return None
    T = (Lp @ Vt.T) / np.sqrt(hsv)  # x = T x_b
    Ti = (U / np.sqrt(hsv)).T @ Lq.T  # T^-1
    return Ti @ A @ T, Ti @ B, C @ T, T, Ti
