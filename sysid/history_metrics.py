"""Errors of a model's time history against a reference one (e.g. a ROM's gust loads against the LTD march).

Loads engineers read a gust response by its envelope: its largest positive and its largest negative load.
For each output ``X`` compared (time convective, loads in the histories' units):

- ``peak_err_X = max(|max y_model - max y_ref|, |min y_model - min y_ref|) / max |y_ref|``: the larger error
  of the two extremes, relative to the reference's largest magnitude (so a history whose positive and
  negative extremes have nearly equal magnitudes is not judged by which of the two happens to be larger);
- ``t_peak_err_X = |t_peak_model - t_peak_ref|``: ``t_peak_ref`` is the time of the reference's largest
  magnitude (:func:`peak`), ``t_peak_model`` the time of the model's extreme of the same sign;
- ``rms_err_X = rms(y_model - y_ref) / rms(y_ref)``.
"""

from __future__ import annotations

from typing import Any, Mapping, Optional, Sequence

import numpy as np

from .errors import TimeDataError

__all__ = ["peak", "envelope_errors", "history_errors"]


def _histories(t, *ys, names=("y",)):
    """``t`` and the histories as 1-D float arrays of one length, finite; :class:`TimeDataError` otherwise."""
    arrays = []
    for name, a in zip(("t",) + tuple(names), (t,) + ys):
        try:
            x = np.asarray(a, dtype=float).reshape(-1)
        except (TypeError, ValueError):
            raise TimeDataError(f"{name} must be an array of numbers, got {a!r}"[:200]) from None
        bad = np.flatnonzero(~np.isfinite(x))
        if bad.size:
            raise TimeDataError(f"{name} contains NaN or inf at index {int(bad[0])}: its errors would be NaN; "
                                "repair or drop that sample")
        arrays.append(x)
    n = arrays[0].size
    if n == 0:
        raise TimeDataError("the histories are empty; give at least one time")
    for name, x in zip(names, arrays[1:]):
        if x.size != n:
            raise TimeDataError(f"{name} has {x.size} samples but t has {n} times; give one value per time")
    return arrays


def peak(t, y) -> tuple:
    """The signed extreme of a history and its time: ``(y[k], t[k])`` with ``k = argmax |y|``.

    Parameters
    ----------
    t, y : array_like, shape (n,)
        Time (convective) and the history.

    Returns
    -------
    tuple of float

    Raises
    ------
    TimeDataError
        Empty, NaN or inf, or ``t`` and ``y`` of different lengths.
    """
    t, y = _histories(t, y)
    k = int(np.argmax(np.abs(y)))
    return float(y[k]), float(t[k])


def envelope_errors(t, y_model, y_ref) -> tuple:
    """Errors of a history's load envelope: ``(peak_err, t_peak_err)`` (see the module docstring).

    Parameters
    ----------
    t : array_like, shape (n,)
        Time (convective).
    y_model, y_ref : array_like, shape (n,)
        The model's and the reference's history (finite).

    Returns
    -------
    peak_err : float
        ``max(|max y_model - max y_ref|, |min y_model - min y_ref|) / max |y_ref|``; ``inf`` when the
        reference is identically zero and the model is not, 0 when both are.
    t_peak_err : float
        Time between the reference's largest magnitude and the model's extreme of the same sign.

    Raises
    ------
    TimeDataError
        Histories of other lengths than ``t`` (a shorter one was compared silently), empty, NaN or inf.
    """
    t, ym, yr = _histories(t, y_model, y_ref, names=("y_model", "y_ref"))
    err = max(abs(ym.max() - yr.max()), abs(ym.min() - yr.min()))
    p_ref, t_ref = peak(t, yr)
    sign = 1.0 if p_ref >= 0.0 else -1.0
    t_model = float(t[int(np.argmax(sign * ym))])
    return _ratio(err, abs(p_ref)), abs(t_model - t_ref)


def history_errors(t, model: Mapping[str, Any], reference: Mapping[str, Any],
                   outputs: Optional[Sequence[str]] = None) -> dict:
    """Envelope and RMS errors of a model's histories against the reference ones (see the module docstring).

    Parameters
    ----------
    t : array_like, shape (n,)
        The common time grid (convective time).
    model, reference : mapping of output name -> array_like, shape (n,)
        Histories, e.g. ``{"Cl": cl, "Cm": cm}``.
    outputs : sequence of str, optional
        The outputs compared, in this order (each in both); default the model's outputs that the reference
        also has.

    Returns
    -------
    dict of str -> float
        ``peak_err_X``, ``t_peak_err_X``, ``rms_err_X`` per output compared: ``inf`` relative errors where the
        reference is identically zero and the model is not (0 where both are), and every error ``inf`` for an
        output whose model history is not finite (an unstable model overflowed).

    Raises
    ------
    TimeDataError
        ``model`` or ``reference`` not a mapping, a reference history that is not finite, a history of another length than ``t``, an output of
        ``outputs`` missing from either mapping, or (``outputs`` not given) no output in common.
    """
    for what, value in (("model", model), ("reference", reference)):
        if not (isinstance(value, Mapping) or (hasattr(value, "keys") and hasattr(value, "__getitem__"))):
            raise TimeDataError(f"{what} must be a mapping of output names to histories (e.g. {{'Cl': array}}), got "
                                f"{type(value).__name__}")
    if outputs is None:
        names = [n for n in model if n in reference]
        if not names:
            raise TimeDataError(f"the model's outputs {list(model)} and the reference's {list(reference)} have none "
                                "in common: nothing to compare")
    else:
        names = list(outputs)
        if not names:
            raise TimeDataError("outputs is empty: name at least one output to compare")
        missing = [n for n in names if n not in model or n not in reference]
        if missing:
            raise TimeDataError(f"outputs {missing} are not in both histories (model: {list(model)}, reference: "
                                f"{list(reference)})")
    out: dict = {}
    for name in names:
        ym = np.asarray(model[name], dtype=float).reshape(-1)
        t_arr, yr = _histories(t, reference[name], names=(f"reference[{name!r}]",))
        if ym.size != t_arr.size:
            raise TimeDataError(f"model[{name!r}] has {ym.size} samples but t has {t_arr.size} times")
        if not np.all(np.isfinite(ym)):  # an unstable model overflowed: its errors are infinite
            out.update({f"peak_err_{name}": float("inf"), f"t_peak_err_{name}": float("inf"),
                        f"rms_err_{name}": float("inf")})
            continue
        out[f"peak_err_{name}"], out[f"t_peak_err_{name}"] = envelope_errors(t, ym, yr)
        out[f"rms_err_{name}"] = _ratio(float(np.sqrt(np.mean((ym - yr) ** 2))), float(np.sqrt(np.mean(yr ** 2))))
    return out


def _ratio(num: float, den: float) -> float:
    if den > 0.0:
        return float(num / den)
    return 0.0 if num == 0.0 else float("inf")
