"""Model-order selection: a sweep over ``N_r = 1..N_max`` from one SVD.

The subspace SVD (:func:`sysid.subspace.hankel_svd`) is computed once; the model of order ``n`` uses its
first ``n`` left singular vectors, so every order costs only a small least-squares problem for ``A``
(shift equation) and one for ``B``, ``D`` (closed form in NumPy, :func:`sysid.subspace.lstsq_bd`, no
constraints and no convex solver: this is a screening tool; refit the chosen order with
:func:`sysid.identify`).

Two suggestions are returned (see :class:`OrderSweep`):

- **gap rule** (``order_gap``): the order ``n`` with the largest drop ``log s_n - log s_{n+1}`` of the
  singular values, ``n = 1..N_max``. Sharp for (nearly) noise-free data of finite order; for responses of
  infinite order whose singular values decay smoothly (e.g. the Sears function of an aerofoil) it often
  picks a very low order, so prefer the hold-out rule there.
- **hold-out rule** (``order_holdout``): identify on the even-indexed frequencies only (a second SVD, of
  the half data set: on McKelvey's grid with even ``M`` that is again an equispaced grid with ``M/2``) and
  measure the RMS relative error on the odd-indexed ones. The suggestion is the *smallest* order whose
  hold-out error is within ``(1 + holdout_tol)`` times the best hold-out error plus ``holdout_atol``
  (defaults 10 % and 1e-10, so round-off-level differences of exact data do not favour spurious states).

``suggested`` is the hold-out order when the hold-out is computed, else the gap order.
"""

from __future__ import annotations

import time
import warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.linalg

from .arrays import freeze_array_fields
from .between import BETWEEN_MIN_ERROR, BETWEEN_RATIO, between_error
from .data_checks import check_fit_data, check_flag, check_tolerance
from .errors import OrderError
from .state_space import lstsq_bd_phi, modal_form, resolvent_C
from .subspace import HankelSVD, hankel_svd

__all__ = ["OrderSweep", "order_sweep"]


@dataclass(frozen=True)
class OrderSweep:
    """Result of :func:`order_sweep`; arrays are indexed by ``orders`` (``1..N_max``).

    Attributes
    ----------
    orders : ndarray of int, shape (N,)
    singular_values : ndarray, shape (k,)
        All singular values of the full-data SVD, decreasing (:attr:`sysid.subspace.HankelSVD.sv`:
        ``k = min(q p, r m)`` for Algorithm 1, ``q p`` for Algorithm 2; not limited to ``N``).
    max_error, rms_error : ndarray, shape (N,)
        Relative FRF errors of each order fitted to all data (definitions in :mod:`sysid.metrics`).
    between_error : ndarray, shape (N,)
        Estimated error between the samples of each order fitted to all data (:func:`sysid.between.between_error`,
        worst output); the hold-out rule passes over orders where it exceeds ``BETWEEN_RATIO`` times ``max_error``
        (and ``BETWEEN_MIN_ERROR``) while any other order is left (:data:`sysid.between.BETWEEN_RATIO`), unless the
        order it falls back on misses the held-out samples by more than the passed-over order is estimated off
        between them; it warns when the fallback misses them by more than twice that order (:func:`_keep_or_warn`).
    holdout_error : ndarray, shape (N,) or None
        RMS relative error on the odd-indexed frequencies of the model identified on the even-indexed ones
        (NaN where the half data set cannot support the order).
    spectral_radius : ndarray, shape (N,)
        Of each order's ``A`` (fitted to all data).
    order_gap, order_holdout : int, int or None
        Suggestions by the two rules (module docstring).
    suggested : int
    method : str
    q, r : int, int or None
    elapsed : float
        Wall time of the sweep in seconds.
    """

    orders: np.ndarray
    singular_values: np.ndarray = field(repr=False)
    max_error: np.ndarray = field(repr=False)
    rms_error: np.ndarray = field(repr=False)
    holdout_error: np.ndarray | None = field(repr=False)
    spectral_radius: np.ndarray = field(repr=False)
    order_gap: int
    order_holdout: int | None
    suggested: int
    method: str
    q: int
    r: int | None
    elapsed: float
    between_error: np.ndarray | None = field(default=None, repr=False)

    def __post_init__(self):
        freeze_array_fields(self)   # the arrays of a frozen result are read-only too

    def table(self) -> str:
        """Plain-text table: order, singular value, max/RMS error, hold-out error, spectral radius."""
        rows = ["order  sing.value   max_err     rms_err     holdout     between     rho"]
        for i, n in enumerate(self.orders):
            ho = self.holdout_error[i] if self.holdout_error is not None else np.nan
            bt = self.between_error[i] if self.between_error is not None else np.nan
            rows.append(f"{n:5d}  {self.singular_values[n - 1]:.3e}  {self.max_error[i]:.3e}  "
                        f"{self.rms_error[i]:.3e}  {ho:.3e}  {bt:.3e}  {self.spectral_radius[i]:.4f}")
        return "\n".join(rows)


def _sweep_errors(svd: HankelSVD, orders: np.ndarray, z_fit: np.ndarray, G_fit: np.ndarray,
                  z_val: np.ndarray | None, G_val: np.ndarray, with_between: bool = False):
    """For each order: A, C from the SVD, B, D by closed-form LS on (z_fit, G_fit), errors on (z_val, G_val).

    ``z_val=None`` validates on the fitting data. ``A`` for every order comes from ONE QR of
    ``Gamma1 = J1 U[:, :N]``: the leading ``n`` columns of a QR factorisation are the QR factorisation of
    the leading ``n`` columns, so ``A_n = R_n^-1 (Q^T J2 U)[:n, :n]``. Each order then needs one
    eigen-decomposition (reused for the fit, the validation and the spectral radius).
    """
    p = svd.p
    N = int(orders.max())
    nrm_val = max(np.linalg.norm(G_val), np.finfo(float).tiny)
    peak = np.maximum(np.abs(G_val).max(axis=(1, 2)), np.finfo(float).tiny)
    rms = np.full(orders.size, np.nan)
    mx = np.full(orders.size, np.nan)
    rho = np.full(orders.size, np.nan)
    between = np.full(orders.size, np.nan)
    readings = {}   # the samples' local readings, made once for all orders (sysid.between.sample_readings)
    Nmax = min(N, svd.max_order)
    Q, R = np.linalg.qr(svd.U[:-p, :Nmax])
    QtU2 = Q.T @ svd.U[p:, :Nmax]
    with np.errstate(all="ignore"):
        for i, n in enumerate(orders):
            if n > svd.max_order:
                continue
            A = scipy.linalg.solve_triangular(R[:n, :n], QtU2[:n, :n])
            C = svd.U[:p, :n]
            try:
                modal = modal_form(A, C)
                phi = resolvent_C(A, C, z_fit, modal)
                B, D = lstsq_bd_phi(phi, G_fit)
                if z_val is not None:
                    phi = resolvent_C(A, C, z_val, modal)
                dH = (phi @ B + D[None]).transpose(1, 2, 0) - G_val
                lam = modal[0] if modal else np.linalg.eigvals(A)
            except np.linalg.LinAlgError:
                continue
            rms[i] = np.linalg.norm(dH) / nrm_val
            mx[i] = np.max(np.abs(dH).max(axis=(1, 2)) / peak)
            rho[i] = np.max(np.abs(lam))
            if z_val is None and with_between:
                between[i] = np.max(between_error(A, B, C, D, np.abs(np.angle(z_fit)), G_fit, cache=readings))
    rms[~np.isfinite(rms)] = np.nan
    mx[~np.isfinite(mx)] = np.nan
    return mx, rms, rho, between


#: :func:`order_sweep` warns when the order it suggests has a hold-out error more than this many times that of the
#: order it passed over for not being pinned down between the samples.
UNPINNED_WARN_RATIO = 2.0


def _keep_or_warn(orders, ho_err, between, pinned, suggested, tol, atol) -> int:
    """The hold-out rule's order after passing over orders not pinned down between the samples, checked against
    the order the rule picks without that (``b``).

    The pass-over trades an order that follows the held-out samples for one whose estimated error between them is
    lower. It is undone when it cannot pay: when ``b``'s estimate between the samples is no larger than the
    suggestion's own hold-out error (exact data of a 3-state system on McKelvey's M = 16 grid: order 3 holds out to
    1e-15 and is estimated 0.0019 of the peak off between the samples, just over the ratio rule, against a hold-out
    error of 0.093 for the order-1 fallback). When it stands and the suggestion misses the held-out samples by more
    than :data:`UNPINNED_WARN_RATIO` times ``b``, no order is right - the samples are too sparse for the response
    (a 12-state system with 0.3 % noise on the M = 64 grid: order 2, hold-out 0.89, against 0.15 from order 12 up,
    whose estimate between the samples is 1.1 of the peak) - and it warns.

    Returns
    -------
    int
        The suggested order.
    """
    fin = np.isfinite(ho_err)
    best = np.min(ho_err[fin])
    i_b = int(np.argmax(fin & (ho_err <= (1.0 + tol) * best + atol)))   # the hold-out rule without the pass-over
    i_s = int(np.flatnonzero(orders == suggested)[0])
    if i_s == i_b or pinned[i_b]:   # (b pinned: nothing was passed over that the rule would have chosen)
        return suggested
    if np.isfinite(between[i_b]) and between[i_b] <= ho_err[i_s]:   # (NaN: b's full-data fit failed)
        return int(orders[i_b])
    if ho_err[i_s] > UNPINNED_WARN_RATIO * ho_err[i_b]:
        warnings.warn(
            f"order_sweep suggests order {suggested} (hold-out error {ho_err[i_s]:.3g}) because every order that "
            f"follows the held-out samples better, e.g. {int(orders[i_b])} ({ho_err[i_b]:.3g}), is estimated "
            f"{between[i_b]:.2g} of the peak off between the samples (sysid.between): the samples are too sparse for "
            f"this response, and no order is pinned down by them. Sample more densely where the response varies "
            f"fast; meanwhile order {int(orders[i_b])} follows the samples and order {suggested} does not",
            RuntimeWarning, stacklevel=3)
    return suggested


def order_sweep(
    frf: Any,
    max_order: int | None = None,
    *,
    method: str = "auto",
    q: int | None = None,
    r: int | None = None,
    holdout: bool = True,
    holdout_tol: float = 0.1,
    holdout_atol: float = 1e-10,
) -> OrderSweep:
    """Fit every order ``1..max_order`` from one SVD and suggest an order.

    Parameters
    ----------
    frf : FrequencyResponse
        Data with discrete frequencies ``omega_d``.
    max_order : int, optional
        Largest order swept; default ``min(40, largest order the data support)``.
    method : {"auto", "mckelvey1", "mckelvey2"}
        Subspace algorithm (see :func:`sysid.subspace.hankel_svd`).
    q, r : int, optional
        Hankel sizes for the full-data SVD; default for the target order ``max_order``
        (:func:`sysid.subspace.default_q`: ``q = min(M, 2 max_order + 2)``, ``r = 2M - q``). The hold-out
        SVD uses the defaults of the half data set.
    holdout : bool
        Compute the hold-out errors (even-indexed frequencies fit, odd-indexed validate).
    holdout_tol, holdout_atol : float
        Tolerances of the hold-out rule (module docstring).

    Returns
    -------
    OrderSweep

    Raises
    ------
    ArgumentTypeError, FrequencyGridError, FrequencyDataError
        Data :func:`sysid.identify` refuses (:func:`sysid.data_checks.check_fit_data`): not a
        :class:`FrequencyResponse`, no ``T``, a ``T`` whose ``2 / T`` lies more than 100 times outside the data's
        frequencies (:func:`sysid.grids.check_period_resolves`), a frequency twice, an output zero everywhere or
        of a magnitude whose squares overflow.
    OrderError
        ``max_order`` beyond what the data support.
    OptionError
        ``holdout`` not a bool, ``holdout_tol`` / ``holdout_atol`` negative or not finite.

    Warns
    -----
    RuntimeWarning
        ``2 / T`` more than 10 times outside the data's frequencies (as :func:`sysid.identify` warns); no order
        pinned down between the samples (module docstring).
    """
    t0 = time.perf_counter()
    check_fit_data(frf, "order_sweep")   # identify's checks: the sweep's errors were NaN where identify refuses
    check_flag(holdout, "holdout")
    holdout_tol = check_tolerance(holdout_tol, "holdout_tol", positive=False)
    holdout_atol = check_tolerance(holdout_atol, "holdout_atol", positive=False)
    if max_order is None:
        max_order = min(40, hankel_svd(frf, method=method, q=q, r=r).max_order)
    if isinstance(max_order, bool) or not isinstance(max_order, (int, np.integer)) or max_order < 1:
        raise OrderError(f"max_order must be a positive integer, got {max_order!r}")
    frf = frf.with_real_ends()   # as identify fits it (a real model cannot follow an imaginary part there)
    svd = hankel_svd(frf, method=method, q=q, r=r, order=int(max_order))
    G = np.asarray(frf.H)
    z = np.exp(1j * np.asarray(frf.omega_d))
    if max_order > svd.max_order:
        raise OrderError(
            f"max_order={max_order} is beyond what the data support with {svd.method} (q={svd.q}, r={svd.r}): "
            f"the largest order is {svd.max_order}; lower max_order or use more frequencies"
        )
    orders = np.arange(1, max_order + 1)
    mx, rms, rho, between = _sweep_errors(svd, orders, z, G, None, G, with_between=True)

    s = svd.sv
    floor = np.finfo(float).tiny
    logs = np.log(np.maximum(s[: max_order + 1], floor))
    if logs.size > max_order:
        gaps = logs[:max_order] - logs[1 : max_order + 1]
    else:  # no s_{N_max + 1}: the last order has no gap
        gaps = np.append(logs[:-1] - logs[1:], -np.inf)
    order_gap = int(np.argmax(gaps) + 1)

    ho_err = None
    order_ho = None
    if holdout:
        K = G.shape[2]
        even = np.arange(0, K, 2)
        odd = np.arange(1, K, 2)
        if odd.size and even.size >= 2:
            half = frf.take(even)
            ho_method = "mckelvey2" if method == "mckelvey2" else "auto"
            try:
                svd_h = hankel_svd(half, method=ho_method, order=int(max_order))
            except OrderError:
                svd_h = None
            if svd_h is not None:
                _, ho_err, _, _ = _sweep_errors(svd_h, orders, z[even], G[:, :, even], z[odd], G[:, :, odd])
                # orders whose estimated error between the samples is far above their error on them are not
                # suggested (when any other is left): the samples do not pin them down
                pinned = ~((between > BETWEEN_RATIO * mx) & (between > BETWEEN_MIN_ERROR))
                finite = np.isfinite(ho_err) & (pinned if np.any(np.isfinite(ho_err) & pinned) else True)
                if finite.any():
                    best = np.min(ho_err[finite])
                    ok = finite & (ho_err <= (1.0 + holdout_tol) * best + holdout_atol)
                    order_ho = _keep_or_warn(orders, ho_err, between, pinned, int(orders[np.argmax(ok)]), holdout_tol,
                                             holdout_atol)
    suggested = order_ho if order_ho is not None else order_gap
    return OrderSweep(
        orders=orders, singular_values=s, max_error=mx, rms_error=rms, holdout_error=ho_err, between_error=between,
        spectral_radius=rho, order_gap=order_gap, order_holdout=order_ho, suggested=suggested,
        method=svd.method, q=svd.q, r=svd.r, elapsed=time.perf_counter() - t0,
    )
