"""docs/equations.md stays true: every function and every test it names exists.

The page is a list of entries, each a ``### `` heading followed by a formula and the lines ``- Code:`` and
``- Test:``. Every ``package.module.name`` in backticks (packages cfd, sysid, studies, aeroelastic) must import
(attributes such as ``Class.method`` are looked up on the module), and every ``tests/...py::test_name`` must be a
test function defined in that file (read with ``ast``, not run). A failure names the entry.
"""

import ast
import importlib
import re
from functools import lru_cache
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "equations.md"
CODE_REF = re.compile(r"`((?:cfd|sysid|studies|aeroelastic)(?:\.[A-Za-z_]\w*)+)`")
TEST_REF = re.compile(r"`(tests/[\w/]+\.py)::(\w+)`")
#: What a ``- Code:`` line without a reference must say instead.
NO_CODE = ("not implemented", "not used")
PAPER_EQUATIONS = range(1, 34)  # Bagheri, Jones & Gaitonde (2016), Eqs. 1-33


def _entries():
    """``[(heading, [lines])]`` for every ``### `` heading of the page."""
    out = []
    for line in DOC.read_text(encoding="utf-8").splitlines():
        if line.startswith("### "):
            out.append((line[4:].strip(), []))
        elif out:
            out[-1][1].append(line)
    return out


ENTRIES = _entries()


def _field(lines, name):
    """Text of the ``- name:`` item (with its indented continuation lines), or None."""
    text = None
    for line in lines:
        if line.startswith(f"- {name}:"):
            text = line[len(name) + 3:]
        elif text is not None and line.startswith("  ") and line.strip():
            text += " " + line.strip()
        elif text is not None:
            break
    return text


def _resolve(dotted):
    """The object named by ``package.module.attr...``: the longest importable module prefix, then attributes."""
    parts = dotted.split(".")
    for i in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:i]))
        except ModuleNotFoundError as e:
            if e.name is not None and not ".".join(parts[:i]).startswith(e.name):
                raise  # a module exists but fails to import something else: a real error, not a missing name
            continue
        for attr in parts[i:]:
            obj = getattr(obj, attr)
        return obj
    raise ModuleNotFoundError(dotted)


@lru_cache(maxsize=None)
def _test_names(path):
    """Names of the test functions (module level and in classes) defined in a test file."""
    tree = ast.parse((ROOT / path).read_text(encoding="utf-8"), filename=path)
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and node.name.startswith("test"):
            names.add(node.name)
    return frozenset(names)


def test_page_has_entries_and_every_paper_equation():
    assert DOC.is_file(), "docs/equations.md is missing"
    assert len(ENTRIES) > 40, f"docs/equations.md has only {len(ENTRIES)} entries"
    numbered = set()
    for heading, _ in ENTRIES:
        m = re.match(r"Eqs?\. (\d+)(?:\s*[-,]\s*(\d+))?", heading)
        if m:
            lo = int(m.group(1))
            hi = int(m.group(2)) if m.group(2) else lo
            numbered.update(range(lo, hi + 1))
    missing = sorted(set(PAPER_EQUATIONS) - numbered)
    assert not missing, f"docs/equations.md has no entry for the paper's Eq(s). {missing}"


@pytest.mark.parametrize("heading, lines", ENTRIES, ids=[h for h, _ in ENTRIES])
def test_entry_names_existing_code_and_tests(heading, lines):
    code = _field(lines, "Code")
    test = _field(lines, "Test")
    assert code is not None, f"entry {heading!r}: no '- Code:' line"
    assert test is not None, f"entry {heading!r}: no '- Test:' line"
    refs = CODE_REF.findall(code)
    if not refs:
        assert any(s in code for s in NO_CODE), (
            f"entry {heading!r}: '- Code:' names no function (`package.module.function`) and does not say "
            f"{' or '.join(repr(s) for s in NO_CODE)}")
    else:
        assert TEST_REF.search(test), f"entry {heading!r}: '- Test:' names no `tests/...py::test_name`"
    problems = []
    for dotted in CODE_REF.findall("\n".join(lines)):
        try:
            _resolve(dotted)
        except (ImportError, AttributeError) as e:
            problems.append(f"`{dotted}` does not exist ({type(e).__name__}: {e})")
    for path, name in TEST_REF.findall("\n".join(lines)):
        if not (ROOT / path).is_file():
            problems.append(f"test file {path} does not exist")
        elif name not in _test_names(path):
            problems.append(f"{path} defines no test {name}")
    assert not problems, (f"entry {heading!r} of docs/equations.md: " + "; ".join(problems)
                          + " (update the entry where the code or the test moved)")
