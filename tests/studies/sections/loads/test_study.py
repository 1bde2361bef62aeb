"""The [loads] section of a study: parsing and its errors, the loads pieces computed from the tiny study's stored
ROMs and cached, a failed point stored and retried, and the report's "Gust loads" part."""

import math

import numpy as np
import pytest
from tinystudy import STUDY, copy_study

import loads
from studies.config import StudyConfigError, loads_study
from studies.run.runner import run_study
from studies.sections.gust_rom.pieces import PIECES, open_store, rom_piece
from studies.sections.loads.schema import describe, loads_piece, rom_point
from studies.sections.loads.study import load_loads, loads_plan, loads_task, rom_model
from studies.store.results import load_results

POINTS = """
[[loads.points]]
case = "T2"
altitude_m = [0, 6000]
chord_m = 2.0
"""

LOADS = "\n[loads]\nmoment_axes = [0.4]\n" + POINTS


def study(extra):
    return loads_study(STUDY + extra, source="tiny.toml")


# ---------------------------------------------------------------------------------------------
# Parsing
# ---------------------------------------------------------------------------------------------

def test_parse_defaults():
    opts = study(LOADS).loads
    # the ROM: the case's highest order, the first method with the exact DC gain and stability, M_base, its T
    assert opts.rom_of("T2") == (pytest.approx(70 / (2 * math.pi)), 16, 4, "dc_stable")
    assert opts.outputs == ("Cl", "Cm", "Cm@0.400") and opts.H_range_m is None and opts.n_grid == 24
    assert [p.name for p in opts.points] == ["T2@0m", "T2@6000m"]
    assert [p.mach for p in opts.points] == [0.735, 0.735] and opts.points[1].F_g == 1.0
    assert "2 flight point(s) (T2@0m, T2@6000m)" in describe(opts)
    # the study hash sees the section; a study without it keeps its hash
    assert study(LOADS).hash() != loads_study(STUDY).hash() and "loads" not in loads_study(STUDY).canonical()


def test_parse_rom_and_alleviation():
    opts = study('\n[loads]\norder = 2\nmethod = "plain"\nM = 8\noutputs = ["Cl"]\n[[loads.points]]\ncase = "t2"\n'
                 'altitude_m = 3000\nchord_m = 2.5\nz_mo_m = 12000\nmlw_mtow = 0.8\nmzfw_mtow = 0.75\n'
                 'design_speed = "VD"\nname = "dive"\n').loads
    assert opts.rom_of("T2")[1:] == (8, 2, "plain") and opts.outputs == ("Cl",)
    (p,) = opts.points
    assert p.name == "dive" and p.case == "T2" and p.design_speed == "VD"
    # CS-25.341(a)(6) by hand: F_gz = 1 - Z_mo / 250 000 ft, F_gm = sqrt(R2 tan(pi R1 / 4)), linear to 1 at Z_mo
    f0 = 0.5 * ((1 - 12000 / (250000 * 0.3048)) + math.sqrt(0.75 * math.tan(math.pi * 0.8 / 4)))
    assert p.F_g == pytest.approx(f0 + (1 - f0) * 3000 / 12000, rel=1e-10)


@pytest.mark.parametrize("extra, key, match", [
    ("\n[loads]\norders = 4\n" + POINTS, "loads.orders", "did you mean 'order'"),
    ("\n[loads]\n", "loads.points", "missing: give at least one"),
    ("\n[loads]\n" + POINTS.replace('"T2"', '"T3"'), "loads.points[0].case", "'T3' is not a case of this study"),
    ("\n[loads]\n" + POINTS.replace("chord_m", "chord"), "loads.points[0].chord", "did you mean 'chord_m'"),
    ("\n[loads]\n" + POINTS.replace("chord_m = 2.0", "chord_m = -1"), "loads.points[0].chord_m", "must be > 0"),
    ("\n[loads]\n" + POINTS.replace("chord_m = 2.0", 'chord_m = "two"'), "loads.points[0].chord_m", "two"),
    ("\n[loads]\n" + POINTS.replace("[0, 6000]", "[0, 90000]"), "loads.points[0].altitude_m[1]", "60 000 ft"),
    ("\n[loads]\n" + POINTS.replace("[0, 6000]", "-6000"), "loads.points[0].altitude_m",
     "outside the ICAO standard atmosphere"),
    ("\n[loads]\n" + POINTS + "F_g = 1.2\n", "loads.points[0].F_g", r"must lie in \(0, 1\]"),
    ("\n[loads]\n" + POINTS + "z_mo_m = 12000\n", "loads.points[0].mlw_mtow", "missing: F_g from the rule"),
    ("\n[loads]\n" + POINTS + "F_g = 0.9\nz_mo_m = 1\nmlw_mtow = 1\nmzfw_mtow = 1\n", "loads.points[0].F_g",
     "not both"),
    ("\n[loads]\n" + POINTS + "z_mo_m = 12000\nmlw_mtow = 1.5\nmzfw_mtow = 0.7\n", "loads.points[0].mlw_mtow",
     r"must lie in \(0, 1\]"),
    ("\n[loads]\n" + POINTS + 'design_speed = "vd"\n', "loads.points[0].design_speed", "did you mean 'VD'"),
    ("\n[loads]\n" + POINTS + 'name = "x"\n', "loads.points[0].name", "one flight point"),
    ("\n[loads]\n" + POINTS + POINTS, "loads.points", "appears twice"),
    ("\n[loads]\norder = 3\n" + POINTS, "loads.order", "not an order of case T2's sweep; the sweep has 2, 4"),
    ('\n[loads]\nmethod = "dc-stable"\n' + POINTS, "loads.method", "did you mean 'dc_stable'"),
    ("\n[loads]\nM = 32\n" + POINTS, "loads.M", "the sweep has 8, 16"),
    ('\n[loads]\noutputs = ["CL"]\n' + POINTS, "loads.outputs[0]", "did you mean 'Cl'"),
    ("\n[loads]\nH_range_m = [5, 100]\n" + POINTS, "loads.H_range_m", "outside the rule's 30 - 350 ft"),
    ("\n[loads]\nH_range_m = [50, 20]\n" + POINTS, "loads.H_range_m", "must not be below"),
    ("\n[loads]\nn_grid = 2\n" + POINTS, "loads.n_grid", "between 3 and"),
    ("\n[loads]\nh_rtol = 0\n" + POINTS, "loads.h_rtol", "positive"),
    # a single table where [[loads.points]] is expected
    ("\n[loads]\n" + POINTS.replace("[[loads.points]]", "[loads.points]"), "loads.points",
     r"must be an array of tables, got a single table .*its own \[\[loads.points\]\] line"),
    ('\n[loads]\npoints = { case = "T2" }\n', "loads.points", r"got a single table \{'case': 'T2'\}"),
    ("\n[loads]\npoints = []\n", "loads.points", r"is empty: give at least one \[\[loads.points\]\]"),
    ('\n[loads]\npoints = ["T2"]\n', "loads.points[0]", "must be a table, got str 'T2'"),
])
def test_parse_errors(extra, key, match):
    with pytest.raises(StudyConfigError, match=match) as info:
        study(extra)
    assert info.value.key == key
    assert "tiny.toml" in str(info.value)


def test_default_method_needs_a_stable_dc_exact_variant():
    text = STUDY.replace('[methods.dc_stable]\ndc_gain = "match"\nstable = true\nmargin = 1e-3\n', "")
    with pytest.raises(StudyConfigError, match="only method 'plain' does not impose the DC gain") as info:
        loads_study(text + "\n[loads]\n" + POINTS, source="tiny.toml")
    assert info.value.key == "loads.method"
    assert loads_study(text + '\n[loads]\nmethod = "plain"\n' + POINTS).loads.rom_of("T2")[3] == "plain"


# ---------------------------------------------------------------------------------------------
# The run: the tiny study's stored ROMs, two flight points
# ---------------------------------------------------------------------------------------------

def with_loads(computed, tmp_path, extra=LOADS):
    config, _, _ = computed
    return copy_study(config, tmp_path).with_section("loads", study(extra).loads)


def test_loads_are_computed_cached_and_reported(computed, tmp_path):
    from studies.report import make_report

    config = with_loads(computed, tmp_path)
    assert load_results(config).missing == ["loads T2 T2@0m", "loads T2 T2@6000m"]
    first = run_study(config, progress=False)
    assert first.run.computed == 2 and first.run.failed_pieces == 0   # the two points, nothing of the tiny study
    assert first.complete and len(first.sections["loads"]) == 2
    again = run_study(config, progress=False)
    assert again.run.computed == 0                                      # cached
    assert loads_plan(config, open_store(config), False) == {"T2": 0}

    sea, high = load_loads(config, open_store(config))
    for r in (sea, high):
        # SI beside the coefficients: q c Cl and q c^2 Cm, q = gamma p M^2 / 2 of the ISO 2533 troposphere by its
        # formulas (T = T0 - L h, p = p0 (T / T0)^(g0 / (R L)) at geopotential h); ambiance's tables agree to 1e-6
        T = 288.15 - 0.0065 * r.spec.altitude_m
        p = 101325.0 * (T / 288.15) ** (9.80665 / (287.05287 * 0.0065))
        q = 0.5 * 1.4 * p * 0.735 ** 2
        assert r.dimensional["Cl"] == pytest.approx(q * 2.0 * r.peak["Cl"], rel=1e-6)
        assert r.dimensional["Cm@0.400"] == pytest.approx(q * 4.0 * r.peak["Cm@0.400"], rel=1e-6)
        assert r.design_dimensional["Cl"] == pytest.approx(q * 2.0 * r.a_bar["Cl"] * r.u_sigma, rel=1e-6)
        # the moment about 0.4 c is the quarter-chord moment moved by 0.15 c of lift, at every peak
        c = r.correlated["Cl"]
        assert c["Cm@0.400"] == pytest.approx(c["Cm"] + 0.15 * c["Cl"], rel=1e-9, abs=1e-12)
        assert all(9.144 - 1e-9 <= h <= 106.68 + 1e-9 for h in r.critical_H.values())
        assert all(v > 0 and math.isfinite(v) for v in list(r.a_bar.values()) + list(r.n0.values()))
    # U_sigma of the rule: 90 ft/s TAS at sea level, linearly to 79 ft/s at 24 000 ft (6000 m = 19 685 ft)
    assert sea.u_sigma == pytest.approx(90 * 0.3048, rel=1e-12)
    assert high.u_sigma == pytest.approx((90 - 11 * (6000 / 0.3048) / 24000) * 0.3048, rel=1e-9)

    # the stored piece is what loads computes from the stored ROM
    store = open_store(config)
    T = config.loads.rom_of("T2")[0]
    rom = store.get("rom", rom_piece(rom_point(config, "T2"), config.M_base, config.cfd))
    assert rom is not None and loads_piece(config, sea.spec)["rom"] == rom_piece(rom_point(config, "T2"),
                                                                                  config.M_base, config.cfd)
    direct = loads.tuned_gust(rom_model(rom, T), sea.spec.flight_point(), moment_axes=[0.4])
    assert direct.peak["Cl"] == pytest.approx(sea.peak["Cl"], rel=1e-12)
    assert direct.critical_H["Cm"] == pytest.approx(sea.critical_H["Cm"], rel=1e-12)

    page = make_report(config, tmp_path / "report", figures=True, dpi=40)
    text = page.read_text()
    assert "## Gust loads (CS-25.341)" in text and "### T2@6000m" in text and "**Envelope**" in text
    assert f"| Cl | rigid | {sea.critical_H['Cl']:.4g} |" in text
    for name in ("loads-points.csv", "loads-envelope.csv", "loads-T2_0m.csv"):
        assert (tmp_path / "report" / "tables" / name).is_file()
    for name in ("loads-envelope.png", "loads-T2_0m.png", "loads-T2_6000m.png"):
        assert (tmp_path / "report" / "figures" / name).is_file()
        assert f"figures/{name}" in text


def test_a_failed_point_is_stored_listed_and_retried(computed, tmp_path, monkeypatch):
    config = with_loads(computed, tmp_path)
    store = open_store(config)
    codes = {p: store.code_version(p) for p in PIECES + ("loads",)}

    def refuse(*args, **kwargs):
        raise loads.GustError("the search refused (test)")

    monkeypatch.setattr(loads, "tuned_gust", refuse)
    reports = loads_task(config, "T2", str(config.store_dir), codes, False)
    assert [r["status"] for r in reports] == ["failed", "failed"] and "the search refused" in reports[0]["error"]
    assert any("loads of T2@0m failed: GustError: the search refused" in f for f in load_results(config).failed)
    assert loads_plan(config, store, False) == {"T2": 2}                # computed again by the next run
    monkeypatch.undo()
    assert [r["status"] for r in loads_task(config, "T2", str(config.store_dir), codes, False)] == ["ok", "ok"]
    assert load_results(config).failed == [] and np.isfinite(load_loads(config, store)[0].peak["Cl"])
