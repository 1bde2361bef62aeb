"""studies.run.progress: events from inside the pieces, their display as lines or a bar, across worker processes,
and the runner's output for the tiny study (serial and with two worker processes)."""

import io
import re
from types import SimpleNamespace

import numpy as np
import pytest

from studies.run import progress as prog
from studies.run.executors import ProcessPool
from studies.run.progress import PieceReporter, ProgressDisplay, resolve_mode, task_key
from studies.run.runner import run_study
from tinystudy import copy_study


class _Stream(io.StringIO):
    def __init__(self, tty):
        super().__init__()
        self.tty = tty

    def isatty(self):
        return self.tty


def test_modes(monkeypatch):
    monkeypatch.delenv("CI", raising=False)
    monkeypatch.setenv("TERM", "xterm")
    assert resolve_mode(False) == "off" and resolve_mode("pieces") == "pieces" and resolve_mode("bar") == "bar"
    assert resolve_mode(True, _Stream(True)) == "bar" and resolve_mode("auto", _Stream(False)) == "lines"
    monkeypatch.setenv("CI", "true")
    assert resolve_mode(True, _Stream(True)) == "lines"  # CI logs get plain lines, even on a pseudo-terminal
    monkeypatch.setenv("CI", "0")
    monkeypatch.setenv("TERM", "dumb")
    assert resolve_mode(True, _Stream(True)) == "lines"
    with pytest.raises(ValueError, match="progress must be True, False or one of"):
        resolve_mode("fancy")
    assert task_key("frf", "T2", 70 / (2 * np.pi)) == "frf T2 T=11.1408" and task_key("ltd", "T2") == "ltd T2"


def test_reporter_throttles_and_adapts_the_solvers_callbacks():
    events = []
    rep = PieceReporter("steady T2", events.append, interval=3600.0)
    rep.steady(1e-10)(0, 2.0, 1e-5, 2.5)
    rep.steady(1e-10)(1, 1.0, 1e-6, 10.0)           # within the interval: dropped
    assert len(events) == 1 and events[0]["fraction"] == pytest.approx(0.5)
    assert events[0]["key"] == "steady T2" and "Runge-Kutta start: residual 1.00e-05" in events[0]["text"]
    rep.ltd()(160, 160, 16.0)                       # the last step is always sent
    assert events[-1]["fraction"] == 1.0 and events[-1]["short"] == "step 160/160"
    basis = SimpleNamespace(shifts=[0.0, 0.43], size=64)
    rep.sweep(16, 1e-8)(basis, 19.0, np.array([0.1, 0.2, 0.3]))  # one per shift: always sent
    ev = events[-1]
    assert ev["fraction"] == pytest.approx(13 / 16) and "shift 2 at omega = 0.43, basis 64" in ev["text"]
    assert "3/16 frequencies to go" in ev["text"] and ev["elapsed"] >= 0.0

    def broken(event):
        raise BrokenPipeError("the queue is gone")

    PieceReporter("ltd T2", broken).ltd()(1, 10, 0.1)  # progress never fails a piece


def test_display_lines_are_throttled_per_task_and_late_events_dropped():
    out, err = io.StringIO(), io.StringIO()
    d = ProgressDisplay("lines", interval=3600.0, out=out, err=err)
    for k in (1, 2, 3):
        d.event({"key": "ltd T2", "text": f"step {k}/3", "short": "", "fraction": k / 3, "elapsed": 1.0})
    d.event({"key": "steady T2", "text": "Newton step 1", "short": "", "fraction": 0.1, "elapsed": 2.0})
    d.task_done("ltd T2")
    d.event({"key": "ltd T2", "text": "late", "short": "", "fraction": 1.0, "elapsed": 3.0})
    d.say("ltd T2 G4: 1.00 s")
    lines = out.getvalue().splitlines()
    assert [re.sub(r"^\[ *[\d.]+ s\]", "", line) for line in lines] == [
        "   ltd T2: step 1/3 (1 s in)", "   steady T2: Newton step 1 (2 s in)", " ltd T2 G4: 1.00 s"]
    assert err.getvalue() == ""
    quiet = ProgressDisplay("pieces", out=out)
    assert quiet.sink is None and ProgressDisplay("off").sink is None and d.sink is not None


def test_display_bar_is_redrawn_in_place_and_cleared():
    out, err = io.StringIO(), io.StringIO()
    d = ProgressDisplay("bar", out=out, err=err)
    d.counts(1, 4)
    d.event({"key": "frf T2 T=11.1408", "text": "", "short": "shift 2 basis 64 13/16 freq", "fraction": 0.8125})
    assert err.getvalue().startswith("\r\x1b[K[##--------] 1/4 pieces 0:00 | frf T2 T=11.1408 [########--]  81% "
                                     "shift 2 basis 64 13/16 freq")
    d.say("frf T2: 7.49 s")
    assert out.getvalue().endswith("] frf T2: 7.49 s\n") and "\n" not in err.getvalue()
    assert err.getvalue().count("\r\x1b[K") == 3  # drawn, cleared for the line, drawn again
    d.task_done("frf T2 T=11.1408")
    d.close()
    assert err.getvalue().endswith("\r\x1b[K") and d.active == {}
    d.active = {f"frf T{i} T=11.1408": {"fraction": 0.5, "short": "shift 2 basis 64 13/16 freq"} for i in range(4)}
    assert len(d.line(80)) < 80 and d.line(80).endswith("...") and "frf T3 T=11.1408 [##---]  50%" in d.line(160)


def _send_events(key, n):
    """A task in a worker process: ``n`` progress events for ``key``, unthrottled."""
    rep = prog.piece_reporter(key)
    if rep is None:
        return "no sink"
    rep.interval = 0.0
    for k in range(1, n + 1):
        rep.ltd()(k, n, 0.1 * k)
    return "sent"


def test_worker_processes_send_their_events_back():
    events = []
    pool = ProcessPool(2, progress=events.append)
    try:
        futures = {pool.submit(_send_events, f"ltd C{i}", 5) for i in range(2)}
        left = set(futures)
        while left:
            _, left = pool.wait(left)
        assert {f.result() for f in futures} == {"sent"}
    finally:
        pool.close()
    pool._drain()  # closed: nothing more, no error
    for i in range(2):  # each worker's own events arrive in order (late ones may be lost after the task ends)
        steps = [int(e["short"].split()[1].split("/")[0]) for e in events if e["key"] == f"ltd C{i}"]
        assert steps == sorted(steps) and steps and steps[0] == 1
    quiet = ProcessPool(2)  # no progress: the workers get no sink (not the parent's, inherited by fork)
    previous = prog.set_sink(events.append)
    try:
        assert quiet.submit(_send_events, "x", 1).result() == "no sink"
    finally:
        prog.set_sink(previous)
        quiet.close()


def _steps(out, key):
    return [int(m) for m in re.findall(rf"\]   {re.escape(key)}: (?:Newton )?step (\d+)", out)]


def test_runner_prints_progress_from_inside_the_pieces(computed, tmp_path, capsys):
    config, first, _ = computed
    study = copy_study(config, tmp_path, drop=("steady", "ltd", "rom", "sim"))
    res = run_study(study, progress="lines", progress_interval=0.0)
    out = capsys.readouterr().out
    assert "]   steady T2: Runge-Kutta start: residual" in out and "of the free stream's (target 1e-10)" in out
    steps = _steps(out, "steady T2")
    assert steps and steps == sorted(steps)
    ltd = _steps(out, "ltd T2")
    assert ltd[-1] == 160 and ltd == sorted(ltd)
    assert "]   roms T2: sweep point 1/8: T2 T=11.1408" in out
    assert out.index("]   steady T2:") < out.index("] steady T2: ") < out.index("]   ltd T2:")
    assert prog._sink is None  # the run leaves no sink behind
    np.testing.assert_array_equal(res.ltd[("T2", "G4")].cl, first.ltd[("T2", "G4")].cl)
    assert res.complete and len(res.sims) == len(first.sims)


def test_runner_with_two_workers_shows_the_workers_progress(computed, tmp_path, capsys):
    config, first, _ = computed
    study = copy_study(config, tmp_path / "w", drop=("frf", "ltd", "rom", "sim"))
    res = run_study(study, workers=2, progress="lines", progress_interval=0.0)
    out = capsys.readouterr().out
    assert "]   frf T2 T=11.1408: shift 1 at omega = 0, basis" in out and "frequencies to go" in out
    assert _steps(out, "ltd T2") and _steps(out, "ltd T2") == sorted(_steps(out, "ltd T2"))
    # the same sweep in a worker process (one BLAS thread) rounds differently and can take another greedy path:
    # both results are within the sweep's tolerance (cfd.lfd_response tol = 1e-8, relative) of the exact
    # response, so they agree to twice that per output's peak, not to round-off (1.6e-10 relative was seen on a
    # Cm sample)
    H, H0 = (r.frf[("T2", config.cases[0].T[0])].frf.H for r in (res, first))
    peak = np.abs(H0).max(axis=(1, 2), keepdims=True)
    assert np.all(np.abs(H - H0) <= 2e-8 * peak)
    quiet = run_study(copy_study(config, tmp_path / "q", drop=("ltd", "rom", "sim")), progress="pieces")
    out = capsys.readouterr().out
    assert "] ltd T2 G4" in out and "]   ltd T2:" not in out and quiet.complete
