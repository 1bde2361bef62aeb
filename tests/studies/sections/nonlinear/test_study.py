"""The [nonlinear] section of a study: parsing and its errors, the march end times, the nonlinear pieces computed,
cached and compared with the study's LTD and ROMs (on the tiny study's store), and the report's section."""

import math
from dataclasses import replace

import numpy as np
import pytest
from tinystudy import STUDY, copy_study

from studies.config.cases import GUST_CASES
from studies.config import StudyConfigError, loads_study
from studies.sections.nonlinear.schema import describe, march_amplitudes, march_end, nonlinear_piece
from studies.sections.nonlinear.study import compare_histories, load_linearity, nonlinear_plan
from studies.sections.gust_rom.pieces import open_store
from studies.report import write_report
from studies.run.runner import run_study

PAPER_GUSTS = """
name = "nl"
cases = ["T2", "T3"]
gusts = ["G1", "G3", "G4", "G6"]
[sweep]
orders = [4]
T = ["70/(2*pi)"]
M_base = 8
[simulation]
dt = 0.02
t_end = 40.0
x0 = -2.0
"""


def study(tmp_path, section, base=PAPER_GUSTS):
    return loads_study(base + section, source="nl.toml", base_dir=tmp_path)


# ---------------------------------------------------------------------------------------------
# Parsing
# ---------------------------------------------------------------------------------------------

def test_defaults_take_every_case_and_gust_at_its_own_angle_below_max_angle(tmp_path):
    cfg = study(tmp_path, "[nonlinear]\n")
    nl = cfg.nonlinear
    # G6's 45 deg is the indicial normalisation, above max_angle: left out when gusts are not named
    assert nl.cases == ("T2", "T3") and nl.gusts == ("G1", "G3", "G4")
    assert nl.amplitudes == () and nl.gust_angle and nl.max_angle == 15.0 and nl.tail == 8.0
    assert march_amplitudes(nl, GUST_CASES["G6"]) == ()
    assert march_amplitudes(nl, GUST_CASES["G3"]) == (5.0,)
    assert "nonlinear" in cfg.canonical() and "nonlinear" not in study(tmp_path, "").canonical()


def test_amplitudes_and_the_gusts_own_angle_are_merged(tmp_path):
    cfg = study(tmp_path, '[nonlinear]\ncases = ["t3"]\ngusts = ["G3", "G6"]\namplitudes = [0.5, 1, 2]\n')
    nl = cfg.nonlinear
    assert nl.cases == ("T3",) and nl.gusts == ("G3", "G6")
    assert march_amplitudes(nl, GUST_CASES["G3"]) == (0.5, 1.0, 2.0, 5.0)
    assert march_amplitudes(nl, GUST_CASES["G6"]) == (0.5, 1.0, 2.0)
    assert "amplitudes 0.5, 1, 2 deg" in describe(nl)


def test_gusts_of_one_shape_share_their_marches(tmp_path):
    from studies.sections.nonlinear.schema import gust_shapes
    from studies.sections.nonlinear.study import _marches

    text = PAPER_GUSTS.replace('gusts = ["G1", "G3", "G4", "G6"]', 'gusts = ["G2", "G3"]')
    cfg = study(tmp_path, '[nonlinear]\ncases = ["T2"]\namplitudes = [1, 2]\n', text)
    ((label, gust, angles),) = gust_shapes(cfg.nonlinear, cfg.gusts)
    assert (label, gust.name, angles) == ("G2/G3", "G2", (1.0, 2.0, 5.0))  # G2's 2 deg once, G3's 5 deg
    assert [(m[1].name, m[2], m[3]) for m in _marches(cfg)] == [("G2", 1.0, "G2/G3"), ("G2", 2.0, "G2/G3"),
                                                               ("G2", 5.0, "G2/G3")]


def test_a_negative_gust_is_marched_with_its_sign(tmp_path):
    text = PAPER_GUSTS.replace('gusts = ["G1", "G3", "G4", "G6"]',
                               'gusts = [{ name = "down", kind = "one_minus_cosine", length = 2.0, angle_deg = -3.0 }]')
    cfg = study(tmp_path, "[nonlinear]\namplitudes = [1]\n", text)
    assert march_amplitudes(cfg.nonlinear, cfg.gusts[0]) == (-1.0, -3.0)


def test_a_gust_still_on_the_aerofoil_at_t_end_is_refused(tmp_path):
    text = PAPER_GUSTS.replace("t_end = 40.0", "t_end = 10.0")
    with pytest.raises(StudyConfigError, match="G4 has not left the trailing edge at .* t_end = 10") as info:
        study(tmp_path, '[nonlinear]\ngusts = ["G1", "G4"]\n', text)
    assert info.value.key == "nonlinear.gusts[1]"


@pytest.mark.parametrize("gust, end", [("G1", 2 + 0.5 + 1 + 8), ("G3", 2 + 1 + 1 + 8), ("G4", 2 + 10 + 1 + 8),
                                       ("G6", 2 + 1 + 16)])
def test_march_ends_after_the_gust_has_left_the_trailing_edge(tmp_path, gust, end):
    cfg = study(tmp_path, "[nonlinear]\n")
    assert march_end(cfg.nonlinear, GUST_CASES[gust], cfg.simulation) == pytest.approx(end, abs=1e-12)


def test_march_end_is_capped_by_the_study_t_end(tmp_path):
    cfg = study(tmp_path, "[nonlinear]\n", PAPER_GUSTS.replace("t_end = 40.0", "t_end = 15.0"))
    assert march_end(cfg.nonlinear, GUST_CASES["G4"], cfg.simulation) == 15.0


@pytest.mark.parametrize("section, key, match", [
    ("[nonlinear]\namplitude = [1]\n", "nonlinear.amplitude", "did you mean 'amplitudes'"),
    ('[nonlinear]\ncases = ["T7"]\n', "nonlinear.cases[0]", "'T7' is not a case of this study"),
    ('[nonlinear]\ngusts = ["G2"]\n', "nonlinear.gusts[0]", "'G2' is not a gust of this study"),
    ('[nonlinear]\ngusts = ["G1", "g1"]\n', "nonlinear.gusts[1]", "appears twice"),
    ("[nonlinear]\namplitudes = [2, 1]\n", "nonlinear.amplitudes", "strictly increasing"),
    ("[nonlinear]\namplitudes = [20]\n", "nonlinear.amplitudes[0]", r"must be in \(0, 15\]"),
    ("[nonlinear]\namplitudes = [0]\n", "nonlinear.amplitudes[0]", "must be in"),
    ("[nonlinear]\nmax_angle = 60\n", "nonlinear.max_angle", "must be in"),
    ("[nonlinear]\ngust_angle = false\n", "nonlinear.amplitudes", "nothing to march"),
    ('[nonlinear]\ngusts = ["G6"]\n', "nonlinear.max_angle", "no amplitude of gust"),
    ("[nonlinear]\ngust_angle = 1\n", "nonlinear.gust_angle", "true or false"),
    ("[nonlinear]\ntail = -1\n", "nonlinear.tail", "must be in"),
    ("nonlinear = 3\n", "nonlinear", "must be a table"),
])
def test_bad_sections_name_the_key(tmp_path, section, key, match):
    text = PAPER_GUSTS.replace('name = "nl"\n', 'name = "nl"\n' + section) if section.startswith("nonlinear =") \
        else PAPER_GUSTS + section
    with pytest.raises(StudyConfigError, match=match) as info:
        loads_study(text, source="nl.toml", base_dir=tmp_path)
    assert info.value.key == key


def test_compare_histories_scales_the_linear_model_and_measures_peak_and_error():
    t = np.linspace(0.0, 1.0, 11)
    lin = {"Cl": np.sin(np.pi * t), "Cm": -0.1 * np.sin(np.pi * t)}
    scale = 3.0
    nl = {"Cl": scale * lin["Cl"] * 1.02, "Cm": scale * lin["Cm"][:11]}
    m = compare_histories(nl, lin, scale)
    assert m["ratio_Cl"] == pytest.approx(1.02) and m["error_Cl"] == pytest.approx(0.02)
    assert m["ratio_Cm"] == pytest.approx(1.0) and m["error_Cm"] == pytest.approx(0.0, abs=1e-15)
    assert math.isnan(compare_histories(nl, {"Cl": 0 * t, "Cm": lin["Cm"]}, 1.0)["error_Cl"])


# ---------------------------------------------------------------------------------------------
# Computed on the tiny study's store (T2 on a 61 x 16 grid, G4, dt = 0.1)
# ---------------------------------------------------------------------------------------------

NONLINEAR = """
[nonlinear]
amplitudes = [0.01, 3]
gust_angle = false
tail = 2
"""


@pytest.fixture(scope="module")
def marched(computed, tmp_path_factory):
    config, _, _ = computed
    tmp = tmp_path_factory.mktemp("nl")
    base = copy_study(config, tmp)
    cfg = loads_study(STUDY + NONLINEAR, source="tiny.toml", base_dir=tmp)
    cfg = replace(cfg, store_dir=base.store_dir, output_dir=base.output_dir)
    assert nonlinear_plan(cfg, open_store(cfg), False) == {"T2": [("G4", 0.01), ("G4", 3.0)]}
    res = run_study(cfg, progress=False)
    return cfg, res


def test_marches_are_stored_and_a_second_run_computes_nothing(marched):
    cfg, res = marched
    assert res.complete and res.failed == []
    assert nonlinear_plan(cfg, open_store(cfg), False) == {}
    assert run_study(cfg, progress=False).run.computed == 0


def test_a_tiny_gust_follows_the_ltd_and_a_large_one_departs_from_it(marched):
    cfg, res = marched
    small, large = load_linearity(res)
    assert (small.amplitude_deg, large.amplitude_deg) == (0.01, 3.0) and small.ok and large.ok
    # G4 from x0 = -2 with tail 2: 2 + 10 + 1 + 2 = 15 chords, 150 steps of the LTD's dt
    assert small.t.size == 151 and small.t[-1] == pytest.approx(15.0)
    # the same time grid and gust input as the LTD's (scaled to the angle): x0, dt and the gust agree
    ltd = res.ltd[("T2", "G4")]
    e = open_store(cfg).get("nonlinear", nonlinear_piece(cfg, cfg.cases[0].case, cfg.gusts[0], 0.01))
    scale = math.tan(math.radians(0.01)) / math.tan(math.radians(cfg.gusts[0].angle_deg))
    assert np.array_equal(small.t, ltd.t[:151]) and np.allclose(e["u"], scale * ltd.u[:151], rtol=1e-12, atol=0)
    # the LTD is the nonlinear scheme's derivative: at 0.01 deg (1.7e-4 rad) the difference is the second-order
    # term, ~1e-5 of the peak on subsonic cases (docs/nonlinear.md: 5e-6 on S1, 2e-6 on S0; 3e-5 on S0 before
    # the far field's switch became a blend); 1e-3 leaves a decade and a half
    assert small.ltd["error_Cl"] < 1e-3 and abs(small.ltd["ratio_Cl"] - 1.0) < 1e-3
    assert small.ltd["error_Cm"] < 1e-2
    # at 3 deg the difference is 300x the 0.01-deg one at least to first order in the amplitude: it must grow
    assert large.ltd["error_Cl"] > 10 * small.ltd["error_Cl"]
    # against the ROMs: the ROM's own error (a few % at order 4) dominates at 0.01 deg
    assert set(small.roms) and all(np.isfinite(m["error_Cl"]) for m in small.roms.values())
    rom = small.rom()
    assert abs(rom["error_Cl"] - np.max(np.abs(small.cl - small.rom_cl)) / np.max(np.abs(small.rom_cl))) < 1e-12
    assert small.metadata["n_factorisations"] >= 1 and small.metadata["iterations_per_step"] >= 1


def test_report_section_has_the_table_and_the_figures(marched, tmp_path):
    cfg, res = marched
    page = write_report(res, tmp_path / "rep", page=tmp_path / "rep" / "page.md")
    text = page.read_text()
    assert "## Where the linear models hold" in text
    assert "(case, gust) pairs stay within 1 % / 5 % / 10 %" in text
    assert (tmp_path / "rep" / "tables" / "linearity.csv").exists()
    for name in ("linearity-map-ltd.png", "linearity-map-rom.png", "linearity-case-T2.png"):
        assert (tmp_path / "rep" / "figures" / name).stat().st_size > 1000
    csv = (tmp_path / "rep" / "tables" / "linearity.csv").read_text().splitlines()
    assert len(csv) == 3 and csv[1].startswith("T2,G4,0.01")


def test_limits_are_the_largest_angle_within_each_level_and_the_slope_is_the_error_order():
    from studies.sections.nonlinear.report import linearity_limits
    from studies.sections.nonlinear.study import LinearityRecord

    amps = [0.5, 1.0, 2.0, 5.0]
    # LTD error 0.0039 a^2 (third-order term: slope 2): 0.1 %, 0.39 %, 1.6 %, 9.75 %
    recs = [LinearityRecord(case="T1", gust="G1", amplitude_deg=a, gust_angle_deg=2.0, status="ok",
                            ltd={"error_Cl": 0.0039 * a ** 2}, roms={"r": {"error_Cl": 0.02 + 0.001 * a}})
            for a in amps]
    # a failed march ends the run of angles
    recs += [LinearityRecord(case="T1", gust="G6", amplitude_deg=a, gust_angle_deg=45.0, status="ok" if a < 2 else
                             "stopped", ltd={"error_Cl": 1e-3} if a < 2 else {}) for a in amps]
    # no linear model stored: NaN, not 0
    recs += [LinearityRecord(case="T2", gust="G1", amplitude_deg=a, gust_angle_deg=2.0, status="ok") for a in amps]
    (g1, g6, none) = linearity_limits(recs, "ltd", "Cl")
    assert (g1["within_1"], g1["within_5"], g1["within_10"]) == (1.0, 2.0, 5.0)
    assert g1["slope"] == pytest.approx(2.0, abs=1e-12)
    assert (g6["within_1"], g6["within_10"]) == (1.0, 1.0) and g6["slope"] == pytest.approx(0.0, abs=1e-12)
    assert math.isnan(none["within_1"]) and math.isnan(none["slope"])
    # every march stopped: 0 (not even the smallest angle), not "no model"
    stopped = [LinearityRecord(case="T3", gust="G1", amplitude_deg=a, gust_angle_deg=2.0, status="stopped")
               for a in amps]
    assert linearity_limits(stopped, "ltd", "Cl")[0]["within_10"] == 0.0
    (rom, _, _) = linearity_limits(recs, "rom", "Cl")
    assert (rom["within_1"], rom["within_5"]) == (0.0, 5.0)


def test_a_march_the_solver_stops_is_kept_and_the_larger_angles_are_skipped(marched, tmp_path, monkeypatch):
    """A march stopped by the solver (here: a LocalMachError injected at 3 deg) is a result: stored with its
    history so far, the larger angles of the gust skipped, not in ``results.failed``, not marched again."""
    import cfd
    from cfd.errors import LocalMachError

    cfg, _ = marched
    from tinystudy import copy_study

    cfg2 = copy_study(cfg, tmp_path)
    cfg2 = cfg2.with_section("nonlinear", replace(cfg2.nonlinear, amplitudes=(0.01, 2.0, 4.0)))
    real = cfd.unsteady_response
    calls = []

    def stop_at_two(sol, gust, dt, t_end, **kw):
        calls.append(gust.angle_deg)
        if gust.angle_deg < 1.0:
            return real(sol, gust, dt, t_end, **kw)
        partial = real(sol, gust, dt, 2.0, **kw)
        raise LocalMachError(f"local Mach number above the limit at step 20 (gust {gust.angle_deg} deg)",
                             partial=partial, step=20, time=2.0, amplitude_deg=gust.angle_deg)

    monkeypatch.setattr(cfd, "unsteady_response", stop_at_two)
    res = run_study(cfg2, progress="lines")
    assert calls == [2.0]  # 0.01 deg is stored; 4 deg is skipped after 2 deg stopped
    assert res.failed == [] and res.complete
    recs = {r.amplitude_deg: r for r in load_linearity(res)}
    assert recs[0.01].ok and recs[2.0].status == recs[4.0].status == "stopped"
    assert recs[2.0].t.size == 21 and "local Mach number" in recs[2.0].error  # s = 0 .. 2 at dt = 0.1
    assert recs[4.0].t.size == 0 and "not marched: the 2 deg march of the same gust stopped" in recs[4.0].error
    assert nonlinear_plan(cfg2, open_store(cfg2), False) == {}
    assert run_study(cfg2, progress=False).run.computed == 0
    page = write_report(res, tmp_path / "rep", page=tmp_path / "rep" / "page.md").read_text()
    assert "2 march(es) stopped or failed" in page and "(2 stopped or failed)" not in page
    assert "2 deg: " in page and "(1 stopped or failed)" in page
