"""Every code block of README.md and docs/*.md runs as printed, and running them leaves the checkout clean.

Sybil (https://sybil.readthedocs.io) finds the fenced blocks of each page; this module makes one test per block:

- ``python``: executed in a fresh namespace (so every block is complete: imports and data of its own), with
  the repository root as the working directory;
- ``bash``: run by ``bash -e`` in the repository root, each line as a user types it; ``.venv/bin/`` (where the
  README's set-up puts the environment) is read as the environment running the tests, and the checkout's
  packages come first on ``PYTHONPATH``;
- ``toml``: parsed; a complete study file (one with ``cases``) is validated as ``lfdrom run`` would
  (``studies.config.parse_study``);
- other languages (``text`` outputs, ``matlab``) are shown, not run.

An HTML comment on the line before a block changes how it runs:
``<!-- docs-test: slow (why) -->`` runs it only in the slow set (``pytest -m slow``): blocks of minutes;
``<!-- docs-test: skip (why) -->`` never runs it (``make test`` is this suite itself).

The last test checks that the blocks run so far left ``git status --porcelain`` as it was: examples write into
``results/`` (ignored), never into tracked files.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest
from sybil import Sybil
from sybil.parsers.markdown import CodeBlockParser, PythonCodeBlockParser

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
DIRECTIVE = re.compile(r"<!--\s*docs-test:\s*(slow|skip)\b\s*(.*?)\s*-->")
SHOWN = ("text", "matlab", "console-output")
SHELL_TIMEOUT = 3600  # s: the longest documented command (the paper study) runs for minutes


def _run_shell(example) -> None:
    env = dict(os.environ, MPLBACKEND="Agg", PYTHONPATH=os.pathsep.join(
        [str(ROOT)] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]))
    venv_bin = Path(sys.executable).parent
    env["PATH"] = os.pathsep.join([str(venv_bin), env.get("PATH", "")])
    source = example.parsed.replace(".venv/bin/", f"{venv_bin}/")
    activate = venv_bin / "activate"   # absent when the suite runs outside a virtual environment: PATH has it already
    source = source.replace("source .venv/bin/activate", f"source {activate}" if activate.exists() else "true")
    proc = subprocess.run(["bash", "-e", "-o", "pipefail", "-c", source], cwd=ROOT, env=env, capture_output=True,
                          text=True, timeout=SHELL_TIMEOUT)
    if proc.returncode != 0:
        raise AssertionError(f"exit status {proc.returncode} of\n{example.parsed}\nstdout:\n{proc.stdout[-3000:]}\n"
                             f"stderr:\n{proc.stderr[-3000:]}")


def _check_toml(example) -> None:
    data = tomllib.loads(example.parsed)
    if "cases" in data:   # a whole study file: as `lfdrom run` reads it, relative paths from studies/
        from studies.config import parse_study

        parse_study(data, source=f"{example.path}:{example.line}", base_dir=ROOT / "studies")


def _ignore(example) -> None:
    return None


SYBIL = Sybil(parsers=[PythonCodeBlockParser(), CodeBlockParser("bash", _run_shell), CodeBlockParser("toml", _check_toml)]
              + [CodeBlockParser(lang, _ignore) for lang in SHOWN], path=str(ROOT))


def _directive(text: str, start: int):
    """``(kind, why)`` of a ``<!-- docs-test: ... -->`` comment on the line just before ``start``, else None."""
    before = text[:start].rstrip("\n").rsplit("\n", 1)[-1]
    match = DIRECTIVE.search(before)
    return (match.group(1), match.group(2)) if match else None


def _blocks():
    out = []
    for page in PAGES:
        doc = SYBIL.parse(page)
        for i, example in enumerate(doc.examples()):
            if example.region.evaluator is _ignore:
                continue
            marks = []
            directive = _directive(doc.text, example.start)
            if directive and directive[0] == "slow":
                marks.append(pytest.mark.slow)
            elif directive:
                marks.append(pytest.mark.skip(reason=directive[1] or "marked docs-test: skip"))
            name = f"{page.relative_to(ROOT)}:{example.line}"
            out.append(pytest.param(page, i, marks=marks, id=name))
    return out


def _status() -> str:
    proc = subprocess.run(["git", "status", "--porcelain", "--untracked-files=all"], cwd=ROOT, capture_output=True,
                          text=True)
    return proc.stdout if proc.returncode == 0 else None


STATUS_BEFORE = _status()


@pytest.mark.parametrize("page, index", _blocks())
def test_block_runs_as_printed(page, index, monkeypatch):
    monkeypatch.chdir(ROOT)
    monkeypatch.setenv("MPLBACKEND", "Agg")
    example = list(SYBIL.parse(page).examples())[index]
    try:
        example.evaluate()
    finally:
        import matplotlib.pyplot as plt

        plt.close("all")


def test_every_page_is_collected():
    # a page whose blocks all vanished (a renamed language, a broken fence) would pass silently otherwise
    assert any(p.name == "README.md" for p in PAGES) and len(PAGES) > 10
    assert sum(1 for p in _blocks()) >= 20


@pytest.mark.skipif(STATUS_BEFORE is None, reason="not a git checkout")
def test_blocks_leave_the_checkout_clean():
    # runs after the blocks (pytest keeps the file's order): whatever they wrote is ignored or temporary
    assert _status() == STATUS_BEFORE


@pytest.mark.slow
@pytest.mark.parametrize("case, naca, mach, cl, cm", [
    ("T4", "0018", 0.25, 0.031, 0.11),
    ("T2", "0010", 0.735, 0.020, 0.39),
])
def test_coarse_grid_accuracy(case, naca, mach, cl, cm):
    # docs/mesh.md, "The coarse grid": the coarse grid's LFD against the paper grid's stored FRF on the 33
    # frequencies of M = 32 (a subset of the stored M = 256 grid); the table quotes two significant digits
    import numpy as np

    import cfd
    import sysid

    paper = sysid.FrequencyResponse.load(ROOT / "docs" / "data" / f"frf-{case}.npz")
    lin = cfd.linearise(cfd.solve_steady(cfd.preset_grid(cfd.naca(naca), "coarse"), mach, 0.0))
    coarse = cfd.lfd_response(lin, sysid.mckelvey_grid(32, paper.T), method="direct")
    ref = np.asarray(paper.H)[:, :, ::8]
    diff = np.max(np.abs(np.asarray(coarse.H) - ref), axis=-1)[:, 0] / np.max(np.abs(ref), axis=-1)[:, 0]
    assert diff == pytest.approx([cl, cm], rel=0.05)
