"""The lfdrom command line: every subcommand has --help, `demo` still works, study subcommands validate first."""

import subprocess
import sys
from pathlib import Path

import pytest

from studies import cli

ROOT = Path(__file__).resolve().parents[3]


@pytest.mark.parametrize("command", ["demo", "cases", "run", "report", "rom"])
def test_every_subcommand_has_help(command, capsys):
    with pytest.raises(SystemExit) as e:
        cli.main([command, "--help"])
    assert e.value.code == 0
    assert "usage: lfdrom " + command in capsys.readouterr().out


def test_top_level_help_lists_the_subcommands(capsys):
    with pytest.raises(SystemExit):
        cli.main(["--help"])
    out = capsys.readouterr().out
    for command in ("demo", "cases", "run", "report", "rom"):
        assert command in out


def test_cases_and_dry_run(capsys):
    assert cli.main(["cases"]) == 0
    out = capsys.readouterr().out
    assert "NACA0006" in out and "G6" in out
    assert cli.main(["run", str(ROOT / "studies" / "demo.toml"), "--dry-run"]) == 0
    assert "12 identifications" in capsys.readouterr().out


def test_bad_study_exit_2(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text('cases = ["T2"]\n[sweep]\norderz = [9]\n')
    assert cli.main(["run", str(bad)]) == 2
    assert "sweep.orderz: unknown key (did you mean 'orders'?)" in capsys.readouterr().err


def test_console_entry_in_a_subprocess():
    r = subprocess.run([sys.executable, "-c", "from studies.cli import main; raise SystemExit(main(['cases', "
                        "'--format', 'json']))"], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert '"G6"' in r.stdout
    r = subprocess.run([sys.executable, "-c", "from studies.cli import main; raise SystemExit(main(['rom', 'T9', "
                        "'--order', '9']))"], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert r.returncode == 2 and "not a paper case" in r.stderr


@pytest.mark.parametrize("argv", [["cases", "--format", "json"], ["run", "studies/paper.toml", "--dry-run"]])
def test_a_closed_output_pipe_ends_quietly(argv):
    # `lfdrom cases | head`: the reader is gone before anything is written; no traceback, the SIGPIPE status
    proc = subprocess.Popen([sys.executable, "-c", f"from studies.cli import main; raise SystemExit(main({argv!r}))"],
                            cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    proc.stdout.close()
    err = proc.stderr.read()
    assert proc.wait(timeout=120) == cli.EXIT_BROKEN_PIPE, err
    assert "Traceback" not in err and "BrokenPipeError" not in err


def test_dry_run_checks_the_scheduler(capsys):
    # the scheduler's form is checked with the rest before anything runs, --dry-run included (exit 2)
    assert cli.main(["run", str(ROOT / "studies" / "demo.toml"), "--scheduler", "bogus", "--dry-run"]) == 2
    assert "scheduler must be a Dask address" in capsys.readouterr().err


def test_report_on_a_store_path_that_is_a_file_says_so(tmp_path, capsys):
    store = tmp_path / "afile"
    store.write_text("not a store")
    status = cli.main(["report", str(ROOT / "studies" / "demo.toml"), "--store", str(store), "--out",
                       str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert status == 2 and "the results store cannot be read" in err and "could not be written" not in err
