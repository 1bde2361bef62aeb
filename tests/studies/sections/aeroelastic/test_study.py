"""The [aeroelastic] section of a study: parsing and its errors, the flutter piece computed and cached (on
Theodorsen's data injected as the motion FRF: no CFD), and the report's "Aeroelastic section"."""

import math

import numpy as np
import pytest

import aeroelastic as ae
from aeroelastic import theodorsen as th
from studies.sections.aeroelastic.schema import DEFAULT_OMEGA, PIVOT, describe, motion_frf_piece
from studies.sections.aeroelastic.study import aeroelastic_plan, flutter_task, load_flutter
from studies.config import StudyConfigError, loads_study
from studies.sections.gust_rom.pieces import PIECES, open_store
from studies.store.results import load_results

BASE = """
name = "aero"
output = "out"
cases = [{ name = "M02", naca = "0006", mach = 0.2 }]
gusts = [{ name = "g10", kind = "one_minus_cosine", length = 10.0, angle_deg = 1.0 }]
[grid]
ni = 61
nj = 16
n_surface = 40
farfield = 10.0
[sweep]
orders = [4]
T = ["70/(2*pi)"]
M_base = 8
[simulation]
dt = 0.1
t_end = 30.0
x0 = -2.0
"""

SECTION = """
[[aeroelastic.sections]]
name = "HP"
mu = 20
a = -0.2
x_alpha = 0.1
r_alpha2 = 0.24
omega_ratio = 0.4
"""

AERO = """
[aeroelastic]
omega = { min = 0.02, max = 2.0, n = 24 }
lags = 4
speeds = { min = 0.05, max = 3.0, n = 120 }
""" + SECTION + "gust_speed = 1.5\n"


def study(tmp_path, extra):
    return loads_study(BASE + extra, source="aero.toml", base_dir=tmp_path)


# ---------------------------------------------------------------------------------------------
# Parsing
# ---------------------------------------------------------------------------------------------

def test_parse_defaults_and_grids(tmp_path):
    cfg = study(tmp_path, "[aeroelastic]\n" + SECTION)
    a = cfg.aeroelastic
    assert a.cases == ("M02",) and a.lags == 4 and a.omega == DEFAULT_OMEGA and a.speeds is None
    assert a.sections[0].name == "HP" and a.sections[0].gust_speed is None
    assert a.sections[0].section().elastic_axis == pytest.approx(0.4)
    cfg = study(tmp_path, AERO)
    a = cfg.aeroelastic
    assert a.omega[0] == 0.0 and len(a.omega) == 25 and a.omega[-1] == pytest.approx(2.0)
    assert len(a.speeds) == 120 and a.sections[0].gust_speed == 1.5
    assert "25 motion frequencies" in describe(a) and "HP (mu 20, a -0.2" in describe(a)
    # a list gets omega = 0 in front (15 values and 0: enough for the default gust_order 8)
    listed = [round(0.1 * k, 1) for k in range(1, 16)]
    cfg = study(tmp_path, f'[aeroelastic]\ncases = ["m02"]\nomega = {listed}\nspeeds = [1, 2, 3]\n' + SECTION)
    assert cfg.aeroelastic.cases == ("M02",) and cfg.aeroelastic.omega == (0.0, *listed)
    # the study hash sees the section; a study without it keeps its hash
    assert study(tmp_path, AERO).hash() != loads_study(BASE, source="aero.toml", base_dir=tmp_path).hash()
    assert "aeroelastic" not in loads_study(BASE, source="aero.toml", base_dir=tmp_path).canonical()


@pytest.mark.parametrize("extra, key, match", [
    ("[aeroelastic]\nlag = 4\n" + SECTION, "aeroelastic.lag", "did you mean 'lags'"),
    ('[aeroelastic]\ncases = ["M03"]\n' + SECTION, "aeroelastic.cases[0]", "'M03' is not a case of this study.*M02"),
    ("[aeroelastic]\n", "aeroelastic.sections", "missing: give at least one"),
    ("[aeroelastic]\n" + SECTION.replace("mu = 20\n", ""), "aeroelastic.sections[0].mu", "missing"),
    ("[aeroelastic]\n" + SECTION.replace("mu = 20", "mu = -1"), "aeroelastic.sections[0].mu", "mu"),
    # r_alpha2 <= x_alpha^2: the message's " must" once made the key mu
    ("[aeroelastic]\n" + SECTION.replace("r_alpha2 = 0.24", "r_alpha2 = 0.001"), "aeroelastic.sections[0].r_alpha2",
     "r_alpha2 = 0.001 must exceed x_alpha\\^2"),
    ("[aeroelastic]\n" + SECTION.replace("a = -0.2", "a = 1.5"), "aeroelastic.sections[0].a", "behind the trailing"),
    ("[aeroelastic]\n" + SECTION.replace("x_alpha = 0.1", "x_alpha = 0.5"), "aeroelastic.sections[0].r_alpha2",
     "r_alpha2 = 0.24 must exceed x_alpha\\^2 = 0.25"),
    ("[aeroelastic]\n" + SECTION.replace("omega_ratio = 0.4", "omega_ratio = 0"), "aeroelastic.sections[0].omega_ratio",
     "omega_ratio must be > 0"),
    ("[aeroelastic]\n" + SECTION.replace("omega_ratio", "omega_ration"), "aeroelastic.sections[0].omega_ration",
     "did you mean 'omega_ratio'"),
    ("[aeroelastic]\n" + SECTION + SECTION, "aeroelastic.sections[1].name", "appears twice"),
    ("[aeroelastic]\nomega = [0.5, 0.1]\n" + SECTION, "aeroelastic.omega", "strictly increasing"),
    ("[aeroelastic]\nspeeds = { min = 0.1, max = 3.0 }\n" + SECTION, "aeroelastic.speeds.n", "missing"),
    ("[aeroelastic]\nspeeds = { min = 3.0, max = 1.0, n = 5 }\n" + SECTION, "aeroelastic.speeds", "above min"),
    ("[aeroelastic]\nlags = 40\n" + SECTION, "aeroelastic.lags", "between 0 and"),
    ("[aeroelastic]\nomega = [0.1, 0.5]\nlags = 12\n" + SECTION, "aeroelastic.lags",
     "12 lag roots need at least 8 frequencies; aeroelastic.omega has 3"),
    ("[aeroelastic]\nomega = { min = 0.05, max = 1.0, n = 10 }\ngust_order = 40\n" + SECTION,
     "aeroelastic.gust_order", "beyond what 11 frequencies support \\(at most 5"),
    ("[aeroelastic]\n" + SECTION + "gust_speed = 0\n", "aeroelastic.sections[0].gust_speed", "positive"),
    ("[aeroelastic]\nomega = 3\n" + SECTION, "aeroelastic.omega", "must be a table"),
    # a single table where [[aeroelastic.sections]] is expected: once a "missing" at sections[0].mu
    ('[aeroelastic]\nsections = { name = "HP" }\n', "aeroelastic.sections",
     r"must be an array of tables, got a single table \{'name': 'HP'\}.*its own \[\[aeroelastic.sections\]\] line"),
    ("[aeroelastic]\n" + SECTION.replace("[[aeroelastic.sections]]", "[aeroelastic.sections]"),
     "aeroelastic.sections", r"got a single table .*\[aeroelastic.sections\] in single brackets"),
    ('[aeroelastic]\nsections = "HP"\n', "aeroelastic.sections",
     r"must be an array of tables \(\[\[aeroelastic.sections\]\]\), got str 'HP'"),
    ("[aeroelastic]\nsections = []\n", "aeroelastic.sections", r"is empty: give at least one \[\[aeroelastic"),
    ('[aeroelastic]\nsections = ["HP"]\n', "aeroelastic.sections[0]", "must be a table, got str 'HP'"),
])
def test_parse_errors(tmp_path, extra, key, match):
    with pytest.raises(StudyConfigError, match=match) as info:
        study(tmp_path, extra)
    assert info.value.key == key
    assert "aero.toml" in str(info.value)


def test_gust_speed_needs_gusts(tmp_path):
    text = (BASE + "[aeroelastic]\n" + SECTION + "gust_speed = 1.5\n").replace(
        'gusts = [{ name = "g10", kind = "one_minus_cosine", length = 10.0, angle_deg = 1.0 }]\n', "")
    with pytest.raises(StudyConfigError, match="no gusts") as info:
        loads_study(text, source="aero.toml", base_dir=tmp_path)
    assert info.value.key == "aeroelastic.sections[0].gust_speed"


# ---------------------------------------------------------------------------------------------
# Pieces: Theodorsen's flat plate injected as the case's motion FRF (quarter-chord pivot and moment)
# ---------------------------------------------------------------------------------------------

def inject_theodorsen(config):
    """Store Theodorsen's loads (pitch and Cm about the quarter chord: a = -1/2) as the case's motion FRF."""
    store = open_store(config)
    case = config.case("M02").case
    omega = np.asarray(config.aeroelastic.omega)
    frf = th.theodorsen_frf(omega, -0.5, gust=True)
    assert list(frf.inputs) == ["gust", "plunge", "pitch"] and list(frf.outputs) == ["Cl", "Cm"]
    store.put("motion_frf", motion_frf_piece(case, omega, config.cfd), {"H": frf.H, "omega": omega},
              dict(status="ok", inputs=list(frf.inputs), outputs=list(frf.outputs), pivot=PIVOT, method="theodorsen",
                   seconds=0.0))
    return store


def codes_of(store):
    return {p: store.code_version(p) for p in PIECES + ("motion_frf", "flutter")}


def test_flutter_piece_computes_and_caches(tmp_path):
    config = study(tmp_path, AERO)
    store = inject_theodorsen(config)
    assert aeroelastic_plan(config, store, False) == {"M02": {"motion": False, "flutter": 1}}
    assert any(m.startswith("flutter M02 HP") for m in load_results(config).missing)

    reports = flutter_task(config, "M02", str(config.store_dir), codes_of(store), False)
    assert [(r["piece"], r["status"]) for r in reports] == [("flutter", "ok")]
    # a second run computes nothing
    assert aeroelastic_plan(config, store, False) == {"M02": {"motion": False, "flutter": 0}}
    assert flutter_task(config, "M02", str(config.store_dir), codes_of(store), False) == []
    assert not [m for m in load_results(config).missing if "flutter" in m or "motion" in m]

    (rec,) = load_flutter(config, store)
    spec = config.aeroelastic.sections[0]
    ref = th.flutter_determinant(spec.section())     # independent k-method solution, exact C(k)
    assert rec.result.kind == "flutter" and rec.result.found
    assert rec.theodorsen["speed_index"] == pytest.approx(ref.speed_index, rel=1e-12)
    assert rec.result.speed_index == pytest.approx(ref.speed_index, rel=2e-3)
    assert rec.result.frequency_ratio == pytest.approx(ref.frequency_ratio, rel=2e-3)
    assert rec.result.flutter_speed_index == pytest.approx(rec.result.speed_index / math.sqrt(spec.mu))
    assert rec.result.eigenvalues.shape == (120, rec.result.eigenvalues.shape[1])
    # the stored gust history is the coupled ROM's, at the section's gust speed
    g = rec.gusts["g10"]
    assert g.speed == 1.5 and g.t.shape == (301,) and np.all(np.isfinite(g.pitch))
    direct = ae.gust_response(ae.fit_motion(ae.to_elastic_axis(th.theodorsen_frf(np.asarray(config.aeroelastic.omega),
                                                                                  -0.5, gust=True),
                                                               spec.section()), 4),
                              spec.section(), 1.5, (g.t, g.u))
    assert np.max(np.abs(direct.Cl - g.Cl)) <= 1e-8 * np.max(np.abs(direct.Cl))


def test_failed_flutter_is_stored_and_retried(tmp_path, monkeypatch):
    import aeroelastic

    config = study(tmp_path, AERO)
    store = inject_theodorsen(config)

    def refuse(*args, **kwargs):
        raise aeroelastic.FitError("the fit refused these data (test)")

    monkeypatch.setattr(aeroelastic, "fit_motion", refuse)
    (report,) = flutter_task(config, "M02", str(config.store_dir), codes_of(store), False)
    assert report["status"] == "failed" and "the fit refused these data" in report["error"]
    assert any("flutter of M02 with section HP failed" in f for f in load_results(config).failed)
    assert aeroelastic_plan(config, store, False)["M02"]["flutter"] == 1   # computed again by the next run


def test_report_section(tmp_path):
    from studies.report import make_report

    config = study(tmp_path, AERO)
    store = inject_theodorsen(config)
    flutter_task(config, "M02", str(config.store_dir), codes_of(store), False)
    page = make_report(load_results(config), tmp_path / "rep", figures=True, dpi=50)
    text = page.read_text()
    assert "## Aeroelastic section" in text
    (rec,) = load_flutter(config, store)
    assert f"| M02 | HP | 20 | {rec.result.speed_index:.5f} | {rec.result.flutter_speed_index:.5f} |" in text
    assert (tmp_path / "rep" / "tables" / "flutter.csv").is_file()
    assert (tmp_path / "rep" / "figures" / "aeroelastic-flutter-M02-HP.png").is_file()
    assert (tmp_path / "rep" / "figures" / "aeroelastic-gust-M02-HP-g10.png").is_file()
    assert "figures/aeroelastic-gust-M02-HP-g10.png" in text


# ---------------------------------------------------------------------------------------------
# The runner with the CFD (61 x 16 grid, 10 motion frequencies, no gusts: 30-70 s on the shared two-core machine,
# so marked slow; run it with -m slow)
# ---------------------------------------------------------------------------------------------

RUNNER = BASE.replace('gusts = [{ name = "g10", kind = "one_minus_cosine", length = 10.0, angle_deg = 1.0 }]\n',
                      "") + """
[aeroelastic]
omega = { min = 0.05, max = 2.0, n = 9 }
lags = 2
gust_order = 4
speeds = { min = 0.05, max = 3.0, n = 60 }
""" + SECTION


@pytest.mark.slow
def test_runner_computes_and_caches_the_aeroelastic_pieces(tmp_path):
    from studies.run.runner import run_study

    config = loads_study(RUNNER, source="aero.toml", base_dir=tmp_path)
    res = run_study(config, progress=False)
    assert res.complete and not res.failed
    assert res.run.computed == 5          # steady, frf, motion_frf, rom, flutter
    (rec,) = load_flutter(config, open_store(config))
    assert rec.result.kind == "flutter"
    # against Theodorsen's flat plate: the compressible, thick, coarse-grid section flutters within a few per cent
    assert abs(rec.result.speed_index / rec.theodorsen["speed_index"] - 1.0) < 0.05
    store = open_store(config)
    e = store.get("motion_frf", motion_frf_piece(config.case("M02").case, config.aeroelastic.omega, config.cfd))
    assert e["H"].shape == (2, 3, 10) and e.metadata["inputs"] == ["gust", "plunge", "pitch"]
    again = run_study(config, progress=False)
    assert again.run.computed == 0
