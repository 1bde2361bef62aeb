"""The coupled model: python-control interconnection, time scaling, still-air and static limits."""

import numpy as np
import pytest

import aeroelastic as ae
from aeroelastic import theodorsen as th
from aeroelastic.coupling import state_matrix

W = np.concatenate([[0.0], np.geomspace(0.01, 4.0, 100)])
HP = ae.TypicalSection(mu=20, a=-0.2, x_alpha=0.1, r_alpha2=0.24, omega_ratio=0.4)


@pytest.fixture(scope="module")
def model():
    return ae.fit_motion(th.theodorsen_frf(W, HP.a, gust=True), 4)


@pytest.mark.parametrize("V", [0.3, 1.7, 3.0])
def test_state_matrix_equals_python_control_feedback(model, V):
    sys = ae.coupled_model(model, HP, V, gust=False)
    e1 = np.sort_complex(np.linalg.eigvals(sys.A))
    e2 = np.sort_complex(np.linalg.eigvals(state_matrix(model, HP, V)))
    np.testing.assert_allclose(e1, e2, atol=1e-10)  # same algebra, different order of operations
    full = ae.coupled_model(model, HP, V)
    assert list(full.input_labels) == ["gust"] and list(full.output_labels)[-2:] == ["Cl", "Cm"]
    assert full.nstates == 4 + 2 * model.n_lags + model.gust.nstates


def test_still_air_limit_is_the_structure_with_apparent_mass(model):
    # V -> 0: the circulatory terms vanish (they scale with V), the apparent mass stays. Exact added mass of a flat
    # plate in these units is -4 Lm M2 with M2 = Theodorsen's s^2 coefficients.
    a = HP.a
    M2 = np.array([[-np.pi / 2, -np.pi * a / 4], [-np.pi * a / 4, -np.pi / 8 * (0.125 + a**2)]])
    Mt = HP.mass_matrix - 4 * HP.load_matrix @ M2
    w_ref = np.sort(np.sqrt(np.linalg.eigvals(np.linalg.solve(Mt, HP.stiffness_matrix)).real))
    ev = np.linalg.eigvals(state_matrix(model, HP, 1e-5))
    osc = np.sort(ev[ev.imag > 1e-3].imag)
    # the fitted M2 is within ~0.3 % of the exact one (lags trade with M2 over a finite band), the added mass is
    # 1/mu of the structure's, so the frequencies agree to ~1e-3 relative
    np.testing.assert_allclose(osc, w_ref, rtol=2e-3)
    # in vacuo (mu -> inf): the coupled structural frequencies
    heavy = ae.TypicalSection(1e9, HP.a, HP.x_alpha, HP.r_alpha2, HP.omega_ratio)
    ev = np.linalg.eigvals(state_matrix(model, heavy, 1e-3))
    np.testing.assert_allclose(np.sort(ev[ev.imag > 1e-3].imag), heavy.natural_frequencies(), rtol=1e-9)


@pytest.mark.parametrize("V", [0.8, 1.6])
def test_static_gust_response_is_the_static_aeroelastic_solution(model, V):
    # DC gain of the coupled gust model = static equilibrium (Ks - V^2 Lm M0) q = V^2 Lm G0 with G0 = [2pi, pi(a+1/2)]:
    # checks the V^2/(pi mu) load scaling and the time scaling (which must leave DC untouched) independently
    sys = ae.coupled_model(model, HP, V)
    dc = np.asarray(sys.dcgain()).reshape(-1)
    G0 = np.array([2 * np.pi, np.pi * (HP.a + 0.5)])
    q = np.linalg.solve(HP.stiffness_matrix - V**2 * HP.load_matrix @ model.M0, V**2 * HP.load_matrix @ G0)
    np.testing.assert_allclose(dc[:2], q, rtol=1e-7)
    np.testing.assert_allclose(dc[6:8], model.M0 @ q + G0, rtol=1e-7)


@pytest.mark.parametrize("speed", [0.0, -1.0, float("nan"), "fast"])
def test_speed_errors(model, speed):
    with pytest.raises(ae.SpeedError, match="speed index"):
        ae.coupled_model(model, HP, speed)


def test_model_errors():
    m = ae.fit_motion(th.theodorsen_frf(W, HP.a), 2)
    with pytest.raises(ae.AeroModelError, match="no gust input"):
        ae.coupled_model(m, HP, 1.0, gust=True)
    with pytest.raises(ae.AeroModelError, match="aero must be"):
        ae.coupled_model(np.eye(2), HP, 1.0)
    with pytest.raises(ae.SectionError, match="TypicalSection"):
        ae.coupled_model(m, (20, -0.2), 1.0)


def test_fit_options_are_fit_motions_keyword_options():
    import inspect

    params = inspect.signature(ae.fit_motion).parameters.values()
    assert set(ae.coupling.FIT_OPTIONS) == {p.name for p in params if p.kind is p.KEYWORD_ONLY}


@pytest.mark.parametrize("call", [
    lambda aero, **kw: ae.flutter(aero, HP, np.linspace(0.1, 3.0, 5), **kw),
    lambda aero, **kw: ae.gust_response(aero, HP, 1.0, (np.linspace(0.0, 1.0, 11), np.zeros(11)), **kw),
    lambda aero, **kw: ae.coupling.as_motion_model(aero, 2, **kw),
])
@pytest.mark.parametrize("data", [False, True])
@pytest.mark.parametrize("kw, bad", [({"optimse": False}, "'optimse'"), ({"gust_ordr": 3, "T": 1.0}, "'gust_ordr'")])
def test_unknown_fit_options_are_refused(model, call, data, kw, bad):
    aero = th.theodorsen_frf(W, HP.a, gust=True) if data else model
    with pytest.raises(ae.AeroModelError, match=rf"unknown option\(s\) \[{bad}\].*\('gust_order', 'T', 'optimise'"):
        call(aero, **kw)


def test_gust_flag_must_be_a_bool():
    m = ae.fit_motion(th.theodorsen_frf(W, HP.a), 2)
    with pytest.raises(ae.AeroModelError, match="gust must be True, False or None"):
        ae.coupled_model(m, HP, 1.0, gust="no")


@pytest.mark.parametrize("call", [
    lambda m: ae.coupled_model(m, None, 1.0),
    lambda m: ae.flutter(m, None, np.linspace(0.5, 3.0, 11)),
    lambda m: ae.root_locus_response(m, None, np.linspace(0.5, 3.0, 11)),
    lambda m: ae.divergence_speed(m, None),
    lambda m: ae.to_elastic_axis(th.theodorsen_frf(W, HP.a), None),
])
def test_a_missing_section_is_a_section_error(call):
    m = ae.fit_motion(th.theodorsen_frf(W, HP.a), 2)
    with pytest.raises(ae.SectionError, match="section must be an aeroelastic.TypicalSection"):
        call(m)
