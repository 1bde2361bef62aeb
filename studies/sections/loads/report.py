"""The report's "Gust loads" part: flight points, flexible sections, the envelope, a table and figures per point.

Reads the study's ``loads`` pieces (:func:`studies.sections.loads.study.load_loads`; nothing is computed here) and
writes

========================================== ============================================================
where                                      what
========================================== ============================================================
``tables/loads-points.{csv,md,tex}``       the flight points: Mach, altitude, chord, F_g, rho, TAS, EAS, q,
                                           ``U_ref``, ``U_sigma``, the ROM
``tables/loads-flexible.{csv,md,tex}``     per flight point and flexible section: mass ratio, speed index, the
                                           section's flutter (or divergence) speed there and the margin, fit error
``tables/loads-envelope.{csv,md,tex}``     per model (rigid, each flexible section) and output: the largest
                                           tuned-gust and turbulence design load over the flight points, and where
``tables/loads-POINT.{csv,md,tex}``        per output and model at one point (the rigid and flexible rows of an
                                           output together): critical H, sign, peak (coefficient and SI),
                                           ``A_bar``, ``N0``, design load (coefficient and SI), error estimates
``figures/loads-POINT.png``                rigid: correlated loads (potato), load against H, response PSD
``figures/loads-POINT-SECTION.png``        the same for a flexible section (potato of its spring loads)
``figures/loads-envelope.png``             the correlated loads of every flight point together (rigid; each
``figures/loads-envelope-SECTION.png``     flexible section apart)
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

__all__ = ["loads_report", "point_rows", "flexible_rows", "envelope_rows", "POINT_COLUMNS", "FLEXIBLE_COLUMNS",
           "LOADS_COLUMNS", "ENVELOPE_COLUMNS"]

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

FLEXIBLE_COLUMNS = (
    Column("point", "flight point"),
    Column("section", "section"),
    Column("mu", "mu", ".4g", r"$\mu$"),
    Column("speed_index", "U/(b omega_alpha)", ".4g", r"$U/(b\omega_\alpha)$"),
    Column("kind", "instability"),
    Column("flutter_tas", "its TAS (m/s)", ".4g"),
    Column("margin", "its TAS / TAS", ".3f"),
    Column("flutter_hz", "its frequency (Hz)", ".3g"),
    Column("fit_max_err", "motion fit max err", ".2%"),
    Column("seconds", "CPU (s)", ".2f"),
)
"""Columns of the flexible-section table (one row per flight point and section)."""

LOADS_COLUMNS = (
    Column("output", "output"),
    Column("model", "model"),
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
    Column("model", "model"),
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
    """One dict per flight point (keys of :data:`POINT_COLUMNS`; CPU: all its pieces)."""
    rows = []
    cpu = {}
    for r in records:
        cpu[r.spec.name] = cpu.get(r.spec.name, 0.0) + r.seconds
    seen = set()
    for r in records:
        if r.spec.name in seen:
            continue
        seen.add(r.spec.name)
        s, a = r.spec, r.atmosphere
        rows.append(dict(point=s.name, case=s.case, mach=s.mach, altitude_m=s.altitude_m, chord_m=s.chord_m,
                         F_g=s.F_g, design_speed=s.design_speed, rho=a["rho"], tas=a["tas"], eas=a["eas"],
                         q=a["q"] / 1e3, time_scale=1e3 * a["time_scale"], u_ref=a["u_ref"], u_sigma=r.u_sigma,
                         rom=f"order {r.rom['order']}, M {r.rom['M']}, {r.rom['method']}",
                         f_data=data_band_hz(r), seconds=cpu[s.name]))
    return rows


def flexible_rows(records) -> list:
    """One dict per flexible record (keys of :data:`FLEXIBLE_COLUMNS`)."""
    rows = []
    for r in records:
        if r.section is None:
            continue
        f = r.flexible
        fl = f.get("flutter", {})
        found = bool(fl.get("found"))
        rows.append(dict(point=r.spec.name, section=r.section, mu=f.get("mu", math.nan),
                         speed_index=f.get("speed_index", math.nan),
                         kind=fl.get("kind", "-") if found else "none below 3 x TAS",
                         flutter_tas=fl.get("tas", math.nan) if found else math.nan,
                         margin=fl.get("tas", math.nan) / r.atmosphere["tas"] if found else math.nan,
                         flutter_hz=fl.get("frequency_hz", math.nan) if found else math.nan,
                         fit_max_err=f.get("fit", {}).get("max_error", math.nan), seconds=r.seconds))
    return rows


def data_band_hz(record) -> float:
    """The highest finite frequency (Hz) of the LFD data the point's ROM was identified from: the last but one
    point of McKelvey's grid (``sysid.mckelvey_grid(M, T)``: ``omega = (2 / T) tan(pi k / (2 M))``, the last one is
    infinite) in convective units, at the point's ``U / c``."""
    T, M = float(record.rom["T"]), int(record.rom["M"])
    omega = (2.0 / T) * math.tan(math.pi * (M - 1) / (2 * M))
    return omega / (2.0 * math.pi * record.atmosphere["time_scale"])


def loads_rows(record) -> list:
    """One dict per output of one flight point and model (keys of :data:`LOADS_COLUMNS`)."""
    rows = []
    for o in record.outputs:
        rows.append(dict(output=o, model=record.model, critical_H_m=record.critical_H[o], critical_H_ft=record.critical_H[o] / FT,
                         sign="up" if record.gust_sign[o] > 0 else "down", peak=record.peak[o],
                         peak_si=record.dimensional[o], unit=record.units[o], a_bar=record.a_bar[o], n0=record.n0[o],
                         design=record.design[o], design_si=record.design_dimensional[o],
                         quad_err=record.quadrature_error[o], trunc_err=record.truncation_error[o]))
    return rows


def point_loads_rows(records) -> list:
    """The rows of one flight point's records (rigid and flexible): grouped by output, in the order the outputs
    first appear, each output's models in the records' order (rigid first)."""
    per = [loads_rows(r) for r in records]
    order = list(dict.fromkeys(row["output"] for rows in per for row in rows))
    return [row for o in order for rows in per for row in rows if row["output"] == o]


def models_of(records) -> list:
    """The models of ``records`` (``"rigid"``, then the flexible sections), in order of appearance."""
    return list(dict.fromkeys(r.model for r in records))


def envelope_rows(records) -> list:
    """Per model and output: the largest dimensional tuned-gust and turbulence loads over the flight points."""
    rows = []
    for m in models_of(records):
        mine = [r for r in records if r.model == m]
        for o in dict.fromkeys(o for r in mine for o in r.outputs):
            have = [r for r in mine if o in r.outputs]
            t = max(have, key=lambda r: abs(r.dimensional[o]))
            d = max(have, key=lambda r: abs(r.design_dimensional[o]))
            tuned, design = abs(t.dimensional[o]), abs(d.design_dimensional[o])
            rows.append(dict(model=m, output=o, unit=t.units[o], tuned_si=tuned, tuned_point=t.spec.name,
                             tuned_H_m=t.critical_H[o], design_si=design, design_point=d.spec.name,
                             ratio=design / tuned if tuned > 0 else math.nan))
    return rows


FLEXIBLE_PAIR = ("plunge_spring", "pitch_spring")
"""The potato plot of a flexible section: its two internal loads, when both were searched."""
FLEXIBLE_CURVES = ("Cl", "load_factor", "plunge_spring", "pitch_spring")
"""The outputs of a flexible section's load-versus-H and PSD panels (those searched; all when none is)."""


def _axes_pair(record):
    outs = list(record.outputs)
    if record.section is not None and set(FLEXIBLE_PAIR) <= set(outs):
        return FLEXIBLE_PAIR
    if len(outs) >= 2:
        return outs[0], outs[1]
    return outs[0], (record.all_outputs[1] if len(record.all_outputs) > 1 else outs[0])


def _point_figure(record, title):
    import matplotlib.pyplot as plt

    import loads

    tg, ct = record.results()
    x, y = _axes_pair(record)
    curves = None
    if record.section is not None:
        curves = [o for o in FLEXIBLE_CURVES if o in record.outputs] or None
    fig, axs = plt.subplots(1, 3, figsize=(15.0, 4.6))
    loads.correlated_loads_plot(tg, ct if y in ct.outputs and x in ct.outputs else None, x=x, y=y, ax=axs[0])
    loads.load_vs_H_plot(tg, curves, ax=axs[1])
    loads.psd_plot(ct, curves, ax=axs[2])
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
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=7, ncol=2, loc="best")
    fig.tight_layout()
    return fig


def _failed_flexible(config) -> dict:
    """Flight point name -> ``[(section, error)]`` of the flexible pieces stored as failures."""
    from ...store.entries import is_failed
    from .schema import flexible_piece

    store = open_store(config)
    out = {}
    for p in config.loads.points:
        for n in p.sections:
            e = store.get("loads", flexible_piece(config, p, config.loads.section(n)))
            if e is not None and is_failed(e):
                out.setdefault(p.name, []).append((n, str(e.metadata.get("error"))))
    return out


def _section_text(opts) -> str:
    rows = [dict(section=s.name, mass=s.mass_kg_m, a=s.a, x_alpha=s.x_alpha, r_alpha2=s.r_alpha2, f_h=s.f_h_hz,
                 f_alpha=s.f_alpha_hz, axis=s.elastic_axis, damping="/".join(f"{d:g}" for d in s.damping),
                 points=sum(s.name in p.sections for p in opts.points)) for s in opts.sections]
    cols = (Column("section", "section"), Column("mass", "mass (kg/m)", ".4g"), Column("a", "a", ".4g"),
            Column("x_alpha", "x_alpha", ".4g"), Column("r_alpha2", "r_alpha2", ".4g"),
            Column("f_h", "f_h (Hz)", ".4g"), Column("f_alpha", "f_alpha (Hz)", ".4g"),
            Column("axis", "elastic axis (c)", ".4g"), Column("damping", "damping"), Column("points", "points"))
    return format_table(rows, cols, "markdown")


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
    what = ("the rigid aerofoil" + (" and of flexible sections" if opts.sections else "") if opts.rigid else
            "flexible sections")
    blocks = ["## Gust loads (CS-25.341)\n",
              f"Certification gust loads of {what} per unit span (package `loads`, docs/loads.md) at the "
              f"study's flight points, from the gust ROM of each point's case ({roms}): the tuned discrete 1-cosine "
              f"gust of CS-25.341(a) over H in {hr}, both signs (`loads.tuned_gust`: a geometric grid of "
              f"{opts.n_grid} gradients, then golden-section search to a relative bracket of {opts.h_rtol:g}; the "
              "histories exact for the continuous gust), and continuous von Karman turbulence of 25.341(b) "
              "(`loads.continuous_turbulence`: L = 2500 ft, `A_bar` per m/s TAS of rms gust velocity, Rice's `N0`, "
              "the design load `A_bar U_sigma`"
              + (f", N0 integral cut off at {opts.f_max_hz:g} Hz" if opts.f_max_hz is not None else "")
              + "). Loads are increments about the 1 g load; coefficients per the model's units (Cl, Cm about the "
              + ("quarter chord for the rigid aerofoil and about the elastic axis for a flexible section"
                 if opts.sections else "quarter chord")
              + ", `Cm@x` about x chords), SI per unit span beside them (N/m, N m/m).\n"]
    if opts.sections:
        omega = [w for w in opts.motion_omega if w > 0]
        blocks.append(
            "**Flexible sections** (`loads.FlexibleSection`: the typical section in dimensional form, its mass ratio "
            "`mu = m / (pi rho b^2)` and speed index `U / (b omega_alpha)` set by each flight point). Aerodynamics: "
            f"the `[aeroelastic]` section's motion FRF of the case (plunge and pitch, {len(opts.motion_omega)} "
            f"frequencies, 0 and {min(omega):.3g} to {max(omega):.3g} U/c) moved to the elastic axis and fitted in "
            f"Roger's form with {opts.lags} lag roots (`aeroelastic.fit_motion`), and the point's gust ROM (the rigid "
            "rows' own) as the gust model, its moment moved to the elastic axis. Outputs: plunge `h` (m, up) and pitch "
            "(rad, nose up), their accelerations, the load factor (g), Cl, Cm and the spring (internal) loads "
            "`k_h h` (N/m) and `k_alpha alpha` (N m/m). A point at or above the section's flutter or divergence speed "
            "there is refused (its response is unbounded) and listed with the failed pieces.\n")
        blocks.append(_section_text(opts))
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
                  f"and `N0` above it rest on the ROM's extrapolation); CPU: the point's pieces, tuned gusts and "
                  f"turbulence; [CSV]({_rel(tables / 'loads-points.csv', page_dir)})):\n")
    blocks.append(format_table(rows, POINT_COLUMNS, "markdown"))
    frows = flexible_rows(records)
    failed = _failed_flexible(config) if opts.sections else {}
    if frows:
        write_tables(frows, tables / "loads-flexible", FLEXIBLE_COLUMNS, formats=context.formats,
                     caption=f"{config.name}: flexible sections at the flight points",
                     label=f"tab:{config.name}-loads-flexible")
        blocks.append("**Flexible sections at the flight points** (the section's flutter or divergence at the "
                      "point's density, `aeroelastic.flutter` on speed indices up to three times the point's, and "
                      "its TAS over the point's: the margin; motion fit error as in the aeroelastic section; "
                      f"[CSV]({_rel(tables / 'loads-flexible.csv', page_dir)})):\n")
        blocks.append(format_table(frows, FLEXIBLE_COLUMNS, "markdown"))
    if failed:
        blocks.append("Refused: " + "; ".join(f"{p}, section {n}: {e}" for p, items in failed.items()
                                               for n, e in items) + ".\n")
    env = envelope_rows(records)
    write_tables(env, tables / "loads-envelope", ENVELOPE_COLUMNS, formats=context.formats,
                 caption=f"{config.name}: gust-load envelope", label=f"tab:{config.name}-loads-envelope")
    npts = len({r.spec.name for r in records})
    blocks.append(f"**Envelope** over the {npts} flight points, per model (largest magnitude per unit span; both "
                  f"signs occur; [CSV]({_rel(tables / 'loads-envelope.csv', page_dir)})):\n")
    blocks.append(format_table(env, ENVELOPE_COLUMNS, "markdown"))
    fig_dir = out_dir / "figures"
    if context.figures:
        import matplotlib.pyplot as plt

        fig_dir.mkdir(parents=True, exist_ok=True)
        for m in models_of(records):
            mine = [r for r in records if r.model == m]
            x, y = _axes_pair(mine[0])
            path = fig_dir / ("loads-envelope.png" if m == "rigid" else f"loads-envelope-{_safe(m)}.png")
            label = "the rigid aerofoil" if m == "rigid" else f"flexible section {m}"
            fig = _envelope_figure(mine, f"{config.name}, {label}: correlated loads of every flight point, {y} "
                                         f"against {x}\nlines: turbulence design ellipses; circles: tuned-gust peaks")
            atomic_savefig(fig, path, dpi=context.dpi)
            plt.close(fig)
            say(f"report {config.name}: {path.name}")
            blocks.append(f"![Correlated loads of every flight point, {label}]({_rel(path, page_dir)})\n")
            blocks.append(f"*{label[0].upper() + label[1:]}: {y} against {x} per unit span at every flight point: the "
                          "continuous-turbulence design ellipse (`loads.turbulence_ellipse`) and the tuned-gust peaks "
                          "of each output with the time-correlated other load (circles, and their mirror for the "
                          "opposite gust).*\n")
    for name in dict.fromkeys(r.spec.name for r in records):
        mine = [r for r in records if r.spec.name == name]
        r0 = mine[0]
        s = r0.spec
        stem = f"loads-{_safe(s.name)}"
        lrows = point_loads_rows(mine)
        write_tables(lrows, tables / stem, LOADS_COLUMNS, formats=context.formats,
                     caption=f"{config.name}: gust loads at {s.name}", label=f"tab:{config.name}-{stem}")
        blocks.append(f"### {s.name}: {s.case}, Mach {s.mach:g}, {s.altitude_m:g} m, chord {s.chord_m:g} m, "
                      f"F_g {s.F_g:.4g}, {s.design_speed}\n")
        grads = ", ".join(f"{r.model} {r.n_gradients}" for r in mine)
        blocks.append(f"TAS {r0.atmosphere['tas']:.2f} m/s, q {r0.atmosphere['q'] / 1e3:.3f} kPa, U_ref "
                      f"{r0.atmosphere['u_ref']:.3f} m/s EAS, U_sigma {r0.u_sigma:.3f} m/s TAS; gust gradients "
                      f"evaluated: {grads} ([CSV]({_rel(tables / (stem + '.csv'), page_dir)})):\n")
        blocks.append(format_table(lrows, LOADS_COLUMNS, "markdown"))
        for n, e in failed.get(name, []):
            blocks.append(f"Flexible section {n}: refused at this point: {e}\n")
        for r in mine:
            # a flexible section's eleven outputs: the key ones only (the tables hold every peak)
            key = list(r.outputs) if r.section is None else [o for o in FLEXIBLE_CURVES if o in r.outputs] or \
                list(r.outputs)
            others = list(r.all_outputs) if r.section is None else key
            corr = "; ".join(f"at the {o} peak " + ", ".join(f"{q} {r.correlated[o][q]:.4g}" for q in others
                                                           if q != o) for o in key)
            rho = ", ".join(f"{a}-{b} {r.rho(a, b):+.3f}" for i, a in enumerate(key) for b in key[i + 1:])
            head = "Rigid aerofoil" if r.section is None else f"Flexible section {r.section}"
            blocks.append(f"{head}: correlated loads (tuned gust, model units): {corr}." +
                          (f" Turbulence correlation coefficients: {rho}." if rho else "") + "\n")
        if context.figures:
            import matplotlib.pyplot as plt

            for r in mine:
                path = fig_dir / (f"{stem}.png" if r.section is None else f"{stem}-{_safe(r.section)}.png")
                which = "rigid" if r.section is None else f"flexible section {r.section}"
                fig = _point_figure(r, f"{config.name}: {s.name}, {which} ({s.case}, Mach {s.mach:g}, "
                                       f"{s.altitude_m:g} m, c = {s.chord_m:g} m, F_g = {s.F_g:.3g}, {s.design_speed})")
                atomic_savefig(fig, path, dpi=context.dpi)
                plt.close(fig)
                say(f"report {config.name}: {path.name}")
                x, y = _axes_pair(r)
                blocks.append(f"![Gust loads at {s.name}, {which}]({_rel(path, page_dir)})\n")
                blocks.append(f"*{s.name}, {which}: correlated loads (left: {y} against {x}, tuned-gust peaks and "
                              "the turbulence ellipse, per unit span), peak load against the gust gradient H relative "
                              "to the tuned peak (middle: the first grid, the star at the critical H after "
                              "refinement), and the response PSD to unit-rms von Karman turbulence normalised by "
                              "`A_bar^2` (right; dotted: the highest finite frequency of the ROM's LFD data at this "
                              "point).*\n")
    if not context.figures:
        blocks.append("(Figures not drawn: `figures = false`.)\n")
    return "\n".join(blocks)
