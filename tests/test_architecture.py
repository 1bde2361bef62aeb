"""docs/architecture.md's table of which package may import which, checked against the code's imports (the
import graph of tests/test_imports.py, grouped by top-level package and by sub-package of ``studies`` and
``cfd``; an import across top-level packages counts as one of the imported package as a whole)."""

import functools
import importlib.util
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "architecture.md"

_spec = importlib.util.spec_from_file_location("import_graph", Path(__file__).with_name("test_imports.py"))
graph = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(graph)


def group(module: str) -> str:
    """``studies.sections.gust_rom.tasks`` -> ``studies.sections.gust_rom``; ``studies.run.runner`` ->
    ``studies.run``; ``cfd.mesh.metrics`` -> ``cfd.mesh`` (a sub-package); ``cfd.lfd`` -> ``cfd``."""
    parts = module.split(".")
    if parts[0] == "cfd":
        return "cfd." + parts[1] if len(parts) >= 2 and (ROOT / "cfd" / parts[1]).is_dir() else "cfd"
    if parts[0] != "studies":
        return parts[0]
    if len(parts) >= 3 and parts[1] == "sections":
        return ".".join(parts[:3])
    return ".".join(parts[:2])


def documented() -> dict:
    """Group -> the groups it may import, from the marked table of docs/architecture.md."""
    text = DOC.read_text()
    block = re.search(r"<!-- architecture:.*?-->(.*?)<!-- /architecture -->", text, re.S).group(1)
    rules = {}
    for line in block.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) != 2 or not cells[0].startswith("`"):
            continue
        rules[cells[0].strip("`")] = set(re.findall(r"`([\w.]+)`", cells[1]))
    return rules


@functools.lru_cache(maxsize=1)
def actual() -> dict:
    modules = graph._sources()
    edges: dict = {}
    for module, target, _, _ in graph._imports(modules):
        owner = graph._owner(target, modules)
        if owner is None or module.startswith("bench") or owner.startswith("bench"):
            continue
        a, b = group(module), group(owner)
        if a.split(".")[0] != b.split(".")[0]:  # across packages: the package as a whole
            b = b.split(".")[0]
        edges.setdefault(a, set())
        if a != b:
            edges[a].add(b)
    return edges


def test_the_documented_table_is_read():
    rules = documented()
    assert rules["cfd"] == {"sysid", "cfd.mesh", "cfd.sweep", "cfd.ltd"} and rules["cfd.mesh"] == {"cfd"}
    assert rules["sysid"] == set() and "studies.sections.protocol" in rules


@pytest.mark.parametrize("name", sorted(actual()))
def test_every_import_is_documented(name):
    rules = documented()
    assert name in rules, f"{name} is not in the table of docs/architecture.md"
    assert actual()[name] <= rules[name], f"{name} imports {sorted(actual()[name] - rules[name])}, not in the table"


def test_every_documented_import_exists():
    edges = actual()
    for name, allowed in documented().items():
        if name not in edges:  # a planned package (loads)
            continue
        assert allowed <= edges[name], f"{name}: the table lists {sorted(allowed - edges[name])}, not imported"
