"""Reports of a study from its stored results only: tables, figures and a Markdown page.

:func:`make_report` reads a study's results with :func:`studies.results.load_results` (it never computes) and
writes, under the output folder (the study's ``output`` by default):

- ``report.md``: the page, embedding the figures and the headline tables, with the missing pieces and failed
  points listed (a report of a partial study is still written);
- ``tables/``: ``roms``, ``sims``, ``summary``, ``methods`` and ``cost`` as ``.csv`` (full precision), ``.md``
  and ``.tex`` (booktabs);
- ``figures/``: PNG figures (``frf-*``, ``hankel-*``, ``errors-*``, ``history-*``, ``ltd-*``, ``heatmap-*``).

With ``page="docs/paper-reproduction.md"`` the page is written there and its figures and tables go to the folder
next to it named after it (``docs/paper-reproduction/``), so that the page and its files can be committed
together. The page has *prose slots*, ``<!-- prose:NAME -->`` ... ``<!-- /prose:NAME -->``: text written
between the markers by hand survives regeneration, and ``prose={NAME: text}`` (or a TOML file of such keys)
fills them. For the paper's cases (T1-T6, G1-G6) the captions name the paper figure each one reproduces and
the slots quote the paper's claims to be checked.

The figures and tables are built by :mod:`studies.plots` and :mod:`studies.tables` from the plain rows of
:func:`rom_rows`, :func:`sim_rows`, :func:`summary_rows` and :func:`cost_rows`.
"""

from __future__ import annotations

import datetime as _dt
import hashlib
import json
import math
import re
import sys
import tomllib
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Callable, Mapping, Optional, Sequence

import numpy as np

from . import plots
from .tables import Column, format_table, write_tables

__all__ = [
    "ReportError",
    "make_report",
    "write_report",
    "rom_rows",
    "sim_rows",
    "summary_rows",
    "method_rows",
    "cost_rows",
    "rom_columns",
    "sim_columns",
    "summary_columns",
    "PAPER_FRF_FIGURES",
    "PAPER_HISTORY_FIGURES",
    "PAPER_CLAIMS",
    "SLOTS",
]


class ReportError(RuntimeError):
    """A report cannot be written (unreadable prose file, results of the wrong type, results unavailable)."""


# ---------------------------------------------------------------------------------------------
# The paper's figures and claims (Bagheri, Jones & Gaitonde 2016)
# ---------------------------------------------------------------------------------------------

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

SLOTS = ("summary", "frf", "hankel", "orders", "histories", "cases", "heatmaps", "methods", "cost")
"""Prose slots of the page, in order."""

PAPER_CLAIMS = {
    "frf": "N_r = 25 gives ROMs that agree well with the LFD for T1-T4, well behaved at small frequencies; for "
           "T5 and T6 (NACA2410) N_r = 25 does not fully capture the dynamics, and N_r = 55 (T5) and 35 (T6) "
           "capture them, especially at higher frequencies; an overly large N_r over-fits (Figs. 11-18). With "
           "N_omega = 33, N_r = 9 still gives a suitable ROM of T2 (Fig. 19).",
    "histories": "ROM and LTD agree in the transient and the steady state (Figs. 20-27). G3 tests the higher "
                 "frequencies, where ROM and LTD disagree somewhat; where the transients are large (NACA0018 and "
                 "NACA2410 at M 0.25) a larger ROM comes closer to the LTD. The T2 ROM with N_omega = 33, N_r = 9 "
                 "matches the G3 peak better but oscillates as Cl settles (Fig. 29). The ROMs are better at low "
                 "frequencies (long gusts, Figs. 30-37), and lag the LTD by one time step.",
    "cases": "NACA2410 at M 0.25 (T5) responds to G3 with a longer rise time and greater transients in Cm than at "
             "M 0.735 (T6) (Fig. 28).",
    "methods": "Further work in the paper: stabilise identified systems, and match the zero-frequency gain exactly "
               "so that the steady-state gains are equal.",
    "cost": "The ROM predicts the response to any input in a fraction of the time of the time-domain simulation.",
}
"""What the paper says, quoted next to the slot where our results are compared with it."""

_SLOT_HINTS = {
    "summary": "the main findings in a few sentences (for the paper's cases: where we agree with it)",
    "frf": "where the ROMs match the LFD and where they do not (see the FRF figures and the summary table)",
    "hankel": "how fast the Hankel singular values decay, and what that says about the orders",
    "orders": "how the errors fall with N_r, T and N_omega",
    "histories": "ROM against LTD for each gust: peaks, transients, settling, time lag",
    "cases": "the LTD responses of the cases side by side",
    "heatmaps": "which cases and gusts are hardest",
    "methods": "what exact DC matching and stability enforcement change",
    "cost": "CFD, identification and ROM simulation times",
}


# ---------------------------------------------------------------------------------------------
# Rows and columns
# ---------------------------------------------------------------------------------------------

def _pct(v) -> str:
    v = float(v)
    if math.isinf(v):
        return "inf"
    return f"{100.0 * v:.3g}%"


def _outputs(results) -> list:
    outs = [o for o in getattr(results.config.cfd, "outputs", ("Cl", "Cm"))]
    return outs or ["Cl", "Cm"]


def _sim_outputs(results) -> list:
    return [o for o in _outputs(results) if o in ("Cl", "Cm")]


def rom_rows(results) -> list:
    """One row per sweep point (ok or failed): ``StudyResults.table("rom")`` (NaN metrics for failed points)."""
    return [dict(r) for r in results.table("rom")]


def sim_rows(results) -> list:
    """One row per ROM gust history: ``StudyResults.table("sim")`` plus ``speedup = seconds_ltd / seconds_rom``."""
    rows = []
    for r in results.table("sim"):
        r = dict(r)
        sr, sl = r.get("seconds_rom"), r.get("seconds_ltd")
        r["speedup"] = (sl / sr) if _num(sr) and _num(sl) and sr > 0 else float("nan")
        rows.append(r)
    return rows


def _num(v) -> bool:
    return v is not None and not isinstance(v, bool) and isinstance(v, (int, float, np.floating, np.integer)) \
        and math.isfinite(float(v))


def _point_key(r) -> tuple:
    return (r["case"], _tkey(r["T"]), r["M"], r["order"], r["method"])


def _tkey(T) -> float:
    return float(f"{float(T):.9g}")


def summary_rows(results) -> list:
    """The headline table: one row per identified ROM, its FRF and DC errors and its worst gust errors.

    Keys: ``case, aerofoil, mach, T, N_omega, order, method, frf_max_err_X`` (each output X),
    ``dc_err_Cl, spectral_radius, stable``, and over the study's gusts ``worst_peak_err_X`` with ``worst_gust_X``
    (for X in Cl, Cm; NaN and "-" when no gust history exists).
    """
    cases = {cs.case.name: cs.case for cs in results.config.cases}
    outs = _outputs(results)
    worst: dict = {}
    for s in sim_rows(results):
        key = _point_key(s)
        for o in ("Cl", "Cm"):
            v = s.get(f"peak_err_{o}")
            if _num(v):
                cur = worst.get((key, o))
                if cur is None or v > cur[0]:
                    worst[(key, o)] = (float(v), s["gust"])
    rows = []
    for r in rom_rows(results):
        if r.get("status") != "ok":
            continue
        c = cases.get(r["case"])
        row = dict(case=r["case"], aerofoil=f"NACA{c.naca}" if c is not None else "", mach=c.mach if c else None,
                   T=r["T"], N_omega=r["N_omega"], order=r["order"], method=r["method"])
        for o in outs:
            row[f"frf_max_err_{o}"] = r.get(f"frf_max_err_{o}")
        row["dc_err_Cl"] = r.get("dc_err_Cl")
        row["spectral_radius"] = r.get("spectral_radius")
        row["stable"] = r.get("stable")
        for o in ("Cl", "Cm"):
            w = worst.get((_point_key(r), o))
            row[f"worst_peak_err_{o}"] = w[0] if w else float("nan")
            row[f"worst_gust_{o}"] = w[1] if w else None
        rows.append(row)
    return rows


def method_rows(results) -> list:
    """Method variants compared: per case and method, the median and worst errors over its ROMs.

    Keys: ``case, method, n_roms, n_failed, n_unstable, median_frf_max_err_Cl, worst_frf_max_err_Cl,
    max_dc_err_Cl, max_spectral_radius, median_peak_err_Cl, worst_peak_err_Cl`` (and the Cm errors).
    """
    rows = []
    roms = rom_rows(results)
    sims = sim_rows(results)
    seen = []
    for r in roms:
        if (r["case"], r["method"]) not in seen:
            seen.append((r["case"], r["method"]))
    for case, method in seen:
        rs = [r for r in roms if r["case"] == case and r["method"] == method]
        ok = [r for r in rs if r.get("status") == "ok"]
        ss = [s for s in sims if s["case"] == case and s["method"] == method]
        row = dict(case=case, method=method, n_roms=len(ok), n_failed=len(rs) - len(ok),
                   n_unstable=sum(1 for r in ok if r.get("stable") is False))
        for o in ("Cl", "Cm"):
            fe = [r.get(f"frf_max_err_{o}") for r in ok if _num(r.get(f"frf_max_err_{o}"))]
            pe = [s.get(f"peak_err_{o}") for s in ss if _num(s.get(f"peak_err_{o}"))]
            row[f"median_frf_max_err_{o}"] = float(np.median(fe)) if fe else float("nan")
            row[f"worst_frf_max_err_{o}"] = float(np.max(fe)) if fe else float("nan")
            row[f"median_peak_err_{o}"] = float(np.median(pe)) if pe else float("nan")
            row[f"worst_peak_err_{o}"] = float(np.max(pe)) if pe else float("nan")
        dc = [r.get("dc_err_Cl") for r in ok if _num(r.get("dc_err_Cl"))]
        sr = [r.get("spectral_radius") for r in ok if _num(r.get("spectral_radius"))]
        row["max_dc_err_Cl"] = float(np.max(dc)) if dc else float("nan")
        row["max_spectral_radius"] = float(np.max(sr)) if sr else float("nan")
        rows.append(row)
    return rows


def cost_rows(results) -> list:
    """Compute times per case: the LFD sweep(s), the LTD marches, identification and ROM simulation.

    Keys: ``case, frf_seconds`` (sum over T), ``n_frequencies``, ``frf_error_estimate`` (the fast sweep's
    largest estimated error relative to the response, over all T; NaN for the direct path), ``ltd_seconds``
    (mean per gust), ``n_gusts``, ``identify_seconds`` (median per ROM), ``rom_sim_seconds`` (median per gust
    history), ``speedup`` (``ltd_seconds / rom_sim_seconds``).
    """
    rows = []
    roms = rom_rows(results)
    sims = sim_rows(results)
    for cs in results.config.cases:
        name = cs.case.name
        fr = [f for (c, _), f in results.frf.items() if c == name]
        lt = [r for (c, _), r in results.ltd.items() if c == name]
        idt = [r.get("seconds") for r in roms if r["case"] == name and _num(r.get("seconds"))]
        rs = [s.get("seconds_rom") for s in sims if s["case"] == name and _num(s.get("seconds_rom"))]
        lts = [float(r.seconds) for r in lt if _num(r.seconds)]
        row = dict(case=name,
                   frf_seconds=float(sum(f.seconds for f in fr)) if fr else float("nan"),
                   n_frequencies=int(fr[0].frf.H.shape[-1]) if fr else None,
                   frf_error_estimate=float(np.nanmax([f.max_relative_error_estimate for f in fr]))
                   if fr and any(_num(f.max_relative_error_estimate) for f in fr) else float("nan"),
                   ltd_seconds=float(np.mean(lts)) if lts else float("nan"), n_gusts=len(lt),
                   identify_seconds=float(np.median(idt)) if idt else float("nan"),
                   rom_sim_seconds=float(np.median(rs)) if rs else float("nan"))
        row["speedup"] = (row["ltd_seconds"] / row["rom_sim_seconds"]
                          if _num(row["ltd_seconds"]) and _num(row["rom_sim_seconds"]) and row["rom_sim_seconds"] > 0
                          else float("nan"))
        rows.append(row)
    return rows


def _id_columns() -> list:
    return [Column("case"), Column("T", "T [c/U]", ".4g", "$T$"), Column("N_omega", "N_omega", "d", r"$N_\omega$"),
            Column("order", "N_r", "d", "$N_r$"), Column("method")]


def rom_columns(outputs: Sequence[str] = ("Cl", "Cm")) -> list:
    """Columns of the ROM table (:func:`rom_rows`), with units in the headers."""
    cols = _id_columns() + [Column("status")]
    for o in outputs:
        cols += [Column(f"frf_max_err_{o}", f"FRF max err {o}", _pct, f"max err ${o[0]}_{o[1:]}$"),
                 Column(f"frf_rms_err_{o}", f"FRF RMS err {o}", _pct, f"RMS err ${o[0]}_{o[1:]}$")]
    cols += [Column("frf_max_err_fit", "max err on fitted points", _pct)]
    for o in outputs:
        cols.append(Column(f"dc_err_{o}", f"DC err {o} [1/rad]", ".1e", f"DC err ${o[0]}_{o[1:]}$ [1/rad]"))
    cols += [Column("spectral_radius", "spectral radius", ".6f", r"$\rho(\hat A)$"), Column("stable"),
             Column("seconds", "identify [s]", ".3g"), Column("error")]
    return cols


def sim_columns(outputs: Sequence[str] = ("Cl", "Cm")) -> list:
    """Columns of the gust-history table (:func:`sim_rows`)."""
    cols = _id_columns() + [Column("gust")]
    for o in outputs:
        cols += [Column(f"peak_err_{o}", f"peak err {o}", _pct, f"peak err ${o[0]}_{o[1:]}$"),
                 Column(f"t_peak_err_{o}", f"peak time err {o} [c/U]", ".3g"),
                 Column(f"rms_err_{o}", f"RMS err {o}", _pct, f"RMS err ${o[0]}_{o[1:]}$")]
    cols += [Column("seconds_rom", "ROM [s]", ".3g"), Column("seconds_ltd", "LTD [s]", ".4g"),
             Column("speedup", "LTD / ROM time", ".3g")]
    return cols


def summary_columns(outputs: Sequence[str] = ("Cl", "Cm")) -> list:
    """Columns of the headline table (:func:`summary_rows`)."""
    cols = [Column("case"), Column("aerofoil"), Column("mach", "Mach", ".4g"), Column("T", "T [c/U]", ".4g", "$T$"),
            Column("N_omega", "N_omega", "d", r"$N_\omega$"),
            Column("order", "N_r", "d", "$N_r$"), Column("method")]
    for o in outputs:
        cols.append(Column(f"frf_max_err_{o}", f"FRF max err {o}", _pct, f"FRF ${o[0]}_{o[1:]}$"))
    cols += [Column("dc_err_Cl", "DC err Cl [1/rad]", ".1e", "DC $C_l$ [1/rad]"),
             Column("spectral_radius", "spectral radius", ".5f", r"$\rho(\hat A)$"), Column("stable")]
    for o in ("Cl", "Cm"):
        cols += [Column(f"worst_peak_err_{o}", f"worst peak err {o}", _pct, f"peak ${o[0]}_{o[1:]}$"),
                 Column(f"worst_gust_{o}", "at gust")]
    return cols


def _method_columns() -> list:
    cols = [Column("case"), Column("method"), Column("n_roms", "ROMs"), Column("n_failed", "failed"),
            Column("n_unstable", "unstable")]
    for o in ("Cl", "Cm"):
        cols += [Column(f"median_frf_max_err_{o}", f"median FRF max err {o}", _pct),
                 Column(f"worst_frf_max_err_{o}", f"worst FRF max err {o}", _pct)]
    cols += [Column("max_dc_err_Cl", "max DC err Cl [1/rad]", ".1e"),
             Column("max_spectral_radius", "max spectral radius", ".5f")]
    for o in ("Cl", "Cm"):
        cols += [Column(f"median_peak_err_{o}", f"median peak err {o}", _pct),
                 Column(f"worst_peak_err_{o}", f"worst peak err {o}", _pct)]
    return cols


def _cost_columns() -> list:
    return [Column("case"), Column("n_frequencies", "LFD frequencies"), Column("frf_seconds", "LFD sweep [s]", ".4g"),
            Column("frf_error_estimate", "LFD est. max rel. error", ".1e"),
            Column("n_gusts", "gusts"), Column("ltd_seconds", "LTD per gust [s]", ".4g"),
            Column("identify_seconds", "identify per ROM [s]", ".3g"),
            Column("rom_sim_seconds", "ROM per gust [s]", ".3g"), Column("speedup", "LTD / ROM time", ".3g")]


def _keep(cols: list, rows: list) -> list:
    """Columns whose key is in some row (outputs a study does not compute drop out)."""
    present = set().union(*(r.keys() for r in rows)) if rows else {c.key for c in cols}
    return [c for c in cols if c.key in present]


# ---------------------------------------------------------------------------------------------
# Figures
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class _Figure:
    section: str
    path: Path
    caption: str


FIGURE_MANIFEST = "manifest.json"
"""File in ``figures/`` naming the figures of the last report and the fingerprint of what they were drawn from."""


def _figure_fingerprint(config, tables: dict, dpi: int, paper: bool) -> str:
    """sha256 of everything the figures depend on: the study, the tables' rows (every metric and every piece's
    compute time, so that any recomputed piece changes it), the resolution, paper mode, and the plotting code."""
    import matplotlib

    from .provenance import source_hash

    blob = json.dumps(dict(study=config.canonical_json(), rows={k: v[0] for k, v in tables.items()}, dpi=dpi,
                           paper=bool(paper), code=source_hash(("studies.plots", "studies.report")),
                           matplotlib=matplotlib.__version__), sort_keys=True, default=repr)
    return hashlib.sha256(blob.encode()).hexdigest()


def _cached_figures(fig_dir: Path, fingerprint: str) -> Optional[list]:
    """The figures listed by the manifest when it has this fingerprint and every file still exists, else None."""
    try:
        data = json.loads((fig_dir / FIGURE_MANIFEST).read_text(encoding="utf-8"))
        if data.get("fingerprint") != fingerprint:
            return None
        figs = [_Figure(f["section"], fig_dir / f["file"], f["caption"]) for f in data["figures"]]
    except (OSError, ValueError, KeyError, TypeError):
        return None
    return figs if all(f.path.is_file() for f in figs) else None


def _write_manifest(fig_dir: Path, fingerprint: str, figs: list) -> None:
    from .cache import atomic_write_bytes

    data = dict(fingerprint=fingerprint, figures=[dict(section=f.section, file=f.path.name, caption=f.caption)
                                                  for f in figs])
    atomic_write_bytes(fig_dir / FIGURE_MANIFEST, (json.dumps(data, indent=1) + "\n").encode("utf-8"))


def _slug(*parts) -> str:
    return re.sub(r"[^A-Za-z0-9_.+-]+", "_", "-".join(str(p) for p in parts if p != ""))


def _paper_case(config, name: str) -> bool:
    """The study's case ``name`` is the paper's case of that name (same aerofoil, Mach, incidence)."""
    from .cases import TEST_CASES

    try:
        c = config.case(name).case
    except Exception:  # noqa: BLE001 - unknown names are simply not paper cases
        return False
    ref = TEST_CASES.get(name)
    return ref is not None and ref.naca == c.naca and ref.mach == c.mach and ref.alpha_deg == c.alpha_deg


def _paper_gust(config, name: str) -> bool:
    from .cases import GUST_CASES

    ref = GUST_CASES.get(name)
    return ref is not None and any(g == ref for g in config.gusts if g.name == name)


def _paper_note(nums) -> str:
    nums = sorted(set(nums))
    if not nums:
        return ""
    return f" Analogue of the paper's Fig{'s' if len(nums) > 1 else ''}. {', '.join(map(str, nums))}."


def _rom_label(r, multi_T: bool, with_method: bool = True) -> str:
    lab = f"N_r={r.order}, N_ω={r.M + 1}"
    if multi_T:
        lab += f", T={r.T:.4g}"
    return lab + (f", {r.method}" if with_method else "")


def _methods(results) -> list:
    return [m.name for m in results.config.methods]


def _case_T_count(results, case) -> int:
    try:
        return len(results.config.case(case).T)
    except Exception:  # noqa: BLE001
        return len({_tkey(r.T) for r in results.roms if r.case == case})


def _frf_figures(results, fig_dir: Path, dpi: int, say, paper: bool = False) -> list:
    figs = []
    methods = _methods(results)
    colours = plots._colours()
    outs = _outputs(results)
    groups: dict = {}
    for r in results.roms:
        if r.status == "ok" and r.frf_rom is not None:
            groups.setdefault((r.case, _tkey(r.T), r.M, r.order), []).append(r)
    for (case, T, M, order), rs in groups.items():
        fr = next((f for (c, t), f in results.frf.items() if c == case and _tkey(t) == T), None)
        if fr is None:
            continue
        rs.sort(key=lambda r: methods.index(r.method) if r.method in methods else len(methods))
        models = [(r.method, np.asarray(r.frf_rom),
                   dict(color=colours[(methods.index(r.method) if r.method in methods else i) % len(colours)],
                        ls=plots.LINESTYLES[i % len(plots.LINESTYLES)]))
                  for i, r in enumerate(rs)]
        step = max(1, fr.M // M)
        samples = np.arange(0, fr.M + 1, step) if M != fr.M else None
        multi_T = _case_T_count(results, case) > 1
        title = f"{case}: ROM (N_r = {order}, N_ω = {M + 1}{f', T = {T:.4g}' if multi_T else ''}) against LFD"
        fig, _ = plots.frf_plot(fr.frf.omega, fr.frf.H, models, outputs=list(fr.frf.outputs or outs),
                                samples=samples, title=title)
        path = plots.save_figure(fig, fig_dir / (_slug("frf", case, f"T{T:.4g}" if multi_T else "", f"N{M + 1}",
                                                       f"r{order}") + ".png"), dpi=dpi)
        note = _paper_note([PAPER_FRF_FIGURES[(case, order, M + 1)]]) \
            if paper and _paper_case(results.config, case) and (case, order, M + 1) in PAPER_FRF_FIGURES else ""
        figs.append(_Figure("frf", path, f"{title}: magnitude, phase (unwrapped) and error against the reduced "
                                         f"frequency k = ω/2, per radian of gust angle.{note}"))
        say(f"  {path}")
    return figs


def _hankel_figures(results, fig_dir: Path, dpi: int, say, paper: bool = False) -> list:
    figs = []
    cases = []
    for r in results.roms:
        if r.case not in cases:
            cases.append(r.case)
    for case in cases:
        best: dict = {}
        orders = set()
        for r in results.roms:
            if r.case != case or r.status != "ok" or r.hankel_sv is None:
                continue
            orders.add(r.order)
            key = (_tkey(r.T), r.M)
            if key not in best or len(r.hankel_sv) > len(best[key]):
                best[key] = np.asarray(r.hankel_sv, dtype=float)
        if not best:
            continue
        multi_T = len({k[0] for k in best}) > 1
        sets = [(rf"$N_\omega$ = {M + 1}" + (f", T = {T:.4g}" if multi_T else ""), sv)
                for (T, M), sv in sorted(best.items(), key=lambda kv: (kv[0][0], -kv[0][1]))]
        title = f"{case}: Hankel singular values of the subspace step"
        fig, _ = plots.hankel_plot(sets, orders=sorted(orders), title=title)
        path = plots.save_figure(fig, fig_dir / (_slug("hankel", case) + ".png"), dpi=dpi)
        figs.append(_Figure("hankel", path, f"{title}, normalised by the largest; dotted lines: the model orders "
                                            f"of the study (the N_r largest values are kept)."))
        say(f"  {path}")
    return figs


ERROR_RANGE = (1e-4, 10.0)
"""Range of relative errors drawn to scale (0.01 % to 1000 %) in the heat maps and the error-against-order
figures: larger errors (unstable ROMs) are drawn at the top and marked."""


def _error_figures(results, fig_dir: Path, dpi: int, say, paper: bool = False) -> list:
    figs = []
    rows = rom_rows(results)
    worst: dict = {}
    for s in sim_rows(results):
        for o in ("Cl", "Cm"):
            v = s.get(f"peak_err_{o}")
            if _num(v):
                k = (_point_key(s), o)
                worst[k] = max(worst.get(k, 0.0), float(v))
    for r in rows:
        for o in ("Cl", "Cm"):
            if (_point_key(r), o) in worst:
                r[f"worst_peak_err_{o}"] = worst[(_point_key(r), o)]
    outs = _outputs(results)
    cases = []
    for r in rows:
        if r["case"] not in cases:
            cases.append(r["case"])
    for case in cases:
        cr = [r for r in rows if r["case"] == case]
        metrics = {f"frf_max_err_{o}": f"FRF max error {o} (relative)" for o in outs}
        metrics.update({f"worst_peak_err_{o}": f"worst gust peak error {o} (relative)" for o in ("Cl", "Cm")
                        if any(_num(r.get(f"worst_peak_err_{o}")) for r in cr)})
        metrics = {k: v for k, v in metrics.items() if any(_num(r.get(k)) for r in cr)}
        if not metrics:
            continue
        group_by = ("T", "M", "method") if _case_T_count(results, case) > 1 else ("M", "method")
        title = f"{case}: errors against the model order"
        fig, _ = plots.error_vs_order_plot(cr, metrics, group_by=group_by, title=title, clip=ERROR_RANGE[1])
        path = plots.save_figure(fig, fig_dir / (_slug("errors", case) + ".png"), dpi=dpi)
        figs.append(_Figure("orders", path, f"{title} for each N_ω (colour) and method (line style): FRF error over "
                                            f"the full LFD grid (peak-normalised, sysid.metrics) and the largest "
                                            f"relative peak error over the gusts; crosses mark unstable ROMs, "
                                            f"triangles errors above {ERROR_RANGE[1]:.0%} (drawn there)."))
        say(f"  {path}")
    return figs


def _history_figures(results, fig_dir: Path, dpi: int, say, paper: bool = False) -> list:
    figs = []
    methods = _methods(results)
    colours = plots._colours()
    souts = _sim_outputs(results)
    by_pair: dict = {}
    for s in results.sims:
        by_pair.setdefault((s.case, s.gust), []).append(s)
    for (case, gust), ltd in results.ltd.items():
        ss = by_pair.get((case, gust), [])
        pts = []
        for s in ss:
            k = (_tkey(s.T), s.M, s.order)
            if k not in pts:
                pts.append(k)
        pts.sort(key=lambda k: (k[0], -k[1], k[2]))
        multi_T = _case_T_count(results, case) > 1
        ss = sorted(ss, key=lambda s: (pts.index((_tkey(s.T), s.M, s.order)),
                                       methods.index(s.method) if s.method in methods else 99))
        models, ckey, skey = [], {}, {}
        for s in ss:
            mi = methods.index(s.method) if s.method in methods else 0
            colour = colours[pts.index((_tkey(s.T), s.M, s.order)) % len(colours)]
            style = dict(color=colour, ls=plots.LINESTYLES[mi % len(plots.LINESTYLES)], lw=1.2)
            models.append((_rom_label(s, multi_T), {"Cl": s.cl, "Cm": s.cm}, style))
            ckey.setdefault("ROM " + _rom_label(s, multi_T, with_method=False), colour)
            skey.setdefault(s.method, style["ls"])
        title = f"{case}: response to gust {gust}, ROMs against LTD"
        fig, axes = plots.history_plot(ltd.t, {"Cl": ltd.cl, "Cm": ltd.cm}, models, outputs=souts, u=ltd.u,
                                       title=title, legend=False)
        plots.key_legend(axes[1, -1], ckey, skey if len(skey) > 1 else None, ref_label="LTD", outside=True)
        fig.tight_layout()
        path = plots.save_figure(fig, fig_dir / (_slug("history", case, gust) + ".png"), dpi=dpi)
        nums = PAPER_HISTORY_FIGURES.get((case, gust), ()) \
            if paper and _paper_case(results.config, case) and _paper_gust(results.config, gust) else ()
        figs.append(_Figure("histories", path, f"{title}: gust angle at the reference point, load perturbations "
                                                f"and ROM - LTD; colour: sweep point, line style: method."
                                                f"{_paper_note(nums)}"))
        say(f"  {path}")
    return figs


def _case_ltd_figures(results, fig_dir: Path, dpi: int, say, paper: bool = False) -> list:
    figs = []
    x0 = results.config.simulation.x0
    gusts = []
    for (_, g) in results.ltd:
        if g not in gusts:
            gusts.append(g)
    for gust in gusts:
        recs = [(c, r) for (c, g), r in results.ltd.items() if g == gust]
        if len(recs) < 2 or len({len(r.t) for _, r in recs}) != 1:
            continue
        t = np.asarray(recs[0][1].t) + x0
        models = [(c, {"Cl": r.cl, "Cm": r.cm}) for c, r in recs]
        title = f"LTD responses to gust {gust}"
        fig, _ = plots.history_plot(t, None, models, outputs=_sim_outputs(results),
                                    t_label="time since the gust reaches the reference point, s - s_0 [c/U]",
                                    title=title)
        path = plots.save_figure(fig, fig_dir / (_slug("ltd", gust) + ".png"), dpi=dpi)
        note = ""
        if paper and gust == "G3" and _paper_gust(results.config, "G3") and all(
                _paper_case(results.config, c) for c in ("T5", "T6")) and {"T5", "T6"} <= {c for c, _ in recs}:
            note = _paper_note([28])
        figs.append(_Figure("cases", path, f"{title} of every case, against the time since the gust front reached "
                                           f"the reference point.{note}"))
        say(f"  {path}")
    return figs


def _heatmap_figures(results, fig_dir: Path, dpi: int, say, paper: bool = False) -> list:
    figs = []
    sims = sim_rows(results)
    if not sims:
        return figs
    gusts = [g.name for g in results.config.gusts]
    methods = [m for m in _methods(results) if any(s["method"] == m for s in sims)]
    pts = []
    for s in sims:
        k = (s["case"], _tkey(s["T"]), s["M"], s["order"])
        if k not in pts:
            pts.append(k)
    multi_T = len({(k[0], k[1]) for k in pts}) > len({k[0] for k in pts})
    labels = [f"{c} N_r={n} N_ω={M + 1}" + (f" T={T:.4g}" if multi_T else "") for c, T, M, n in pts]
    for o in _sim_outputs(results):
        vals = np.full((len(methods), len(pts), len(gusts)), np.nan)
        for s in sims:
            v = s.get(f"peak_err_{o}")
            if (_num(v) or v == float("inf")) and s["gust"] in gusts:  # inf: an unstable ROM's history overflowed
                vals[methods.index(s["method"]), pts.index((s["case"], _tkey(s["T"]), s["M"], s["order"])),
                     gusts.index(s["gust"])] = v
        fin = vals[np.isfinite(vals)]
        if not fin.size:
            continue
        pos = fin[fin > 0]
        vmin = max(float(pos.min()), ERROR_RANGE[0]) if pos.size else ERROR_RANGE[0]
        vmax = min(max(float(fin.max()), vmin * 10), ERROR_RANGE[1])
        plt = plots._plt()
        heights = [len(pts) + 1.5 for _ in methods]
        fig, axes = plt.subplots(len(methods), 1, figsize=(0.95 * len(gusts) + 4.2, 0.36 * sum(heights) + 0.8),
                                 squeeze=False, layout="constrained", gridspec_kw=dict(height_ratios=heights))
        for ax, m, v in zip(axes[:, 0], methods, vals):
            plots.heatmap_plot(v, labels, gusts, ax=ax, vmin=vmin, vmax=vmax, colorbar=False, title=f"method {m}")
        title = (f"Peak error of {o}, ROM against LTD (load envelope):\n"
                 f"max(|max ROM - max LTD|, |min ROM - min LTD|) / max |LTD|")
        fig.suptitle(title, fontsize=10)
        cb = fig.colorbar(axes[0, 0].images[0], ax=list(axes[:, 0]), fraction=0.05, pad=0.02, shrink=0.8)
        cb.set_label(f"peak error {o}", fontsize=9)
        cb.formatter = plots.percent_formatter()
        path = plots.save_figure(fig, fig_dir / (_slug("heatmap", "peak", o) + ".png"), dpi=dpi,
                                 palette=False)  # a palette would band the continuous colour bar
        figs.append(_Figure("heatmaps", path, f"{title.replace(chr(10), ' ')}; rows: sweep points, columns: gusts, "
                                              f"one panel per method (common log colour scale, clipped at "
                                              f"{ERROR_RANGE[1]:.0%}; inf: the ROM's history overflowed; hatched: no "
                                              f"history)."))
        say(f"  {path}")
    return figs


# ---------------------------------------------------------------------------------------------
# The page
# ---------------------------------------------------------------------------------------------

_SLOT_RE = re.compile(r"<!-- prose:(?P<name>[A-Za-z0-9_]+) -->\n(?P<body>.*?)<!-- /prose:(?P=name) -->", re.S)


def _read_prose(prose, page_path: Path) -> dict:
    """Prose slots: those in the existing page, overridden by ``prose`` (dict or TOML file of strings)."""
    slots = {}
    if page_path.exists():
        for m in _SLOT_RE.finditer(page_path.read_text(encoding="utf-8")):
            body = m.group("body").strip("\n")
            if not body.startswith("_(prose to be written"):
                slots[m.group("name")] = body
    if prose is None:
        return slots
    if isinstance(prose, (str, Path)):
        p = Path(prose)
        try:
            data = tomllib.loads(p.read_text(encoding="utf-8"))
        except FileNotFoundError:
            raise ReportError(f"{p}: no such prose file (a TOML file of slot = \"text\" strings; slots: "
                              f"{', '.join(SLOTS)})") from None
        except (OSError, tomllib.TOMLDecodeError) as e:
            raise ReportError(f"{p}: cannot read the prose file: {e}") from None
        prose = data
    if not isinstance(prose, Mapping):
        raise ReportError(f"prose must be a mapping of slot -> text or a TOML file, got {type(prose).__name__}")
    for k, v in prose.items():
        if k not in SLOTS:
            raise ReportError(f"unknown prose slot {k!r}; slots: {', '.join(SLOTS)}")
        if not isinstance(v, str):
            raise ReportError(f"prose slot {k!r} must be text, got {type(v).__name__}")
        slots[k] = v.strip("\n")
    return slots


def _slot(name: str, slots: dict, paper: bool) -> str:
    lines = []
    if paper and name in PAPER_CLAIMS:
        lines.append(f"> **The paper:** {PAPER_CLAIMS[name]}\n")
    body = slots.get(name) or f"_(prose to be written: {_SLOT_HINTS.get(name, name)})_"
    lines.append(f"<!-- prose:{name} -->\n{body}\n<!-- /prose:{name} -->\n")
    return "\n".join(lines)


def _rel(path: Path, start: Path) -> str:
    import os

    return Path(os.path.relpath(path, start)).as_posix()


def _git_commit() -> str:
    from .provenance import git_commit

    try:
        info = git_commit()
    except Exception:  # noqa: BLE001 - provenance is best effort
        return "unknown"
    if not isinstance(info, Mapping):
        return "unknown"
    commit = str(info.get("commit") or "unknown")[:12]
    return commit + (" (dirty tree)" if info.get("dirty") else "")


def _study_table(config) -> str:
    rows = []
    for cs in config.cases:
        c = cs.case
        rows.append(dict(case=c.name, aerofoil=f"NACA{c.naca}", mach=c.mach, alpha=c.alpha_deg,
                         grid=f"{c.grid.ni} x {c.grid.nj}", orders=", ".join(map(str, cs.orders)),
                         T=", ".join(f"{t:.4g}" for t in cs.T), N_omega=", ".join(str(m + 1) for m in cs.M)))
    return format_table(rows, [Column("case"), Column("aerofoil"), Column("mach", "Mach", ".4g"),
                               Column("alpha", "alpha [deg]", ".3g"), Column("grid"), Column("orders", "N_r"),
                               Column("T", "T [c/U]"), Column("N_omega")], "markdown")


def _gust_table(config) -> str:
    rows = [dict(gust=g.name, kind=g.kind.replace("_", "-"), length=g.length, angle=g.angle_deg)
            for g in config.gusts]
    if not rows:
        return "_(no gusts)_\n"
    return format_table(rows, [Column("gust"), Column("kind"), Column("length", "length [c]", ".4g"),
                               Column("angle", "angle [deg]", ".4g")], "markdown")


def _method_table(config) -> str:
    rows = [dict(method=m.name, dc_gain=m.dc_gain, stable=m.stable, margin=m.margin if m.stable else None,
                 weights=m.weights, algorithm=m.algorithm) for m in config.methods]
    return format_table(rows, [Column("method"), Column("dc_gain", "DC gain"), Column("stable", "stability enforced"),
                               Column("margin", "margin", ".0e"), Column("weights"), Column("algorithm")], "markdown")


_DOCS = Path(__file__).resolve().parents[1] / "docs"


def _paper_elsewhere(page_dir: Path) -> str:
    """Where the paper's figures that are not part of a study are reproduced (grids, steady flow, SVM/FVM)."""
    def link(name, anchor=""):
        return f"[{name}]({_rel(_DOCS / name, page_dir)}{anchor})"

    return ("The paper's figures outside a study are reproduced elsewhere: the C-grid (Figs. 1-2) in "
            f"{link('mesh.md')}, the steady pressure distributions of T1-T6 (Figs. 3-8) in {link('validation.md')} "
            f"(section 6), and the SVM against FVM LFD responses of T2 and T4 (Figs. 9-10) in "
            f"{link('gust_validation.md')} (section 6). The figures below are the analogues of Figs. 11-37.\n")


def _bullets(items: Sequence[str], limit: int = 40) -> str:
    out = [f"- {i}" for i in items[:limit]]
    if len(items) > limit:
        out.append(f"- ... and {len(items) - limit} more (see the tables)")
    return "\n".join(out) + "\n"


def _figs_md(figs, page_dir: Path, section: str) -> str:
    if figs is None:
        return "_(figures not drawn in this run: `figures=False`)_\n"
    out = []
    for f in figs:
        if f.section == section:
            out.append(f"![{f.path.stem}]({_rel(f.path, page_dir)})\n\n*{f.caption}*\n")
    return "\n".join(out) if out else "_(no data for these figures yet)_\n"


def write_report(results, out_dir, *, page=None, prose=None, progress: bool = False, dpi: int = 120,
                 title: Optional[str] = None, paper: Optional[bool] = None, figures: bool = True,
                 formats: Sequence[str] = ("csv", "markdown", "latex"), redraw: bool = False) -> Path:
    """Write the tables, figures and Markdown page of a :class:`studies.results.StudyResults`.

    Parameters
    ----------
    results : StudyResults
        What the store holds (complete or not), e.g. from :func:`studies.results.load_results` or
        :func:`studies.synthetic.synthetic_results`.
    out_dir : path-like
        Folder of ``tables/`` and ``figures/`` (created); also of ``report.md`` when ``page`` is not given.
    page : path-like, optional
        Where to write the Markdown page instead of ``out_dir/report.md``.
    prose : mapping or path-like, optional
        Text for the prose slots (see the module docstring); slots already written in an existing page are kept.
    progress : bool
        Print the files as they are written (to stderr).
    dpi : int
        Resolution of the PNG figures.
    title : str, optional
        Page title (default: "Study report: NAME", or the paper's reproduction title in paper mode).
    paper : bool, optional
        Paper mode: captions name the paper's figures and the prose slots quote its claims. Default: on when a
        case of the study is one of the paper's T1-T6.
    figures : bool
        Draw the figures (the slow part, about a second each); False writes the tables and the page only, the
        page saying where the figures were left out.
    formats : sequence of str
        Table formats to write.
    redraw : bool
        Draw the figures even when ``figures/manifest.json`` says that they are up to date. By default a
        report whose inputs (study, every table row including each piece's compute time, resolution, paper
        mode, plotting code) are those of the last one keeps its figures, so that a warm ``lfdrom run``
        rewrites the page in seconds.

    Returns
    -------
    pathlib.Path
        The Markdown page.

    Raises
    ------
    ReportError
        ``results`` is not a StudyResults, or the prose is unreadable or names an unknown slot.
    """
    for attr in ("config", "frf", "ltd", "roms", "sims", "missing"):
        if not hasattr(results, attr):
            raise ReportError(f"results must be a studies.results.StudyResults (no attribute {attr!r}); got "
                              f"{type(results).__name__}")
    if "matplotlib.pyplot" not in sys.modules:  # nobody chose a backend: files only, no display needed
        import matplotlib

        matplotlib.use("Agg")
    say = (lambda msg: print(msg, file=sys.stderr)) if progress else (lambda msg: None)
    out_dir = Path(out_dir)
    page_path = Path(page) if page is not None else out_dir / "report.md"
    slots = _read_prose(prose, page_path)
    config = results.config
    fig_dir, tab_dir = out_dir / "figures", out_dir / "tables"
    tab_dir.mkdir(parents=True, exist_ok=True)
    page_dir = page_path.parent
    page_dir.mkdir(parents=True, exist_ok=True)
    outs = _outputs(results)
    souts = _sim_outputs(results)

    # tables
    say(f"report {config.name}: tables in {tab_dir}")
    roms, sims = rom_rows(results), sim_rows(results)
    summ, meths, cost = summary_rows(results), method_rows(results), cost_rows(results)
    tables = {}
    for name, rows, cols in (("roms", roms, rom_columns(outs)), ("sims", sims, sim_columns(souts)),
                             ("summary", summ, summary_columns(outs)), ("methods", meths, _method_columns()),
                             ("cost", cost, _cost_columns())):
        cols = _keep(cols, rows)
        tables[name] = (rows, cols)
        if rows:
            write_tables(rows, tab_dir / name, cols, formats,
                         caption=f"{config.name}: {name}", label=f"tab:{config.name}-{name}")

    # figures
    say(f"report {config.name}: figures in {fig_dir}")
    if paper is None:
        paper = any(_paper_case(config, cs.case.name) for cs in config.cases)
    figs = []
    if figures:
        fingerprint = _figure_fingerprint(config, tables, dpi, paper)
        cached = None if redraw else _cached_figures(fig_dir, fingerprint)
        if cached is not None:
            figs = cached
            say(f"report {config.name}: {len(figs)} figures up to date ({fig_dir / FIGURE_MANIFEST}), not redrawn")
        else:
            for fn in (_frf_figures, _hankel_figures, _error_figures, _history_figures, _case_ltd_figures,
                       _heatmap_figures):
                figs += fn(results, fig_dir, dpi, say, paper)
            _write_manifest(fig_dir, fingerprint, figs)
    else:
        say(f"report {config.name}: figures not drawn (figures=False)")

    failed_points = [r for r in results.roms if r.status != "ok"]
    n_ok = sum(1 for r in results.roms if r.status == "ok")
    md = []
    if title is None:
        title = (f"Reproduction of Bagheri, Jones & Gaitonde (2016): study {config.name}" if paper
                 else f"Study report: {config.name}")
    md.append(f"# {title}\n")
    md.append(f"Generated by `studies.report` from the results store of `{config.source}` only (nothing is computed "
              f"here) on {_dt.datetime.now(_dt.timezone.utc):%Y-%m-%d %H:%M} UTC, code at git {_git_commit()}; study "
              f"hash `{config.hash()[:16]}`. Regenerate with `lfdrom report {config.source}`; the text of the prose "
              f"slots (between their HTML comment markers) is kept.\n")
    if getattr(config, "description", ""):
        md.append(f"{config.description}\n")
    md.append("## Status\n")
    md.append(f"{n_ok} of {len(config.points())} identifications done, {len(failed_points)} failed; "
              f"{len(results.sims)} ROM gust histories against {len(results.ltd)} LTD references; "
              f"{len(results.missing)} piece(s) missing, {len(getattr(results, 'failed', []))} other failure(s).\n")
    if results.missing:
        md.append("**Missing** (not in the store yet; run `lfdrom run` to compute them):\n")
        md.append(_bullets(list(results.missing)))
    if failed_points or getattr(results, "failed", []):
        md.append("**Failed** (recorded with their error; the other points went on):\n")
        md.append(_bullets([f"{r.case} T={r.T:.4g} N_omega={r.M + 1} N_r={r.order} {r.method}: {r.error}"
                            for r in failed_points] + list(getattr(results, "failed", []))))
    md.append(_slot("summary", slots, paper))
    if paper:
        md.append(_paper_elsewhere(page_dir))
    md.append("## Study\n")
    md.append(_study_table(config))
    md.append("\nGusts (angle = peak effective gust angle; responses are at this amplitude):\n")
    md.append(_gust_table(config))
    md.append("\nIdentification variants:\n")
    md.append(_method_table(config))
    sim = config.simulation
    md.append(f"\nGust responses: LTD and ROM ({sim.discretisation} re-discretisation) at dt = {sim.dt:g} c/U up to "
              f"s = {sim.t_end:g}, gust front at x0 = {sim.x0:g} c at s = 0; gust method {config.cfd.gust_method}.\n")

    md.append("## Headline accuracy\n")
    md.append("One row per identified ROM: FRF error against the LFD over the whole base grid (peak-normalised, "
              "`sysid.metrics`), DC error (absolute, per radian of gust angle), spectral radius of the discrete ROM "
              "at T, and the largest relative peak error over the gusts with the gust where it occurs.\n")
    rows, cols = tables["summary"]
    if not any(len(cs.T) > 1 for cs in config.cases):
        cols = [c for c in cols if c.key != "T"]  # one T per case: in the study table above
    md.append(format_table(rows, cols, "markdown") if rows else "_(no ROM identified yet)_\n")

    if not figures:
        figs = None
    md.append("\n## Frequency responses: ROM against LFD\n")
    md.append(_figs_md(figs, page_dir, "frf"))
    md.append(_slot("frf", slots, paper))
    md.append("## Hankel singular values\n")
    md.append(_figs_md(figs, page_dir, "hankel"))
    md.append(_slot("hankel", slots, paper))
    md.append("## Errors against N_r, T and N_omega\n")
    md.append(_figs_md(figs, page_dir, "orders"))
    md.append(_slot("orders", slots, paper))
    md.append("## Gust responses: ROM against LTD\n")
    md.append(_figs_md(figs, page_dir, "histories"))
    md.append(_slot("histories", slots, paper))
    if figs is None or any(f.section == "cases" for f in figs):
        md.append("## LTD responses of the cases\n")
        md.append(_figs_md(figs, page_dir, "cases"))
        md.append(_slot("cases", slots, paper))
    md.append("## Peak errors\n")
    md.append(_figs_md(figs, page_dir, "heatmaps"))
    md.append(_slot("heatmaps", slots, paper))
    md.append("## Identification variants: DC matching and stability\n")
    rows, cols = tables["methods"]
    md.append(format_table(rows, cols, "markdown") if rows else "_(no ROM yet)_\n")
    md.append(_slot("methods", slots, paper))
    md.append("## Cost\n")
    rows, cols = tables["cost"]
    md.append("Wall-clock seconds as stored with each piece (LTD time per gust; ROM time: re-discretisation and "
              "simulation of one gust history).\n")
    md.append(format_table(rows, cols, "markdown") if rows else "_(nothing computed yet)_\n")
    md.append(_slot("cost", slots, paper))
    md.append("## Tables\n")
    links = []
    for name in ("summary", "roms", "sims", "methods", "cost"):
        if tables[name][0]:
            files = sorted(tab_dir.glob(f"{name}.*"))
            links.append(f"- {name}: " + ", ".join(f"[{p.suffix[1:]}]({_rel(p, page_dir)})" for p in files))
    md.append("\n".join(links) + "\n" if links else "_(no tables yet)_\n")
    md.append("Columns: T in convective time c/U; N_omega = M + 1 frequencies identified from; N_r the model order; "
              "FRF errors relative (max: peak-normalised per output over the full LFD grid; RMS: energy-normalised); "
              "DC errors absolute per radian of gust angle; peak error |peak_ROM - peak_LTD| / |peak_LTD| with the "
              "peak the signed extreme; peak time error in c/U; RMS error rms(ROM - LTD) / rms(LTD); times in "
              "seconds.\n")
    page_path.write_text("\n".join(md), encoding="utf-8")
    say(f"report {config.name}: {page_path}")
    return page_path


def make_report(study_or_path, output_dir=None, *, store_dir=None, page=None, prose=None, progress: bool = False,
                out_dir=None, dpi: int = 120, title: Optional[str] = None, paper: Optional[bool] = None,
                figures: Optional[bool] = None, redraw: bool = False) -> Path:
    """Tables, figures and a Markdown page of a study, from its results store only.

    Parameters
    ----------
    study_or_path : StudyConfig, path-like or StudyResults
        A validated study, the path of its TOML file, or results already loaded.
    output_dir : path-like, optional
        Where ``report.md``, ``tables/`` and ``figures/`` go. Default: with a page (``page``, or the study's
        ``[report] page`` when ``output_dir`` is not given either), the folder next to the page named after it
        (``docs/paper-reproduction/``); otherwise the study's ``output`` folder.
    store_dir : path-like, optional
        Overrides the study's results store.
    page : path-like, optional
        Write the page there (e.g. ``docs/paper-reproduction.md``) instead of ``output_dir/report.md``.
        Default: the study's ``[report] page`` unless ``output_dir`` is given.
    prose : mapping or path-like, optional
        Text of the prose slots (see the module docstring); default the study's ``[report] prose``.
    progress : bool
        Print the files written (stderr).
    out_dir : path-like, optional
        Same as ``output_dir`` (the name used in the results contract).
    dpi : int
    title : str, optional
    paper : bool, optional
        See :func:`write_report`.
    figures : bool, optional
        See :func:`write_report`; default the study's ``[report] figures`` (true).
    redraw : bool
        See :func:`write_report`.

    Returns
    -------
    pathlib.Path
        The Markdown page.

    Raises
    ------
    studies.config.StudyConfigError
        The study file is invalid.
    ReportError
        The results cannot be read, or the prose is unusable.
    """
    from .config import StudyConfig, load_study

    if output_dir is not None and out_dir is not None and Path(output_dir) != Path(out_dir):
        raise ReportError(f"output_dir ({output_dir}) and out_dir ({out_dir}) disagree; give one of them")
    out = output_dir if output_dir is not None else out_dir
    if hasattr(study_or_path, "roms") and hasattr(study_or_path, "config"):
        results = study_or_path
    else:
        if isinstance(study_or_path, StudyConfig):
            config = study_or_path
        elif isinstance(study_or_path, (str, Path)):
            config = load_study(study_or_path)
        else:
            raise ReportError(f"expected a StudyConfig, a study file or StudyResults, got "
                              f"{type(study_or_path).__name__}")
        if store_dir is not None:
            config = replace(config, store_dir=Path(store_dir))
        from . import results as _results

        loader: Optional[Callable[..., Any]] = getattr(_results, "load_results", None)
        if loader is None:
            raise ReportError("studies.results.load_results is not available in this version")
        results = loader(config)
    rep = getattr(results.config, "report", None)
    if rep is not None:
        if page is None and out is None:
            page = rep.page
        if prose is None:
            prose = rep.prose
        if figures is None:
            figures = rep.figures
        if title is None:
            title = rep.title
        if paper is None:
            paper = rep.paper
    figures = True if figures is None else bool(figures)
    if out is None:
        out = Path(page).with_suffix("") if page is not None else results.config.output_dir
    return write_report(results, out, page=page, prose=prose, progress=progress, dpi=dpi, title=title, paper=paper,
                        figures=figures, redraw=redraw)
