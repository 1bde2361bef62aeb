"""The case catalogue: the paper's tables, lookups, user cases and their validation, cfd gust objects."""

import dataclasses
import math

import pytest

import cfd
from studies.config.cases import (
    GUST_CASES,
    TEST_CASES,
    CaseError,
    FlowCase,
    GridSpec,
    GustCase,
    UnknownCaseError,
    case_table,
    flow_case,
    gust_case,
    to_gust,
    user_case,
)

PAPER_T = {"T1": ("0006", 0.85), "T2": ("0010", 0.735), "T3": ("0010", 0.85), "T4": ("0018", 0.25),
           "T5": ("2410", 0.25), "T6": ("2410", 0.735)}
PAPER_G = {"G1": ("one_minus_cosine", 0.5, 2.0), "G2": ("one_minus_cosine", 1.0, 2.0),
           "G3": ("one_minus_cosine", 1.0, 5.0), "G4": ("one_minus_cosine", 10.0, 5.0),
           "G5": ("one_minus_cosine", 25.0, 1.0), "G6": ("sharp_edged", None, 45.0)}


def test_paper_tables():
    assert list(TEST_CASES) == list(PAPER_T)
    for name, (code, mach) in PAPER_T.items():
        c = flow_case(name)
        assert (c.naca, c.mach, c.alpha_deg) == (code, mach, 0.0)
        assert c.grid == GridSpec(181, 60, 100, 25.0) and c.aerofoil == f"NACA{code}"
    assert list(GUST_CASES) == list(PAPER_G)
    for name, (kind, length, angle) in PAPER_G.items():
        g = gust_case(name)
        assert (g.kind, g.length, g.angle_deg) == (kind, length, angle)


def test_g6_is_the_unit_step():
    g6 = gust_case("G6")
    assert g6.amplitude == pytest.approx(1.0, abs=1e-15)
    gust = to_gust(g6, x0=-2.0)
    assert isinstance(gust, cfd.SharpEdged)
    assert gust.input([1.0, 3.0]) == pytest.approx([0.0, 1.0], abs=1e-15)


@pytest.mark.parametrize("name", ["t2", "T2", " t2 "])
def test_lookup_is_case_insensitive(name):
    assert flow_case(name) is TEST_CASES["T2"]
    assert gust_case(name.replace("2", "3").replace("t", "g").replace("T", "G")) is GUST_CASES["G3"]


@pytest.mark.parametrize("lookup,name,known", [(flow_case, "T7", "T1, T2, T3, T4, T5, T6"),
                                               (gust_case, "G0", "G1, G2, G3, G4, G5, G6"),
                                               (flow_case, 3, "T1")])
def test_unknown_names_list_the_known_ones(lookup, name, known):
    with pytest.raises(UnknownCaseError, match=known) as e:
        lookup(name)
    assert isinstance(e.value, KeyError) and isinstance(e.value, ValueError)
    assert str(e.value).startswith("unknown")  # no KeyError quoting


def test_user_case_and_default_name():
    c = user_case("naca0012", 0.5, alpha_deg=1.0, grid={"nj": 48})
    assert (c.name, c.naca, c.mach, c.alpha_deg, c.grid.nj, c.grid.ni) == ("NACA0012-M0.5-a1", "0012", 0.5, 1.0, 48, 181)
    assert user_case(12, 0.3).naca == "0012"
    assert c.with_grid(farfield=50.0).grid.farfield == 50.0
    assert c.foil().t == pytest.approx(0.12)


@pytest.mark.parametrize("kwargs,match", [
    (dict(naca="0a12", mach=0.5), "non-digit"),
    (dict(naca="0000", mach=0.5), "zero thickness"),
    (dict(naca="12345", mach=0.5), "not 4"),
    (dict(naca="0012", mach=1.0), "0.01 <= mach < 1"),
    (dict(naca="0012", mach=0.0), "0.01 <= mach < 1"),
    (dict(naca="0012", mach=0.005), "0.01 <= mach < 1"),   # the solver's floor, refused when the study is read
    (dict(naca="0012", mach="fast"), "real number"),
    (dict(naca="0012", mach=0.5, alpha_deg=math.nan), "finite"),
    (dict(naca="0012", mach=0.5, alpha_deg=math.inf), "finite"),
    (dict(naca="0012", mach=0.5, alpha_deg=95.0), "incidence"),
    (dict(naca="0012", mach=0.5, grid={"nj": 8}), "nj >= 16"),
    (dict(naca="0012", mach=0.5, grid={"ni": 180}), "wake cells"),
    (dict(naca="0012", mach=0.5, grid={"nk": 3}), "ni, nj, n_surface, farfield"),
    (dict(naca="0012", mach=0.5, name="a b"), "name"),
])
def test_user_case_validation(kwargs, match):
    with pytest.raises(CaseError, match=match):
        user_case(**kwargs)


@pytest.mark.parametrize("args,match", [
    (("g", "step", None, 1.0), "kind"),
    (("g", "sharp_edged", 1.0, 1.0), "no length"),
    (("g", "one_minus_cosine", None, 1.0), "needs a length"),
    (("g", "one_minus_cosine", -1.0, 1.0), "positive"),
    (("g", "one_minus_cosine", 1.0, 0.0), "0 < |angle_deg| < 90"),
    (("g", "one_minus_cosine", 1.0, 90.0), "0 < |angle_deg| < 90"),
])
def test_gust_validation(args, match):
    with pytest.raises(CaseError, match=match):
        GustCase(*args)


def test_to_gust_builds_the_cfd_objects():
    g = to_gust(gust_case("G4"), x0=-3.0)
    assert isinstance(g, cfd.OneMinusCosine) and (g.length, g.angle_deg, g.x0) == (10.0, 5.0, -3.0)
    assert g.amplitude == pytest.approx(math.tan(math.radians(5.0)))
    with pytest.raises(cfd.GustPositionError):
        to_gust(gust_case("G1"), x0=0.0)
    with pytest.raises(TypeError):
        to_gust("G1")


def test_frozen_and_table():
    with pytest.raises(dataclasses.FrozenInstanceError, match="cannot assign to field 'mach'"):
        TEST_CASES["T1"].mach = 0.3
    flows, gusts = case_table()
    assert [r["name"] for r in flows] == list(PAPER_T) and [r["name"] for r in gusts] == list(PAPER_G)
    assert FlowCase("x", "2410", 0.3).naca == "2410"


def test_the_study_mach_floor_is_the_solvers():
    from cfd.flow import MIN_MACH

    from studies.config.case_types import MIN_MACH as STUDY_MIN_MACH

    assert STUDY_MIN_MACH == MIN_MACH


def test_the_study_step_limit_is_the_ltds():
    from cfd.ltd import MAX_STEPS

    from studies.config.schema import MAX_STEPS as STUDY_MAX_STEPS

    assert STUDY_MAX_STEPS == MAX_STEPS
