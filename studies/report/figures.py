"""The report's figures: a table of figure families (:data:`FIGURE_SPECS`) and one loop that draws them.

Each family is a :class:`FigureSpec`: the page section its figures go to, the function that selects the data of
each figure from the results (one :class:`FigureData` per figure), the file-name pattern, the plotting function
(:mod:`studies.report.plots`, or a small composition of its functions) and the title and caption patterns.
:func:`draw_figures` draws every figure of every family; :func:`report_figures` keeps the figures of the last
report when nothing they depend on changed (``figures/manifest.json``, :data:`FIGURE_MANIFEST`).

For the paper's cases (T1-T6, G1-G6) the captions name the paper figure each one reproduces
(:data:`PAPER_FRF_FIGURES`, :data:`PAPER_HISTORY_FIGURES`).
"""

from __future__ import annotations

import hashlib
import json
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Iterable, Mapping, Optional

import numpy as np

from . import plots
from ..store.files import atomic_write_bytes
from .rows import T_key, history_outputs, frf_outputs, is_number, point_key, rom_rows, sim_rows

__all__ = [
    "Figure",
    "FigureData",
    "FigureSpec",
    "FIGURE_SPECS",
    "FIGURE_MANIFEST",
    "ERROR_RANGE",
    "PAPER_FRF_FIGURES",
    "PAPER_HISTORY_FIGURES",
    "draw_figures",
    "report_figures",
    "is_paper_case",
    "is_paper_study",
]

PAPER_FRF_FIGURES = {("T1", 25, 257): 11, ("T2", 25, 257): 12, ("T3", 25, 257): 13, ("T4", 25, 257): 14,
                     ("T5", 25, 257): 15, ("T5", 55, 257): 16, ("T6", 25, 257): 17, ("T6", 35, 257): 18,
                     ("T2", 9, 33): 19}
"""(case, N_r, N_omega) -> number of the paper's ROM-against-LFD figure."""

PAPER_HISTORY_FIGURES = {("T1", "G3"): (20,), ("T1", "G6"): (20,), ("T2", "G3"): (21, 29), ("T2", "G6"): (21,),
                         ("T3", "G3"): (22,), ("T3", "G6"): (22,), ("T4", "G3"): (23,), ("T5", "G3"): (24, 25),
                         ("T6", "G3"): (26, 27), ("T1", "G1"): (30,), ("T1", "G4"): (31,), ("T2", "G2"): (32,),
                         ("T2", "G5"): (33,), ("T4", "G4"): (34,), ("T4", "G2"): (35,), ("T6", "G1"): (36,),
                         ("T6", "G5"): (37,)}
"""(case, gust) -> the paper's ROM-against-LTD figures of that pair."""

ERROR_RANGE = (1e-4, 10.0)
"""Range of relative errors drawn to scale (0.01 % to 1000 %) in the heat maps and the error-against-order
figures: larger errors (unstable ROMs) are drawn at the top and marked."""

FIGURE_MANIFEST = "manifest.json"
"""File in ``figures/`` naming the figures of the last report and the fingerprint of what they were drawn from."""


@dataclass(frozen=True)
class Figure:
    """A drawn figure: the page section it belongs to, its file and its caption."""

    section: str
    path: Path
    caption: str


@dataclass(frozen=True)
class FigureData:
    """What one figure of a family is drawn from.

    ``fields`` fill the family's file-name, title and caption patterns; the plotting function is called as
    ``plot(*args, title=title, **options)``; ``paper_figures`` are the numbers of the paper's figures it
    reproduces (named in the caption).
    """

    fields: Mapping[str, Any]
    args: tuple
    options: Mapping[str, Any] = field(default_factory=dict)
    paper_figures: tuple = ()


@dataclass(frozen=True)
class FigureSpec:
    """A figure family.

    ``select(results, paper)`` yields one :class:`FigureData` per figure; ``file`` is the file-name pattern,
    parts joined by "-" (parts that come out empty are left out); ``plot`` draws one figure and returns
    ``(fig, axes)``; ``title`` and ``caption`` are patterns (the caption gets ``{title}`` and ``{paper_note}``
    as well); ``save`` are keywords of :func:`studies.report.plots.save_figure`.
    """

    name: str
    section: str
    select: Callable[[Any, bool], Iterable[FigureData]]
    file: tuple
    plot: Callable
    title: str
    caption: str
    save: Mapping[str, Any] = field(default_factory=dict)


# ---------------------------------------------------------------------------------------------
# Helpers
# ---------------------------------------------------------------------------------------------

def slug(*parts) -> str:
    """A file name from ``parts`` joined by "-" (empty parts left out, other characters than ``A-Za-z0-9_.+-``
    replaced by "_")."""
    return re.sub(r"[^A-Za-z0-9_.+-]+", "_", "-".join(str(part) for part in parts if part != ""))


def is_paper_case(config, name: str) -> bool:
    """The study's case ``name`` is the paper's case of that name (same aerofoil, Mach, incidence)."""
    from ..config.cases import TEST_CASES

    try:
        case = config.case(name).case
    except Exception:  # noqa: BLE001 - unknown names are simply not paper cases
        return False
    reference = TEST_CASES.get(name)
    return reference is not None and reference.naca == case.naca and reference.mach == case.mach \
        and reference.alpha_deg == case.alpha_deg


def is_paper_gust(config, name: str) -> bool:
    """The study's gust ``name`` is the paper's gust of that name."""
    from ..config.cases import GUST_CASES

    reference = GUST_CASES.get(name)
    return reference is not None and any(gust == reference for gust in config.gusts if gust.name == name)


def is_paper_study(config) -> bool:
    """A case of the study is one of the paper's (the default of paper mode)."""
    return any(is_paper_case(config, study_case.case.name) for study_case in config.cases)


def paper_note(numbers) -> str:
    """The caption's note on the paper's figures ``numbers``: " Analogue of the paper's Figs. N, M." ("" for none)."""
    numbers = sorted(set(numbers))
    if not numbers:
        return ""
    return f" Analogue of the paper's Fig{'s' if len(numbers) > 1 else ''}. {', '.join(map(str, numbers))}."


def _rom_label(rom, multi_T: bool, with_method: bool = True) -> str:
    label = f"N_r={rom.order}, N_ω={rom.M + 1}"
    if multi_T:
        label += f", T={rom.T:.4g}"
    return label + (f", {rom.method}" if with_method else "")


def _method_names(results) -> list:
    return [method.name for method in results.config.methods]


def _case_T_count(results, case) -> int:
    try:
        return len(results.config.case(case).T)
    except Exception:  # noqa: BLE001
        return len({T_key(rom.T) for rom in results.roms if rom.case == case})


def _in_order(values) -> list:
    """``values`` without repeats, in the order they first come."""
    seen = []
    for value in values:
        if value not in seen:
            seen.append(value)
    return seen


# ---------------------------------------------------------------------------------------------
# The data of each family's figures
# ---------------------------------------------------------------------------------------------

def _frf_data(results, paper: bool):
    """One figure per sweep point (case, T, N_omega, N_r): every method's ROM against the LFD."""
    methods = _method_names(results)
    colours = plots.colour_cycle()
    outputs = frf_outputs(results)
    groups: dict = {}
    for rom in results.roms:
        if rom.status == "ok" and rom.frf_rom is not None:
            groups.setdefault((rom.case, T_key(rom.T), rom.M, rom.order), []).append(rom)
    for (case, T, M, order), roms in groups.items():
        sweep = next((frf for (name, frf_T), frf in results.frf.items() if name == case and T_key(frf_T) == T), None)
        if sweep is None:
            continue
        roms.sort(key=lambda rom: methods.index(rom.method) if rom.method in methods else len(methods))
        models = [(rom.method, np.asarray(rom.frf_rom),
                   dict(color=colours[(methods.index(rom.method) if rom.method in methods else i) % len(colours)],
                        ls=plots.LINESTYLES[i % len(plots.LINESTYLES)]))
                  for i, rom in enumerate(roms)]
        step = max(1, sweep.M // M)
        samples = np.arange(0, sweep.M + 1, step) if M != sweep.M else None
        multi_T = _case_T_count(results, case) > 1
        numbers = (PAPER_FRF_FIGURES[(case, order, M + 1)],) \
            if paper and is_paper_case(results.config, case) and (case, order, M + 1) in PAPER_FRF_FIGURES else ()
        yield FigureData(dict(case=case, order=order, N_omega=M + 1, T_tag=f"T{T:.4g}" if multi_T else "",
                              T_text=f", T = {T:.4g}" if multi_T else ""),
                         (sweep.frf.omega, sweep.frf.H, models),
                         dict(outputs=list(sweep.frf.outputs or outputs), samples=samples), numbers)


def _hankel_data(results, paper: bool):
    """One figure per case: the Hankel singular values of each N_omega (and T), the largest set of each."""
    for case in _in_order(rom.case for rom in results.roms):
        best: dict = {}
        orders = set()
        for rom in results.roms:
            if rom.case != case or rom.status != "ok" or rom.hankel_sv is None:
                continue
            orders.add(rom.order)
            key = (T_key(rom.T), rom.M)
            if key not in best or len(rom.hankel_sv) > len(best[key]):
                best[key] = np.asarray(rom.hankel_sv, dtype=float)
        if not best:
            continue
        multi_T = len({key[0] for key in best}) > 1
        sets = [(rf"$N_\omega$ = {M + 1}" + (f", T = {T:.4g}" if multi_T else ""), values)
                for (T, M), values in sorted(best.items(), key=lambda item: (item[0][0], -item[0][1]))]
        yield FigureData(dict(case=case), (sets,), dict(orders=sorted(orders)))


def _error_data(results, paper: bool):
    """One figure per case: FRF and worst gust peak errors against the model order."""
    rows = rom_rows(results)
    worst: dict = {}
    for sim in sim_rows(results):
        for output in ("Cl", "Cm"):
            value = sim.get(f"peak_err_{output}")
            if is_number(value):
                key = (point_key(sim), output)
                worst[key] = max(worst.get(key, 0.0), float(value))
    for row in rows:
        for output in ("Cl", "Cm"):
            if (point_key(row), output) in worst:
                row[f"worst_peak_err_{output}"] = worst[(point_key(row), output)]
    outputs = frf_outputs(results)
    for case in _in_order(row["case"] for row in rows):
        case_rows = [row for row in rows if row["case"] == case]
        metrics = {f"frf_max_err_{output}": f"FRF max error {output} (relative)" for output in outputs}
        metrics.update({f"worst_peak_err_{output}": f"worst gust peak error {output} (relative)"
                        for output in ("Cl", "Cm")
                        if any(is_number(row.get(f"worst_peak_err_{output}")) for row in case_rows)})
        metrics = {key: label for key, label in metrics.items() if any(is_number(row.get(key)) for row in case_rows)}
        if not metrics:
            continue
        group_by = ("T", "M", "method") if _case_T_count(results, case) > 1 else ("M", "method")
        yield FigureData(dict(case=case, clip=ERROR_RANGE[1]), (case_rows, metrics),
                         dict(group_by=group_by, clip=ERROR_RANGE[1]))


def _history_data(results, paper: bool):
    """One figure per LTD reference (case, gust): every ROM's history against it."""
    methods = _method_names(results)
    colours = plots.colour_cycle()
    outputs = history_outputs(results)
    by_pair: dict = {}
    for sim in results.sims:
        by_pair.setdefault((sim.case, sim.gust), []).append(sim)
    for (case, gust), ltd in results.ltd.items():
        sims = by_pair.get((case, gust), [])
        points = _in_order((T_key(sim.T), sim.M, sim.order) for sim in sims)
        points.sort(key=lambda point: (point[0], -point[1], point[2]))
        multi_T = _case_T_count(results, case) > 1
        sims = sorted(sims, key=lambda sim: (points.index((T_key(sim.T), sim.M, sim.order)),
                                             methods.index(sim.method) if sim.method in methods else 99))
        models, colour_key, style_key = [], {}, {}
        for sim in sims:
            method_index = methods.index(sim.method) if sim.method in methods else 0
            colour = colours[points.index((T_key(sim.T), sim.M, sim.order)) % len(colours)]
            style = dict(color=colour, ls=plots.LINESTYLES[method_index % len(plots.LINESTYLES)], lw=1.2)
            models.append((_rom_label(sim, multi_T), {"Cl": sim.cl, "Cm": sim.cm}, style))
            colour_key.setdefault("ROM " + _rom_label(sim, multi_T, with_method=False), colour)
            style_key.setdefault(sim.method, style["ls"])
        numbers = PAPER_HISTORY_FIGURES.get((case, gust), ()) \
            if paper and is_paper_case(results.config, case) and is_paper_gust(results.config, gust) else ()
        yield FigureData(dict(case=case, gust=gust), (ltd.t, {"Cl": ltd.cl, "Cm": ltd.cm}, models),
                         dict(outputs=outputs, u=ltd.u, colour_key=colour_key,
                              style_key=style_key if len(style_key) > 1 else None), numbers)


def _case_ltd_data(results, paper: bool):
    """One figure per gust met by two or more cases: their LTD responses together."""
    x0 = results.config.simulation.x0
    for gust in _in_order(name for (_, name) in results.ltd):
        references = [(case, ltd) for (case, name), ltd in results.ltd.items() if name == gust]
        if len(references) < 2 or len({len(ltd.t) for _, ltd in references}) != 1:
            continue
        t = np.asarray(references[0][1].t) + x0
        models = [(case, {"Cl": ltd.cl, "Cm": ltd.cm}) for case, ltd in references]
        numbers = ()
        if paper and gust == "G3" and is_paper_gust(results.config, "G3") and all(
                is_paper_case(results.config, case) for case in ("T5", "T6")) \
                and {"T5", "T6"} <= {case for case, _ in references}:
            numbers = (28,)
        yield FigureData(dict(gust=gust), (t, None, models),
                         dict(outputs=history_outputs(results),
                              t_label="time since the gust reaches the reference point, s - s_0 [c/U]"), numbers)


def _heatmap_data(results, paper: bool):
    """One figure per output: the peak error of every sweep point (rows) and gust (columns), a panel per method."""
    sims = sim_rows(results)
    if not sims:
        return
    gusts = [gust.name for gust in results.config.gusts]
    methods = [method for method in _method_names(results) if any(sim["method"] == method for sim in sims)]
    points = _in_order((sim["case"], T_key(sim["T"]), sim["M"], sim["order"]) for sim in sims)
    multi_T = len({(point[0], point[1]) for point in points}) > len({point[0] for point in points})
    labels = [f"{case} N_r={order} N_ω={M + 1}" + (f" T={T:.4g}" if multi_T else "")
              for case, T, M, order in points]
    for output in history_outputs(results):
        values = np.full((len(methods), len(points), len(gusts)), np.nan)
        for sim in sims:
            value = sim.get(f"peak_err_{output}")
            if (is_number(value) or value == float("inf")) and sim["gust"] in gusts:  # inf: history overflowed
                values[methods.index(sim["method"]), points.index((sim["case"], T_key(sim["T"]), sim["M"],
                                                                   sim["order"])), gusts.index(sim["gust"])] = value
        finite = values[np.isfinite(values)]
        if not finite.size:
            continue
        positive = finite[finite > 0]
        vmin = max(float(positive.min()), ERROR_RANGE[0]) if positive.size else ERROR_RANGE[0]
        vmax = min(max(float(finite.max()), vmin * 10), ERROR_RANGE[1])
        yield FigureData(dict(output=output, clip=ERROR_RANGE[1]), (values, labels, gusts),
                         dict(methods=methods, output=output, vmin=vmin, vmax=vmax))


# ---------------------------------------------------------------------------------------------
# Figures composed of several plots.* calls
# ---------------------------------------------------------------------------------------------

def keyed_history_plot(t, reference, models, *, colour_key, style_key, title, **options):
    """:func:`studies.report.plots.history_plot` with one key of colours (sweep points) and line styles (methods)
    outside the axes instead of a legend per model."""
    fig, axes = plots.history_plot(t, reference, models, title=title, legend=False, **options)
    plots.key_legend(axes[1, -1], colour_key, style_key, ref_label="LTD", outside=True)
    fig.tight_layout()
    return fig, axes


def method_heatmaps_plot(values, row_labels, col_labels, *, methods, output, vmin, vmax, title):
    """One :func:`studies.report.plots.heatmap_plot` panel per method (``values[i]`` is method ``i``'s) on a common
    colour scale, with one colour bar."""
    from matplotlib.colors import LogNorm
    from matplotlib.ticker import LogLocator

    plt = plots.pyplot()
    heights = [len(row_labels) + 1.5 for _ in methods]
    # (at least 3 in high: a one-row, one-method map left the colour bar's ticks and label no room)
    fig, axes = plt.subplots(len(methods), 1, figsize=(0.95 * len(col_labels) + 4.2, max(0.36 * sum(heights) + 0.8, 3.0)),
                             squeeze=False, layout="constrained", gridspec_kw=dict(height_ratios=heights))
    for ax, method, panel in zip(axes[:, 0], methods, values):
        plots.heatmap_plot(panel, row_labels, col_labels, ax=ax, vmin=vmin, vmax=vmax, colorbar=False,
                           title=f"method {method}")
    fig.suptitle(title, fontsize=10)
    colour_bar = fig.colorbar(axes[0, 0].images[0], ax=list(axes[:, 0]), fraction=0.05, pad=0.02, shrink=0.8)
    colour_bar.set_label(f"peak error {output}", fontsize=9)
    colour_bar.formatter = plots.percent_formatter()
    if isinstance(colour_bar.norm, LogNorm):   # minor ticks at 2 and 5 per decade, as percentages (not 2e-2)
        colour_bar.ax.yaxis.set_minor_locator(LogLocator(subs=(2.0, 5.0)))
        colour_bar.ax.yaxis.set_minor_formatter(plots.percent_formatter())
    return fig, axes


# ---------------------------------------------------------------------------------------------
# The table of figure families and the loop
# ---------------------------------------------------------------------------------------------

FIGURE_SPECS = (
    FigureSpec("frf", "frf", _frf_data, ("frf", "{case}", "{T_tag}", "N{N_omega}", "r{order}"), plots.frf_plot,
               "{case}: ROM (N_r = {order}, N_ω = {N_omega}{T_text}) against LFD",
               "{title}: magnitude, phase (unwrapped) and error against the reduced frequency k = ω/2, per radian of "
               "gust angle.{paper_note}"),
    FigureSpec("hankel", "hankel", _hankel_data, ("hankel", "{case}"), plots.hankel_plot,
               "{case}: Hankel singular values of the subspace step",
               "{title}, normalised by the largest; dotted lines: the model orders of the study (the N_r largest "
               "values are kept)."),
    FigureSpec("errors", "orders", _error_data, ("errors", "{case}"), plots.error_vs_order_plot,
               "{case}: errors against the model order",
               "{title} for each N_ω (colour) and method (line style): FRF error over the full LFD grid "
               "(peak-normalised, sysid.metrics) and the largest relative peak error over the gusts; crosses mark "
               "unstable ROMs, triangles errors above {clip:.0%} (drawn there)."),
    FigureSpec("history", "histories", _history_data, ("history", "{case}", "{gust}"), keyed_history_plot,
               "{case}: response to gust {gust}, ROMs against LTD",
               "{title}: gust angle at the reference point, load perturbations and ROM - LTD; colour: sweep point, "
               "line style: method.{paper_note}"),
    FigureSpec("ltd", "cases", _case_ltd_data, ("ltd", "{gust}"), plots.history_plot,
               "LTD responses to gust {gust}",
               "{title} of every case, against the time since the gust front reached the reference point."
               "{paper_note}"),
    FigureSpec("heatmap", "heatmaps", _heatmap_data, ("heatmap", "peak", "{output}"), method_heatmaps_plot,
               "Peak error of {output}, ROM against LTD (load envelope):\n"
               "max(|max ROM - max LTD|, |min ROM - min LTD|) / max |LTD|",
               "{title}; rows: sweep points, columns: gusts, one panel per method (common log colour scale, clipped "
               "at {clip:.0%}; inf: the ROM's history overflowed; hatched: no history).",
               save=dict(palette=False)),  # a palette would band the continuous colour bar
)
"""The figure families of a report, in the order they are drawn (file names ``figures/NAME-....png``)."""


def draw_figures(results, fig_dir: Path, dpi: int, say, paper: bool = False) -> list:
    """Draw every figure of every family of :data:`FIGURE_SPECS` into ``fig_dir``; the :class:`Figure` list."""
    figures = []
    for spec in FIGURE_SPECS:
        for data in spec.select(results, paper):
            title = spec.title.format(**data.fields)
            fig, _ = spec.plot(*data.args, title=title, **data.options)
            name = slug(*(part.format(**data.fields) for part in spec.file)) + ".png"
            path = plots.save_figure(fig, fig_dir / name, dpi=dpi, **spec.save)
            caption = spec.caption.format(title=title.replace("\n", " "), paper_note=paper_note(data.paper_figures),
                                          **data.fields)
            figures.append(Figure(spec.section, path, caption))
            say(f"  {path}")
    return figures


FIGURE_CODE = ("studies.report.plots", "studies.report.plot_style", "studies.report.plot_data",
               "studies.report.figure_files", "studies.report.frf_plots", "studies.report.hankel_plots",
               "studies.report.error_plots", "studies.report.history_plots", "studies.report.heatmap_plots",
               "studies.report.make", "studies.report.figures", "studies.report.rows")
"""The modules whose source is part of the figures' fingerprint."""


def figure_fingerprint(config, tables: dict, dpi: int, paper: bool) -> str:
    """sha256 of everything the figures depend on: the study, the tables' rows (every metric and every piece's
    compute time, so that any recomputed piece changes it), the resolution, paper mode, and the plotting code."""
    import matplotlib

    from ..store.provenance import source_hash

    blob = json.dumps(dict(study=config.canonical_json(), rows={name: table[0] for name, table in tables.items()},
                           dpi=dpi, paper=bool(paper), code=source_hash(FIGURE_CODE),
                           matplotlib=matplotlib.__version__), sort_keys=True, default=repr)
    return hashlib.sha256(blob.encode()).hexdigest()


def cached_figures(fig_dir: Path, fingerprint: str) -> Optional[list]:
    """The figures listed by the manifest when it has this fingerprint and every file still exists, else None."""
    try:
        data = json.loads((fig_dir / FIGURE_MANIFEST).read_text(encoding="utf-8"))
        if data.get("fingerprint") != fingerprint:
            return None
        figures = [Figure(entry["section"], fig_dir / entry["file"], entry["caption"]) for entry in data["figures"]]
    except (OSError, ValueError, KeyError, TypeError):
        return None
    return figures if all(figure.path.is_file() for figure in figures) else None


def write_manifest(fig_dir: Path, fingerprint: str, figures: list) -> None:
    """Write ``figures/manifest.json``: the fingerprint and each figure's section, file and caption."""
    data = dict(fingerprint=fingerprint, figures=[dict(section=figure.section, file=figure.path.name,
                                                       caption=figure.caption) for figure in figures])
    atomic_write_bytes(fig_dir / FIGURE_MANIFEST, (json.dumps(data, indent=1) + "\n").encode("utf-8"))


def report_figures(results, tables: dict, fig_dir: Path, *, dpi: int, paper: bool, redraw: bool, say) -> list:
    """The report's figures: those of the manifest when it is up to date (and ``redraw`` is false), else drawn
    anew (:func:`draw_figures`) and listed in a new manifest."""
    config = results.config
    fingerprint = figure_fingerprint(config, tables, dpi, paper)
    cached = None if redraw else cached_figures(fig_dir, fingerprint)
    if cached is not None:
        say(f"report {config.name}: {len(cached)} figures up to date ({fig_dir / FIGURE_MANIFEST}), not redrawn")
        return cached
    figures = draw_figures(results, fig_dir, dpi, say, paper)
    write_manifest(fig_dir, fingerprint, figures)
    return figures
