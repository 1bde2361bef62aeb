"""FlightPoint: the ICAO atmosphere, airspeeds, the rule's gust velocities, F_g, bad input."""

import math

import numpy as np
import pytest

import loads
from loads.atmosphere import FT


def test_standard_atmosphere_values():
    # ICAO standard atmosphere tables (ISO 2533): sea level 1.2250 kg/m^3, 340.29 m/s; 11 000 m 0.36392 kg/m^3,
    # 295.07 m/s (tabulated to 5 digits, hence rel 1e-4)
    sl = loads.FlightPoint(0.3, 0.0, 1.0)
    assert sl.rho == pytest.approx(1.2250, rel=1e-4) and sl.speed_of_sound == pytest.approx(340.29, rel=1e-4)
    tp = loads.FlightPoint(0.8, 11000.0, 1.0)
    assert tp.rho == pytest.approx(0.36392, rel=1e-4) and tp.speed_of_sound == pytest.approx(295.07, rel=1e-4)
    assert tp.tas == pytest.approx(0.8 * tp.speed_of_sound)
    assert tp.eas == pytest.approx(tp.tas * math.sqrt(tp.rho / 1.225))
    assert tp.q == pytest.approx(0.5 * tp.rho * tp.tas**2)
    assert loads.FlightPoint(0.5, 3000.0, 2.0).time_scale == pytest.approx(2.0 / (0.5 * 328.58), rel=1e-4)


@pytest.mark.parametrize("alt_ft, u_ref_ft, u_sigma_ft", [
    (0.0, 56.0, 90.0), (7500.0, 50.0, 90.0 - 11.0 * 7500 / 24000), (15000.0, 44.0, 90.0 - 11.0 * 15000 / 24000),
    (37500.0, (44.0 + 20.86) / 2, 79.0), (60000.0, 20.86, 79.0)])
def test_rule_velocities_by_altitude(alt_ft, u_ref_ft, u_sigma_ft):
    # CS-25.341(a)(5)(i) and (b)(3)(i): piecewise linear in altitude
    pt = loads.FlightPoint(0.5, alt_ft * FT, 1.0)
    assert pt.reference_gust_velocity() == pytest.approx(u_ref_ft * FT, rel=1e-12)
    assert pt.turbulence_intensity() == pytest.approx(u_sigma_ft * FT, rel=1e-12)
    vd = loads.FlightPoint(0.5, alt_ft * FT, 1.0, design_speed="VD")
    assert vd.reference_gust_velocity() == pytest.approx(0.5 * u_ref_ft * FT, rel=1e-12)


def test_design_gust_velocity_and_angle():
    pt = loads.FlightPoint(0.6, 5000.0, 3.0, F_g=0.8)
    H = np.array([30.0, 350.0]) * FT
    u_eas = pt.reference_gust_velocity() * 0.8 * (H / (350 * FT)) ** (1 / 6)
    assert np.allclose(pt.design_gust_velocity(H), u_eas * math.sqrt(1.225 / pt.rho), rtol=1e-12)
    assert np.allclose(pt.gust_angle(H), u_eas / pt.eas, rtol=1e-4)   # U_ds,EAS / V_EAS (rho_0 to 1e-4)


def test_alleviation_factor():
    # F_gz = 1 - 41000/250000, F_gm = sqrt(0.6 tan(pi 0.8 / 4)); F_g rises linearly to 1 at Z_mo
    z = 41000 * FT
    f0 = 0.5 * ((1 - 41000 / 250000) + math.sqrt(0.6 * math.tan(math.pi * 0.8 / 4)))
    assert loads.alleviation_factor(0.0, z, 0.8, 0.6) == pytest.approx(f0, rel=1e-12)
    assert loads.alleviation_factor(z / 2, z, 0.8, 0.6) == pytest.approx(0.5 * (f0 + 1), rel=1e-12)
    assert loads.alleviation_factor(z * 1.2, z, 0.8, 0.6) == 1.0


@pytest.mark.parametrize("kw, match", [
    (dict(mach=0.0), "mach must lie in"), (dict(mach=1.2), "mach must lie in"), (dict(mach="fast"), "real number"),
    (dict(altitude_m=-6000.0), "outside the ICAO"), (dict(altitude_m=90000.0), "outside the ICAO"),
    (dict(chord_m=-1.0), "chord_m must be > 0"), (dict(chord_m=float("nan")), "finite"),
    (dict(F_g=0.0), r"F_g .* \(0, 1\]"), (dict(F_g=1.5), r"\(0, 1\]"), (dict(design_speed="VB"), "design_speed"),
    # text is refused, not parsed (as cfd.FlowCondition refuses it); a bool is not a number
    (dict(mach="0.5"), r"mach must be a real number, got '0.5'"), (dict(altitude_m=b"0"), "altitude_m must be a real"),
    (dict(chord_m="2"), "chord_m must be a real number"), (dict(F_g="1"), "F_g must be a real number"),
    (dict(mach=np.True_), "mach must be a real number"),
])
def test_bad_flight_points(kw, match):
    args = dict(mach=0.5, altitude_m=1000.0, chord_m=2.0) | kw
    with pytest.raises(loads.FlightPointError, match=match):
        loads.FlightPoint(**args)


def test_above_the_rule_and_bad_alleviation_inputs():
    with pytest.raises(loads.GustError, match="60 000 ft"):
        loads.FlightPoint(0.8, 20000.0, 1.0).reference_gust_velocity()
    # 25.341(b)(3): U_sigma_ref constant from 24 000 ft "up to 60 000 ft", none above
    assert loads.FlightPoint(0.8, 18288.0, 1.0).turbulence_intensity() == pytest.approx(79 * FT, rel=1e-12)
    with pytest.raises(loads.GustError, match="U_sigma_ref is defined up to 60 000 ft"):
        loads.FlightPoint(0.8, 20000.0, 1.0).turbulence_intensity()
    # MZFW <= MLW <= MTOW: R2 > R1 is impossible (the two ratios swapped)
    with pytest.raises(loads.FlightPointError, match="must not exceed mlw_over_mtow"):
        loads.alleviation_factor(0.0, 12000.0, 0.6, 0.95)
    with pytest.raises(loads.FlightPointError, match="mlw_over_mtow"):
        loads.alleviation_factor(0.0, 10000.0, 1.3, 0.6)
    with pytest.raises(loads.FlightPointError, match="z_mo_m must be a real number, got '10000'"):
        loads.alleviation_factor(0.0, "10000", 0.9, 0.6)


def test_flight_point_of_numbers_in_any_form():
    pt = loads.FlightPoint(np.float64(0.5), np.int64(3000), 2, F_g=np.float32(0.5))
    assert pt == loads.FlightPoint(0.5, 3000.0, 2.0, F_g=0.5) and isinstance(pt.mach, float)


@pytest.mark.parametrize("H, match", [
    (-5.0, r"H_m must be finite and > 0 m \(the rule's range is 30 \.\. 350 ft, 9\.144 \.\. 106\.68 m\), got -5"),  # NaN
    (0.0, r"finite and > 0 m .*got 0"),
    (float("nan"), r"finite and > 0 m .*got nan"),
    (np.inf, r"finite and > 0 m .*got inf"),
    ([10.0, -5.0, 20.0], r"got -5\.0 \(the first of 1 bad values among 3\)"),                               # NaN
    (10 + 1j, r"H_m must be a real number of metres .*got \(10\+1j\)"),                                      # TypeError
    ("10", r"H_m must be a real number of metres .*got '10'"),                                               # parsed
    (True, r"H_m must be a real number of metres"),
])
def test_bad_gust_gradients_are_refused(H, match):
    pt = loads.FlightPoint(0.5, 3000.0, 2.0)
    with pytest.raises(loads.GustError, match=match):
        pt.design_gust_velocity(H)
    with pytest.raises(loads.GustError, match=match):
        pt.gust_angle(H)


def test_gust_gradients_outside_the_rule_are_evaluated():
    # tuned_gust(..., outside_rule=True) searches such gradients with the same formula
    pt = loads.FlightPoint(0.5, 3000.0, 2.0)
    H = np.array([1.0, 1000.0])
    assert np.allclose(pt.design_gust_velocity(H), pt.design_gust_velocity(350 * FT) * (H / (350 * FT)) ** (1 / 6),
                       rtol=1e-12)
    assert pt.design_gust_velocity(np.int64(30)).shape == () and pt.design_gust_velocity([]).shape == (0,)
