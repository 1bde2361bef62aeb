"""studies.run.runner: a tiny study end to end on a coarse grid, resume, failures, interruption, executors, `lfdrom rom`."""

import argparse
import importlib.util
import json
from dataclasses import replace
from pathlib import Path

import control
import numpy as np
import pytest

import sysid
from studies.cli import commands
from studies.run import runner
from studies.sections.gust_rom import tasks
from studies.config import load_study
from studies.store.results import load_results
from studies.run.runner import RunnerError, auto_workers, run_study
from tinystudy import N_POINTS, copy_study

@pytest.fixture
def counts(monkeypatch):
    """Count the calls of the tasks' compute functions (inline runs only)."""
    calls = {}

    def wrap(name):
        fn = getattr(tasks, name)

        def counted(*a, **k):
            calls[name] = calls.get(name, 0) + 1
            return fn(*a, **k)

        monkeypatch.setattr(tasks, name, counted)

    for name in ("_steady", "_linear_system", "lfd_on_mckelvey_grid", "_ltds", "_identify", "rom_simulation"):
        wrap(name)
    return calls


def test_end_to_end_metrics(computed):
    config, res, elapsed = computed
    assert res.complete and res.failed == []  # no wall-clock bound: speed is measured in bench/, not in tests
    assert len(res.roms) == N_POINTS and all(r.ok for r in res.roms)
    assert len(res.sims) == N_POINTS and len(res.ltd) == 1
    (frf,) = res.frf.values()
    assert frf.frf.H.shape == (2, 1, 17) and frf.method in ("direct", "fast") and frf.seconds > 0
    # the highest order fits the LFD response of Cl closely on all 17 points (the coarse-grid response is smooth)
    best = res.rom(config.cases[0].case.name, config.cases[0].T[0], 16, 4, "plain")
    assert best.metrics["frf_max_err_Cl"] < 0.05
    assert best.metrics["frf_max_err_Cl"] < res.rom("T2", config.cases[0].T[0], 16, 2, "plain").metrics["frf_max_err_Cl"]
    # DC matching and stability hold by construction
    for r in res.roms:
        if r.method == "dc_stable":
            assert abs(r.metrics["dc_err_Cl"]) < 1e-8 * abs(res.frf[("T2", r.T)].frf.H[0, 0, 0])
            assert r.metrics["spectral_radius"] < 1 - 1e-3 + 1e-9 and r.metrics["stable"]
    # ROM against LTD: both discretise the same linear system; the gap is the ROM's FRF error (a few %),
    # BDF2 and Tustin at dt = 0.1 (phase errors ~ (omega dt)^2 / 3 < 1e-3 at omega ~ 0.6) and the ROM's
    # extrapolation above the sampled band; 10 % on the Cl peak at order 4 is a loose, safe bound
    sim = next(s for s in res.sims if (s.M, s.order, s.method) == (16, 4, "plain"))
    assert sim.metrics["peak_err_Cl"] < 0.1 and sim.metrics["rms_err_Cl"] < 0.2
    assert sim.metrics["t_peak_err_Cl"] < 1.0
    assert all(np.isfinite(list(s.metrics.values())).all() for s in res.sims)
    ltd = res.ltd[("T2", "G4")]
    np.testing.assert_array_equal(sim.t, ltd.t)
    assert ltd.t[-1] == pytest.approx(16.0) and abs(ltd.cl).max() > 0
    log = json.loads((config.output_dir / "run-log.json").read_text())
    assert log["totals"]["rom"]["count"] == N_POINTS and log["totals"]["sim"]["count"] == N_POINTS


def test_second_run_computes_nothing(computed, counts, capsys):
    config, first, _ = computed
    again = run_study(config, progress=True)
    assert counts == {}
    out = capsys.readouterr().out
    assert "to compute: 0 CFD piece(s), up to 0 ROM piece(s)" in out and "0 piece(s) computed" in out
    for a, b in zip(first.roms, again.roms):
        np.testing.assert_array_equal(a.A, b.A)
    assert load_results(config).complete


def test_failing_point_is_recorded_and_retried(computed, counts, tmp_path, monkeypatch):
    config, first, _ = computed
    study = copy_study(config, tmp_path, drop=("rom", "sim"))
    real = sysid.identify

    def flaky(frf, order, **kw):
        if order == 4:
            raise sysid.OrderError("order 4 refused for the test")
        return real(frf, order, **kw)

    monkeypatch.setattr(sysid, "identify", flaky)
    res = run_study(study, progress=False)
    failed = [r for r in res.roms if not r.ok]
    assert len(failed) == 4 and {r.order for r in failed} == {4}
    assert all(r.error == "OrderError: order 4 refused for the test" and r.A is None for r in failed)
    assert sum(r.ok for r in res.roms) == 4 and {s.order for s in res.sims} == {2}
    assert res.complete  # failures count as done
    assert "_steady" not in counts and "lfd_on_mckelvey_grid" not in counts and "_ltds" not in counts
    rows = res.table("rom")
    assert [r["status"] for r in rows].count("failed") == 4
    # the next run retries the failed points only
    monkeypatch.setattr(sysid, "identify", real)
    counts.clear()
    res = run_study(study, progress=False)
    assert counts == {"_identify": 4, "rom_simulation": 4}
    assert all(r.ok for r in res.roms) and len(res.sims) == N_POINTS


def test_interrupted_run_keeps_finished_pieces(computed, counts, tmp_path, monkeypatch):
    config, first, _ = computed
    study = copy_study(config, tmp_path, drop=("ltd", "rom", "sim"))
    real = tasks._identify
    n = {"calls": 0}

    def interrupt(*a, **k):
        n["calls"] += 1
        if n["calls"] == 3:
            raise KeyboardInterrupt
        return real(*a, **k)

    monkeypatch.setattr(tasks, "_identify", interrupt)
    with pytest.raises(KeyboardInterrupt):
        run_study(study, progress=False)
    part = load_results(study)
    assert len(part.ltd) == 1 and sum(r.ok for r in part.roms) == 2 and not part.complete
    assert sum(m.startswith("rom ") for m in part.missing) == N_POINTS - 2
    monkeypatch.setattr(tasks, "_identify", real)
    counts.clear()
    res = run_study(study, progress=False)
    assert "_ltds" not in counts and "lfd_on_mckelvey_grid" not in counts and counts["_identify"] == N_POINTS - 2
    assert res.complete and len(res.sims) == N_POINTS
    for a in first.sims:  # same numbers as the uninterrupted run
        b = next(s for s in res.sims if (s.M, s.order, s.method) == (a.M, a.order, a.method))
        np.testing.assert_allclose(b.cl, a.cl, rtol=1e-10, atol=1e-12)


def test_cfd_failure_marks_the_case_failed(computed, tmp_path, monkeypatch):
    config, _, _ = computed

    def diverge(case):
        raise RuntimeError(f"steady solver diverged for {case.name}")

    monkeypatch.setattr(tasks, "_steady", diverge)
    study = copy_study(config, tmp_path, drop=("steady", "frf", "ltd", "rom", "sim"))
    res = run_study(study, progress=False)
    assert len(res.roms) == N_POINTS and not any(r.ok for r in res.roms)
    assert all("steady flow of T2 failed: RuntimeError: steady solver diverged for T2" in r.error for r in res.roms)
    assert res.frf == {} and res.ltd == {} and res.sims == [] and res.complete
    assert any("steady flow of T2 failed" in f for f in res.failed)


def test_local_processes_give_the_same_results(computed, tmp_path):
    config, first, _ = computed
    study = copy_study(config, tmp_path, drop=("ltd", "rom", "sim"))
    res = run_study(study, workers=2, progress=False)
    assert res.complete and len(res.sims) == N_POINTS
    for a, b in zip(first.roms, res.roms):
        np.testing.assert_allclose(b.frf_rom, a.frf_rom, rtol=1e-8, atol=1e-12)


@pytest.mark.skipif(importlib.util.find_spec("distributed") is None, reason="needs dask[distributed]")
def test_dask_local_cluster(computed, tmp_path):
    config, first, _ = computed
    study = copy_study(config, tmp_path, drop=("ltd", "rom", "sim"))
    res = run_study(study, scheduler="local", workers=1, progress=False)
    assert res.complete and len(res.ltd) == 1 and len(res.sims) == N_POINTS
    np.testing.assert_allclose(res.ltd[("T2", "G4")].cl, first.ltd[("T2", "G4")].cl, rtol=1e-10, atol=1e-14)


@pytest.mark.parametrize("kw, match", [
    (dict(workers=0), "workers must be a positive integer"),
    (dict(workers="2"), "workers must be a positive integer"),
    (dict(scheduler="somewhere"), "scheduler must be a Dask address"),
])
def test_bad_options(computed, kw, match):
    with pytest.raises(RunnerError, match=match):
        run_study(computed[0], progress=False, **kw)


@pytest.mark.parametrize("study, cpus, expected", [
    ("paper.toml", 2, 2),     # six cases, one sweep and one gust march each: 12 tasks, two CPUs
    ("paper.toml", 64, 12),
    ("demo.toml", 16, 2),     # one case: its LFD sweep beside its gust march
    ("demo.toml", 1, 1),
])
def test_auto_workers(study, cpus, expected):
    config = load_study(Path(__file__).resolve().parents[3] / "studies" / study)
    assert auto_workers(config, cpus=cpus) == expected
    assert auto_workers(replace(config, gusts=()), cpus=cpus) == min(cpus, len(config.cases))


def test_an_unwritable_store_is_refused_before_computing(computed, monkeypatch):
    # the run computed the steady flow, logged a FileNotFoundError and returned "0 failed" before
    import studies.run.runner as runner
    from studies.store.files import NotWritableError

    monkeypatch.setattr(runner, "_run", lambda *a, **k: pytest.fail("computed with an unwritable store"))
    with pytest.raises(NotWritableError, match="results store"):
        run_study(computed[0], store_dir="/proc/no/store", progress=False)


def test_bad_study_argument():
    with pytest.raises(TypeError, match="StudyConfig or the path"):
        run_study(3.5)


def test_lfdrom_rom_writes_npz_and_mat(computed, tmp_path, monkeypatch, capsys):
    """`lfdrom rom` exports the runner's ROM; the runner is pointed at the tiny grid's cached FRF."""
    config, _, _ = computed
    from dataclasses import replace

    real = runner.run_study

    def on_tiny_grid(study, **kw):  # same case on the tiny grid, reusing the computed store
        case = replace(study.cases[0], case=replace(study.cases[0].case, grid=config.cases[0].case.grid))
        return real(replace(study, cases=(case,), store_dir=config.store_dir), progress=False)

    monkeypatch.setattr(runner, "run_study", on_tiny_grid)
    p = argparse.ArgumentParser(prog="lfdrom")
    commands.add_subcommands(p.add_subparsers(dest="command"))
    out = tmp_path / "rom.mat"
    status = commands.dispatch(p.parse_args(["rom", "T2", "--order", "4", "--M", "16", "--dc-gain", "--out", str(out),
                                             "--quiet"]))
    assert status == 0 and "wrote" in capsys.readouterr().out
    from studies.store.rom_export import load_rom_npz
    import scipy.io

    model, meta = load_rom_npz(tmp_path / "rom.npz")
    mat = scipy.io.loadmat(out)
    assert model.nstates == 4 and model.dt == pytest.approx(70 / (2 * np.pi), rel=1e-11)
    np.testing.assert_allclose(mat["A"], model.A)
    assert meta["order"] == 4 and meta["case"] == "T2" and meta["method"]["dc_gain"] == "match"
    assert list(model.output_labels) == ["Cl", "Cm"]


def test_a_dead_worker_fails_its_tasks_and_the_run_ends_resumable(computed, tmp_path, monkeypatch):
    """A worker killed mid-run (BrokenProcessPool: the task in flight fails, every later submit raises) must not
    stop the runner with a traceback: the lost tasks are recorded with the cause, the run ends (exit 3), what
    was stored stays, and the next run computes the rest."""
    from concurrent.futures import Future
    from concurrent.futures.process import BrokenProcessPool

    from studies.run.executors import InlinePool

    config, _, _ = computed
    study = copy_study(config, tmp_path, drop=("ltd", "rom", "sim"))

    class BreakingPool(InlinePool):
        name = "a pool whose second task loses its worker"

        def __init__(self):
            self.n = 0

        def submit(self, fn, *args):
            self.n += 1
            if self.n == 2:
                f = Future()
                f.set_exception(BrokenProcessPool("A process in the process pool was terminated abruptly"))
                return f
            if self.n > 2:
                raise BrokenProcessPool("A child process terminated abruptly, the process pool is not usable")
            return super().submit(fn, *args)

    monkeypatch.setattr(runner, "make_pool", lambda *a, **k: BreakingPool())
    res = run_study(study, progress=False)
    lost = res.run.task_failures
    assert lost and all("a worker process died" in t["error"] and not t["write"] for t in lost)
    status, message = commands.run_status(res)
    assert status == commands.EXIT_INCOMPLETE and "incomplete" in message
    monkeypatch.undo()
    again = run_study(study, progress=False)
    assert again.complete and again.run.task_failures == ()


def test_interruption_counts_tasks_that_ended_before_it(computed, tmp_path, monkeypatch):
    """With one process a task runs inside submit: a Ctrl-C in the case's FRF task comes after its LTD task
    ended (its pieces stored) but before the runner took that task's reports; the message counts them."""
    from studies.run.runner import RunInterrupted

    config, _, _ = computed
    study = copy_study(config, tmp_path, drop=("frf", "ltd", "rom", "sim"))

    def interrupt(*a, **k):
        raise KeyboardInterrupt

    monkeypatch.setattr(tasks, "lfd_on_mckelvey_grid", interrupt)
    with pytest.raises(RunInterrupted) as e:
        run_study(study, progress=False)
    assert e.value.computed == len(load_results(study).ltd) == len(config.gusts) >= 1


def _stored_piece(label):
    """A task of the fake section below: one piece 'stored' (nothing computed)."""
    return [{"piece": "fake", "label": label, "status": "ok", "seconds": 0.25}]


def _ctrl_c(label):
    raise KeyboardInterrupt


class _FakeSection:
    """A section whose tasks store nothing (no CFD): piece 'a', then ``second`` (after 'a' or not)."""

    def __init__(self, second, after):
        self.second, self.after = second, after

    def plan(self, config, store, force):
        from studies.sections.protocol import Plan, Task

        return Plan(tasks=(Task("fake", "T2", _stored_piece, ("a",), ids=("a",), priority=0),
                           Task("fake", "T2", self.second, ("b",), ids=("b",), after=self.after, priority=1)),
                    rom_pieces=2)

    def summary(self, config, results):
        return None


def _fake_study(tmp_path, monkeypatch, second, after=("a",)):
    from tinystudy import STUDY

    (tmp_path / "s.toml").write_text(STUDY)
    monkeypatch.setattr(runner, "active_sections", lambda config: [_FakeSection(second, after)])
    return load_study(tmp_path / "s.toml")


def test_a_finished_run_log_is_not_marked_interrupted(tmp_path, monkeypatch):
    config = _fake_study(tmp_path, monkeypatch, _stored_piece)
    run_study(config, progress=False)
    log = json.loads((config.output_dir / "run-log.json").read_text())
    assert "interrupted" not in log and [p["label"] for p in log["pieces"]] == ["a", "b"]


@pytest.mark.parametrize("after", [("a",), ()])
def test_an_interrupted_run_writes_its_log(tmp_path, monkeypatch, after):
    """A run of two tasks, the second interrupted. With after=() both are ready together, so the first ended
    (inside submit, one process) before the runner took its report: it is logged all the same."""
    config = _fake_study(tmp_path, monkeypatch, _ctrl_c, after)
    with pytest.raises(runner.RunInterrupted) as e:
        run_study(config, progress=False)
    assert e.value.computed == 1
    log = json.loads((config.output_dir / "run-log.json").read_text())
    assert log["interrupted"] is True and log["study"] == config.name
    assert [p["label"] for p in log["pieces"]] == ["a"] and log["totals"]["fake"]["count"] == 1
