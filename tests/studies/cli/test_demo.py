"""The identification demo runs quickly and delivers what it promises."""

import csv
import re

import numpy as np
import pytest

from studies import cli
from studies.cli.demo import gust_like_system, make_data, run_demo


def test_demo_writes_outputs_and_matches_dc(tmp_path):
    res = run_demo(tmp_path / "out", M=64, orders=(4, 6, 12), verbose=False)
    for path in (res.figure, res.table_md, res.table_csv):
        assert path.exists() and path.stat().st_size > 0
    assert res.figure.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    rows = list(csv.DictReader(res.table_csv.open()))
    assert len(rows) == 9
    dc_rows = [r for r in rows if r["variant"].startswith("dc")]
    assert dc_rows and all(float(r["dc_rel_err"]) < 1e-10 for r in dc_rows)
    assert all(r["stable"] == "True" for r in rows if r["variant"] == "dc+stable")
    # at the true order (6) the ROM is close to the truth, despite the noise
    six = [r for r in rows if r["order"] == "6" and r["variant"] == "dc+stable"][0]
    assert float(six["rms_err_truth"]) < 1e-2
    assert "| order | variant |" in res.table_md.read_text()


def test_truth_is_strictly_proper_with_the_prandtl_glauert_dc_lift():
    A, B, C, D = gust_like_system()
    dc = -C @ np.linalg.solve(A, B)
    # Kussner lags give the Prandtl-Glauert slope at DC; each mode adds its gain (0.25 + 0.15)
    assert dc[0, 0] == pytest.approx(2 * np.pi / np.sqrt(1 - 0.735**2) + 0.25 + 0.15, rel=1e-12)
    frf, H_true = make_data(M=16, noise=0.0)
    assert np.all(H_true[:, :, -1] == 0) and frf.outputs == ("Cl", "Cm") and frf.inputs == ("gust",)
    assert np.allclose(frf.H[:, :, 0].real, dc)


def test_cli_demo_and_help(tmp_path, capsys):
    assert cli.main(["demo", "--out", str(tmp_path / "d"), "--M", "32", "--orders", "4", "--quiet"]) == 0
    assert (tmp_path / "d" / "frf.png").exists()
    with pytest.raises(SystemExit) as e:
        cli.main(["--help"])
    assert e.value.code == 0
    assert "demo" in capsys.readouterr().out
    assert cli.main([]) == 2


def test_demo_says_which_roms_are_unstable(tmp_path, capsys):
    # the demo shows the paper's plain fit beside the constrained ones: an unstable row says so in words
    res = run_demo(tmp_path / "out", M=64, orders=(4, 12), verbose=True)
    lines = [line for line in capsys.readouterr().out.splitlines() if " rho " in line]
    assert len(lines) == len(res.rows)
    for row, line in zip(res.rows, lines):
        assert ("UNSTABLE" in line) == (not row["stable"])


@pytest.mark.parametrize("argv, code, match", [
    # each was a traceback and exit 1 (or, --noise -1, accepted)
    (["--M", "0"], 2, "--M: 0 grid intervals"),
    (["--M", "3"], 2, r"--orders: \[4, 6, 40\] outside 1 .. 2"),
    (["--orders", "0"], 2, r"--orders: \[0\] outside"),
    (["--noise", "nan"], 2, "--noise: nan"),
    (["--noise", "-1"], 2, "--noise: -1.0"),
    (["--seed", "-1"], 2, "--seed: -1"),
    (["--out", "/proc/forbidden/demo"], 4, "cannot write the demo output folder"),
])
def test_cli_demo_refuses_bad_options_before_computing(argv, code, match, capsys, monkeypatch):
    import studies.cli.demo as demo

    monkeypatch.setattr(demo, "run_demo", lambda *a, **k: pytest.fail("computed despite bad options"))
    assert cli.main(["demo", "--quiet"] + argv) == code
    assert re.search(match, capsys.readouterr().err)
