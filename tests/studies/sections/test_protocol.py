"""The section protocol: a section defined and registered here, in a test module, is parsed by parse_study,
planned and run by run_study, read back by load_results (cached: a second run computes nothing) and reported by
make_report, none of which names it; the built-in sections are found through the same registry."""

import ast
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest
from tinystudy import STUDY, copy_study

from studies.config import StudyConfigError, loads_study
from studies.config.reader import did_you_mean
from studies.report import make_report
from studies.run.compute import compute_piece, piece_report, pinned_store
from studies.run.runner import auto_workers, run_study
from studies.sections import protocol
from studies.sections.protocol import PieceKind, Plan, Section, SectionError, SectionRead, Task, step_id
from studies.store.entries import is_failed, open_store
from studies.store.results import load_results

ROOT = Path(__file__).resolve().parents[3]
TOY_KEYS = ("case", "values")


@dataclass(frozen=True)
class ToyOptions:
    case: str
    values: tuple

    def canonical(self) -> dict:
        return {"case": self.case, "values": list(self.values)}


def square_task(config, values: list, root: str, codes: dict) -> list:
    """Store ``x**2`` for each ``x`` of ``values`` (one ``toy_square`` piece each)."""
    store = pinned_store(root, codes)
    reports = []
    for x in values:
        entry, seconds = compute_piece(store, "toy_square", {"x": x},
                                       lambda x=x: ({"y": np.array([x * x])}, {"status": "ok"}))
        reports.append(piece_report("toy_square", f"toy_square {config.toy.case} {x:g}", entry, seconds))
    return reports


class ToySection(Section):
    """Squares of numbers: one piece per number, computed once the case's steady flow is stored."""

    name = "toy"
    table = "toy"
    pieces = (PieceKind("toy_square", ("studies.sections.protocol",), ("y",)),)

    def parse(self, table, error, study):
        if not isinstance(table, dict):
            raise error("toy", f"must be a table, got {table!r}")
        for key in table:
            if key not in TOY_KEYS:
                raise error(f"toy.{key}", f"unknown key{did_you_mean(key, TOY_KEYS)}")
        names = [case_sweep.case.name for case_sweep in study.cases]
        if table.get("case") not in names:  # up-front: a case of the study
            raise error("toy.case", f"{table.get('case')!r} is not a case of this study ({', '.join(names)})")
        return ToyOptions(table["case"], tuple(float(v) for v in table.get("values", ())))

    def describe(self, options) -> str:
        return f"  toy: {len(options.values)} squares"

    def width(self, config) -> int:
        return 1

    def plan(self, config, store, force):
        opts = config.toy
        todo = [x for x in opts.values if force or store.get("toy_square", {"x": x}) is None]
        if not todo:
            return Plan()
        task = Task("toy", opts.case, square_task, (config, todo, str(store.root), store.codes), None,
                    needs_ok=(step_id("steady", opts.case),), priority=70)
        return Plan(tasks=(task,), rom_pieces=len(todo))

    def read(self, config, store):
        records, missing = {}, []
        for x in config.toy.values:
            e = store.get("toy_square", {"x": x})
            if e is None or is_failed(e):
                missing.append(f"toy_square {config.toy.case} {x:g}")
            else:
                records[x] = float(e["y"][0])
        return SectionRead(records=records, missing=missing)

    def has_results(self, results):
        return bool(results.sections.get("toy"))

    def report(self, context):
        squares = context.results.sections.get("toy", {})
        rows = "".join(f"| {x:g} | {y:g} |\n" for x, y in squares.items())
        return f"## Toy section\n\n| x | x^2 |\n|---|---|\n{rows}"


TOY = '\n[toy]\ncase = "T2"\nvalues = [1.5, 3.0]\n'


@pytest.fixture
def toy():
    section = protocol.register(ToySection())
    yield section
    protocol.unregister("toy")


def test_builtin_sections_are_registered():
    names = protocol.section_names()
    assert names[:3] == ("gust_rom", "aeroelastic", "nonlinear")
    kinds = protocol.piece_kinds()
    assert list(kinds)[:8] == ["steady", "frf", "ltd", "rom", "sim", "motion_frf", "flutter", "nonlinear"]
    assert kinds["frf"].dependencies == ("cfd",)  # the CFD pieces depend on cfd alone (their keys are kept)


def test_toy_section_is_parsed_with_its_errors(toy):
    config = loads_study(STUDY + TOY)
    assert config.toy == ToyOptions("T2", (1.5, 3.0))
    assert config.section("toy") is config.toy and config.aeroelastic is None
    assert "toy" in config.canonical()  # part of the study's hash
    with pytest.raises(StudyConfigError, match=r"toy\.valuse.*did you mean 'values'"):
        loads_study(STUDY + '\n[toy]\ncase = "T2"\nvaluse = [1]\n')
    with pytest.raises(StudyConfigError, match=r"toy\.case.*'T9' is not a case of this study"):
        loads_study(STUDY + '\n[toy]\ncase = "T9"\n')
    with pytest.raises(StudyConfigError, match=r"toi.*did you mean 'toy'"):
        loads_study(STUDY + '\n[toi]\ncase = "T2"\n')


def test_unregistered_section_table_is_an_unknown_key():
    with pytest.raises(StudyConfigError, match=r"\btoy\b.*unknown key"):
        loads_study(STUDY + TOY)


def test_toy_section_is_planned_run_cached_and_reported(toy, computed, tmp_path):
    config, _, _ = computed
    config = copy_study(config, tmp_path)
    toyed = loads_study(STUDY + TOY)
    config = config.with_section("toy", toyed.toy)
    assert auto_workers(config, cpus=64) == auto_workers(loads_study(STUDY), cpus=64) + 1

    first = run_study(config, progress=False)
    assert first.run.computed == 2 and first.run.failed_pieces == 0  # the two squares, nothing of the tiny study
    assert first.sections["toy"] == {1.5: 2.25, 3.0: 9.0}
    assert first.complete

    again = run_study(config, progress=False)
    assert again.run.computed == 0  # cached
    read = load_results(config)
    assert read.sections["toy"] == {1.5: 2.25, 3.0: 9.0} and len(read.roms) == len(first.roms)
    assert open_store(config).get("toy_square", {"x": 3.0})["y"][0] == 9.0

    page = make_report(config, tmp_path / "report", figures=False)
    text = page.read_text()
    assert "## Toy section" in text and "| 3 | 9 |" in text
    assert text.index("## Toy section") > text.index("ROM")  # after the gust-ROM part


def test_a_missing_piece_of_the_toy_section_is_listed(toy, computed, tmp_path):
    config, _, _ = computed
    config = copy_study(config, tmp_path).with_section("toy", loads_study(STUDY + TOY).toy)
    results = load_results(config)
    assert results.missing == ["toy_square T2 1.5", "toy_square T2 3"]


@pytest.mark.parametrize("bad, match", [
    (object(), "must be a studies.sections.protocol.Section"),
    (type("Clash", (ToySection,), {"name": "clash"})(), r"table \[toy\] is section 'toy'"),
    (type("Kinds", (Section,), {"name": "kinds", "pieces": (PieceKind("frf", ("cfd",)),)})(),
     r"piece kind\(s\) \['frf'\] are section 'gust_rom'"),
    (type("Bad", (Section,), {"name": "no good"})(), "must be a Python identifier"),
])
def test_register_refuses_clashes(toy, bad, match):
    with pytest.raises(SectionError, match=match):
        protocol.register(bad)


CORE = ("studies/config/study.py", "studies/run/runner.py", "studies/store/results.py", "studies/report/make.py")


@pytest.mark.parametrize("path", CORE)
def test_core_stages_import_no_section(path):
    """parse_study, the runner, load_results and make_report reach the sections through the registry only."""
    tree = ast.parse((ROOT / path).read_text())
    imported = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            imported.add("." * node.level + (node.module or ""))
        elif isinstance(node, ast.Import):
            imported.update(alias.name for alias in node.names)
    named = {m for m in imported for s in ("gust_rom", "aeroelastic", "nonlinear") if f"sections.{s}" in m}
    assert not named
    source = (ROOT / path).read_text()
    assert "getattr(config, \"aeroelastic\"" not in source and "getattr(config, \"nonlinear\"" not in source
