"""The parts of a study file that :func:`studies.config.parse_study` reads by delegation: one entry of
``cases`` (:func:`parse_case_entry`) and the ``[report]`` table (:func:`parse_report_table`)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from .case_types import MIN_MACH
from .cases import TEST_CASES, CaseError, FlowCase, GridSpec, flow_case, naca_code
from .reader import CASE_KEYS, GRID_KEYS, REPORT_KEYS, ConfigReader, grid_config_error
from .schema import CaseSweep, ReportOptions

__all__ = ["parse_case_entry", "parse_report_table"]


def parse_case_entry(P: ConfigReader, entry, key, base_grid, g_orders, g_T, g_M, parse_order, parse_T,
                     parse_M) -> CaseSweep:
    """One entry of ``cases`` (a paper case name or a table) as a :class:`CaseSweep`.

    Parameters
    ----------
    P : ConfigReader
    entry : str or dict
    key : str
        Its dotted key, ``"cases[i]"``.
    base_grid : GridSpec
        The study's ``[grid]``, under the entry's own ``grid``.
    g_orders, g_T, g_M : tuple or None
        The ``[sweep]`` axes, used where the entry gives none.
    parse_order, parse_T, parse_M : callable
        ``(value, key) -> value``: the readers of one axis value (they know ``M_base``).
    """
    if isinstance(entry, str):
        if entry.casefold() not in {n.casefold() for n in TEST_CASES}:
            raise P.err(key, f"unknown test case {entry!r}; the paper's are {', '.join(TEST_CASES)} (case-insensitive); "
                        "define your own as a table, e.g. {name = \"mine\", naca = \"0012\", mach = 0.5}")
        entry = {"name": entry}
    entry = P.table(entry, key)
    P.check_keys(entry, CASE_KEYS, key)
    if "name" not in entry:
        raise P.err(f"{key}.name", "missing: every case needs a name (a paper case T1-T6, or your own label)")
    name = entry["name"]
    if not isinstance(name, str):
        raise P.err(f"{key}.name", f"must be a string, got {name!r}")
    flow_keys = [k for k in ("naca", "mach", "alpha_deg") if k in entry]
    grid_t = P.table(entry.get("grid", {}), f"{key}.grid")
    P.check_keys(grid_t, GRID_KEYS, f"{key}.grid")
    try:
        grid = GridSpec(**{**base_grid.kwargs(), **grid_t})
    except CaseError as e:
        raise grid_config_error(P, f"{key}.grid", e) from None
    is_paper = name.casefold() in {n.casefold() for n in TEST_CASES}
    if is_paper:
        if flow_keys:
            raise P.err(f"{key}.{flow_keys[0]}", f"{name!r} is a paper case with a fixed aerofoil, Mach number "
                        "and incidence; give your case another name to define it yourself")
        case = replace(flow_case(name), grid=grid)
    else:
        missing = [k for k in ("naca", "mach") if k not in entry]
        if missing:
            raise P.err(f"{key}.{missing[0]}", (
                f"missing: {name!r} is not a paper case ({', '.join(TEST_CASES)}), so it needs naca and mach "
                "(and optionally alpha_deg, grid)"))
        try:
            naca = naca_code(f"case {name!r}", entry["naca"])
        except CaseError as e:
            raise P.err(f"{key}.naca", str(e)) from None
        mach = P.number(entry["mach"], f"{key}.mach")
        if not MIN_MACH <= mach < 1.0:
            raise P.err(f"{key}.mach", f"mach = {mach} is out of range; use {MIN_MACH} <= mach < 1 (subsonic free "
                                       "stream; below 0.01 the solver's low-Mach dissipation spoils the flow)")
        alpha = P.number(entry.get("alpha_deg", 0.0), f"{key}.alpha_deg")
        if abs(alpha) >= 90.0:
            raise P.err(f"{key}.alpha_deg", f"alpha_deg = {alpha} is not an incidence; use |alpha_deg| < 90")
        try:
            case = FlowCase(name, naca, mach, alpha, grid)
        except CaseError as e:
            raise P.err(f"{key}.name", str(e)) from None
    orders = P.axis(entry["orders"], f"{key}.orders", parse_order) if "orders" in entry else g_orders
    if orders is None:
        raise P.err("sweep.orders", f"missing: give the model orders N_r in [sweep] (orders = [9, 15, 25]) or "
                    f"in {key}")
    T = P.axis(entry["T"], f"{key}.T", parse_T) if "T" in entry else g_T
    M = P.axis(entry["M"], f"{key}.M", parse_M) if "M" in entry else g_M
    return CaseSweep(case=case, orders=orders, T=T, M=M)


def parse_report_table(P: ConfigReader, table, base: Path) -> ReportOptions:
    """The ``[report]`` table as :class:`ReportOptions` (paths taken from ``base``, the study file's folder)."""
    rep = P.table(table, "report")
    P.check_keys(rep, REPORT_KEYS, "report")
    page = rep.get("page")
    if page is not None:
        page = (base / P.string(page, "report.page")).resolve()
        if page.suffix != ".md":
            raise P.err("report.page", f"{page.name!r} is not a Markdown file; give a path ending in .md (its "
                        "tables and figures go to the folder of the same name)")
        if page.exists() and not page.is_file():
            raise P.err("report.page", f"{page} exists and is not a file")
    prose = rep.get("prose")
    if prose is not None:
        prose = (base / P.string(prose, "report.prose")).resolve()
        if not prose.is_file():
            raise P.err("report.prose", f"no such file {prose}; give a TOML file of slot = \"text\" lines, or "
                        "leave the key out")
    figures = P.boolean(rep.get("figures", True), "report.figures")
    title = P.string(rep["title"], "report.title") if "title" in rep else None
    if title is not None and not title.strip():
        raise P.err("report.title", "must not be empty; leave the key out for the default title")
    paper = P.boolean(rep["paper"], "report.paper") if "paper" in rep else None
    return ReportOptions(page=page, prose=prose, figures=figures, title=title, paper=paper)
