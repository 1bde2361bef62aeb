"""Tables of study results as CSV, Markdown and LaTeX, from plain lists of dictionaries.

No store access and no pandas: the rows are any sequence of mappings (e.g. ``StudyResults.table("rom")`` or
:func:`studies.report.rom_rows`), the columns say which keys to show, under which header and number format.

- **CSV** (``csv`` module) keeps full precision: floats are written with ``repr`` (shortest round-trip form),
  booleans as ``true``/``false``, missing values as empty cells. Formats apply only to the other two.
- **Markdown**: a pipe table, numbers right-aligned, ``|`` escaped, missing values ``-``.
- **LaTeX**: a ``booktabs`` tabular (``\\toprule``, ``\\midrule``, ``\\bottomrule``), text escaped, numbers in
  e-notation typeset as ``$1.2 \\times 10^{-3}$``; wrapped in a ``table`` float when a caption is given.

>>> rows = [{"case": "T2", "order": 25, "err": 1.234e-3, "stable": True}]
>>> print(format_table(rows, ["case", "order", Column("err", "max error", ".2e"), "stable"], "markdown"), end="")
| case | order | max error | stable |
| --- | ---: | ---: | --- |
| T2 | 25 | 1.23e-03 | yes |
"""

from __future__ import annotations

import csv
import io
import math
import numbers
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Iterable, Mapping, Sequence, Union

from ..store.files import atomic_write_text

__all__ = ["Column", "TableError", "cell_text", "format_table", "write_table", "write_tables", "FORMATS", "SUFFIXES"]

FORMATS = ("csv", "markdown", "latex")
SUFFIXES = {"csv": ".csv", "markdown": ".md", "latex": ".tex"}
_BY_SUFFIX = {".csv": "csv", ".md": "markdown", ".markdown": "markdown", ".tex": "latex"}
_ALIASES = {"md": "markdown", "tex": "latex", "csv": "csv", "markdown": "markdown", "latex": "latex"}


class TableError(ValueError):
    """A table cannot be written as asked (unknown column or format, no columns)."""


@dataclass(frozen=True)
class Column:
    """One column of a table.

    Parameters
    ----------
    key : str
        Key of the value in each row.
    header : str, optional
        Header text (default ``key``). Plain text: escaped for LaTeX unless ``latex`` is given.
    fmt : str or callable, optional
        Number format for Markdown and LaTeX: a format spec (``".3e"``, ``".1%"``, ``"d"``) applied to
        numbers, or a callable ``value -> str`` applied to every non-missing value. Default: integers as
        they are, floats with ``".4g"``.
    latex : str, optional
        Header for LaTeX, used verbatim (e.g. ``"$N_r$"``).
    """

    key: str
    header: str | None = None
    fmt: Union[str, Callable[[Any], str], None] = None
    latex: str | None = None

    @property
    def title(self) -> str:
        return self.header if self.header is not None else self.key


ColumnLike = Union[str, Column, tuple]


def _as_columns(columns: Sequence[ColumnLike] | None, rows: Sequence[Mapping]) -> list[Column]:
    if columns is None:
        keys: list[str] = []
        for r in rows:
            for k in r:
                if k not in keys:
                    keys.append(k)
        columns = keys
    out = []
    for c in columns:
        if isinstance(c, Column):
            out.append(c)
        elif isinstance(c, str):
            out.append(Column(c))
        elif isinstance(c, tuple) and 1 <= len(c) <= 4 and isinstance(c[0], str):
            out.append(Column(*c))
        else:
            raise TableError(f"a column must be a key (str), a Column or a tuple (key, header, fmt, latex); got {c!r}")
    if not out:
        raise TableError("no columns to write: give at least one column (or rows with keys)")
    if rows:
        present = set().union(*(r.keys() for r in rows))
        absent = [c.key for c in out if c.key not in present]
        if absent:
            raise TableError(f"column(s) {', '.join(map(repr, absent))} are in no row; the rows have "
                             f"{', '.join(sorted(map(str, present)))}")
    return out


def _missing(v: Any) -> bool:
    return v is None or (isinstance(v, float) and math.isnan(v))


def _is_number(v: Any) -> bool:
    return isinstance(v, numbers.Number) and not isinstance(v, bool)


def _text(v: Any, col: Column) -> str:
    """Formatted cell for Markdown and LaTeX ('' for missing values)."""
    if _missing(v):
        return ""
    if isinstance(v, bool) or (hasattr(v, "dtype") and getattr(v, "dtype", None) == bool):
        return "yes" if bool(v) else "no"
    if callable(col.fmt):
        return str(col.fmt(v))
    if _is_number(v):
        if isinstance(v, numbers.Integral) and (col.fmt is None or col.fmt in ("d", "")):
            return str(int(v))
        spec = col.fmt if col.fmt is not None else ".4g"
        try:
            x = int(v) if isinstance(v, numbers.Integral) and spec.endswith("d") else float(v)
            return format(x, spec)
        except ValueError as e:
            raise TableError(f"column {col.key!r}: format {spec!r} does not apply to {v!r}: {e}") from None
    return str(v)


def cell_text(v: Any, col: Column) -> str:
    """A value as the Markdown table shows it in column ``col`` ('' for a missing value): for numbers quoted
    from a table elsewhere (:mod:`studies.report.numbers`)."""
    return _text(v, col)


def _csv_value(v: Any) -> str:
    if _missing(v):
        return ""
    if isinstance(v, bool) or (hasattr(v, "dtype") and getattr(v, "dtype", None) == bool):
        return "true" if bool(v) else "false"
    if isinstance(v, numbers.Integral):
        return str(int(v))
    if isinstance(v, numbers.Real):
        return repr(float(v))
    return str(v)


def _md_escape(s: str) -> str:
    return s.replace("|", "\\|").replace("\n", " ")


_TEX_SPECIAL = {"\\": r"\textbackslash{}", "&": r"\&", "%": r"\%", "$": r"\$", "#": r"\#", "_": r"\_",
                "{": r"\{", "}": r"\}", "~": r"\textasciitilde{}", "^": r"\textasciicircum{}"}
_E_NUMBER = re.compile(r"^([+-]?\d+(?:\.\d*)?)[eE]([+-]?)0*(\d+)$")


def _tex_escape(s: str) -> str:
    return "".join(_TEX_SPECIAL.get(ch, ch) for ch in s)


def _tex_cell(s: str, numeric: bool) -> str:
    if numeric:
        pct = s.endswith("%")
        core = s[:-1] if pct else s
        m = _E_NUMBER.match(core)
        if m:
            mant, sign, exp = m.groups()
            core = f"${mant} \\times 10^{{{'-' if sign == '-' else ''}{exp}}}$"
        return core + (r"\%" if pct else "")
    return _tex_escape(s)


def _normalise_format(fmt: str) -> str:
    f = _ALIASES.get(str(fmt).lower().lstrip("."))
    if f is None:
        raise TableError(f"unknown table format {fmt!r}; use one of {', '.join(FORMATS)} (or md, tex)")
    return f


def format_table(rows: Sequence[Mapping[str, Any]], columns: Sequence[ColumnLike] | None = None,
                 fmt: str = "markdown", *, caption: str | None = None, label: str | None = None) -> str:
    """A table as text.

    Parameters
    ----------
    rows : sequence of mapping
        One mapping per row. A key missing from a row is an empty cell (``-`` in Markdown).
    columns : sequence of str, Column or tuple, optional
        What to show, in order; a tuple is ``(key, header, fmt, latex)`` (trailing items optional). Default: every
        key of the rows, in order of first appearance.
    fmt : {"markdown", "csv", "latex"}
        Also ``"md"`` and ``"tex"``.
    caption, label : str, optional
        LaTeX only: wrap the tabular in a ``table`` float with this caption (plain text, escaped) and label.

    Returns
    -------
    str
        The table, ending with a newline.

    Raises
    ------
    TableError
        Unknown format, no columns, a column key in no row, a format spec that does not apply.
    """
    fmt = _normalise_format(fmt)
    rows = list(rows)
    cols = _as_columns(columns, rows)
    if fmt == "csv":
        buf = io.StringIO()
        w = csv.writer(buf, lineterminator="\n")
        w.writerow([c.key for c in cols])
        for r in rows:
            w.writerow([_csv_value(r.get(c.key)) for c in cols])
        return buf.getvalue()
    numeric = [bool(rows) and all(_missing(r.get(c.key)) or _is_number(r.get(c.key)) for r in rows)
               and any(not _missing(r.get(c.key)) for r in rows) for c in cols]
    cells = [[_text(r.get(c.key), c) for c in cols] for r in rows]
    if fmt == "markdown":
        lines = ["| " + " | ".join(_md_escape(c.title) for c in cols) + " |",
                 "| " + " | ".join("---:" if n else "---" for n in numeric) + " |"]
        lines += ["| " + " | ".join(_md_escape(v) if v else "-" for v in row) + " |" for row in cells]
        return "\n".join(lines) + "\n"
    # latex
    align = "".join("r" if n else "l" for n in numeric)
    head = " & ".join(c.latex if c.latex is not None else _tex_escape(c.title) for c in cols)
    body = [" & ".join(_tex_cell(v, n) if v else "--" for v, n in zip(row, numeric)) + r" \\" for row in cells]
    tab = [f"\\begin{{tabular}}{{{align}}}", r"\toprule", head + r" \\", r"\midrule", *body, r"\bottomrule",
           r"\end{tabular}"]
    if caption is not None or label is not None:
        tab = [r"\begin{table}", r"\centering", *(["\\caption{" + _tex_escape(caption) + "}"] if caption else []),
               *(["\\label{" + label + "}"] if label else []), *tab, r"\end{table}"]
    return "\n".join(tab) + "\n"


def write_table(rows: Sequence[Mapping[str, Any]], path, columns: Sequence[ColumnLike] | None = None,
                fmt: str | None = None, **kwargs) -> Path:
    """Write :func:`format_table` to ``path``; the format defaults to the suffix (.csv, .md, .tex).

    The file is replaced atomically (:func:`studies.store.files.atomic_write_text`): a failed write leaves an
    existing file as it was.

    Returns
    -------
    pathlib.Path
        The file written (parent folders created).

    Raises
    ------
    TableError
        As :func:`format_table`, or a suffix that names no format when ``fmt`` is not given.
    OSError
        The file cannot be written (the old one, if any, is unchanged).
    """
    path = Path(path)
    if fmt is None:
        fmt = _BY_SUFFIX.get(path.suffix.lower())
        if fmt is None:
            raise TableError(f"{path}: cannot tell the table format from the suffix {path.suffix!r}; use .csv, .md "
                             f"or .tex, or give fmt")
    text = format_table(rows, columns, fmt, **kwargs)
    atomic_write_text(path, text)
    return path


def write_tables(rows: Sequence[Mapping[str, Any]], stem, columns: Sequence[ColumnLike] | None = None,
                 formats: Iterable[str] = FORMATS, **kwargs) -> dict[str, Path]:
    """Write the same table in several formats: ``stem.csv``, ``stem.md``, ``stem.tex``.

    Returns
    -------
    dict
        Format name (``"csv"``, ``"markdown"``, ``"latex"``) -> path written.
    """
    stem = Path(stem)
    out = {}
    for f in formats:
        f = _normalise_format(f)
        kw = kwargs if f == "latex" else {}
        out[f] = write_table(rows, stem.with_name(stem.name + SUFFIXES[f]), columns, f, **kw)
    return out
