"""Frequency-domain subspace identification (McKelvey, Akcay & Ljung, IEEE TAC 41(7), 1996).

Two algorithms estimate ``A`` and ``C`` of a discrete model ``G(z) = D + C (zI - A)^-1 B`` from samples
``G_k = G(exp(1j omega_k))``; ``B`` and ``D`` then come from a (constrained) least squares in
:mod:`sysid.refit`.

- **Algorithm 1** (:func:`mckelvey1`) needs the equispaced grid ``omega_k = pi k / M``, ``k = 0..M``. The
  samples are extended to the full circle with complex conjugates, an inverse DFT of length ``2M`` gives the
  time-aliased impulse response ``h_i = C A^(i-1) (I - A^(2M))^-1 B`` (``i >= 1``: aliasing changes ``B``
  only), whose ``q x r`` block Hankel matrix has rank ``n``.
- **Algorithm 2** (:func:`mckelvey2`) works on arbitrary frequencies: the data matrix
  ``[W_q(omega_k) kron G_k]`` is projected onto the orthogonal complement of ``[W_q(omega_k) kron I_m]``
  (real and imaginary parts stacked) by an LQ factorisation, and the SVD of that projection ``R22``
  gives the range of the extended observability matrix.

Both then read ``A`` from the shift invariance of ``Gamma = U_s`` (the ``n`` leading left singular
vectors)::

    Gamma1 = J1 U_s (drop the last block row),  Gamma2 = J2 U_s (drop the first),
    A = Gamma1^+ Gamma2,  C = first p rows of U_s.

The SVD is the expensive step and is done once per data set (:func:`hankel_svd`); models of every order
are then cheap slices of it (:func:`from_basis`), which the order sweep in :mod:`sysid.order` uses.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .arrays import freeze_array_fields
from .errors import FrequencyDataError, FrequencyGridError, OptionError, OrderError
from .grids import check_discrete_frequencies, check_distinct
from .state_space import evaluate_ss, lstsq_bd, lstsq_bd_phi, modal_form, resolvent_C  # noqa: F401

__all__ = [
    "SubspaceResult",
    "HankelSVD",
    "hankel_svd",
    "hankel_singular_values",
    "from_basis",
    "mckelvey1",
    "mckelvey2",
    "subspace_identify",
    "default_q",
    "order_hint",
    # state-space evaluation, from sysid.state_space
    "modal_form",
    "resolvent_C",
    "lstsq_bd_phi",
    "lstsq_bd",
    "evaluate_ss",
]

_GRID_ATOL = 1e-9 * np.pi


@dataclass(frozen=True)
class HankelSVD:
    """The SVD step of a subspace identification, shared by all model orders.

    Attributes
    ----------
    U : ndarray, shape (q p, k)
        Left singular vectors (columns), ``k = min`` of the matrix dimensions.
    sv : ndarray, shape (k,)
        Singular values, decreasing; ``k = min(q p, r m)`` (Algorithm 1) or ``q p`` (Algorithm 2).
    p, m : int
        Outputs and inputs.
    q : int
        Block rows (the observability horizon).
    r : int or None
        Block columns of the Hankel matrix (Algorithm 1); ``None`` for Algorithm 2.
    method : str
        ``"mckelvey1"`` or ``"mckelvey2"``.
    max_order : int
        Largest order the sizes support (``< q``, ``<= (q - 1) p``, ``<= number of singular values``).
    """

    U: np.ndarray = field(repr=False)
    sv: np.ndarray = field(repr=False)
    p: int
    m: int
    q: int
    r: int | None
    method: str
    max_order: int

    def __post_init__(self):
        freeze_array_fields(self)   # the arrays of a frozen result are read-only too


@dataclass(frozen=True)
class SubspaceResult:
    """``A`` and ``C`` of one order, with what produced them.

    Attributes
    ----------
    A : ndarray, shape (n, n)
        Discrete state matrix from the shift equation ``Gamma1 A = Gamma2`` (least squares).
    C : ndarray, shape (p, n)
        Output matrix (first ``p`` rows of ``U_s``).
    singular_values : ndarray, shape (k,)
        All singular values of the Hankel matrix (Alg. 1) or of ``R22`` (Alg. 2), decreasing (the
        :attr:`HankelSVD.sv` of the SVD step): ``k = min(q p, r m)`` for Algorithm 1, ``k = q p`` for Algorithm 2.
    gamma1, gamma2 : ndarray, shape ((q - 1) p, n)
        ``J1 U_s`` and ``J2 U_s``; the stability module fits ``A`` to ``gamma1 A ~= gamma2``.
    q, r : int, int or None
        Hankel block rows and columns (``r = None`` for Algorithm 2).
    order : int
    method : str
    """

    A: np.ndarray
    C: np.ndarray
    singular_values: np.ndarray = field(repr=False)
    gamma1: np.ndarray = field(repr=False)
    gamma2: np.ndarray = field(repr=False)
    q: int
    r: int | None
    order: int
    method: str

    def __post_init__(self):
        freeze_array_fields(self)   # the arrays of a frozen result are read-only too

    @property
    def spectral_radius(self) -> float:
        """Largest eigenvalue modulus of ``A``."""
        return float(np.max(np.abs(np.linalg.eigvals(self.A)))) if self.A.size else 0.0


# --------------------------------------------------------------------------------------------------
# input handling
# --------------------------------------------------------------------------------------------------
def _as_G(G: Any) -> np.ndarray:
    try:
        arr = np.asarray(G, dtype=complex)
    except (TypeError, ValueError):
        raise FrequencyDataError(f"G must be an array of numbers of shape (p, m, K) or a FrequencyResponse, got "
                                 f"{type(G).__name__}") from None
    if arr.ndim == 1:
        arr = arr.reshape(1, 1, -1)
    if arr.ndim != 3:
        raise FrequencyDataError(f"G must have shape (p, m, K), got shape {arr.shape}")
    if not np.isfinite(arr).all():
        raise FrequencyDataError("G contains NaN or inf values; remove those frequencies")
    return arr


def _is_mckelvey_grid(omega_d: np.ndarray) -> bool:
    M = omega_d.size - 1
    return M >= 1 and bool(np.allclose(omega_d, np.pi * np.arange(M + 1) / M, rtol=0.0, atol=_GRID_ATOL))


def _unpack(data: Any, omega_d: Any = None) -> tuple[np.ndarray, np.ndarray]:
    """Accept a FrequencyResponse or (G, omega_d) arrays; return G (p, m, K) and omega_d (K,)."""
    if hasattr(data, "H") and hasattr(data, "omega_d"):
        if data.omega_d is None:
            raise FrequencyGridError(
                "the response has no discrete frequencies omega_d; give a sampling period T "
                "(FrequencyResponse.with_T(T) or from_continuous(H, omega, T))"
            )
        return np.asarray(data.H), np.asarray(data.omega_d)
    G = _as_G(data)
    if omega_d is None:
        # arrays without frequencies: assume McKelvey's grid
        M = G.shape[2] - 1
        if M < 1:
            raise FrequencyGridError("need at least 2 frequencies")
        return G, np.pi * np.arange(M + 1) / M
    wd = check_discrete_frequencies(omega_d)  # finite, in [0, pi]
    if wd.size != G.shape[2]:
        raise FrequencyDataError(f"omega_d has {wd.size} frequencies but G has K={G.shape[2]} (G.shape[2])")
    check_distinct(wd, "omega_d")   # (every frequency equal gave a model on the unit circle)
    return G, wd


def default_q(method: str, p: int, m: int, K: int, order: int | None = None) -> tuple[int, int | None]:
    """Default Hankel sizes ``(q, r)``.

    Algorithm 1 (``K = M + 1`` samples):

    - with a target order ``n``: ``q = min(M, 2n + 2)`` block rows and ``r = 2M - q`` block columns. ``r``
      then uses every one of the ``2M - 1`` aliased impulse-response samples ``h_1 .. h_{2M-1}``, and a
      ``q`` fixed by the order (not growing with ``M``) keeps the estimate consistent as ``M`` grows
      (McKelvey et al. 1996: fixed ``q``, ``r -> inf``). The symmetric choice ``q = r = M`` is not: the
      noise then spreads over as many rows as the signal. Measured with white noise (mean over seeds of
      the relative error against the true system, M = 32 -> 256): random 6th-order 2x2 systems, error
      falls by 2.75x with this default (``M^-1/2`` predicts 2.83x) but only 1.9x with ``q = r = M``;
      random 4th-order SISO systems, 2.2x against none at all with ``q = r = M``.
    - without an order (e.g. :func:`hankel_singular_values` for a first look): ``q = r = M``, which shows
      all ``M`` singular values.

    Algorithm 2 (``K`` arbitrary frequencies): the projection needs ``q (m + p) <= 2 K m`` (more real
    equations than rows), so ``q <= q_max = floor(2 K m / (m + p)) - 1``. With a target order
    ``q = min(q_max, 2n + 2)``; without one ``q = min(q_max, max(2, K // 2))``.
    """
    if method == "mckelvey1":
        M = K - 1
        if order is None:
            return M, M
        q = max(2, min(M, 2 * int(order) + 2))
        return q, 2 * M - q
    qmax = (2 * K * m) // (m + p) - 1
    if order is None:
        return max(1, min(qmax, max(2, K // 2))), None
    return max(1, min(qmax, 2 * int(order) + 2)), None


# --------------------------------------------------------------------------------------------------
# SVD step
# --------------------------------------------------------------------------------------------------
def _block_hankel(h: np.ndarray, q: int, r: int) -> np.ndarray:
    """Block Hankel matrix, block (i, j) = h[:, :, i + j + 1] (0-based i, j): shape (q p, r m)."""
    p, m, _ = h.shape
    idx = np.arange(q)[:, None] + np.arange(r)[None, :] + 1  # (q, r)
    blocks = h[:, :, idx]  # (p, m, q, r)
    return blocks.transpose(2, 0, 3, 1).reshape(q * p, r * m)


def _svd1(G: np.ndarray, q: int | None, r: int | None, order: int | None) -> HankelSVD:
    p, m, K = G.shape
    M = K - 1
    if M < 1:
        raise FrequencyGridError("Algorithm 1 needs at least 2 frequencies (M >= 1)")
    q0, _ = default_q("mckelvey1", p, m, K, order)
    q = q0 if q is None else int(q)
    r = 2 * M - q if r is None else int(r)  # default: every impulse-response sample once
    if q < 2 or r < 1 or q + r > 2 * M:
        raise OrderError(
            f"Hankel sizes q={q}, r={r} are invalid for M={M}: need q >= 2, r >= 1 and q + r <= 2M = {2 * M} "
            "(the inverse DFT gives 2M - 1 usable impulse-response samples); reduce q or r, or use more "
            "frequencies"
        )
    # full circle: G_{2M-k} = conj(G_k), k = 1..M-1
    full = np.concatenate([G, np.conj(G[:, :, M - 1:0:-1])], axis=2)  # (p, m, 2M)
    h = np.fft.ifft(full, axis=2).real  # h_i = (1/2M) sum_k G_k exp(+j 2 pi i k / 2M)
    Hk = _block_hankel(h, q, r)
    U, s, _ = np.linalg.svd(Hk, full_matrices=False)
    max_order = min(q - 1, (q - 1) * p, r * m, s.size)
    return HankelSVD(U=U, sv=s, p=p, m=m, q=q, r=r, method="mckelvey1", max_order=max_order)


def _svd2(G: np.ndarray, omega_d: np.ndarray, q: int | None, order: int | None) -> HankelSVD:
    p, m, K = G.shape
    q0, _ = default_q("mckelvey2", p, m, K, order)
    q = q0 if q is None else int(q)
    if q < 2 or q * (m + p) > 2 * K * m:
        qmax = (2 * K * m) // (m + p)
        raise OrderError(
            f"q={q} block rows is invalid for K={K} frequencies with m={m}, p={p}: need 2 <= q <= "
            f"2 K m / (m + p) = {qmax}; reduce q or add frequencies"
        )
    z = np.exp(1j * omega_d)  # (K,)
    W = z[None, :] ** np.arange(q)[:, None]  # (q, K): W_q(omega_k) as columns
    # Gbig[(i, a), (k, b)] = z_k^i G_k[a, b]  -> (q p, K m)
    Gbig = (W[:, None, :, None] * G.transpose(0, 2, 1)[None, :, :, :]).reshape(q * p, K * m)
    # Ubig[(i, a), (k, b)] = z_k^i delta_ab -> (q m, K m)
    eye = np.eye(m)
    Ubig = (W[:, None, :, None] * eye[None, :, None, :]).reshape(q * m, K * m)
    stack = np.concatenate([Ubig, Gbig], axis=0)
    stack = np.concatenate([stack.real, stack.imag], axis=1)  # (q (m + p), 2 K m)
    # LQ of stack = QR of its transpose: stack^T = Q R, stack = R^T Q^T = L Q^T.
    R = np.linalg.qr(stack.T, mode="r")
    L22 = R[q * m:, q * m:].T  # (q p, q p): the part of G orthogonal to the rows of U
    U, s, _ = np.linalg.svd(L22, full_matrices=False)
    max_order = min(q - 1, (q - 1) * p, s.size)
    return HankelSVD(U=U, sv=s, p=p, m=m, q=q, r=None, method="mckelvey2", max_order=max_order)


def _resolve_method(method: str, omega_d: np.ndarray) -> str:
    if method == "auto":
        return "mckelvey1" if _is_mckelvey_grid(omega_d) else "mckelvey2"
    if method not in ("mckelvey1", "mckelvey2"):
        raise OptionError(f"method must be 'auto', 'mckelvey1' or 'mckelvey2', got {method!r}")
    if method == "mckelvey1" and not _is_mckelvey_grid(omega_d):
        raise FrequencyGridError(
            "Algorithm 1 (method='mckelvey1') needs the equispaced grid omega_d = pi k / M, k = 0..M "
            "(sysid.mckelvey_grid); these frequencies are not on it: use method='mckelvey2' (Algorithm 2, "
            "arbitrary frequencies) or method='auto'"
        )
    return method


def hankel_svd(data: Any, omega_d: Any = None, *, method: str = "auto", q: int | None = None,
               r: int | None = None, order: int | None = None) -> HankelSVD:
    """Compute the SVD step once (reused for every model order).

    Parameters
    ----------
    data : FrequencyResponse or array_like, complex, shape (p, m, K)
        Frequency response. Plain arrays without ``omega_d`` are taken to lie on McKelvey's grid.
    omega_d : array_like, shape (K,), optional
        Discrete frequencies in ``[0, pi]`` (when ``data`` is an array).
    method : {"auto", "mckelvey1", "mckelvey2"}
        ``"auto"`` picks Algorithm 1 on the equispaced grid and Algorithm 2 otherwise.
    q, r : int, optional
        Block rows and columns; defaults in :func:`default_q` (``r = 2M - q`` when only ``q`` is given).
    order : int, optional
        Target (largest) model order; sets the default ``q`` (see :func:`default_q`).

    Returns
    -------
    HankelSVD
    """
    G, wd = _unpack(data, omega_d)
    method = _resolve_method(method, wd)
    if order is not None and (isinstance(order, bool) or not isinstance(order, (int, np.integer)) or order < 1):
        raise OrderError(f"order must be a positive integer, got {order!r}")
    if method == "mckelvey1":
        return _svd1(G, q, r, order)
    if r is not None:
        raise OrderError("r (Hankel block columns) applies to Algorithm 1 only; leave r=None for 'mckelvey2'")
    return _svd2(G, wd, q, order)


def hankel_singular_values(data: Any, omega_d: Any = None, *, method: str = "auto", q: int | None = None,
                           r: int | None = None) -> np.ndarray:
    """Singular values that guide the order choice, decreasing.

    The SVD step of :func:`hankel_svd` without a target order, so with the order-free default Hankel sizes of
    :func:`default_q`: ``q = r = M`` for Algorithm 1, ``q = min(q_max, max(2, K // 2))`` for Algorithm 2.

    Parameters
    ----------
    data : FrequencyResponse or array_like, complex, shape (p, m, K)
        Frequency response (``(K,)`` accepted for SISO). Plain arrays without ``omega_d`` are taken to lie on
        McKelvey's grid ``omega_d = pi k / M``, ``k = 0..M`` (``K = M + 1``).
    omega_d : array_like, shape (K,), optional
        Discrete frequencies in ``[0, pi]`` (rad/sample), when ``data`` is an array.
    method : {"auto", "mckelvey1", "mckelvey2"}
        ``"auto"`` picks Algorithm 1 on the equispaced grid and Algorithm 2 otherwise.
    q, r : int, optional
        Hankel block rows and columns (``r``: Algorithm 1 only; ``r = 2M - q`` when only ``q`` is given).

    Returns
    -------
    ndarray, shape (k,)
        Singular values, decreasing; ``k = min(q p, r m)`` (Algorithm 1) or ``q p`` (Algorithm 2).

    Raises
    ------
    OptionError
        Unknown ``method``.
    FrequencyGridError
        No ``omega_d`` (a FrequencyResponse without ``T``), ``omega_d`` outside ``[0, pi]`` or not finite, fewer
        than 2 frequencies, or ``method="mckelvey1"`` off the equispaced grid.
    FrequencyDataError
        ``G`` not of shape (p, m, K), NaN or inf in it, or ``omega_d`` of another length than ``K``.
    OrderError
        Invalid Hankel sizes ``q``, ``r`` (or ``r`` given for Algorithm 2).
    """
    return hankel_svd(data, omega_d, method=method, q=q, r=r).sv


def _check_order(order: Any, svd: HankelSVD) -> int:
    if isinstance(order, bool) or not isinstance(order, (int, np.integer)):
        raise OrderError(f"order must be a positive integer, got {order!r}")
    n = int(order)
    if n < 1:
        raise OrderError(f"order must be >= 1, got {n}")
    if n > svd.max_order:
        lim = []
        if n >= svd.q:
            lim.append(f"order < q = {svd.q} block rows")
        if svd.r is not None and n > svd.r * svd.m:
            lim.append(f"order <= r m = {svd.r * svd.m}")
        if n > svd.sv.size:
            lim.append(f"order <= {svd.sv.size} singular values")
        fix = ("use more frequencies (larger M) or a lower order" if svd.method == "mckelvey1"
               else "increase q (up to 2 K m / (m + p)), add frequencies, or lower the order")
        raise OrderError(
            f"order {n} is beyond what the data support with {svd.method} (q={svd.q}, r={svd.r}): need "
            f"{' and '.join(lim) or f'order <= {svd.max_order}'}; the largest possible order is "
            f"{svd.max_order}; {fix}"
        )
    return n


def from_basis(svd: HankelSVD, order: int, *, warn: bool = True) -> SubspaceResult:
    """``A`` and ``C`` of one order from a precomputed :class:`HankelSVD` (cheap).

    Parameters
    ----------
    svd : HankelSVD
    order : int
        Model order ``n``, ``1 <= n <= svd.max_order``.
    warn : bool
        Warn (``RuntimeWarning``) when ``sv[n-1] <= 10 eps sv[0] max(U.shape)`` (round-off level): the data
        then support a lower order and the extra states are fitted to round-off.
    """
    n = _check_order(order, svd)
    s = svd.sv
    if warn and s[0] > 0 and s[n - 1] <= 10 * np.finfo(float).eps * s[0] * max(svd.U.shape):
        rank = int(np.sum(s > 10 * np.finfo(float).eps * s[0] * max(svd.U.shape)))
        warnings.warn(
            f"singular value {n} is at round-off level ({s[n - 1]:.3g} vs {s[0]:.3g}): the data support order "
            f"{rank}; the extra states are fitted to round-off",
            RuntimeWarning,
            stacklevel=2,
        )
    p = svd.p
    Us = svd.U[:, :n]
    gamma1 = Us[:-p]
    gamma2 = Us[p:]
    A = np.linalg.lstsq(gamma1, gamma2, rcond=None)[0]
    C = np.array(Us[:p])
    return SubspaceResult(A=A, C=C, singular_values=s, gamma1=gamma1, gamma2=gamma2,
                          q=svd.q, r=svd.r, order=n, method=svd.method)




def mckelvey1(G: Any, order: int, *, q: int | None = None, r: int | None = None) -> SubspaceResult:
    """McKelvey's Algorithm 1 on the equispaced grid ``omega_d = pi k / M``, ``k = 0..M``.

    Parameters
    ----------
    G : FrequencyResponse or array_like, complex, shape (p, m, M + 1)
        Samples on the grid (a FrequencyResponse must be equispaced).
    order : int
        Model order ``n < q``.
    q, r : int, optional
        Hankel block rows / columns, ``q + r <= 2M``; default ``q = min(M, 2n + 2)``, ``r = 2M - q``
        (:func:`default_q`).

    Returns
    -------
    SubspaceResult
        ``A`` (n, n) and ``C`` (p, n) of order ``n``, with the singular values and shift matrices.

    Raises
    ------
    FrequencyGridError
        A FrequencyResponse whose frequencies are not equispaced (use :func:`mckelvey2`) or without ``T``, or
        fewer than 2 frequencies.
    FrequencyDataError
        ``G`` not of shape (p, m, M + 1), or NaN or inf in it.
    OrderError
        ``order`` not a positive integer, ``order >= q`` or beyond the Hankel rank limit, or invalid ``q``, ``r``.
    """
    svd = hankel_svd(G, None, method="mckelvey1", q=q, r=r, order=order_hint(order))
    return from_basis(svd, order)


def mckelvey2(G: Any, omega_d: Any, order: int, *, q: int | None = None) -> SubspaceResult:
    """McKelvey's Algorithm 2 on arbitrary discrete frequencies.

    Parameters
    ----------
    G : array_like, complex, shape (p, m, K), or FrequencyResponse (then ``omega_d`` may be None)
        Frequency-response samples (``(K,)`` accepted for SISO).
    omega_d : array_like, shape (K,)
        Discrete frequencies in ``[0, pi]`` (rad/sample, distinct). ``None`` with a plain array assumes
        McKelvey's grid ``pi k / (K - 1)``.
    order : int
        Model order ``n < q``.
    q : int, optional
        Block rows; default in :func:`default_q`.

    Returns
    -------
    SubspaceResult
        ``A`` (n, n) and ``C`` (p, n) of order ``n``, with the singular values and shift matrices (``r = None``).

    Raises
    ------
    FrequencyGridError
        ``omega_d`` outside ``[0, pi]`` or not finite, a FrequencyResponse without ``T``, or (``omega_d=None``)
        fewer than 2 frequencies.
    FrequencyDataError
        ``G`` not of shape (p, m, K), NaN or inf in it, or ``omega_d`` of another length than ``K``.
    OrderError
        ``order`` not a positive integer or beyond what ``q`` supports, or ``q`` outside
        ``2 <= q <= 2 K m / (m + p)``.
    """
    svd = hankel_svd(G, omega_d, method="mckelvey2", q=q, order=order_hint(order))
    return from_basis(svd, order)


def subspace_identify(data: Any, order: int, *, omega_d: Any = None, method: str = "auto",
                      q: int | None = None, r: int | None = None) -> SubspaceResult:
    """``A`` and ``C`` by Algorithm 1 or 2 (``method="auto"``: 1 on the equispaced grid, else 2).

    Parameters
    ----------
    data : FrequencyResponse or array_like, complex, shape (p, m, K)
        Frequency response (``(K,)`` accepted for SISO). Plain arrays without ``omega_d`` are taken to lie on
        McKelvey's grid ``omega_d = pi k / M``, ``k = 0..M`` (``K = M + 1``).
    order : int
        Model order ``n``, ``1 <= n`` and within what the Hankel sizes support.
    omega_d : array_like, shape (K,), optional
        Discrete frequencies in ``[0, pi]`` (rad/sample), when ``data`` is an array.
    method : {"auto", "mckelvey1", "mckelvey2"}
        ``"auto"`` picks Algorithm 1 on the equispaced grid and Algorithm 2 otherwise.
    q, r : int, optional
        Hankel block rows and columns (``r``: Algorithm 1 only); defaults in :func:`default_q` for this order.

    Returns
    -------
    SubspaceResult
        ``A`` (n, n) and ``C`` (p, n), with the singular values and shift matrices.

    Raises
    ------
    OptionError
        Unknown ``method``.
    FrequencyGridError
        No ``omega_d`` (a FrequencyResponse without ``T``), ``omega_d`` outside ``[0, pi]`` or not finite, fewer
        than 2 frequencies, or ``method="mckelvey1"`` off the equispaced grid.
    FrequencyDataError
        ``G`` not of shape (p, m, K), NaN or inf in it, or ``omega_d`` of another length than ``K``.
    OrderError
        ``order`` not a positive integer or beyond what the data support, or invalid ``q``, ``r``.
    """
    return from_basis(hankel_svd(data, omega_d, method=method, q=q, r=r, order=order_hint(order)), order)


def order_hint(order: Any) -> int | None:
    """The order as a hint for the default Hankel sizes (:func:`default_q`).

    Parameters
    ----------
    order : any
        A requested model order, not yet checked.

    Returns
    -------
    int or None
        ``order`` when it is a positive integer, else None (an invalid order is refused later, with the data
        at hand to say why).
    """
    if isinstance(order, (int, np.integer)) and not isinstance(order, bool) and order >= 1:
        return int(order)
    return None
