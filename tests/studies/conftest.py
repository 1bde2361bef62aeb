"""Fixtures of the studies tests: the tiny study computed once per test session (CFD in seconds)."""

import time

import pytest
from tinystudy import STUDY

from studies.config import load_study
from studies.run.runner import run_study


@pytest.fixture(scope="session")
def computed(tmp_path_factory):
    """The tiny study computed once (inline), with its elapsed time."""
    d = tmp_path_factory.mktemp("tiny")
    (d / "tiny.toml").write_text(STUDY)
    config = load_study(d / "tiny.toml")
    t0 = time.perf_counter()
    results = run_study(config, progress=False)
    return config, results, time.perf_counter() - t0
