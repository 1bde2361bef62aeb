"""The module paths of the flat cfd package still import, for one release, as the modules at their new homes
(``cfd.mesh``, ``cfd.sweep``, ``cfd.ltd``) with a DeprecationWarning; the project's own code, tests, benchmarks,
documentation and study files use the new homes only (the old paths' imports and the project-wide import scan:
tests/test_legacy_paths.py)."""

import importlib
import re
import sys
from pathlib import Path

import pytest

import cfd
from cfd.legacy import MOVED

ROOT = Path(__file__).resolve().parents[2]


def test_from_import_of_an_old_path_gives_the_same_objects():
    sys.modules.pop("cfd.sweep_basis", None)
    with pytest.warns(DeprecationWarning, match="cfd.sweep_basis moved to cfd.sweep.basis"):
        from cfd.sweep_basis import SweepBasis
    from cfd.sweep.basis import SweepBasis as new

    assert SweepBasis is new


def test_every_moved_module_exists_and_the_old_file_is_gone():
    for old, new in MOVED.items():
        assert (ROOT / (new.replace(".", "/") + ".py")).is_file(), new
        assert not (ROOT / (old.replace(".", "/") + ".py")).exists(), old


@pytest.mark.parametrize("name", cfd.__all__)
def test_public_names_keep_their_path(name):
    assert getattr(cfd, name) is not None


@pytest.mark.parametrize("module, names", [
    ("cfd.mesh", ("Grid", "GridQuality", "c_grid", "grid_from_nodes", "grid_quality")),
    ("cfd.sweep", ("fast_sweep", "SweepBasis", "gust_operator", "face_gust_vector", "SAFETY", "MAX_WORKERS")),
    ("cfd.ltd", ("ltd_response", "ltd_responses", "LTDHistory", "phase_error_estimate", "check_march", "MAX_STEPS",
                 "RADAU_STEP")),
])
def test_modules_that_became_packages_keep_their_names(module, names):
    mod = importlib.import_module(module)
    assert all(hasattr(mod, name) for name in names)


def test_docs_and_study_files_name_no_old_path():
    """Dotted names (``cfd.mesh_metrics``) and file paths (``cfd/mesh_metrics.py``) of the old modules, in the
    documentation, the study files and the code's own docstrings and messages; a paragraph that names
    ``cfd.legacy`` (the one that says the old paths still import) may name them."""
    stems = "|".join(re.escape(old.split(".", 1)[1]) for old in MOVED)
    pattern = re.compile(rf"\bcfd[./]({stems})\b")
    found = []
    paths = [*ROOT.glob("*.md"), *(ROOT / "docs").rglob("*.md"), *(ROOT / "studies").rglob("*.toml"),
             *(p for folder in ("cfd", "studies", "bench", "sysid", "aeroelastic", "loads")
               for p in (ROOT / folder).rglob("*.py") if p != ROOT / "cfd" / "legacy.py")]
    for path in paths:
        for paragraph in re.split(r"\n\s*\n", path.read_text()):
            if "cfd.legacy" not in paragraph:
                found += [f"{path.relative_to(ROOT)}: {line.strip()}" for line in paragraph.splitlines()
                          if pattern.search(line)]
    assert not found
