"""studies.report.tables: CSV / Markdown / LaTeX tables from lists of dicts."""

import csv
import io
import math

import pytest

from studies.report.tables import Column, TableError, format_table, write_table, write_tables

ROWS = [
    dict(case="T2", order=25, err=1.234567e-3, stable=True, note="a|b", gust=None),
    dict(case="T5_x", order=55, err=float("nan"), stable=False, note="50% & more", gust="G3"),
]
COLS = ["case", Column("order", "N_r", "d", "$N_r$"), Column("err", "max err", ".2e"), "stable", "note", "gust"]


def test_markdown_cells_alignment_and_escapes():
    text = format_table(ROWS, COLS, "md")
    lines = text.splitlines()
    assert lines[0] == "| case | N_r | max err | stable | note | gust |"
    assert lines[1] == "| --- | ---: | ---: | --- | --- | --- |"  # numbers right-aligned
    assert lines[2] == "| T2 | 25 | 1.23e-03 | yes | a\\|b | - |"  # pipe escaped, None -> '-'
    assert lines[3] == "| T5_x | 55 | - | no | 50% & more | G3 |"  # NaN -> '-'
    assert text.endswith("\n")


def test_csv_keeps_full_precision_and_reads_back():
    text = format_table(ROWS, COLS, "csv")
    rows = list(csv.DictReader(io.StringIO(text)))
    assert list(rows[0]) == ["case", "order", "err", "stable", "note", "gust"]  # keys, not headers
    assert float(rows[0]["err"]) == ROWS[0]["err"]  # no rounding by the format
    assert rows[0]["stable"] == "true" and rows[1]["stable"] == "false"
    assert rows[1]["err"] == "" and rows[0]["gust"] == "" and rows[0]["note"] == "a|b"


def test_latex_booktabs_escapes_and_powers_of_ten():
    text = format_table(ROWS, COLS, "latex", caption="Errors of T2_x", label="tab:err")
    assert text.startswith("\\begin{table}") and "\\caption{Errors of T2\\_x}" in text and "\\label{tab:err}" in text
    assert "\\begin{tabular}{lrrlll}" in text and "\\toprule" in text and "\\bottomrule" in text
    assert "case & $N_r$ & max err" in text  # verbatim LaTeX header, escaped plain ones
    assert "$1.23 \\times 10^{-3}$" in text
    assert "T5\\_x" in text and "50\\% \\& more" in text
    assert "T5\\_x & 55 & -- & no" in text  # missing value
    assert not format_table(ROWS, COLS, "tex").startswith("\\begin{table}")  # no float without a caption


def test_percent_callable_and_default_formats():
    rows = [dict(x=0.01234, n=3, big=123456.789)]
    md = format_table(rows, [Column("x", fmt=lambda v: f"{100 * v:.3g}%"), "n", "big"], "markdown")
    assert "| 1.23% | 3 | 1.235e+05 |" in md
    tex = format_table([dict(x=2e-12)], [Column("x", fmt=lambda v: f"{100 * v:.2g}%")], "latex")
    assert "$2 \\times 10^{-10}$\\%" in tex


def test_default_columns_are_every_key_in_order():
    rows = [dict(a=1, b=2), dict(b=3, c=4.5)]
    assert format_table(rows, None, "md").splitlines()[0] == "| a | b | c |"
    assert format_table(rows, None, "md").splitlines()[3] == "| - | 3 | 4.5 |"


@pytest.mark.parametrize("fmt, suffix", [("csv", ".csv"), ("markdown", ".md"), ("latex", ".tex")])
def test_write_table_by_suffix(tmp_path, fmt, suffix):
    path = write_table(ROWS, tmp_path / "sub" / f"t{suffix}", COLS)
    assert path.read_text() == format_table(ROWS, COLS, fmt)


def test_write_tables_all_formats(tmp_path):
    out = write_tables(ROWS, tmp_path / "roms", COLS, caption="c")
    assert sorted(p.name for p in out.values()) == ["roms.csv", "roms.md", "roms.tex"]
    assert "\\caption{c}" in out["latex"].read_text() and "caption" not in out["markdown"].read_text()


@pytest.mark.parametrize("call, match", [
    (lambda: format_table(ROWS, COLS, "html"), "unknown table format 'html'"),
    (lambda: format_table(ROWS, ["case", "nope"], "md"), "column\\(s\\) 'nope' are in no row"),
    (lambda: format_table(ROWS, [3], "md"), "a column must be a key"),
    (lambda: format_table([], [], "md"), "no columns"),
    (lambda: format_table([dict(x=1.5)], [Column("x", fmt="d")], "md"), "format 'd' does not apply"),
    (lambda: write_table(ROWS, "t.html", COLS), "cannot tell the table format"),
])
def test_bad_requests(call, match):
    with pytest.raises(TableError, match=match):
        call()


def test_table_error_is_a_value_error():
    assert issubclass(TableError, ValueError)
    assert math.isnan(ROWS[1]["err"])  # the fixture row really holds a NaN (the '-' cells above come from it)
