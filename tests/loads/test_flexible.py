"""The flexible section for loads: Pratt's gust alleviation factor, internal loads, damping, bad input."""

import dataclasses
import warnings

import numpy as np
import pytest

import aeroelastic as ae
import loads
from aeroelastic.theodorsen import WAGNER_JONES, jones_frf

PT = loads.FlightPoint(0.2, 0.0, 2.0)


@pytest.fixture(scope="module")
def jones_aero():
    """Jones' Wagner and Kussner approximations, fitted exactly: Roger's form with Jones' own lag roots (2 b_i in
    U/c) represents Theodorsen's loads with C_Jones(k) exactly, and the gust column is rational of order 3."""
    frf = jones_frf(np.concatenate([[0.0], np.geomspace(1e-3, 20.0, 120)]), -0.5)
    model = ae.fit_motion(frf, 2, poles=[2 * b for _, b in WAGNER_JONES], optimise=False, gust_order=3)
    assert model.max_error < 1e-12 and model.gust_max_error < 1e-12
    return model


def _pratt_kg(aero, mu_g):
    """Peak load factor of a section free to plunge (a spring of 1e-4 rad/s: (omega_h t_gust)^2 ~ 1e-9), pitch held
    (2000 rad/s about the quarter chord, where the gust and circulatory lift act), in a 1-cosine gust 25 chords
    long, over the quasi-static load factor q c 2 pi (w / U) / (m g)."""
    c = PT.chord_m
    m = mu_g * PT.rho * c * c * np.pi             # 2-D: mu_g = 2 (m / c) / (rho c a), a = 2 pi
    sec = loads.FlexibleSection(aero, mass=m, a=-0.5, x_alpha=0.0, r_alpha2=0.25, omega_h=1e-4, omega_alpha=2000.0,
                                damping=0.0)
    H = 12.5 * c
    tg = loads.tuned_gust(sec, PT, outputs=["load_factor"], H_range=(H, H), outside_rule=True)
    n_qs = PT.q * c * 2 * np.pi * PT.gust_angle(H) / (m * 9.80665)
    return tg.dimensional["load_factor"] / n_qs


MU_G = [5.0, 10.0, 20.0, 50.0, 200.0]


@pytest.mark.parametrize("mu_g", MU_G)
def test_pratt_gust_alleviation_factor(jones_aero, mu_g):
    """K_g = 0.88 mu_g / (5.3 + mu_g) (Pratt, NACA TN 2964, 1953; NACA TR 1206, 1954): a fit to the calculated
    peak load factor of a wing free to plunge in a 25-chord 1-cosine gust with circulatory unsteady lift (Wagner
    and Kussner functions). With the apparent mass left out as in that calculation, within 2 % (Jones' exponentials
    approximate Theodorsen's function to 2.3 % at most, aeroelastic.theodorsen.theodorsen_jones; measured:
    1.2 % at mu_g = 5, 0.2 - 0.4 % from 10 to 200). With the apparent mass (Theodorsen's full loads) the section
    is heavier by pi rho b^2 / m = 1 / (4 mu_g): below Pratt's K_g, by 3.5 % at mu_g = 5 and 0.4 % at 200."""
    pratt = 0.88 * mu_g / (5.3 + mu_g)
    circulatory = dataclasses.replace(jones_aero, M2=np.zeros((2, 2)))
    assert _pratt_kg(circulatory, mu_g) == pytest.approx(pratt, rel=0.02)
    full = _pratt_kg(jones_aero, mu_g)
    assert pratt * (1 - 0.04) < full < pratt


def test_flexible_outputs_and_internal_loads(jones_aero):
    pt = loads.FlightPoint(0.3, 2000.0, 2.0)
    sec = loads.FlexibleSection(jones_aero, mass=400.0, a=-0.5, x_alpha=0.1, r_alpha2=0.3, omega_h=12.0,
                                omega_alpha=40.0, damping=0.02)
    tg = loads.tuned_gust(sec, pt, outputs=["plunge", "plunge_spring", "pitch_spring", "Cl", "load_factor"])
    gs = tg.system
    # spring loads are k h and k_alpha alpha in SI
    assert tg.dimensional["plunge_spring"] == pytest.approx(400.0 * 12.0**2 * tg.dimensional["plunge"], rel=1e-12)
    ip, ia = gs.index("pitch"), gs.index("pitch_spring")
    assert gs.scale[ia] / gs.scale[ip] == pytest.approx(400.0 * 1.0 * 0.3 * 40.0**2)
    assert tg.units["Cl"] == "N/m" and tg.units["load_factor"] == "g"
    # Cm of the flexible section is about its elastic axis
    assert tg.system.outputs.count("Cm") == 1


def test_damping_lowers_a_resonant_peak(jones_aero):
    pt = loads.FlightPoint(0.3, 2000.0, 2.0)
    peaks = []
    for z in (0.0, 0.02, 0.05):
        sec = loads.FlexibleSection(jones_aero, mass=30.0, a=-0.5, x_alpha=0.2, r_alpha2=0.3, omega_h=20.0,
                                    omega_alpha=50.0, damping=z)
        peaks.append(loads.tuned_gust(sec, pt, outputs=["pitch"]).peak["pitch"])
    assert peaks[0] > peaks[1] > peaks[2]


def test_bad_sections(jones_aero):
    with pytest.raises(ae.SectionError, match="mass must be a positive"):
        loads.FlexibleSection(jones_aero, mass=-1.0, a=-0.5, x_alpha=0.0, r_alpha2=0.25, omega_h=1.0, omega_alpha=2.0)
    with pytest.raises(ae.SectionError, match="behind the trailing edge"):
        loads.FlexibleSection(jones_aero, mass=1.0, a=5.0, x_alpha=0.0, r_alpha2=0.25, omega_h=1.0, omega_alpha=2.0)
    # text is refused, not parsed (as cfd.FlowCondition refuses it)
    with pytest.raises(ae.SectionError, match=r"mass must be a positive, finite number \(SI units\), got '100'"):
        loads.FlexibleSection(jones_aero, mass="100", a=-0.5, x_alpha=0.0, r_alpha2=0.25, omega_h=1.0, omega_alpha=2.0)
    with pytest.raises(ae.SectionError, match="damping must be a real number, got '0.02'"):
        loads.FlexibleSection(jones_aero, mass=1.0, a=-0.5, x_alpha=0.0, r_alpha2=0.25, omega_h=1.0, omega_alpha=2.0,
                              damping="0.02")
    no_gust = dataclasses.replace(jones_aero, gust=None)
    with pytest.raises(loads.LoadsModelError, match="no gust input"):
        loads.FlexibleSection(no_gust, mass=1.0, a=-0.5, x_alpha=0.0, r_alpha2=0.25, omega_h=1.0, omega_alpha=2.0)


@pytest.mark.parametrize("method", ["state_space", "speed_index", "typical_section"])
def test_a_point_that_is_not_a_flight_point_is_refused(jones_aero, method):
    # an AttributeError ('NoneType' object has no attribute 'chord_m') before
    sec = loads.FlexibleSection(jones_aero, mass=1.0, a=-0.5, x_alpha=0.0, r_alpha2=0.25, omega_h=1.0, omega_alpha=2.0)
    with pytest.raises(loads.FlightPointError, match=r"point must be a loads.FlightPoint.*got NoneType"):
        getattr(sec, method)(None)


def test_above_flutter_is_refused(jones_aero):
    # speed index 8.2 at M 0.6, sea level; aeroelastic.flutter puts this section's flutter at 2.49
    sec = loads.FlexibleSection(jones_aero, mass=50.0, a=-0.5, x_alpha=0.2, r_alpha2=0.3, omega_h=10.0,
                                omega_alpha=25.0, damping=0.0)
    with pytest.raises(loads.LoadsModelError, match="unstable"):
        loads.tuned_gust(sec, loads.FlightPoint(0.6, 0.0, 2.0))


def test_a_coupled_model_in_structural_time_is_refused(jones_aero):
    sec = ae.TypicalSection(mu=20, a=-0.5, x_alpha=0.1, r_alpha2=0.25, omega_ratio=0.5)
    sys = ae.coupled_model(jones_aero, sec, 1.0, gust=True)
    with pytest.raises(loads.LoadsModelError, match="loads.FlexibleSection"):
        loads.tuned_gust(sys, PT)


def test_data_about_another_axis_are_refused():
    data = jones_frf(np.linspace(0.0, 5.0, 41), -0.5)               # about the quarter chord
    with pytest.raises(ae.AeroModelError, match="to_elastic_axis"):
        loads.FlexibleSection(data, mass=100.0, a=-0.2, x_alpha=0.1, r_alpha2=0.3, omega_h=10.0, omega_alpha=30.0)
