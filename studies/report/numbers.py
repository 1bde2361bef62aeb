"""Numbers in a report's prose that come from its tables: ``{{...}}`` templates, filled on every regeneration.

A prose slot (:mod:`studies.report_page`) that quotes a result names the table cell instead of copying the
number, so that the page cannot contradict its tables when the results change::

    T5 N_r = 25: Cm FRF error {{T5/257/25/dc_stable/frf_max_err_Cm}},
    {{max:*/257/>=25/dc_stable/frf_max_err_Cm}} at most

A template is ``{{[AGG:]PATH}}`` with ``PATH`` one of

- ``CASE/N_OMEGA/N_R/METHOD/COLUMN``: a column of the ROM table (``tables/roms``), else of the headline table
  (``worst_peak_err_Cl``, ``worst_gust_Cm``, ...), for the ROM of that case, number of frequencies, order
  and identification method;
- ``CASE/N_OMEGA/N_R/METHOD/GUST/COLUMN``: a column of the gust-history table (``tables/sims``:
  ``peak_err_Cm``, ``rms_err_Cl``, ``speedup``, ...);
- ``CASE/COLUMN``: a column of the cost table (``tables/cost``: ``frf_seconds``, ``frf_error_estimate``,
  ``ltd_seconds``, ``identify_seconds``, ``rom_sim_seconds``, ``speedup``), one row per case;
- ``CASE/GUST/ANGLE/COLUMN``: a column of the linearity table of a study with a ``[nonlinear]`` section
  (``tables/linearity``: ``ltd_error_Cl``, ``rom_ratio_Cm``, ``n_factorisations``, ...), for the march of that
  case and gust at that gust angle in degrees.

``CASE`` may carry the sampling period (not in a cost template: the cost table's rows are per case), ``T4@2.5`` or ``*@2,4`` (matched as the tables print T, four
significant digits).
Each part of the selection is a value, a comma list (``T1,T3``), ``*`` (any) or, for N_OMEGA and N_R, a
bound (``>=25``, ``<=33``). Without ``AGG`` the selection must be one row; with it, ``min``, ``max``,
``mean``, ``median`` or ``range`` (``min - max``) over the rows selected (values that are not finite numbers
are left out; a selection without any is shown as missing). The value is formatted as its table
formats that column (``0.366%``, ``1.8e-15``, ``0.99900``), so that the number on the page is the one in
the table.

The linearity table names the gusts that share a march ``G2/G3``; ``G2`` or ``G3`` selects that row.

The page keeps each template beside its value, ``<!--{{PATH}}-->0.366%<!--/-->`` (HTML comments: invisible
when rendered), so that a slot kept from the page (:func:`studies.report_page.read_prose`) is filled anew
from the store on the next regeneration instead of keeping the old number (:func:`unfill`).

A template that cannot name a cell (bad syntax, unknown column, several rows without ``AGG``) is a
:class:`studies.report_page.ReportError`; one whose cell is not in the store yet (an incomplete run) is
shown as ``**(no result: PATH)**``.
"""

from __future__ import annotations

import math
import re
import statistics
from typing import Mapping, Sequence

__all__ = ["TemplateError", "TEMPLATE_RE", "check_templates", "fill", "unfill", "AGGREGATES"]

TEMPLATE_RE = re.compile(r"\{\{\s*(?P<body>[^{}]+?)\s*\}\}")
"""A template in prose text: ``{{...}}``."""

_FILLED_RE = re.compile(r"<!--(?P<template>\{\{[^{}]+\}\})-->.*?<!--/-->", re.S)
"""A filled template in a page: the template in a comment, its value, the closing comment."""

AGGREGATES = ("min", "max", "mean", "median", "range")
_KEYS = ("case", "N_omega", "order", "method")


class TemplateError(ValueError):
    """A template that cannot name a table cell; the message says which and why."""


def _parse(body: str) -> tuple:
    """``(aggregate or None, selection dict, column, table kind)`` of a template body."""
    agg = None
    head, sep, rest = body.partition(":")
    if sep:
        if head.strip() not in AGGREGATES:
            raise TemplateError(f"{{{{{body}}}}}: {head.strip()!r} is not one of {', '.join(AGGREGATES)}")
        agg, body = head.strip(), rest
    parts = [p.strip() for p in body.split("/")]
    if len(parts) not in (2, 4, 5, 6) or not all(parts):
        raise TemplateError(f"{{{{{body}}}}}: give CASE/N_OMEGA/N_R/METHOD/COLUMN (ROM and headline tables), "
                            "CASE/N_OMEGA/N_R/METHOD/GUST/COLUMN (gust-history table), CASE/COLUMN (cost table) "
                            "or CASE/GUST/ANGLE/COLUMN (linearity table)")
    if len(parts) == 2:
        if "@" in parts[0]:
            raise TemplateError(f"{{{{{body}}}}}: the cost table has one row per case, not per T; drop the @T")
        return agg, dict(case=parts[0], T=None), parts[-1], "cost"
    if len(parts) == 4:
        sel = dict(case=parts[0], gust=parts[1], amplitude_deg=parts[2], T=None)
        if parts[2] != "*" and not re.fullmatch(r"(>=|<=|>|<)?[0-9.]+(,[0-9.]+)*", parts[2]):
            raise TemplateError(f"{{{{{body}}}}}: angle {parts[2]!r} is not a number, a comma list, * or a bound")
        return agg, sel, parts[-1], "linearity"
    case, T = (parts[0].split("@", 1) + [None])[:2]
    sel = dict(zip(_KEYS, [case] + parts[1:4]))
    sel["T"] = T
    kind = "sims" if len(parts) == 6 else "roms"
    if kind == "sims":
        sel["gust"] = parts[4]
    for key in ("N_omega", "order"):
        spec = sel[key]
        if spec != "*" and not re.fullmatch(r"(>=|<=|>|<)?\d+(,\d+)*", spec):
            raise TemplateError(f"{{{{{body}}}}}: {key} {spec!r} is not a number, a comma list, * or a bound "
                                "(>=25)")
    if T is not None:
        try:
            sel["T"] = [float(f"{float(v):.4g}") for v in T.split(",")]
        except ValueError:
            raise TemplateError(f"{{{{{body}}}}}: T {T!r} (after @) is not a number or a comma list") from None
    return agg, sel, parts[-1], kind


def check_templates(text: str, where: str = "prose") -> None:
    """Check the syntax of every template in ``text`` (before anything is computed).

    Raises
    ------
    TemplateError
        Names ``where`` and the template.
    """
    for match in TEMPLATE_RE.finditer(text):
        try:
            _parse(match.group("body"))
        except TemplateError as e:
            raise TemplateError(f"{where}: {e}") from None


def _matches(value, spec) -> bool:
    if spec is None or spec == "*":
        return True
    if isinstance(value, float) and not isinstance(spec, str):
        return False
    if isinstance(spec, str) and spec[:2] in (">=", "<="):
        bound = float(spec[2:])
        return value is not None and (value >= bound if spec[:2] == ">=" else value <= bound)
    if isinstance(spec, str) and spec[:1] in (">", "<"):
        bound = float(spec[1:])
        return value is not None and (value > bound if spec[0] == ">" else value < bound)
    if isinstance(value, float):   # an angle: 5 matches 5.0
        return any(value == float(v) for v in spec.split(","))
    # a shared entry (the linearity table's "G2/G3": gusts of one shape share their march) matches either name
    return any(part in spec.split(",") for part in str(value).split("/"))


def _select(rows: Sequence[Mapping], sel: dict) -> list:
    out = []
    keys = [k for k in sel if k != "T"]
    for row in rows:
        if not all(_matches(row.get(k), sel[k]) for k in keys):
            continue
        if sel["T"] is not None and float(f"{float(row.get('T', math.nan)):.4g}") not in sel["T"]:
            continue
        out.append(row)
    return out


def _value(body: str, tables: Mapping) -> str | None:
    """The formatted value of one template; None when the store has no such result yet."""
    from .tables import TableError, cell_text

    agg, sel, column, kind = _parse(body)
    names = {"sims": ("sims",), "linearity": ("linearity",), "cost": ("cost",)}.get(kind, ("roms", "summary"))
    found = [(tables[n][0], {c.key: c for c in tables[n][1]}) for n in names if n in tables]
    found = [(rows, cols) for rows, cols in found if column in cols]
    if not found:
        from .rows import cost_columns, rom_columns, sim_columns, summary_columns

        if kind == "linearity":  # offered by a section (Section.template_tables) whose results are not stored yet
            return None
        known = {c.key for c in {"sims": sim_columns, "cost": cost_columns}.get(
            kind, lambda: rom_columns() + summary_columns())()}
        if column not in known:
            raise TemplateError(f"{{{{{body}}}}}: no column {column!r} in the {' or '.join(names)} table")
        return None
    rows, cols = found[0]
    picked = _select(rows, sel)
    if agg is None:
        if len(picked) > 1:
            what = ("case, gust, angle" if kind == "linearity" else "case" if kind == "cost" else
                    f"case, N_omega, N_r, method{', gust' if kind == 'sims' else ''}, T with CASE@T")
            raise TemplateError(f"{{{{{body}}}}}: selects {len(picked)} rows; name one ({what}) or aggregate "
                                f"({'/'.join(AGGREGATES)}:...)")
        if not picked or picked[0].get(column) is None:
            return None
        return cell_text(picked[0][column], cols[column]) or None
    values = [r[column] for r in picked
              if isinstance(r.get(column), (int, float)) and not isinstance(r.get(column), bool)
              and math.isfinite(float(r[column]))]
    if not values:
        return None

    def fmt(v):
        try:
            return cell_text(v, cols[column])
        except TableError:   # a mean or median of an integer column
            return f"{v:.4g}"
    if agg == "range":
        lo, hi = fmt(min(values)), fmt(max(values))
        return lo if lo == hi else f"{lo} - {hi}"
    return fmt({"min": min, "max": max, "mean": statistics.fmean, "median": statistics.median}[agg](values))


def fill(text: str, tables: Mapping, where: str = "prose") -> str:
    """``text`` with every template replaced by its value from ``tables``, the template kept beside it.

    Parameters
    ----------
    text : str
        A prose slot's text (templates ``{{...}}``; filled ones from a page are read back first, :func:`unfill`).
    tables : mapping
        :func:`studies.report_rows.report_tables` of the results: name -> ``(rows, columns)``.
    where : str
        For messages (the slot's name).

    Raises
    ------
    TemplateError
        A template that names no cell (module docstring).
    """
    def one(match):
        body = match.group("body")
        try:
            value = _value(body, tables)
        except TemplateError as e:
            raise TemplateError(f"{where}: {e}") from None
        shown = value if value is not None else f"**(no result: {body})**"
        return f"<!--{{{{{body}}}}}-->{shown}<!--/-->"

    return TEMPLATE_RE.sub(one, unfill(text))


def unfill(text: str) -> str:
    """The templates of a filled text (a slot read from a page): ``<!--{{X}}-->value<!--/-->`` -> ``{{X}}``."""
    return _FILLED_RE.sub(lambda m: m.group("template"), text)
