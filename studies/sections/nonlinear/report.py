"""The report's "Where the linear models hold" section: the nonlinear marches against the LTD and the ROMs.

Reads the study's ``nonlinear`` pieces (:func:`studies.sections.nonlinear.study.load_linearity`; nothing is computed
here) and writes

=========================================== ==========================================================
where                                       what
=========================================== ==========================================================
``tables/linearity.{csv,md,tex}``           one row per march: peak ratios and history errors of the LTD
                                            and of the case's first ROM, solver counts, time
``figures/linearity-map-ltd.png``           heat maps (cases x gusts, one column of panels per amplitude,
``figures/linearity-map-rom.png``           Cl above, Cm below) of the history error of the LTD / the ROM
``figures/linearity-CASE.png``              the histories (per unit gust input) of the case's gust with
                                            the largest Cl error of the LTD: nonlinear at each amplitude,
                                            LTD, ROM
=========================================== ==========================================================

and returns the Markdown of the section, which :func:`studies.report.write_report` appends to the page.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Callable, Optional

import numpy as np

from ...store.files import atomic_savefig, page_link, safe_name
from .schema import gust_shapes, march_end
from .study import load_linearity
from ...report.tables import Column, format_table, write_tables

__all__ = ["nonlinear_section", "linearity_rows", "linearity_grid", "linearity_limits", "LINEARITY_COLUMNS",
           "LIMIT_COLUMNS", "THRESHOLDS",
           "linearity_map_plot", "linearity_history_plot"]

THRESHOLDS = (0.01, 0.05, 0.10)
"""History-error levels the section counts (1 %, 5 %, 10 % of the linear model's peak)."""

LINEARITY_COLUMNS = (
    Column("case", "case"),
    Column("gust", "gust"),
    Column("amplitude_deg", "angle (deg)", ".3g"),
    Column("ltd_ratio_Cl", "Cl peak NL/LTD", ".4f"),
    Column("ltd_error_Cl", "Cl err LTD", ".2%"),
    Column("ltd_ratio_Cm", "Cm peak NL/LTD", ".4f"),
    Column("ltd_error_Cm", "Cm err LTD", ".2%"),
    Column("rom_ratio_Cl", "Cl peak NL/ROM", ".4f"),
    Column("rom_error_Cl", "Cl err ROM", ".2%"),
    Column("rom_ratio_Cm", "Cm peak NL/ROM", ".4f"),
    Column("rom_error_Cm", "Cm err ROM", ".2%"),
    Column("max_local_mach", "max local Mach", ".3f"),
    Column("iterations_per_step", "iterations / step", ".2f"),
    Column("n_factorisations", "factorisations", "d"),
    Column("seconds", "seconds", ".1f"),
    Column("status", "status"),
    Column("notes", "notes"),
)
"""Columns of the linearity table (keys of the CSV; headers of the Markdown and LaTeX)."""


def linearity_rows(records) -> list:
    """One dict per :class:`studies.sections.nonlinear.study.LinearityRecord` (keys of :data:`LINEARITY_COLUMNS`)."""
    rows = []
    for r in records:
        row = dict(case=r.case, gust=r.gust, amplitude_deg=r.amplitude_deg,
                   status="ok" if r.ok else f"{r.status}: " + (r.error or "")[:160], notes=_notes(r))
        if r.ok:
            md = r.metadata
            row.update({f"ltd_{k}": v for k, v in r.ltd.items()})
            row.update({f"rom_{k}": v for k, v in r.rom().items()})
            row.update(max_local_mach=md.get("max_local_mach"), iterations_per_step=md.get("iterations_per_step"),
                       n_factorisations=md.get("n_factorisations"), seconds=md.get("seconds"))
        rows.append(row)
    return rows


def _notes(record) -> str:
    """Short flags for the solver's warnings of a march (stored with the piece)."""
    notes = []
    for w in record.metadata.get("warnings", []):
        if "separat" in w:
            notes.append("peak local Mach above the separation limit: a viscous flow would separate")
        elif "phase" in w:
            notes.append("dt coarse for the gust (BDF2 phase error above 1 %; the LTD has the same)")
    return "; ".join(dict.fromkeys(notes))


def _history_error(record, model: str, output: str) -> float:
    """The history error of ``model`` ("ltd" or "rom": the case's closest ROM) in ``output``; NaN if absent."""
    measures = record.ltd if model == "ltd" else record.rom()
    return float(measures.get(f"error_{output}", math.nan))


def linearity_grid(records, model: str, output: str) -> tuple:
    """The history errors as arrays for the heat maps.

    Parameters
    ----------
    records : list of LinearityRecord
    model : {"ltd", "rom"}
    output : {"Cl", "Cm"}

    Returns
    -------
    cases, gusts : list of str
    amplitudes : ndarray, shape (a,)
    values : ndarray, shape (a, len(cases), len(gusts))
        NaN where no march is stored or the linear model is missing; ``inf`` where the march failed (the
        linear model could not be judged: drawn in the top colour).
    """
    cases = list(dict.fromkeys(r.case for r in records))
    gusts = list(dict.fromkeys(r.gust for r in records))
    amps = np.array(sorted({r.amplitude_deg for r in records}))
    v = np.full((amps.size, len(cases), len(gusts)), np.nan)
    for r in records:
        i, j, k = int(np.searchsorted(amps, r.amplitude_deg)), cases.index(r.case), gusts.index(r.gust)
        if not r.ok:
            v[i, j, k] = np.inf
            continue
        v[i, j, k] = _history_error(r, model, output)
    return cases, gusts, amps, v


def linearity_map_plot(records, model: str, *, vmin: float = 1e-4, vmax: float = 1.0, title: str = ""):
    """Heat maps of the history error of the LTD or the ROM: one column of panels per amplitude, Cl above, Cm
    below, cases down, gusts across.

    Parameters
    ----------
    records : list of LinearityRecord
    model : {"ltd", "rom"}
    vmin, vmax : float
        Shared colour limits (relative errors; log scale).
    title : str

    Returns
    -------
    matplotlib.figure.Figure
    """
    from ...report.heatmap_plots import heatmap_plot
    from ...report.plot_style import pyplot

    plt = pyplot()
    _, _, amps, _ = linearity_grid(records, model, "Cl")
    fig, axes = plt.subplots(2, amps.size, figsize=(2.9 * amps.size + 1.2, 6.8), squeeze=False, layout="constrained")
    for row, output in enumerate(("Cl", "Cm")):
        cases, gusts, amps, v = linearity_grid(records, model, output)
        for i, a in enumerate(amps):
            heatmap_plot(v[i], cases, gusts, vmin=vmin, vmax=vmax, colorbar=False, ax=axes[row, i],
                         title=f"{output}, {a:g} deg")
    fig.colorbar(axes[0, 0].images[0], ax=axes, shrink=0.8,
                 label=f"history error of the {'LTD' if model == 'ltd' else 'ROM'} / its peak")
    if title:
        fig.suptitle(title, fontsize=10)
    return fig


def linearity_history_plot(records, case: str, gust: str, *, title: str = ""):
    """The nonlinear histories of one case and gust per unit gust input (``/ tan(angle)``) at each amplitude,
    with the LTD's and the ROM's (one line each: they are linear): Cl above, Cm below.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from ...report.plot_style import pyplot

    plt = pyplot()
    rs = sorted((r for r in records if r.case == case and r.gust == gust and r.ok), key=lambda r: r.amplitude_deg)
    fig, axes = plt.subplots(2, 1, figsize=(8.0, 6.0), sharex=True)
    colours = plt.get_cmap("viridis")(np.linspace(0.0, 0.85, max(len(rs), 1)))
    for ax, name in zip(axes, ("cl", "cm")):
        for r, c in zip(rs, colours):
            A = math.tan(math.radians(r.amplitude_deg))
            ax.plot(r.t, getattr(r, name) / A, color=c, lw=1.3, label=f"nonlinear, {r.amplitude_deg:g} deg")
        longest = max(rs, key=lambda r: r.t.size, default=None)
        if longest is not None:
            A = math.tan(math.radians(longest.amplitude_deg))
            for attr, style, label in ((f"ltd_{name}", dict(color="k", ls="--", lw=1.2), "LTD"),
                                       (f"rom_{name}", dict(color="tab:red", ls=":", lw=1.5), "ROM")):
                y = getattr(longest, attr)
                if y.size:
                    ax.plot(longest.t, y / A, label=label, **style)
        ax.set_ylabel(f"{'Cl' if name == 'cl' else 'Cm'} / tan(gust angle)")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8, ncol=2)
    axes[-1].set_xlabel("convective time s = t U / c")
    if title:
        axes[0].set_title(title, fontsize=10)
    fig.tight_layout()
    return fig


def linearity_limits(records, model: str, output: str) -> list:
    """Per (case, gust): the largest marched angle up to which the linear model's history error stays within
    each of :data:`THRESHOLDS`, and the log-log slope of the error against the angle.

    Parameters
    ----------
    records : list of LinearityRecord
    model : {"ltd", "rom"}
    output : {"Cl", "Cm"}

    Returns
    -------
    list of dict
        ``case``, ``gust``, ``within_1``, ``within_5``, ``within_10`` (deg; 0 when the smallest angle already
        exceeds it, NaN when the linear model is not stored; an angle counts only if every smaller one is within
        too, and a march that stopped or failed ends the run of angles) and ``slope`` (least squares of ``log error`` on ``log angle`` over the marched angles: 1 when
        the error is the second-order term of a smooth response, 2 for the third-order one; NaN with fewer than
        two angles).
    """
    out = []
    pairs = list(dict.fromkeys((r.case, r.gust) for r in records))
    for case, gust in pairs:
        rs = sorted((r for r in records if (r.case, r.gust) == (case, gust)), key=lambda r: r.amplitude_deg)
        row = dict(case=case, gust=gust)
        errors = [_history_error(r, model, output) if r.ok else math.inf
                  for r in rs]
        judged = [e for e in errors if not math.isinf(e)]
        absent = bool(judged) and all(math.isnan(e) for e in judged)  # marches, but no linear model to judge
        for t in THRESHOLDS:
            best = math.nan if absent else 0.0
            for r, e in zip(rs, errors):
                if absent or not e <= t:
                    break
                best = r.amplitude_deg
            row[f"within_{round(100 * t)}"] = best
        pts = [(r.amplitude_deg, _history_error(r, model, output))
               for r in rs if r.ok]
        pts = [(a, e) for a, e in pts if np.isfinite(e) and e > 0]
        row["slope"] = (float(np.polyfit(np.log([a for a, _ in pts]), np.log([e for _, e in pts]), 1)[0])
                        if len(pts) >= 2 else math.nan)
        out.append(row)
    return out


LIMIT_COLUMNS = (
    Column("case", "case"),
    Column("gust", "gust"),
    Column("within_1", "within 1 % up to (deg)", ".3g"),
    Column("within_5", "within 5 % up to (deg)", ".3g"),
    Column("within_10", "within 10 % up to (deg)", ".3g"),
    Column("slope", "slope of the error", ".2f"),
)
"""Columns of the limits tables (:func:`linearity_limits`)."""


def _count_line(records, model: str, output: str) -> str:
    parts = []
    for a in sorted({r.amplitude_deg for r in records}):
        errs = [_history_error(r, model, output)
                for r in records if r.amplitude_deg == a and r.ok]
        errs = [e for e in errs if np.isfinite(e)]
        n_all = sum(r.amplitude_deg == a for r in records)
        n_stop = sum(r.amplitude_deg == a and not r.ok for r in records)
        within = " / ".join(str(sum(e <= t for e in errs)) for t in THRESHOLDS)
        parts.append(f"{a:g} deg: {within} of {n_all}" + (f" ({n_stop} stopped or failed)" if n_stop else ""))
    return "; ".join(parts)


def _cost_line(records, results) -> str:
    """The marches' cost against the LTD's, per time step (wall seconds of the pieces)."""
    ok = [r for r in records if r.ok and np.isfinite(r.metadata.get("seconds", math.nan))]
    if not ok:
        return ""
    per_step = np.array([r.metadata["seconds"] / max(r.t.size - 1, 1) for r in ok])
    total = float(sum(r.metadata["seconds"] for r in ok))
    ltd = [rec.seconds / max(rec.t.size - 1, 1) for (case, _), rec in results.ltd.items()
           if np.isfinite(rec.seconds) and case in {r.case for r in ok}]
    text = (f"**Cost**: {len(ok)} marches in {total / 60:.1f} min of worker time, {1e3 * np.median(per_step):.1f} ms "
            f"per step (median; {1e3 * per_step.min():.1f} - {1e3 * per_step.max():.1f}), iterations per step "
            f"{np.median([r.metadata.get('iterations_per_step', math.nan) for r in ok]):.2f} (median)")
    if ltd:
        text += (f"; the LTD: {1e3 * np.median(ltd):.1f} ms per step and gust (median; its gusts are marched "
                 f"together, one back-substitution with several right-hand sides), so a nonlinear gust costs "
                 f"{np.median(per_step) / np.median(ltd):.0f}x an LTD gust here")
    return text + ". Wall times of the pieces, on the machine and with the load of the run.\n"


def nonlinear_section(results, out_dir, page_dir, *, figures: bool = True, dpi: int = 120,
                      say: Optional[Callable[[str], None]] = None) -> str:
    """Write the linearity table and figures of a study and return the page's section.

    Parameters
    ----------
    results : studies.store.results.StudyResults
        Its ``config.nonlinear`` names the marches; its LTD and ROM histories are the linear models.
    out_dir : path-like
        The report's folder (``tables/`` and ``figures/`` in it).
    page_dir : path-like
        The page's folder (links are relative to it).
    figures : bool
        Draw the figures; False: the table only.
    dpi : int
    say : callable, optional
        Progress messages.

    Returns
    -------
    str
        Markdown (empty when the study has no ``[nonlinear]`` section).
    """
    config = results.config
    opts = getattr(config, "nonlinear", None)
    if opts is None:
        return ""
    say = say or (lambda message: None)
    out_dir, page_dir = Path(out_dir), Path(page_dir)
    records = load_linearity(results)
    sim = config.simulation
    blocks = ["## Where the linear models hold: the nonlinear Euler equations\n"]
    own = (f" and each gust's own angle up to {opts.max_angle:g} deg" if opts.gust_angle else "")
    blocks.append(
        f"The nonlinear Euler equations with the gust (`cfd.unsteady_response`, {config.cfd.gust_method.upper()}, "
        f"BDF2 with chord-Newton steps on the exact Jacobian; docs/nonlinear.md) for cases {', '.join(opts.cases)} "
        f"and gusts {', '.join(opts.gusts)} at gust angles {', '.join(f'{a:g}' for a in opts.amplitudes) or '-'} "
        f"deg{own}, with the study's `dt = {sim.dt:g}` and gust start `x0 = {sim.x0:g}` (those of the LTD, so that "
        f"the difference is the nonlinearity alone), each until the gust has left the trailing edge {opts.tail:g} "
        f"chords before (sharp-edged: {2 * opts.tail:g} chords after it reached the trailing edge). Each is "
        "compared with the linear models of the same gust shape, scaled to its angle: the LTD and the case's "
        "ROM. *Peak ratio*: `max|y_NL| / max|y_lin|` (above 1: the linear model under-predicts the peak load); "
        "*history error*: `max_t |y_NL - y_lin| / max_t |y_lin|` over the march.\n")
    ends = ", ".join(f"{label} {march_end(opts, g, sim):g}" for label, g, _ in gust_shapes(opts, config.gusts))
    blocks.append(f"March ends (convective time s): {ends}. Gusts of the same shape (kind and length) share "
                  "their marches (the LTD and ROM of the first are the linear models; the others differ only "
                  "in angle).\n")
    if not records:
        blocks.append("No nonlinear march is in the store yet (see the missing and failed pieces above); run "
                      f"`lfdrom run {config.source}`.\n")
        return "\n".join(blocks)

    rom_names = sorted({next(iter(r.roms), "") for r in records if r.ok and r.roms} - {""})
    blocks.append("**How many (case, gust) pairs stay within 1 % / 5 % / 10 % history error**, per gust angle:\n")
    for model, label in (("ltd", "LTD"), ("rom", "ROM" + (f" ({', '.join(rom_names)})" if rom_names else ""))):
        for output in ("Cl", "Cm"):
            line = _count_line(records, model, output)
            if line:
                blocks.append(f"- {label}, {output}: {line}")
    blocks.append("")
    blocks.append(_cost_line(records, results))
    failed = [r for r in records if not r.ok]
    if failed:
        blocks.append("")
        blocks.append(f"**{len(failed)} march(es) stopped or failed** (the linear models cannot be judged there; "
                      "stopped: the solver stopped at a step it could not resolve, or the march was skipped after a "
                      "smaller angle of its gust stopped; the message):\n")
        blocks += [f"- {r.case} {r.gust} {r.amplitude_deg:g} deg: {r.error}" for r in failed]
    blocks.append("")

    limit_blocks = ["**Where the linear models hold**: per case and gust, the largest gust angle up to which the "
                    "history error stays within 1 %, 5 %, 10 % (0: not even at the smallest angle marched). For the "
                    "LTD also the log-log slope of its error against the angle: 1 where the error is the "
                    "second-order term of a smooth response, 2 where it is the third-order one (Cl and Cm of a "
                    "symmetric aerofoil at zero incidence are odd in the gust), other values where the discrete "
                    "response is not smooth over these angles (a shock moving across cells, the switches of the "
                    "JST sensor: docs/nonlinear.md). The ROM's error also holds its own identification error, "
                    "which dominates at small angles.\n"]
    for model, label in (("rom", "ROM"), ("ltd", "LTD")):
        if model == "rom" and not rom_names:
            continue
        columns = LIMIT_COLUMNS if model == "ltd" else LIMIT_COLUMNS[:-1]
        for output in ("Cl", "Cm"):
            lim = linearity_limits(records, model, output)
            write_tables(lim, out_dir / "tables" / f"linearity-limits-{model}-{output}", columns,
                         caption=f"{config.name}: where the {label} holds ({output})",
                         label=f"tab:{config.name}-limits-{model}-{output}")
            limit_blocks.append(f"*{label}, {output}:*\n")
            limit_blocks.append(format_table(lim, columns, "markdown"))
    rows = linearity_rows(records)
    columns = [c for c in LINEARITY_COLUMNS if any(c.key in r for r in rows)]  # no ROM columns without ROMs
    write_tables(rows, out_dir / "tables" / "linearity", columns, caption=f"{config.name}: linearity",
                 label=f"tab:{config.name}-linearity")
    if figures:
        fig_dir = out_dir / "figures"
        fig_dir.mkdir(parents=True, exist_ok=True)
        import matplotlib.pyplot as plt

        for model, label in (("ltd", "LTD"), ("rom", "ROM")):
            if model == "rom" and not rom_names:
                continue
            path = fig_dir / f"linearity-map-{model}.png"
            fig = linearity_map_plot(records, model, title=f"{config.name}: history error of the {label} against "
                                                           "the nonlinear Euler response")
            atomic_savefig(fig, path, dpi=dpi)
            plt.close(fig)
            say(f"report {config.name}: {path.name}")
            blocks.append(f"![History error of the {label}]({page_link(path, page_dir)})\n")
            blocks.append(f"*History error of the {label} against the nonlinear response, relative to the "
                          f"{label}'s peak, per case (rows), gust (columns) and gust angle (panels); Cl above, Cm "
                          "below; hatched: not marched; top colour with 'inf': the march failed.*\n")
        for case in dict.fromkeys(r.case for r in records):
            worst = max((r for r in records if r.case == case and r.ok and np.isfinite(r.ltd.get("error_Cl", np.nan))),
                        key=lambda r: r.ltd["error_Cl"], default=None)
            if worst is None:
                continue
            path = fig_dir / f"linearity-case-{safe_name(case)}.png"
            fig = linearity_history_plot(records, case, worst.gust,
                                         title=f"{config.name}: {case}, gust {worst.gust} (the largest Cl error of "
                                               f"the LTD: {worst.ltd['error_Cl']:.2%} at {worst.amplitude_deg:g} deg)")
            atomic_savefig(fig, path, dpi=dpi)
            plt.close(fig)
            say(f"report {config.name}: {path.name}")
            blocks.append(f"![{case} {worst.gust} at every amplitude]({page_link(path, page_dir)})\n")
            blocks.append(f"*{case}, gust {worst.gust} (the case's largest Cl history error of the LTD): the "
                          "nonlinear Cl and Cm per unit gust input (divided by tan of the gust angle) at each angle "
                          f"marched, with the LTD and the ROM (linear: one line each). At {worst.amplitude_deg:g} "
                          f"deg the LTD's history error is {worst.ltd.get('error_Cl', math.nan):.2%} in Cl and "
                          f"{worst.ltd.get('error_Cm', math.nan):.2%} in Cm.*\n")
    blocks += limit_blocks
    blocks.append(f"**Every march** ([CSV]({page_link(out_dir / 'tables' / 'linearity.csv', page_dir)})):\n")
    blocks.append(format_table(rows, columns, "markdown"))
    return "\n".join(blocks)
