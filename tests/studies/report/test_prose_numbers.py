"""A percentage in a report's prose is a template filled from the store, or a listed external measurement.

The prose files (``studies/*-prose.toml``) are the source of the committed pages' prose slots. An error quoted by
hand from a table goes stale when the results move (issue 34: the paper page quoted numbers its regenerated
tables no longer held); a template (``{{...}}``, :mod:`studies.report.numbers`) cannot. This test finds every
number with a per-cent sign outside a template and fails unless the phrase around it is listed in
:data:`EXTERNAL`, the numbers that are not table cells (older runs' numbers, measurements on the histories or
the LFD data), each of which says in the prose where it comes from. Numbers without a per-cent sign (k values,
grid sizes, timings of other runs) are not checked: too many of them are not results to tell them apart.
"""

import re
import tomllib
from pathlib import Path

import pytest

from studies.report.numbers import TEMPLATE_RE

STUDIES = Path(__file__).resolve().parents[3] / "studies"

PERCENT_RE = re.compile(r"(?<![\w.])\d+(?:\.\d+)?(?:e[+-]?\d+)?(?:\s*-\s*\d+(?:\.\d+)?)?\s*%")
"""A number (or a range ``a - b``) with a per-cent sign."""

EXTERNAL = {
    "paper-prose.toml": [
        # the LTD of the study against finer marches (2026-12-02) and the store's ROM peaks (2026-12-04)
        "overshoots it by 25 - 28 %", "fall 12 - 19 % short", "20 - 22 % off this LTD", "also 12 - 19 %",
        # the older stable subspace fits (the page of 2026-12-02, git 3490e00)
        "T4 26 % then", "under G1 15 % then", "0.05 -\n0.13 % then", "0.04 - 0.06 % then", "(0.45 % then",
        "T4 Cl 2.9 %, Cm 12.8 %", "T5 Cl 2.7 %, Cm 9.9 %", "33 frequencies 1.4 % against",
        # the signed-extreme peak error of an earlier page
        "reported 189 - 198 %",
        # ratios of table cells (dc against paper rows); a threshold on the histories' error
        "at most 2.2 % of",
        "above 1 % of the LTD peak",
        # the LTD histories' decay (a measurement on the histories, not a table cell)
        "within 5 % of the peak", "within 5 % after",
    ],
    "sweep-T-prose.toml": [
        # the LTD of the study against finer marches (2026-12-02)
        "20 - 22 % off it", "20 - 22 % off the LTD",
        # the Radau step's estimated growth-rate error (cfd.ltd.phase_error_estimate)
        "0.02:\n0.5 %), 1.6 % at k = 10 and over 100 % at k = 15",
        # measurements on the histories
        "above 1 % of the LTD peak", "within 5 % of it",
    ],
    "linearity-paper-grid-prose.toml": [
        # the 97 x 25 column: docs/linearity.md, another study's page (update them when it changes)
        "0.18 / 0.62 %", "0.18 / 11.0 %", "3.7 / 206 %", "0.54 / 2.8 %", "1.9 / 4.2 %", "7.5 / 15 %",
        "0.35 / 4.7 %", "0.35 / 37 %", "2.7 / 160 %",
    ],
}


def _prose(name):
    return tomllib.loads((STUDIES / name).read_text(encoding="utf-8"))


@pytest.mark.parametrize("name", sorted(p.name for p in STUDIES.glob("*-prose.toml")))
def test_every_percentage_in_the_prose_is_a_template_or_external(name):
    allowed = EXTERNAL.get(name, [])
    unused = set(allowed)
    for slot, body in _prose(name).items():
        text = TEMPLATE_RE.sub("{{}}", body)
        for phrase in allowed:
            if phrase in text:
                unused.discard(phrase)
                text = text.replace(phrase, "")
        bare = [m.group(0) for m in PERCENT_RE.finditer(text)]
        assert not bare, (f"{name}, slot {slot!r}: {bare} are per-cent numbers written by hand; template them "
                          "({{CASE/N_OMEGA/N_R/METHOD/COLUMN}}, studies/report/numbers.py) or, if they are not table "
                          f"cells, say in the prose where they come from and list the phrase in EXTERNAL")
    assert not unused, f"{name}: EXTERNAL lists phrases no longer in the prose: {sorted(unused)}; remove them"


@pytest.mark.parametrize("text, found", [
    ("within 1.6 % in Cl", ["1.6 %"]),
    ("0.04 - 0.06 % then", ["0.04 - 0.06 %"]),
    ("errors 12%, 7.3e-2% and 100 %", ["12%", "7.3e-2%", "100 %"]),
    ("k = 0.03 up, 1e-14, T5 N_r = 55", []),
])
def test_the_percentages_found(text, found):
    assert [m.group(0) for m in PERCENT_RE.finditer(text)] == found


def test_the_coarse_grid_column_of_the_paper_grid_page_is_that_of_the_linearity_page():
    # docs/linearity-paper-grid.md's prose copies the 97 x 25 LTD errors from docs/linearity.md's table (another
    # study's store, which a template cannot read): each copied "Cl / Cm %" must be that table's cell rounded as
    # written (the number of significant digits given), so that a regenerated linearity page makes this fail
    import csv

    table = STUDIES.parent / "docs" / "linearity" / "tables" / "linearity.csv"
    rows = list(csv.DictReader(table.open(encoding="utf-8")))
    body = _prose("linearity-paper-grid-prose.toml")["summary"]
    lines = re.findall(r"^\| (T\d) (G\d) (\d+) deg \| [^|]+\| ([\d.]+) / ([\d.]+) % \|$", body, re.M)
    assert len(lines) == 9
    for case, gust, angle, cl, cm in lines:
        row = next(r for r in rows if r["case"] == case and gust in r["gust"].split("/")
                   and float(r["amplitude_deg"]) == float(angle))
        for written, column in ((cl, "ltd_error_Cl"), (cm, "ltd_error_Cm")):
            digits = len(written.replace(".", "").lstrip("0"))
            value = 100 * float(row[column])
            assert float(f"{value:.{digits}g}") == float(written), (case, gust, angle, column, value, written)
