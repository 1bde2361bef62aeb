"""fit_motion: Roger form with exact static derivatives; gust column through sysid.identify."""

import numpy as np
import pytest
import sysid

import aeroelastic as ae
from aeroelastic import theodorsen as th

W = np.concatenate([[0.0], np.geomspace(0.01, 4.0, 100)])


@pytest.fixture(scope="module")
def theo_fit():
    return ae.fit_motion(th.theodorsen_frf(W, -0.2, gust=True), 4)


def test_theodorsen_fit_error_and_structure(theo_fit):
    m = theo_fit
    # measured 1.8e-3 (order 4); C(k) has a logarithmic branch point at k = 0 that no finite sum of poles
    # represents exactly, so the error falls with the order but never reaches round-off
    assert m.max_error < 3e-3 and m.rms_error < 1e-3
    assert m.static_exact
    np.testing.assert_array_equal(m.M0, [[0.0, 2 * np.pi], [0.0, np.pi * 0.3]])  # exact, not fitted
    assert np.all(m.poles > 0) and m.n_lags == 4
    # apparent mass (exact: Cl_h = -pi/2, Cm_a = -(pi/2)(1/8 + a^2)/4 per (d/ds)^2); the lag terms trade a little
    # with M2 over a finite band, so 1 % is what the fit can promise
    assert m.M2[0, 0] == pytest.approx(-np.pi / 2, rel=1e-2)
    assert m.M2[1, 1] == pytest.approx(-np.pi / 8 * (0.125 + 0.04), rel=1e-2)
    # gust column: 8 states through sysid.identify, measured 4e-5 of the peak
    assert m.gust_max_error < 1e-3
    assert np.all(np.linalg.eigvals(m.gust.A).real < 0)
    np.testing.assert_allclose(m.evaluate_gust([0.0])[:, 0, 0], [2 * np.pi, 2 * np.pi * 0.3 / 2], rtol=1e-8)


def test_fit_error_falls_with_order():
    # Theodorsen's C(k) is not rational: each added lag root must lower the error (measured 1.6e-2, 5.3e-3,
    # 1.8e-3, 2.2e-4), and six roots bring it below 1e-3 of the data
    errors = [ae.fit_motion(th.theodorsen_frf(W, -0.2), order).max_error for order in (2, 3, 4, 6)]
    assert np.all(np.diff(errors) < 0) and errors[-1] < 1e-3


def test_exact_models_are_recovered():
    # quasi-steady (C = 1) data are a quadratic polynomial: order 0 recovers them to round-off
    m = ae.fit_motion(th.theodorsen_frf(W, 0.1, quasi_steady=True), 0)
    assert m.max_error < 1e-12
    # Jones' approximation is exactly of Roger's form with 2 lags
    mj = ae.fit_motion(th.jones_frf(W, -0.2), 2, gust_order=3)
    assert mj.max_error < 1e-9
    np.testing.assert_allclose(mj.poles, [0.0455 * 2, 0.3 * 2], rtol=1e-6)  # semichord -> chord time


def test_lag_model_matches_evaluate(theo_fit):
    lag = theo_fit.lag_model()
    w = np.array([0.1, 1.0])
    G = np.array([np.asarray(lag(1j * x)) for x in w]).transpose(1, 2, 0)
    s = 1j * w
    poly = theo_fit.M0[:, :, None] + theo_fit.M1[:, :, None] * s + theo_fit.M2[:, :, None] * s**2
    np.testing.assert_allclose(G + poly, theo_fit.evaluate(w), rtol=1e-12)


def test_errors():
    frf = th.theodorsen_frf(W, -0.2)
    with pytest.raises(ae.AeroModelError, match="missing"):
        ae.fit_motion(frf.replace(inputs=["h", "pitch"]), 2)
    with pytest.raises(ae.AeroModelError, match="expects a sysid.FrequencyResponse"):
        ae.fit_motion(np.ones((2, 2, 5)), 2)
    disc = sysid.FrequencyResponse(np.ones((2, 2, 5)), np.linspace(0, np.pi, 5), None,
                                   inputs=["plunge", "pitch"], outputs=["Cl", "Cm"])
    with pytest.raises(ae.AeroModelError, match="no continuous frequencies"):
        ae.fit_motion(disc, 2)
    with pytest.raises(ae.FitError, match="order"):
        ae.fit_motion(frf, -1)
    with pytest.raises(ae.FitError, match="cannot determine"):
        ae.fit_motion(th.theodorsen_frf([0.0, 0.5, 1.0], -0.2), 4)
    with pytest.raises(ae.FitError, match="positive lag roots"):
        ae.fit_motion(frf, 2, poles=[0.1, -0.2])


@pytest.mark.parametrize("change, match", [
    (dict(M0=np.full((2, 2), np.nan)), "M0 contains NaN"),
    (dict(M1=np.zeros((3, 3))), r"M1 must have shape \(2, 2\)"),
    (dict(M2="x"), "M2 must be an array of real numbers"),
    (dict(poles=np.array([-0.3])), "poles must be a 1-D array of positive"),
    (dict(residues=np.zeros((2, 2, 2))), r"residues must have shape \(1, 2, 2\)"),
])
def test_motion_model_checks_its_arrays(change, match):
    good = dict(M0=np.eye(2), M1=np.zeros((2, 2)), M2=np.zeros((2, 2)), poles=np.array([0.3]),
                residues=np.zeros((1, 2, 2)))
    with pytest.raises(ae.AeroModelError, match=match):
        ae.MotionModel(**{**good, **change})
    assert ae.MotionModel(**good).n_lags == 1


def test_all_zero_motion_data_is_a_fit_error():
    frf = th.theodorsen_frf(W, -0.2)
    zero = sysid.FrequencyResponse.from_continuous(np.zeros_like(frf.H), frf.omega, frf.T, inputs=frf.inputs,
                                                   outputs=frf.outputs)
    with pytest.raises(ae.FitError, match="zero at every frequency"):
        ae.fit_motion(zero, 2)


def test_motion_model_keeps_its_arrays_frozen_even_from_lists():
    m = ae.MotionModel(M0=[[1.0, 0.0], [0.0, 1.0]], M1=np.zeros((2, 2)), M2=np.zeros((2, 2)), poles=[0.3],
                       residues=np.zeros((1, 2, 2)))
    assert m.n_lags == 1 and isinstance(m.poles, np.ndarray) and not m.M0.flags.writeable


OMEGA = np.r_[0.0, np.geomspace(0.01, 4.0, 100)]


def test_a_gust_output_that_is_zero_everywhere_is_a_zero_row():
    # about the quarter chord (a = -1/2) the flat plate's gust moment is identically zero: valid data, not a
    # fitting failure; Lee, Price & Wong's section (mu 100, a -1/2, x_alpha 1/4, r_alpha^2 1/4, omega ratio 0.2)
    frf = th.theodorsen_frf(OMEGA, -0.5, gust=True)
    assert np.all(np.asarray(frf.H)[1, frf.inputs.index("gust")] == 0.0)
    model = ae.fit_motion(frf, 4)
    assert np.all(np.asarray(model.gust.C)[1] == 0.0) and np.all(np.asarray(model.gust.D)[1] == 0.0)
    assert model.gust_max_error < 1e-3
    section = ae.TypicalSection(100, -0.5, 0.25, 0.25, 0.2)
    res = ae.flutter(frf, section)   # failed with sysid's "output 'Cm' is zero at every frequency"
    motion_only = ae.flutter(th.theodorsen_frf(OMEGA, -0.5), section)   # the gust column plays no part in flutter
    assert res.kind == "flutter" and res.speed_index == pytest.approx(motion_only.speed_index, rel=1e-12)


@pytest.mark.parametrize("kwargs, match", [
    (dict(gust_order=0), r"gust column cannot be fitted with gust_order = 0"),
    (dict(gust_order=100), r"gust column cannot be fitted with gust_order = 100 .*choose another gust_order"),
])
def test_a_gust_fit_that_sysid_refuses_is_a_fit_error(kwargs, match):
    with pytest.raises(ae.FitError, match=match):
        ae.fit_motion(th.theodorsen_frf(OMEGA, -0.2, gust=True), 4, **kwargs)


# --- input checks (issue 34) ---------------------------------------------------------------------------------------

@pytest.mark.parametrize("T, match", [
    (0, r"T \(sampling period .*\) must be a positive finite number or None .*got 0"),
    (-1.0, r"must be a positive finite number or None"),
    (np.nan, r"must be a positive finite number or None"),
    ("2", r"must be a positive finite number or None .*got '2'"),
    (True, r"must be a positive finite number or None .*got True"),
    # 2 / T = 2e300, 5e299 times the highest frequency: every sample at omega_d ~ 0 (was accepted)
    (1e-300, r"T = 1e-300 puts the bilinear map's centre frequency 2 / T = 2e\+300 above the data's frequencies "
             r"\(0.01 to 4\) by more than 100x: the gust model would see the DC gain alone; give T between 0.005 and "
             r"2e\+04"),
    (1e6, r"centre frequency 2 / T = 2e-06 below the data's frequencies .* the feedthrough alone"),
])
def test_the_gust_identification_period_is_checked_against_the_data(T, match):
    # checked before any fit (T = -1 was refused by sysid after the motion fit; T = 1e-300 was accepted)
    with pytest.raises(ae.FitError, match=match):
        ae.fit_motion(th.theodorsen_frf(W, -0.2, gust=True), 2, T=T)


def test_the_period_band_edges_are_accepted():
    # 2 / T exactly 100 times the highest and 1/100 of the lowest positive frequency: legal
    frf = th.theodorsen_frf(W, -0.2, gust=True)
    for T in (2.0 / (4.0 * ae.fit.T_BAND), 2.0 / (0.01 / ae.fit.T_BAND)):
        assert ae.fit_motion(frf, 2, gust_order=2, T=T * (1 + 1e-12) if T < 1 else T * (1 - 1e-12)).has_gust


def test_the_period_of_motion_only_data_is_still_a_period():
    with pytest.raises(ae.FitError, match="positive finite number or None"):
        ae.fit_motion(th.theodorsen_frf(W, -0.2), 2, T=0)


@pytest.mark.parametrize("kwargs, error, match", [
    (dict(optimise="no"), ae.AeroModelError, r"optimise must be True or False, got 'no'"),
    (dict(poles="ab"), ae.FitError, r"poles must be 2 positive lag roots \(U/c\), finite, in a 1-D array; got 'ab'"),
    (dict(poles=[[0.1], [1.0]]), ae.FitError, r"poles must be 2 positive lag roots"),
    (dict(poles=[np.inf, 1.0]), ae.FitError, r"poles must be 2 positive lag roots"),
])
def test_fit_options_are_checked(kwargs, error, match):
    with pytest.raises(error, match=match):
        ae.fit_motion(th.theodorsen_frf(W, -0.2), 2, **kwargs)

