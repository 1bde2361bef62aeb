"""The module paths of the flat studies package still import, for one release, as the modules at their new
homes with a DeprecationWarning; the project's own code and tests use the new homes only."""

import ast
import importlib
import sys
from pathlib import Path

import pytest

from studies.legacy import MOVED

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("old", sorted(MOVED))
def test_old_path_is_the_new_module_with_a_warning(old):
    sys.modules.pop(old, None)
    with pytest.warns(DeprecationWarning, match=rf"{old} moved to {MOVED[old]}"):
        module = importlib.import_module(old)
    assert module is importlib.import_module(MOVED[old])
    assert module.__spec__.name == MOVED[old]  # find_spec of the new name (hashed into store keys) unchanged


@pytest.mark.parametrize("module, name", [("studies.config", "frf_piece"), ("studies.store.results", "sim_payload")])
def test_moved_names_warn(module, name):
    with pytest.warns(DeprecationWarning, match=f"moved to studies.sections.gust_rom.pieces.{name}"):
        value = getattr(importlib.import_module(module), name)
    assert value is getattr(importlib.import_module("studies.sections.gust_rom.pieces"), name)


def test_packages_keep_their_names():
    import studies.cli
    import studies.config
    import studies.report

    assert callable(studies.cli.main) and callable(studies.config.load_study) and callable(studies.report.make_report)


def _imports(path: Path):
    for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
        if isinstance(node, ast.Import):
            yield from (alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            yield node.module
            yield from (f"{node.module}.{alias.name}" for alias in node.names)


def test_project_imports_no_old_path():
    old = []
    for folder in ("studies", "tests", "bench", "cfd", "sysid", "aeroelastic"):
        for path in sorted((ROOT / folder).rglob("*.py")):
            if path.name == "test_legacy.py":
                continue
            old += [f"{path.relative_to(ROOT)}: {name}" for name in _imports(path) if name in MOVED]
    assert not old
