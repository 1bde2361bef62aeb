"""Heat-map figures: a value (e.g. an error) over two sweep axes, log colour scale, values written in the cells."""

from __future__ import annotations

from typing import Sequence

import numpy as np

from .plot_data import PlotDataError
from .plot_style import percent_formatter, percent_text, pyplot

__all__ = ["heatmap_plot"]


def heatmap_plot(values, row_labels: Sequence[str], col_labels: Sequence[str], *, log: bool = True,
                 percent: bool = True, cbar_label: str = "relative error", vmin: float | None = None,
                 vmax: float | None = None, annotate: bool = True, colorbar: bool = True, cmap: str = "YlOrRd",
                 title: str | None = None, ax=None):
    """A table of errors as a coloured grid (e.g. peak error, rows = ROMs, columns = gusts).

    Parameters
    ----------
    values : array_like, shape (n_rows, n_cols)
        Non-negative errors; NaN marks a missing cell (drawn hatched, annotated "-"), ``inf`` a diverged one
        (e.g. an unstable ROM whose history overflowed: drawn in the top colour, annotated "inf").
    row_labels, col_labels : sequence of str
    log : bool
        Logarithmic colour scale (zeros are clipped to the smallest positive value).
    percent : bool
        Annotate cells as percentages (``0.012`` -> ``1.2%``), else in e-notation.
    cbar_label : str
    vmin, vmax : float, optional
        Colour limits (share them between panels to compare them). Cells above ``vmax`` are drawn in the top
        colour and annotated ``>vmax`` (so that an unstable ROM's 1e80 error does not flatten the scale or
        overflow its cell).
    annotate : bool
    colorbar : bool
        Draw a colour bar next to ``ax`` (leave it out on all but one of several panels sharing limits).
    cmap : str
        Colour map (default light yellow for small errors to dark red for large ones).
    title : str, optional
    ax : Axes, optional

    Returns
    -------
    fig, ax
        The image is ``ax.images[0]`` (for a shared colour bar: ``fig.colorbar(ax.images[0], ax=axes)``).

    Raises
    ------
    PlotDataError
        Labels that do not match the shape, negative values.
    """
    from matplotlib.colors import LogNorm, Normalize

    v = np.asarray(values, dtype=float)
    if v.ndim != 2 or v.shape != (len(row_labels), len(col_labels)):
        raise PlotDataError(f"values have shape {v.shape} but there are {len(row_labels)} row and "
                            f"{len(col_labels)} column labels")
    fin = np.isfinite(v)
    if (v[fin] < 0).any():
        raise PlotDataError("heat-map values must be non-negative errors")
    plt = pyplot()
    own = ax is None
    if own:
        fig, ax = plt.subplots(figsize=(1.1 * len(col_labels) + 3.2, 0.42 * len(row_labels) + 1.8))
    else:
        fig = ax.figure
    pos = v[fin & (v > 0)]
    lo = vmin if vmin is not None else (float(pos.min()) if pos.size else 1e-6)
    hi = vmax if vmax is not None else (float(v[fin].max()) if fin.any() else 1.0)
    hi = max(hi, lo * 10 if log else lo + 1e-12)
    norm = LogNorm(lo, hi) if log else Normalize(lo if vmin is not None else 0.0, hi)
    diverged = np.isposinf(v)
    shown = np.where(fin, np.clip(v, lo, hi) if log else np.minimum(v, hi), np.where(diverged, hi, np.nan))
    cm = plt.get_cmap(cmap).with_extremes(bad="0.93")
    im = ax.imshow(np.ma.masked_invalid(shown), cmap=cm, norm=norm, aspect="auto")
    missing = ~fin & ~diverged
    if missing.any():
        ys, xs = np.nonzero(missing)
        for yy, xx in zip(ys, xs):
            ax.add_patch(plt.Rectangle((xx - 0.5, yy - 0.5), 1, 1, fill=False, hatch="//", ec="0.6", lw=0))
    ax.set_xticks(range(len(col_labels)), labels=list(col_labels))
    ax.set_yticks(range(len(row_labels)), labels=list(row_labels), fontsize=8)
    ax.tick_params(axis="x", labelsize=8, top=True, labeltop=True, bottom=False, labelbottom=False)
    if annotate:
        fmt = percent_text if percent else (lambda x: f"{x:.1e}")
        for (yy, xx), val in np.ndenumerate(v):
            if missing[yy, xx]:
                ax.text(xx, yy, "-", ha="center", va="center", fontsize=7.5, color="0.4")
                continue
            txt = "inf" if diverged[yy, xx] else (f">{fmt(hi)}" if val > hi else fmt(val))
            rgba = im.cmap(im.norm(shown[yy, xx]))
            colour = "k" if (0.299 * rgba[0] + 0.587 * rgba[1] + 0.114 * rgba[2]) > 0.5 else "w"
            ax.text(xx, yy, txt, ha="center", va="center", fontsize=7.5, color=colour)
    if colorbar:
        cb = fig.colorbar(im, ax=ax, fraction=0.046, pad=0.03)
        cb.set_label(cbar_label, fontsize=9)
        if percent:
            cb.formatter = percent_formatter()
    if title:
        ax.set_title(title, fontsize=10, pad=16)  # room for the column labels on top
    if own:
        fig.tight_layout()
    return fig, ax
