"""The import graph of the packages: no import circle between modules, no private name taken across modules.

Reads every ``*.py`` of ``cfd``, ``sysid``, ``studies``, ``aeroelastic``, ``loads`` and ``bench`` with :mod:`ast` (imports
inside functions count too: a circle that only a late import hides is still a circle). A name is private when
it starts with one underscore (dunders such as ``__version__`` are not). Tests may use private names.
"""

import ast
from pathlib import Path

import pytest

KNOWN = ("bench.nonlinear_stall",)
"""Known exceptions (module prefixes), each to be removed with its module's next edit. ``bench.nonlinear_stall``
instruments ``cfd.unsteady._March.step`` to print the cells that hold the residual of a failed step (a diagnostic;
changing ``cfd`` would recompute every stored result): it goes when ``cfd.UnsteadyStepError`` reports those cells
itself."""

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("cfd", "sysid", "studies", "aeroelastic", "loads", "bench")


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _sources() -> dict:
    """Module name -> (path, parsed tree)."""
    out = {}
    for package in PACKAGES:
        for path in sorted((ROOT / package).rglob("*.py")):
            if "__pycache__" not in path.parts:
                out[_module_name(path)] = (path, ast.parse(path.read_text(), filename=str(path)))
    return out


def _resolve(module: str, path: Path, level: int, target) -> str:
    """The absolute dotted name of ``from <level dots><target> import ...`` written in ``module``."""
    if level == 0:
        return target or ""
    base = module.split(".") if path.name == "__init__.py" else module.split(".")[:-1]
    base = base[: len(base) - (level - 1)]
    return ".".join(base + ([target] if target else []))


def _imports(modules: dict):
    """Yield ``(module, imported module, names taken from it, line)`` for every import of our modules."""
    for module, (path, tree) in modules.items():
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                for alias in node.names:
                    yield module, alias.name, (), node.lineno
            elif isinstance(node, ast.ImportFrom):
                source = _resolve(module, path, node.level, node.module)
                plain = []
                for alias in node.names:
                    sub = f"{source}.{alias.name}"
                    if sub in modules:  # "from . import plots": the submodule itself
                        yield module, sub, (), node.lineno
                    else:
                        plain.append(alias.name)
                if plain:
                    yield module, source, tuple(plain), node.lineno


def _owner(name: str, modules: dict):
    """The module of ours that ``name`` (a dotted import target) is, or None for outside code."""
    while name and name not in modules:
        name = name.rpartition(".")[0]
    return name or None


def _module_aliases(module: str, path: Path, tree, modules: dict) -> dict:
    """Local name -> module of ours, for ``import a.b as x`` and ``from a import b`` (b a module)."""
    aliases = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.asname and alias.name in modules:
                    aliases[alias.asname] = alias.name
        elif isinstance(node, ast.ImportFrom):
            source = _resolve(module, path, node.level, node.module)
            for alias in node.names:
                if f"{source}.{alias.name}" in modules:
                    aliases[alias.asname or alias.name] = f"{source}.{alias.name}"
    return {name: full for name, full in aliases.items() if full != module}


def _private(name: str) -> bool:
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


@pytest.fixture(scope="module")
def modules():
    return _sources()


def test_no_import_circles(modules):
    graph = {m: set() for m in modules}
    for module, target, _, _ in _imports(modules):
        owner = _owner(target, modules)
        if owner is not None and owner != module:
            graph[module].add(owner)
    circles = []
    state: dict = {}

    def visit(node, stack):
        state[node] = "open"
        stack.append(node)
        for nxt in sorted(graph[node]):
            if state.get(nxt) == "open":
                circles.append(" -> ".join(stack[stack.index(nxt):] + [nxt]))
            elif nxt not in state:
                visit(nxt, stack)
        stack.pop()
        state[node] = "done"

    for node in sorted(graph):
        if node not in state:
            visit(node, [])
    assert not circles, "import circles:\n" + "\n".join(circles)


def test_no_private_names_across_modules(modules):
    bad = []
    for module, target, names, line in _imports(modules):
        owner = _owner(target, modules)
        if owner is None or owner == module:
            continue
        bad += [f"{module}:{line} takes {owner}.{n}" for n in names if _private(n)]
    for module, (path, tree) in modules.items():  # module._name on a module of ours bound to a name
        aliases = _module_aliases(module, path, tree, modules)
        for node in ast.walk(tree):
            if isinstance(node, ast.Attribute) and _private(node.attr) and isinstance(node.value, ast.Name) \
                    and node.value.id in aliases:
                bad.append(f"{module}:{node.lineno} takes {aliases[node.value.id]}.{node.attr}")
    bad = [b for b in bad if not b.startswith(KNOWN)]
    assert not bad, "private names used across modules:\n" + "\n".join(sorted(set(bad)))


@pytest.mark.parametrize("package", ["cfd", "sysid", "aeroelastic", "studies"])
def test_each_package_lists_its_public_names(package):
    """``__all__`` names exactly what the package's ``__init__`` exposes (``from cfd import *`` gets the whole
    API, and nothing is public by accident)."""
    import importlib
    import types

    module = importlib.import_module(package)
    exposed = {name for name in vars(module) if not name.startswith("_") and name != "annotations"
               and not isinstance(getattr(module, name), types.ModuleType)}
    listed = set(module.__all__)
    assert len(module.__all__) == len(listed), "a name listed twice"
    assert exposed <= listed, f"exposed but not in __all__: {sorted(exposed - listed)}"
    for name in listed:   # resolvable (studies imports its two entry points on first use)
        assert getattr(module, name) is not None


def test_loads_uses_neither_cfd_nor_studies(modules):
    """loads builds on sysid's ROMs and aeroelastic's section only: a study may use loads, not the reverse, and
    the CFD is reached through the ROMs it produced."""
    bad = [f"{m}:{line} imports {t}" for m, t, _, line in _imports(modules)
           if m.startswith("loads") and t.split(".")[0] in ("cfd", "studies")]
    assert not bad, "\n".join(bad)
