"""Checks of frequency-response data shared by the identification entry points (:func:`sysid.identify`,
:func:`sysid.fit_relocated`, the refits): weights, constraint values, all-zero channels.

Each raises a typed error (:mod:`sysid.errors`) that says what was wrong and what to do.
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np

from .errors import ConstraintError, FrequencyDataError

__all__ = ["check_weights", "check_constraint", "check_nonzero_outputs"]


def check_weights(weights: Any, p: int, m: int, K: int) -> np.ndarray | None:
    """``weights`` as a float array of shape ``(K,)`` or ``(p, m, K)``, finite and nonnegative (None stays None).

    Raises
    ------
    FrequencyDataError
        Another shape, NaN, inf or a negative weight.
    """
    if weights is None:
        return None
    w = np.asarray(weights, dtype=float)
    if w.shape not in ((K,), (p, m, K)):
        raise FrequencyDataError(f"weights must have shape (K,) = ({K},) or (p, m, K) = ({p}, {m}, {K}); "
                                 f"got {w.shape}.")
    if not np.all(np.isfinite(w)) or np.any(w < 0):
        raise FrequencyDataError("weights must be finite and nonnegative.")
    return w


def check_constraint(value: Any, name: str, p: int, m: int, z0: float) -> np.ndarray:
    """A constraint value ``G(z0)`` (``dc_gain`` at ``z0 = 1``, ``feedthrough`` at ``z0 = -1``) as a real
    ``(p, m)`` array (a scalar when ``p = m = 1``).

    Raises
    ------
    ConstraintError
        Complex, of another shape, NaN or inf.
    """
    v = np.asarray(value)
    if np.iscomplexobj(v):
        if np.abs(v.imag).max(initial=0.0) > 1e-12 * max(1.0, np.abs(v).max(initial=0.0)):
            raise ConstraintError(
                f"{name} must be real (G at z = {z0:+.0f} of a real system is real); got complex values. "
                "Pass its real part."
            )
        v = v.real
    v = np.asarray(v, dtype=float)
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
