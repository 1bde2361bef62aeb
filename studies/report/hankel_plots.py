"""Hankel singular value figures: the singular values that choose the model order, with the chosen orders marked."""

from __future__ import annotations

from typing import Mapping, Sequence

import numpy as np

from .plot_data import PlotDataError, model_entry, model_items
from .plot_style import colour_cycle, line_style, pyplot

__all__ = ["hankel_plot"]


def hankel_plot(sv, *, orders: Sequence[int] = (), normalise: bool = True, title: str | None = None, ax=None):
    """Hankel singular values (log scale) against their index, with the model orders marked.

    Parameters
    ----------
    sv : array_like, shape (q,), or sequence of (label, array) / mapping label -> array
        Singular values, decreasing (e.g. ``RomRecord.hankel_sv``); several sets are overlaid.
    orders : sequence of int
        Model orders ``N_r`` to mark with vertical lines (the states kept are the ``N_r`` largest values).
    normalise : bool
        Divide each set by its largest value.
    title : str, optional
    ax : matplotlib Axes, optional

    Returns
    -------
    fig, ax

    Raises
    ------
    PlotDataError
        An empty or non-1-D set of singular values.
    """
    if isinstance(sv, Mapping) or (isinstance(sv, (list, tuple)) and sv and isinstance(sv[0], (list, tuple))
                                   and len(sv[0]) in (2, 3) and isinstance(sv[0][0], str)):
        sets = model_items(sv)
    else:
        sets = [("Hankel singular values", sv)]
    if not sets:
        raise PlotDataError("no singular values to plot")
    plt = pyplot()
    if ax is None:
        fig, ax = plt.subplots(figsize=(6.4, 4.2))
    else:
        fig = ax.figure
    colours = colour_cycle()
    for i, item in enumerate(sets):
        lab, s, st = model_entry(item, 2, "singular-value")
        s = np.asarray(s, dtype=float)
        if s.ndim != 1 or s.size == 0:
            raise PlotDataError(f"singular values {lab!r} must be a non-empty 1-D array; got shape {s.shape}")
        if normalise and s[0] > 0:
            s = s / s[0]
        style = line_style(i, st, colours)
        ax.semilogy(np.arange(1, s.size + 1), np.maximum(s, 1e-300), marker="o", ms=3, label=lab, **style)
    for j, n in enumerate(sorted(set(int(o) for o in orders))):
        ax.axvline(n + 0.5, color="0.4", ls=":", lw=1.0, label="model orders $N_r$" if j == 0 else None)
        ax.text(n + 0.5, 1.0, f" {n}", transform=ax.get_xaxis_transform(), va="top", ha="left", fontsize=8,
                color="0.3")
    from matplotlib.ticker import MaxNLocator

    ax.xaxis.set_major_locator(MaxNLocator(integer=True))
    ax.set_xlabel("index i")
    ax.set_ylabel(r"$\sigma_i / \sigma_1$" if normalise else r"$\sigma_i$")
    ax.grid(True, which="major", color="0.85")
    ax.legend(fontsize=8, loc="lower left")
    if title:
        ax.set_title(title, fontsize=10)
    fig.tight_layout()
    return fig, ax
