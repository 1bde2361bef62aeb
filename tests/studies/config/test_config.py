"""Study files: the shipped examples, every error path (file and key named), canonical form, order limit."""

import math
import re
import warnings
from pathlib import Path

import numpy as np
import pytest

import sysid
from studies.config.cases import TEST_CASES
from studies.config import (
    T_PAPER,
    StudyConfig,
    StudyConfigError,
    canonical_json,
    load_study,
    loads_study,
    max_order,
    parse_number,
)
from studies.sections.gust_rom.pieces import frf_piece, rom_piece, sim_piece, steady_piece

STUDIES = Path(__file__).resolve().parents[3] / "studies"
BASE = 'cases = ["T2"]\n[sweep]\norders = [9]\n'

GOOD = """
name = "t"
cases = ["T2", {name = "mine", naca = "0012", mach = 0.5, alpha_deg = 1.0, grid = {nj = 48}}]
gusts = ["G3", {name = "long", kind = "one_minus_cosine", length = 2.0, angle_deg = 1.0}]
[sweep]
orders = [15, 9]
T = ["70/(2*pi)", 5]
M_base = 64
M = [64, 16]
[methods.plain]
[methods.dc]
dc_gain = "match"
stable = true
"""


def test_demo_toml():
    c = load_study(STUDIES / "demo.toml")
    assert isinstance(c, StudyConfig) and c.name == "demo"
    (t2,) = c.cases
    assert t2.case == TEST_CASES["T2"]
    assert t2.orders == (9, 15, 25) and t2.M == (32, 256) and t2.T == (pytest.approx(T_PAPER, rel=1e-11),)
    assert [g.name for g in c.gusts] == ["G3", "G6"]
    assert {m.name for m in c.methods} == {"plain", "dc_stable"}
    assert len(c.points()) == 3 * 2 * 2
    assert c.output_dir == (STUDIES.parent / "results" / "demo").resolve()


def test_paper_toml():
    c = load_study(STUDIES / "paper.toml")
    assert [cs.case.name for cs in c.cases] == ["T1", "T2", "T3", "T4", "T5", "T6"]
    assert all(cs.case == TEST_CASES[cs.case.name] for cs in c.cases)
    orders = {cs.case.name: cs.orders for cs in c.cases}
    assert orders == {"T1": (25,), "T2": (9, 25), "T3": (25,), "T4": (25,), "T5": (25, 55), "T6": (25, 35)}
    assert c.case("t2").M == (32, 256) and c.case("T5").M == (256,)
    assert any(p.case.name == "T2" and p.order == 9 and p.n_omega == 33 for p in c.points())
    assert [g.name for g in c.gusts] == [f"G{i}" for i in range(1, 7)]
    assert c.M_base == 256 and c.simulation.discretisation == "tustin" and c.simulation.scheme == "radau5"
    assert c.report.page == (STUDIES.parent / "docs" / "paper-reproduction.md").resolve() and c.report.figures
    assert c.report.prose == STUDIES / "paper-prose.toml"


def test_sweep_T_toml_shares_the_paper_store():
    c, paper = load_study(STUDIES / "sweep-T.toml"), load_study(STUDIES / "paper.toml")
    assert c.store_dir == paper.store_dir and [cs.case.name for cs in c.cases] == ["T4", "T5"]
    assert c.case("T4").T == (2.0, 4.0, pytest.approx(T_PAPER, rel=1e-11))
    # the pieces it shares with the paper study have the same keys: steady flows, LTD histories, FRF at T_PAPER
    for name in ("T4", "T5"):
        case = c.case(name).case
        assert steady_piece(case) == steady_piece(paper.case(name).case)
        assert frf_piece(case, T_PAPER, c.M_base, c.cfd) == frf_piece(case, T_PAPER, paper.M_base, paper.cfd)
    assert c.simulation == paper.simulation and c.cfd == paper.cfd


def test_report_paths_are_relative_to_the_study_file(tmp_path):
    (tmp_path / "prose.toml").write_text('summary = "x"\n')
    study = tmp_path / "s" / "study.toml"
    study.parent.mkdir()
    study.write_text(BASE + "[report]\npage = '../docs/s.md'\nprose = '../prose.toml'\nfigures = false\n")
    c = load_study(study)
    assert c.report.page == (tmp_path / "docs" / "s.md").resolve()
    assert c.report.prose == (tmp_path / "prose.toml").resolve() and c.report.figures is False
    assert c.hash() == loads_study(BASE).hash()  # where the report goes changes no result
    assert load_study(STUDIES / "demo.toml").report.page is None  # the default: <output>/report.md


def test_good_study_with_user_case():
    c = loads_study(GOOD, source="good.toml")
    mine = c.case("mine")
    assert (mine.case.naca, mine.case.mach, mine.case.alpha_deg, mine.case.grid.nj) == ("0012", 0.5, 1.0, 48)
    assert mine.orders == (9, 15) and mine.T == (5.0, pytest.approx(T_PAPER, rel=1e-11)) and mine.M == (16, 64)
    dc = [m for m in c.methods if m.name == "dc"][0]
    assert dc.identify_kwargs() == dict(dc_gain="match", stable=True, margin=1e-3, algorithm="auto", method="auto")
    assert loads_study(BASE + "[method]\nalgorithm = \"mckelvey2\"\n").methods[0].identify_kwargs()["algorithm"] == "subspace"
    w = loads_study(BASE + "[method]\nweights = 'inverse_magnitude'\n").methods[0]
    H = np.array([[[2.0, 1.0, 0.5, 0.0]]])
    np.testing.assert_allclose(w.identify_kwargs(H)["weights"], [[[0.25, 1.0, 4.0, 1 / 0.002**2]]])
    with pytest.raises(ValueError, match="needs the data"):
        w.identify_kwargs()
    assert len(c.points()) == 2 * (2 * 2 * 2 * 2)



@pytest.mark.parametrize("text,key,match", [
    # unknown keys, with a suggestion
    (BASE + "M_bse = 256\n", "sweep.M_bse", "did you mean 'M_base'"),
    ('cases = ["T2"]\n[sweep]\nN_r = [9]\n', "sweep.N_r", "did you mean 'orders'"),
    (BASE + "[simulation]\ndiscretization = 'zoh'\n", "simulation.discretization", "did you mean 'discretisation'"),
    (BASE + "[simulation]\nscheme = 'radau'\n", "simulation.scheme", "radau5"),
    (BASE + "[methods.a]\nstabel = true\n", "methods.a.stabel", "did you mean 'stable'"),
    (BASE + "[grid]\nnii = 181\n", "grid.nii", "did you mean 'ni'"),
    ('cases = [{name = "T2", ordrs = [3]}]\n[sweep]\norders = [9]\n', r"cases\[0\].ordrs", "did you mean 'orders'"),
    ('gusts = [{name = "x", kind = "sharp_edged", angle = 1.0}]\n' + BASE, r"gusts\[0\].angle", "angle_deg"),
    ('outptu = "x"\n' + BASE, "outptu", "did you mean 'output'"),
    # bad values
    ('cases = ["T2"]\n[sweep]\norders = [-3]\n', r"sweep.orders\[0\]", ">= 1"),
    ('cases = ["T2"]\n[sweep]\norders = [2.5]\n', r"sweep.orders\[0\]", "integer"),
    ('cases = ["T2"]\n[sweep]\norders = []\n', "sweep.orders", "empty"),
    (BASE + "T = [0]\n", r"sweep.T\[0\]", "positive"),
    (BASE + "T = ['-70/(2*pi)']\n", r"sweep.T\[0\]", "positive"),
    (BASE + "T = ['__import__(\"os\").getcwd()']\n", r"sweep.T\[0\]", "only numbers, pi"),
    (BASE + "T = ['1/0']\n", r"sweep.T\[0\]", "divides by zero"),
    (BASE + "M = [24]\n", r"sweep.M\[0\]", "power of two"),
    (BASE + "M_base = 64\nM = [128]\n", r"sweep.M\[0\]", "does not divide"),
    (BASE + "M_base = 100\n", "sweep.M_base", "power of two"),
    ('cases = [{name = "x", naca = "0012", mach = 1.2}]\n[sweep]\norders = [9]\n', r"cases\[0\].mach",
     "0.01 <= mach < 1"),
    ('cases = [{name = "x", naca = "0012", mach = -0.1}]\n[sweep]\norders = [9]\n', r"cases\[0\].mach",
     "0.01 <= mach"),
    ('cases = [{name = "x", naca = "0012", mach = 0.005}]\n[sweep]\norders = [9]\n', r"cases\[0\].mach",
     "0.01 <= mach < 1 .*low-Mach"),
    ('cases = [{name = "x", naca = "00x2", mach = 0.5}]\n[sweep]\norders = [9]\n', r"cases\[0\].naca", "non-digit"),
    ('cases = [{name = "x", mach = 0.5}]\n[sweep]\norders = [9]\n', r"cases\[0\].naca", "missing"),
    ('cases = [{name = "T2", mach = 0.5}]\n[sweep]\norders = [9]\n', r"cases\[0\].mach", "paper case"),
    ('cases = ["T9"]\n[sweep]\norders = [9]\n', r"cases\[0\]", "T1, T2, T3, T4, T5, T6"),
    ('cases = ["T2", "t2"]\n[sweep]\norders = [9]\n', r"cases\[1\].name", "twice"),
    ('gusts = ["G7"]\n' + BASE, r"gusts\[0\]", "G1, G2"),
    ('gusts = [{name = "G3", kind = "sharp_edged", angle_deg = 1.0}]\n' + BASE, r"gusts\[0\].name", "paper gust"),
    ('gusts = [{name = "x", kind = "sharp_edged", length = 1.0, angle_deg = 1.0}]\n' + BASE, r"gusts\[0\].length",
     "no length"),
    ('gusts = [{name = "x", kind = "bogus", angle_deg = 1.0}]\n' + BASE, r"gusts\[0\].kind", "unknown"),
    ('gusts = [{name = "x", kind = "one_minus_cosine", length = -1.0, angle_deg = 1.0}]\n' + BASE,
     r"gusts\[0\].length", "must be positive"),
    ('gusts = [{name = "x", kind = "sharp_edged", angle_deg = 0.0}]\n' + BASE, r"gusts\[0\].angle_deg", "0 < "),
    ('gusts = [{name = "my length/x", kind = "sharp_edged", angle_deg = 1.0}]\n' + BASE, r"gusts\[0\].name",
     "letters, digits"),
    ('gusts = [{name = "x", kind = "one_minus_cosine", length = 1e-9, angle_deg = 1.0}]\n' + BASE,
     r"gusts\[0\].length", "passes the aerofoil in 5e-08 time steps"),
    ('gusts = ["G3"]\n' + BASE + "[simulation]\ndt = 0.6\n", r"gusts\[0\]$", "the march would not resolve it"),
    (BASE + "[grid]\nnj = 8\n", "grid.nj", "nj >= 16"),
    (BASE + "[methods.a]\ndc_gain = 'yes'\n", "methods.a.dc_gain", "'none', 'match'"),
    (BASE + "[method]\nmargin = 1.5\n", "method.margin", r"\[0, 1\)"),
    (BASE + "[method]\nweights = 'inverse'\n", "method.weights", "inverse_magnitude"),
    (BASE + "[method]\n[methods.a]\n", "method", "not both"),
    (BASE + "[simulation]\ndt = 0\n", "simulation.dt", "positive"),
    (BASE + "[simulation]\nx0 = 0.0\n", "simulation.x0", "region of influence"),
    (BASE + "[simulation]\nt_end = 1.5\n", "simulation.t_end", "before the gust reaches"),
    (BASE + "[cfd]\noutputs = ['Cl', 'Cx']\n", r"cfd.outputs\[1\]", "'Cl', 'Cm', 'Cd'"),
    (BASE + "[report]\npages = 'a.md'\n", "report.pages", "did you mean 'page'"),
    (BASE + "[report]\npage = 'report.html'\n", "report.page", "not a Markdown file"),
    (BASE + "[report]\nprose = 'no-such-prose.toml'\n", "report.prose", "no such file"),
    (BASE + "[report]\nfigures = 'yes'\n", "report.figures", "true or false"),
    (BASE + "[report]\ntitle = ' '\n", "report.title", "must not be empty"),
    (BASE + "[report]\npaper = 1\n", "report.paper", "true or false"),
    ('[sweep]\norders = [9]\n', "cases", "missing"),
    ('cases = ["T2"]\n', "sweep.orders", "missing"),
    # impossible sweep points: order too large for N_omega (the subspace limit)
    ('cases = ["T2"]\n[sweep]\norders = [9, 32]\nM = [32]\n', "sweep.orders", "order 32 is impossible.*at most 31"),
    ('cases = [{name = "T2", orders = [9, 16]}]\n[sweep]\norders = [5]\nM = [16]\n', r"cases\[0\].orders",
     "N_omega = 17"),
    ('cases = ["T2"]\n[sweep]\norders = [21]\nM = [32]\n[method]\nalgorithm = "mckelvey2"\n', "sweep.orders",
     "at most 20"),
])
def test_errors_name_file_and_key(text, key, match):
    with pytest.raises(StudyConfigError, match=match) as e:
        loads_study(text, source="bad.toml")
    assert e.value.file == "bad.toml"
    assert str(e.value).startswith("bad.toml: ")
    import re

    assert re.fullmatch(key, e.value.key), (e.value.key, key)
    assert isinstance(e.value, ValueError)


def test_file_level_errors(tmp_path):
    with pytest.raises(StudyConfigError, match="no such study file") as e:
        load_study(tmp_path / "missing.toml")
    assert e.value.key is None
    bad = tmp_path / "bad.toml"
    bad.write_text("cases = [\n")
    with pytest.raises(StudyConfigError, match="not valid TOML") as e:
        load_study(bad)
    assert e.value.file == str(bad)


@pytest.mark.parametrize("names, advice", [
    ((), r"this folder holds none; examples: studies/demo.toml"),
    (("only.toml",), r"give the path of the \.toml study file: .*/d/only\.toml$"),
    (("a.toml", "b.toml", "notes.txt"), r"this folder holds 2: a\.toml, b\.toml\)$"),
])
def test_a_folder_given_as_the_study_file(tmp_path, capsys, names, advice):
    # it said "cannot read the study file: [Errno 21] Is a directory"
    folder = tmp_path / "d"
    folder.mkdir()
    for name in names:
        (folder / name).write_text(BASE)
    with pytest.raises(StudyConfigError, match=r"is a folder, not a study file; give the path of the \.toml") as e:
        load_study(folder)
    assert re.search(advice, str(e.value)) and e.value.key is None and e.value.file == str(folder)
    from studies.cli import main

    assert main(["run", str(folder)]) == 2
    assert re.search(advice, capsys.readouterr().err.strip())


@pytest.mark.parametrize("output, problem", [
    ('""', "is empty"), ('"  "', "is empty"), ('"/"', "'/' is the filesystem root /"),
    ('"/.."', "'/..' is the filesystem root /"),
])
def test_output_must_not_be_empty_or_the_root(tmp_path, output, problem):
    # "" wrote the results among the study files without saying so, "/" into the root
    study = tmp_path / "d" / "s.toml"
    study.parent.mkdir()
    study.write_text(f"output = {output}\n" + BASE)
    with pytest.raises(StudyConfigError, match=re.escape(problem) + r".*e\.g\. \"results/s\"") as e:
        load_study(study)
    assert e.value.key == "output"


@pytest.mark.parametrize("output, where", [("out", "d/out"), ("..", "."), ("../results/s", "results/s"),
                                           (".", "d"), ("../d", "d")])   # the study file's own folder, on purpose
def test_output_inside_beside_or_above_the_study_s_folder(tmp_path, output, where):
    study = tmp_path / "d" / "s.toml"
    study.parent.mkdir()
    study.write_text(f"output = {output!r}\n" + BASE)
    assert load_study(study).output_dir == (tmp_path / where).resolve()


@pytest.mark.parametrize("store, problem", [
    ('""', "is empty"), ('"  "', "is empty"), ('"/"', "'/' is the filesystem root /"),
    ('"/.."', "'/..' is the filesystem root /"),
])
def test_store_must_not_be_empty_or_the_root(tmp_path, store, problem):
    # "" put the cache entries among the study files without saying so, "/" into the root
    study = tmp_path / "d" / "s.toml"
    study.parent.mkdir()
    study.write_text(f"store = {store}\n" + BASE)
    with pytest.raises(StudyConfigError, match=re.escape(problem) + r".*e\.g\. \"results/store\".*leave store "
                                               r"out \(default: <output>/store\)$") as e:
        load_study(study)
    assert e.value.key == "store"


@pytest.mark.parametrize("store, where", [(None, "d/results/s/store"), ("cache", "d/cache"), ("..", "."),
                                          ("../results/store", "results/store")])
def test_store_default_inside_beside_or_above_the_study_s_folder(tmp_path, store, where):
    study = tmp_path / "d" / "s.toml"
    study.parent.mkdir()
    study.write_text((f"store = {store!r}\n" if store is not None else "") + BASE)
    assert load_study(study).store_dir == (tmp_path / where).resolve()


def test_a_store_shared_by_two_studies(tmp_path):
    (tmp_path / "d").mkdir()
    configs = []
    for stem in ("a", "b"):
        (tmp_path / "d" / f"{stem}.toml").write_text('store = "../results/store"\n' + BASE)
        configs.append(load_study(tmp_path / "d" / f"{stem}.toml"))
    assert configs[0].store_dir == configs[1].store_dir == (tmp_path / "results" / "store").resolve()
    assert configs[0].output_dir != configs[1].output_dir


def test_canonical_form_is_stable_under_reordering():
    a = loads_study(GOOD)
    b = loads_study("""
gusts = ["G3", {angle_deg = 1.0, length = 2.0, kind = "one_minus_cosine", name = "long"}]
cases = ["T2", {grid = {nj = 48}, alpha_deg = 1.0, mach = 0.5, naca = "NACA0012", name = "mine"}]
name = "t"
[methods.dc]
stable = true
dc_gain = true
[methods.plain]
[sweep]
M = [16, 64]
M_base = 64
T = [5.0, "70/2/pi"]
orders = [15, 9]
""")
    assert a.canonical_json() == b.canonical_json() and a.hash() == b.hash()
    c = loads_study(GOOD.replace("orders = [15, 9]", "orders = [15, 10]"))
    assert c.hash() != a.hash()
    assert canonical_json({"b": 1, "a": [0.1 + 0.2, -0.0]}) == '{"a":[0.3,0.0],"b":1}'


def test_piece_configs_separate_what_they_depend_on():
    c = loads_study(GOOD)
    p9, p15 = [p for p in c.points() if p.case.name == "T2" and p.M == 64 and p.T == 5.0 and p.method.name == "plain"]
    assert p9.order == 9 and p15.order == 15
    assert rom_piece(p9, c.M_base, c.cfd) != rom_piece(p15, c.M_base, c.cfd)
    assert rom_piece(p9, c.M_base, c.cfd)["frf"] == rom_piece(p15, c.M_base, c.cfd)["frf"]
    # the FRF does not depend on M (subsampled) nor the case's name
    q = [p for p in c.points() if p.case.name == "T2" and p.M == 16 and p.T == 5.0][0]
    assert rom_piece(q, c.M_base, c.cfd)["frf"] == frf_piece(p9.case, 5.0, c.M_base, c.cfd)
    assert steady_piece(p9.case) == steady_piece(TEST_CASES["T2"]) and "name" not in steady_piece(p9.case)
    assert sim_piece(p9, c.gusts[0], c.M_base, c.simulation, c.cfd)["rom"] == rom_piece(p9, c.M_base, c.cfd)


@pytest.mark.parametrize("value,expected", [(3, 3.0), (2.5, 2.5), ("70/(2*pi)", 70 / (2 * math.pi)),
                                            ("2**3 - -1", 9.0), ("tau/4", math.pi / 2), (" 1e-3 ", 1e-3)])
def test_parse_number(value, expected):
    assert parse_number(value) == pytest.approx(expected, rel=1e-15)


@pytest.mark.parametrize("value, match", [
    ("pi()", "only numbers, pi, e, tau"), ("x", "only numbers, pi, e, tau"), ("a.b", "only numbers, pi, e, tau"),
    ("[1]", "only numbers, pi, e, tau"), ("10**10**10", "overflows"), ("1 if 1 else 2", "only numbers, pi, e, tau"),
    (True, "expected a number"), (None, "expected a number"), ("", "expected a number"), ("1/0", "divides by zero"),
])
def test_parse_number_rejects(value, match):
    with pytest.raises(ValueError, match=match):
        parse_number(value)


@pytest.mark.parametrize("M", [4, 8, 16])
@pytest.mark.parametrize("algorithm", ["auto", "mckelvey2"])
def test_order_limit_is_sysid_s(M, algorithm):
    """max_order agrees with what sysid.identify actually accepts (orders up to the limit + 1)."""
    rng = np.random.default_rng(M)
    lim = max_order(M, algorithm, p=2)
    assert lim >= 1
    H = rng.standard_normal((2, 1, M + 1)) + 1j * rng.standard_normal((2, 1, M + 1))
    H[:, :, 0] = H[:, :, 0].real
    H[:, :, -1] = 0.0
    frf = sysid.FrequencyResponse(H, np.pi * np.arange(M + 1) / M, 1.0, inputs=["gust"], outputs=["Cl", "Cm"])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for n in (lim - 1, lim):
            if n >= 1:
                sysid.identify(frf, n, method=algorithm, solver="numpy")
        with pytest.raises(sysid.OrderError):
            sysid.identify(frf, lim + 1, method=algorithm, solver="numpy")
