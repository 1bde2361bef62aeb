"""Plot input checks and the frequency axes of the figures: :class:`PlotDataError`, the reduced frequency, unwrapped
phases and the model entries that the ``*_plot`` functions of :mod:`studies.report.plots` take."""

from __future__ import annotations

from typing import Mapping

import numpy as np

__all__ = ["PlotDataError", "reduced_frequency", "unwrapped_phase_deg", "model_items", "model_entry"]


class PlotDataError(ValueError):
    """Arrays given to a plot do not fit together (shapes, lengths, empty data)."""


def reduced_frequency(omega) -> np.ndarray:
    """``k = omega / 2`` (``omega`` in ``U / c``; ``inf`` stays ``inf``)."""
    return np.asarray(omega, dtype=float) / 2.0


def unwrapped_phase_deg(H, like=None) -> np.ndarray:
    """Phase of ``H`` (last axis = frequency) in degrees, unwrapped along frequency.

    Unwrapping assumes the phase changes by less than 180 degrees between neighbouring samples; a coarse grid
    at high frequency (McKelvey's grid near ``omega_d = pi``) with a large delay can break that, and the curve
    then jumps by whole turns there.

    Parameters
    ----------
    H : array_like, complex, shape (..., K)
    like : array_like, shape (..., K), optional
        A reference phase (degrees): the result is shifted by whole turns so that its first sample lies within
        180 degrees of ``like``'s, so that a model and its data are drawn on the same branch.
    """
    ph = np.degrees(np.unwrap(np.angle(np.asarray(H)), axis=-1))
    if like is not None:
        like = np.asarray(like, dtype=float)
        turns = np.round((like[..., :1] - ph[..., :1]) / 360.0)
        ph = ph + 360.0 * turns
    return ph


def model_items(models) -> list:
    """The models of a plot as a list of entries: a mapping gives ``(label, data)`` pairs, a sequence is listed,
    None gives ``[]``."""
    if models is None:
        return []
    if isinstance(models, Mapping):
        return [(k, v) for k, v in models.items()]
    return list(models)


def model_entry(item, n_min: int, what: str):
    """``(label, data, style or None)`` of one model entry, ``(label, data)`` or ``(label, data, style dict)``.

    ``n_min`` is the length without the style (2); ``what`` names the entries in the :class:`PlotDataError`.
    """
    if not isinstance(item, (tuple, list)) or not n_min <= len(item) <= n_min + 1:
        raise PlotDataError(f"each {what} entry must be (label, data) or (label, data, style dict); got {item!r:.80}")
    return item[0], item[1], (item[2] if len(item) > n_min else None)
