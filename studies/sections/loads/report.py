"""The report's "Gust loads" part: flight points, the envelope, a table and a figure per flight point.

Reads the study's ``loads`` pieces (:func:`studies.sections.loads.study.load_loads`; nothing is computed here) and
writes

========================================== ============================================================
where                                      what
========================================== ============================================================
``tables/loads-points.{csv,md,tex}``       the flight points: Mach, altitude, chord, F_g, rho, TAS, EAS, q,
                                           ``U_ref``, ``U_sigma``, the ROM
``tables/loads-envelope.{csv,md,tex}``     per output: the largest tuned-gust and turbulence design load over the
                                           flight points, and where
``tables/loads-POINT.{csv,md,tex}``        per output at one point: critical H, sign, peak (coefficient and SI),
                                           ``A_bar``, ``N0``, design load (coefficient and SI), error estimates
``figures/loads-POINT.png``                correlated loads (potato), load against H, response PSD
``figures/loads-envelope.png``             the correlated loads of every flight point together
========================================== ============================================================
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ...report.tables import Column, format_table, write_tables
from ...store.entries import open_store
from ...store.files import atomic_savefig, page_link as _rel, safe_name as _safe
from .study import load_loads

__all__ = ["loads_report", "point_rows", "envelope_rows", "POINT_COLUMNS", "LOADS_COLUMNS", "ENVELOPE_COLUMNS"]

FT = 0.3048

POINT_COLUMNS = (
    Column("point", "flight point"),
    Column("case", "case"),
    Column("mach", "Mach", ".3g"),
    Column("altitude_m", "altitude (m)", ".6g"),
    Column("chord_m", "chord (m)", ".4g"),
    Column("F_g", "F_g", ".4f"),
    Column("design_speed", "speed"),
    Column("rho", "rho (kg/m^3)", ".4f", r"$\rho$ (kg/m$^3$)"),
    Column("tas", "TAS (m/s)", ".2f"),
    Column("eas", "EAS (m/s)", ".2f"),
    Column("q", "q (kPa)", ".3f"),
    Column("time_scale", "c/U (ms)", ".2f"),
    Column("u_ref", "U_ref (m/s EAS)", ".3f", r"$U_\mathrm{ref}$ (m/s EAS)"),
    Column("u_sigma", "U_sigma (m/s TAS)", ".3f", r"$U_\sigma$ (m/s TAS)"),
    Column("rom", "ROM"),
    Column("f_data", "ROM data up to (Hz)", ".4g"),
    Column("seconds", "CPU (s)", ".2f"),
)
"""Columns of the flight-point table."""

LOADS_COLUMNS = (
    Column("output", "output"),
    Column("critical_H_m", "critical H (m)", ".4g"),
    Column("critical_H_ft", "critical H (ft)", ".4g"),
    Column("sign", "gust"),
    Column("peak", "tuned peak", ".5g"),
    Column("peak_si", "tuned peak (SI)", ".5g"),
    Column("unit", "unit"),
    Column("a_bar", "A_bar (per m/s)", ".5g", r"$\bar A$ (per m/s)"),
    Column("n0", "N0 (1/s)", ".4g", r"$N_0$ (1/s)"),
    Column("design", "turbulence design", ".5g"),
    Column("design_si", "turbulence design (SI)", ".5g"),
    Column("quad_err", "quadrature err", ".1e"),
    Column("trunc_err", "truncation err", ".1e"),
)
"""Columns of a flight point's loads table (coefficients, and SI per unit span beside them)."""

ENVELOPE_COLUMNS = (
    Column("output", "output"),
    Column("unit", "unit"),
    Column("tuned_si", "largest tuned peak (SI)", ".5g"),
    Column("tuned_point", "tuned at"),
    Column("tuned_H_m", "its H (m)", ".4g"),
    Column("design_si", "largest turbulence design (SI)", ".5g"),
    Column("design_point", "turbulence at"),
    Column("ratio", "turbulence / tuned", ".3f"),
)
"""Columns of the envelope table."""


def point_rows(records) -> list:
    """One dict per flight point (keys of :data:`POINT_COLUMNS`)."""
    rows = []
    for r in records:
        s, a = r.spec, r.atmosphere
        rows.append(dict(point=s.name, case=s.case, mach=s.mach, altitude_m=s.altitude_m, chord_m=s.chord_m,
                         F_g=s.F_g, design_speed=s.design_speed, rho=a["rho"], tas=a["tas"], eas=a["eas"],
                         q=a["q"] / 1e3, time_scale=1e3 * a["time_scale"], u_ref=a["u_ref"], u_sigma=r.u_sigma,
                         rom=f"order {r.rom['order']}, M {r.rom['M']}, {r.rom['method']}",
                         f_data=data_band_hz(r), seconds=r.seconds))
    return rows


def data_band_hz(record) -> float:
    """The highest finite frequency (Hz) of the LFD data the point's ROM was identified from: the last but one
    point of McKelvey's grid (``sysid.mckelvey_grid(M, T)``: ``omega = (2 / T) tan(pi k / (2 M))``, the last one is
    infinite) in convective units, at the point's ``U / c``."""
    T, M = float(record.rom["T"]), int(record.rom["M"])
    omega = (2.0 / T) * math.tan(math.pi * (M - 1) / (2 * M))
    return omega / (2.0 * math.pi * record.atmosphere["time_scale"])


def loads_rows(record) -> list:
    """One dict per output of one flight point (keys of :data:`LOADS_COLUMNS`)."""
    rows = []
    for o in record.outputs:
        rows.append(dict(output=o, critical_H_m=record.critical_H[o], critical_H_ft=record.critical_H[o] / FT,
                         sign="up" if record.gust_sign[o] > 0 else "down", peak=record.peak[o],
                         peak_si=record.dimensional[o], unit=record.units[o], a_bar=record.a_bar[o], n0=record.n0[o],
                         design=record.design[o], design_si=record.design_dimensional[o],
                         quad_err=record.quadrature_error[o], trunc_err=record.truncation_error[o]))
    return rows


def envelope_rows(records) -> list:
    """Per output: the largest dimensional tuned-gust and turbulence loads over the flight points."""
    rows = []
    for o in records[0].outputs:
        have = [r for r in records if o in r.outputs]
        t = max(have, key=lambda r: abs(r.dimensional[o]))
        d = max(have, key=lambda r: abs(r.design_dimensional[o]))
        tuned, design = abs(t.dimensional[o]), abs(d.design_dimensional[o])
        rows.append(dict(output=o, unit=t.units[o], tuned_si=tuned, tuned_point=t.spec.name,
                         tuned_H_m=t.critical_H[o], design_si=design, design_point=d.spec.name,
                         ratio=design / tuned if tuned > 0 else math.nan))
    return rows


def _axes_pair(record):
    outs = list(record.outputs)
    if len(outs) >= 2:
        return outs[0], outs[1]
    return outs[0], (record.all_outputs[1] if len(record.all_outputs) > 1 else outs[0])


def _point_figure(record, title):
    import matplotlib.pyplot as plt

    import loads

    tg, ct = record.results()
    x, y = _axes_pair(record)
    fig, axs = plt.subplots(1, 3, figsize=(15.0, 4.6))
    loads.correlated_loads_plot(tg, ct if y in ct.outputs and x in ct.outputs else None, x=x, y=y, ax=axs[0])
    loads.load_vs_H_plot(tg, ax=axs[1])
    loads.psd_plot(ct, ax=axs[2])
    axs[2].axvline(data_band_hz(record), color="0.5", ls=":", lw=1.0)
    axs[2].annotate("ROM data end", (data_band_hz(record), 0.02), xycoords=("data", "axes fraction"), rotation=90,
                    fontsize=7, color="0.4", ha="right", va="bottom")
    from matplotlib.ticker import MaxNLocator

    axs[0].xaxis.set_major_locator(MaxNLocator(5))
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return fig


def _envelope_figure(records, title):
    import matplotlib.pyplot as plt

    import loads

    x, y = _axes_pair(records[0])
    fig, ax = plt.subplots(figsize=(7.5, 5.5))
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for k, r in enumerate(records):
        tg, ct = r.results()
        c = colours[k % len(colours)]
        if x in ct.outputs and y in ct.outputs:
            ex, ey = loads.turbulence_ellipse(ct, x, y)
            ax.plot(ex, ey, "-", color=c, lw=1.0, label=r.spec.name)
        for o in tg.outputs:
            px = tg.correlated[o][x] * r.scales[x]
            py = tg.correlated[o][y] * r.scales[y]
            ax.plot([px, -px], [py, -py], "o", color=c, mfc="none", ms=5)
    ax.axhline(0.0, color="0.8", lw=0.6, zorder=0)
    ax.axvline(0.0, color="0.8", lw=0.6, zorder=0)
    ux = records[0].all_units[list(records[0].all_outputs).index(x)]
    uy = records[0].all_units[list(records[0].all_outputs).index(y)]
    ax.set_xlabel(f"{x} [{ux}]")
    ax.set_ylabel(f"{y} [{uy}]")
    ax.set_title(title, fontsize=10)
    ax.legend(fontsize=7, ncol=2, loc="best")
    fig.tight_layout()
    return fig


def loads_report(context) -> str:
    """Write the loads tables and figures of a study and return the page's "Gust loads" part.

    Parameters
    ----------
    context : studies.sections.protocol.ReportContext

    Returns
    -------
    str
        Markdown (empty when the study has no ``[loads]`` section).
    """
    results = context.results
    config = results.config
    opts = config.loads
    if opts is None:
        return ""
    say = context.say or (lambda message: None)
    out_dir, page_dir = Path(context.out_dir), Path(context.page_dir)
    records = results.sections.get("loads")
    if records is None:
        records = load_loads(config, open_store(config))
    hr = ("the rule's 30 - 350 ft (9.144 - 106.68 m)" if opts.H_range_m is None else
          f"{opts.H_range_m[0]:g} - {opts.H_range_m[1]:g} m" + (" (outside the rule's range)" if opts.outside_rule
                                                                 else ""))
    roms = "; ".join(f"{c}: order {o}, T = {T:.6g}, M = {M}, method {m}" for c, (T, M, o, m) in opts.rom)
    blocks = ["## Gust loads (CS-25.341)\n",
              "Certification gust loads of the rigid aerofoil per unit span (package `loads`, docs/loads.md) at the "
              f"study's flight points, from the gust ROM of each point's case ({roms}): the tuned discrete 1-cosine "
              f"gust of CS-25.341(a) over H in {hr}, both signs (`loads.tuned_gust`: a geometric grid of "
              f"{opts.n_grid} gradients, then golden-section search to a relative bracket of {opts.h_rtol:g}; the "
              "histories exact for the continuous gust), and continuous von Karman turbulence of 25.341(b) "
              "(`loads.continuous_turbulence`: L = 2500 ft, `A_bar` per m/s TAS of rms gust velocity, Rice's `N0`, "
              "the design load `A_bar U_sigma`"
              + (f", integrals cut off at {opts.f_max_hz:g} Hz" if opts.f_max_hz is not None else "")
              + "). Loads are increments about the 1 g load; coefficients per the model's units (Cl, Cm about the "
              "quarter chord, `Cm@x` about x chords), SI per unit span beside them (N/m, N m/m).\n"]
    if not records:
        blocks.append("No loads piece is in the store yet (see the missing and failed pieces above); run "
                      f"`lfdrom run {config.source}`.\n")
        return "\n".join(blocks)
    tables = out_dir / "tables"
    rows = point_rows(records)
    write_tables(rows, tables / "loads-points", POINT_COLUMNS, formats=context.formats,
                 caption=f"{config.name}: flight points", label=f"tab:{config.name}-loads-points")
    blocks.append(f"**Flight points** (ICAO standard atmosphere; `U_ref` the discrete gust's reference velocity "
                  f"at the altitude, `U_sigma` the turbulence intensity with F_g; ROM data up to: the highest finite "
                  f"frequency of the LFD data the ROM was identified from, at the point's speed and chord (the PSD "
                  f"and `N0` above it rest on the ROM's extrapolation); CPU: the piece's tuned gusts and "
                  f"turbulence; [CSV]({_rel(tables / 'loads-points.csv', page_dir)})):\n")
    blocks.append(format_table(rows, POINT_COLUMNS, "markdown"))
    env = envelope_rows(records)
    write_tables(env, tables / "loads-envelope", ENVELOPE_COLUMNS, formats=context.formats,
                 caption=f"{config.name}: gust-load envelope", label=f"tab:{config.name}-loads-envelope")
    blocks.append(f"**Envelope** over the {len(records)} flight points (largest magnitude per unit span; both signs "
                  f"occur; [CSV]({_rel(tables / 'loads-envelope.csv', page_dir)})):\n")
    blocks.append(format_table(env, ENVELOPE_COLUMNS, "markdown"))
    fig_dir = out_dir / "figures"
    if context.figures:
        import matplotlib.pyplot as plt

        fig_dir.mkdir(parents=True, exist_ok=True)
        x, y = _axes_pair(records[0])
        path = fig_dir / "loads-envelope.png"
        fig = _envelope_figure(records, f"{config.name}: correlated loads of every flight point ({y} against {x})\n"
                                        "lines: turbulence design ellipses; circles: tuned-gust peaks")
        atomic_savefig(fig, path, dpi=context.dpi)
        plt.close(fig)
        say(f"report {config.name}: {path.name}")
        blocks.append(f"![Correlated loads of every flight point]({_rel(path, page_dir)})\n")
        blocks.append(f"*{y} against {x} per unit span at every flight point: the continuous-turbulence design "
                      "ellipse (`loads.turbulence_ellipse`) and the tuned-gust peaks of each output with the "
                      "time-correlated other load (circles, and their mirror for the opposite gust).*\n")
    for r in records:
        s = r.spec
        stem = f"loads-{_safe(s.name)}"
        lrows = loads_rows(r)
        write_tables(lrows, tables / stem, LOADS_COLUMNS, formats=context.formats,
                     caption=f"{config.name}: gust loads at {s.name}", label=f"tab:{config.name}-{stem}")
        blocks.append(f"### {s.name}: {s.case}, Mach {s.mach:g}, {s.altitude_m:g} m, chord {s.chord_m:g} m, "
                      f"F_g {s.F_g:.4g}, {s.design_speed}\n")
        blocks.append(f"TAS {r.atmosphere['tas']:.2f} m/s, q {r.atmosphere['q'] / 1e3:.3f} kPa, U_ref "
                      f"{r.atmosphere['u_ref']:.3f} m/s EAS, U_sigma {r.u_sigma:.3f} m/s TAS; "
                      f"{r.n_gradients} gust gradients evaluated "
                      f"([CSV]({_rel(tables / (stem + '.csv'), page_dir)})):\n")
        blocks.append(format_table(lrows, LOADS_COLUMNS, "markdown"))
        corr = "; ".join(f"at the {o} peak " + ", ".join(f"{q} {r.correlated[o][q]:.4g}" for q in r.all_outputs
                                                       if q != o) for o in r.outputs)
        rho = ", ".join(f"{a}-{b} {r.rho(a, b):+.3f}" for i, a in enumerate(r.outputs) for b in r.outputs[i + 1:])
        blocks.append(f"Correlated loads (tuned gust, coefficients): {corr}." + (f" Turbulence correlation "
                                                                                   f"coefficients: {rho}." if rho else "")
                      + "\n")
        if context.figures:
            import matplotlib.pyplot as plt

            path = fig_dir / f"{stem}.png"
            fig = _point_figure(r, f"{config.name}: {s.name} ({s.case}, Mach {s.mach:g}, {s.altitude_m:g} m, "
                                   f"c = {s.chord_m:g} m, F_g = {s.F_g:.3g}, {s.design_speed})")
            atomic_savefig(fig, path, dpi=context.dpi)
            plt.close(fig)
            say(f"report {config.name}: {path.name}")
            blocks.append(f"![Gust loads at {s.name}]({_rel(path, page_dir)})\n")
            blocks.append(f"*{s.name}: correlated loads (left: tuned-gust peaks and the turbulence ellipse, per "
                          "unit span), peak load against the gust gradient H relative to the tuned peak (middle: the "
                          "first grid, the star at the critical H after refinement), and the response PSD to "
                          "unit-rms von Karman turbulence normalised by `A_bar^2` (right; dotted: the highest finite frequency of the "
                          "ROM's LFD data at this point).*\n")
    if not context.figures:
        blocks.append("(Figures not drawn: `figures = false`.)\n")
    return "\n".join(blocks)
