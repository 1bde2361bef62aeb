"""Time-history figures: load histories of models against a reference (ROM against LTD) for one gust."""

from __future__ import annotations

from typing import Any, Mapping, Sequence

import numpy as np

from .plot_data import PlotDataError, model_entry, model_items
from .plot_style import REF_STYLE, colour_cycle, line_style, output_label, pyplot

__all__ = ["history_plot", "OFF_SCALE"]


OFF_SCALE = 3.0
"""A model whose history departs from the reference by more than this many reference ranges is drawn off
scale (the axes keep the reference's scale and the legend says so)."""


def history_plot(t, reference: Mapping[str, Any] | None, models=(), *, outputs: Sequence[str] = ("Cl", "Cm"),
                 ref_label: str = "LTD", u=None, error: bool = True, t_label: str | None = None,
                 title: str | None = None, legend: bool = True, fig=None):
    """Load histories of models against a reference (e.g. ROM against LTD) for one gust.

    Columns are outputs; rows are the gust input (when ``u`` is given, in degrees), the loads and, with ``error``
    and a reference, the difference model - reference.

    Parameters
    ----------
    t : array_like, shape (n,)
        Convective time ``s = t U / c`` (or any shifted time, see ``t_label``).
    reference : mapping output -> array (n,), or None
        Reference histories (the LTD), e.g. ``{"Cl": cl, "Cm": cm}``; load perturbations about the steady flow.
    models : sequence of (label, mapping) or (label, mapping, style), or mapping label -> mapping
        Model histories on the same time grid.
    outputs : sequence of str
        Which keys to draw, one column each.
    ref_label : str
    u : array_like, shape (n,), optional
        Gust input ``v_g / U`` at the reference point; drawn in a top row as the gust angle
        ``atan(v_g / U)`` in degrees (paper Eq. 18), so that G6 (``v_g / U = 1``) reads 45 degrees.
    error : bool
        Add the row of model - reference (needs a reference and models).
    t_label : str, optional
        x-axis label (default ``"convective time s = t U / c"``).
    title : str, optional
    legend : bool
        Draw the legend (first loads panel); with many models, draw your own with :func:`key_legend`.
    fig : Figure, optional

    Returns
    -------
    fig, axes (ndarray of Axes, shape (n_rows, n_outputs))

    Raises
    ------
    PlotDataError
        Lengths that do not match ``t``, an output missing from the data, nothing to draw.
    """
    t = np.asarray(t, dtype=float).ravel()
    n = t.size
    outputs = list(outputs)
    if not outputs:
        raise PlotDataError("give at least one output to plot")

    def check(data, what):
        out = {}
        for o in outputs:
            if o not in data:
                raise PlotDataError(f"{what} has no {o!r} history (it has {', '.join(map(str, data))})")
            a = np.asarray(data[o], dtype=float).ravel()
            if a.size != n:
                raise PlotDataError(f"{what} {o!r} has {a.size} samples but t has {n}")
            out[o] = a
        return out

    ref = check(reference, f"reference {ref_label!r}") if reference is not None else None
    mods = []
    for it in model_items(models):
        lab, data, st = model_entry(it, 2, "model")
        mods.append((lab, check(data, f"model {lab!r}"), st))
    if ref is None and not mods:
        raise PlotDataError("nothing to plot: give a reference or at least one model")
    rows = (["u"] if u is not None else []) + ["y"] + (["e"] if error and ref is not None and mods else [])
    heights = [0.45 if r == "u" else 1.0 if r == "y" else 0.6 for r in rows]
    plt = pyplot()
    if fig is None:
        fig = plt.figure(figsize=(5.4 * len(outputs) + 0.6, 1.0 + 3.3 * sum(heights)))
    axes = np.asarray(fig.subplots(len(rows), len(outputs), sharex=True, squeeze=False,
                                   gridspec_kw=dict(height_ratios=heights)))
    colours = colour_cycle()
    for j, o in enumerate(outputs):
        col = {r: axes[i, j] for i, r in enumerate(rows)}
        if "u" in col:
            uu = np.asarray(u, dtype=float).ravel()
            if uu.size != n:
                raise PlotDataError(f"u has {uu.size} samples but t has {n}")
            col["u"].plot(t, np.degrees(np.arctan(uu)), color="0.35", lw=1.2)
            col["u"].set_ylabel("gust angle [deg]", fontsize=8)
        ay = col["y"]
        if ref is not None:
            ay.plot(t, ref[o], label=ref_label, **REF_STYLE, zorder=5)
        span = None
        if ref is not None and np.all(np.isfinite(ref[o])):
            span = max(float(np.ptp(ref[o])), 1e-12)
            lo, hi = float(np.min(ref[o])) - 0.5 * span, float(np.max(ref[o])) + 0.5 * span  # the shown scale
        clipped = False
        for i, (lab, data, st) in enumerate(mods):
            style = line_style(i, st, colours)
            off = span is not None and not (np.max(np.abs(data[o] - ref[o]), initial=0.0) <= OFF_SCALE * span)
            clipped |= off
            shown = np.where(np.isfinite(data[o]), data[o], np.nan)
            if off:  # drawn until it first leaves the reference's scale: an oscillating divergence drawn to the
                # end painted the whole panel (unstable ROMs of docs/sweep-T.md)
                with np.errstate(invalid="ignore"):
                    outside = np.flatnonzero(~((shown >= lo) & (shown <= hi)))
                if outside.size:
                    shown = shown.copy()
                    shown[outside[0] + 1:] = np.nan
            ay.plot(t, shown, label=lab + (" (diverges, off scale)" if off and j == 0 else ""), zorder=3, **style)
            if "e" in col:
                col["e"].plot(t, shown - ref[o], zorder=3, **style)
        if clipped:  # a diverging (unstable) model would flatten everything else: keep the reference's scale
            ay.set_ylim(lo, hi)
            if "e" in col:
                col["e"].set_ylim(-0.5 * span, 0.5 * span)
        ay.set_ylabel(rf"$\Delta${output_label(o)}")
        ay.set_title(rf"$\Delta${output_label(o)} (perturbation about the steady flow)", fontsize=10)
        if "e" in col:
            col["e"].axhline(0.0, color="k", lw=0.6)
            col["e"].set_ylabel(f"model - {ref_label}", fontsize=9)
        axes[-1, j].set_xlabel(t_label or "convective time s = t U / c")
        for ax in axes[:, j]:
            ax.grid(True, color="0.85")
    if legend:
        axes[rows.index("y"), 0].legend(fontsize=8, loc="best")
    if title:
        fig.suptitle(title, fontsize=11)
    fig.tight_layout()
    return fig, axes
