"""``lfdrom fit``: the three file formats, recovery of known systems, --order auto, bad files and exit codes."""

import importlib.util
import re
import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.io

import sysid
from studies import cli
from studies.cli import fit
from studies.cli.fit import FitInputError, fit_data, load_data

ROOT = Path(__file__).resolve().parents[3]
EXAMPLE = ROOT / "docs" / "data" / "fit-example.csv"

# a continuous 2-output system of order 4 with known poles (U/c units): two real, one lightly damped pair
POLES = np.array([-0.26, -2.0, -0.3 + 1j * np.sqrt(8.91), -0.3 - 1j * np.sqrt(8.91)])


def known(omega):
    """(2, 1, K) response of the order-4 system at continuous omega (inf -> 0 feedthrough)."""
    w = np.asarray(omega, dtype=float)
    fin = np.isfinite(w)
    s = 1j * np.where(fin, w, 0.0)
    mode = 0.6 * s / (s**2 + 0.6 * s + 9.0)
    cl = 2 * np.pi * (0.13 / (s + 0.26) + 1.0 / (s + 2.0) + 0.03 * mode)
    cm = 2 * np.pi * (-0.0052 / (s + 0.26) + 0.06 / (s + 2.0) - 0.01 * mode)
    H = np.stack([np.where(fin, cl, 0.0), np.where(fin, cm, 0.0)])[:, None, :]
    return H


def grid_k():
    return np.concatenate([[0.0], np.logspace(-2, np.log10(5.0), 50), [np.inf]])


def write_csv(path, k, H, header="k,Cl_re,Cl_im,Cm_re,Cm_im", comments=("# input: gust",)):
    lines = list(comments) + [header]
    for j in range(k.size):
        vals = [k[j], H[0, 0, j].real, H[0, 0, j].imag, H[1, 0, j].real, H[1, 0, j].imag]
        lines.append(",".join("inf" if np.isinf(v) else repr(float(v)) for v in vals))
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.fixture
def files(tmp_path):
    k = grid_k()
    H = known(2 * k)
    csv = write_csv(tmp_path / "data.csv", k, H)
    mat = tmp_path / "data.mat"
    scipy.io.savemat(mat, {"H": H, "omega": 2 * k, "outputs": np.array(["Cl", "Cm"], dtype=object),
                           "inputs": np.array(["gust"], dtype=object)})
    npz = sysid.FrequencyResponse.from_continuous(H, 2 * k, inputs=["gust"], outputs=["Cl", "Cm"]).save(
        tmp_path / "data.npz")
    plain = tmp_path / "plain.npz"
    np.savez(plain, H_re=H.real, H_im=H.imag, k=k, T=np.float64(2.0))
    return dict(csv=csv, mat=mat, npz=npz, plain=plain, k=k, H=H)


def continuous_poles(res):
    z = np.linalg.eigvals(np.asarray(res.model.A))
    return (2.0 / res.T) * (z - 1.0) / (z + 1.0)


def match(a, b):
    a, b = np.sort_complex(np.asarray(a)), list(np.asarray(b))
    err = 0.0
    for x in a:
        j = int(np.argmin([abs(x - y) for y in b]))
        err = max(err, abs(x - b.pop(j)) / max(1.0, abs(x)))
    return err


# ------------------------------------------------------------------------------------------ formats
def test_three_formats_read_the_same_data(files):
    frfs = {name: load_data(files[name]) for name in ("csv", "mat", "npz", "plain")}
    for name, frf in frfs.items():
        assert frf.shape == (2, 1, files["k"].size), name
        assert np.allclose(frf.H, files["H"], rtol=1e-12, atol=1e-14), name
        assert np.array_equal(frf.omega, 2 * files["k"]), name
    for name in ("csv", "mat", "npz"):
        assert frfs[name].outputs == ("Cl", "Cm") and frfs[name].inputs == ("gust",), name
    assert frfs["csv"].T is None and frfs["plain"].T == 2.0 and frfs["plain"].outputs == ("y[0]", "y[1]")


def test_csv_frequency_units(tmp_path, files):
    k, H = files["k"], files["H"]
    # a column named 'freq' needs the unit: from a comment, or from the option (which wins)
    p = write_csv(tmp_path / "f.csv", k, H, header="freq,Cl_re,Cl_im,Cm_re,Cm_im", comments=("# frequency: k",))
    assert np.array_equal(load_data(p).omega, 2 * k)
    assert np.array_equal(load_data(p, freq_unit="omega").omega, k)
    # omega_d with '# T:' in the file
    T = 2.0
    wd = sysid.continuous_to_discrete(2 * k, T)
    p = write_csv(tmp_path / "d.csv", wd, H, header="omega_d,Cl_re,Cl_im,Cm_re,Cm_im", comments=("# T: 2",))
    frf = load_data(p)
    assert frf.T == 2.0 and np.allclose(frf.omega_d, wd) and np.isinf(frf.omega[-1])


# ------------------------------------------------------------------------------------------ fitting
def test_recovery_of_a_known_system(files):
    out = fit_data(load_data(files["csv"]), order=4)
    res = out.result
    assert res.order == 4 and res.spectral_radius < 1
    assert res.max_error < 1e-8 and res.dc_error < 1e-12
    assert res.enforced["dc_gain"] and res.enforced["feedthrough"] and res.enforced["stable"]
    assert match(continuous_poles(res), POLES) < 1e-7
    # the default T puts the band's geometric mean at omega_d = pi / 2
    w = 2 * files["k"][1:-1]
    assert res.T == pytest.approx(2 / np.sqrt(w.min() * w.max()))
    assert out.diagnostics.ok


def test_order_auto_picks_the_true_order_continuous_grid(files):
    out = fit_data(load_data(files["mat"]), order="auto", max_order=8)
    assert out.selection.chosen == 4 and out.result.order == 4
    assert out.selection.errors[3] < 1e-8 and out.selection.errors[2] > 1e-3


@pytest.mark.parametrize("workers", [1, 2])
def test_holdout_errors_do_not_depend_on_the_worker_processes(files, workers):
    # the orders are fitted in forked processes side by side or one after another: the same deterministic fits,
    # so the same errors to the last bit and the same order (the true order 4 of the synthetic system)
    frf = load_data(files["mat"])
    w = frf.omega[np.isfinite(frf.omega) & (frf.omega > 0)]
    frf = frf.with_T(2 / np.sqrt(w.min() * w.max()))   # lfdrom fit's default T
    dc = np.asarray(frf.dc_gain).real
    ref = fit.holdout_order(frf, max_order=6, dc_gain=dc, workers=1)
    sel = fit.holdout_order(frf, max_order=6, dc_gain=dc, workers=workers)
    np.testing.assert_array_equal(sel.errors, ref.errors)
    assert sel.chosen == ref.chosen == 4


def test_effort_reaches_the_fit_and_the_summary(files, tmp_path):
    # --effort thorough is passed to sysid.identify (the relocation's candidates) and named in summary.md; on the
    # noise-free synthetic system both efforts recover the true poles
    for effort in ("fast", "thorough"):
        out = fit_data(load_data(files["csv"]), order=4, effort=effort)
        assert out.options["effort"] == effort and out.result.algorithm == "relocation"
        assert match(continuous_poles(out.result), POLES) < 1e-7
    assert cli.main(["fit", str(files["csv"]), "--order", "4", "--effort", "thorough", "--no-figures", "--quiet",
                     "--out", str(tmp_path / "o")]) == 0
    assert "(effort thorough)" in (tmp_path / "o" / "summary.md").read_text()
    with pytest.raises(SystemExit):
        cli.main(["fit", str(files["csv"]), "--effort", "quick"])


def test_order_auto_picks_the_true_order_mckelvey_grid(tmp_path):
    sys.path.insert(0, str(ROOT / "tests" / "sysid"))
    from sysid_synth import freqresp, random_system

    A, B, C, D, _ = random_system(6, 2, 1, 5, rho=0.9)
    wd, _ = sysid.mckelvey_grid(64, 1.0)
    frf = sysid.FrequencyResponse(freqresp(A, B, C, D, np.exp(1j * wd)), wd, 1.0)
    frf.save(tmp_path / "d.npz")
    out = fit_data(load_data(tmp_path / "d.npz"), order="auto", max_order=10)
    assert out.selection.chosen == 6 and out.result.max_error < 1e-7


def test_command_line_end_to_end(files, tmp_path, capsys):
    out_dir = tmp_path / "out"
    rc = cli.main(["fit", str(files["csv"]), "--order", "4", "--out", str(out_dir)])
    assert rc == 0
    text = capsys.readouterr().out
    assert "order 4 (given)" in text and "wrote" in text
    for name in ("rom.npz", "rom.mat", "summary.md", "bode.png", "error.png", "hankel.png", "poles.png"):
        assert (out_dir / name).stat().st_size > 0, name
    from studies.store.rom_export import load_rom_npz

    model, meta = load_rom_npz(out_dir / "rom.npz")
    assert model.nstates == 4 and meta["order"] == 4 and meta["source"] == "data.csv"
    m = scipy.io.loadmat(out_dir / "rom.mat")
    assert m["A"].shape == (4, 4) and float(m["T"].squeeze()) == pytest.approx(model.dt)
    md = (out_dir / "summary.md").read_text()
    for part in ("## Data diagnostics", "## Order", "| Cl |", "spectral radius", "DC error"):
        assert part in md


def test_help(capsys):
    with pytest.raises(SystemExit) as e:
        cli.main(["fit", "--help"])
    assert e.value.code == 0
    text = capsys.readouterr().out
    for option in ("--order N|auto", "--dc-gain", "--stable", "--no-stable", "--T", "--out", "--freq-unit"):
        assert option in text


def test_command_line_options(files, tmp_path, capsys):
    rc = cli.main(["fit", str(files["npz"]), "--order", "4", "--T", "2", "--dc-gain", "none", "--no-stable",
                   "--out", str(tmp_path / "o"), "--no-figures", "--quiet"])
    assert rc == 0
    md = (tmp_path / "o" / "summary.md").read_text()
    assert "T = 2 (given)" in md and "dc_gain=none, stable=False" in md
    assert not (tmp_path / "o" / "bode.png").exists()


# ------------------------------------------------------------------------------------------ bad input
def bad_csv(tmp_path, text, name="bad.csv"):
    p = tmp_path / name
    p.write_text(text)
    return p


@pytest.mark.parametrize("text, where, what", [
    ("k,Cl_re,Cl_im\n0,1,0\n0.1,abc,0\n", "line 3", "'abc' is not a number"),
    ("# input: gust\nk,Cl_re,Cl_im\n0,1,0\n0.1,1\n", "line 4", "2 values but the header"),
    ("k,Cl_re,Cm_im\n0,1,0\n", "line 1", "Cl_im is missing"),
    ("freq,Cl_re,Cl_im\n0,1,0\n", "line 1", "'freq' is not a frequency column"),
    ("# frequency: hertz\nfreq,Cl_re,Cl_im\n0,1,0\n", "line 1", "'# frequency: hertz' is not one of"),
    ("k,Cl_re,Cl_im\n0,1,0\n0.1,1,0\n0.1,1,0\n", "line 4", "appears twice"),
    ("k,Cl_re,Cl_im\n0,1,0\n-0.1,1,0\n", "line 3", "negative frequency"),
    ("k,Cl,Cl_im\n0,1,0\n", "line 1", "NAME_re and NAME_im"),
    ("omega_d,Cl_re,Cl_im\n0,1,0\n", "line 1", "need the sampling period T"),
    ("k,Cl_re,Cl_im\n", "line 1", "a header but no data"),
    ("# T: 2\nk;Cl_re;Cl_im\n0;1;0\n", "line 2", "separate the columns with commas"),
    ("# T: fast\nk,Cl_re,Cl_im\n0,1,0\n", "line 1", "'# T: fast' is not a number"),
    ("# frequency: omega\nk,Cl_re,Cl_im\n0,1,0\n", "line 2", "named 'k' but line 1 says '# frequency: omega'"),
])
def test_bad_csv_names_the_line(tmp_path, text, where, what):
    p = bad_csv(tmp_path, text)
    with pytest.raises(FitInputError, match=rf"bad\.csv: {where}: .*{what}") as e:
        load_data(p)
    assert e.value.where == where and isinstance(e.value, ValueError)


@pytest.mark.parametrize("content, key, what", [
    ({"omega": np.arange(3.0)}, "key 'H'", "missing: found keys"),
    ({"H": np.ones(4, complex), "omega": np.arange(3.0)}, "key 'H'", "has 4 frequencies"),
    ({"H": np.ones(3, complex)}, "key 'omega'", "missing"),
    ({"H": np.ones(3, complex), "omega": np.arange(3.0), "k": np.arange(3.0)}, "key 'omega'", "ambiguous"),
    ({"H": np.ones(3, complex), "omega_d": np.arange(3.0)}, "key 'omega_d'", "need the sampling period"),
    ({"H": np.ones(3, complex), "omega": np.arange(3.0), "T": -1.0}, "key 'T'", "positive"),
    ({"H": np.ones(3, complex), "omega": np.arange(3.0), "T": np.array([1.0, 2.0])}, "key 'T'", "must be one number"),
    ({"H": np.array([1, np.nan, 1], complex), "omega": np.arange(3.0)}, "key 'H'", "NaN or inf"),
    ({"H": np.ones((2, 1, 3), complex), "omega": np.arange(3.0), "outputs": np.array(["Cl"], dtype=object)},
     "key 'outputs'", "has 1 names"),
])
@pytest.mark.parametrize("suffix", [".mat", ".npz"])
def test_bad_mat_and_npz_name_the_key(tmp_path, content, key, what, suffix):
    p = tmp_path / f"bad{suffix}"
    if suffix == ".mat":
        scipy.io.savemat(p, content)
    else:
        np.savez(p, **{k: (v if not (isinstance(v, np.ndarray) and v.dtype == object) else v.astype(str))
                       for k, v in content.items()})
    with pytest.raises(FitInputError, match=rf"bad\{suffix}: {key}: .*{what}"):
        load_data(p)


def test_bad_input_exit_code_2(tmp_path, capsys):
    p = bad_csv(tmp_path, "k,Cl_re,Cl_im\n0,1,0\n0.1,x,0\n")
    assert cli.main(["fit", str(p), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "bad.csv: line 3:" in err and "'x' is not a number" in err
    assert not (tmp_path / "o").exists()
    cases = [([str(tmp_path / "none.csv")], "no such file"),
             ([str(EXAMPLE), "--T", "-1"], "--T: must be positive"),
             ([str(EXAMPLE), "--T", "abc"], "--T: 'abc': only numbers, pi, e, tau"),
             ([str(EXAMPLE), "--order", "x"], "--order: 'x' is neither"),
             ([str(tmp_path / "data.xlsx")], "no such file")]
    for argv, msg in cases:
        assert cli.main(["fit", *argv, "--out", str(tmp_path / "o")]) == 2, argv
        assert msg in capsys.readouterr().err
    (tmp_path / "data.xlsx").write_text("x")
    assert cli.main(["fit", str(tmp_path / "data.xlsx")]) == 2
    assert "unknown suffix '.xlsx'" in capsys.readouterr().err


@pytest.mark.parametrize("argv, msg", [
    # said "no order could be fitted ... give --order N" (the order search failed at every order)
    (["--scale", "1e200"], "outside 1e-150 .. 1e+150"),
    # a DC gain 1e300 times the data's: a ROM 1.6e301 % off, exit 0, with a warning
    (["--order", "4", "--dc-gain", "1e300,1"], "times the largest |H| of the data"),
])
def test_data_or_dc_gain_out_of_scale_exit_2(tmp_path, capsys, argv, msg):
    src = EXAMPLE
    if argv[:1] == ["--scale"]:
        from studies.cli.fit_data import load_data

        frf = load_data(EXAMPLE)
        src = tmp_path / "big.npz"
        np.savez(src, H=np.asarray(frf.H) * float(argv[1]), omega=frf.omega)
        argv = []
    assert cli.main(["fit", str(src), *argv, "--no-figures", "--quiet", "--out", str(tmp_path / "o")]) == 2
    assert msg in capsys.readouterr().err


def _unreadable(tmp_path, kind):
    k = np.r_[0.0, np.geomspace(0.01, 5.0, 12)]
    good = tmp_path / "good.npz"
    np.savez(good, H=known(2 * k)[0:1], k=k)
    files = {
        "latin1.csv": ("# input: angle in \u00b0\nk,y_re,y_im\n0,1,0\n".encode("latin-1"),
                       "line 1: not readable as UTF-8"),
        "empty.npz": (b"", "not readable as a .npz file"),
        "truncated.npz": (good.read_bytes()[:100], "not readable as a .npz file"),
        "empty.mat": (b"", "not readable as a MATLAB .mat file"),
        "random.npz": (bytes(range(7, 107)), "not a .npz file"),
        "npy.npz": (b"\x93NUMPY" + good.read_bytes()[6:60], "not a .npz file"),
    }
    if kind in files:
        (tmp_path / kind).write_bytes(files[kind][0])
        return tmp_path / kind, files[kind][1]
    if kind == "objects.npz":
        np.savez(tmp_path / kind, H=known(2 * k)[0:1], k=k, outputs=np.array(["Cl"], dtype=object))
        return tmp_path / kind, "not readable as a .npz of plain arrays"
    np.savez(tmp_path / kind, H_re=np.array(["a"] * k.size), H_im=np.zeros(k.size), k=k)
    return tmp_path / kind, "key 'H_re': is not numeric"


@pytest.mark.parametrize("kind", ["latin1.csv", "empty.npz", "truncated.npz", "random.npz", "npy.npz", "empty.mat",
                                  "objects.npz", "string_re.npz"])
def test_unreadable_file_is_bad_input(tmp_path, capsys, kind):
    p, what = _unreadable(tmp_path, kind)
    with pytest.raises(FitInputError, match=rf"{p.name}: {what}"):
        load_data(p)
    assert cli.main(["fit", str(p), "--order", "2", "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert what in err and "Traceback" not in err


@pytest.mark.parametrize("text, value", [("11.14", 11.14), ("70/(2*pi)", 70 / (2 * np.pi)), (" 2 ", 2.0),
                                         ("1e1", 10.0), ("-(-3)", 3.0), ("pi/2 + 1 - 0.5", np.pi / 2 + 0.5)])
def test_T_option_arithmetic(text, value):
    assert fit._parse_T(text, "d.csv") == pytest.approx(value, rel=1e-15)


@pytest.mark.parametrize("text, what", [("9**9**9", "overflows"), ("True", "only numbers, pi, e, tau"),
                                        ("__import__('os')", "only numbers, pi, e, tau"), ("1/0", "divides by zero"),
                                        ("abs(-2)", "only numbers, pi, e, tau"), ("1j", "only numbers, pi, e, tau"),
                                        ("-2", "must be positive"), ("1e308*10", "is not finite")])
def test_T_option_rejects_anything_but_arithmetic(text, what, capsys, tmp_path):
    with pytest.raises(FitInputError, match=f"d.csv: --T: .*{what}"):
        fit._parse_T(text, "d.csv")
    assert cli.main(["fit", str(EXAMPLE), "--T", text, "--out", str(tmp_path / "o")]) == 2
    assert "--T:" in capsys.readouterr().err


def test_T_option_places_discrete_npz_saved_without_T(tmp_path, capsys):
    wd, w = sysid.mckelvey_grid(32, 1.0)
    p = tmp_path / "disc.npz"
    sysid.FrequencyResponse(known(w), wd).save(p)
    with pytest.raises(FitInputError, match=r"disc\.npz: --T: .*discrete frequencies .*give it with --T"):
        fit_data(load_data(p), order=4)
    frf = load_data(p, T=1.0)
    assert frf.T == 1.0 and np.allclose(frf.omega_d, wd)
    assert fit_data(frf, order=4, T=1.0).result.max_error < 1e-6
    assert fit_data(load_data(p), order=4, T=1.0).result.max_error < 1e-6
    assert cli.main(["fit", str(p), "--T", "1", "--order", "4", "--no-figures", "--out", str(tmp_path / "o")]) == 0
    assert cli.main(["fit", str(p), "--order", "4", "--out", str(tmp_path / "o")]) == 2
    assert "disc.npz: --T:" in capsys.readouterr().err


def test_holdout_messages_name_the_file(tmp_path):
    p = tmp_path / "two.npz"
    sysid.FrequencyResponse(np.ones((1, 1, 2), complex), np.array([0.0, np.pi]), 1.0).save(p)
    with pytest.raises(FitInputError, match=r"two\.npz: --order: too few frequencies"):
        fit_data(load_data(p), order="auto")


@pytest.mark.parametrize("order", ["auto", "2"])
def test_output_zero_everywhere_is_bad_input(tmp_path, capsys, order):
    k = grid_k()
    H = known(2 * k)
    H[1] = 0.0
    p = write_csv(tmp_path / "zero.csv", k, H)
    assert cli.main(["fit", str(p), "--order", order, "--no-figures", "--out", str(tmp_path / "o")]) == 2
    assert "zero.csv: output 'Cm' is zero at every frequency; drop it" in capsys.readouterr().err


def test_dc_match_without_dc_sample_is_bad_input(tmp_path):
    k = np.logspace(-2, 0, 30)
    p = write_csv(tmp_path / "nodc.csv", k, known(2 * k))
    with pytest.raises(FitInputError, match="--dc-gain: match needs an omega = 0 sample"):
        fit_data(load_data(p), order=4, dc_gain="match")
    out = fit_data(load_data(p), order=4)  # default: no DC constraint without the sample
    assert out.options["dc_gain"] == "none" and not out.result.enforced["dc_gain"]


def test_worked_example_file_is_what_the_script_writes(tmp_path):
    spec = importlib.util.spec_from_file_location("make_fit_example", ROOT / "bench" / "make_fit_example.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    assert mod.main(tmp_path / "ex.csv").read_text() == EXAMPLE.read_text()
    frf = load_data(EXAMPLE)
    assert frf.outputs == ("Cl", "Cm") and frf.inputs == ("gust",)
    assert np.allclose(frf.H, np.stack(mod.response(frf.omega))[:, None, :], rtol=1e-10, atol=1e-12)


def test_unwritable_output_exit_code_4_and_too_large_order_exit_code_2(files, tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    assert cli.main(["fit", str(files["csv"]), "--order", "4", "--out", str(blocker / "o")]) == 4
    assert "cannot write to" in capsys.readouterr().err
    assert cli.main(["fit", str(files["csv"]), "--order", "500", "--no-figures", "--out", str(tmp_path / "o")]) == 2
    assert "--order" in capsys.readouterr().err


def test_mimo_csv_and_order_auto(tmp_path):
    # two inputs: columns NAME/INPUT_re, NAME/INPUT_im; McMillan degree 4 (pole -1 with a rank-2 residue)
    k = np.concatenate([[0.0], np.logspace(-2, 0.5, 40)])
    s = 1j * 2 * k
    H = np.array([[1 / (s + 1), 0.5 / (s + 0.3)], [2 / (s + 2), -0.2 / (s + 1)]])
    cols = ["k"] + [f"{o}/{i}_{part}" for o in ("Cl", "Cm") for i in ("gust", "pitch") for part in ("re", "im")]
    rows = [[k[j]] + [v for o in range(2) for i in range(2) for v in (H[o, i, j].real, H[o, i, j].imag)]
            for j in range(k.size)]
    p = tmp_path / "mimo.csv"
    p.write_text("\n".join([",".join(cols)] + [",".join(repr(float(x)) for x in r) for r in rows]) + "\n")
    frf = load_data(p)
    assert frf.outputs == ("Cl", "Cm") and frf.inputs == ("gust", "pitch") and np.allclose(frf.H, H)
    out = fit_data(frf, order="auto", max_order=6)
    assert out.selection.chosen == 4 and out.result.max_error < 1e-8


def test_order_auto_skips_orders_below_what_the_data_need(files, monkeypatch):
    # an OrderError before any order fitted (e.g. fewer states than inputs) does not end the search
    real = sysid.identify

    def identify(frf, order, **kw):
        if order < 3:
            raise sysid.OrderError(f"order {order} is below the number of inputs")
        return real(frf, order, **kw)

    monkeypatch.setattr(sysid, "identify", identify)
    out = fit_data(load_data(files["csv"]), order="auto", max_order=6)
    assert np.isnan(out.selection.errors[:2]).all() and out.selection.chosen == 4


def test_data_without_a_dc_sample_say_so_instead_of_a_nan(tmp_path, capsys):
    k = np.geomspace(0.01, 5.0, 40)   # no omega = 0 sample: the DC gain is neither imposed nor checked
    csv = write_csv(tmp_path / "nodc.csv", k, known(2 * k))
    assert cli.main(["fit", str(csv), "--order", "4", "--dc-gain", "none", "--out", str(tmp_path / "o")]) == 0
    out = capsys.readouterr().out
    assert "no omega = 0 sample (DC not checked)" in out and "nan" not in out


def test_the_algorithm_can_be_chosen(files, tmp_path, capsys):
    # the paper's method on the command line: subspace, no constraints; and the default path for comparison
    out = tmp_path / "paper"
    assert cli.main(["fit", str(files["csv"]), "--order", "4", "--algorithm", "subspace", "--dc-gain", "none",
                     "--no-stable", "--out", str(out)]) == 0
    assert "algorithm subspace" in (out / "summary.md").read_text()
    assert cli.main(["fit", str(files["csv"]), "--order", "4", "--out", str(tmp_path / "default")]) == 0
    assert "algorithm relocation" in (tmp_path / "default" / "summary.md").read_text()
    with pytest.raises(SystemExit):
        cli.main(["fit", str(files["csv"]), "--algorithm", "vf"])
    assert "invalid choice: 'vf'" in capsys.readouterr().err


def test_the_fits_warnings_are_reported_with_it(tmp_path, capsys):
    # 0.3 % noise on a 12-state response fitted at order 14: identify warns of a resonance the samples cannot see
    # (tests/sysid/test_identify.py, _resonating_twelve_states); lfdrom fit prints it after the errors and writes it
    # into summary.md, not as a Python warning with a path
    from sysid_synth import noisy_resonant_system

    wd, w = sysid.mckelvey_grid(64, 1.0)
    H, _ = noisy_resonant_system(w, w[:2], seed=59, noise=0.003)
    data = sysid.FrequencyResponse(H[None, None, :], wd, 1.0).save(tmp_path / "noisy.npz")
    assert cli.main(["fit", str(data), "--order", "14", "--out", str(tmp_path / "o")]) == 0
    captured = capsys.readouterr()
    assert "warning: the order-14 model has a resonance at omega = 1.0" in captured.out   # 1.098 (2026-12-04)
    assert "RuntimeWarning" not in captured.err
    summary = (tmp_path / "o" / "summary.md").read_text()
    assert "**Warnings of the fit**" in summary and "invisible at the samples" in summary


# ------------------------------------------------------------------------------------------ the user's files
def _foreign(path):
    """A file of a name lfdrom fit writes, made by another program (valid of its kind, without the marker)."""
    if path.suffix == ".md":
        path.write_text("# my notes\n\nnot written by lfdrom\n")
    elif path.suffix == ".npz":
        np.savez(path, A=np.eye(2), metadata=np.array('{"generator": "my script"}'))
    elif path.suffix == ".mat":
        scipy.io.savemat(path, {"A": np.eye(2)})
    else:
        import matplotlib.pyplot as plt

        fig = plt.figure(figsize=(1, 1))
        fig.savefig(path)
        plt.close(fig)
    return path.read_bytes()


@pytest.mark.parametrize("name", fit.FIT_FILES)
def test_fit_refuses_to_replace_a_users_file(files, tmp_path, capsys, name):
    out_dir = tmp_path / "mine"
    out_dir.mkdir()
    before = _foreign(out_dir / name)
    rc = cli.main(["fit", str(files["csv"]), "--order", "4", "--out", str(out_dir)])
    assert rc == 2
    err = capsys.readouterr().err
    assert f"holds {name}, not written by lfdrom fit" in err and "give another --out" in err
    assert (out_dir / name).read_bytes() == before
    assert sorted(p.name for p in out_dir.iterdir()) == [name]   # refused before anything was written


def test_fit_refuses_an_out_folder_that_holds_its_input(files, tmp_path, capsys):
    data = tmp_path / "d" / "rom.npz"   # the user's data, named as the fit's ROM
    data.parent.mkdir()
    before = files["npz"].read_bytes()
    data.write_bytes(before)
    assert cli.main(["fit", str(data), "--order", "4", "--out", str(data.parent)]) == 2
    assert "holds the input rom.npz" in capsys.readouterr().err
    assert data.read_bytes() == before and sorted(p.name for p in data.parent.iterdir()) == ["rom.npz"]
    csv = data.parent / "data.csv"   # any input in the folder, even one no fit file would overwrite
    csv.write_bytes(files["csv"].read_bytes())
    assert cli.main(["fit", str(csv), "--order", "4", "--out", str(data.parent)]) == 2


def test_fit_replaces_its_own_files_and_only_them(files, tmp_path, capsys):
    out_dir = tmp_path / "o"
    assert cli.main(["fit", str(files["csv"]), "--order", "4", "--out", str(out_dir)]) == 0
    assert all(fit.written_by_fit(out_dir / name) for name in fit.FIT_FILES)
    assert (out_dir / "summary.md").read_text().startswith("<!-- generated by lfdrom fit from data.csv")
    (out_dir / "notes.txt").write_text("mine")
    assert cli.main(["fit", str(files["mat"]), "--order", "3", "--out", str(out_dir), "--no-figures"]) == 0
    # again into the same folder: the ROM and summary replaced, the earlier figures (another model) removed
    assert "order 3, given" in (out_dir / "summary.md").read_text()
    assert sorted(p.name for p in out_dir.iterdir()) == ["notes.txt", "rom.mat", "rom.npz", "summary.md"]
    for name in ("rom.npz", "rom.mat"):   # a ROM file edited by its user is no longer ours
        _foreign(out_dir / name)
        assert not fit.written_by_fit(out_dir / name)


# ------------------------------------------------------------------------------------------ options refused
@pytest.mark.parametrize("T, side", [("1e-300", "far above"), ("1e-13", "far above"), ("1e300", "far below")])
def test_a_period_far_outside_the_data_is_refused(files, tmp_path, capsys, T, side):
    """T = 1e-300 gave exit 0, a model 99 % off, 'KK residual nan ... ok' and numpy warnings with source lines;
    it is refused as `lfdrom run` refuses such a T (the data's band, k from 0.01 to 5 here: omega 0.02 - 10)."""
    rc = cli.main(["fit", str(files["csv"]), "--T", T, "--order", "4", "--out", str(tmp_path / "o")])
    captured = capsys.readouterr()
    assert rc == 2 and f"--T: T = {float(T):.6g} puts the bilinear map's centre frequency" in captured.err
    assert side in captured.err and "use 0.02 <= T <= 1000" in captured.err
    assert "Warning" not in captured.err + captured.out and ".py:" not in captured.err
    assert not (tmp_path / "o").exists()
    with pytest.raises(FitInputError, match="far "):
        fit_data(load_data(files["csv"]), order=4, T=float(T))


def test_the_band_limits_of_T_are_accepted(files, tmp_path, capsys):
    for T in (0.02, 1000.0):   # 2/T = 10 x the top frequency and 1/10 of the lowest positive one
        assert fit_data(load_data(files["csv"]), order=4, T=T).result.order == 4
        # whatever the diagnostics and the fit warn about is printed as 'warning:' lines, never with a source line
        rc = cli.main(["fit", str(files["csv"]), "--T", str(T), "--order", "4", "--out", str(tmp_path / f"o{T}"),
                       "--no-figures"])
        captured = capsys.readouterr()
        assert rc == 0 and ".py:" not in captured.err + captured.out and "Warning:" not in captured.err


def test_an_empty_input_name_is_refused(files, tmp_path, capsys):
    assert cli.main(["fit", str(files["csv"]), "--input", "", "--out", str(tmp_path / "o")]) == 2
    assert "--input: '' is empty" in capsys.readouterr().err


# ------------------------------------------------------------------------------------------ anyone's data
def _resonator_csv(path, dc=False):
    """S21 of a two-mode resonator measured from 75 to 110 GHz (no omega = 0 or inf sample), in Hz."""
    f = np.linspace(75e9, 110e9, 81)
    s = 2j * np.pi * f
    poles = 2 * np.pi * np.array([-1.5e9 + 92e9j, -3e9 + 101e9j])
    res = 2 * np.pi * np.array([1e9, 0.6e9])
    H = sum(r / (s - p) + r / (s - np.conj(p)) for r, p in zip(res, poles))
    lines = ["# frequency: Hz", "f,S21_re,S21_im"] + [f"{float(a)!r},{float(h.real)!r},{float(h.imag)!r}"
                                                        for a, h in zip(f, H)]
    path.write_text("\n".join(lines) + "\n")
    return path, poles


def test_data_in_hz_are_shown_in_hz(tmp_path, capsys):
    """Non-aerofoil data: the axes and the summary say GHz, not 'reduced frequency k' with one tick '3e+11'; the
    order rule does not claim omega = 0 and inf samples the data do not have."""
    from studies.cli import fit_plots

    csv, poles = _resonator_csv(tmp_path / "s21.csv")
    frf = load_data(csv)
    assert frf.omega[0] == pytest.approx(2 * np.pi * 75e9)
    out = fit_data(frf, order="auto", max_order=8)
    assert out.result.order == 4 and match(continuous_poles(out.result), np.r_[poles, poles.conj()]) < 1e-6
    assert "(even-indexed)" in out.selection.rule and "omega = 0" not in out.selection.rule
    fig = fit_plots.bode_figure(out)
    ax = fig.axes[1]
    assert ax.get_xlabel() == "frequency f [GHz]" and 70 < ax.get_xlim()[0] < 75 and 110 < ax.get_xlim()[1] < 115
    fig.canvas.draw()
    shown = [t.get_text() for t in ax.xaxis.get_ticklabels(minor=True) + ax.xaxis.get_ticklabels() if t.get_text()]
    assert len(shown) >= 2 and all("e+" not in t for t in shown)
    md = fit.summary_markdown(out, csv)
    assert "f from 75 to 110 GHz" in md and "s in rad per s" in md
    assert fit_plots._tick_text(3e11) == r"$3\times10^{11}$" and fit_plots._tick_text(0.02) == "0.02"


def test_a_single_output_title_is_wrapped_not_clipped(files):
    from studies.cli import fit_plots

    k = grid_k()
    frf = load_data(files["csv"]).take(np.arange(k.size))
    out = fit_data(frf.replace(H=frf.H[:1], outputs=["Cl"]), order=4)
    fig = fit_plots.bode_figure(out)
    title = fig._suptitle.get_text()
    assert "omega = inf sample imposed" in title.replace("\n", " ")
    assert max(len(line) for line in title.split("\n")) <= fig.get_figwidth() * 12


def test_a_known_dc_gain_is_imposed(tmp_path, capsys):
    k = np.geomspace(0.01, 5.0, 40)   # no omega = 0 sample; the true DC gain is known
    csv = write_csv(tmp_path / "nodc.csv", k, known(2 * k))
    dc = known(np.array([0.0]))[:, 0, 0].real
    rc = cli.main(["fit", str(csv), "--order", "4", "--dc-gain", f"{float(dc[0])!r},{float(dc[1])!r}",
                   "--out", str(tmp_path / "o")])
    assert rc == 0
    text = capsys.readouterr().out
    assert "DC gain given (--dc-gain), imposed" in text and "no omega = 0 sample: the DC gain" not in text
    from studies.store.rom_export import load_rom_npz

    model, meta = load_rom_npz(tmp_path / "o" / "rom.npz")
    z = 1.0   # omega = 0 is z = 1 in the discrete model
    H0 = (np.asarray(model.C) @ np.linalg.solve(z * np.eye(model.nstates) - np.asarray(model.A), np.asarray(model.B))
          + np.asarray(model.D))[:, 0]
    np.testing.assert_allclose(H0, dc, rtol=1e-9)   # imposed as an equality: round-off of the solve
    assert meta["dc_gain"] == "given" and "(to the given DC gain)" in (tmp_path / "o" / "summary.md").read_text()
    assert cli.main(["fit", str(csv), "--dc-gain", "6.28", "--out", str(tmp_path / "p")]) == 2
    assert "1 value(s) for 2 output(s) x 1 input(s); give 2" in capsys.readouterr().err
    assert cli.main(["fit", str(csv), "--dc-gain", "six", "--out", str(tmp_path / "p")]) == 2


@pytest.mark.parametrize("option, advice", [(["--dc-gain", "none"], False), ([], True)])
def test_no_dc_warning_when_none_was_asked(tmp_path, capsys, option, advice):
    k = np.geomspace(0.01, 5.0, 40)
    csv = write_csv(tmp_path / "nodc.csv", k, known(2 * k))
    assert cli.main(["fit", str(csv), "--order", "4", *option, "--out", str(tmp_path / "o"), "--no-figures"]) == 0
    out = capsys.readouterr().out
    assert "pass the DC gain as an array" not in out
    assert ("give it with --dc-gain VALUE[,VALUE...]" in out) is advice


def test_a_poor_fit_is_warned_about_even_when_quiet(files, tmp_path, capsys):
    # order 1 for the worked example's four poles: written (exit 0), but never without a word
    assert cli.main(["fit", str(files["csv"]), "--order", "1", "--out", str(tmp_path / "o"), "--quiet",
                     "--no-figures"]) == 0
    err = capsys.readouterr().err
    assert re.search(r"lfdrom: warning: the ROM is far off its data \(max error / peak: Cl \d", err)


@pytest.mark.parametrize("radius, errors, match", [
    (1.05, [0.01], r"^the ROM is unstable \(spectral radius 1.05 >= 1\)"),
    (float("nan"), [0.01], r"^the ROM is unstable \(spectral radius nan"),
    (0.99, [0.2], r"^the ROM is far off its data \(max error / peak: Cl 20 %"),
    (0.99, [float("nan")], r"^the ROM is far off its data \(max error / peak: Cl nan %"),
])
def test_fit_result_warnings(radius, errors, match):
    import types

    from studies.cli.fit import result_warnings

    res = types.SimpleNamespace(spectral_radius=radius, errors=types.SimpleNamespace(max_rel_per_output=errors))
    (note,) = result_warnings(types.SimpleNamespace(result=res, data=types.SimpleNamespace(outputs=("Cl",))))
    assert re.search(match, note)
    res.spectral_radius, res.errors.max_rel_per_output = 0.99, [0.01]
    assert result_warnings(types.SimpleNamespace(result=res, data=types.SimpleNamespace(outputs=("Cl",)))) == []


def test_fit_and_rom_warn_at_the_same_error():
    from studies.cli.commands import ROM_ERROR_WARNING
    from studies.cli.fit import FIT_ERROR_WARNING

    assert FIT_ERROR_WARNING == ROM_ERROR_WARNING


def _small_npz(tmp_path, omega, **extra):
    """20 samples of a two-output first-order system (the audit's file) at ``omega``."""
    w = np.linspace(0, 4, 20)
    H = np.vstack([1 / (1 + 1j * w), 0.2 / (1 + 0.5j * w)])[:, None, :]
    p = tmp_path / "small.npz"
    np.savez(p, **({"H": H, "omega": omega} | extra))
    return p


@pytest.mark.parametrize("asked, note", [(None, False), (3, False), (4, False), (5, True), (100000, True)])
def test_max_order_is_capped_at_what_the_data_support(tmp_path, capsys, asked, note):
    # 10 of the 20 frequencies are fitted by the hold-out: Algorithm 2 with 2 outputs supports order 4 there;
    # 100000 used to fit every order (minutes) to reach the same choice
    p = _small_npz(tmp_path, np.linspace(0, 4, 20))
    option = [] if asked is None else ["--max-order", str(asked)]
    assert cli.main(["fit", str(p), *option, "--no-figures", "--quiet", "--out", str(tmp_path / "o")]) == 0
    err = capsys.readouterr().err
    assert ("lfdrom: note: --max-order" in err) is note
    if note:
        assert re.search(rf"--max-order {asked} is more than the data support: the hold-out fits use 10 of the 20 "
                         r"frequencies, which support orders up to 4 .*more frequencies", err)
    sel = fit_data(load_data(p), max_order=asked or 30).selection
    assert sel.supported == 4 and sel.orders.max() == min(asked or 30, 4) and sel.chosen == 2


@pytest.mark.filterwarnings("ignore:singular value .* round-off:RuntimeWarning")
def test_supported_order_is_what_identify_accepts(files):
    frf = fit_data(load_data(files["csv"]), order=4).data
    top = fit.supported_order(frf)
    sysid.identify(frf, top, dc_gain="match")
    with pytest.raises(sysid.OrderError):
        sysid.identify(frf, top + 1, dc_gain="match")


@pytest.mark.parametrize("imag, ok", [(0.0, True), (1e-3, False)])
def test_complex_H_re_is_refused(tmp_path, capsys, imag, ok):
    w = np.linspace(0, 4, 20)
    H = np.vstack([1 / (1 + 1j * w), 0.2 / (1 + 0.5j * w)])[:, None, :]
    p = tmp_path / "rc.npz"
    np.savez(p, H_re=H.real + 1j * imag, H_im=H.imag, omega=w)
    if ok:   # a complex array whose imaginary parts are all zero loses nothing
        np.testing.assert_array_equal(load_data(p).H, load_data(_small_npz(tmp_path, w)).H)
        return
    with pytest.raises(FitInputError, match=r"rc.npz: key 'H_re': is complex .* H_re and H_im must be real"):
        load_data(p)
    assert cli.main(["fit", str(p), "--order", "2", "--no-figures", "--out", str(tmp_path / "o")]) == 2
    assert "H_re and H_im must be real" in capsys.readouterr().err


@pytest.mark.parametrize("error", [sysid.FrequencyGridError, sysid.FrequencyDataError])
def test_no_default_T_is_bad_input(tmp_path, capsys, monkeypatch, error):
    # omega ~ 1e-300: omega_lo omega_hi underflows; sysid.diagnostics.default_T refuses it with a typed error
    import sysid.diagnostics

    def refuse(omega):
        raise error("no usable frequency to choose T from; give T explicitly")

    monkeypatch.setattr(sysid.diagnostics, "default_T", refuse)
    p = _small_npz(tmp_path, np.linspace(0, 4, 20) * 1e-300)
    with pytest.raises(FitInputError, match=r"small.npz: --T: no default sampling period .*give the sampling period "
                                            r"with --T .* or rescale the frequencies"):
        fit_data(load_data(p), order=2)
    assert cli.main(["fit", str(p), "--order", "2", "--no-figures", "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "--T" in err and "rescale the frequencies" in err and "failed" not in err


@pytest.mark.parametrize("error, advice", [(sysid.FrequencyGridError, True), (sysid.FrequencyDataError, False),
                                           (sysid.OptionError, False), (sysid.ConstraintError, False)])
def test_sysid_input_errors_of_the_fit_are_bad_input(tmp_path, capsys, monkeypatch, error, advice):
    def refuse(*a, **k):
        raise error("unusable")

    monkeypatch.setattr(sysid, "identify", refuse)
    p = _small_npz(tmp_path, np.linspace(0, 4, 20))
    assert cli.main(["fit", str(p), "--order", "2", "--no-figures", "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "small.npz: unusable" in err and "failed" not in err
    assert ("rescale the frequencies" in err) is advice


def test_a_solver_failure_is_a_failed_fit(tmp_path, capsys, monkeypatch):
    def fail(*a, **k):
        raise sysid.SolverError("infeasible")

    monkeypatch.setattr(sysid, "identify", fail)
    p = _small_npz(tmp_path, np.linspace(0, 4, 20))
    assert cli.main(["fit", str(p), "--order", "2", "--no-figures", "--out", str(tmp_path / "o")]) == 1
    assert "failed: SolverError: infeasible" in capsys.readouterr().err
