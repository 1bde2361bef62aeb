"""Frequency-response figures: magnitude, phase and error of models against a reference, against the reduced
frequency."""

from __future__ import annotations

from typing import Sequence

import numpy as np

from .plot_data import PlotDataError, model_entry, model_items, reduced_frequency, unwrapped_phase_deg
from .plot_style import REF_STYLE, colour_cycle, line_style, output_label, plain_log_ticks, pyplot

__all__ = ["frf_plot"]


def _as_pmk(H, name: str, K: int | None = None) -> np.ndarray:
    a = np.asarray(H)
    if a.ndim == 1:
        a = a.reshape(1, 1, -1)
    elif a.ndim == 2:
        a = a[:, None, :]
    elif a.ndim != 3:
        raise PlotDataError(f"{name} must have shape (p, m, K), (p, K) or (K,); got {a.shape}")
    if K is not None and a.shape[-1] != K:
        raise PlotDataError(f"{name} has {a.shape[-1]} frequencies but omega has {K}")
    return a


def frf_plot(omega, H_ref, models=(), *, outputs: Sequence[str] = ("Cl", "Cm"), input_index: int = 0,
             ref_label: str = "LFD", samples=None, error: bool = True, title: str | None = None,
             legend: bool = True, fig=None):
    """Magnitude and phase of a reference response and of models against the reduced frequency.

    Columns are outputs; rows are magnitude (log-log), phase (degrees, unwrapped, log k) and, with ``error``,
    the model error ``|H_model - H_ref| / max_k |H_ref|`` (log-log; the normalisation of ``sysid.metrics``).
    ``omega = 0`` and ``omega = inf`` samples are left out of the log axes (their values are in the tables).

    Parameters
    ----------
    omega : array_like, shape (K,)
        Angular frequencies in ``U / c`` (continuous; e.g. ``FrequencyResponse.omega``).
    H_ref : array_like, complex, shape (p, m, K), (p, K) or (K,)
        Reference response (the LFD), per radian of gust angle.
    models : sequence of (label, H) or (label, H, style), or mapping label -> H
        Model responses on the same frequencies, same shape as ``H_ref``; ``style`` is a dict of line
        properties (e.g. ``{"ls": "--"}``).
    outputs : sequence of str
        Output names, one per row of ``H``; at most ``p`` are drawn (the first ones).
    input_index : int
        The input column of ``H`` to draw.
    ref_label : str
    samples : array_like of int or bool, shape (K,), optional
        The frequencies used for identification (e.g. a subsampled grid); drawn as markers on the reference.
    error : bool
        Add the error row.
    title : str, optional
    legend : bool
        Draw the legend (in the first magnitude panel).
    fig : matplotlib.figure.Figure, optional
        Draw into this (empty) figure instead of a new one.

    Returns
    -------
    fig : matplotlib.figure.Figure
    axes : ndarray of Axes, shape (2 or 3, n_outputs)

    Raises
    ------
    PlotDataError
        Shapes that do not match ``omega``, no positive finite frequency.
    """
    omega = np.asarray(omega, dtype=float).ravel()
    K = omega.size
    H_ref = _as_pmk(H_ref, "H_ref", K)
    items = [model_entry(it, 2, "model") for it in model_items(models)]
    mods = [(lab, _as_pmk(H, f"model {lab!r}", K), st) for lab, H, st in items]
    for lab, H, _ in mods:
        if H.shape != H_ref.shape:
            raise PlotDataError(f"model {lab!r} has shape {H.shape} but H_ref has {H_ref.shape}")
    k = reduced_frequency(omega)
    sel = np.isfinite(k) & (k > 0)
    if not sel.any():
        raise PlotDataError("no positive finite frequency to plot")
    outputs = list(outputs)[: H_ref.shape[0]]
    if len(outputs) < H_ref.shape[0]:
        outputs += [f"y{i}" for i in range(len(outputs), H_ref.shape[0])]
    nrow = 3 if error and mods else 2
    plt = pyplot()
    if fig is None:
        fig = plt.figure(figsize=(5.2 * len(outputs) + 0.6, 2.6 * nrow + 0.9))
    axes = np.asarray(fig.subplots(nrow, len(outputs), sharex=True, squeeze=False))
    colours = colour_cycle()
    ks = k[sel]
    mask = None
    if samples is not None:
        samples = np.asarray(samples)
        mask = np.zeros(K, bool)
        mask[samples] = True
        mask &= sel
    for j, name in enumerate(outputs):
        ref = H_ref[j, input_index]
        ph_ref = unwrapped_phase_deg(ref[sel])
        a_m, a_p = axes[0, j], axes[1, j]
        a_m.loglog(ks, np.abs(ref[sel]), label=ref_label, **REF_STYLE, zorder=5)
        a_p.semilogx(ks, ph_ref, **REF_STYLE, zorder=5)
        if mask is not None and mask.any():
            a_m.loglog(k[mask], np.abs(ref[mask]), "o", mfc="none", mec="k", ms=4.5, zorder=2.5,
                       label=f"{ref_label} samples used ({int(mask.sum())})")
        scale = max(float(np.abs(ref).max()), np.finfo(float).tiny)
        for i, (lab, H, st) in enumerate(mods):
            style = line_style(i, st, colours)
            h = H[j, input_index]
            a_m.loglog(ks, np.abs(h[sel]), label=lab, zorder=3, **style)
            a_p.semilogx(ks, unwrapped_phase_deg(h[sel], like=ph_ref), zorder=3, **style)
            if nrow == 3:
                err = np.abs(h[sel] - ref[sel]) / scale
                axes[2, j].loglog(ks, np.maximum(err, 1e-17), zorder=3, **style)
        a_m.set_title(f"{output_label(name)} per radian of gust angle")
        a_m.set_ylabel(f"|{output_label(name)}| [1/rad]")
        a_p.set_ylabel("phase [deg]")
        if nrow == 3:
            axes[2, j].set_ylabel("|model - ref| / max |ref|")
        axes[-1, j].set_xlabel(r"reduced frequency $k = \omega c / (2U)$")
        for ax in axes[:, j]:
            ax.grid(True, which="major", color="0.85")
            ax.grid(True, which="minor", color="0.94", lw=0.6)
    for ax in axes[0]:
        plain_log_ticks(ax, "y")
    if nrow == 3:
        for ax in axes[2]:
            plain_log_ticks(ax, "y")
    if legend:
        axes[0, 0].legend(fontsize=8, loc="lower left")
    if title:
        fig.suptitle(title, fontsize=11)
    fig.tight_layout()
    return fig, axes
