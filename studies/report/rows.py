"""The report's rows and tables: plain rows of a :class:`studies.store.results.StudyResults` and their columns.

:func:`rom_rows`, :func:`sim_rows`, :func:`summary_rows`, :func:`method_rows` and :func:`cost_rows` read the
stored results only; :func:`report_tables` pairs each with its columns (:mod:`studies.report.tables`) under the names of
the files in ``tables/``. The figures (:mod:`studies.report.figures`) and the page (:mod:`studies.report.page`)
are built from these rows.
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np

from .tables import Column

__all__ = [
    "TABLE_NAMES",
    "percent",
    "is_number",
    "T_key",
    "point_key",
    "frf_outputs",
    "history_outputs",
    "rom_rows",
    "sim_rows",
    "summary_rows",
    "method_rows",
    "cost_rows",
    "rom_columns",
    "sim_columns",
    "summary_columns",
    "method_columns",
    "cost_columns",
    "present_columns",
    "report_tables",
]

TABLE_NAMES = ("roms", "sims", "summary", "methods", "cost")
"""The report's tables, in the order they are written (``tables/NAME.{csv,md,tex}``)."""


def percent(value) -> str:
    """A relative error as a percentage with three significant digits ("inf" for an infinite one)."""
    value = float(value)
    if math.isinf(value):
        return "inf"
    return f"{100.0 * value:.3g}%"


def is_number(value) -> bool:
    """``value`` is a finite real number (not a bool, not None)."""
    return value is not None and not isinstance(value, bool) \
        and isinstance(value, (int, float, np.floating, np.integer)) and math.isfinite(float(value))


def T_key(T) -> float:
    """``T`` rounded to nine significant digits: equal for the same sampling period read from any record."""
    return float(f"{float(T):.9g}")


def point_key(row) -> tuple:
    """``(case, T, M, order, method)`` of a ROM or gust-history row: the sweep point and variant it belongs to."""
    return (row["case"], T_key(row["T"]), row["M"], row["order"], row["method"])


def frf_outputs(results) -> list:
    """The outputs of the study's frequency responses (default Cl and Cm)."""
    outputs = [name for name in getattr(results.config.cfd, "outputs", ("Cl", "Cm"))]
    return outputs or ["Cl", "Cm"]


def history_outputs(results) -> list:
    """The outputs of the gust histories: those of :func:`frf_outputs` that are Cl or Cm."""
    return [name for name in frf_outputs(results) if name in ("Cl", "Cm")]


def rom_rows(results) -> list:
    """One row per sweep point (ok or failed): ``StudyResults.table("rom")`` (NaN metrics for failed points)."""
    return [dict(row) for row in results.table("rom")]


def sim_rows(results) -> list:
    """One row per ROM gust history: ``StudyResults.table("sim")`` plus ``speedup = seconds_ltd / seconds_rom``."""
    rows = []
    for row in results.table("sim"):
        row = dict(row)
        seconds_rom, seconds_ltd = row.get("seconds_rom"), row.get("seconds_ltd")
        row["speedup"] = (seconds_ltd / seconds_rom) if is_number(seconds_rom) and is_number(seconds_ltd) \
            and seconds_rom > 0 else float("nan")
        rows.append(row)
    return rows


def summary_rows(results) -> list:
    """The headline table: one row per identified ROM, its FRF and DC errors and its worst gust errors.

    Keys: ``case, aerofoil, mach, T, N_omega, order, method, frf_max_err_X`` (each output X),
    ``dc_err_Cl, spectral_radius, stable``, and over the study's gusts ``worst_peak_err_X`` with ``worst_gust_X``
    (for X in Cl, Cm; NaN and "-" when no gust history exists).
    """
    cases = {study_case.case.name: study_case.case for study_case in results.config.cases}
    outputs = frf_outputs(results)
    worst: dict = {}
    for sim in sim_rows(results):
        key = point_key(sim)
        for output in ("Cl", "Cm"):
            value = sim.get(f"peak_err_{output}")
            if is_number(value):
                current = worst.get((key, output))
                if current is None or value > current[0]:
                    worst[(key, output)] = (float(value), sim["gust"])
    rows = []
    for rom in rom_rows(results):
        if rom.get("status") != "ok":
            continue
        case = cases.get(rom["case"])
        row = dict(case=rom["case"], aerofoil=f"NACA{case.naca}" if case is not None else "",
                   mach=case.mach if case else None, T=rom["T"], N_omega=rom["N_omega"], order=rom["order"],
                   method=rom["method"])
        for output in outputs:
            row[f"frf_max_err_{output}"] = rom.get(f"frf_max_err_{output}")
        row["dc_err_Cl"] = rom.get("dc_err_Cl")
        row["spectral_radius"] = rom.get("spectral_radius")
        row["stable"] = rom.get("stable")
        for output in ("Cl", "Cm"):
            found = worst.get((point_key(rom), output))
            row[f"worst_peak_err_{output}"] = found[0] if found else float("nan")
            row[f"worst_gust_{output}"] = found[1] if found else None
        rows.append(row)
    return rows


def _median(values) -> float:
    return float(np.median(values)) if values else float("nan")


def _largest(values) -> float:
    return float(np.max(values)) if values else float("nan")


def method_rows(results) -> list:
    """Method variants compared: per case and method, the median and worst errors over its ROMs.

    Keys: ``case, method, n_roms, n_failed, n_unstable, median_frf_max_err_Cl, worst_frf_max_err_Cl,
    max_dc_err_Cl, max_spectral_radius, median_peak_err_Cl, worst_peak_err_Cl`` (and the Cm errors).
    """
    rows = []
    roms = rom_rows(results)
    sims = sim_rows(results)
    seen = []
    for rom in roms:
        if (rom["case"], rom["method"]) not in seen:
            seen.append((rom["case"], rom["method"]))
    for case, method in seen:
        variant_roms = [rom for rom in roms if rom["case"] == case and rom["method"] == method]
        ok = [rom for rom in variant_roms if rom.get("status") == "ok"]
        variant_sims = [sim for sim in sims if sim["case"] == case and sim["method"] == method]
        row = dict(case=case, method=method, n_roms=len(ok), n_failed=len(variant_roms) - len(ok),
                   n_unstable=sum(1 for rom in ok if rom.get("stable") is False))
        for output in ("Cl", "Cm"):
            frf_errors = [rom.get(f"frf_max_err_{output}") for rom in ok if is_number(rom.get(f"frf_max_err_{output}"))]
            peak_errors = [sim.get(f"peak_err_{output}") for sim in variant_sims
                           if is_number(sim.get(f"peak_err_{output}"))]
            row[f"median_frf_max_err_{output}"] = _median(frf_errors)
            row[f"worst_frf_max_err_{output}"] = _largest(frf_errors)
            row[f"median_peak_err_{output}"] = _median(peak_errors)
            row[f"worst_peak_err_{output}"] = _largest(peak_errors)
        dc_errors = [rom.get("dc_err_Cl") for rom in ok if is_number(rom.get("dc_err_Cl"))]
        radii = [rom.get("spectral_radius") for rom in ok if is_number(rom.get("spectral_radius"))]
        row["max_dc_err_Cl"] = _largest(dc_errors)
        row["max_spectral_radius"] = _largest(radii)
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
    for study_case in results.config.cases:
        name = study_case.case.name
        sweeps = [frf for (case, _), frf in results.frf.items() if case == name]
        references = [ltd for (case, _), ltd in results.ltd.items() if case == name]
        identify = [rom.get("seconds") for rom in roms if rom["case"] == name and is_number(rom.get("seconds"))]
        rom_seconds = [sim.get("seconds_rom") for sim in sims
                       if sim["case"] == name and is_number(sim.get("seconds_rom"))]
        ltd_seconds = [float(ltd.seconds) for ltd in references if is_number(ltd.seconds)]
        row = dict(case=name,
                   frf_seconds=float(sum(frf.seconds for frf in sweeps)) if sweeps else float("nan"),
                   n_frequencies=int(sweeps[0].frf.H.shape[-1]) if sweeps else None,
                   frf_error_estimate=float(np.nanmax([frf.max_relative_error_estimate for frf in sweeps]))
                   if sweeps and any(is_number(frf.max_relative_error_estimate) for frf in sweeps) else float("nan"),
                   ltd_seconds=float(np.mean(ltd_seconds)) if ltd_seconds else float("nan"), n_gusts=len(references),
                   identify_seconds=_median(identify),
                   rom_sim_seconds=_median(rom_seconds))
        row["speedup"] = (row["ltd_seconds"] / row["rom_sim_seconds"]
                          if is_number(row["ltd_seconds"]) and is_number(row["rom_sim_seconds"])
                          and row["rom_sim_seconds"] > 0 else float("nan"))
        rows.append(row)
    return rows


def _point_columns() -> list:
    return [Column("case"), Column("T", "T [c/U]", ".4g", "$T$"), Column("N_omega", "N_omega", "d", r"$N_\omega$"),
            Column("order", "N_r", "d", "$N_r$"), Column("method")]


def _tex(output: str) -> str:
    """``Cl`` -> ``$C_l$``."""
    return f"${output[0]}_{output[1:]}$"


def rom_columns(outputs: Sequence[str] = ("Cl", "Cm")) -> list:
    """Columns of the ROM table (:func:`rom_rows`), with units in the headers."""
    columns = _point_columns() + [Column("status")]
    for output in outputs:
        columns += [Column(f"frf_max_err_{output}", f"FRF max err {output}", percent, f"max err {_tex(output)}"),
                    Column(f"frf_rms_err_{output}", f"FRF RMS err {output}", percent, f"RMS err {_tex(output)}")]
    columns += [Column("frf_max_err_fit", "max err on fitted points", percent)]
    for output in outputs:
        columns.append(Column(f"dc_err_{output}", f"DC err {output} [1/rad]", ".1e", f"DC err {_tex(output)} [1/rad]"))
    columns += [Column("spectral_radius", "spectral radius", ".6f", r"$\rho(\hat A)$"), Column("stable"),
                Column("seconds", "identify [s]", ".3g"), Column("error")]
    return columns


def sim_columns(outputs: Sequence[str] = ("Cl", "Cm")) -> list:
    """Columns of the gust-history table (:func:`sim_rows`)."""
    columns = _point_columns() + [Column("gust")]
    for output in outputs:
        columns += [Column(f"peak_err_{output}", f"peak err {output}", percent, f"peak err {_tex(output)}"),
                    Column(f"t_peak_err_{output}", f"peak time err {output} [c/U]", ".3g"),
                    Column(f"rms_err_{output}", f"RMS err {output}", percent, f"RMS err {_tex(output)}")]
    columns += [Column("seconds_rom", "ROM [s]", ".3g"), Column("seconds_ltd", "LTD [s]", ".4g"),
                Column("speedup", "LTD / ROM time", ".3g")]
    return columns


def summary_columns(outputs: Sequence[str] = ("Cl", "Cm")) -> list:
    """Columns of the headline table (:func:`summary_rows`)."""
    columns = [Column("case"), Column("aerofoil"), Column("mach", "Mach", ".4g"),
               Column("T", "T [c/U]", ".4g", "$T$"), Column("N_omega", "N_omega", "d", r"$N_\omega$"),
               Column("order", "N_r", "d", "$N_r$"), Column("method")]
    for output in outputs:
        columns.append(Column(f"frf_max_err_{output}", f"FRF max err {output}", percent, f"FRF {_tex(output)}"))
    columns += [Column("dc_err_Cl", "DC err Cl [1/rad]", ".1e", "DC $C_l$ [1/rad]"),
                Column("spectral_radius", "spectral radius", ".5f", r"$\rho(\hat A)$"), Column("stable")]
    for output in ("Cl", "Cm"):
        columns += [Column(f"worst_peak_err_{output}", f"worst peak err {output}", percent, f"peak {_tex(output)}"),
                    Column(f"worst_gust_{output}", "at gust")]
    return columns


def method_columns() -> list:
    """Columns of the method-variant table (:func:`method_rows`)."""
    columns = [Column("case"), Column("method"), Column("n_roms", "ROMs"), Column("n_failed", "failed"),
               Column("n_unstable", "unstable")]
    for output in ("Cl", "Cm"):
        columns += [Column(f"median_frf_max_err_{output}", f"median FRF max err {output}", percent),
                    Column(f"worst_frf_max_err_{output}", f"worst FRF max err {output}", percent)]
    columns += [Column("max_dc_err_Cl", "max DC err Cl [1/rad]", ".1e"),
                Column("max_spectral_radius", "max spectral radius", ".5f")]
    for output in ("Cl", "Cm"):
        columns += [Column(f"median_peak_err_{output}", f"median peak err {output}", percent),
                    Column(f"worst_peak_err_{output}", f"worst peak err {output}", percent)]
    return columns


def cost_columns() -> list:
    """Columns of the cost table (:func:`cost_rows`)."""
    return [Column("case"), Column("n_frequencies", "LFD frequencies"),
            Column("frf_seconds", "LFD sweep [s]", ".4g"),
            Column("frf_error_estimate", "LFD est. max rel. error", ".1e"),
            Column("n_gusts", "gusts"), Column("ltd_seconds", "LTD per gust [s]", ".4g"),
            Column("identify_seconds", "identify per ROM [s]", ".3g"),
            Column("rom_sim_seconds", "ROM per gust [s]", ".3g"), Column("speedup", "LTD / ROM time", ".3g")]


def present_columns(columns: list, rows: list) -> list:
    """Columns whose key is in some row (outputs a study does not compute drop out)."""
    present = set().union(*(row.keys() for row in rows)) if rows else {column.key for column in columns}
    return [column for column in columns if column.key in present]


def report_tables(results) -> dict:
    """The report's tables: name (:data:`TABLE_NAMES`) -> ``(rows, columns)``, the columns those in the rows."""
    outputs = frf_outputs(results)
    built = {"roms": (rom_rows(results), rom_columns(outputs)),
             "sims": (sim_rows(results), sim_columns(history_outputs(results))),
             "summary": (summary_rows(results), summary_columns(outputs)),
             "methods": (method_rows(results), method_columns()),
             "cost": (cost_rows(results), cost_columns())}
    return {name: (rows, present_columns(columns, rows)) for name, (rows, columns) in built.items()}
