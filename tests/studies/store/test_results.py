"""studies.store.results: records read back from a synthetic store (no CFD), metrics, tables."""

import types

import control
import numpy as np
import pytest

import sysid
from studies.config import loads_study
from studies.sections.gust_rom.pieces import (
    failure_payload,
    frf_payload,
    frf_piece,
    ltd_payload,
    ltd_piece,
    open_store,
    rom_payload,
    rom_piece,
    sim_metrics,
    sim_payload,
    sim_piece,
    steady_payload,
    steady_piece,
)
from studies.store.results import FRFRecord, RomRecord, StudyResults, load_results
from sysid.history_metrics import envelope_errors, peak
from sysid.metrics import rom_metrics

STUDY = """
name = "synthetic"
cases = ["T2", {{name = "T4", orders = [2]}}]
gusts = ["G3", "G6"]
store = "{store}"
[grid]
ni = 41
nj = 16
n_surface = 20
[sweep]
orders = [2, 4]
T = [2.0]
M_base = 16
M = [16, 8]
[methods.plain]
[methods.dc]
dc_gain = "match"
[simulation]
dt = 0.5
t_end = 6.0
"""


def true_system(T):
    """A stable 2-output, 1-input discrete system (order 2): the 'LFD data' of the synthetic store."""
    A = np.array([[0.6, 0.2], [-0.2, 0.6]])
    B = np.array([[1.0], [0.5]])
    C = np.array([[1.0, 0.0], [0.3, -0.4]])
    D = np.zeros((2, 1))
    return control.ss(A, B, C, D, T)


def fake_frf(T, M):
    omega_d, omega = sysid.mckelvey_grid(M, T)
    sys = true_system(T)
    H = np.asarray(sys(np.exp(1j * omega_d)))
    H = H.reshape(2, 1, -1)
    H[:, :, -1] = 0.0  # omega = inf: zero feedthrough, as the CFD gives
    return sysid.FrequencyResponse(H, omega_d, T, inputs=["gust"], outputs=["Cl", "Cm"])


@pytest.fixture
def config(tmp_path):
    return loads_study(STUDY.format(store=tmp_path / "store"), base_dir=tmp_path)


def write_case(store, config, case_name, *, fail_steady=False, fail_order=None, skip_sim=None):
    """Write every piece of one case; optionally a failed steady flow or a failed identification."""
    cs = config.case(case_name)
    c = cs.case
    if fail_steady:
        store.put("steady", steady_piece(c), *failure_payload(RuntimeError("did not converge")))
        return
    sol = types.SimpleNamespace(q=np.ones((3, 2, 4)), cl=0.0, cd=0.01, cm=0.0, converged=True, iterations=5)
    store.put("steady", steady_piece(c), *steady_payload(sol, 1.5))
    t = np.arange(13) * 0.5
    for T in cs.T:
        frf = fake_frf(T, config.M_base)
        store.put("frf", frf_piece(c, T, config.M_base, config.cfd), *frf_payload(frf, config.M_base, "direct", 2.5))
    for g in config.gusts:
        hist = types.SimpleNamespace(t=t, u=np.sin(t), cl=np.sin(t), cm=-0.1 * np.sin(t), cd=0 * t, dt=0.5)
        store.put("ltd", ltd_piece(c, g, config.simulation, config.cfd), *ltd_payload(hist, 3.0, "svm"))
    for pt in config.points():
        if pt.case.name != c.name:
            continue
        rkey = rom_piece(pt, config.M_base, config.cfd)
        if pt.order == fail_order:
            store.put("rom", rkey, *failure_payload(ValueError(f"order {pt.order} refused")))
            continue
        sys = true_system(pt.T)
        frf = fake_frf(pt.T, config.M_base)
        m = rom_metrics(frf.H, frf.H, np.arange(0, 17, 16 // pt.M), ["Cl", "Cm"], np.asarray(sys.dcgain()).reshape(2, 1),
                        0.63, 0.1)
        store.put("rom", rkey, *rom_payload(sys.A, sys.B, sys.C, sys.D, np.array([3.0, 2.0, 1e-9]), frf.H, m,
                                            identify_method="mckelvey1", outputs=["Cl", "Cm"]))
        for g in config.gusts:
            if skip_sim == (pt.order, g.name):
                continue
            sm = sim_metrics(t, {"Cl": np.sin(t), "Cm": -0.1 * np.sin(t)}, {"Cl": np.sin(t), "Cm": -0.1 * np.sin(t)},
                             0.01, 3.0)
            store.put("sim", sim_piece(pt, g, config.M_base, config.simulation, config.cfd),
                      *sim_payload(t, np.sin(t), -0.1 * np.sin(t), sm))


def test_empty_store_lists_everything_missing(config):
    res = load_results(config)
    assert isinstance(res, StudyResults) and not res.complete
    assert (res.frf, res.ltd, res.roms, res.sims, res.failed) == ({}, {}, [], [], [])
    n_points = len(config.points())  # T2: 2 M x 2 orders x 2 methods = 8; T4: 2 x 1 x 2 = 4
    assert n_points == 12
    kinds = [m.split()[0] for m in res.missing]
    assert kinds.count("steady") == 2 and kinds.count("frf") == 2 and kinds.count("ltd") == 4
    assert kinds.count("rom") == n_points and kinds.count("sim") == 0  # sims are listed once their ROM exists
    assert not config.store_dir.exists()  # reading creates nothing


def test_full_store_round_trip(config):
    store = open_store(config)
    write_case(store, config, "T2")
    write_case(store, config, "T4")
    res = load_results(config)
    assert res.complete and res.failed == []
    assert set(res.frf) == {("T2", 2.0), ("T4", 2.0)}
    rec = res.frf[("T2", 2.0)]
    assert isinstance(rec, FRFRecord) and rec.M == 16 and rec.method == "direct" and rec.seconds == 2.5
    assert rec.frf.H.shape == (2, 1, 17) and rec.frf.T == 2.0 and np.isinf(rec.frf.omega[-1])
    assert rec.frf.outputs == ("Cl", "Cm") and rec.frf.inputs == ("gust",)
    assert set(res.ltd) == {(c, g) for c in ("T2", "T4") for g in ("G3", "G6")}
    assert res.ltd[("T2", "G6")].t.shape == (13,) and res.ltd[("T2", "G6")].seconds == 3.0
    assert len(res.roms) == 12 and all(r.ok for r in res.roms)
    assert [(r.case, r.M, r.order, r.method) for r in res.roms[:3]] == [("T2", 8, 2, "plain"), ("T2", 8, 2, "dc"),
                                                                        ("T2", 8, 4, "plain")]
    r = res.rom("T2", 2.0, 16, 4, "dc")
    assert r.A.shape == (2, 2) and r.frf_rom.shape == (2, 1, 17) and r.hankel_sv.shape == (3,)
    model = r.model()
    assert model.dt == 2.0 and list(model.output_labels) == ["Cl", "Cm"]
    assert r.metrics["frf_max_err_Cl"] == 0.0 and r.metrics["stable"] is True
    assert len(res.sims) == 12 * 2 and res.sims[0].metrics["peak_err_Cl"] == 0.0
    assert res.steady["T2"]["cd"] == 0.01
    rows = res.table("rom")
    assert len(rows) == 12 and rows[0]["N_omega"] == 9 and rows[0]["status"] == "ok"
    assert {"frf_max_err_Cm", "dc_err_Cl", "spectral_radius", "seconds"} <= set(rows[0])
    srows = res.table("sim")
    assert len(srows) == 24 and {"gust", "rms_err_Cm", "seconds_ltd"} <= set(srows[0])
    assert len(res.table("frf")) == 2 and res.table("ltd")[0]["n_steps"] == 12


def test_failures_and_partial_store(config):
    store = open_store(config)
    write_case(store, config, "T2", fail_order=4, skip_sim=(2, "G6"))
    write_case(store, config, "T4", fail_steady=True)
    res = load_results(config)
    t2 = [r for r in res.roms if r.case == "T2"]
    assert [r.status for r in t2 if r.order == 4] == ["failed"] * 4
    assert all(r.error == "ValueError: order 4 refused" for r in t2 if r.order == 4)
    assert all(r.ok for r in t2 if r.order == 2)
    bad = [r for r in res.roms if r.case == "T4"]  # no FRF, steady failed: the points carry the reason
    assert len(bad) == 4 and all(r.status == "failed" and "did not converge" in r.error for r in bad)
    assert any("steady flow of T4 failed: RuntimeError: did not converge" in f for f in res.failed)
    # the failed rows keep every metric key (NaN) so tables are rectangular
    rows = res.table("rom")
    assert len({tuple(r) for r in rows}) == 1
    assert np.isnan(next(r for r in rows if r["status"] == "failed")["frf_max_err_Cl"])
    # missing: the sim of order 2 / G6 (both methods, both M) only; T4's FRF and LTDs cannot be computed
    # without its steady flow, so they are not listed
    assert sorted(res.missing) == sorted(f"sim T2 T=2 M={M} N_r=2 {m} G6" for M in (8, 16) for m in ("plain", "dc"))


def test_load_results_from_path(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(STUDY.format(store=tmp_path / "store"))
    res = load_results(path)
    assert res.config.name == "synthetic" and len(res.missing) > 0
    other = load_results(path, store_dir=tmp_path / "elsewhere")
    assert other.missing == res.missing


@pytest.mark.parametrize("bad, exc, match", [
    (42, TypeError, "StudyConfig or the path"),
    ("/nonexistent/study.toml", ValueError, "no such study file"),
])
def test_load_results_bad_input(bad, exc, match):
    with pytest.raises(exc, match=match):
        load_results(bad)


def test_table_kind_and_lookup_errors(config):
    res = load_results(config)
    with pytest.raises(ValueError, match="table kind must be"):
        res.table("heatmap")
    with pytest.raises(KeyError, match="no ROM record for T2"):
        res.rom("T2", 2.0, 16, 2, "plain")
    with pytest.raises(ValueError, match="failed"):
        RomRecord(case="T2", T=2.0, M=16, order=2, method="plain", status="failed", error="X: y").model()


@pytest.mark.parametrize("y, expected", [
    ([0.0, 1.0, -3.0, 2.0], (-3.0, 2.0)),
    ([0.0, 0.5, 0.25, 0.0], (0.5, 1.0)),
])
def test_peak_is_signed_extreme(y, expected):
    assert peak(np.arange(4.0), y) == expected


def test_sim_metrics_values():
    t = np.linspace(0.0, 10.0, 101)
    ltd = np.exp(-((t - 3.0) ** 2))             # peak 1 at t = 3
    rom = 1.1 * np.exp(-((t - 3.5) ** 2))       # peak 1.1 at t = 3.5
    m = sim_metrics(t, {"Cl": rom, "Cm": ltd}, {"Cl": ltd, "Cm": ltd}, 0.2, 30.0)
    assert m["peak_err_Cl"] == pytest.approx(0.1)
    assert m["t_peak_err_Cl"] == pytest.approx(0.5)
    assert m["rms_err_Cl"] == pytest.approx(np.sqrt(np.mean((rom - ltd) ** 2) / np.mean(ltd ** 2)))
    assert (m["peak_err_Cm"], m["t_peak_err_Cm"], m["rms_err_Cm"]) == (0.0, 0.0, 0.0)
    assert (m["seconds_rom"], m["seconds_ltd"]) == (0.2, 30.0)
    z = np.zeros_like(t)
    m0 = sim_metrics(t, {"Cl": z + 1.0}, {"Cl": z}, 0.0, 0.0)
    assert m0["peak_err_Cl"] == np.inf and "peak_err_Cm" not in m0
    blown = np.where(t > 5, np.inf, ltd)  # an unstable ROM that overflowed
    blown[-1] = np.nan
    m1 = sim_metrics(t, {"Cl": blown}, {"Cl": ltd}, 0.0, 0.0)
    assert (m1["peak_err_Cl"], m1["t_peak_err_Cl"], m1["rms_err_Cl"]) == (np.inf, np.inf, np.inf)


def test_envelope_error_compares_both_extremes():
    # a history whose positive peak (0.155) and final negative value (-0.138) have nearly equal magnitudes, as
    # the pitching moment of a low-Mach aerofoil after a sharp-edged gust: a model 10 % low on the positive
    # peak is 10 % of the peak off, not (0.155 + 0.138) / 0.155 = 189 % as a signed-extreme comparison says
    t = np.linspace(0.0, 40.0, 2001)
    bump = 0.19 * np.exp(-((t - 3.0) / 0.3) ** 2)
    ref = bump - 0.138 * (1.0 - np.exp(-np.clip(t - 2.0, 0.0, None) / 3.0))   # +0.151 at s = 3, -0.138 at the end
    model = ref - 0.1 * bump
    assert peak(t, model)[0] < 0.0 < peak(t, ref)[0]  # the signed extremes have opposite signs
    err, t_err = envelope_errors(t, model, ref)
    assert err == pytest.approx(0.019 / ref.max(), rel=1e-3) and err < 0.13
    assert t_err == pytest.approx(0.0, abs=0.021)  # the model's positive peak, at the reference's time
    # an error in the negative extreme counts as much, relative to the same largest magnitude
    low = ref.copy()
    low[-1] -= 0.02
    assert envelope_errors(t, low, ref)[0] == pytest.approx(0.02 / np.abs(ref).max())
    assert envelope_errors(t, ref, ref) == (0.0, 0.0)


def test_rom_metrics_values():
    H = np.ones((2, 1, 5), complex)
    Hm = H.copy()
    Hm[0, 0, 2] = 1.5  # Cl off by 0.5 at one point, not a fitted one
    m = rom_metrics(Hm, H, [0, 4], ["Cl", "Cm"], np.array([[1.25], [1.0]]), 1.02, 0.3)
    assert m["frf_max_err_Cl"] == pytest.approx(0.5) and m["frf_max_err_Cm"] == 0.0
    assert m["frf_rms_err_Cl"] == pytest.approx(np.sqrt(0.25 / 5))
    assert m["frf_max_err_fit"] == 0.0 and m["frf_rms_err_fit"] == 0.0
    assert m["dc_err_Cl"] == pytest.approx(0.25) and m["dc_err_Cm"] == 0.0
    assert m["stable"] is False and m["spectral_radius"] == 1.02 and m["seconds"] == 0.3


@pytest.mark.parametrize("piece, has_results", [("steady", False), ("frf", False), ("ltd", False), ("rom", True),
                                                ("sim", True)])
def test_metric_code_enters_the_rom_and_sim_keys(piece, has_results):
    """The ROM pieces' metrics are computed by sysid (metrics, simulation) and studies.sections.gust_rom.pieces (sim_metrics)."""
    from studies.sections.gust_rom.pieces import store_dependencies

    deps = store_dependencies()[piece]
    assert ("sysid" in deps and "studies.sections.gust_rom.pieces" in deps and "studies.sections.gust_rom.tasks" in deps) == has_results
    assert "cfd" in deps and (deps == ("cfd",)) == (not has_results)


def test_fast_sweep_metadata_survives_the_store(config):
    """The fast sweep's own metadata (error estimate, tol_met, shifts) is stored and read back with the FRF."""
    store = open_store(config)
    write_case(store, config, "T2")
    c = config.cases[0].case
    frf = fake_frf(2.0, config.M_base)
    est = 1e-9 * np.abs(frf.H[:, 0])
    est[:, -1] = 0.0
    frf = frf.replace(metadata={"method": "fast", "tol": 1e-8, "tol_met": True, "error_estimate": est.tolist(),
                                "shifts": [0.0, 1.5], "basis_size": 64})
    store.put("frf", frf_piece(c, 2.0, config.M_base, config.cfd), *frf_payload(frf, config.M_base, "fast", 1.5))
    rec = load_results(config).frf[("T2", 2.0)]
    assert rec.method == "fast" and rec.tol_met is True and rec.lfd["shifts"] == [0.0, 1.5]
    assert rec.max_relative_error_estimate == pytest.approx(1e-9, rel=1e-12)
    assert rec.frf.metadata["basis_size"] == 64 and rec.frf.metadata["case"] == "T2"
    write_case(store, config, "T4")  # the direct path: no estimate, nothing to meet
    direct = load_results(config).frf[("T4", 2.0)]
    assert direct.tol_met is None and np.isnan(direct.max_relative_error_estimate)
