"""The report's "Aeroelastic section": the flutter table, root loci, V-g plots and flexible-section gust histories.

Reads the study's ``flutter`` pieces (:func:`studies.sections.aeroelastic.study.load_flutter`; nothing is computed here)
and writes

============================================ ==========================================================
where                                        what
============================================ ==========================================================
``tables/flutter.{csv,md,tex}``              one row per (case, section): speed index ``U/(b omega_alpha)``,
                                             ``V_f``, ``omega/omega_alpha``, ``k``, kind, fit errors, times
``figures/aeroelastic-flutter-CASE-SEC.png`` root locus (left) and V-g plot (right), ``aeroelastic.flutter_plot``
``figures/aeroelastic-gust-CASE-SEC-G.png``  gust angle, plunge, pitch, Cl, Cm of the flexible section at its
                                             ``gust_speed`` (``aeroelastic.gust_response_plot``)
============================================ ==========================================================

and returns the Markdown of the section, which :func:`studies.report.write_report` appends to the page.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Callable, Optional

import numpy as np

from .study import load_flutter
from ...store.files import atomic_savefig, page_link as _rel, safe_name as _safe
from ..gust_rom.pieces import open_store
from ...report.tables import Column, format_table, write_tables

__all__ = ["aeroelastic_section", "flutter_rows", "FLUTTER_COLUMNS"]

FLUTTER_COLUMNS = (
    Column("case", "case"),
    Column("section", "section"),
    Column("mu", "mu", ".4g"),
    Column("speed_index", "U/(b omega_alpha)", ".5f", r"$U/(b\omega_\alpha)$"),
    Column("flutter_speed_index", "V_f", ".5f", r"$V_f$"),
    Column("frequency_ratio", "omega/omega_alpha", ".5f", r"$\omega/\omega_\alpha$"),
    Column("reduced_frequency", "k", ".4f", "$k$"),
    Column("kind", "kind"),
    Column("theodorsen_speed_index", "Theodorsen U/(b omega_alpha)", ".5f", r"Theodorsen $U/(b\omega_\alpha)$"),
    Column("speed_vs_theodorsen", "speed vs Theodorsen", "+.2%"),
    Column("theodorsen_frequency_ratio", "Theodorsen omega/omega_alpha", ".5f",
           r"Theodorsen $\omega/\omega_\alpha$"),
    Column("fit_max_err", "motion fit max err", ".2%"),
    Column("gust_fit_max_err", "gust fit max err", ".2%"),
    Column("seconds_motion", "motion FRF (s)", ".1f"),
    Column("seconds", "flutter piece (s)", ".2f"),
)
"""Columns of the flutter table (keys of the CSV; headers of the Markdown and LaTeX)."""


def flutter_rows(records) -> list:
    """One dict per :class:`studies.sections.aeroelastic.study.FlutterRecord` (keys of :data:`FLUTTER_COLUMNS`)."""
    rows = []
    for r in records:
        res = r.result
        ts = float(r.theodorsen.get("speed_index", math.nan))
        rows.append(dict(case=r.case, section=r.section, mu=r.spec.mu, speed_index=res.speed_index,
                         flutter_speed_index=res.flutter_speed_index, frequency_ratio=res.frequency_ratio,
                         reduced_frequency=res.reduced_frequency, kind=res.kind,
                         theodorsen_speed_index=ts, speed_vs_theodorsen=res.speed_index / ts - 1.0,
                         theodorsen_frequency_ratio=float(r.theodorsen.get("frequency_ratio", math.nan)),
                         fit_max_err=float(r.fit.get("max_error", math.nan)),
                         gust_fit_max_err=float(r.fit.get("gust_max_error", math.nan)),
                         seconds_motion=r.motion_seconds, seconds=r.seconds))
    return rows


def aeroelastic_section(results, out_dir, page_dir, *, figures: bool = True, dpi: int = 120,
                        say: Optional[Callable[[str], None]] = None) -> str:
    """Write the flutter table and figures of a study and return the page's "Aeroelastic section".

    Parameters
    ----------
    results : studies.store.results.StudyResults
        Its ``config.aeroelastic`` names the cases and sections; the pieces are read from its store.
    out_dir : path-like
        The report's folder (``tables/`` and ``figures/`` in it).
    page_dir : path-like
        The page's folder (links are relative to it).
    figures : bool
        Draw the figures (about a second each); False: the table only.
    dpi : int
    say : callable, optional
        Progress messages.

    Returns
    -------
    str
        Markdown (empty when the study has no ``[aeroelastic]`` section).
    """
    config = results.config
    opts = getattr(config, "aeroelastic", None)
    if opts is None:
        return ""
    say = say or (lambda message: None)
    out_dir, page_dir = Path(out_dir), Path(page_dir)
    records = load_flutter(config, open_store(config))
    blocks = ["## Aeroelastic section\n"]
    omega = np.asarray(opts.omega)
    pos = omega[omega > 0]
    speeds = ("the default grid of `aeroelastic.flutter` (`V_f` from 0.02 to 3)" if opts.speeds is None else
              f"{len(opts.speeds)} speed indices from {opts.speeds[0]:.4g} to {opts.speeds[-1]:.4g}")
    blocks.append(
        f"Typical sections (Theodorsen's notation, docs/aeroelastic.md) with the aerodynamics of the study's flow "
        f"cases {', '.join(opts.cases)}: `cfd.lfd_response` with inputs gust, plunge and pitch (pivot 0.25 c) on "
        f"{omega.size} frequencies (omega = 0 and {pos.size} from {pos.min():.3g} to {pos.max():.3g} U/c, k up to "
        f"{pos.max() / 2:.3g}), moved to the elastic axis (`aeroelastic.to_elastic_axis`), fitted in Roger's form "
        f"with {opts.lags} lag roots (`aeroelastic.fit_motion`; gust model of order {opts.gust_order}), flutter as "
        f"the eigenvalues of the coupled model over {speeds} (`aeroelastic.flutter`).\n")
    sec_rows = [dict(section=s.name, mu=s.mu, a=s.a, x_alpha=s.x_alpha, r_alpha2=s.r_alpha2,
                     omega_ratio=s.omega_ratio, gust_speed="-" if s.gust_speed is None else f"{s.gust_speed:g}")
                for s in opts.sections]
    blocks.append(format_table(sec_rows, None, "markdown"))
    if not records:
        blocks.append("No flutter piece is in the store yet (see the missing and failed pieces above); run "
                      f"`lfdrom run {config.source}`.\n")
        return "\n".join(blocks)

    rows = flutter_rows(records)
    write_tables(rows, out_dir / "tables" / "flutter", FLUTTER_COLUMNS, caption=f"{config.name}: flutter",
                 label=f"tab:{config.name}-flutter")
    blocks.append("**Flutter** (speed index `U/(b omega_alpha)`, flutter speed index `V_f = U/(b omega_alpha "
                  "sqrt(mu))`, frequency ratio and reduced frequency `k = omega b / U` of the critical root; Theodorsen: the "
                  "same section on the incompressible flat plate (k-method determinant, exact C(k)); fit "
                  "errors: max over entries and frequencies of `|fit - data| / max(|data|, 1 % of peak)`, gust "
                  f"column relative to its peak; [CSV]({_rel(out_dir / 'tables' / 'flutter.csv', page_dir)})):\n")
    blocks.append(format_table(rows, FLUTTER_COLUMNS, "markdown"))
    for r in records:
        res = r.result
        blocks.append(f"- {r.case}, section {r.section}: {res.summary()}; lag roots "
                      f"{', '.join(f'{p:.3g}' for p in r.fit.get('poles', []))} U/c.")
    blocks.append("")
    if not figures:
        blocks.append("(Figures not drawn: `figures = false`.)\n")
        return "\n".join(blocks)

    import matplotlib.pyplot as plt

    import aeroelastic as ae

    fig_dir = out_dir / "figures"
    fig_dir.mkdir(parents=True, exist_ok=True)
    for r in records:
        res = r.result
        path = fig_dir / f"aeroelastic-flutter-{_safe(r.case)}-{_safe(r.section)}.png"
        fig = ae.flutter_plot(res)
        fig.suptitle(f"{config.name}: {r.case}, section {r.section} (mu = {r.spec.mu:g}, a = {r.spec.a:g}, "
                     f"x_alpha = {r.spec.x_alpha:g}, r_alpha^2 = {r.spec.r_alpha2:g}, "
                     f"omega_h/omega_alpha = {r.spec.omega_ratio:g})", fontsize=10)
        fig.tight_layout()
        atomic_savefig(fig, path, dpi=dpi)
        plt.close(fig)
        say(f"report {config.name}: {path.name}")
        blocks.append(f"![Root locus and V-g plot, {r.case}, {r.section}]({_rel(path, page_dir)})\n")
        blocks.append(f"*Root locus (left: eigenvalues in units of omega_alpha from V = {res.speeds[0]:.3g} "
                      f"(circle) to {res.speeds[-1]:.3g} (triangle); grey: the lag roots) and V-g plot (right: "
                      f"g = 2 Re(lambda) / Im(lambda) and the frequency of the two structural branches) of section "
                      f"{r.section} with the aerodynamics of {r.case}: {res.summary()}.*\n")
        for gname, g in r.gusts.items():
            path = fig_dir / f"aeroelastic-gust-{_safe(r.case)}-{_safe(r.section)}-{_safe(gname)}.png"
            axs = ae.gust_response_plot(g)
            fig = axs[0].figure
            axs[0].set_title(f"{r.case}, section {r.section}, gust {gname}: speed index V = {g.speed:.3g}"
                             + (f" ({g.speed / res.speed_index:.0%} of flutter)" if res.found else ""))
            fig.tight_layout()
            atomic_savefig(fig, path, dpi=dpi)
            plt.close(fig)
            say(f"report {config.name}: {path.name}")
            peaks = ", ".join(f"{name} {np.max(np.abs(getattr(g, attr))):.4g}" for name, attr in
                              (("h/c", "plunge"), ("pitch (rad)", "pitch"), ("Cl", "Cl"), ("Cm", "Cm")))
            blocks.append(f"![Gust response, {r.case}, {r.section}, {gname}]({_rel(path, page_dir)})\n")
            blocks.append(f"*The flexible section {r.section} in gust {gname} at speed index {g.speed:g} "
                          f"(aerodynamics of {r.case}, coupled ROM `aeroelastic.gust_response`, from rest; Cm about "
                          f"the elastic axis): peaks {peaks}.*\n")
    return "\n".join(blocks)
