"""The study subcommands (studies.cli.commands) through their own parser: validation first, hand-over, exit codes."""

import argparse
import json
import re
import sys
import types
from pathlib import Path

import pytest

from studies.cli import commands

STUDIES = Path(__file__).resolve().parents[3] / "studies"


def run(argv):
    p = argparse.ArgumentParser(prog="lfdrom")
    sub = p.add_subparsers(dest="command")
    commands.add_subcommands(sub)
    return commands.dispatch(p.parse_args(argv))


@pytest.fixture
def fake_modules(monkeypatch):
    """Replace studies.run.runner.run_study / studies.report.make_report by recorders of their calls."""
    import importlib

    calls = []

    def install(name, function, *, fail=False, params=None):
        def fake(config, **kw):
            calls.append((function, config, {"kw": kw, **kw}))
            if fail:
                raise RuntimeError("boom")
            return types.SimpleNamespace(roms=[], sims=[], failed=[], missing=[], run=None, config=config)

        monkeypatch.setattr(importlib.import_module(name), function, fake)

    # `lfdrom report` reads the store afterwards to say whether the study is complete: a complete one here
    monkeypatch.setattr(importlib.import_module("studies.store.results"), "load_results",
                        lambda config, **kw: types.SimpleNamespace(roms=[], sims=[], failed=[], missing=[], run=None,
                                                                   config=config))
    install.calls = calls
    return install


def test_cases_table(capsys):
    assert run(["cases"]) == 0
    out = capsys.readouterr().out
    for name in ["T1", "T6", "NACA2410", "G1", "G6", "sharp_edged", "0.735"]:
        assert name in out
    assert run(["cases", "--format", "json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert [r["name"] for r in data["gust_cases"]] == [f"G{i}" for i in range(1, 7)]
    assert run(["cases", "--format", "markdown"]) == 0
    assert "| name | aerofoil |" in capsys.readouterr().out


def test_run_dry_run(capsys):
    assert run(["run", str(STUDIES / "paper.toml"), "--dry-run"]) == 0
    out = capsys.readouterr().out
    assert "33 identifications" in out and "T5: NACA2410 M0.25" in out and "N_r [25, 55]" in out


def test_bad_study_is_rejected_before_the_runner(tmp_path, capsys, fake_modules):
    fake_modules("studies.run.runner", "run_study")
    bad = tmp_path / "bad.toml"
    bad.write_text('cases = ["T2"]\n[sweep]\norders = [40]\nM = [32]\n')
    assert run(["run", str(bad)]) == 2
    assert f"{bad}: sweep.orders: order 40 is impossible" in capsys.readouterr().err
    assert fake_modules.calls == []
    assert run(["report", str(tmp_path / "nope.toml")]) == 2
    assert "no such study file" in capsys.readouterr().err


def test_run_hands_over_with_accepted_options(tmp_path, fake_modules, capsys):
    fake_modules("studies.run.runner", "run_study")
    fake_modules("studies.report.make", "make_report", params="config, **kw")
    assert run(["run", str(STUDIES / "demo.toml"), "--out", str(tmp_path / "o"), "--quiet"]) == 0
    (name, config, kw), (rname, rconfig, rkw) = fake_modules.calls
    assert name == "run_study" and config.name == "demo"
    assert kw["output_dir"] == (tmp_path / "o").resolve() and kw["store_dir"] == (tmp_path / "o" / "store").resolve()
    # then the report, into --out (the study's own page only without --out)
    assert rname == "make_report" and rkw["kw"]["output_dir"] == (tmp_path / "o").resolve()
    assert rkw["kw"]["store_dir"] == kw["store_dir"]
    assert run(["run", str(STUDIES / "demo.toml"), "--scheduler", "tcp://x:1", "--quiet", "--no-report"]) == 0
    assert fake_modules.calls[-1][2]["scheduler"] == "tcp://x:1"
    assert [c[0] for c in fake_modules.calls] == ["run_study", "make_report", "run_study"]


def test_run_progress_option(fake_modules, tmp_path):
    fake_modules("studies.run.runner", "run_study")
    base = ["run", str(STUDIES / "demo.toml"), "--out", str(tmp_path / "o"), "--no-report"]
    for extra, expected in (([], True), (["--progress", "lines"], "lines"), (["--progress", "pieces"], "pieces"),
                            (["--progress", "bar", "--quiet"], False)):
        assert run(base + extra) == 0
        assert fake_modules.calls[-1][2]["progress"] == expected


def test_run_writes_the_study_page(fake_modules):
    fake_modules("studies.run.runner", "run_study", params="config, workers=None, **kw")
    fake_modules("studies.report.make", "make_report", params="config, **kw")
    assert run(["run", str(STUDIES / "paper.toml"), "--quiet"]) == 0
    (_, config, kw), (_, rconfig, rkw) = fake_modules.calls
    assert kw["workers"] == "auto"  # the default: the runner sizes the pool
    assert config.report.page == (STUDIES.parent / "docs" / "paper-reproduction.md").resolve()
    assert "output_dir" not in rkw["kw"] and rkw["kw"]["page"] is None  # make_report takes the study's page


def test_run_failure_writes_no_report(fake_modules, capsys):
    fake_modules("studies.run.runner", "run_study", fail=True)
    fake_modules("studies.report.make", "make_report", params="config, **kw")
    assert run(["run", str(STUDIES / "demo.toml"), "--quiet"]) == 1
    assert [c[0] for c in fake_modules.calls] == ["run_study"]
    assert "the study runner failed: RuntimeError: boom" in capsys.readouterr().err


@pytest.mark.parametrize("value, message", [("0", "give at least 1"), ("two", "a positive integer or auto")])
def test_run_bad_workers(value, message, fake_modules, capsys):
    fake_modules("studies.run.runner", "run_study")
    assert run(["run", str(STUDIES / "demo.toml"), "--workers", value, "--quiet"]) == 2
    assert message in capsys.readouterr().err and fake_modules.calls == []


def test_failures_and_report(fake_modules, capsys):
    fake_modules("studies.report.make", "make_report", fail=True)
    assert run(["report", str(STUDIES / "demo.toml"), "--quiet"]) == 1
    assert "RuntimeError: boom" in capsys.readouterr().err
    fake_modules("studies.report.make", "make_report", params="config, **kw")
    assert run(["report", str(STUDIES / "demo.toml")]) == 0
    assert fake_modules.calls[-1][2]["kw"]["progress"] is True
    assert fake_modules.calls[-1][2]["kw"]["page"] is None  # not given: the report's default page


def test_report_page_and_prose_are_handed_over(fake_modules, tmp_path):
    fake_modules("studies.report.make", "make_report", params="config, **kw")
    page, prose = tmp_path / "paper.md", tmp_path / "prose.toml"
    prose.write_text('summary = "What the study found."\n')
    assert run(["report", str(STUDIES / "demo.toml"), "--quiet", "--page", str(page), "--prose", str(prose)]) == 0
    kw = fake_modules.calls[-1][2]["kw"]
    assert kw["page"] == str(page) and kw["prose"] == str(prose)


@pytest.mark.parametrize("argv,match", [
    (["rom", "T9", "--order", "9"], "CASE: 'T9' is not a paper case"),
    (["rom", "T2", "--order", "40", "--M", "32"], "--order: order 40 is impossible"),
    (["rom", "T2", "--order", "0"], "--order: must be >= 1"),
    (["rom", "T2", "--order", "9", "--M", "48"], "--M: must be a power of two"),
    (["rom", "T2", "--order", "9", "--T", "-1"], "--T: must be positive"),
    (["rom", "T2", "--order", "9", "--naca", "0012"], "--naca: T2 is a paper case"),
    (["rom", "T2", "--order", "9", "--mach", "0.3"], "--mach: T2 is a paper case"),       # named --naca before
    (["rom", "T2", "--order", "9", "--alpha", "3"], "--alpha: T2 is a paper case"),       # ignored before (alpha 0)
    (["rom", "mine", "--naca", "0012", "--mach", "1.5", "--order", "9"], "--mach: mach = 1.5 is out of range"),
    (["rom", "mine", "--naca", "00x2", "--mach", "0.5", "--order", "9"], "--naca: .*non-digit"),
    (["rom", "mine", "--naca", "0012", "--mach", "fast", "--order", "9"], "--mach: 'fast' is not a number"),
    (["rom", "T2", "--order", "9", "--out", "/"], "--out: '/' is the filesystem root /.*e.g. \"results/rom\"$"),
    (["rom", "T2", "--order", "9", "--store", "/"],
     "--store: '/' is the filesystem root /.*e.g. \"results/store\"$"),
])
def test_rom_validation(argv, match, capsys, fake_modules):
    fake_modules("studies.run.runner", "run_study")
    assert run(argv + ["--quiet"]) == 2
    assert re.search(match, capsys.readouterr().err)
    assert fake_modules.calls == []


@pytest.mark.parametrize("command, flag, what", [("run", "--out", "output folder"), ("run", "--store", "results store"),
                                                  ("report", "--out", "report page's folder")])
def test_run_and_report_refuse_the_filesystem_root_as_out_or_store(command, flag, what, capsys, fake_modules):
    # the study file's checks refuse output = "/" and store = "/"; --out / and --store / replaced them afterwards
    # (lfdrom report only reads the store: --store / finds nothing there and says the store is incomplete)
    fake_modules("studies.run.runner", "run_study")
    assert run([command, str(STUDIES / "demo.toml"), flag, "/", "--quiet"]) == commands.EXIT_UNAVAILABLE
    assert re.search(rf"^lfdrom: error: /: the {what} would be the filesystem root; give another",
                     capsys.readouterr().err.strip())
    assert fake_modules.calls == []


def test_rom_one_point_study(tmp_path, fake_modules):
    fake_modules("studies.run.runner", "run_study")
    # the fake runner stores nothing: no ROM to export is an incomplete run (exit 3), not a success
    assert run(["rom", "mine", "--naca", "0012", "--mach", "0.5", "--order", "12", "--M", "32", "--dc-gain",
                "--stable", "--out", str(tmp_path), "--quiet"]) == commands.EXIT_INCOMPLETE
    (_, config, _), = fake_modules.calls
    (point,) = config.points()
    assert (point.case.naca, point.case.mach, point.order, point.M) == ("0012", 0.5, 12, 32)
    assert point.method.dc_gain == "match" and point.method.stable and config.gusts == ()


@pytest.mark.parametrize("out, expected", [
    ("rom-output", ("rom-output/T2_N9_M256.npz", "rom-output/T2_N9_M256.mat")),
    ("x/mine.npz", ("x/mine.npz", "x/mine.mat")),
    ("x/mine.mat", ("x/mine.npz", "x/mine.mat")),
])
def test_rom_file_names(out, expected):
    args = argparse.Namespace(out=Path(out), case="T2", order=9, M=256)
    assert commands._rom_files(args) == tuple(Path(e) for e in expected)


def test_rom_reports_a_failed_identification(tmp_path, monkeypatch, capsys):
    from studies.store.results import RomRecord

    def run_study(config, **kw):
        rec = RomRecord(case="T2", T=1.0, M=32, order=9, method="default", status="failed",
                        error="OrderError: too large")
        return types.SimpleNamespace(roms=[rec], missing=[], failed=[], config=config)

    import studies.run.runner

    monkeypatch.setattr(studies.run.runner, "run_study", run_study)
    assert run(["rom", "T2", "--order", "9", "--M", "32", "--out", str(tmp_path), "--quiet"]) == commands.EXIT_INCOMPLETE
    assert "the identification failed: OrderError: too large" in capsys.readouterr().err
    assert not list(tmp_path.glob("*.npz"))


def test_rom_defaults_to_the_stable_dc_exact_identification(tmp_path, fake_modules):
    # a newcomer's `lfdrom rom` must not get the paper's unconstrained fit (spectral radius 1.32 on a NACA0012
    # M0.5 case) without asking for it
    fake_modules("studies.run.runner", "run_study")
    run(["rom", "T2", "--order", "9", "--M", "32", "--out", str(tmp_path), "--quiet"])
    (_, config, _), = fake_modules.calls
    (point,) = config.points()
    assert point.method.dc_gain == "match" and point.method.stable
    assert point.case.grid.ni == 181   # the paper grid unless asked


@pytest.mark.parametrize("flags, dc_gain, stable", [
    (["--paper"], "none", False),
    (["--no-dc-gain", "--no-stable"], "none", False),
    (["--no-stable"], "match", False),
    (["--dc-gain", "--stable"], "match", True),
])
def test_rom_method_options(flags, dc_gain, stable, tmp_path, fake_modules):
    fake_modules("studies.run.runner", "run_study")
    run(["rom", "T2", "--order", "9", "--M", "32", "--out", str(tmp_path), "--quiet"] + flags)
    (_, config, _), = fake_modules.calls
    (point,) = config.points()
    assert (point.method.dc_gain, point.method.stable) == (dc_gain, stable)


def test_rom_coarse_grid(tmp_path, fake_modules):
    import cfd
    from studies.config.grid_spec import COARSE_GRID

    assert COARSE_GRID.kwargs() == dict(cfd.GRID_PRESETS["coarse"])   # one preset, two packages
    fake_modules("studies.run.runner", "run_study")
    run(["rom", "T2", "--order", "9", "--M", "32", "--grid", "coarse", "--out", str(tmp_path), "--quiet"])
    (_, config, _), = fake_modules.calls
    (point,) = config.points()
    assert point.case.grid == COARSE_GRID
    args = argparse.Namespace(out=tmp_path, case="T2", order=9, M=32, grid="coarse")
    assert commands._rom_files(args)[0].name == "T2_N9_M32_coarse.npz"   # never overwrites the paper grid's ROM


def _fake_rom_run(monkeypatch, metrics):
    """studies.run.runner.run_study replaced by one that 'identifies' a ROM with the given metrics."""
    import studies.run.runner
    from studies.store.results import RomRecord

    def run_study(config, **kw):
        stored = RomRecord(case="T2", T=1.0, M=32, order=2, method="default", status="ok", metrics=metrics)
        rec = types.SimpleNamespace(**{k: getattr(stored, k) for k in ("case", "T", "M", "order", "metrics", "ok")},
                                    label=stored.label, model=lambda outputs=None: None)
        return types.SimpleNamespace(roms=[rec], missing=[], failed=[], config=config)

    monkeypatch.setattr(studies.run.runner, "run_study", run_study)
    import studies.store.rom_export

    monkeypatch.setattr(studies.store.rom_export, "export_rom_npz", lambda path, model, meta: Path(path).touch())
    monkeypatch.setattr(studies.store.rom_export, "export_rom_mat", lambda path, model, meta: Path(path).touch())


@pytest.mark.parametrize("metrics, match", [
    ({"spectral_radius": 1.32, "frf_max_err_Cl": 0.01, "frf_max_err_Cm": 0.18},
     r"unstable \(spectral radius 1.32 >= 1\).*\n.*far off.*Cm 18 %"),
    ({"spectral_radius": 0.998, "frf_max_err_Cl": 0.01, "frf_max_err_Cm": 0.06}, r"far off.*Cm 6 %"),
    ({"spectral_radius": float("nan"), "frf_max_err_Cl": float("nan"), "frf_max_err_Cm": 0.01},
     r"unstable \(spectral radius nan.*\n.*far off.*Cl nan %"),
])
def test_rom_warns_about_an_unstable_or_poor_model(metrics, match, tmp_path, monkeypatch, capsys):
    # exit 0 (the ROM was asked for and written) but never without a word, even with --quiet
    _fake_rom_run(monkeypatch, metrics)
    assert run(["rom", "T2", "--order", "2", "--M", "32", "--paper", "--out", str(tmp_path), "--quiet"]) == 0
    captured = capsys.readouterr()
    assert re.search(match, captured.err)
    assert "spectral radius" in captured.out   # the summary line, printed despite --quiet


def test_rom_sound_model_is_quiet(tmp_path, monkeypatch, capsys):
    _fake_rom_run(monkeypatch, {"spectral_radius": 0.998, "frf_max_err_Cl": 0.004, "frf_max_err_Cm": 0.0103})
    assert run(["rom", "T2", "--order", "2", "--M", "32", "--out", str(tmp_path), "--quiet"]) == 0
    captured = capsys.readouterr()
    assert captured.err == "" and captured.out.startswith("wrote ")


def test_run_names_unstable_roms():
    from studies.store.results import RomRecord

    roms = [RomRecord(case="T2", T=1.0, M=32, order=25, method="paper", status="ok", metrics={"spectral_radius": 1.3}),
            RomRecord(case="T2", T=1.0, M=32, order=25, method="dc_stable", status="ok",
                      metrics={"spectral_radius": 0.99})]
    note = commands.unstable_rom_note(types.SimpleNamespace(roms=roms))
    assert note.startswith("1 of 2 ROM(s) are unstable") and "1.3)" in note
    assert commands.unstable_rom_note(types.SimpleNamespace(roms=roms[1:])) == ""
