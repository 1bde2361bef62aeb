"""Figures of a study from plain arrays: frequency responses, Hankel singular values, errors, gust histories.

Data in, figure out: no store access, no CFD. Each ``*_plot`` draws a new figure (or into the axes it is given)
and returns ``(fig, axes)``; the caller saves and closes it (:func:`save_figure` does both).

Conventions (docs/conventions.md): angular frequency ``omega`` in units of ``U / c``, plotted against the
reduced frequency ``k = omega c / (2 U) = omega / 2``; time is convective, ``s = t U / c``; frequency responses
have shape ``(n_outputs, n_inputs, n_frequencies)`` and are per radian of gust angle; phases are unwrapped
along frequency and shown in degrees; time histories are load perturbations about the steady flow.
"""

from __future__ import annotations

from .error_plots import error_vs_order_plot
from .figure_files import save_figure
from .frf_plots import frf_plot
from .hankel_plots import hankel_plot
from .heatmap_plots import heatmap_plot
from .history_plots import OFF_SCALE, history_plot
from .plot_data import PlotDataError, reduced_frequency, unwrapped_phase_deg
from .plot_style import LINESTYLES, REF_STYLE, colour_cycle, key_legend, percent_formatter, plain_log_ticks, pyplot

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
    "REF_STYLE",
    "OFF_SCALE",
]
# One module per figure family, the names above re-exported from them: studies.report.frf_plots, studies.report.hankel_plots,
# studies.report.error_plots, studies.report.history_plots, studies.report.heatmap_plots; the shared look in studies.report.plot_style, the
# input checks and frequency axes in studies.report.plot_data, saving in studies.report.figure_files.
