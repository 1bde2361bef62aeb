"""studies.report: tables, figures and the Markdown page from a synthetic StudyResults (no runner, no CFD)."""

import json
import re
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402

from studies import report  # noqa: E402
from studies.config import StudyConfigError, loads_study  # noqa: E402
from studies.report import ReportError, make_report  # noqa: E402
from studies.cli.synthetic import synthetic_results  # noqa: E402
from smallstudy import small_results, small_study_text  # noqa: E402

GUSTS = ("G3", "G6", "G4")


def study_text(out):
    return small_study_text(out, GUSTS, "two methods, two grids, two gusts")



PAPER_LIKE = """
name = "paperlike"
output = "{out}"
cases = [{{name = "T2", orders = [9], M = [32]}}, {{name = "T5", orders = [25]}}]
gusts = ["G3"]
[sweep]
T = ["70/(2*pi)"]
M_base = 64
M = [64]
[simulation]
dt = 0.1
t_end = 12.0
"""


@pytest.fixture(scope="module")
def small(tmp_path_factory):
    out = tmp_path_factory.mktemp("small")
    # one failed identification, one LTD reference missing (with its ROM histories)
    return small_results(out, GUSTS, fail=[("synth", 16, 6, "plain")], drop=[("synth", "G4")])


@pytest.fixture(scope="module")
def written(small, tmp_path_factory):
    out = tmp_path_factory.mktemp("report")
    return make_report(small, out, dpi=60), out


def page_links(page):
    return re.findall(r"\]\(([^)]+)\)", page.read_text())


def test_report_writes_page_tables_and_figures(written):
    page, out = written
    assert page == out / "report.md"
    names = {p.name for p in (out / "figures").iterdir() if p.suffix == ".png"}  # and manifest.json
    assert {"frf-synth-N33-r2.png", "frf-synth-N17-r6.png", "hankel-synth.png", "errors-synth.png",
            "history-synth-G3.png", "history-synth-G6.png", "heatmap-peak-Cl.png", "heatmap-peak-Cm.png"} <= names
    assert "history-synth-G4.png" not in names  # no LTD reference for G4
    assert len([n for n in names if n.startswith("frf-")]) == 4  # (M, order) pairs; methods share a figure
    for kind in ("roms", "sims", "summary", "methods", "cost"):
        for suffix in (".csv", ".md", ".tex"):
            assert (out / "tables" / f"{kind}{suffix}").is_file()
    links = page_links(page)
    assert len(links) >= len(names) + 15  # every figure and table is linked
    for link in links:
        assert (page.parent / link).is_file(), link


def test_page_lists_failed_and_missing_pieces(written):
    text = written[0].read_text()
    assert "7 of 8 identifications done, 1 failed" in text
    assert "synth T=11.14 N_omega=17 N_r=6 plain: SolverError: synthetic failure" in text
    assert "- ltd synth G4" in text
    assert text.count("<!-- prose:") == text.count("<!-- /prose:") >= 8
    assert "The paper:" not in text and "Analogue of the paper" not in text  # not a paper case


def test_rows_and_summary_agree_with_the_records(small):
    sims = report.sim_rows(small)
    assert len(sims) == 7 * 2  # 7 ROMs x gusts G3, G6
    assert all(s["speedup"] == pytest.approx(s["seconds_ltd"] / s["seconds_rom"]) for s in sims)
    summ = report.summary_rows(small)
    assert len(summ) == 7
    for row in summ:
        mine = [s for s in sims if (s["M"], s["order"], s["method"]) == (row["N_omega"] - 1, row["order"], row["method"])]
        worst = max(mine, key=lambda s: s["peak_err_Cl"])
        assert row["worst_peak_err_Cl"] == worst["peak_err_Cl"] and row["worst_gust_Cl"] == worst["gust"]
        assert row["aerofoil"] == "NACA0012" and row["mach"] == 0.5
    meth = {r["method"]: r for r in report.method_rows(small)}
    assert (meth["plain"]["n_roms"], meth["plain"]["n_failed"], meth["dc_stable"]["n_roms"]) == (3, 1, 4)
    assert meth["dc_stable"]["max_dc_err_Cl"] < 1e-10 < meth["plain"]["max_dc_err_Cl"]  # DC matching is exact
    (cost,) = report.cost_rows(small)
    assert cost["n_gusts"] == 2 and cost["n_frequencies"] == 33


@pytest.mark.parametrize("kind, outputs, expected", [
    ("rom", ("Cl", "Cm"), ["frf_max_err_Cl", "frf_rms_err_Cm", "dc_err_Cm", "spectral_radius", "error"]),
    ("rom", ("Cl",), ["frf_max_err_Cl", "dc_err_Cl"]),
    ("sim", ("Cl", "Cm"), ["gust", "peak_err_Cm", "t_peak_err_Cl", "rms_err_Cl", "speedup"]),
    ("summary", ("Cl", "Cm"), ["aerofoil", "worst_peak_err_Cm", "worst_gust_Cl", "stable"]),
])
def test_columns_carry_units_and_outputs(kind, outputs, expected):
    cols = {"rom": report.rom_columns, "sim": report.sim_columns, "summary": report.summary_columns}[kind](outputs)
    keys = [c.key for c in cols]
    for k in expected:
        assert k in keys
    if outputs == ("Cl",):
        assert "frf_max_err_Cm" not in keys
    headers = {c.key: c.title for c in cols}
    assert headers["T"] == "T [c/U]" and headers["order"] == "N_r"
    if kind == "sim":
        assert headers["t_peak_err_Cl"].endswith("[c/U]") and headers["seconds_ltd"] == "LTD [s]"


def test_prose_survives_regeneration_and_can_be_given(small, tmp_path):
    page = make_report(small, tmp_path, figures=False)
    text = page.read_text().replace("<!-- prose:orders -->\n<!-- /prose:orders -->",
                                    "<!-- prose:orders -->\nErrors fall fast with N_r.\n<!-- /prose:orders -->")
    page.write_text(text)
    page = make_report(small, tmp_path, prose={"cost": "Cheap."}, figures=False)
    text = page.read_text()
    assert "<!-- prose:orders -->\nErrors fall fast with N_r.\n<!-- /prose:orders -->" in text
    assert "<!-- prose:cost -->\nCheap.\n<!-- /prose:cost -->" in text
    prose_file = tmp_path / "prose.toml"
    prose_file.write_text('summary = """All good."""\n')
    text = make_report(small, tmp_path, prose=prose_file, figures=False).read_text()
    assert "All good." in text and "Cheap." in text and "figures not drawn" in text
    assert not (tmp_path / "figures").exists()


@pytest.mark.parametrize("prose, match", [
    ({"nonsense": "x"}, "unknown prose slot 'nonsense'"),
    ({"cost": 3}, "prose slot 'cost' must be text"),
    ("no-such-file.toml", "no such prose file"),
    (42, "prose must be a mapping"),
])
def test_bad_prose(small, tmp_path, prose, match):
    with pytest.raises(ReportError, match=match):
        make_report(small, tmp_path, prose=prose)


@pytest.fixture(scope="module")
def paperlike(tmp_path_factory):
    out = tmp_path_factory.mktemp("paperlike")
    return synthetic_results(loads_study(PAPER_LIKE.format(out=out.as_posix()), base_dir=out))


def test_paper_mode_names_the_paper_figures_and_claims(paperlike, tmp_path):
    page = make_report(paperlike, page=tmp_path / "docs" / "paper-reproduction.md", dpi=60)
    assert page == tmp_path / "docs" / "paper-reproduction.md"
    assets = tmp_path / "docs" / "paper-reproduction"
    assert (assets / "figures" / "frf-T2-N33-r9.png").is_file() and (assets / "tables" / "summary.csv").is_file()
    text = page.read_text()
    assert text.startswith("<!-- generated by lfdrom report from ")
    assert text.splitlines()[1].startswith("# Reproduction of Bagheri, Jones & Gaitonde (2016)")
    assert "Analogue of the paper's Fig. 19." in text  # T2, N_r = 9, N_omega = 33
    assert "Fig. 15." not in text  # T5 with N_r = 25 but N_omega = 65: not the paper's setting (257)
    assert "Analogue of the paper's Figs. 21, 29." in text and "Analogue of the paper's Figs. 24, 25." in text
    assert "Analogue of the paper's Fig. 28." not in text  # needs T6 as well
    assert "> **The paper:** N_r = 25 gives ROMs" in text
    assert "(Figs. 9-10) in [gust_validation.md](../../" in text  # relative to the page, wherever it is
    for link in page_links(page):
        assert (page.parent / link).is_file(), link
    off = make_report(paperlike, tmp_path / "plain", paper=False, figures=False).read_text()
    assert "The paper:" not in off and off.splitlines()[1] == "# Study report: paperlike"


def test_make_report_from_a_study_file_with_an_empty_store(tmp_path):
    study = tmp_path / "s.toml"
    study.write_text(study_text(tmp_path / "out"))
    page = make_report(study)
    assert page == tmp_path / "out" / "report.md"
    text = page.read_text()
    assert "0 of 8 identifications done" in text and "- steady synth" in text and "- frf synth T=11.1408" in text
    assert "_(no ROM identified yet)_" in text


def test_an_empty_store_does_not_replace_an_existing_page(tmp_path):
    # make_report("studies/paper.toml") on a checkout without the paper's store used to turn the committed page
    # into "0 of 33 identifications done"
    study = tmp_path / "s.toml"
    study.write_text(study_text(tmp_path / "out"))
    page = make_report(study)                         # a first report of nothing: there was no page
    page.write_text(page.read_text() + "\nresults of an earlier run\n")
    with pytest.raises(ReportError, match=r"holds no result of this study .*lfdrom run STUDY.toml.*--force-page"):
        make_report(study)
    assert page.read_text().endswith("results of an earlier run\n")
    assert make_report(study, force_page=True) == page and "earlier run" not in page.read_text()


def test_paper_prose_fills_every_slot():
    from studies.config import load_study

    prose = load_study(Path(__file__).resolve().parents[3] / "studies" / "paper.toml").report.prose
    slots = report.read_prose(prose, Path("/nonexistent/page.md"))
    assert set(slots) == set(report.SLOTS) and all(len(text) > 200 for text in slots.values())


def test_make_report_writes_the_study_page(tmp_path):
    study = tmp_path / "s.toml"
    text = study_text(tmp_path / "out")
    study.write_text(text + '\n[report]\npage = "docs/s.md"\nfigures = false\ntitle = "My sweep"\npaper = false\n')
    page = make_report(study)
    assert page == (tmp_path / "docs" / "s.md").resolve() and page.is_file()
    assert page.read_text().splitlines()[1] == "# My sweep" and "The paper:" not in page.read_text()
    assert (tmp_path / "docs" / "s" / "tables").is_dir() and not (tmp_path / "out" / "report.md").exists()
    # an explicit output folder wins over the study's page
    assert make_report(study, output_dir=tmp_path / "elsewhere") == tmp_path / "elsewhere" / "report.md"


def test_make_report_loads_with_the_store_override(small, tmp_path, monkeypatch):
    seen = {}

    def fake_load(config):
        seen["store"] = config.store_dir
        return small

    monkeypatch.setattr("studies.store.results.load_results", fake_load)
    page = make_report(small.config, output_dir=tmp_path, store_dir=tmp_path / "elsewhere", progress=True,
                       figures=False)
    assert seen["store"] == tmp_path / "elsewhere" and page.is_file()


@pytest.mark.parametrize("call, error, match", [
    (lambda tmp: make_report(3.5), ReportError, "expected a StudyConfig, a study file or StudyResults"),
    (lambda tmp: make_report("missing.toml"), StudyConfigError, "no such study file"),
    (lambda tmp: make_report("x.toml", output_dir=tmp / "a", out_dir=tmp / "b"), ReportError, "disagree"),
    (lambda tmp: report.write_report(object(), tmp), ReportError, "must be a studies.store.results.StudyResults"),
])
def test_bad_arguments(tmp_path, call, error, match):
    with pytest.raises(error, match=match):
        call(tmp_path)


def test_command_line_report(tmp_path, capsys):
    from studies.cli import main

    study = tmp_path / "s.toml"
    study.write_text(study_text(tmp_path / "out"))
    # nothing computed yet: the page is written (it says what is missing) and the status is "incomplete"
    assert main(["report", str(study), "--out", str(tmp_path / "elsewhere")]) == 3
    assert (tmp_path / "elsewhere" / "report.md").is_file()
    err = capsys.readouterr().err
    assert "report.md" in err and "written from an incomplete store" in err.strip().splitlines()[-1]
    assert main(["report", str(tmp_path / "nope.toml")]) == 2


def test_synthetic_results_are_consistent(small):
    assert len(small.roms) == 8 and small.missing == ["ltd synth G4"]
    ok = [r for r in small.roms if r.ok]
    assert all(r.frf_rom.shape == (2, 1, 33) and r.metrics["stable"] for r in ok)
    fr = small.frf[("synth", small.config.cases[0].T[0])]
    r = small.rom("synth", fr.T, 32, 6, "dc_stable")
    assert r.metrics["dc_err_Cl"] < 1e-10
    assert r.metrics["frf_max_err_Cl"] == pytest.approx(
        np.abs(r.frf_rom[0] - fr.frf.H[0]).max() / np.abs(fr.frf.H[0]).max())
    assert sys.modules["studies.report"] is report


def test_figures_are_kept_when_nothing_changed(small, tmp_path, monkeypatch):
    page = make_report(small, tmp_path, dpi=40)
    manifest = tmp_path / "figures" / report.FIGURE_MANIFEST
    listed = json.loads(manifest.read_text())["figures"]
    assert listed and all((tmp_path / "figures" / f["file"]).is_file() for f in listed)
    first = page.read_text()
    drawn = []
    import matplotlib.pyplot as plt

    def fake_save(fig, path, **kw):
        plt.close(fig)
        drawn.append(path)
        return path

    monkeypatch.setattr(report.plots, "save_figure", fake_save)
    again = make_report(small, tmp_path, dpi=40).read_text()
    assert drawn == []  # same inputs: no figure drawn, the page lists the same figures
    assert _figure_lines(again) == _figure_lines(first)
    make_report(small, tmp_path, dpi=40, redraw=True)
    assert len(drawn) == len(listed)
    drawn.clear()
    make_report(small, tmp_path, dpi=41)  # another input (the resolution): drawn again
    assert len(drawn) == len(listed)
    drawn.clear()
    (tmp_path / "figures" / listed[0]["file"]).unlink()  # a figure file lost: drawn again
    make_report(small, tmp_path, dpi=41)
    assert len(drawn) == len(listed)


def _figure_lines(text):
    return [line for line in text.splitlines() if line.startswith("![")]
