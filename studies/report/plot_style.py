"""The look shared by the study figures: line styles, colours, output labels, legends, log-axis ticks and percent
formatting, and :func:`pyplot` (matplotlib imported on first use)."""

from __future__ import annotations

from typing import Any, Mapping

import numpy as np

__all__ = ["LINESTYLES", "REF_STYLE", "pyplot", "output_label", "line_style", "colour_cycle", "plain_log_ticks",
           "key_legend", "percent_formatter", "percent_text"]

LINESTYLES = ("-", "--", ":", "-.", (0, (5, 1, 1, 1, 1, 1)), (0, (1, 3)))
REF_STYLE = dict(color="k", lw=1.8, ls=(0, (1, 1.5)), dash_capstyle="round")
"""The reference curve (LTD, LFD): black, dotted, drawn on top of the models (zorder 5) so that a model that follows
it cannot hide it (a thick grey line underneath vanished under every ROM that matched it)."""
_TEX_NAMES = {"Cl": r"$C_l$", "Cm": r"$C_m$", "Cd": r"$C_d$"}


def pyplot():
    """``matplotlib.pyplot``, imported on first use (so that importing this module stays light)."""
    import matplotlib.pyplot as plt

    return plt


def output_label(name: str) -> str:
    """The axis label of an output: ``"Cl"`` -> ``$C_l$`` (TeX), other names as given."""
    return _TEX_NAMES.get(name, name)


def line_style(i: int, extra: Mapping | None, colours) -> dict:
    """Line properties of model ``i``: colour ``i`` of ``colours`` (cycled), width 1.3, updated by ``extra``."""
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
        Add the reference line (black, dotted: REF_STYLE) first.
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


def percent_formatter():
    """A tick formatter writing fractions as percentages (``0.012`` -> ``1.2%``), e.g. for colour bars."""
    from matplotlib.ticker import FuncFormatter

    return FuncFormatter(lambda v, _: percent_text(v) if v > 0 else "0%")


def percent_text(v: float) -> str:
    """A fraction as a percentage of two significant digits (``0.012`` -> ``"1.2%"``, ``0.25`` -> ``"25%"``)."""
    p = 100.0 * float(v)
    if p >= 9.95:
        return f"{p:.0f}%"
    if p >= 0.01 or p == 0.0:
        return f"{p:.2g}%"
    return f"{p:.0e}%"
