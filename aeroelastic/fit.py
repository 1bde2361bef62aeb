"""Fitting frequency-response data of a moving section with a state-space-realisable model.

Motion columns (inputs ``plunge``, ``pitch``) grow like ``omega^2`` at high frequency (apparent mass), so no
proper state-space model holds them. :func:`fit_motion` uses Roger's rational function approximation
(K. L. Roger, AGARD CP-228, 1977)::

    H(s) ~= M0 + M1 s + M2 s^2 + sum_j A_j s / (s + beta_j),      s = i omega  (U/c units)

- ``M0 = Re H(0)`` exactly when the data hold ``omega = 0`` (the static derivatives are kept; the lag terms
  vanish at ``s = 0``);
- for fixed lag roots ``beta_j > 0``, ``M1``, ``M2`` and the ``A_j`` are one real linear least-squares problem
  (convex), solved per entry of ``H`` with relative weights (each frequency's residual divided by
  ``max(|H_ij(omega)|, 0.01 max|H_ij|)``, so the small low-frequency values count as much as the large
  apparent-mass values);
- the ``beta_j`` (shared by all entries) are then optimised by variable projection
  (:func:`scipy.optimize.least_squares` on ``log beta``: the linear coefficients are eliminated at each step),
  starting from a geometric spread over the data's band, and bounded to ``[0.1 min(omega > 0), 2 max(omega)]``
  (:data:`ROOT_BAND`: a root far above the data is not determined by them, and the fit would use it with a huge
  residue as a second apparent mass, ``M2 - A_j / beta_j^2``, which spoils the coupled model's mass matrix; seen
  on CFD data). ``beta_j > 0`` by construction, so the lag part is stable whatever the data.

Why not :func:`sysid.identify` on the remainder ``H - M0 - M1 s - M2 s^2``: that needs ``M1`` and ``M2``
first, and estimating them from the high-frequency data alone is ill-conditioned (they are only the
asymptote); Roger's form finds them jointly with the lags in one convex problem, keeps the static derivatives
exactly and gives real stable poles, which is what flutter codes expect (Karpel's minimum-state form would
need fewer states but a non-convex fit). The gust column (proper: it decays at high frequency) is identified
with :func:`sysid.identify` (subspace + constrained least-squares refit of B, D with the exact DC gain by the
closed-form null-space solver, stability enforced) and converted to continuous time (paper Eq. 26).

The lag part is realised with two states per root (one per motion input)::

    x_j' = -beta_j x_j + q,      y_lag = sum_j A_j (q - beta_j x_j)      (' = d/ds, s convective)
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy import optimize

from sysid.arrays import read_only
from sysid.grids import period_factor, period_range

from .errors import AeroModelError, FitError

__all__ = ["MotionModel", "fit_motion", "channel_indices", "real_array", "MOTION_INPUTS", "LOAD_OUTPUTS", "ROOT_BAND",
           "T_BAND"]

MOTION_INPUTS = ("plunge", "pitch")
ROOT_BAND = (0.1, 2.0)
"""Optimised lag roots stay within ``[0.1 min(omega > 0), 2 max(omega)]`` of the data."""
LOAD_OUTPUTS = ("Cl", "Cm")



T_BAND = 100.0
"""How far (a factor) the bilinear map's centre frequency ``2 / T`` of the gust identification may lie outside the
data's positive frequencies. ``omega_d = 2 atan(omega T / 2)``: with ``2 / T`` a hundred times above the highest
frequency every sample lies below ``omega_d = 0.02`` rad (the model sees the DC gain alone), a hundred times below
the lowest one every sample lies within 0.02 rad of ``pi`` (the feedthrough alone); ``T = 1e-300`` was accepted."""


def _check_T(T, wpos):
    """``T`` (None or the gust identification's sampling period) checked: a positive finite number whose centre
    frequency ``2 / T`` lies within :data:`T_BAND` of the data's positive frequencies ``wpos``; else
    :class:`FitError` (the class a period sysid refused raised before)."""
    if T is None:
        return None
    try:
        Tf = float("nan") if isinstance(T, (bool, str, bytes)) else float(T)
    except (TypeError, ValueError):
        Tf = float("nan")
    if not (np.isfinite(Tf) and Tf > 0.0):
        raise FitError(f"T (sampling period of the gust identification, convective time) must be a positive "
                             f"finite number or None (default 2 / omega_mid), got {T!r}")
    if wpos.size and period_factor(Tf, wpos) > T_BAND:   # sysid's one rule for a period against a band
        raise FitError(f"T = {Tf:g} puts the bilinear map's centre frequency 2 / T = {2.0 / Tf:.3g} "
                             f"{'above' if 2.0 / Tf > wpos.max() else 'below'} the data's frequencies ({wpos.min():.3g} "
                             f"to {wpos.max():.3g}) by more than {T_BAND:g}x: the gust model would see "
                             f"{'the DC gain' if 2.0 / Tf > wpos.max() else 'the feedthrough'} alone; give T between "
                             f"{period_range(wpos, T_BAND)[0]:.3g} and {period_range(wpos, T_BAND)[1]:.3g}, or None "
                             f"(default {2.0 / np.sqrt(wpos.min() * wpos.max()):.3g})")
    return Tf


def _check_poles(poles, order):
    """Initial lag roots: a 1-D array of ``order`` positive finite numbers, else :class:`FitError`."""
    try:
        beta = np.asarray(poles, dtype=float)
    except (TypeError, ValueError):
        beta = None
    if beta is None or beta.ndim != 1 or beta.size != order or not np.all(np.isfinite(beta) & (beta > 0)):
        raise FitError(f"poles must be {order} positive lag roots (U/c), finite, in a 1-D array; got {poles!r}")
    return beta


def real_array(name, a):
    """``a`` as a float array if it holds real numbers, else :class:`AeroModelError` naming ``name``.

    Parameters
    ----------
    name : str
        The argument, for the message.
    a : array_like

    Returns
    -------
    ndarray of float
    """
    try:
        v = np.asarray(a)
    except (TypeError, ValueError):
        v = None
    if v is None or v.dtype.kind not in "biuf":
        kind = f"dtype {v.dtype}" if isinstance(v, np.ndarray) else type(a).__name__
        raise AeroModelError(f"{name} must be an array of real numbers, got {kind}")
    return v.astype(float)


def _check_real(name, a, shape):
    """``a`` as a float array if it is real, finite and of ``shape`` (None: any), else AeroModelError."""
    v = real_array(f"MotionModel.{name}", a)
    if shape is not None and v.shape != shape:
        raise AeroModelError(f"MotionModel.{name} must have shape {shape}, got {v.shape}")
    if not np.all(np.isfinite(v)):
        raise AeroModelError(f"MotionModel.{name} contains NaN or inf")
    return v


@dataclass(frozen=True)
class MotionModel:
    """Fitted aerodynamic model of the section's motion (and optionally gust), convective time.

    Attributes
    ----------
    M0, M1, M2 : ndarray, shape (2, 2)
        Polynomial part: stiffness, damping and apparent-mass matrices (outputs ``[Cl, Cm]``, inputs
        ``[plunge, pitch]``; ``M1`` per unit ``d/ds``, ``M2`` per unit ``d^2/ds^2``).
    poles : ndarray, shape (n_lags,)
        Lag roots ``beta_j > 0`` (U/c units); the lag poles are ``s = -beta_j``.
    residues : ndarray, shape (n_lags, 2, 2)
        ``A_j``.
    gust : control.StateSpace or None
        Continuous gust model (input ``gust``, outputs ``[Cl, Cm]``, time ``s = t U / c``), when the data had a
        ``"gust"`` input.
    static_exact : bool
        True when ``M0`` is the data's ``omega = 0`` value (imposed exactly).
    max_error, rms_error : float
        Motion fit errors over the data: ``|fit - data| / max(|data|, 0.01 max|data_ij|)``, max and RMS over
        entries and frequencies (an entry that is zero throughout is measured against ``1e-12`` of the largest).
    gust_max_error : float
        Max error of the gust model over the data relative to the peak of each output (``nan`` without gust, the
        default).
    omega : ndarray, shape (K,)
        Frequencies of the data fitted (U/c).
    gust_identification : sysid.IdentificationResult or None
        The identification of the gust column.
    """

    M0: np.ndarray
    M1: np.ndarray
    M2: np.ndarray
    poles: np.ndarray
    residues: np.ndarray
    gust: Any = field(default=None, repr=False)
    static_exact: bool = True
    max_error: float = float("nan")
    rms_error: float = float("nan")
    gust_max_error: float = float("nan")
    omega: np.ndarray = field(default=None, repr=False)
    gust_identification: Any = field(default=None, repr=False)

    def __post_init__(self):
        """Shapes and values checked once (a model built by hand reaches flutter and gust solvers unchecked
        otherwise): :class:`AeroModelError` naming the attribute."""
        for name in ("M0", "M1", "M2"):
            object.__setattr__(self, name, read_only(_check_real(name, getattr(self, name), (2, 2))))
        poles = _check_real("poles", self.poles, None)
        if poles.ndim != 1 or np.any(poles <= 0):
            raise AeroModelError(f"poles must be a 1-D array of positive lag roots beta_j (poles s = -beta_j); got "
                                 f"{np.array2string(poles, precision=4)}")
        object.__setattr__(self, "poles", read_only(poles))
        object.__setattr__(self, "residues", read_only(_check_real("residues", self.residues, (poles.size, 2, 2))))

    @property
    def n_lags(self) -> int:
        return int(self.poles.size)

    @property
    def has_gust(self) -> bool:
        return self.gust is not None

    def evaluate(self, omega: Any) -> np.ndarray:
        """Motion response of the model, shape (2, 2, K), at ``omega`` (U/c, finite)."""
        s = 1j * np.asarray(omega, dtype=float).reshape(-1)
        H = self.M0[:, :, None] + self.M1[:, :, None] * s + self.M2[:, :, None] * s**2
        for b, A in zip(self.poles, self.residues):
            H = H + A[:, :, None] * (s / (s + b))
        return H

    def evaluate_gust(self, omega: Any) -> np.ndarray:
        """Gust response of the model, shape (2, 1, K), at ``omega`` (U/c)."""
        if self.gust is None:
            raise AeroModelError("this model has no gust input; fit data with a 'gust' input")
        s = 1j * np.asarray(omega, dtype=float).reshape(-1)
        g = self.gust
        A, B, C, D = (np.asarray(x) for x in (g.A, g.B, g.C, g.D))
        n = A.shape[0]
        out = np.empty((C.shape[0], B.shape[1], s.size), dtype=complex)
        for i, si in enumerate(s):
            out[:, :, i] = C @ np.linalg.solve(si * np.eye(n) - A, B) + D
        return out

    def lag_model(self):
        """The lag part as a continuous :class:`control.StateSpace` (convective time), zero DC gain.

        Inputs ``[plunge, pitch]``, outputs ``[Cl, Cm]``; ``2 n_lags`` states; ``D = sum_j A_j``.
        """
        import control

        n = self.n_lags
        I2 = np.eye(2)
        if n == 0:
            return control.ss(np.zeros((0, 0)), np.zeros((0, 2)), np.zeros((2, 0)), np.zeros((2, 2)),
                              inputs=list(MOTION_INPUTS), outputs=list(LOAD_OUTPUTS))
        A = np.kron(np.diag(-self.poles), I2)
        B = np.kron(np.ones((n, 1)), I2)
        C = np.hstack([-b * R for b, R in zip(self.poles, self.residues)])
        D = self.residues.sum(axis=0)
        return control.ss(A, B, C, D, inputs=list(MOTION_INPUTS), outputs=list(LOAD_OUTPUTS))


def channel_indices(names, wanted, what):
    """Positions of the channels ``wanted`` among ``names``.

    Parameters
    ----------
    names : sequence of str
        The data's channel names (``frf.outputs`` or ``frf.inputs``).
    wanted : sequence of str
        The channels needed, in the order wanted.
    what : str
        ``"outputs"`` or ``"inputs"``, for the error message.

    Returns
    -------
    list of int
        ``len(wanted)`` indices into ``names``.

    Raises
    ------
    AeroModelError
        A wanted channel is missing.
    """
    names = list(names)
    missing = [w for w in wanted if w not in names]
    if missing:
        raise AeroModelError(
            f"the aerodynamic data need {what} {list(wanted)}, missing {missing} (have {names}); name the channels "
            "e.g. FrequencyResponse.from_continuous(H, omega, inputs=['gust', 'plunge', 'pitch'], outputs=['Cl', 'Cm'])"
        )
    return [names.index(w) for w in wanted]


def _basis(s: np.ndarray, beta: np.ndarray, with_m0: bool) -> np.ndarray:
    cols = ([np.ones_like(s)] if with_m0 else []) + [s, s**2] + [s / (s + b) for b in beta]
    return np.stack(cols, axis=1)  # (K, n_coef)


def _solve_entries(s, Hm, W, beta, M0):
    """Weighted LS for every entry with lag roots ``beta``; returns coefficients (2, 2, n_coef) and residuals."""
    with_m0 = M0 is None
    Phi = _basis(s, beta, with_m0)
    coef = np.empty((2, 2, Phi.shape[1]))
    res = []
    for i in range(2):
        for j in range(2):
            y = Hm[i, j] - (0.0 if with_m0 else M0[i, j])
            w = W[i, j][:, None]
            Ar = np.vstack([(w * Phi).real, (w * Phi).imag])
            br = np.concatenate([(W[i, j] * y).real, (W[i, j] * y).imag])
            c, *_ = np.linalg.lstsq(Ar, br, rcond=None)
            coef[i, j] = c
            res.append(Ar @ c - br)
    return coef, np.concatenate(res)


def fit_motion(frf, order: int = 4, *, gust_order: int = 8, T: float | None = None, optimise: bool = True,
               poles: Any = None) -> MotionModel:
    """Fit motion (and gust) frequency-response data with a state-space-realisable model.

    Parameters
    ----------
    frf : sysid.FrequencyResponse
        Continuous frequencies ``omega`` (U/c, finite; include ``omega = 0`` to keep the static derivatives
        exactly), outputs containing ``"Cl"`` and ``"Cm"`` (``Cm`` about the elastic axis), inputs containing
        ``"plunge"`` (``h / c`` up) and ``"pitch"`` (rad, nose up about the elastic axis), optionally
        ``"gust"``. See :func:`aeroelastic.change_axes` to bring quarter-chord data to the elastic axis.
    order : int
        Number of lag roots ``n_lags`` (``2 n_lags`` states); 0 gives the quasi-steady polynomial fit.
    gust_order : int
        State dimension of the gust model (:func:`sysid.identify`).
    T : float, optional
        Sampling period for the gust identification (the bilinear map only; the model returned is
        continuous). Default: ``2 / omega_mid`` with ``omega_mid`` the geometric middle of the positive data
        frequencies, which places the band's centre at ``omega_d = pi / 2``.
    optimise : bool
        Optimise the lag roots (variable projection); otherwise keep the initial (or given) roots.
    poles : array_like, shape (order,), optional
        Initial lag roots ``beta_j > 0`` (U/c).

    Returns
    -------
    MotionModel

    Raises
    ------
    AeroModelError
        Missing channels, no continuous frequencies, an ``inf`` frequency among the motion data, an ``optimise``
        that is not a bool.
    FitError
        Fewer frequencies than coefficients to fit; ``poles`` not ``order`` positive finite numbers in a 1-D array;
        a ``T`` that is not a positive finite number or whose ``2 / T`` lies more than :data:`T_BAND` times outside
        the data's positive frequencies (checked before any fit, for motion-only data too).
    """
    import sysid

    if not isinstance(frf, sysid.FrequencyResponse):
        raise AeroModelError(f"fit_motion() expects a sysid.FrequencyResponse, got {type(frf).__name__}")
    if frf.omega is None:
        raise AeroModelError("the data have no continuous frequencies; build them with FrequencyResponse.from_continuous")
    if isinstance(order, bool) or not isinstance(order, (int, np.integer)) or order < 0:
        raise FitError(f"order (number of lag roots) must be an integer >= 0, got {order!r}")
    if not isinstance(optimise, (bool, np.bool_)):
        raise AeroModelError(f"optimise must be True or False, got {optimise!r}")
    oi = channel_indices(frf.outputs, LOAD_OUTPUTS, "outputs")
    ii = channel_indices(frf.inputs, MOTION_INPUTS, "inputs")
    omega = np.asarray(frf.omega, dtype=float)
    finite = np.isfinite(omega)
    w = omega[finite]
    Hm = np.asarray(frf.H)[np.ix_(oi, ii)][:, :, finite]
    if not finite.all() and not np.allclose(np.asarray(frf.H)[np.ix_(oi, ii)][:, :, ~finite], 0):
        warnings.warn("the omega = inf sample of the motion columns is ignored (the motion response is unbounded there)",
                      RuntimeWarning, stacklevel=2)
    at0 = np.flatnonzero(w == 0.0)
    M0 = np.asarray(Hm[:, :, at0[0]].real) if at0.size else None
    n_coef = (0 if M0 is not None else 1) + 2 + order
    if 2 * w.size < n_coef + 1:
        raise FitError(f"{w.size} frequencies cannot determine {n_coef} real coefficients per entry; give more frequencies "
                       "or a lower order")
    if not np.any(Hm != 0):
        raise FitError("the motion data (Cl and Cm for plunge and pitch) are zero at every frequency: nothing to fit; "
                       "check the data's inputs and outputs")
    if order and not np.any(w > 0):
        raise FitError(f"{order} lag roots need data at positive frequencies; give some, or order=0")
    s = 1j * w
    peak = np.abs(Hm).max(axis=2, keepdims=True)
    # an entry that is zero throughout (e.g. the plunge column of static data) is weighted by the largest entry
    floor = np.maximum(0.01 * peak, 1e-12 * max(float(np.abs(Hm).max()), 1e-300))
    W = 1.0 / np.maximum(np.abs(Hm), floor)

    wpos = w[w > 0]
    T = _check_T(T, wpos) if "gust" in frf.inputs else _check_T(T, np.zeros(0))
    if poles is not None:
        beta = _check_poles(poles, order)
    elif order:
        lo = max(wpos.min(), 1e-3 * wpos.max()) if wpos.size else 0.05
        hi = wpos.max() if wpos.size else 1.0
        beta = np.geomspace(lo, 0.5 * hi, order + 2)[1:-1] if order else np.zeros(0)
    else:
        beta = np.zeros(0)
    if optimise and order:
        def resid(logb):
            return _solve_entries(s, Hm, W, np.exp(logb), M0)[1]

        # the roots stay in the data's band: a root far above the highest frequency is not determined by the data,
        # and the fit then uses it with a huge residue as a second apparent mass (M2 - A / beta^2), which ruins the
        # coupled model's mass matrix (seen on CFD data: roots at 1e2-1e4 for data to omega = 2)
        lo_b, hi_b = ROOT_BAND[0] * wpos.min(), ROOT_BAND[1] * wpos.max()
        x0 = np.clip(np.log(beta), np.log(lo_b) + 1e-9, np.log(hi_b) - 1e-9)
        sol = optimize.least_squares(resid, x0, method="trf", x_scale=1.0, max_nfev=200 * order,
                                     bounds=(np.log(lo_b), np.log(hi_b)))
        beta = np.sort(np.exp(sol.x))
    coef, _ = _solve_entries(s, Hm, W, beta, M0)
    k0 = 0
    if M0 is None:
        M0 = coef[:, :, 0]
        k0 = 1
    M1 = coef[:, :, k0]
    M2 = coef[:, :, k0 + 1]
    res = np.moveaxis(coef[:, :, k0 + 2:], 2, 0) if order else np.zeros((0, 2, 2))
    model = MotionModel(read_only(M0), read_only(M1), read_only(M2), read_only(beta), read_only(res),
                        static_exact=bool(at0.size), omega=read_only(w))
    err = np.abs(model.evaluate(w) - Hm) * W
    object.__setattr__(model, "max_error", float(err.max()))
    object.__setattr__(model, "rms_error", float(np.sqrt(np.mean(err**2))))

    if "gust" in frf.inputs:
        gi = frf.inputs.index("gust")
        Hg = np.asarray(frf.H)[np.ix_(oi, [gi])]
        if T is None:
            mid = np.sqrt(wpos.min() * wpos.max()) if wpos.size else 1.0
            T = 2.0 / mid
        # an output the gust does not reach (Cm about the quarter chord of a flat plate: a = -1/2) is a zero row
        # of the model, not data to identify
        live = np.abs(Hg).max(axis=(1, 2)) > 0.0
        if not live.any():
            raise FitError("the gust data are zero for Cl and Cm at every frequency: nothing to fit; drop the gust "
                           "column (flutter needs the motion columns only) or check the data")
        names = [o for o, keep in zip(LOAD_OUTPUTS, live) if keep]
        has_dc = bool(np.any(omega == 0.0))
        try:
            gfrf = sysid.FrequencyResponse.from_continuous(Hg[live], omega, T, inputs=["gust"], outputs=names)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)
                ident = sysid.identify(gfrf, gust_order, dc_gain="match" if has_dc else None, stable=True,
                                       solver="numpy")
        except (sysid.OrderError, sysid.FrequencyGridError, sysid.FrequencyDataError, sysid.ConstraintError,
                sysid.OptionError, sysid.SolverError) as e:
            raise FitError(f"the gust column cannot be fitted with gust_order = {gust_order!r} (T = {T!r}): {e}; "
                           "choose another gust_order (fewer states for fewer frequencies) or T") from None
        gc = ident.continuous()
        import control

        C = np.zeros((len(LOAD_OUTPUTS), gc.A.shape[0]))
        D = np.zeros((len(LOAD_OUTPUTS), 1))
        C[live], D[live] = np.asarray(gc.C), np.asarray(gc.D)
        gc = control.ss(gc.A, gc.B, C, D, inputs=["gust"], outputs=list(LOAD_OUTPUTS))
        object.__setattr__(model, "gust", gc)
        object.__setattr__(model, "gust_identification", ident)
        Hgf = model.evaluate_gust(w)
        gpk = np.maximum(np.abs(Hg[:, :, finite]).max(axis=2, keepdims=True), np.finfo(float).tiny)
        object.__setattr__(model, "gust_max_error", float((np.abs(Hgf - Hg[:, :, finite]) / gpk).max()))
    return model
