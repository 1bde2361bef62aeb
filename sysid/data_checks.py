"""Checks of frequency-response data shared by the identification entry points (:func:`sysid.identify`,
:func:`sysid.fit_relocated`, the refits): weights, constraint values, all-zero channels, the data's magnitude,
flags that must be booleans.

Each raises a typed error (:mod:`sysid.errors`) that says what was wrong and what to do.
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np

from .errors import ArgumentTypeError, ConstraintError, FrequencyDataError, FrequencyGridError, OptionError

__all__ = ["check_weights", "check_constraint", "check_nonzero_outputs", "check_flag", "check_data_scale",
           "check_fit_data", "check_tolerance", "MAX_DATA_SCALE"]

MAX_DATA_SCALE = 1e150
"""Largest peak magnitude of an output (and ``1 / MAX_DATA_SCALE`` the smallest nonzero one) that the
identification takes (:func:`check_data_scale`). Its fits square the samples (least squares, the Hankel
products, the Gram matrices of the Gauss-Newton steps), and squares overflow beyond about 1.3e154: data scaled
by 1e200 or with a DC value of 1e300 gave ``rms_error = nan`` with numpy overflow warnings, while 1e-150 ..
1e150 fit to round-off (tests/sysid/test_identify.py). The relative errors and the model's poles do not depend
on the outputs' units, so dividing an output by a unit scale and multiplying the model's ``C`` and ``D`` rows
back loses nothing."""


def check_flag(value: Any, name: str) -> bool:
    """``value`` as a bool; :class:`OptionError` naming ``name`` unless it is ``True`` or ``False`` (NumPy's
    booleans included). ``stable="no"`` imposed stability because any truthy value did."""
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    raise OptionError(f"{name} must be True or False, got {value!r}")


def check_tolerance(value, name: str, *, positive: bool = True) -> float:
    """``value`` as a float, or :class:`OptionError` naming ``name`` unless it is a finite number ``> 0`` (``>= 0``
    when not ``positive``): ``tol=-1`` and ``rtol=nan`` were accepted by the refits, ``holdout_tol=nan`` by
    ``order_sweep``."""
    if isinstance(value, (bool, np.bool_)) or np.ndim(value) != 0 or np.asarray(value).dtype.kind not in "iuf" \
            or not np.isfinite(value) or (value <= 0 if positive else value < 0):
        raise OptionError(f"{name} must be a finite number {'> 0' if positive else '>= 0'}; got {value!r}.")
    return float(value)


def check_data_scale(H: Any, outputs: Sequence[str] | None = None) -> None:
    """Raise :class:`FrequencyDataError` when an output's peak ``max |H[i]|`` lies outside
    ``[1 / MAX_DATA_SCALE, MAX_DATA_SCALE]`` (zero outputs are left to :func:`check_nonzero_outputs`).

    Parameters
    ----------
    H : array_like, shape (p, m, K)
    outputs : sequence of str, optional
        Output names for the message.
    """
    peak = np.abs(np.asarray(H)).max(axis=(1, 2))
    bad = np.flatnonzero((peak > MAX_DATA_SCALE) | ((peak > 0) & (peak < 1.0 / MAX_DATA_SCALE)))
    if bad.size:
        i = int(bad[0])
        label = f"output {outputs[i]!r}" if outputs is not None else f"output {i}"
        raise FrequencyDataError(
            f"{label} has a peak |H| of {peak[i]:.3g}, outside {1.0 / MAX_DATA_SCALE:g} .. {MAX_DATA_SCALE:g} "
            "(sysid.data_checks.MAX_DATA_SCALE), where the fit's squares overflow or underflow; divide that output "
            f"by a unit scale (e.g. frf.replace(H=H / s) with s = {peak[i]:.3g} for it) and multiply the model's C "
            "and D rows by s afterwards: the relative errors and the poles do not depend on the scale")


def check_weights(weights: Any, p: int, m: int, K: int, outputs: Sequence[str] | None = None) -> np.ndarray | None:
    """``weights`` as a float array of shape ``(K,)`` or ``(p, m, K)``, finite and nonnegative, not zero
    everywhere nor for a whole output (None stays None).

    Raises
    ------
    FrequencyDataError
        Another shape, complex values, NaN, inf or a negative weight; weights that are zero at every frequency (of all outputs,
        or of one: that output would be fitted to nothing; ``np.zeros(K)`` raised cvxpy's "Parameter value must
        be real").
    """
    if weights is None:
        return None
    if np.iscomplexobj(weights):
        wc = np.asarray(weights)
        if np.abs(wc.imag).max(initial=0.0) > 1e-12 * np.abs(wc).max(initial=0.0):   # round-off, as check_constraint
            raise FrequencyDataError("weights must be real and nonnegative (they multiply the squared residuals); "
                                     "got complex values, whose imaginary part would be dropped")
        weights = wc.real   # e.g. H * H.conj(): complex type, real values (to 1e-16)
    try:
        w = np.asarray(weights, dtype=float)
    except (TypeError, ValueError):
        raise FrequencyDataError(f"weights must be an array of numbers, got {weights!r}") from None
    if w.shape not in ((K,), (p, m, K)):
        raise FrequencyDataError(f"weights must have shape (K,) = ({K},) or (p, m, K) = ({p}, {m}, {K}); "
                                 f"got {w.shape}.")
    if not np.all(np.isfinite(w)) or np.any(w < 0):
        raise FrequencyDataError("weights must be finite and nonnegative.")
    if not np.any(w > 0):
        raise FrequencyDataError("weights are zero at every frequency: there is nothing to fit; give positive "
                                 "weights where the data count (e.g. 1 / sigma^2), or pass weights=None")
    if w.ndim == 3:
        rows = np.flatnonzero(~np.any(w > 0, axis=(1, 2)))
        if rows.size:
            i = int(rows[0])
            label = f"output {outputs[i]!r}" if outputs is not None else f"output {i}"
            raise FrequencyDataError(f"weights of {label} are zero at every frequency: that output would be fitted "
                                     "to nothing; give it positive weights or drop the output")
    return w


def check_constraint(value: Any, name: str, p: int, m: int, z0: float) -> np.ndarray:
    """A constraint value ``G(z0)`` (``dc_gain`` at ``z0 = 1``, ``feedthrough`` at ``z0 = -1``) as a real
    ``(p, m)`` array (a scalar when ``p = m = 1``).

    Raises
    ------
    ConstraintError
        Complex, not numbers, of another shape, NaN or inf.
    """
    v = np.asarray(value)
    if np.iscomplexobj(v):
        if np.abs(v.imag).max(initial=0.0) > 1e-12 * max(1.0, np.abs(v).max(initial=0.0)):
            raise ConstraintError(
                f"{name} must be real (G at z = {z0:+.0f} of a real system is real); got complex values. "
                "Pass its real part."
            )
        v = v.real
    try:
        v = np.asarray(v, dtype=float)
    except (TypeError, ValueError):
        raise ConstraintError(f"{name} must be an array of real numbers of shape (p, m) = ({p}, {m}); got "
                              f"{value!r}"[:300]) from None
    if v.ndim == 0 and p == 1 and m == 1:
        v = v.reshape(1, 1)
    if v.shape != (p, m):
        raise ConstraintError(f"{name} must have shape (p, m) = ({p}, {m}); got {v.shape}.")
    if not np.all(np.isfinite(v)):
        raise ConstraintError(f"{name} contains NaN or inf.")
    return v


def check_nonzero_outputs(G: Any, outputs: Sequence[str] | None = None, *, per_input: bool = False) -> None:
    """Raise :class:`FrequencyDataError` when an output is zero at every frequency (its relative errors and the
    per-output scaling of the fits would divide by zero).

    Parameters
    ----------
    G : array_like, shape (p, m, K)
    outputs : sequence of str, optional
        Output names for the message (default ``"output i"``).
    per_input : bool
        Also refuse one output's response to one input that is zero at every frequency (the pole relocation
        fits each input column on its own).
    """
    G = np.asarray(G)
    zero = ~np.any(G != 0, axis=2)  # (p, m)
    label = (lambda i: f"output {outputs[i]!r}") if outputs is not None else (lambda i: f"output {i}")
    rows = np.flatnonzero(zero.all(axis=1))
    if rows.size:
        raise FrequencyDataError(f"{label(int(rows[0]))} is zero at every frequency; drop it (there is nothing to "
                                 "fit, and its relative error is undefined)")
    if per_input and zero.any():
        i, j = (int(x) for x in np.argwhere(zero)[0])
        raise FrequencyDataError(f"the response of {label(i)} to input {j} is zero at every frequency; the pole "
                                 "relocation fits each input column on its own: drop that pair or use "
                                 "algorithm='subspace'")


def check_fit_data(frf: Any, who: str) -> None:
    """The checks every fit of a :class:`sysid.FrequencyResponse` makes before any work (:func:`sysid.identify`,
    :func:`sysid.order_sweep`): its type, a period ``T`` that resolves the data's frequencies, distinct
    frequencies, no output zero everywhere, every output's magnitude within :data:`MAX_DATA_SCALE`.

    Parameters
    ----------
    frf : sysid.FrequencyResponse
    who : str
        The calling function's name, for the messages (``"identify"``).

    Raises
    ------
    ArgumentTypeError
        ``frf`` is not a :class:`sysid.FrequencyResponse`.
    FrequencyGridError
        No ``T``, a ``T`` that does not resolve the frequencies, or a frequency given twice.
    FrequencyDataError
        An output zero at every frequency, or one whose peak is outside ``1 / MAX_DATA_SCALE .. MAX_DATA_SCALE``.
    """
    from .frd import FrequencyResponse
    from .grids import check_distinct, check_period_resolves

    if not isinstance(frf, FrequencyResponse):
        raise ArgumentTypeError(f"{who}() expects a sysid.FrequencyResponse, got {type(frf).__name__}")
    if frf.T is None or frf.omega_d is None:
        raise FrequencyGridError(
            f"{who}() needs the sampling period T to place the data on the unit circle "
            "(omega_d = 2 arctan(omega T / 2)); build the data with a T, e.g. "
            "FrequencyResponse.from_continuous(H, omega, T) or frf.with_T(T)"
        )
    if frf.omega is not None:   # before the distinct check: T = 1e300 sends every sample to omega_d = pi
        check_period_resolves(frf.T, frf.omega)   # T = 1e-300 sent every sample to z = 1
    check_distinct(frf.omega_d, "omega_d")
    check_nonzero_outputs(frf.H, frf.outputs)
    check_data_scale(frf.H, frf.outputs)
