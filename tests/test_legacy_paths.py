"""The old module paths that the package splits left behind (:data:`cfd.legacy.MOVED`,
:data:`studies.legacy.MOVED`): each still imports, as the module at its new home with a DeprecationWarning, and no
project code imports one. (Package-specific checks: tests/cfd/test_legacy.py, tests/studies/test_legacy.py.)"""

import ast
import importlib
import sys
from pathlib import Path

import pytest

from cfd.legacy import MOVED as CFD_MOVED
from studies.legacy import MOVED as STUDIES_MOVED

ROOT = Path(__file__).resolve().parents[1]
MOVED = {**CFD_MOVED, **STUDIES_MOVED}


@pytest.mark.parametrize("old", sorted(MOVED))
def test_old_path_is_the_new_module_with_a_warning(old):
    sys.modules.pop(old, None)
    with pytest.warns(DeprecationWarning, match=rf"{old} moved to {MOVED[old]}"):
        module = importlib.import_module(old)
    assert module is importlib.import_module(MOVED[old])
    assert module.__spec__.name == MOVED[old]  # find_spec of the new name (hashed into store keys) unchanged


def _imports(path: Path):
    for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
        if isinstance(node, ast.Import):
            yield from (alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            yield node.module
            yield from (f"{node.module}.{alias.name}" for alias in node.names)


def test_project_imports_no_old_path():
    old = []
    for folder in ("cfd", "sysid", "aeroelastic", "loads", "studies", "tests", "bench"):
        for path in sorted((ROOT / folder).rglob("*.py")):
            if path.name == "test_legacy.py" or "__pycache__" in path.parts:
                continue
            old += [f"{path.relative_to(ROOT)}: {name}" for name in _imports(path) if name in MOVED]
    assert not old
