"""Error figures: error metrics against the model order, one line per group of sweep points and method."""

from __future__ import annotations

from typing import Any, Mapping, Sequence

import numpy as np

from .plot_data import PlotDataError
from .plot_style import LINESTYLES, colour_cycle, key_legend, percent_text, plain_log_ticks, pyplot

__all__ = ["error_vs_order_plot"]


def _group_label(key: tuple, names: Sequence[str]) -> str:
    parts = []
    for name, v in zip(names, key):
        if name == "M":
            parts.append(rf"$N_\omega$ = {int(v) + 1}")
        elif name == "n_omega":
            parts.append(rf"$N_\omega$ = {int(v)}")
        elif name == "T":
            parts.append(f"T = {float(v):.4g}")
        elif name == "method":
            parts.append(str(v))
        else:
            parts.append(f"{name} = {v}")
    return ", ".join(parts)


def error_vs_order_plot(rows: Sequence[Mapping[str, Any]], metrics: Sequence[str] | Mapping[str, str],
                        *, x: str = "order", group_by: Sequence[str] = ("T", "M", "method"), ncols: int = 2,
                        title: str | None = None, clip: float | None = None, fig=None):
    """Error metrics against the model order, one panel per metric, one line per group.

    Rows whose ``status`` is not ``"ok"`` or whose metric is missing are skipped. A row with ``stable`` false is
    drawn with a cross instead of a dot. The y axes are logarithmic.

    Parameters
    ----------
    rows : sequence of mapping
        Flat rows (e.g. :func:`studies.report.rom_rows`), with the keys ``x``, ``group_by`` and ``metrics``.
    metrics : sequence of str, or mapping key -> axis label
        The keys to plot (relative errors, dimensionless).
    x : str
        Key of the abscissa (default ``"order"``, the model order ``N_r``).
    group_by : sequence of str
        Keys that make one line; ``"M"`` is shown as ``N_omega = M + 1``.
    ncols : int
    title : str, optional
    clip : float, optional
        Values above it (e.g. an unstable ROM's 1e48 gust error) are drawn at ``clip`` with an upward triangle,
        so that they do not flatten the axis; the legend says "off scale".
    fig : Figure, optional

    Returns
    -------
    fig, axes (ndarray of Axes, one per metric, row-major)

    Raises
    ------
    PlotDataError
        No metric, or no row with a value for any metric.
    """
    labels = dict(metrics) if isinstance(metrics, Mapping) else {m: m for m in metrics}
    if not labels:
        raise PlotDataError("give at least one metric to plot")
    ok = [r for r in rows if r.get("status", "ok") == "ok"]
    groups: dict[tuple, list] = {}
    for r in ok:
        groups.setdefault(tuple(r.get(g) for g in group_by), []).append(r)
    if not any(_finite(r.get(m)) for r in ok for m in labels):
        raise PlotDataError(f"no row has a value for {', '.join(labels)}")
    n = len(labels)
    ncols = max(1, min(ncols, n))
    nrows = -(-n // ncols)
    plt = pyplot()
    if fig is None:
        fig = plt.figure(figsize=(5.0 * ncols + 1.0, 3.6 * nrows + 0.8))
    axes = np.asarray(fig.subplots(nrows, ncols, squeeze=False)).ravel()
    colours = colour_cycle()
    # colour: the group without its method; line style: the method (in order of first appearance)
    mi = list(group_by).index("method") if "method" in group_by else None
    methods, ckeys = [], []
    for key in groups:
        if mi is not None and key[mi] not in methods:
            methods.append(key[mi])
        ck = tuple(v for i, v in enumerate(key) if i != mi)
        if ck not in ckeys:
            ckeys.append(ck)
    ckeys.sort(key=lambda t: tuple((v is None, v if isinstance(v, (int, float)) else str(v)) for v in t))
    cnames = [g for i, g in enumerate(group_by) if i != mi]
    keys = sorted(groups, key=lambda k: (ckeys.index(tuple(v for i, v in enumerate(k) if i != mi)),
                                         methods.index(k[mi]) if mi is not None else 0))
    any_clipped = False
    for ax, (metric, mlabel) in zip(axes, labels.items()):
        for key in keys:
            pts = sorted((r[x], r.get(metric), r.get("stable", True)) for r in groups[key] if _finite(r.get(metric)))
            if not pts:
                continue
            xs = np.array([p[0] for p in pts], float)
            ys = np.maximum(np.array([p[1] for p in pts], float), 1e-17)
            off = ys > clip if clip is not None else np.zeros(len(ys), bool)
            ys = np.minimum(ys, clip) if clip is not None else ys
            st = np.array([bool(p[2]) if p[2] is not None else True for p in pts])
            ls = LINESTYLES[methods.index(key[mi]) % len(LINESTYLES)] if mi is not None else "-"
            c = colours[ckeys.index(tuple(v for i, v in enumerate(key) if i != mi)) % len(colours)]
            ax.semilogy(xs, ys, ls=ls, color=c, lw=1.3)
            ax.semilogy(xs[st & ~off], ys[st & ~off], "o", color=c, ms=4)
            if (~st & ~off).any():
                ax.semilogy(xs[~st & ~off], ys[~st & ~off], "x", color=c, ms=8, mew=2)
            if off.any():
                any_clipped = True
                ax.semilogy(xs[off], ys[off], "^", color=c, ms=8, mfc="none", mew=1.6)
        ax.set_xlabel(r"model order $N_r$" if x == "order" else x)
        ax.set_ylabel(mlabel)
        ax.grid(True, which="major", color="0.85")
        ax.grid(True, which="minor", color="0.94", lw=0.6)
        if x == "order":
            from matplotlib.ticker import MaxNLocator

            ax.xaxis.set_major_locator(MaxNLocator(integer=True))
    for ax in axes[:n]:
        plain_log_ticks(ax, "y")
    for ax in axes[n:]:
        ax.set_visible(False)
    cl = {(_group_label(ck, cnames) if cnames else "ROMs"): colours[i % len(colours)] for i, ck in enumerate(ckeys)}
    sl = {str(m): LINESTYLES[i % len(LINESTYLES)] for i, m in enumerate(methods)} if len(methods) > 1 else {}
    leg = key_legend(axes[0], cl, sl, loc="best", fontsize=7.5)
    extra = []
    if any(r.get("stable", True) is False for r in ok):
        extra.append((dict(marker="x", ms=8, mew=2), "unstable ROM"))
    if any_clipped:
        extra.append((dict(marker="^", ms=8, mfc="none", mew=1.6), f"off scale (> {percent_text(clip)})"))
    if extra:
        from matplotlib.lines import Line2D

        handles = list(leg.legend_handles) + [Line2D([], [], ls="none", color="k", **kw) for kw, _ in extra]
        texts = [t.get_text() for t in leg.get_texts()] + [t for _, t in extra]
        axes[0].legend(handles, texts, fontsize=7.5, loc="best")
    if title:
        fig.suptitle(title, fontsize=11)
    fig.tight_layout()
    return fig, axes[:n]


def _finite(v) -> bool:
    try:
        return v is not None and not isinstance(v, bool) and np.isfinite(float(v))
    except (TypeError, ValueError):
        return False
