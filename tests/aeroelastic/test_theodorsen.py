"""Analytic references: Theodorsen, Sears, Jones; loads in the project's conventions."""

import numpy as np
import pytest
from scipy import special

import aeroelastic as ae
from aeroelastic import theodorsen as th
from aeroelastic import AeroModelError

K = np.array([0.05, 0.1, 0.3, 0.5, 1.0, 2.0])


def test_theodorsen_function_against_the_modified_bessel_form():
    # C(k) = K1(ik) / (K0(ik) + K1(ik)) is the same function written with modified Bessel functions
    # (an independent evaluation path in scipy); agreement to round-off of the special functions.
    C_ref = special.kv(1, 1j * K) / (special.kv(0, 1j * K) + special.kv(1, 1j * K))
    np.testing.assert_allclose(th.theodorsen_function(K), C_ref, rtol=1e-10)
    assert th.theodorsen_function([0.0])[0] == 1.0
    assert th.theodorsen_function([1e4])[0] == pytest.approx(0.5, abs=1e-4)
    assert np.all(th.theodorsen_function(K).imag < 0)


def test_sears_function_against_the_bessel_form_and_table():
    S_ref = 1.0 / (1j * K * (special.kv(0, 1j * K) + special.kv(1, 1j * K)))
    np.testing.assert_allclose(th.sears_function(K), S_ref, rtol=1e-10)
    # tabulated |S| and phase (docs/references.md section 3, 3 significant digits): k = 0.05, 0.1, 0.5, 1, 2
    k = np.array([0.05, 0.1, 0.5, 1.0, 2.0])
    S = th.sears_function(k)
    np.testing.assert_allclose(np.abs(S), [0.914, 0.837, 0.526, 0.390, 0.280], atol=1.5e-3)
    np.testing.assert_allclose(np.degrees(np.angle(S)), [-8.1, -11.3, -4.8, 18.9, 73.1], atol=0.1)
    np.testing.assert_allclose(th.sears_function(k, "leading_edge"), S * np.exp(-1j * k), rtol=1e-14)
    with pytest.raises(ValueError, match="reference must be"):
        th.sears_function(k, "trailing_edge")


def test_jones_approximations_are_within_their_known_accuracy():
    # Jones' C(k) is within about 2.5 % of Theodorsen's over k = 0.05 .. 2 (that is what the approximation is)
    rel = np.abs(th.theodorsen_jones(K) / th.theodorsen_function(K) - 1)
    assert rel.max() < 0.025
    assert th.wagner_jones(0.0) == pytest.approx(0.5)
    # Kussner psi ranges from the references: s = 1, 2, 5, 10, 20 semichords
    psi = th.kussner_jones([1, 2, 5, 10, 20])
    lo, hi = np.array([0.38, 0.54, 0.74, 0.85, 0.93]), np.array([0.42, 0.55, 0.75, 0.86, 0.96])
    assert np.all((psi >= lo - 0.01) & (psi <= hi + 0.01))


@pytest.mark.parametrize("fn", [th.wagner_jones, th.kussner_jones])
def test_jones_indicial_functions_are_zero_before_the_step(fn):
    # as cfd.wagner and cfd.kussner: no lift before the step (the exponentials would grow without bound)
    tau = np.array([-50.0, -1.0, -1e-12, 0.0, 1.0])
    out = fn(tau)
    assert np.array_equal(out[:3], [0.0, 0.0, 0.0])
    assert out[3] == fn(0.0) > 0.0 and out[4] > out[3]
    assert fn(-50.0) == 0.0 and np.isscalar(fn(-50.0))
    with pytest.raises(AeroModelError, match="NaN"):   # refused, as cfd.wagner and cfd.kussner do (it returned NaN)
        fn(np.nan)


HP_SECTION = dict(mu=20, a=-0.2, x_alpha=0.1, r_alpha2=0.24, omega_ratio=0.4)


@pytest.mark.parametrize("kw, match", [
    (dict(k_range=(0.0, 3.0)), "k_range must be two distinct positive finite"),
    (dict(k_range=(-1.0, 3.0)), "k_range must be two distinct positive finite"),
    (dict(k_range=(0.02, np.inf)), "k_range must be two distinct positive finite"),
    (dict(k_range=(1.0, 1.0)), "k_range must be two distinct positive finite"),
    (dict(k_range=3.0), "k_range must be two distinct positive finite"),
    (dict(n_k=2.5), "n_k must be a whole number >= 2"),
    (dict(n_k=1), "n_k must be a whole number >= 2"),
])
def test_flutter_determinant_settings_are_checked(kw, match):
    with pytest.raises(ae.SpeedError, match=match):
        th.flutter_determinant(ae.TypicalSection(**HP_SECTION), **kw)


@pytest.mark.parametrize("call", [lambda s: th.flutter_determinant(s), lambda s: th.jones_section_model(s, 1.0)])
@pytest.mark.parametrize("section", [None, HP_SECTION])
def test_section_must_be_a_typical_section(call, section):
    with pytest.raises(ae.SectionError, match="section must be an aeroelastic.TypicalSection"):
        call(section)


@pytest.mark.parametrize("speed", ["a", None, 0.0, np.nan])
def test_jones_section_model_speed_is_checked(speed):
    with pytest.raises(ae.SpeedError, match="speed index must be positive and finite"):
        th.jones_section_model(ae.TypicalSection(**HP_SECTION), speed)


@pytest.mark.parametrize("a", [-0.5, -0.2, 0.0, 0.3])
def test_motion_loads_quasi_steady_limits(a):
    H = th.theodorsen_motion([0.0, 1e-6], a)
    np.testing.assert_allclose(H[:, :, 0], [[0, 2 * np.pi], [0, np.pi * (a + 0.5)]], atol=1e-15)
    # a plunge velocity up acts as the incidence -d(h/c)/ds: Cl_h ~ -2 pi (i omega) as omega -> 0 (C -> 1)
    assert H[0, 0, 1] / (1j * 1e-6) == pytest.approx(-2 * np.pi, rel=1e-4)
    # quasi-steady circulation is a polynomial in s = i omega: apparent mass Cl_h = -(pi/2) s^2 - 2 pi s
    w = np.array([0.3, 2.0])
    s = 1j * w
    Hq = th.theodorsen_motion(w, a, quasi_steady=True)
    np.testing.assert_allclose(Hq[0, 0], -np.pi / 2 * s**2 - 2 * np.pi * s, rtol=1e-14)


def test_frf_layout_and_errors():
    w = np.linspace(0, 3, 7)
    frf = th.theodorsen_frf(w, -0.2, gust=True)
    assert frf.inputs == ("gust", "plunge", "pitch") and frf.outputs == ("Cl", "Cm")
    np.testing.assert_allclose(frf.H[1, 0], frf.H[0, 0] * (-0.2 + 0.5) / 2)
    with pytest.raises(AeroModelError, match="infinite at omega = inf"):
        th.theodorsen_motion([0.0, np.inf], -0.2)


@pytest.mark.parametrize("k", [-1.0, np.nan, "x"])
def test_bad_reduced_frequency_is_a_speed_error(k):
    with pytest.raises(ae.SpeedError, match="reduced frequencies k"):
        th.theodorsen_function(k)
    with pytest.raises(ae.SpeedError, match="reduced frequencies k"):
        th.sears_function(k)


# --- input checks (issue 34) ---------------------------------------------------------------------------------------

@pytest.mark.parametrize("call, error, match", [
    (lambda: th.theodorsen_motion(K, -0.2, quasi_steady="no"), AeroModelError, r"quasi_steady must be True or False"),
    (lambda: th.theodorsen_motion(K, -0.2, circulation=3), AeroModelError, r"circulation must be a callable"),
    (lambda: th.theodorsen_frf(K, -0.2, gust="yes"), AeroModelError, r"gust must be True or False, got 'yes'"),
    (lambda: th.theodorsen_frf(np.ones((2, 2)), -0.2), AeroModelError, r"omega must be 1-D .*got shape \(2, 2\)"),
    (lambda: th.theodorsen_frf("fast", -0.2), AeroModelError, r"omega must be an array of real frequencies"),
    (lambda: th.jones_frf(np.ones((2, 2)), -0.2), AeroModelError, r"omega must be 1-D"),
    (lambda: th.flutter_determinant(ae.TypicalSection(20, -0.2, 0.1, 0.24, 0.4), quasi_steady="no"), AeroModelError,
     r"quasi_steady must be True or False"),
    (lambda: th.flutter_determinant(ae.TypicalSection(20, -0.2, 0.1, 0.24, 0.4), n_k=10**10), ae.SpeedError,
     r"n_k = 10000000000 grid points is more than MAX_K_POINTS = 100000"),
    (lambda: th.wagner_jones(np.nan), AeroModelError, r"tau .* contains NaN"),
    (lambda: th.kussner_jones([0.0, np.nan]), AeroModelError, r"tau .* contains NaN"),
    (lambda: th.wagner_jones("a"), AeroModelError, r"tau .* must be a number or an array of numbers"),
])
def test_bad_arguments_are_refused(call, error, match):
    with pytest.raises(error, match=match):
        call()


def test_the_limits_of_the_step_responses_stay_legal():
    # before the step 0, long after it 1 (the Jones sums tend to 1 - 0 = 1)
    assert th.wagner_jones(-np.inf) == 0.0 and th.wagner_jones(np.inf) == 1.0
    assert th.kussner_jones(-1.0) == 0.0 and th.kussner_jones(np.inf) == 1.0
