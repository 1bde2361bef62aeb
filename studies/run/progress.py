"""Progress output of a study run: one line per finished piece, progress from inside the long CFD pieces, and a
progress bar on a terminal.

Two sides:

- **In the task** (any process): :func:`piece_reporter` gives a :class:`PieceReporter` for a task's key
  (:func:`task_key`) when this process has a sink (:func:`set_sink`), else None. Its adapters
  :meth:`PieceReporter.steady`, :meth:`~PieceReporter.sweep` and :meth:`~PieceReporter.ltd` are the
  ``progress=`` callables of ``cfd.solve_steady``, ``cfd.sweep.fast_sweep`` and ``cfd.ltd_responses``; each
  turns the solver's numbers into an event (a small dict: ``key``, ``text``, ``short``, ``fraction``,
  ``elapsed``) and sends it at most every :data:`SEND_INTERVAL` seconds. In the main process (``workers=1``)
  the sink is the display itself; in a local worker process it puts the event on a ``multiprocessing`` queue
  that the main process drains while it waits for its tasks (``studies.run.executors.ProcessPool``). On a Dask
  cluster the workers have no sink: only the piece lines are shown.
- **In the main process**: :class:`ProgressDisplay` prints the runner's lines (``[elapsed s] text``, on
  stdout) and shows the events: in mode ``"lines"`` as indented lines, at most one per task every
  ``interval`` seconds (10 by default); in mode ``"bar"`` as one status line on stderr, redrawn in place
  (overall pieces, then each running task with its bar and its latest numbers), cleared before each printed
  line and at the end.

The callables only observe: nothing they do enters a piece's configuration or key, and the pieces are stored
exactly as without them (an interrupted run keeps every stored piece, as before).
"""

from __future__ import annotations

import math
import os
import sys
import time
from typing import Callable, Optional

__all__ = ["MODES", "SEND_INTERVAL", "resolve_mode", "task_key", "set_sink", "piece_reporter", "PieceReporter",
           "ProgressDisplay"]

MODES = ("auto", "bar", "lines", "pieces", "off")
"""Progress modes: ``"auto"`` (a bar when stderr is a terminal and not in CI, else lines), ``"bar"``,
``"lines"``, ``"pieces"`` (only the runner's lines: one per finished piece) and ``"off"``."""

SEND_INTERVAL = 0.5
"""Seconds between two events a task sends (the display throttles further)."""

_sink: Optional[Callable[[dict], None]] = None


def resolve_mode(progress, stream=None) -> str:
    """The effective mode of ``run_study(progress=...)``: True is ``"auto"``, False ``"off"``.

    ``"auto"`` is ``"bar"`` when ``stream`` (default ``sys.stderr``) is a terminal, ``TERM`` is not ``dumb`` and
    the ``CI`` environment variable is unset (or ``0`` / ``false``); else ``"lines"``.

    Raises
    ------
    ValueError
        An unknown mode.
    """
    if progress is True or progress is None:
        progress = "auto"
    elif progress is False:
        progress = "off"
    if progress not in MODES:
        raise ValueError(f"progress must be True, False or one of {MODES}; got {progress!r}")
    if progress != "auto":
        return progress
    stream = sys.stderr if stream is None else stream
    try:
        tty = bool(stream.isatty())
    except (AttributeError, ValueError, OSError):
        tty = False
    ci = os.environ.get("CI", "").strip().lower() not in ("", "0", "false", "no")
    return "bar" if tty and not ci and os.environ.get("TERM", "") != "dumb" else "lines"


def task_key(kind: str, case: str, T: Optional[float] = None) -> str:
    """The name of a CFD task in the progress output: ``"steady T2"``, ``"frf T2 T=11.1408"``, ``"ltd T2"``."""
    return f"{kind} {case}" if T is None else f"{kind} {case} T={T:.6g}"


def set_sink(sink: Optional[Callable[[dict], None]]):
    """Send this process's progress events to ``sink`` (None: none are made); returns the previous sink."""
    global _sink
    previous, _sink = _sink, sink
    return previous


def piece_reporter(key: str) -> Optional["PieceReporter"]:
    """A :class:`PieceReporter` for the task ``key`` if this process has a sink, else None."""
    return None if _sink is None else PieceReporter(key, _sink)


def _fraction_log(value: float, target: float) -> float:
    """Progress of a quantity that falls from 1 to ``target`` on a log scale, in [0, 1]."""
    if not (value > 0.0) or not (0.0 < target < 1.0):
        return 1.0 if value == 0.0 else 0.0
    return min(1.0, max(0.0, math.log(value) / math.log(target)))


class PieceReporter:
    """Sends a task's progress events to the process's sink, at most every :data:`SEND_INTERVAL` seconds."""

    def __init__(self, key: str, sink: Callable[[dict], None], interval: float = SEND_INTERVAL):
        self.key, self.sink, self.interval = key, sink, float(interval)
        self.t0 = time.perf_counter()
        self.last = -math.inf

    def update(self, text: str, short: str, fraction: Optional[float] = None, force: bool = False) -> None:
        """Send an event (unless one was sent less than ``interval`` seconds ago and not ``force``)."""
        now = time.perf_counter()
        if not force and now - self.last < self.interval:
            return
        self.last = now
        try:
            self.sink({"key": self.key, "text": text, "short": short, "fraction": fraction,
                       "elapsed": now - self.t0})
        except Exception:  # noqa: BLE001 - progress must never fail a piece (e.g. a closed queue)
            pass

    def steady(self, tol: float) -> Callable:
        """``progress`` of ``cfd.solve_steady`` with the solve's ``tol``: the bar is the residual's fall."""

        def progress(step, residual, relative, cfl):
            what = "Runge-Kutta start" if step == 0 else f"Newton step {step}"
            self.update(f"{what}: residual {relative:.2e} of the free stream's (target {tol:.0e}), CFL {cfl:.3g}",
                        f"step {step} |R| {relative:.1e}", _fraction_log(relative, tol))

        return progress

    def sweep(self, n_frequencies: int, tol: float) -> Callable:
        """``progress`` of ``cfd.sweep.fast_sweep`` over ``n_frequencies`` finite frequencies: the bar is the share
        of frequencies whose error estimate meets ``tol``."""

        def progress(basis, worst, failing):
            n_fail = len(failing)
            n = max(int(n_frequencies), 1)
            self.update(f"shift {len(basis.shifts)} at omega = {basis.shifts[-1]:.4g}, basis {basis.size}, worst "
                        f"error estimate {worst:.1e} (target {tol:.0e}), {n_fail}/{n} frequencies to go",
                        f"shift {len(basis.shifts)} basis {basis.size} {n - n_fail}/{n} freq", 1.0 - n_fail / n,
                        force=True)  # one call per shift (a factorisation each): every one is worth a look

        return progress

    def ltd(self) -> Callable:
        """``progress`` of ``cfd.ltd_responses``: the bar is the share of the time steps done."""

        def progress(step, n_steps, t):
            self.update(f"step {step}/{n_steps} (s = {t:.2f})", f"step {step}/{n_steps}", step / max(n_steps, 1),
                        force=step == n_steps)

        return progress


def _clock(seconds: float) -> str:
    m, s = divmod(int(seconds), 60)
    h, m = divmod(m, 60)
    return f"{h}:{m:02d}:{s:02d}" if h else f"{m}:{s:02d}"


def _bar(fraction, width: int) -> str:
    if fraction is None:
        return "[" + "?" * width + "]"
    n = int(round(min(1.0, max(0.0, fraction)) * width))
    return "[" + "#" * n + "-" * (width - n) + "]"


class ProgressDisplay:
    """The main process's progress output (see the module docstring).

    Parameters
    ----------
    mode : {"bar", "lines", "pieces", "off"}
        As :func:`resolve_mode` returns.
    interval : float
        Lines mode: seconds between two lines of the same task.
    out, err : text streams, optional
        Where lines (default ``sys.stdout``) and the bar (default ``sys.stderr``) go.
    """

    def __init__(self, mode: str, interval: float = 10.0, out=None, err=None):
        if mode not in MODES or mode == "auto":
            raise ValueError(f"mode must be one of {MODES[1:]}; got {mode!r}")
        self.mode, self.interval = mode, float(interval)
        self.out = out if out is not None else sys.stdout
        self.err = err if err is not None else sys.stderr
        self.t0 = time.perf_counter()
        self.active: dict = {}      # key -> latest event
        self.last_line: dict = {}   # key -> time of its last line (lines mode)
        self.finished: set = set()  # keys whose task is done: late events are dropped
        self.done = self.total = 0
        self._drawn = False

    @property
    def enabled(self) -> bool:
        return self.mode != "off"

    @property
    def sink(self) -> Optional[Callable[[dict], None]]:
        """Where tasks send their events (None in modes ``"pieces"`` and ``"off"``: no events are made)."""
        return self.event if self.mode in ("bar", "lines") else None

    def _elapsed(self) -> float:
        return time.perf_counter() - self.t0

    def say(self, text: str) -> None:
        """One line ``[elapsed s] text`` on ``out`` (nothing in mode ``"off"``)."""
        if not self.enabled:
            return
        self._clear()
        print(f"[{self._elapsed():8.1f} s] {text}", file=self.out, flush=True)
        self._draw()

    def counts(self, done: int, total: int) -> None:
        """Pieces finished and expected, for the bar."""
        self.done, self.total = int(done), int(total)

    def event(self, ev: dict) -> None:
        """An event of a running task (from :class:`PieceReporter`)."""
        key = ev.get("key")
        if key is None or key in self.finished or self.mode not in ("bar", "lines"):
            return
        self.active[key] = ev
        if self.mode == "lines":
            now = time.perf_counter()
            if now - self.last_line.get(key, -math.inf) >= self.interval:
                self.last_line[key] = now
                print(f"[{self._elapsed():8.1f} s]   {key}: {ev.get('text', '')} ({ev.get('elapsed', 0.0):.0f} s in)",
                      file=self.out, flush=True)
        else:
            self._draw()  # every event (each task sends at most one every SEND_INTERVAL seconds)

    def task_done(self, key: Optional[str]) -> None:
        """The task ``key`` has finished: drop it from the bar and ignore its late events."""
        if key is None:
            return
        self.finished.add(key)
        self.active.pop(key, None)
        self._draw()

    def close(self) -> None:
        """Clear the bar (call at the end of the run, also when it fails or is interrupted)."""
        self._clear()
        self.active.clear()

    # -- the bar ------------------------------------------------------------------------------------

    def _width(self) -> int:
        try:
            cols = os.get_terminal_size(self.err.fileno()).columns
        except (AttributeError, ValueError, OSError):
            cols = 0
        if cols <= 0:  # not known (a pseudo-terminal without a size): COLUMNS, else 100
            try:
                cols = int(os.environ.get("COLUMNS", "100"))
            except ValueError:
                cols = 100
        return max(40, cols)

    def line(self, width: int) -> str:
        """The status line (without control characters), at most ``width - 1`` characters: pieces done and the
        elapsed time, then each running task with its bar, its percentage and its latest numbers (left out, then
        the bars shortened, when the line would be too long)."""
        total = max(self.total, 1)
        head = f"{self.done}/{self.total} pieces {_clock(self._elapsed())}"
        text = ""
        for bar_w, short, overall in ((10, True, True), (10, False, True), (5, False, False)):
            parts = [f"{_bar(self.done / total, 10)} {head}" if overall else head]
            for key, ev in self.active.items():
                frac = ev.get("fraction")
                pct = "" if frac is None else f" {100 * min(1.0, max(0.0, frac)):3.0f}%"
                tail = f" {ev.get('short', '')}" if short and ev.get("short") else ""
                parts.append(f"{key} {_bar(frac, bar_w)}{pct}{tail}")
            text = " | ".join(parts)
            if len(text) < width:
                return text
        return text[:max(width - 4, 0)] + "..."

    def _draw(self) -> None:
        if self.mode != "bar" or not (self.active or self._drawn):
            return
        try:
            self.err.write("\r\x1b[K" + self.line(self._width()))
            self.err.flush()
            self._drawn = True
        except (OSError, ValueError):
            pass

    def _clear(self) -> None:
        if self.mode == "bar" and self._drawn:
            try:
                self.err.write("\r\x1b[K")
                self.err.flush()
            except (OSError, ValueError):
                pass
            self._drawn = False
