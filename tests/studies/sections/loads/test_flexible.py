"""The [loads] section's flexible sections: parsing and its errors, the plan (a flexible task waits for the case's
motion FRF and ROMs), pieces computed from the tiny study's stored ROM and an injected motion FRF (Theodorsen's
flat plate, as the [aeroelastic] tests), cached, a point above flutter refused and stored as such, the same peaks
as the loads API called directly, and the report's rigid and flexible rows."""

import dataclasses
import math

import numpy as np
import pytest
from tinystudy import STUDY, copy_study

import aeroelastic as ae
import loads
from aeroelastic import theodorsen as th
from studies.config import StudyConfigError, loads_study
from studies.run.runner import run_study
from studies.sections.aeroelastic.schema import PIVOT, motion_frf_piece
from studies.sections.gust_rom.pieces import open_store
from studies.sections.loads.schema import describe, flexible_piece, loads_piece, motion_key
from studies.sections.loads.section import SECTION
from studies.sections.loads.study import flexible_plan, flexible_task, load_loads, loads_plan, rom_model
from studies.sections.protocol import step_id
from studies.store.results import load_results

AERO = """
[aeroelastic]
cases = ["T2"]
omega = { min = 0.02, max = 2.0, n = 16 }
lags = 2
speeds = { min = 0.05, max = 3.0, n = 40 }
[[aeroelastic.sections]]
name = "HP"
mu = 20
a = -0.2
x_alpha = 0.1
r_alpha2 = 0.24
omega_ratio = 0.4
"""

# 2 m chord at Mach 0.735: TAS 250 m/s at sea level, 235 m/s at 6000 m. "stiff" (8 / 24 Hz) is below its flutter
# speed at both altitudes; "soft" (2 / 8 Hz, speed index 5.0 at sea level) flutters below the flight speed.
SECTIONS = """
[[loads.sections]]
name = "stiff"
mass_kg_m = 150.0
a = -0.2
x_alpha = 0.1
r_alpha2 = 0.24
f_h_hz = 8.0
f_alpha_hz = 24.0
"""

SOFT = """
[[loads.sections]]
name = "soft"
mass_kg_m = 150.0
a = -0.2
x_alpha = 0.1
r_alpha2 = 0.24
f_h_hz = 2.0
f_alpha_hz = 8.0
damping = [0.01, 0.03]
"""

POINTS = """
[[loads.points]]
case = "T2"
altitude_m = [0, 6000]
chord_m = 2.0
"""

LOADS = "\n[loads]\nmoment_axes = [0.4]\n" + SECTIONS + POINTS
# the run's outputs: four (each output's H search costs; the parse tests check the default list)
RUN = '\n[loads]\nmoment_axes = [0.4]\nflexible_outputs = ["Cl", "load_factor", "plunge_spring", "pitch_spring"]\n'



def study(extra, aero=AERO):
    return loads_study(STUDY + aero + extra, source="tiny.toml")


# ---------------------------------------------------------------------------------------------
# Parsing
# ---------------------------------------------------------------------------------------------

def test_parse_flexible_sections():
    config = study(LOADS)
    opts = config.loads
    (s,) = opts.sections
    assert (s.name, s.mass_kg_m, s.f_h_hz, s.f_alpha_hz, s.damping) == ("stiff", 150.0, 8.0, 24.0, (0.02, 0.02))
    assert s.elastic_axis == pytest.approx(0.4)
    assert opts.rigid and [p.sections for p in opts.points] == [("stiff",), ("stiff",)]
    assert opts.flexible_outputs == ("Cl", "Cm", "load_factor", "plunge", "pitch", "pitch_acc", "plunge_spring",
                                     "pitch_spring")
    # the motion data are the [aeroelastic] section's: its frequencies (0 added) and lag count
    assert opts.motion_omega == config.aeroelastic.omega and len(opts.motion_omega) == 17 and opts.lags == 2
    assert motion_key(config, "T2") == motion_frf_piece(config.case("T2").case, config.aeroelastic.omega, config.cfd)
    fs = s.flexible_section(ae.fit_motion(ae.to_elastic_axis(th.theodorsen_frf(np.asarray(opts.motion_omega), -0.5,
                                                                               gust=True), s.typical_section()), 2))
    assert fs.omega_alpha == pytest.approx(2 * math.pi * 24.0) and fs.mass == 150.0
    assert "flexible sections: stiff (150 kg/m" in describe(opts)
    # the key holds the motion piece's key and the section, not its name; the study hash sees the sections
    key = flexible_piece(config, opts.points[0], s)
    assert key["motion"] == motion_key(config, "T2") and key["section"]["f_alpha_hz"] == 24.0 and "name" not in key["section"]
    assert key["rom"] == loads_piece(config, opts.points[0])["rom"]
    assert study(LOADS).hash() != study("\n[loads]\nmoment_axes = [0.4]\n" + POINTS).hash()
    # a rigid-only [loads] keeps its canonical form (no flexible keys)
    assert set(study("\n[loads]\n" + POINTS).loads.canonical()) == {"rom", "outputs", "moment_axes", "H_range_m",
                                                                     "outside_rule", "n_grid", "h_rtol", "f_max_hz",
                                                                     "points"}


def test_parse_point_sections_and_rigid_off():
    opts = study("\n[loads]\nrigid = false\nflexible_outputs = [\"load_factor\"]\n" + SECTIONS + SOFT + POINTS
                 + 'sections = ["soft"]\n' + POINTS.replace("[0, 6000]", "3000")).loads
    assert not opts.rigid and [p.sections for p in opts.points] == [("soft",), ("soft",), ("stiff", "soft")]
    assert opts.flexible_outputs == ("load_factor",) and opts.section("soft").damping == (0.01, 0.03)
    # a moment about another axis is searched when listed
    assert study('\n[loads]\nmoment_axes = [0.25]\nflexible_outputs = ["Cm@0.250", "pitch"]\n' + SECTIONS
                 + POINTS).loads.flexible_outputs == ("Cm@0.250", "pitch")
    # a rigid-only point of a case without motion data is fine
    assert study("\n[loads]\n" + SECTIONS + POINTS + "sections = []\n", aero="").loads.flexible_cases == ()


def bad(key, value):
    return SECTIONS.replace(f"{key} = " + SECTIONS.split(f"{key} = ")[1].split("\n")[0], f"{key} = {value}")


@pytest.mark.parametrize("extra, aero, key, match", [
    ("\n[loads]\n" + SECTIONS.replace("mass_kg_m", "mass") + POINTS, AERO, "loads.sections[0].mass",
     "did you mean 'mass_kg_m'"),
    ("\n[loads]\n" + SECTIONS.replace("f_alpha_hz = 24.0\n", "") + POINTS, AERO, "loads.sections[0].f_alpha_hz",
     "missing: a flexible section needs"),
    ("\n[loads]\n" + bad("mass_kg_m", "-150") + POINTS, AERO, "loads.sections[0].mass_kg_m", "must be positive"),
    ("\n[loads]\n" + bad("f_h_hz", "0") + POINTS, AERO, "loads.sections[0].f_h_hz", "must be positive"),
    ("\n[loads]\n" + bad("r_alpha2", "-0.2") + POINTS, AERO, "loads.sections[0].r_alpha2", "r_alpha2"),
    ("\n[loads]\n" + SECTIONS + "damping = 1.5\n" + POINTS, AERO, "loads.sections[0].damping", r"\[0, 1\)"),
    ("\n[loads]\n" + SECTIONS + SECTIONS + POINTS, AERO, "loads.sections[1].name", "is taken"),
    ("\n[loads]\n" + SECTIONS.replace('"stiff"', '"rigid"') + POINTS, AERO, "loads.sections[0].name", "not 'rigid'"),
    ("\n[loads]\n" + SECTIONS + POINTS + 'sections = ["stif"]\n', AERO, "loads.points[0].sections[0]",
     "did you mean 'stiff'"),
    ("\n[loads]\n" + POINTS + 'sections = ["stiff"]\n', AERO, "loads.points[0].sections[0]",
     "the study has no"),
    ("\n[loads]\nrigid = false\n" + SECTIONS + POINTS + "sections = []\n", AERO, "loads.points[0].sections",
     "would have no loads"),
    ("\n[loads]\nrigid = 1\n" + SECTIONS + POINTS, AERO, "loads.rigid", "true or false"),
    ('\n[loads]\nflexible_outputs = ["load_factr"]\n' + SECTIONS + POINTS, AERO, "loads.flexible_outputs[0]",
     "did you mean 'load_factor'"),
    ('\n[loads]\nflexible_outputs = ["Cl"]\n' + POINTS, AERO, "loads.flexible_outputs", "no flexible section"),
    # flexible loads need the [aeroelastic] section's motion FRF of the point's case
    ("\n[loads]\n" + SECTIONS + POINTS, "", "loads.sections", "which the \\[aeroelastic\\] section computes"),
    ("\n[loads]\n" + SECTIONS + POINTS, AERO.replace('cases = ["T2"]\n', 'cases = []\n'), "aeroelastic.cases",
     "non-empty"),
    # a single table where [[loads.sections]] is expected: once a "missing" at loads.sections[0].mass_kg_m
    ('\n[loads]\nsections = { name = "stiff" }\n' + POINTS, AERO, "loads.sections",
     r"must be an array of tables, got a single table .*its own \[\[loads.sections\]\] line"),
    ("\n[loads]\n" + POINTS + SECTIONS.replace("[[loads.sections]]", "[loads.sections]"), AERO, "loads.sections",
     r"\[loads.sections\] in single brackets"),
    ("\n[loads]\nsections = [" + ", ".join(['{ name = "s" }'] * 21) + "]\n" + POINTS, AERO, "loads.sections",
     r"has 21 tables, at most 20 are allowed"),
])
def test_parse_errors(extra, aero, key, match):
    with pytest.raises(StudyConfigError, match=match) as info:
        study(extra, aero)
    assert info.value.key == key
    assert "tiny.toml" in str(info.value)


def test_a_case_without_motion_data_is_refused():
    text = STUDY.replace('cases = ["T2"]', 'cases = ["T2", "T4"]').replace("[sweep]", "[sweep]\n")
    with pytest.raises(StudyConfigError, match="case 'T4' has no motion data for the flexible sections") as info:
        loads_study(text + AERO + "\n[loads]\n" + SECTIONS + POINTS + POINTS.replace('"T2"', '"T4"'),
                    source="tiny.toml")
    assert info.value.key == "loads.points[1].case"


# ---------------------------------------------------------------------------------------------
# The plan and the pieces: the tiny study's stored ROM, Theodorsen's flat plate as the motion FRF
# ---------------------------------------------------------------------------------------------

def inject_theodorsen(config):
    """Store Theodorsen's loads (pitch and Cm about the quarter chord) as the case's motion FRF."""
    store = open_store(config)
    omega = np.asarray(config.aeroelastic.omega)
    frf = th.theodorsen_frf(omega, -0.5, gust=True)
    store.put("motion_frf", motion_frf_piece(config.case("T2").case, omega, config.cfd), {"H": frf.H, "omega": omega},
              dict(status="ok", inputs=list(frf.inputs), outputs=list(frf.outputs), pivot=PIVOT, method="theodorsen",
                   seconds=0.0))
    return store


def with_flexible(computed, tmp_path, extra=LOADS):
    config, _, _ = computed
    parsed = study(extra)
    config = copy_study(config, tmp_path).with_section("aeroelastic", parsed.aeroelastic)
    return config.with_section("loads", parsed.loads)


def pinned(config):
    """The store as the runner opens it (the code versions of every piece kind pinned)."""
    from studies.run.compute import pinned_store
    from studies.sections.protocol import piece_kinds

    base = open_store(config)
    return pinned_store(str(config.store_dir), {p: base.code_version(p) for p in piece_kinds()})


def test_the_flexible_task_waits_for_the_motion_frf(computed, tmp_path):
    config = with_flexible(computed, tmp_path)
    store = pinned(config)
    tasks = {t.kind: t for t in SECTION.plan(config, store, False).tasks}
    flex = tasks["flexible loads"]
    assert flex.fn is flexible_task and flex.case == "T2"
    assert step_id("motion", "T2") in flex.needs_ok and step_id("roms", "T2") in flex.after
    assert step_id("motion", "T2") not in tasks["loads"].needs_ok + tasks["loads"].after   # rigid loads do not wait
    assert flexible_plan(config, store, False) == {"T2": 2} and loads_plan(config, store, False) == {"T2": 2}
    # the motion FRF is the [aeroelastic] section's piece: that section plans it, with the id the loads task waits on
    from studies.sections.protocol import section

    motion = [t for t in section("aeroelastic").plan(config, store, False).tasks if t.kind == "motion"]
    assert [t.ids for t in motion] == [(step_id("motion", "T2"),)]
    assert "loads T2 T2@0m stiff" in load_results(config).missing


def test_flexible_loads_computed_cached_and_as_the_api(computed, tmp_path):
    config = with_flexible(computed, tmp_path, RUN + SECTIONS + SOFT + POINTS)
    inject_theodorsen(config)
    first = run_study(config, progress=False)
    # 2 rigid + 4 flexible loads pieces and the [aeroelastic] section's flutter piece (its motion FRF is stored)
    assert first.run.computed == 7 and first.run.failed_pieces == 2
    # "soft" is above its flutter speed at both altitudes: stored as failures that say so, and (as every failed
    # piece) retried by the next run, which computes nothing else
    again = run_study(config, progress=False)
    assert again.run.computed == 2 and again.run.failed_pieces == 2
    store = open_store(config)
    assert flexible_plan(config, store, False) == {"T2": 2} and loads_plan(config, store, False) == {"T2": 0}
    # without "soft" the study is complete and a run computes nothing (a piece's key holds its own section only)
    stiff_only = config.with_section("loads", study(RUN + SECTIONS + POINTS).loads)
    assert run_study(stiff_only, progress=False).run.computed == 0 and load_results(stiff_only).failed == []
    failed = load_results(config).failed
    assert len(failed) == 2 and all("flexible section soft, failed: LoadsModelError: flexible section soft reaches "
                                    "flutter at" in f and "at or below the flight point's" in f for f in failed)
    records = load_loads(config, store)
    assert [(r.spec.name, r.model) for r in records] == [("T2@0m", "rigid"), ("T2@0m", "stiff"),
                                                        ("T2@6000m", "rigid"), ("T2@6000m", "stiff")]
    rigid, stiff = records[0], records[1]
    fl = stiff.flexible["flutter"]
    assert fl["found"] and fl["tas"] > rigid.atmosphere["tas"]
    # the flutter TAS is the speed index times b omega_alpha; mu = m / (pi rho b^2)
    assert fl["tas"] == pytest.approx(fl["speed_index"] * 1.0 * 2 * math.pi * 24.0, rel=1e-12)
    assert stiff.flexible["mu"] == pytest.approx(150.0 / (math.pi * rigid.atmosphere["rho"]), rel=1e-12)
    assert set(stiff.outputs) == set(config.loads.flexible_outputs)
    # SI factors of loads.flexible: q c Cl, k_h h = m omega_h^2 c (h / c)
    q = rigid.atmosphere["q"]
    assert stiff.dimensional["Cl"] == pytest.approx(q * 2.0 * stiff.peak["Cl"], rel=1e-12)
    assert stiff.dimensional["plunge_spring"] == pytest.approx(150.0 * (2 * math.pi * 8.0) ** 2 * 2.0
                                                               * stiff.peak["plunge_spring"], rel=1e-12)

    # the same peaks as the loads API called directly with the same ROM and motion data (an independent build of
    # the aerodynamic model: Roger's fit of the data about the elastic axis, the ROM's gust response moved there)
    e = store.get("motion_frf", motion_key(config, "T2"))
    sec = config.loads.section("stiff")
    motion = th.theodorsen_frf(np.asarray(e["omega"]), -0.5, gust=False)     # plunge and pitch only
    model = ae.fit_motion(ae.to_elastic_axis(motion, sec.typical_section()), 2)
    rom = store.get("rom", loads_piece(config, rigid.spec)["rom"])
    T = config.loads.rom_of("T2")[0]
    import control
    import sysid

    g = sysid.d2c_bilinear(rom_model(rom, T))
    shift = np.array([[1.0, 0.0], [0.4 - 0.25, 1.0]])   # [Cl, Cm_e] = T_out [Cl, Cm_1/4] (aeroelastic.axes)
    gust = control.ss(g.A, g.B, shift @ np.asarray(g.C)[:2], shift @ np.asarray(g.D)[:2], inputs=["gust"],
                      outputs=["Cl", "Cm"])
    fs = loads.FlexibleSection(dataclasses.replace(model, gust=gust), mass=150.0, a=-0.2, x_alpha=0.1, r_alpha2=0.24,
                               omega_h=2 * math.pi * 8.0, omega_alpha=2 * math.pi * 24.0, damping=0.02)
    for r in (records[1], records[3]):
        point = r.spec.flight_point()
        tg = loads.tuned_gust(fs, point, outputs=list(r.outputs), moment_axes=[0.4])
        ct = loads.continuous_turbulence(loads.gust_system(fs, point, moment_axes=[0.4]), point,
                                         outputs=list(r.outputs))
        for o in r.outputs:
            # same model to round-off (the fit is deterministic; the search's steps are the same)
            assert r.peak[o] == pytest.approx(tg.peak[o], rel=1e-9), o
            assert r.critical_H[o] == pytest.approx(tg.critical_H[o], rel=1e-9), o
            assert r.a_bar[o] == pytest.approx(ct.a_bar[o], rel=1e-9), o
    # the flexible section's Cm about 0.4 c (its elastic axis) is its Cm, at every peak
    c = stiff.correlated["load_factor"]
    assert c["Cm@0.400"] == pytest.approx(c["Cm"], rel=1e-9, abs=1e-12)

    # the report's loads part: the rigid and flexible rows of an output together, the flexible table, the
    # refusals, the figures (the section's part alone: the other sections' figures are not this test's)
    from studies.sections.protocol import ReportContext

    out = tmp_path / "report"
    text = SECTION.report(ReportContext(results=load_results(config), out_dir=out, page_dir=out,
                                        page_path=out / "report.md", dpi=40, say=lambda m: None))
    assert "**Flexible sections**" in text and "**Flexible sections at the flight points**" in text
    assert f"| Cl | rigid | {rigid.critical_H['Cl']:.4g} |" in text
    assert f"| Cl | stiff | {stiff.critical_H['Cl']:.4g} |" in text
    assert text.index("| Cl | rigid |") < text.index("| Cl | stiff |") < text.index("| Cm | rigid |")
    assert text.index("| Cm@0.400 | rigid |") < text.index("| load_factor | stiff |")
    assert f"| T2@0m | stiff | {stiff.flexible['mu']:.4g} |" in text
    assert "Flexible section soft: refused at this point: LoadsModelError: flexible section soft reaches" in text
    for name in ("loads-points.csv", "loads-flexible.csv", "loads-envelope.csv", "loads-T2_0m.csv"):
        assert (tmp_path / "report" / "tables" / name).is_file()
    for name in ("loads-envelope.png", "loads-envelope-stiff.png", "loads-T2_0m.png", "loads-T2_0m-stiff.png",
                 "loads-T2_6000m-stiff.png"):
        assert (tmp_path / "report" / "figures" / name).is_file()
        assert f"figures/{name}" in text
    assert "| stiff | plunge_spring | N/m |" in text                 # the envelope, per model


def test_a_failed_fit_or_motion_frf_is_stored_listed_and_retried(computed, tmp_path, monkeypatch):
    from studies.store.entries import failure_payload

    config = with_flexible(computed, tmp_path, RUN + SECTIONS + POINTS)
    store = open_store(config)
    codes = {p: store.code_version(p) for p in ("steady", "frf", "rom", "motion_frf", "flutter", "loads")}
    # a failed motion FRF: the flexible task stores nothing, the reader says why
    store.put("motion_frf", motion_key(config, "T2"), *failure_payload("CFDError: the sweep diverged (test)"))
    assert flexible_task(config, "T2", str(config.store_dir), codes, False) == []
    failed = load_results(config).failed
    assert any("loads of T2@6000m, flexible section stiff, its motion FRF (T2) failed: CFDError" in f
               for f in failed), failed

    # a fit that fails: each piece stored as a failure with its error, computed again by the next run
    inject_theodorsen(config)

    def refuse(*args, **kwargs):
        raise ae.FitError("the fit refused these data (test)")

    monkeypatch.setattr(ae, "fit_motion", refuse)
    reports = flexible_task(config, "T2", str(config.store_dir), codes, False)
    assert [r["status"] for r in reports] == ["failed", "failed"] and "the fit refused" in reports[0]["error"]
    assert any("loads of T2@0m, flexible section stiff, failed: FitError: the fit refused" in f
               for f in load_results(config).failed)
    assert flexible_plan(config, store, False) == {"T2": 2}
    monkeypatch.undo()
    assert [r["status"] for r in flexible_task(config, "T2", str(config.store_dir), codes, False)] == ["ok", "ok"]
    assert flexible_plan(config, store, False) == {"T2": 0}
