"""Error metrics for identified models against frequency-response data.

Relative errors are normalised per output channel, so that they stay meaningful where the response
itself is small (e.g. the zero feedthrough at ``omega = inf``, where a pointwise relative error would
divide by zero):

- ``max_rel[i] = max_{j,k} |H_model[i,j,k] - H[i,j,k]| / max_{j,k} |H[i,j,k]|``  (peak-normalised);
- ``rms_rel[i] = sqrt(mean_{j,k} |dH[i,j,k]|^2) / sqrt(mean_{j,k} |H[i,j,k]|^2)`` (energy-normalised);

and the overall values are ``max_i max_rel[i]`` and ``||dH||_F / ||H||_F``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .arrays import freeze_array_fields
from .errors import FrequencyDataError, FrequencyIndexError, ModelError

__all__ = ["FitErrors", "frf_errors", "max_relative_error", "rms_relative_error", "dc_error", "spectral_radius",
           "rom_metrics"]


def _refuse_nan(a: np.ndarray, name: str, *, inf: bool = False) -> None:
    """:class:`FrequencyDataError` naming the first NaN (and, with ``inf``, inf) of ``a``."""
    bad = np.isnan(a) | (np.isinf(a) if inf else False)
    if bad.any():
        k = tuple(int(x) for x in np.argwhere(bad)[0])
        what = "NaN" if np.isnan(a[k]) else "inf"
        raise FrequencyDataError(f"{name} contains {what} (first at {list(k)}): an error of it would be "
                                 f"{what}; {'the model overflowed or holds NaN: check its matrices' if name in ('H_model', 'dc_model') else 'repair or drop that sample'}")


def _pair(H_model, H_data):
    """``(Hm, Hd, s)``: both as complex (p, m, K) arrays divided by ``s``, shape (p, 1, 1), each output's peak of
    the data (of the model where the data are zero), so that no square below overflows or underflows."""
    try:
        Hm = np.asarray(H_model, dtype=complex)
        Hd = np.asarray(H_data, dtype=complex)
    except (TypeError, ValueError):
        raise FrequencyDataError("H_model and H_data must be arrays of numbers, shape (p, m, K) or (K,); got "
                                 f"{type(H_model).__name__} and {type(H_data).__name__}") from None
    if Hm.ndim == 1:
        Hm = Hm.reshape(1, 1, -1)
    if Hd.ndim == 1:
        Hd = Hd.reshape(1, 1, -1)
    if Hm.shape != Hd.shape:
        raise FrequencyDataError(f"H_model has shape {Hm.shape} but H_data has shape {Hd.shape}; they must match")
    if Hd.ndim != 3 or Hd.shape[2] == 0 or Hd.shape[0] == 0:
        raise FrequencyDataError(f"H_model and H_data must have shape (p, m, K) with p >= 1 and K >= 1 frequencies "
                                 f"(or (K,)); got {Hd.shape}")
    _refuse_nan(Hm, "H_model")
    _refuse_nan(Hd, "H_data", inf=True)
    return Hm, Hd


def _scaled(Hm: np.ndarray, Hd: np.ndarray, axis) -> tuple[np.ndarray, np.ndarray]:
    """Both divided by the data's peak over ``axis`` (the model's where the data are zero; 1 where both are):
    the relative errors are unchanged and no square overflows or underflows (data of 1e200 gave rms nan)."""
    s = np.abs(Hd).max(axis=axis, keepdims=True) if Hd.size else np.ones((1, 1, 1))
    with np.errstate(invalid="ignore"):
        sm = np.abs(Hm).max(axis=axis, keepdims=True) if Hm.size else s
    s = np.where(s > 0, s, np.where(np.isfinite(sm) & (sm > 0), sm, 1.0))
    with np.errstate(invalid="ignore"):   # inf / s in complex arithmetic: inf + nan j, whose modulus is inf
        return Hm / s, Hd / s


@dataclass(frozen=True)
class FitErrors:
    """FRF error summary.

    Attributes
    ----------
    max_rel : float
        Largest peak-normalised error over all outputs.
    rms_rel : float
        ``||H_model - H||_F / ||H||_F`` over all samples.
    max_rel_per_output, rms_rel_per_output : ndarray, shape (p,)
    """

    max_rel: float
    rms_rel: float
    max_rel_per_output: np.ndarray
    rms_rel_per_output: np.ndarray

    def __post_init__(self):
        freeze_array_fields(self)   # the arrays of a frozen result are read-only too


def max_relative_error(H_model, H_data, *, per_output: bool = False):
    """Peak-normalised max error (see module docstring).

    Parameters
    ----------
    H_model, H_data : array_like, complex, shape (p, m, K)
        Model and data responses at the same ``K`` frequencies (``(K,)`` accepted for SISO); same shape.
    per_output : bool
        Return the error of each output instead of the largest one (default False).

    Returns
    -------
    float or ndarray, shape (p,)
        ``per_output=False``: the scalar ``max_i max_rel[i]``; ``per_output=True``: ``max_rel[i]`` per output.

    Raises
    ------
    FrequencyDataError
        ``H_model`` and ``H_data`` differ in shape, are empty or not numbers, either contains NaN, or ``H_data``
        contains inf (an inf in ``H_model``, a pole on the sampled axis, is an infinite error; so is a nonzero
        model where an output's data are zero at every frequency, and 0 where both are). The errors are computed on both arrays
        divided by each output's peak, so data of any magnitude representable in floating point give the same
        relative errors (1e200 and 1e-200 gave NaN and 0).
    """
    Hm, Hd = _scaled(*_pair(H_model, H_data), axis=(1, 2))
    err = np.abs(Hm - Hd).max(axis=(1, 2))
    per = _relative(err, np.abs(Hd).max(axis=(1, 2)))
    return per if per_output else float(per.max())


def rms_relative_error(H_model, H_data, *, per_output: bool = False):
    """Energy-normalised RMS error (see module docstring).

    Parameters
    ----------
    H_model, H_data : array_like, complex, shape (p, m, K)
        Model and data responses at the same ``K`` frequencies (``(K,)`` accepted for SISO); same shape.
    per_output : bool
        Return the error of each output instead of the overall one (default False).

    Returns
    -------
    float or ndarray, shape (p,)
        ``per_output=False``: the scalar ``||H_model - H_data||_F / ||H_data||_F`` over all samples (not the
        largest per-output value); ``per_output=True``: ``rms_rel[i]`` per output.

    Raises
    ------
    FrequencyDataError
        ``H_model`` and ``H_data`` differ in shape, are empty or not numbers, either contains NaN, or ``H_data``
        contains inf (an inf in ``H_model``, a pole on the sampled axis, is an infinite error; so is a nonzero
        model where an output's data are zero at every frequency, and 0 where both are). The errors are computed on both arrays
        divided by each output's peak, so data of any magnitude representable in floating point give the same
        relative errors (1e200 and 1e-200 gave NaN and 0).
    """
    Hm, Hd = _pair(H_model, H_data)
    if per_output:
        Hm, Hd = _scaled(Hm, Hd, axis=(1, 2))
        num = np.sqrt(np.mean(np.abs(Hm - Hd) ** 2, axis=(1, 2)))
        return _relative(num, np.sqrt(np.mean(np.abs(Hd) ** 2, axis=(1, 2))))
    Hm, Hd = _scaled(Hm, Hd, axis=None)
    num = np.sqrt(np.sum(np.abs(Hm - Hd) ** 2))   # not np.linalg.norm: it gives nan for an inf entry
    return float(_relative(np.array([num]), np.array([np.sqrt(np.sum(np.abs(Hd) ** 2))]))[0])


def _relative(err: np.ndarray, scale: np.ndarray) -> np.ndarray:
    """``err / scale``, with ``inf`` where the data are zero and the model is not and 0 where both are (as
    :func:`sysid.history_metrics.envelope_errors`; dividing by the smallest double gave 4.5e307)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(scale > 0, err / np.where(scale > 0, scale, 1.0), np.where(err > 0, np.inf, 0.0))


def frf_errors(H_model, H_data) -> FitErrors:
    """All FRF error metrics at once.

    Parameters
    ----------
    H_model, H_data : array_like, complex, shape (p, m, K)
        Model and data responses at the same ``K`` frequencies (``(K,)`` accepted for SISO); same shape.

    Returns
    -------
    FitErrors
        Overall :func:`max_relative_error` and :func:`rms_relative_error` (floats) and their per-output
        values (shape (p,)).

    Raises
    ------
    FrequencyDataError
        ``H_model`` and ``H_data`` differ in shape, are empty or not numbers, either contains NaN, or ``H_data``
        contains inf (an inf in ``H_model``, a pole on the sampled axis, is an infinite error; so is a nonzero
        model where an output's data are zero at every frequency, and 0 where both are). The errors are computed on both arrays
        divided by each output's peak, so data of any magnitude representable in floating point give the same
        relative errors (1e200 and 1e-200 gave NaN and 0).
    """
    return FitErrors(
        max_rel=max_relative_error(H_model, H_data),
        rms_rel=rms_relative_error(H_model, H_data),
        max_rel_per_output=max_relative_error(H_model, H_data, per_output=True),
        rms_rel_per_output=rms_relative_error(H_model, H_data, per_output=True),
    )


def dc_error(dc_model, dc_data, *, relative: bool = True) -> float:
    """Max error of the DC gain, ``max |G_model(1) - G_data(0)|``.

    Parameters
    ----------
    dc_model, dc_data : array_like, shape (p, m)
        DC gains of the model (``z = 1``) and of the data (``omega = 0``); same shape.
    relative : bool
        Divide by ``max |dc_data|`` (when it is nonzero; default True).

    Returns
    -------
    float
        The max abs error, relative to ``max |dc_data|`` when ``relative`` and that is nonzero, else absolute;
        0.0 for empty arrays.

    Raises
    ------
    FrequencyDataError
        ``dc_model`` and ``dc_data`` differ in shape, either contains NaN or ``dc_data`` contains inf.
    """
    a = np.asarray(dc_model)
    b = np.asarray(dc_data)
    if a.shape != b.shape:
        raise FrequencyDataError(f"dc_model has shape {a.shape} but dc_data has shape {b.shape}")
    _refuse_nan(a, "dc_model")
    _refuse_nan(b, "dc_data", inf=True)
    err = float(np.abs(a - b).max()) if a.size else 0.0
    if relative:
        scale = float(np.abs(b).max()) if b.size else 0.0
        return err / scale if scale > 0 else err
    return err


def spectral_radius(A) -> float:
    """Largest eigenvalue modulus of ``A``.

    Parameters
    ----------
    A : array_like, shape (n, n)
        State matrix (discrete: the model is stable when the result is ``< 1``).

    Returns
    -------
    float
        ``max |eig(A)|``; 0.0 for an empty matrix.

    Raises
    ------
    ModelError
        ``A`` not square or containing NaN or inf (numpy's LinAlgError before).
    """
    A = np.asarray(A)
    if A.ndim != 2 or A.shape[0] != A.shape[1]:
        raise ModelError(f"A must be a square (n, n) matrix, got shape {A.shape}")
    if not np.all(np.isfinite(A)):
        raise ModelError("A contains NaN or inf: its spectral radius is undefined; repair the model")
    return float(np.max(np.abs(np.linalg.eigvals(A)))) if A.size else 0.0


def rom_metrics(frf_rom, H, fit_index, outputs, dc_model, spectral_radius: float, seconds: float) -> dict:
    """Metrics of one identified ROM against the frequency response it was identified from.

    Parameters
    ----------
    frf_rom : array_like, complex, shape (p, 1, K)
        ROM on the base grid (``K = M_base + 1``).
    H : array_like, complex, shape (p, 1, K)
        Reference response on the base grid (``H[:, :, 0]`` at ``omega = 0``).
    fit_index : array_like of int, shape (M + 1,)
        Indices into the ``K`` base-grid points (each in ``[0, K)``) of the ``M + 1`` points identified from.
    outputs : sequence of str
        Names of the ``p`` outputs.
    dc_model : array_like, shape (p, 1)
        ``G_rom(z = 1)``.
    spectral_radius : float
        Of the discrete ROM.
    seconds : float
        Identification time (s).

    Returns
    -------
    dict of str -> float or bool
        In this order: ``frf_max_err_X``, ``frf_rms_err_X`` per output ``X`` (:func:`max_relative_error`,
        :func:`rms_relative_error` on all ``K`` points); ``frf_max_err_fit``, ``frf_rms_err_fit`` (overall, on
        the points of ``fit_index``); ``dc_err_X = |G_rom(1) - H(0)|`` (absolute, per radian);
        ``spectral_radius``, ``stable`` (``spectral_radius < 1``) and ``seconds``.

    Raises
    ------
    FrequencyDataError
        Not one name per output, shapes that differ, NaN (as :func:`frf_errors`).
    FrequencyIndexError
        ``fit_index`` outside ``0 .. K-1`` or not whole numbers.
    """
    Hm = np.asarray(frf_rom, dtype=complex)
    Hd = np.asarray(H, dtype=complex)
    outputs = list(outputs)
    if Hd.ndim != 3 or len(outputs) != Hd.shape[0]:
        raise FrequencyDataError(f"{len(outputs)} output names for H of shape {Hd.shape}: give one name per output "
                                 "(H has shape (p, 1, K))")
    idx = np.asarray(fit_index)
    if idx.size and (idx.dtype.kind not in "iu" or idx.min() < 0 or idx.max() >= Hd.shape[2]):
        raise FrequencyIndexError(f"fit_index must hold whole numbers in 0 .. {Hd.shape[2] - 1} (the base grid's "
                                  f"K = {Hd.shape[2]} points), got {fit_index!r}"[:300])
    mx = max_relative_error(Hm, Hd, per_output=True)
    rms = rms_relative_error(Hm, Hd, per_output=True)
    out: dict = {}
    for i, name in enumerate(outputs):
        out[f"frf_max_err_{name}"] = float(mx[i])
        out[f"frf_rms_err_{name}"] = float(rms[i])
    idx = np.asarray(fit_index, dtype=int)
    out["frf_max_err_fit"] = max_relative_error(Hm[:, :, idx], Hd[:, :, idx])
    out["frf_rms_err_fit"] = rms_relative_error(Hm[:, :, idx], Hd[:, :, idx])
    dc = np.asarray(dc_model, dtype=float).reshape(len(outputs), -1)
    for i, name in enumerate(outputs):
        out[f"dc_err_{name}"] = float(np.abs(dc[i, 0] - Hd[i, 0, 0].real))
    out["spectral_radius"] = float(spectral_radius)
    out["stable"] = bool(spectral_radius < 1.0)
    out["seconds"] = float(seconds)
    return out
