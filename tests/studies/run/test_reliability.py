"""Reliability of the study commands: what a user can get wrong is refused before any computation, exit codes
mean something, worker processes never outlive their parent, Ctrl-C stops cleanly, NaN is never "ok".

Each test is the regression of a defect found by probing bad inputs and faults (issue "Hardening").
"""

import argparse
import os
import signal
import subprocess
import sys
import textwrap
import time
import types
from pathlib import Path

import numpy as np
import pytest
from tinystudy import N_POINTS, copy_study

import sysid
from studies.cli import commands
from studies.run import executors
from studies.run import runner
from studies.config import MAX_STEPS, T_RANGE, StudyConfigError, loads_study, min_order
from studies.store.results import RomRecord
from studies.run.runner import RunInterrupted, RunSummary, run_study

REPO = Path(__file__).resolve().parents[3]
STUDIES = REPO / "studies"

BASE = """
cases = ["T2"]
gusts = ["G3"]
[sweep]
orders = [{orders}]
T = [{T}]
[method]
dc_gain = "{dc}"
algorithm = "{algorithm}"
[simulation]
dt = {dt}
t_end = {t_end}
[grid]
nj = {nj}
"""


def study_text(orders="9", T="11", dc="none", dt="0.02", t_end="40", nj="60", algorithm="auto"):
    return BASE.format(orders=orders, T=T, dc=dc, dt=dt, t_end=t_end, nj=nj, algorithm=algorithm)


def cli(argv):
    p = argparse.ArgumentParser(prog="lfdrom")
    commands.add_subcommands(p.add_subparsers(dest="command"))
    return commands.dispatch(p.parse_args(argv))


# ------------------------------------------------------------------ validation before any computation
@pytest.mark.parametrize("kw, key, match", [
    (dict(T="1e-300"), "sweep.T[0]", r"2/T = 2e\+300 .* far above .* feedthrough alone"),
    (dict(T='"0.1**300"'), "sweep.T[0]", r"far above"),
    (dict(T="1e-13"), "sweep.T[0]", r"k = 1e\+13\) far above"),
    (dict(T="1e6"), "sweep.T[0]", r"far below .* DC gain alone"),
    (dict(dt="1e-9"), "simulation.dt", r"4e\+10 time steps .* TiB"),
    (dict(t_end="1e12"), "simulation.t_end", r"5e\+13 time steps"),
    (dict(nj="100000000"), "grid.nj", r"nj = 100000000 .* use nj < 6251"),
    (dict(orders="1", dc="match", algorithm="subspace"), "sweep.orders", r"order 1 cannot meet .* orders >= 2"),
])
def test_impossible_studies_are_refused_with_the_key(kw, key, match):
    with pytest.raises(StudyConfigError, match=match) as e:
        loads_study(study_text(**kw))
    assert e.value.key == key


def test_accepted_limits_are_accepted():
    low = loads_study(study_text(T=str(T_RANGE[0]), orders="2", dc="match"))
    assert low.cases[0].T == (T_RANGE[0],) and low.cases[0].orders == (2,) and low.methods[0].dc_gain == "match"
    assert loads_study(study_text(T=str(T_RANGE[1]))).cases[0].T == (T_RANGE[1],)
    longest = loads_study(study_text(dt="0.02", t_end=str(0.02 * MAX_STEPS))).simulation
    assert (longest.dt, longest.t_end) == (0.02, 0.02 * MAX_STEPS)


@pytest.mark.parametrize("algorithm", ["subspace", "relocation"])
@pytest.mark.parametrize("p", [1, 2, 3])
def test_min_order_is_what_the_identification_needs(p, algorithm):
    """The order limit of studies.config against sysid itself (not a rule written twice): identify succeeds
    at min_order and refuses one state less."""
    import control

    rng = np.random.default_rng(p)
    A = np.diag([0.5, -0.3, 0.7])
    B, C = rng.standard_normal((3, 1)), rng.standard_normal((p, 3))
    frf = sysid.FrequencyResponse.from_model(control.ss(A, B, C, np.zeros((p, 1)), 1.0),
                                             sysid.mckelvey_grid(32, 1.0)[0])
    n = min_order(p, 1, "match", algorithm)
    res = sysid.identify(frf, n, dc_gain="match", algorithm=algorithm)
    assert res.algorithm == algorithm
    if n > 1:
        with pytest.raises(sysid.ConstraintError, match="equality constraints"):
            sysid.identify(frf, n - 1, dc_gain="match", algorithm=algorithm)


@pytest.mark.parametrize("dc, stable, p, expected", [
    ("none", False, 2, "subspace"), ("match", False, 2, "relocation"), ("none", True, 2, "relocation"),
    ("match", True, 1, "relocation"),
])
def test_study_methods_resolve_as_identify_does(dc, stable, p, expected):
    """MethodOptions.resolved_algorithm (used for the order limits) against what sysid.identify runs."""
    import control

    from studies.config import MethodOptions

    meth = MethodOptions(name="m", dc_gain=dc, stable=stable)
    rng = np.random.default_rng(0)
    frf = sysid.FrequencyResponse.from_model(
        control.ss(np.diag([0.5, -0.3, 0.7]), rng.standard_normal((3, 1)), rng.standard_normal((p, 3)),
                   np.zeros((p, 1)), 1.0), sysid.mckelvey_grid(32, 1.0)[0])
    res = sysid.identify(frf, 3, **meth.identify_kwargs())
    assert meth.resolved_algorithm(p, 1) == res.algorithm == expected


@pytest.mark.parametrize("argv, match", [
    (["--T", "1e-300"], "--T: T = 1e-300"),
    (["--M", "1048576"], r"--M: M_base = 1048576 asks the LFD for 1048577 frequencies .* M_base <= 4096"),
])
def test_rom_command_refuses_what_cannot_be_computed(capsys, argv, match):
    assert cli(["rom", "T2", "--order", "9", "--quiet"] + argv) == commands.EXIT_UNAVAILABLE
    assert __import__("re").search(match, capsys.readouterr().err)


# ------------------------------------------------------------------ output locations probed first
@pytest.fixture
def recorder(monkeypatch):
    """run_study / make_report replaced by recorders returning the given results."""
    calls = []
    state = {"results": None}

    def run_study(config, **kw):
        calls.append("run_study")
        r = state["results"]
        return r(config) if callable(r) else types.SimpleNamespace(roms=[], sims=[], failed=[], missing=[],
                                                                      run=None, config=config)

    def make_report(config, **kw):
        calls.append("make_report")

    monkeypatch.setattr(runner, "run_study", run_study)
    import studies.report.make

    monkeypatch.setattr(studies.report.make, "make_report", make_report)
    return types.SimpleNamespace(calls=calls, state=state)


def test_unwritable_store_is_found_before_computing(tmp_path, recorder, capsys):
    blocker = tmp_path / "a-file"
    blocker.write_text("not a folder")
    status = cli(["run", str(STUDIES / "demo.toml"), "--store", str(blocker / "store"), "--out", str(tmp_path / "o"),
                  "--no-report", "--quiet"])
    assert status == commands.EXIT_NOT_WRITTEN and recorder.calls == []
    err = capsys.readouterr().err
    assert "results store" in err and "is a file, not a folder" in err and "--store" in err


def test_unwritable_rom_output_is_found_before_computing(tmp_path, recorder, capsys):
    blocker = tmp_path / "a-file"
    blocker.write_text("x")
    status = cli(["rom", "T2", "--order", "9", "--out", str(blocker / "rom.npz"), "--store", str(tmp_path / "s"),
                  "--quiet"])
    assert status == commands.EXIT_NOT_WRITTEN and recorder.calls == []
    err = capsys.readouterr().err
    assert "output folder" in err and "is a file, not a folder" in err and "--out" in err


def test_unwritable_page_folder_is_found_before_computing(tmp_path, recorder, capsys):
    blocker = tmp_path / "a-file"
    blocker.write_text("x")
    status = cli(["report", str(STUDIES / "demo.toml"), "--out", str(tmp_path / "o"), "--quiet",
                  "--page", str(blocker / "page.md")])
    assert status == commands.EXIT_NOT_WRITTEN and recorder.calls == []
    assert "report page's folder" in capsys.readouterr().err


@pytest.mark.parametrize("prose, match", [
    ('summary = "unterminated\n', r"prose.toml.*line 1"),
    ('no_such_slot = "text"\n', r"no_such_slot"),
])
def test_bad_prose_is_found_before_computing(tmp_path, recorder, capsys, prose, match):
    study = tmp_path / "s.toml"
    (tmp_path / "prose.toml").write_text(prose)
    study.write_text(study_text() + '\n[report]\nprose = "prose.toml"\npage = "page.md"\n')
    assert cli(["run", str(study), "--quiet"]) == commands.EXIT_UNAVAILABLE
    assert recorder.calls == []
    assert __import__("re").search(match, capsys.readouterr().err)


# ------------------------------------------------------------------ exit codes
def _results(config, *, failed=(), missing=(), roms=(), run=None):
    return types.SimpleNamespace(roms=list(roms), sims=[], failed=list(failed), missing=list(missing), run=run,
                                 config=config)


@pytest.mark.parametrize("make, status, last", [
    (lambda c: _results(c, run=RunSummary(3, 0)), commands.EXIT_OK, "done: every piece computed and stored"),
    (lambda c: _results(c, failed=["steady T2: ConvergenceError: diverged"]), commands.EXIT_INCOMPLETE,
     "incomplete: 1 piece(s) failed"),
    (lambda c: _results(c, roms=[RomRecord(case="T2", T=1.0, M=32, order=9, method="m", status="failed",
                                           error="OrderError: x")]), commands.EXIT_INCOMPLETE, "1 piece(s) failed"),
    (lambda c: _results(c, missing=["ltd T2 G3"]), commands.EXIT_INCOMPLETE, "1 missing"),
    (lambda c: _results(c, run=RunSummary(0, 0, ({"kind": "steady", "case": "T2", "error": "OSError: [Errno 28] "
                                                  "No space left on device", "write": True},))),
     commands.EXIT_NOT_WRITTEN, "nothing written for 1 task(s)"),
])
def test_exit_status_says_what_happened(tmp_path, recorder, capsys, make, status, last):
    recorder.state["results"] = make
    code = cli(["run", str(STUDIES / "demo.toml"), "--out", str(tmp_path / "o"), "--quiet", "--no-report"])
    assert code == status
    captured = capsys.readouterr()
    final = (captured.out if status == 0 else captured.err).strip().splitlines()[-1]
    assert final.startswith("lfdrom") and last in final


def test_interrupted_command_says_how_to_resume(tmp_path, monkeypatch, capsys):
    def interrupted(config, **kw):
        raise RunInterrupted(5, config.store_dir)

    monkeypatch.setattr(runner, "run_study", interrupted)
    assert cli(["run", str(STUDIES / "demo.toml"), "--out", str(tmp_path), "--quiet"]) == commands.EXIT_INTERRUPTED
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "5 piece(s) stored" in err[0] and "running the same command again resumes" in err[0]


def test_rom_summary_names_every_output():
    rec = RomRecord(case="T2", T=1.0, M=32, order=9, method="m", status="ok",
                    metrics={"frf_max_err_Cl": 0.01, "frf_max_err_Cm": 0.087, "dc_err_Cl": 1e-14, "dc_err_Cm": 2e-14,
                             "spectral_radius": 0.99})
    line = commands.rom_summary_line(rec, ["Cl", "Cm"])
    assert "Cl 1 %" in line and "Cm 8.7 %" in line and "spectral radius 0.990000" in line


# ------------------------------------------------------------------ NaN is never "ok"
def test_non_finite_metrics_fail_the_piece(computed, tmp_path, monkeypatch):
    config, _, _ = computed
    study = copy_study(config, tmp_path, drop=("rom", "sim"))
    real = sysid.identify

    class Overflowed:
        def __init__(self, res):
            self._res = res

        def __getattr__(self, name):
            return getattr(self._res, name)

        def evaluate(self, omega_d):
            out = self._res.evaluate(omega_d)
            return np.full_like(out, np.nan)

    monkeypatch.setattr(sysid, "identify", lambda frf, order, **kw: Overflowed(real(frf, order, **kw)))
    res = run_study(study, progress=False)
    assert len(res.roms) == N_POINTS and not any(r.ok for r in res.roms)
    assert all("FloatingPointError" in r.error and "non-finite" in r.error for r in res.roms)
    assert all(r.status == "failed" for r in res.roms)


# ------------------------------------------------------------------ workers
def test_workers_are_capped_at_the_study_width(computed, tmp_path):
    config, _, _ = computed
    study = copy_study(config, tmp_path)
    with pytest.warns(RuntimeWarning, match=r"workers = 24 is more than this study can use .* using 2"):
        res = run_study(study, workers=24, progress=False)
    assert res.complete and res.run.computed == 0


WORKER_SCRIPT = textwrap.dedent("""
    import os, sys, time
    from pathlib import Path
    from studies.run import executors

    def sleeper(path):
        Path(path).write_text(str(os.getpid()))
        time.sleep(60)

    pool = executors.ProcessPool(2)
    futures = [pool.submit(sleeper, sys.argv[1] + str(i)) for i in range(2)]
    print("ready", flush=True)
    try:
        pool.wait(set(futures))
    except KeyboardInterrupt:
        pool.close(abort=True)
        print("stopped", flush=True)
        sys.exit(130)
""")


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    stat = Path(f"/proc/{pid}/stat")
    return not (stat.exists() and stat.read_text().split(") ")[1].startswith("Z"))  # a zombie is gone


def _sigint_default():
    """``preexec_fn`` of the child processes that receive Ctrl-C: SIGINT back to its default disposition. A
    shell without job control starts background jobs with SIGINT ignored, and an ignored signal stays ignored
    across exec (Python then installs no KeyboardInterrupt handler): a suite started with ``&`` would otherwise
    send Ctrl-C to processes that cannot hear it."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _start_pool_script(tmp_path):
    script = tmp_path / "pool.py"
    script.write_text(WORKER_SCRIPT)
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(filter(None, [str(REPO), os.environ.get("PYTHONPATH")])))
    proc = subprocess.Popen([sys.executable, str(script), str(tmp_path / "pid")], cwd=REPO, env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, preexec_fn=_sigint_default)
    assert proc.stdout.readline().strip() == "ready"
    files = [tmp_path / f"pid{i}" for i in range(2)]
    deadline = time.monotonic() + 60
    while not all(f.exists() and f.read_text() for f in files):
        assert time.monotonic() < deadline, "the workers did not start"
        time.sleep(0.1)
    return proc, [int(f.read_text()) for f in files]


def _wait_gone(pids, seconds):
    deadline = time.monotonic() + seconds
    while any(_alive(p) for p in pids) and time.monotonic() < deadline:
        time.sleep(0.1)
    return [p for p in pids if _alive(p)]


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="kill -9 and /proc")
def test_workers_die_with_their_parent(tmp_path):
    """kill -9 of the runner's process ends its workers (they were left blocked on a pipe forever)."""
    proc, pids = _start_pool_script(tmp_path)
    proc.send_signal(signal.SIGKILL)
    proc.wait(timeout=10)
    # PR_SET_PDEATHSIG ends them at once; the parent-pid poll within executors.PARENT_POLL_S otherwise
    left = _wait_gone(pids, 10 * executors.PARENT_POLL_S)
    for p in left:
        os.kill(p, signal.SIGKILL)
    assert left == []


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="signals and /proc")
def test_ctrl_c_stops_the_workers_without_tracebacks(tmp_path):
    proc, pids = _start_pool_script(tmp_path)
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=30)
    assert proc.returncode == 130 and "stopped" in out
    assert "Traceback" not in err  # the workers ignore SIGINT; the parent stops them
    assert _wait_gone(pids, 10) == []


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="process groups")
def test_ctrl_c_on_lfdrom_run(tmp_path):
    """Ctrl-C (SIGINT to the whole process group, as a terminal sends it) during `lfdrom run --workers 2`:
    exit 130, no traceback, and a line that says how to resume."""
    from tinystudy import STUDY

    (tmp_path / "tiny.toml").write_text(STUDY)
    proc = subprocess.Popen([sys.executable, "-m", "studies.cli", "run", str(tmp_path / "tiny.toml"), "--workers",
                             "2"], cwd=REPO, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True, preexec_fn=_sigint_default)
    line = proc.stdout.readline()
    deadline = time.monotonic() + 60
    while "study 'tiny'" not in line or "to compute" not in line:  # the runner's first progress line
        assert line and time.monotonic() < deadline, "the run did not start"
        line = proc.stdout.readline()
    time.sleep(1.0)
    os.killpg(proc.pid, signal.SIGINT)
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == commands.EXIT_INTERRUPTED, err
    assert "Traceback" not in err and "interrupted" in err and "resume" in err


def test_rediscretisation_error_names_the_simulation_step(monkeypatch):
    """The re-discretisation at the simulation step fails (a continuous pole at s = 2/dt, which sysid reports as
    "choose a different T"): the message names dt, the step it happened at, not the identification's T."""
    def singular(model, T):
        raise sysid.ModelError(f"c2d_bilinear(): a pole at s = 2/T = {2.0 / T:g}; choose a different T")

    monkeypatch.setattr(sysid.simulate, "c2d_bilinear", singular)
    t = 0.1 * np.arange(10)
    with pytest.raises(sysid.ModelError, match=r"identified with T = 1 .* simulation step dt = 0\.1 .* s = 2/dt = 20"):
        sysid.simulate.rom_simulation([[0.5]], [[1.0]], [[1.0]], [[0.0]], 1.0, t, np.ones_like(t))


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="kill -9")
def test_kill_9_then_rerun_equals_the_uninterrupted_run(computed, tmp_path):
    """`lfdrom run` killed with SIGKILL (process group: the workers too) after its first pieces; the rerun
    computes only the rest and its results equal an uninterrupted run's (store corruption: test_cache.py)."""
    from tinystudy import STUDY

    from studies.config import load_study
    from studies.store.results import load_results

    config, first, _ = computed
    (tmp_path / "tiny.toml").write_text(STUDY)
    proc = subprocess.Popen([sys.executable, "-m", "studies.cli", "run", str(tmp_path / "tiny.toml"), "--workers",
                             "2", "--no-report"], cwd=REPO, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)
    deadline = time.monotonic() + 120
    line = proc.stdout.readline()
    while " pieces, " not in line:  # the first stored piece
        assert line and time.monotonic() < deadline, "no piece was stored"
        line = proc.stdout.readline()
    os.killpg(proc.pid, signal.SIGKILL)
    proc.wait(timeout=30)
    study = load_study(tmp_path / "tiny.toml")
    part = load_results(study)
    assert not part.complete and part.steady  # killed mid-way, the steady flow kept
    res = run_study(study, progress=False)
    assert res.complete and res.run.computed < N_POINTS * 2 + 3 and not res.failed
    for a in first.sims:
        b = next(s for s in res.sims if (s.M, s.order, s.method, s.gust) == (a.M, a.order, a.method, a.gust))
        # same code and inputs on the same machine: the stored results agree to round-off of the solves
        np.testing.assert_allclose(b.cl, a.cl, rtol=1e-9, atol=1e-12 * np.abs(a.cl).max())


def test_a_page_that_is_not_ours_is_refused_before_computing(tmp_path, recorder, capsys):
    """`[report] page` naming a hand-written file: refused before any CFD (it was refused only after the run),
    untouched; --force-page lets the run go on."""
    page = tmp_path / "notes.md"
    page.write_text("# My notes\n\nhand-written\n")
    study = tmp_path / "s.toml"
    study.write_text(study_text() + '\n[report]\npage = "notes.md"\n')
    assert cli(["run", str(study), "--quiet"]) == commands.EXIT_UNAVAILABLE
    assert recorder.calls == [] and page.read_text() == "# My notes\n\nhand-written\n"
    assert "was not written by lfdrom report" in capsys.readouterr().err
    assert cli(["run", str(study), "--quiet", "--force-page"]) == commands.EXIT_OK
    assert recorder.calls == ["run_study", "make_report"]


def test_dry_run_checks_what_the_run_would_refuse(tmp_path, recorder, capsys):
    page = tmp_path / "notes.md"
    page.write_text("hand-written\n")
    study = tmp_path / "s.toml"
    study.write_text(study_text() + '\n[report]\npage = "notes.md"\n')
    assert cli(["run", str(study), "--dry-run"]) == commands.EXIT_UNAVAILABLE
    assert recorder.calls == [] and "was not written by lfdrom report" in capsys.readouterr().err


def test_report_folders_are_probed_before_computing(tmp_path, recorder, capsys):
    out = tmp_path / "o"
    out.mkdir()
    (out / "tables").write_text("a file where the tables folder goes")
    assert cli(["run", str(STUDIES / "demo.toml"), "--out", str(out), "--quiet"]) == commands.EXIT_NOT_WRITTEN
    assert recorder.calls == []
    assert "report's tables folder" in capsys.readouterr().err


@pytest.mark.parametrize("page", ["pg/noext", "pg/notes.txt"])
def test_report_page_must_be_markdown(tmp_path, recorder, capsys, page):
    assert cli(["report", str(STUDIES / "demo.toml"), "--page", str(tmp_path / page), "--quiet"]) == \
        commands.EXIT_UNAVAILABLE
    assert recorder.calls == [] and "must be a Markdown file ending in .md" in capsys.readouterr().err
    assert not (tmp_path / "pg").exists()


def test_rom_output_that_is_a_folder_is_refused_before_computing(tmp_path, recorder, capsys):
    (tmp_path / "d.npz").mkdir()
    assert cli(["rom", "T2", "--order", "9", "--out", str(tmp_path / "d.npz"), "--quiet"]) == commands.EXIT_NOT_WRITTEN
    assert recorder.calls == [] and "d.npz: is a folder" in capsys.readouterr().err


def test_report_of_an_incomplete_store_is_not_a_success(computed, tmp_path, capsys):
    """`lfdrom report` on a store that lacks pieces writes the page and exits 3, saying what to run."""
    from tinystudy import STUDY

    config, _, _ = computed
    (tmp_path / "tiny.toml").write_text(STUDY)
    study = copy_study(config, tmp_path, drop=("sim",))
    status = cli(["report", str(tmp_path / "tiny.toml"), "--store", str(study.store_dir), "--out", str(tmp_path / "r"),
                  "--quiet"])
    assert status == commands.EXIT_INCOMPLETE and (tmp_path / "r" / "report.md").is_file()
    last = capsys.readouterr().err.strip().splitlines()[-1]
    assert "written from an incomplete store" in last and "missing" in last and "lfdrom run" in last


def test_no_gusts_no_step_limit():
    cfg = loads_study(study_text(dt="1e-9").replace('gusts = ["G3"]\n', ""))
    assert cfg.gusts == () and cfg.simulation.dt == 1e-9


@pytest.mark.parametrize("edit, key, match", [
    (('orders = [9]', 'orders = [9, 25, 9]'), "sweep.orders[2]",
     r"9 is sweep.orders\[0\] again .* give each value once"),
    (('T = [11]', 'T = ["70/(2*pi)", 11.140846016432674]'), "sweep.T[1]", r"is sweep.T\[0\] again"),
    (('gusts = ["G3"]', 'gusts = []'), "gusts", r"is empty: name the gusts .* leave the key out"),
])
def test_study_files_that_repeat_a_value_or_list_no_gust_are_refused(edit, key, match):
    """Accepted without a word before: duplicates were silently dropped, gusts = [] meant no gust responses."""
    text = study_text()
    assert edit[0] in text
    with pytest.raises(StudyConfigError, match=match) as e:
        loads_study(text.replace(*edit))
    assert e.value.key == key


def test_grid_limits():
    from studies.config.cases import CaseError, GridSpec

    with pytest.raises(CaseError, match="farfield = 1000 chords .* at most 200"):
        GridSpec(farfield=1000.0)
    with pytest.raises(CaseError, match=r"3001 x 600 has 1,797,000 cells: a worker would need about 6\d\d GiB"):
        GridSpec(ni=3001, nj=600)


# ------------------------------------------------------------------ reproducibility and unreadable stores
def _blas_threads():
    from threadpoolctl import threadpool_info

    return sorted({lib["num_threads"] for lib in threadpool_info() if lib["user_api"] == "blas"})


@pytest.mark.parametrize("workers", [1, 2])
def test_every_task_runs_with_one_blas_thread(workers):
    """A lone worker (this process) had the machine's default BLAS threads, two on two cores, while each of two
    workers had one: the stored results then differed in the last bits with the worker count."""
    pool = executors.make_pool(None, workers)
    try:
        (threads,) = [f.result() for f in [pool.submit(_blas_threads)]]
    finally:
        pool.close()
    assert threads == [executors.BLAS_THREADS] == [1]


def test_results_do_not_depend_on_the_worker_count(computed, tmp_path):
    """The ROMs and their gust histories of the tiny study, identified again by two worker processes and again
    in this process, are bit-for-bit those of the `computed` fixture (workers = 1). Before, they were 1.1e-12
    relative apart: the first identification in a process compiles its refit problems, later ones re-solve
    them from sysid's cache (now emptied at the start of every task, studies.executors.pinned_call), and a lone
    worker had the default BLAS threads (5e-9 apart on the paper study)."""
    config, first, _ = computed
    for workers, where in ((2, "w2"), (1, "w1")):
        res = run_study(copy_study(config, tmp_path / where, drop=("rom", "sim")), workers=workers, progress=False)
        assert res.complete and res.run.computed == N_POINTS * 2
        for a in first.roms:
            b = next(r for r in res.roms if (r.M, r.order, r.method) == (a.M, a.order, a.method))
            assert {k: v for k, v in a.metrics.items() if k != "seconds"} == \
                   {k: v for k, v in b.metrics.items() if k != "seconds"}
    for a in first.sims:
        b = next(s for s in res.sims if (s.M, s.order, s.method, s.gust) == (a.M, a.order, a.method, a.gust))
        assert np.array_equal(a.cl, b.cl) and np.array_equal(a.cm, b.cm)


def test_a_store_folder_replaced_by_a_file_is_an_incomplete_run(computed, tmp_path, capsys):
    """`lfdrom run` over a store whose rom/ folder is a file: the other pieces go on, the ROM task is recorded
    as failed and the run ends with exit 3 as docs/studies.md says (it stopped in its plan with exit 1)."""
    from tinystudy import STUDY

    config, _, _ = computed
    study = copy_study(config, tmp_path)
    import shutil

    shutil.rmtree(study.store_dir / "rom")
    (study.store_dir / "rom").write_text("not a folder")
    (tmp_path / "tiny.toml").write_text(STUDY)
    status = cli(["run", str(tmp_path / "tiny.toml"), "--store", str(study.store_dir), "--out", str(tmp_path / "o"),
                  "--no-report", "--workers", "1", "--quiet"])
    assert status == commands.EXIT_INCOMPLETE
    err = capsys.readouterr().err
    assert "the results store cannot be read" in err and "run again" in err and "Traceback" not in err
