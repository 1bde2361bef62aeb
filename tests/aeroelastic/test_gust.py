"""Gust response of the flexible section: the fitted coupled model against Jones' time-domain model."""

import warnings

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import aeroelastic as ae
from aeroelastic import theodorsen as th

W = np.concatenate([[0.0], np.geomspace(0.01, 4.0, 100)])
HP = ae.TypicalSection(mu=20, a=-0.2, x_alpha=0.1, r_alpha2=0.24, omega_ratio=0.4)
T = np.linspace(0.0, 60.0, 601)
U = np.where(T < 10.0, 0.5 * (1 - np.cos(2 * np.pi * T / 10.0)), 0.0) * np.radians(1.0)  # 1-cos, 10 chords, 1 deg


def jones_reference(V):
    """Jones' model integrated with scipy (DOP853, tight tolerances), gust linear between samples."""
    sys = th.jones_section_model(HP, V)
    A, B, C, D = (np.asarray(x) for x in (sys.A, sys.B, sys.C, sys.D))
    tau = 2 * T / V

    def rhs(t, x):
        return A @ x + B[:, 0] * np.interp(t, tau, U)

    # integrate piece by piece between the gust's kinks (t = 0 and 10) so the adaptive steps never straddle one
    kinks = [0.0, 2 * 10.0 / V, tau[-1]]
    y0, ys = np.zeros(A.shape[0]), []
    for t0, t1 in zip(kinks[:-1], kinks[1:]):
        sel = (tau >= t0) & (tau < t1) if t1 < tau[-1] else (tau >= t0)
        sol = solve_ivp(rhs, (t0, t1), y0, t_eval=tau[sel], method="DOP853", rtol=1e-10, atol=1e-13, dense_output=True)
        ys.append(sol.y)
        y0 = sol.sol(t1)
    sol_y = np.hstack(ys)
    Y = C @ sol_y + D @ U[None, :]
    return dict(zip(["plunge", "pitch", "Cl", "Cm"], Y))


@pytest.fixture(scope="module")
def theo():
    return ae.fit_motion(th.theodorsen_frf(W, HP.a, gust=True), 4)


@pytest.mark.parametrize("V", [1.0, 1.5])
def test_fitted_jones_data_reproduce_the_jones_time_domain_model(V):
    # same aerodynamics (Jones' approximations) by two routes: frequency data -> fit -> python-control coupling in
    # structural time, and the textbook ODE in Theodorsen's notation integrated by scipy. The fit is exact here
    # (Roger's form contains Jones'), so only the ODE tolerances (1e-10) remain (both integrate the same
    # piecewise-linear input exactly).
    model = ae.fit_motion(th.jones_frf(W, HP.a), 2, gust_order=3)
    r = ae.gust_response(model, HP, V, (T, U))
    ref = jones_reference(V)
    for k in ("plunge", "pitch", "Cl", "Cm"):
        y, yr = getattr(r, k), ref[k]
        assert np.abs(y - yr).max() < 1e-6 * np.abs(yr).max(), k


@pytest.mark.parametrize("V, bounds", [(1.0, (0.015, 0.03, 0.02, 0.02)), (1.5, (0.015, 0.035, 0.02, 0.02))])
def test_theodorsen_sears_fit_against_jones_time_domain(theo, V, bounds):
    # exact Theodorsen/Sears data (fitted, errors 1.8e-3 and 4e-5) against Jones' approximations: the two
    # aerodynamic models differ by 1-2.3 % in C(k) and a few per cent in the early Kussner rise; the flexible
    # section filters them. Measured (max difference / peak) at V = 1.5: plunge 1.1 %, pitch 2.9 %, Cl 1.5 %,
    # Cm 1.6 %; at V = 1.0: see docs/aeroelastic.md.
    r = ae.gust_response(theo, HP, V, (T, U))
    ref = jones_reference(V)
    for k, b in zip(("plunge", "pitch", "Cl", "Cm"), bounds):
        y, yr = getattr(r, k), ref[k]
        assert np.abs(y - yr).max() / np.abs(yr).max() < b, k
    assert r.speed == V and r.t[0] == 0.0 and r.tau[-1] == pytest.approx(2 * 60 / V)


def test_input_forms_and_errors(theo):
    class Hist:
        t, u = T, U

    a = ae.gust_response(theo, HP, 1.2, (T, U))
    b = ae.gust_response(theo, HP, 1.2, Hist())
    c = ae.gust_response(theo, HP, 1.2, U, t=T)
    np.testing.assert_array_equal(a.Cl, b.Cl)
    np.testing.assert_array_equal(a.Cl, c.Cl)
    with pytest.raises(ValueError, match="read-only"):
        a.Cl[0] = 1.0
    with pytest.raises(ae.AeroModelError, match="give the gust history"):
        ae.gust_response(theo, HP, 1.2, U)
    with pytest.raises(ae.AeroModelError, match="strictly increasing"):
        ae.gust_response(theo, HP, 1.2, (T[::-1], U))
    with pytest.raises(ae.AeroModelError, match="no 'gust' input"):
        ae.gust_response(ae.fit_motion(th.theodorsen_frf(W, HP.a), 2), HP, 1.2, (T, U))
    with pytest.raises(ae.SpeedError, match="speed"):
        ae.gust_response(theo, HP, 0.0, (T, U))


@pytest.mark.parametrize("history, match", [
    ((T[:, None], U), r"t must be 1-D .*got shape \(601, 1\)"),
    ((T, U[None, :]), r"u must be 1-D .*got shape \(1, 601\)"),
    ((T[:600].reshape(2, -1), U[:600].reshape(2, -1)), "t must be 1-D"),
    ((T, U.astype(complex)), "u must be an array of real numbers"),
    ((T, ["a"] * T.size), "u must be an array of real numbers"),
    ((np.float64(1.0), np.float64(0.0)), r"t must be 1-D .*got shape \(\)"),
    # python-control's bare ValueError before: the times must be equispaced
    ((np.array([0.0, 5.0, 30.0, 60.0, 100.0]), np.zeros(5)), r"t must be equispaced: t\[2\] - t\[1\] = 25"),
])
def test_gust_history_must_be_one_dimensional_and_real(theo, history, match):
    with pytest.raises(ae.AeroModelError, match=match):
        ae.gust_response(theo, HP, 1.2, history)


def test_above_the_flutter_speed_the_response_warns(theo):
    # flutter of this section at V = 2.18 (Theodorsen): below it no warning, above it a RuntimeWarning
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ae.gust_response(theo, HP, 1.5, U, t=T)
    with pytest.warns(RuntimeWarning, match="unstable at speed 2.6"):
        ae.gust_response(theo, HP, 2.6, U, t=T)


def test_a_step_too_coarse_for_the_section_is_reported(theo):
    # a 10-chord 1-cosine gust at V = 1.2 sampled every 2.5 chords: fewer than ten samples per period of the
    # fastest mode, and the pitch peak is off (compare a fine step)
    def history(step):
        t = np.arange(0.0, 60.0 + step / 2, step)
        return t, np.where(t <= 10.0, 0.5 * (1.0 - np.cos(2.0 * np.pi * t / 10.0)), 0.0)

    # a step of 2.5 also puts only 2 samples above the 10-chord gust's half peak: that warning is expected too
    with pytest.warns(RuntimeWarning, match=r"the time step 2.5 .*samples the section's fastest oscillation"), \
            pytest.warns(RuntimeWarning, match=r"reaches half its peak at 2 sample"):
        coarse = ae.gust_response(theo, HP, 1.2, history(2.5))
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        fine = ae.gust_response(theo, HP, 1.2, history(0.05))
    assert abs(np.abs(coarse.pitch).max() / np.abs(fine.pitch).max() - 1.0) > 0.05


# --- input checks (issue 34): a gust between the samples, a gust on too few samples --------------------------------

def test_a_gust_history_of_zeros_is_refused(theo):
    # what cfd.ltd_response returned for a gust shorter than its step: zeros, and a zero response without a word
    t = np.arange(0.0, 40.0, 5.0)
    with pytest.raises(ae.AeroModelError, match=r"the gust history u is zero at all 8 samples: there is nothing to "
                                                r"respond to. A gust shorter than the time step"):
        ae.gust_response(theo, HP, 1.0, (t, 0.0 * t))


def test_a_gust_on_one_or_two_samples_warns(theo):
    t = np.arange(0.0, 60.0, 0.25)
    u = np.where(t == 5.0, 0.01, 0.0)                 # a spike: the gust fell on one sample
    with pytest.warns(RuntimeWarning, match=r"reaches half its peak at 1 sample\(s\) only \(step 0.25\)"):
        ae.gust_response(theo, HP, 1.0, (t, u))
    with warnings.catch_warnings():                   # the 10-chord gust on a 0.1 step: no warning
        warnings.simplefilter("error")
        ae.gust_response(theo, HP, 1.0, (T, U))


def test_a_speed_is_a_number_not_a_flag_nor_astronomical(theo):
    with pytest.raises(ae.SpeedError, match=r"must be a number, got True"):
        ae.gust_response(theo, HP, True, (T, U))
    # 1e200 overflowed in the state matrix (Python's OverflowError)
    with pytest.raises(ae.SpeedError, match=r"= 1e\+200 is above MAX_SPEED = 1e\+06"):
        ae.coupled_model(theo, HP, 1e200)
