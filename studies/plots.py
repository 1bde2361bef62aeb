"""Figures of a study from plain arrays: frequency responses, Hankel singular values, errors, gust histories.

Data in, figure out: no store access, no CFD. Each ``*_plot`` draws a new figure (or into the axes it is given)
and returns ``(fig, axes)``; the caller saves and closes it (:func:`save_figure` does both).

Conventions (``shared/DESIGN.md``): angular frequency ``omega`` in units of ``U / c``, plotted against the
reduced frequency ``k = omega c / (2 U) = omega / 2``; time is convective, ``s = t U / c``; frequency responses
have shape ``(n_outputs, n_inputs, n_frequencies)`` and are per radian of gust angle; phases are unwrapped
along frequency and shown in degrees; time histories are load perturbations about the steady flow.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np

from .files import atomic_path

__all__ = [
    "PlotDataError",
    "frf_plot",
    "hankel_plot",
    "error_vs_order_plot",
    "history_plot",
    "heatmap_plot",
    "save_figure",
    "key_legend",
    "plain_log_ticks",
    "percent_formatter",
    "reduced_frequency",
    "unwrapped_phase_deg",
    "pyplot",
    "colour_cycle",
    "LINESTYLES",
]

LINESTYLES = ("-", "--", ":", "-.", (0, (5, 1, 1, 1, 1, 1)), (0, (1, 3)))
REF_STYLE = dict(color="0.2", lw=2.2)
_TEX_NAMES = {"Cl": r"$C_l$", "Cm": r"$C_m$", "Cd": r"$C_d$"}


class PlotDataError(ValueError):
    """Arrays given to a plot do not fit together (shapes, lengths, empty data)."""


def pyplot():
    """``matplotlib.pyplot``, imported on first use (so that importing this module stays light)."""
    import matplotlib.pyplot as plt

    return plt


def _label(name: str) -> str:
    return _TEX_NAMES.get(name, name)


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


def _items(models) -> list:
    if models is None:
        return []
    if isinstance(models, Mapping):
        return [(k, v) for k, v in models.items()]
    return list(models)


def _style(i: int, extra: Mapping | None, colours) -> dict:
    st = dict(color=colours[i % len(colours)], lw=1.3)
    if extra:
        st.update(extra)
    return st


def colour_cycle():
    """The colours of matplotlib's current property cycle (list of colour strings)."""
    plt = pyplot()
    return plt.rcParams["axes.prop_cycle"].by_key()["color"]


def plain_log_ticks(ax, axis: str = "y", *, plain: bool = True) -> None:
    """Tidy the labels of a log axis.

    Major ticks are labelled with plain numbers (``0.2``, ``5``, ``1e-05``) when ``plain``, else as matplotlib
    does (``10^-3``). When fewer than two powers of ten lie on the axis, minor ticks are labelled too, in plain
    numbers (all of them within a factor 3, 2, 3 and 5 times a power of ten within a decade, 2 and 5 beyond);
    otherwise they are not.
    """
    from matplotlib.ticker import FuncFormatter, NullFormatter

    a = ax.yaxis if axis == "y" else ax.xaxis
    lo, hi = (ax.get_ylim() if axis == "y" else ax.get_xlim())
    if plain:
        a.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
    if lo > 0 and hi > lo:
        n_major = int(np.floor(np.log10(hi)) - np.ceil(np.log10(lo))) + 1
        keep = ((2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0) if hi / lo <= 3.0 else (2.0, 3.0, 5.0) if hi / lo <= 10.0
                else (2.0, 5.0))
    else:
        n_major = 2
    if n_major < 2:
        a.set_minor_formatter(FuncFormatter(lambda v, _: f"{v:g}" if v > 0 and round(
            v / 10 ** np.floor(np.log10(v)), 6) in keep else ""))
    else:
        a.set_minor_formatter(NullFormatter())


def key_legend(ax, colours: Mapping[str, Any] = None, styles: Mapping[str, Any] = None, *, ref_label=None,
               loc: str = "best", outside: bool = False, fontsize: float = 8):
    """A compact legend: one entry per colour (e.g. sweep point) and one per line style (e.g. method).

    Parameters
    ----------
    ax : Axes
    colours : mapping label -> colour, optional
    styles : mapping label -> line style, optional (drawn in grey)
    ref_label : str, optional
        Add the reference line (thick black) first.
    loc : str
    outside : bool
        Place the legend to the right of ``ax``.

    Returns
    -------
    matplotlib.legend.Legend
    """
    from matplotlib.lines import Line2D

    handles, labels = [], []
    if ref_label:
        handles.append(Line2D([], [], **REF_STYLE))
        labels.append(ref_label)
    for lab, c in (colours or {}).items():
        handles.append(Line2D([], [], color=c, lw=2.0))
        labels.append(lab)
    for lab, ls in (styles or {}).items():
        handles.append(Line2D([], [], color="0.3", ls=ls, lw=1.4))
        labels.append(lab)
    if outside:
        return ax.legend(handles, labels, fontsize=fontsize, loc="upper left", bbox_to_anchor=(1.02, 1.0),
                         borderaxespad=0.0)
    return ax.legend(handles, labels, fontsize=fontsize, loc=loc)


def _unpack(item, n_min: int, what: str):
    if not isinstance(item, (tuple, list)) or not n_min <= len(item) <= n_min + 1:
        raise PlotDataError(f"each {what} entry must be (label, data) or (label, data, style dict); got {item!r:.80}")
    return item[0], item[1], (item[2] if len(item) > n_min else None)


# ---------------------------------------------------------------------------------------------
# Frequency responses
# ---------------------------------------------------------------------------------------------

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
    items = [_unpack(it, 2, "model") for it in _items(models)]
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
        a_m.loglog(ks, np.abs(ref[sel]), label=ref_label, **REF_STYLE, zorder=2)
        a_p.semilogx(ks, ph_ref, **REF_STYLE, zorder=2)
        if mask is not None and mask.any():
            a_m.loglog(k[mask], np.abs(ref[mask]), "o", mfc="none", mec="k", ms=4.5, zorder=2.5,
                       label=f"{ref_label} samples used ({int(mask.sum())})")
        scale = max(float(np.abs(ref).max()), np.finfo(float).tiny)
        for i, (lab, H, st) in enumerate(mods):
            style = _style(i, st, colours)
            h = H[j, input_index]
            a_m.loglog(ks, np.abs(h[sel]), label=lab, zorder=3, **style)
            a_p.semilogx(ks, unwrapped_phase_deg(h[sel], like=ph_ref), zorder=3, **style)
            if nrow == 3:
                err = np.abs(h[sel] - ref[sel]) / scale
                axes[2, j].loglog(ks, np.maximum(err, 1e-17), zorder=3, **style)
        a_m.set_title(f"{_label(name)} per radian of gust angle")
        a_m.set_ylabel(f"|{_label(name)}| [1/rad]")
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


# ---------------------------------------------------------------------------------------------
# Hankel singular values
# ---------------------------------------------------------------------------------------------

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
        sets = _items(sv)
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
        lab, s, st = _unpack(item, 2, "singular-value")
        s = np.asarray(s, dtype=float)
        if s.ndim != 1 or s.size == 0:
            raise PlotDataError(f"singular values {lab!r} must be a non-empty 1-D array; got shape {s.shape}")
        if normalise and s[0] > 0:
            s = s / s[0]
        style = _style(i, st, colours)
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


# ---------------------------------------------------------------------------------------------
# Errors against the model order
# ---------------------------------------------------------------------------------------------

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
        extra.append((dict(marker="^", ms=8, mfc="none", mew=1.6), f"off scale (> {_percent_text(clip)})"))
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


# ---------------------------------------------------------------------------------------------
# Time histories
# ---------------------------------------------------------------------------------------------

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
    for it in _items(models):
        lab, data, st = _unpack(it, 2, "model")
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
            ay.plot(t, ref[o], label=ref_label, **REF_STYLE, zorder=2)
        span = None
        if ref is not None and np.all(np.isfinite(ref[o])):
            span = max(float(np.ptp(ref[o])), 1e-12)
        clipped = False
        for i, (lab, data, st) in enumerate(mods):
            style = _style(i, st, colours)
            off = span is not None and not (np.max(np.abs(data[o] - ref[o]), initial=0.0) <= OFF_SCALE * span)
            clipped |= off
            shown = np.where(np.isfinite(data[o]), data[o], np.nan)
            ay.plot(t, shown, label=lab + (" (diverges, off scale)" if off and j == 0 else ""), zorder=3, **style)
            if "e" in col:
                col["e"].plot(t, shown - ref[o], zorder=3, **style)
        if clipped:  # a diverging (unstable) model would flatten everything else: keep the reference's scale
            lo, hi = float(np.min(ref[o])), float(np.max(ref[o]))
            ay.set_ylim(lo - 0.5 * span, hi + 0.5 * span)
            if "e" in col:
                col["e"].set_ylim(-0.5 * span, 0.5 * span)
        ay.set_ylabel(rf"$\Delta${_label(o)}")
        ay.set_title(rf"$\Delta${_label(o)} (perturbation about the steady flow)", fontsize=10)
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


# ---------------------------------------------------------------------------------------------
# Heat maps
# ---------------------------------------------------------------------------------------------

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
        fmt = _percent_text if percent else (lambda x: f"{x:.1e}")
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


def percent_formatter():
    """A tick formatter writing fractions as percentages (``0.012`` -> ``1.2%``), e.g. for colour bars."""
    from matplotlib.ticker import FuncFormatter

    return FuncFormatter(lambda v, _: _percent_text(v) if v > 0 else "0%")


def _percent_text(v: float) -> str:
    p = 100.0 * float(v)
    if p >= 9.95:
        return f"{p:.0f}%"
    if p >= 0.01 or p == 0.0:
        return f"{p:.2g}%"
    return f"{p:.0e}%"


def save_figure(fig, path, *, dpi: int = 120, palette: bool = True) -> Path:
    """Save ``fig`` to ``path`` atomically (parent folders created) and close it.

    The figure is drawn to a temporary file beside ``path`` and renamed over it
    (:func:`studies.files.atomic_path`): a failure while drawing or writing leaves an existing file as it was.

    Parameters
    ----------
    fig : Figure
    path : path-like
        The format follows the suffix (``.png``, ``.pdf``, ``.svg``).
    dpi : int
    palette : bool
        PNG only: store with a 256-colour palette (no dithering), about three times smaller than RGBA and
        indistinguishable for line plots, so that generated figures can be committed.

    Returns
    -------
    pathlib.Path
    """
    path = Path(path)
    fmt = path.suffix[1:].lower() or None
    try:
        with atomic_path(path) as tmp:
            fig.savefig(tmp, dpi=dpi, format=fmt)
            if palette and fmt == "png":
                from PIL import Image

                with Image.open(tmp) as im:
                    q = im.convert("RGB").quantize(colors=256, method=Image.Quantize.FASTOCTREE,
                                                   dither=Image.Dither.NONE)
                q.save(tmp, format="PNG", optimize=True)
    finally:
        pyplot().close(fig)
    return path
