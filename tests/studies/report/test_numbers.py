"""Numbers in prose slots filled from the report's tables (``studies.report.numbers``): a page cannot quote a
number its tables do not hold, and a regenerated page quotes the store's current value."""

import re
import tomllib
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import pytest  # noqa: E402

from studies.report import ReportError, make_report  # noqa: E402
from studies.report.numbers import TemplateError, check_templates, fill, unfill  # noqa: E402
from studies.report.rows import report_tables  # noqa: E402
from studies.report.tables import cell_text  # noqa: E402
from smallstudy import small_results  # noqa: E402

STUDIES = Path(__file__).resolve().parents[3] / "studies"



@pytest.fixture(scope="module")
def small(tmp_path_factory):
    out = tmp_path_factory.mktemp("small")
    return small_results(out, ("G3", "G4"))


@pytest.fixture(scope="module")
def tables(small):
    return report_tables(small)


def _cell(tables, name, column, **where):
    rows, columns = tables[name]
    (row,) = [r for r in rows if all(r[k] == v for k, v in where.items())]
    return cell_text(row[column], {c.key: c for c in columns}[column])


def _value(filled):
    return re.fullmatch(r"<!--\{\{.*\}\}-->(.*)<!--/-->", filled).group(1)


def test_a_template_is_its_table_cell(tables):
    text = fill("{{synth/33/6/dc_stable/frf_max_err_Cm}}", tables)
    assert _value(text) == _cell(tables, "roms", "frf_max_err_Cm", N_omega=33, order=6, method="dc_stable")
    assert _value(text).endswith("%")
    gust = fill("{{synth/17/2/plain/G4/peak_err_Cl}}", tables)
    assert _value(gust) == _cell(tables, "sims", "peak_err_Cl", N_omega=17, order=2, method="plain", gust="G4")
    worst = fill("{{synth/33/6/plain/worst_peak_err_Cl}}", tables)   # the headline table's columns too
    assert _value(worst) == _cell(tables, "summary", "worst_peak_err_Cl", N_omega=33, order=6, method="plain")


def test_aggregates_select_rows_and_format_as_the_table(tables):
    rows, columns = tables["roms"]
    col = {c.key: c for c in columns}["frf_max_err_Cl"]
    picked = [r["frf_max_err_Cl"] for r in rows if r["order"] >= 6]
    assert _value(fill("{{max:*/*/>=6/*/frf_max_err_Cl}}", tables)) == cell_text(max(picked), col)
    assert _value(fill("{{range:synth/33/2,6/plain/frf_max_err_Cl}}", tables)) == " - ".join(
        cell_text(v, col) for v in sorted(r["frf_max_err_Cl"] for r in rows if r["N_omega"] == 33
                                          and r["method"] == "plain"))
    assert _value(fill("{{synth@11.14/33/6/plain/order}}", tables)) == "6"   # T as the tables print it
    assert _value(fill("{{synth@2,11.14/33/6/plain/order}}", tables)) == "6"
    assert "no result" in fill("{{synth@2/33/6/plain/order}}", tables)
    both = [r["frf_max_err_Cl"] for r in rows if r["N_omega"] == 33 and r["method"] == "plain"]
    assert _value(fill("{{mean:synth/33/*/plain/frf_max_err_Cl}}", tables)) == cell_text(sum(both) / 2, col)


def test_cost_templates_name_a_case_and_a_column(tables):
    """CASE/COLUMN: a cell of the cost table (one row per case: the timings stored with the pieces)."""
    rows, columns = tables["cost"]
    col = {c.key: c for c in columns}
    assert _value(fill("{{synth/frf_seconds}}", tables)) == _cell(tables, "cost", "frf_seconds", case="synth")
    assert _value(fill("{{range:*/identify_seconds}}", tables)) == cell_text(rows[0]["identify_seconds"],
                                                                             col["identify_seconds"])
    assert "no result" in fill("{{T9/ltd_seconds}}", tables)
    with pytest.raises(TemplateError, match="no column 'seconds' in the cost table"):
        fill("{{synth/seconds}}", tables)
    with pytest.raises(TemplateError, match="one row per case, not per T"):
        check_templates("{{synth@2/frf_seconds}}")


def test_the_page_keeps_the_template_and_refills_it(small, tmp_path):
    prose = {"frf": "Cm error {{synth/33/6/dc_stable/frf_max_err_Cm}} at N_r = 6."}
    page = make_report(small, tmp_path, prose=prose, figures=False)
    text = page.read_text()
    value = _cell(report_tables(small), "roms", "frf_max_err_Cm", N_omega=33, order=6, method="dc_stable")
    assert f"Cm error <!--{{{{synth/33/6/dc_stable/frf_max_err_Cm}}}}-->{value}<!--/--> at N_r = 6." in text
    # the page's slot, kept without a prose file, is filled again from the store, not copied with its number
    page.write_text(text.replace(f"-->{value}<!--/-->", "-->0.001%<!--/-->"))
    assert f"-->{value}<!--/-->" in make_report(small, tmp_path, figures=False).read_text()


@pytest.mark.parametrize("template, match", [
    ("{{synth/33/frf_max_err_Cm}}", "give CASE/N_OMEGA/N_R/METHOD/COLUMN"),
    ("{{average:synth/33/6/plain/frf_max_err_Cm}}", "'average' is not one of min, max, mean, median, range"),
    ("{{synth/33/six/plain/frf_max_err_Cm}}", "order 'six' is not a number"),
    ("{{synth@x/33/6/plain/frf_max_err_Cm}}", "T 'x' .* is not a number"),
])
def test_bad_templates_are_refused_before_computing(small, tmp_path, template, match):
    with pytest.raises(TemplateError, match=match):
        check_templates(template)
    with pytest.raises(ReportError, match=match):
        make_report(small, tmp_path, prose={"frf": template}, figures=False)
    assert not (tmp_path / "report.md").exists()


@pytest.mark.parametrize("template, match", [
    ("{{synth/33/*/plain/frf_max_err_Cm}}", "selects 2 rows; name one"),
    ("{{synth/33/6/plain/frf_max_error_Cm}}", "no column 'frf_max_error_Cm'"),
])
def test_templates_that_name_no_cell_are_refused(tables, template, match):
    with pytest.raises(TemplateError, match=match):
        fill(template, tables)


def test_a_result_not_in_the_store_is_shown_as_missing(tables):
    missing = "**(no result: T9/257/25/plain/frf_max_err_Cm)**"
    assert _value(fill("{{T9/257/25/plain/frf_max_err_Cm}}", tables)) == missing
    assert unfill(fill("a {{T9/257/25/plain/order}} b", tables)) == "a {{T9/257/25/plain/order}} b"


@pytest.mark.parametrize("name", ["paper-prose.toml", "sweep-T-prose.toml", "linearity-prose.toml",
                                  "linearity-paper-grid-prose.toml"])
def test_the_shipped_prose_names_existing_columns(name):
    """Every template of the shipped prose parses and names a column of its table (against no results: each
    is then 'no result'; the pages are filled from the study's store by `lfdrom report`)."""
    for slot, body in tomllib.loads((STUDIES / name).read_text()).items():
        filled = fill(body, {}, slot)
        assert "{{" not in filled.replace("<!--{{", "")


def test_linearity_templates_select_case_gust_and_angle():
    """CASE/GUST/ANGLE/COLUMN: a cell of the linearity table (a [nonlinear] study); the gusts of one shape share a
    march, named "G2/G3" in the table, which G2 or G3 selects."""
    from studies.sections.nonlinear.report import LINEARITY_COLUMNS

    rows = [dict(case="T3", gust="G2/G3", amplitude_deg=5.0, ltd_error_Cl=0.0054, n_factorisations=1),
            dict(case="T3", gust="G4", amplitude_deg=0.5, ltd_error_Cl=0.0129, n_factorisations=24),
            dict(case="T3", gust="G4", amplitude_deg=5.0, ltd_error_Cl=0.0485, n_factorisations=130)]
    tables = {"linearity": (rows, list(LINEARITY_COLUMNS))}
    assert _value(fill("{{T3/G3/5/ltd_error_Cl}}", tables)) == "0.54%"   # the table's ".2%"
    assert _value(fill("{{range:T3/G4/*/ltd_error_Cl}}", tables)) == "1.29% - 4.85%"
    assert _value(fill("{{max:*/*/>=1/n_factorisations}}", tables)) == "130"
    assert _value(fill("{{median:T3/*/*/n_factorisations}}", tables)) == "24"
    with pytest.raises(TemplateError, match="selects 2 rows; name one \\(case, gust, angle\\)"):
        fill("{{T3/G4/*/ltd_error_Cl}}", tables)
    with pytest.raises(TemplateError, match="angle 'five' is not a number"):
        check_templates("{{T3/G4/five/ltd_error_Cl}}")
