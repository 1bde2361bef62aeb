"""Tests of sysid.identify: the full pipeline (subspace -> stability -> constrained refit)."""

import warnings
from pathlib import Path

import control
import numpy as np
import pytest
from sysid_synth import freqresp, noisy_resonant_system, pole_mismatch, random_system

import sysid
from sysid import (ConstraintError, FrequencyGridError, FrequencyResponse, IdentificationResult, OrderError,
                   identify, mckelvey_grid)


def data(n=6, p=2, m=2, seed=0, M=64, T=1.0, sigma=0.0, rho=0.95):
    A, B, C, D, poles = random_system(n, p, m, seed, rho=rho)
    wd, _ = mckelvey_grid(M, T)
    G = freqresp(A, B, C, D, np.exp(1j * wd))
    if sigma:
        rng = np.random.default_rng(1000 + seed)
        G = G + sigma * (rng.standard_normal(G.shape) + 1j * rng.standard_normal(G.shape))
    frf = FrequencyResponse(G, wd, T, inputs=[f"u{j}" for j in range(m)], outputs=[f"y{i}" for i in range(p)])
    return frf, (A, B, C, D, poles)


# ---------------------------------------------------------------------------- exact recovery
@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("method", ["mckelvey1", "mckelvey2"])
def test_exact_recovery(seed, method):
    frf, (A, B, C, D, poles) = data(seed=seed)
    res = identify(frf, 6, method=method)
    assert isinstance(res, IdentificationResult)
    assert res.model.dt == 1.0 and res.model.nstates == 6 and res.order == 6 and res.method == method
    assert list(res.model.input_labels) == ["u0", "u1"] and list(res.model.output_labels) == ["y0", "y1"]
    assert res.max_error < 1e-8 and res.rms_error < 1e-8
    assert pole_mismatch(np.linalg.eigvals(res.model.A), poles) < 1e-8
    # the model matches the TRUE system away from the data points too
    zf = np.exp(1j * np.linspace(0.0, np.pi, 333))
    Gt = freqresp(A, B, C, D, zf)
    Gm = freqresp(res.model.A, res.model.B, res.model.C, res.model.D, zf)
    assert np.abs(Gm - Gt).max() < 1e-8 * np.abs(Gt).max()
    assert res.enforced == {"dc_gain": False, "feedthrough": True, "stable": False}
    np.testing.assert_allclose(res.spectral_radius, np.abs(poles).max(), rtol=1e-8)


def test_exact_recovery_arbitrary_frequencies_from_continuous():
    # Continuous data on a non-equispaced grid, with T: identify uses Algorithm 2 on omega_d.
    A, B, C, D, poles = random_system(4, 1, 2, 5)
    T = 0.5
    sysd = control.ss(A, B, C, D, T)
    sysc = sysid.d2c_bilinear(sysd)
    w = np.concatenate([[0.0], np.geomspace(0.01, 50.0, 30), [np.inf]])
    H = np.stack([np.asarray(sysc.C) @ np.linalg.solve(1j * x * np.eye(4) - np.asarray(sysc.A), sysc.B) + sysc.D
                  for x in w[:-1]], axis=-1)
    H = np.concatenate([H, np.asarray(sysc.D)[:, :, None]], axis=2)
    frf = FrequencyResponse.from_continuous(H, w, T)
    res = identify(frf, 4, dc_gain="match")
    assert res.method == "mckelvey2"
    assert res.max_error < 1e-8 and res.dc_error < 1e-10
    assert pole_mismatch(np.linalg.eigvals(res.model.A), poles) < 1e-8
    # the continuous model reproduces the continuous data (paper Eq. 26)
    sc = res.continuous()
    Hc = np.stack([np.asarray(sc.C) @ np.linalg.solve(1j * x * np.eye(4) - np.asarray(sc.A), sc.B) + sc.D
                   for x in w[:-1]], axis=-1)
    np.testing.assert_allclose(Hc, H[:, :, :-1], atol=1e-8 * np.abs(H).max())


# ---------------------------------------------------------------------------------- constraints
def test_dc_match_and_feedthrough_exact_on_noisy_data():
    frf, _ = data(seed=3, sigma=0.02)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # noisy DC / Nyquist samples are complex
        dc_data, ft_data = frf.H[:, :, 0].real, frf.H[:, :, -1].real
        res = identify(frf, 6, dc_gain="match")
    m = res.model
    G1 = freqresp(m.A, m.B, m.C, m.D, [1.0])[:, :, 0]
    Gm1 = freqresp(m.A, m.B, m.C, m.D, [-1.0])[:, :, 0]
    np.testing.assert_allclose(G1.real, dc_data, atol=1e-9)  # DC imposed exactly
    np.testing.assert_allclose(Gm1.real, ft_data, atol=1e-9)  # G(z=-1) = H(pi): continuous feedthrough
    assert res.enforced["dc_gain"] and res.enforced["feedthrough"]
    assert res.dc_error < 1e-9
    # the continuous model's D is the Nyquist value
    np.testing.assert_allclose(res.continuous().D, ft_data, atol=1e-9)
    # and the fit is still at the noise level
    assert res.rms_error < 0.05


@pytest.mark.filterwarnings("ignore:the order-.* model has a resonance")   # the imposed DC needs a pole at z ~ 1
def test_dc_gain_array_and_zero_feedthrough():
    A, B, C, D, _ = random_system(5, 1, 1, 11)
    wd, _ = mckelvey_grid(32, 1.0)
    G = freqresp(A, B, C, D, np.exp(1j * wd))
    G[:, :, -1] = 0.0  # aerofoil-style data: zero feedthrough at omega = inf
    frf = FrequencyResponse(G, wd, 1.0)
    target = np.array([[2.5]])
    res = identify(frf, 5, dc_gain=target)
    m = res.model
    np.testing.assert_allclose(freqresp(m.A, m.B, m.C, m.D, [1.0])[:, :, 0].real, target, atol=1e-9)
    np.testing.assert_allclose(freqresp(m.A, m.B, m.C, m.D, [-1.0])[:, :, 0], 0.0, atol=1e-9)
    np.testing.assert_allclose(res.continuous().D, 0.0, atol=1e-9)


def test_fix_feedthrough_off():
    frf, _ = data(seed=4, sigma=0.02)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        res = identify(frf, 6, fix_feedthrough=False)
    assert res.enforced["feedthrough"] is False


def test_dc_match_needs_zero_frequency():
    frf, _ = data(seed=0, M=32)
    inner = frf.take(np.arange(1, 33))
    with pytest.raises(ConstraintError, match="omega = 0"):
        identify(inner, 6, dc_gain="match")


@pytest.mark.parametrize("flag, enforced", [(True, True), (False, False), (np.True_, True)])
def test_dc_gain_bool_means_match_or_none(flag, enforced):
    # True is the study file's dc_gain = true ("match"), not a DC gain of 1
    wd, w = mckelvey_grid(32, 1.0)
    s = 1j * np.where(np.isfinite(w), w, 0.0)
    G = np.where(np.isfinite(w), 3.0 / (s ** 2 + 0.4 * s + 1.0), 0.0).reshape(1, 1, -1)
    frf = FrequencyResponse(G, wd, 1.0)
    res = identify(frf, 2, dc_gain=flag)
    assert res.enforced["dc_gain"] is enforced
    if enforced:
        np.testing.assert_allclose(res.evaluate(np.array([0.0]))[0, 0, 0].real, 3.0, rtol=1e-9)
        with pytest.raises(ConstraintError, match="dc_gain='match' needs a sample at omega = 0"):
            identify(frf.take(np.arange(1, 33)), 2, dc_gain=flag)
    else:  # False imposes nothing, like None: the same algorithm ("auto": subspace without stability) and model
        ref = identify(frf, 2)
        assert res.algorithm == ref.algorithm == "subspace"
        np.testing.assert_array_equal(res.model.A, ref.model.A)


def test_dc_gain_wrong_shape():
    frf, _ = data(seed=0, M=32)
    with pytest.raises(ConstraintError, match=r"\(p, m\)"):
        identify(frf, 6, dc_gain=np.ones((3, 2)))


def test_dc_constraint_with_pole_at_one():
    # an integrator (pole exactly at z = 1) is recovered from data that avoid omega = 0; a DC constraint
    # is then impossible and the refit's ConstraintError propagates
    A = np.diag([1.0, 0.5, -0.3])
    B = np.ones((3, 1))
    C = np.array([[1.0, 2.0, 1.0]])
    wd = np.linspace(0.05, np.pi, 40)
    frf = FrequencyResponse(freqresp(A, B, C, np.zeros((1, 1)), np.exp(1j * wd)), wd, 1.0)
    res = identify(frf, 3)
    assert np.min(np.abs(np.linalg.eigvals(res.model.A) - 1.0)) < 1e-9
    with pytest.raises(ConstraintError, match="z = 1"):
        identify(frf, 3, dc_gain=np.array([[1.0]]), algorithm="subspace")


# ------------------------------------------------------------------------------------ stability
@pytest.mark.parametrize("stabilise_method", ["lmi", "reflect"])
def test_stable_enforced_on_overfitted_noisy_data(stabilise_method):
    frf, _ = data(seed=1, sigma=0.05, rho=0.97)
    margin = 0.05
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        free = identify(frf, 16)
        res = identify(frf, 16, stable=True, margin=margin, stabilise_method=stabilise_method, dc_gain="match")
    assert free.spectral_radius >= 1 - margin  # the case really needs stabilisation
    assert res.spectral_radius < 1 - margin
    assert np.max(np.abs(np.linalg.eigvals(res.model.A))) < 1 - margin
    rep = res.stabilisation
    assert rep.method == stabilise_method
    np.testing.assert_allclose(rep.spectral_radius_before, free.spectral_radius, rtol=1e-12)
    assert rep.spectral_radius_after < 1 - margin and rep.relative_change > 0
    assert rep.rms_error_after == pytest.approx(res.rms_error)
    assert res.enforced["stable"] and res.enforced["dc_gain"]
    assert res.dc_error < 1e-9  # constraints still exact after stabilisation


@pytest.mark.parametrize("stabilise_method", ["lmi", "reflect"])
def test_output_matrix_refitted_after_stabilisation(stabilise_method):
    """With A changed by stabilisation, refitting C too (the default) never fits worse than keeping the
    subspace C, and keeps the DC gain exact."""
    frf, _ = data(seed=1, sigma=0.05, rho=0.97)
    kw = dict(stable=True, margin=0.05, stabilise_method=stabilise_method, dc_gain="match")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        keep = identify(frf, 16, refit_c=False, **kw)
        both = identify(frf, 16, **kw)
    assert isinstance(both.refit, sysid.refit.AlternatingFit) and isinstance(keep.refit, sysid.BDFit)
    assert both.refit.residual <= keep.refit.residual * (1 + 1e-9)
    assert not np.allclose(both.model.C, keep.model.C)
    assert both.dc_error < 1e-9 and both.spectral_radius < 1 - 0.05
    np.testing.assert_array_equal(both.model.A, keep.model.A)


def test_output_matrix_refit_on_aerofoil_data():
    """T5 (NACA2410, M0.25) LFD data, N_r = 25, DC gain and stability: keeping the subspace C after the LMI
    moved A left the Cm error at 2.5 x max|Cm|; refitting C brings it to 0.10 (measured), Cl 0.044 -> 0.027."""
    path = Path(__file__).resolve().parents[2] / "docs" / "data" / "frf-T5.npz"
    frf = FrequencyResponse.load(path)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        keep = identify(frf, 25, dc_gain="match", stable=True, refit_c=False, algorithm="subspace")
        both = identify(frf, 25, dc_gain="match", stable=True, algorithm="subspace")
    G = np.asarray(frf.H)[:, 0]

    def err(res):
        return np.abs(res.evaluate(frf.omega_d)[:, 0] - G).max(axis=-1) / np.abs(G).max(axis=-1)

    # the refit must mend what keeping C broke (Cm above its own peak) and improve both outputs, Cm by 10x at least
    e_keep, e_both = err(keep), err(both)
    assert e_keep[1] > 1.0 and e_both[1] < 0.1 * e_keep[1] and e_both[0] < e_keep[0]
    assert both.stabilisation.method == "lmi" and both.spectral_radius < 1 - 1e-3 and both.dc_error < 1e-9


def test_stability_sdp_with_a_rank_deficient_objective():
    """T5 LFD data with each output scaled to unit peak, N_r = 55: the shift-equation matrices [G1, -G2] on the
    unstable subspace are rank-deficient (singular values down to 1e-14 of the largest) and Clarabel failed on
    the SDP until the negligible directions were dropped from its objective."""
    path = Path(__file__).resolve().parents[2] / "docs" / "data" / "frf-T5.npz"
    frf = FrequencyResponse.load(path)
    H = np.asarray(frf.H)
    scaled = FrequencyResponse(H / np.abs(H).max(axis=(1, 2))[:, None, None], frf.omega_d, frf.T)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        res = identify(scaled, 55, dc_gain="match", stable=True, algorithm="subspace")
    assert res.subspace.spectral_radius > 1.5  # the subspace model is far from stable
    assert res.stabilisation.method == "lmi" and res.spectral_radius < 1 - 1e-3 and res.dc_error < 1e-9
    G = np.asarray(scaled.H)[:, 0]
    err = np.abs(res.evaluate(scaled.omega_d)[:, 0] - G).max(axis=-1) / np.abs(G).max(axis=-1)
    assert np.all(err < 0.1)


def test_refit_c_bad_value():
    frf, _ = data(seed=2)
    with pytest.raises(sysid.OptionError, match="refit_c must be 'auto', True or False"):
        identify(frf, 6, refit_c="yes")


@pytest.mark.parametrize("kwargs, match", [
    (dict(solver="mosek"), r"solver must be one of \('clarabel', 'numpy'\); got 'mosek'"),
    # not needed on this path (stable=False), refused all the same: a typo must not wait for the day it matters
    (dict(stabilise_method="LMI"), r"stabilise_method must be one of \('lmi', 'reflect'\); got 'LMI'"),
    (dict(method="mckelvey3"), r"method must be one of \('auto', 'mckelvey1', 'mckelvey2'\)"),
    (dict(algorithm=None), r"algorithm must be one of"),
    (dict(effort="quick"), r"effort must be one of \('fast', 'thorough'\); got 'quick'"),
    (dict(margin="small"), r"margin must be a number in \[0, 1\), got 'small'"),
    (dict(margin=True), r"margin must be a number in \[0, 1\), got True"),
    (dict(margin=1.0), r"margin must be a number in \[0, 1\), got 1.0"),
    (dict(margin=np.array([1e-3])), r"margin must be a number in \[0, 1\)"),
    # checked before the subspace step: an order beyond the data would otherwise be reported first
    (dict(dc_gain="Match"), r"dc_gain must be None, 'match' or a \(p, m\) array, got 'Match'"),
])
def test_bad_options_are_option_errors_before_any_work(kwargs, match):
    frf, _ = data(seed=2)
    with pytest.raises(sysid.OptionError, match=match):
        identify(frf, 6, **kwargs)
    with pytest.raises(sysid.OptionError, match=match):   # not an OrderError: the options come first
        identify(frf, 500, **kwargs)


def test_a_zero_dimensional_margin_is_a_number():
    frf, _ = data(seed=2)
    res = identify(frf, 6, stable=True, margin=np.array(1e-3))
    assert res.spectral_radius < 1 - 1e-3 + 1e-12
    assert issubclass(sysid.OptionError, ValueError)   # callers catching ValueError keep working


def test_stable_when_already_stable_changes_nothing():
    frf, _ = data(seed=2)
    res = identify(frf, 6, stable=True)
    assert res.stabilisation.method == "none" and res.stabilisation.relative_change == 0.0
    assert res.max_error < 1e-8


# ---------------------------------------------------------------------------------- weights
def test_weights_reach_the_refit():
    # The subspace step is unweighted, so A and C are the same with and without weights; the refit
    # minimises the WEIGHTED cost, so it must do at least as well on that cost as the unweighted fit,
    # and weighting outliers out must improve the fit at the clean samples.
    A, B, C, D, poles = random_system(4, 1, 1, 12)
    wd = np.sort(np.random.default_rng(0).uniform(0.0, np.pi, 50))
    G = freqresp(A, B, C, D, np.exp(1j * wd))
    bad = np.zeros(50, dtype=bool)
    bad[[5, 17, 33]] = True
    Gc = G.copy()
    Gc[:, :, bad] += 0.3  # outliers
    w = np.where(bad, 0.0, 1.0)
    frf = FrequencyResponse(Gc, wd, 1.0)
    res_w = identify(frf, 4, weights=w)
    res_u = identify(frf, 4)
    np.testing.assert_array_equal(res_w.model.A, res_u.model.A)

    def wcost(r):
        return float(np.sum(w * np.abs(r.evaluate(wd) - Gc)[0, 0] ** 2))

    assert wcost(res_w) <= wcost(res_u) * (1 + 1e-9)
    err_w = np.abs(res_w.evaluate(wd) - G)[:, :, ~bad].max()
    err_u = np.abs(res_u.evaluate(wd) - G)[:, :, ~bad].max()
    assert err_w < err_u


# ------------------------------------------------------------------------------------- helpers
def test_frequency_response_helper():
    frf, (A, B, C, D, _) = data(seed=6, M=32)
    res = identify(frf, 6)
    fr = res.frequency_response()
    assert isinstance(fr, FrequencyResponse) and fr.T == frf.T and fr.outputs == frf.outputs
    np.testing.assert_allclose(fr.omega_d, frf.omega_d)
    z = np.exp(1j * frf.omega_d)
    np.testing.assert_allclose(fr.H, np.stack([res.model(zk) for zk in z], axis=-1), rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(fr.H, frf.H, atol=1e-8 * np.abs(frf.H).max())
    assert res.hankel_sv.ndim == 1 and res.hankel_sv[5] > 1e-8 * res.hankel_sv[0] > res.hankel_sv[6]


def test_evaluate_continuous_and_summary():
    A, B, C, D, _ = random_system(4, 1, 1, 13)
    T = 0.7
    sysc = sysid.d2c_bilinear(control.ss(A, B, C, D, T))
    frf = FrequencyResponse.from_model(sysc, mckelvey_grid(32, T)[0], T=T)
    res = identify(frf, 4, dc_gain="match")
    w = np.array([0.0, 0.3, 2.0, 40.0, np.inf])
    ref = np.stack([np.asarray(sysc.C) @ np.linalg.solve(1j * x * np.eye(4) - np.asarray(sysc.A), sysc.B) + sysc.D
                    for x in w[:-1]] + [np.asarray(sysc.D)], axis=-1)
    np.testing.assert_allclose(res.evaluate_continuous(w), ref, atol=1e-9 * np.abs(ref).max())
    text = res.summary()
    assert "order 4" in text and "dc_gain" in text and "feedthrough" in text


def test_result_pickles():
    import pickle

    frf, _ = data(seed=6, M=32)
    res = identify(frf, 6, stable=True)
    back = pickle.loads(pickle.dumps(res))
    np.testing.assert_array_equal(back.model.A, res.model.A)
    assert back.model.dt == res.model.dt and back.model.output_labels == res.model.output_labels
    assert back.max_error == res.max_error and back.stabilisation == res.stabilisation
    assert back.data == frf


# --------------------------------------------------------------------------------------- errors
def test_needs_T():
    frf = FrequencyResponse.from_continuous(np.ones(5), [0.0, 1.0, 2.0, 3.0, 4.0])
    with pytest.raises(FrequencyGridError, match="sampling period T"):
        identify(frf, 1)


def test_method_1_on_non_equispaced():
    frf = FrequencyResponse(np.ones(6), [0.0, 0.2, 0.5, 1.0, 2.0, np.pi], 1.0)
    with pytest.raises(FrequencyGridError, match="mckelvey2"):
        identify(frf, 1, method="mckelvey1")


@pytest.mark.parametrize("order, match", [(0, "order must be >= 1"), (40, "order 40 is beyond what the data support")])
def test_bad_order(order, match):
    frf, _ = data(seed=0, M=16)
    with pytest.raises(OrderError, match=match):
        identify(frf, order)


# expected: T4 at N_r = 25 on the paper grid is 27 % off between the samples in Cm (the dense LFD: 58 %): the warning is right here
@pytest.mark.filterwarnings("ignore:the order-25 model:RuntimeWarning")
def test_default_falls_back_when_the_relocated_model_resonates_between_samples(monkeypatch):
    """The last guard of the default: a relocated model whose gain between the samples (8 points per interval)
    exceeds UNOBSERVED_GAIN_LIMIT times the data's peak is compared with the subspace model, which is returned
    with a warning when its gain is smaller and its estimated error between the samples too. The relocation's own
    gap bounds keep T4 N_r = 25 at ~1.01 of Cm's peak, so the limit is lowered to 1.0 here to exercise the
    comparison; the explicit algorithm="relocation" keeps the relocated model."""
    import importlib
    from pathlib import Path

    ident = importlib.import_module("sysid.identify")  # the module (the package exports the function)

    frf = FrequencyResponse.load(Path(__file__).resolve().parents[2] / "docs" / "data" / "frf-T4.npz")
    reloc = identify(frf, 25, dc_gain="match", stable=True, algorithm="relocation")
    alt = identify(frf, 25, dc_gain="match", stable=True, algorithm="subspace")
    g_reloc, g_alt = ident.unobserved_gain(reloc.model, frf).max(), ident.unobserved_gain(alt.model, frf).max()
    assert 1.0 < g_reloc < ident.UNOBSERVED_GAIN_LIMIT  # within the default limit: no fallback by default
    monkeypatch.setattr(ident, "UNOBSERVED_GAIN_LIMIT", 1.0)
    if g_alt < g_reloc and alt.between_error < reloc.between_error:
        with pytest.warns(RuntimeWarning, match="between the data's frequencies reaches .* subspace model"):
            res = identify(frf, 25, dc_gain="match", stable=True)
        assert res.algorithm == "subspace" and res.spectral_radius < 1.0
    else:  # the subspace model resonates more, or is estimated farther off between the samples: the relocated one
        # is kept
        res = identify(frf, 25, dc_gain="match", stable=True)
        assert res.algorithm == "relocation"


def test_no_fall_back_to_a_subspace_model_estimated_farther_off():
    # a 1 % noisy 12-state system at order 11: the relocated model (at the noise level, 0.076 off on the samples)
    # peaks at 2.3 times the data's peak between two samples - as the truth may: it is 0.077 off the truth between
    # the samples (VF at this order 0.076). The subspace model resonates less (1.95 times) but is 0.14 off on the
    # samples and 1.18 off the truth; sysid.between estimates the two 0.16 and 0.35 off between the samples, so the
    # default keeps the relocated model (it returned the subspace one: bench/sysid_truth_between_bench.py --seeds,
    # seed 1, 15.6 times VF's error between the samples)
    frf, dense, truth, peak = _noisy_twelve_states(seed=11, noise=0.01)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        res = identify(frf, 11, dc_gain="match", stable=True)
    assert res.algorithm == "relocation"
    assert np.abs(res.evaluate(dense)[0, 0] - truth).max() / peak < 0.1


def test_unobserved_gain_of_an_exact_model_is_its_peak_ratio():
    """A first-order system sampled on McKelvey's grid: the dense-grid peak is the DC value, which the data
    hold, so the gain is 1 to round-off."""
    import control

    from sysid.identify import unobserved_gain

    sysd = control.ss([[0.5]], [[1.0]], [[1.0]], [[0.0]], 1.0)
    frf = FrequencyResponse.from_model(sysd, mckelvey_grid(16, 1.0)[0])
    np.testing.assert_allclose(unobserved_gain(sysd, frf), [1.0], rtol=1e-12)


def test_summary_reports_the_data_diagnostics():
    """The summary's last line is sysid.diagnose of the data: a system's own samples are consistent; the T4 LFD
    data (1.7e-3 of Cm's impulse-response energy at negative time, docs/fit.md) are flagged, per channel."""
    from pathlib import Path

    frf, _ = data(seed=3)
    res = identify(frf, 6)
    assert res.diagnostics.ok
    assert res.summary().splitlines()[-1].startswith("data: consistent with a causal, stable, real LTI system")
    t4 = FrequencyResponse.load(Path(__file__).resolve().parents[2] / "docs" / "data" / "frf-T4.npz")
    line = identify(t4, 9, dc_gain="match", stable=True).summary().splitlines()[-1]
    assert line.startswith("data: not consistent") and "Cm/gust FLAG (negative-time energy 1.7e-03" in line


# ---------------------------------------------------------------------------- bad input
def siso(M=32, T=1.0):
    wd, w = mckelvey_grid(M, T)
    s = 1j * np.where(np.isfinite(w), w, 0.0)
    return wd, np.where(np.isfinite(w), 1.0 / (s ** 2 + 0.4 * s + 1.0), 0.0)


@pytest.mark.parametrize("kw", [{}, {"stable": True}, {"dc_gain": "match"}, {"algorithm": "subspace"}])
def test_output_zero_at_every_frequency(kw):
    wd, h = siso()
    frf = FrequencyResponse(np.stack([h, 0 * h])[:, None], wd, 1.0, outputs=["Cl", "Cd"])
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)  # no divide-by-zero on the way
        with pytest.raises(sysid.FrequencyDataError, match="output 'Cd' is zero at every frequency; drop it"):
            identify(frf, 2, **kw)


@pytest.mark.parametrize("kw", [{}, {"stable": True}, {"dc_gain": "match"}, {"algorithm": "subspace", "stable": True}])
@pytest.mark.parametrize("weights", [np.ones(5), np.ones((1, 1, 5)), -np.ones(33)])
def test_bad_weights_same_error_on_every_path(kw, weights):
    wd, h = siso()
    frf = FrequencyResponse(h.reshape(1, 1, -1), wd, 1.0)
    what = "finite and nonnegative" if weights.size == 33 else r"weights must have shape \(K,\) = \(33,\)"
    with pytest.raises(sysid.FrequencyDataError, match=what):
        identify(frf, 2, weights=weights, **kw)


@pytest.mark.parametrize("kw", [{}, {"stable": True, "dc_gain": "match"}])
def test_repeated_frequency(kw):
    wd, h = siso()
    frf = FrequencyResponse(np.r_[h, 5.0].reshape(1, 1, -1), np.r_[wd, wd[5]], 1.0)
    with pytest.raises(FrequencyGridError, match=r"omega_d\[5\] and omega_d\[33\] are the same frequency"):
        identify(frf, 2, **kw)


def _noisy_order_8_fit():
    """1 % noise on an order-4 system (McKelvey M = 64, T = 1): ``(frf, samples, s)``. Fitted at order 8 with DC and
    stability it put a pole pair of half-width 1e-3 at omega = 0.44, a fiftieth of the spacing there, and was 20 %
    of the peak off between the samples (measured 2026-12-04, before candidates at the noise level were told
    apart by their estimate between the samples)."""
    wd, w = mckelvey_grid(64, 1.0)
    s = 1j * np.where(np.isinf(w), 0.0, w)
    H = np.where(np.isinf(w), 0.0, 2 * np.pi * (0.13 / (s + 0.26) + 1 / (s + 2)) + 1.8 / (s**2 + 0.6 * s + 9))
    rng = np.random.default_rng(3)
    H = H + 0.01 * np.abs(H).max() * (rng.standard_normal(65) + 1j * rng.standard_normal(65)) / np.sqrt(2)
    H[0], H[-1] = H[0].real, 0.0
    return FrequencyResponse(H, wd, 1.0), H, s


@pytest.mark.parametrize("order", [8, 10, 12])
def test_a_fit_at_the_noise_level_does_not_follow_the_noise_with_a_resonance(order):
    # 1 % noise on an order-4 system fitted at 2 - 3 times its order: the relocation's candidates at the noise level
    # that resonate between the samples (estimated far off there) give way to those that do not (sysid.candidates
    # .pick_candidates). Measured 2026-12-04, true error between the samples at orders 8, 10, 12: 0.202, 0.202,
    # 0.239 before, each with a resonance warning; 0.014, 0.016, 0.016 after - the noise's own size (1 % per sample,
    # its largest of 65 about 2.5 %)
    from sysid.identify import unresolved_resonances

    frf, H, s = _noisy_order_8_fit()
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)   # no resonance warning, nothing left open
        res = identify(frf, order, dc_gain="match", stable=True)
    wd = np.linspace(0.0, np.pi, 20001)[:-1]
    sd = 1j * 2.0 * np.tan(wd / 2.0)
    truth = 2 * np.pi * (0.13 / (sd + 0.26) + 1 / (sd + 2)) + 1.8 / (sd**2 + 0.6 * sd + 9)
    assert np.abs(res.evaluate(wd)[0, 0] - truth).max() / np.abs(H).max() < 0.025
    assert len(unresolved_resonances(res.model, frf)) == 0


def _resonating_twelve_states():
    """A noisy 12-state system (0.3 % noise) fitted at order 14 whose relocation keeps a resonance at omega = 1.10
    of half-width 1.3e-3, 0.02 of the spacing there: 0.0046 of the peak off on the samples, 0.12 between them
    against the truth, estimated 0.115 (measured 2026-12-04; no other candidate of the relocation came within 3
    times its error on the samples). ``(frf, dense omega_d, truth there, peak)``."""
    return _noisy_twelve_states(seed=59, noise=0.003)


def test_a_resonance_the_samples_cannot_see_is_reported():
    from sysid.identify import UNRESOLVED_WIDTH, unresolved_resonances

    frf, dense, truth, peak = _resonating_twelve_states()
    with pytest.warns(RuntimeWarning, match=r"resonance at omega = 1\.\d*.* invisible at the samples"):
        res = identify(frf, 14, dc_gain="match", stable=True)
    narrow = unresolved_resonances(res.model, frf)
    assert narrow.shape[1] == 3 and np.all(narrow[:, 1] < UNRESOLVED_WIDTH * narrow[:, 2])
    # what the warning is about: between the samples the model is far from the system the data came from
    between = np.abs(res.evaluate(dense)[0, 0] - truth).max() / peak
    assert res.max_error < 0.01 and between > 10 * res.max_error


def test_resonances_of_a_noise_free_fit_are_not_reported():
    # a resonance of damping ratio 1e-4 halfway between two samples, sampled without noise: the paper's method
    # fits it to round-off, so the samples determine it although it is far narrower than their spacing
    from sysid.identify import unresolved_resonances

    wd, w = mckelvey_grid(64, 1.0)
    wn = 2.0 * np.tan(np.pi * 10.5 / 128)
    s = 1j * np.where(np.isinf(w), 0.0, w)
    H = np.where(np.isinf(w), 0.0, wn**2 / (s**2 + 2e-4 * wn * s + wn**2) + 1.0 / (s + 1.0))
    frf = FrequencyResponse(H, wd, 1.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        res = identify(frf, 3)
    assert res.max_error < 1e-9 and len(unresolved_resonances(res.model, frf)) == 1


@pytest.mark.parametrize("scale", [1e-9, 1e15])
def test_the_convex_refit_does_not_depend_on_the_data_units(scale):
    # an exact order-4 system in other units: the constrained B/D refit is homogeneous in the data, so the fit is
    # at round-off whatever the scale (on Clarabel's absolute tolerances it raised SolverError at 1e15 and
    # stopped at 3e-9 at 1e-9)
    A, B, C, D, _ = random_system(4, 1, 1, 5, rho=0.9)
    wd, _ = mckelvey_grid(64, 1.0)
    frf = FrequencyResponse(scale * freqresp(A, B, C, D, np.exp(1j * wd)), wd, 1.0)
    res = identify(frf, 4, dc_gain="match", stable=True, algorithm="subspace")
    assert res.max_error < 1e-10 and res.dc_error < 1e-10


def test_an_imaginary_part_at_dc_is_dropped_before_the_fit():
    # a real model's DC gain is real: the data's imaginary part there is warned about and no longer fitted (it
    # stayed in the minimax: 2.7 % true error and a spectral radius of 0.999 for this exactly order-4 system)
    A, B, C, D, _ = random_system(4, 1, 1, 5, rho=0.9)
    wd, _ = mckelvey_grid(64, 1.0)
    G = freqresp(A, B, C, D, np.exp(1j * wd))
    G[:, :, 0] += 0.5j * np.abs(G).max()
    with pytest.warns(RuntimeWarning, match="imaginary part"):
        res = identify(FrequencyResponse(G, wd, 1.0), 4, dc_gain="match", stable=True)
    dense = np.linspace(0.0, np.pi, 2001)
    truth = freqresp(A, B, C, D, np.exp(1j * dense))
    assert np.abs(res.evaluate(dense) - truth).max() < 1e-9 * np.abs(truth).max()
    assert np.all(np.asarray(res.data.H)[:, :, 0].imag == 0.0)


def test_a_model_that_nearly_interpolates_the_data_is_reported():
    # five samples of a smooth order-4 response fitted at order 3 (the largest the grid supports): 7 parameters
    # for 8 real values; the fit matches the samples and is far off between them
    from sysid.identify import INTERPOLATION_RATIO, data_use

    w = np.array([0.0, 4.147, 5.0, 6.473, np.inf])
    s = 1j * np.where(np.isinf(w), 0.0, w)
    H = np.where(np.isinf(w), 0.0, 2 * np.pi * (0.13 / (s + 0.26) + 1 / (s + 2)) + 1.8 / (s**2 + 0.6 * s + 9))
    frf = FrequencyResponse.from_continuous(H, w, 0.386)
    assert data_use(3, frf) == pytest.approx(7 / 8) and data_use(3, frf) > INTERPOLATION_RATIO
    with pytest.warns(RuntimeWarning, match=r"order-3 model has 88% as many parameters as the data have real values"):
        identify(frf, 3, dc_gain="match", stable=True)


def test_a_negative_continuous_frequency_gives_the_conjugate_response():
    frf, _ = data(seed=2)
    res = identify(frf, 6)
    np.testing.assert_allclose(res.evaluate_continuous([-1.0, -0.2]), np.conj(res.evaluate_continuous([1.0, 0.2])),
                               rtol=0, atol=0)


# ---------------------------------------------------------------------- input checks (issue 34 findings)
def test_a_period_that_does_not_resolve_the_data_is_refused():
    # T = 1e-300 mapped every sample to z = 1 and returned a model 119 % off (or NaN)
    frf, _ = data(n=4, p=1, m=1, seed=0, M=32)
    with pytest.raises(FrequencyGridError, match=r"T = 1e-300 .* centre frequency 2/T = 2e\+300"):
        identify(frf.with_T(1e-300), 4)
    with pytest.raises(FrequencyGridError, match=r"T = 1e\+300"):
        identify(frf.with_T(1e300), 4, stable=True)
    # McKelvey's grid at any T puts 2/T at the geometric mean of its frequencies: always accepted
    wd, w = mckelvey_grid(32, 1e-6)
    assert identify(FrequencyResponse(frf.H, wd, 1e-6), 4).max_error < 1e-8


@pytest.mark.parametrize("name", ["stable", "fix_feedthrough"])
@pytest.mark.parametrize("value", ["no", 1, None, np.array([True])])
def test_flags_must_be_booleans(name, value):
    # stable="no" imposed stability (any truthy value did)
    frf, _ = data(seed=2)
    with pytest.raises(sysid.OptionError, match=rf"{name} must be True or False, got"):
        identify(frf, 6, **{name: value})


@pytest.mark.parametrize("value", [1, 0, "yes"])
def test_refit_c_must_be_auto_or_a_boolean(value):
    frf, _ = data(seed=2)
    with pytest.raises(sysid.OptionError, match="refit_c must be 'auto', True or False"):
        identify(frf, 6, refit_c=value)


def test_numpy_booleans_are_booleans():
    frf, _ = data(seed=2)
    assert identify(frf, 6, stable=np.True_).enforced["stable"] is True


@pytest.mark.parametrize("stable", [False, True])
def test_weights_that_are_zero_everywhere_are_refused(stable):
    # cvxpy's "Parameter value must be real" (stable=False), a 107 % model with divide-by-zero warnings (True)
    frf, _ = data(n=4, p=2, m=1, seed=0)
    K = frf.nfreq
    with pytest.raises(sysid.FrequencyDataError, match="weights are zero at every frequency"):
        identify(frf, 4, weights=np.zeros(K), stable=stable)
    w = np.ones((2, 1, K))
    w[1] = 0.0
    with pytest.raises(sysid.FrequencyDataError, match=r"weights of output 'y1' are zero at every frequency"):
        identify(frf, 4, weights=w, stable=stable)


@pytest.mark.parametrize("scale", [1e-140, 1e140])
@pytest.mark.parametrize("stable", [False, True])
def test_far_from_order_one_data_fit_as_well(scale, stable):
    frf, _ = data(n=4, p=2, m=1, seed=0)
    ref = identify(frf, 4, stable=stable, dc_gain="match" if stable else None)
    with warnings.catch_warnings():
        warnings.simplefilter("error")   # no raw numpy overflow warning
        got = identify(frf.replace(H=np.asarray(frf.H) * scale), 4, stable=stable,
                       dc_gain="match" if stable else None)
    # both round-off: the relative errors of exact data are at the level of eps times the conditioning
    assert got.max_error < 1e-10 and got.rms_error < 1e-10 and ref.max_error < 1e-10


@pytest.mark.parametrize("scale, where", [(1e200, "all"), (1e300, "dc"), (1e-200, "all")])
def test_data_whose_squares_do_not_fit_a_float_are_refused(scale, where):
    # 1e200 and a DC value of 1e300 gave rms_error = nan with raw numpy overflow warnings
    frf, _ = data(n=4, p=2, m=1, seed=0)
    H = np.array(frf.H)
    if where == "all":
        H = H * scale
    else:
        H[0, 0, 0] = scale
    with pytest.raises(sysid.FrequencyDataError, match=r"output 'y0' .* peak .* 1e-150 .* 1e\+150.* divide"):
        identify(frf.replace(H=H), 4)
# --------------------------------------------------------------------------------------------- units
def _continuous_test_data(kind):
    """``(omega, G, T, order)``: a known stable continuous system (four resonances, two real poles, two outputs
    of peaks 1 and 1e3) sampled exactly or with 1 % complex noise at 61 frequencies; or the paper's T4 LFD data
    (measured-like: not exactly rational) on every fourth sample."""
    if kind == "T4":
        frf = FrequencyResponse.load(Path(__file__).resolve().parents[2] / "docs" / "data" / "frf-T4.npz")
        keep = np.arange(0, len(frf.omega), 4)
        return np.asarray(frf.omega)[keep], np.asarray(frf.H)[:, :, keep], frf.T, 10
    rng = np.random.default_rng(1)
    wn, zeta = np.array([0.3, 1.1, 2.5, 6.0]), np.array([0.05, 0.08, 0.03, 0.1])
    up = -zeta * wn + 1j * wn * np.sqrt(1 - zeta**2)
    poles = np.concatenate([up, np.conj(up), [-0.5, -4.0]])
    res = rng.standard_normal((2, 10)) + 1j * rng.standard_normal((2, 10))
    res[:, 4:8], res[:, 8:] = np.conj(res[:, :4]), res[:, 8:].real
    res[1] *= 1e3
    omega = np.concatenate([[0.0], np.geomspace(0.05, 20.0, 60)])
    G = (res[:, :, None] / (1j * omega[None, None, :] - poles[None, :, None])).sum(axis=1)[:, None, :] + 0.2
    if kind == "noisy":
        G = G * (1 + 0.01 * (rng.standard_normal(G.shape) + 1j * rng.standard_normal(G.shape)))
    G[:, :, 0] = G[:, :, 0].real
    return omega, G, 0.2, 8   # order 8 < 10: an approximation, not a round-off fit, so every step matters


_UNIT_REFERENCE = {}


def _fit_in_units(kind, f_omega, f_out):
    """The default fit of ``_continuous_test_data(kind)`` with omega times ``f_omega`` (T divided by it) and output
    ``i`` times ``f_out[i]``; ``(result, response on 1001 points of omega_d, undone to the original units)``."""
    omega, G, T, order = _continuous_test_data(kind)
    fy = np.array(f_out[:G.shape[0]])[:, None, None]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        res = identify(FrequencyResponse.from_continuous(fy * G, omega * f_omega, T / f_omega), order,
                       dc_gain="match", stable=True)
    return res, res.evaluate(np.linspace(0.0, np.pi, 1001)) / fy


@pytest.mark.parametrize("kind", ["exact", "noisy", "T4"])
@pytest.mark.parametrize("f_omega, f_out", [(1e-12, (1.0, 1.0)), (1e12, (1.0, 1.0)), (1.0, (1e-9, 1e9)),
                                            (1e6, (1e9, 1e-5))])
def test_the_default_fit_does_not_depend_on_the_units(kind, f_omega, f_out):
    # the same data with omega times f_omega (T divided by it: the same omega_d) and each output times its own
    # factor: the default fit runs in the data's own units (omega T / 2, each output at unit peak), so the models
    # agree to round-off. Before, omega / 1e12 gave a different relocation (which 'auto' then replaced by the
    # subspace model) and the tolerances saw the output units. "Round-off" is measured, not assumed: the reference
    # fit is compared with fits of the data perturbed in the last place (omega, then the outputs, times 1 +- 2 eps),
    # as a change of units perturbs them; it may differ from the reference by 10 times the larger change plus
    # 1e-12 of the peak (the rational data: 1e-13 - 4e-13). The measured-like T4 data (65 samples at order 10) are
    # fitted less smoothly: one-ulp perturbations of their outputs moved the model by up to 2.3e-6 of the peak
    # (measured 2026-12-03), so there at most 1e-5 is allowed (before, omega / 1e12 changed the fit outright).
    # The poles are less well determined than the response: 1000 times the response's tolerance.
    if kind not in _UNIT_REFERENCE:
        ref, Gr = _fit_in_units(kind, 1.0, (1.0, 1.0))
        peak = np.abs(Gr).max(axis=(1, 2))[:, None, None]
        eps = 2 * np.finfo(float).eps
        ulp = max(float((np.abs(_fit_in_units(kind, fw, fy)[1] - Gr) / peak).max())
                  for fw, fy in ((1.0 + eps, (1.0, 1.0)), (1.0, (1.0 + eps, 1.0 - eps))))
        _UNIT_REFERENCE[kind] = ref, Gr, peak, ulp
    ref, Gr, peak, ulp = _UNIT_REFERENCE[kind]
    res, Gs = _fit_in_units(kind, f_omega, f_out)
    assert res.algorithm == ref.algorithm == "relocation"
    tol = max(10 * ulp, 1e-5 if kind == "T4" else 0.0) + 1e-12
    assert float((np.abs(Gs - Gr) / peak).max()) <= tol
    np.testing.assert_allclose(res.errors.max_rel_per_output, ref.errors.max_rel_per_output, rtol=tol)
    np.testing.assert_allclose(res.relocation.poles / f_omega, ref.relocation.poles, rtol=0,
                               atol=1e3 * tol * np.abs(ref.relocation.poles).max())


# --------------------------------------------------------------------------------------------- between the samples
def _noisy_twelve_states(seed=13, noise=0.003):
    """:func:`sysid_synth.noisy_resonant_system` as a FrequencyResponse (McKelvey's grid, M = 64, T = 1), the truth
    on 7999 points strictly between 0 and pi, and the data's peak."""
    wd, w = mckelvey_grid(64, 1.0)
    dense = np.linspace(0.0, np.pi, 8001)[1:-1]
    G, truth = noisy_resonant_system(w, 2.0 * np.tan(dense / 2.0), seed=seed, noise=noise)
    return FrequencyResponse(G, wd, 1.0), dense, truth, np.abs(G).max()


def test_the_error_between_the_samples_is_estimated_and_reported():
    # the estimate (no truth: the model against local readings of the samples) is within a factor 2 of the true error
    # between the samples: 1 % noisy order-4 data fitted at orders 8 and 6 (estimates 0.0154 and 0.0176 against
    # 0.0142 and 0.0142), and a noisy 12-state system's order-14 fit that resonates between two samples (0.115
    # against 0.121 of the peak, 25 times its error on them); measured 2026-12-04
    frf, H, s = _noisy_order_8_fit()
    wd = np.linspace(0.0, np.pi, 20001)[:-1]
    sd = 1j * 2.0 * np.tan(wd / 2.0)
    truth = 2 * np.pi * (0.13 / (sd + 0.26) + 1 / (sd + 2)) + 1.8 / (sd**2 + 0.6 * sd + 9)
    frf12, dense, truth12, peak12 = _resonating_twelve_states()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        fits = [(identify(frf, n, dc_gain="match", stable=True), wd, truth, np.abs(H).max()) for n in (8, 6)]
        fits.append((identify(frf12, 14, dc_gain="match", stable=True), dense, truth12, peak12))
    for res, points, exact, peak in fits:
        true_between = np.abs(res.evaluate(points)[0, 0] - exact).max() / peak
        assert 0.5 * true_between <= res.between_error <= 2.0 * true_between
        assert res.between_error_per_output.shape == (1,) and not res.between_error_per_output.flags.writeable
        assert "between the samples (estimate" in res.summary()
    assert all(res.between_error < 2 * res.max_error for res, *_ in fits[:2])
    assert fits[2][0].between_error > 5 * fits[2][0].max_error


def test_samples_that_leave_an_output_open_between_them_are_named():
    # the paper's T5 at N_r = 10: Cm is 0.7 % off on the samples and estimated as much between them, but the grid has
    # eight samples above k = 2, where Cm's phase turns fast and local readings of the samples disagree by 0.58 of
    # the peak: the model is 0.36 off there against the LFD on a grid eight times denser (M = 2048,
    # bench/sysid_between_bench.py, measured 2026-12-04). The estimate cannot see that; the uncertainty does, and the
    # warning says so. Cl, whose readings agree to 0.7 %, is not named
    frf = FrequencyResponse.load(Path(__file__).resolve().parents[2] / "docs" / "data" / "frf-T5.npz")
    with pytest.warns(RuntimeWarning, match=r"the samples leave Cm open between them: .* disagree by up to 0\.5\d"):
        res = identify(frf, 10, dc_gain="match", stable=True)
    u, e = res.between_uncertainty_per_output, res.between_error_per_output
    assert u.shape == (2,) and not u.flags.writeable
    assert u[1] > 0.5 and u[1] > 50 * max(e[1], res.errors.max_rel_per_output[1]) and u[0] < 0.02
    assert "left open by the samples" in res.summary()
    # the noisy 12-state system at its true order: the readings' disagreement is the noise's (0.023 of the peak,
    # below sysid.between.READING_FLOOR): no such warning
    frf, _, _, _ = _noisy_twelve_states(seed=13)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = identify(frf, 12, dc_gain="match", stable=True)
    assert not any("open between them" in str(w.message) for w in caught)
    assert res.between_uncertainty < 0.05


def test_each_warning_names_its_own_output():
    # output 0 estimated far off between the samples (4 times its error on them), output 1 with a low estimate but
    # samples that leave it open (readings 0.2 of the peak apart): the "not pinned down" warning names output 0
    # (it named the largest ratio over all outputs, here output 1's 1e4) and the "open" warning output 1 only
    import dataclasses

    from sysid.identify import _reported

    wd, w = mckelvey_grid(40, 1.0)
    A, B, C, D, _ = random_system(4, 2, 1, 3, rho=0.8)
    frf = FrequencyResponse(freqresp(A, B, C, D, np.exp(1j * wd)), wd, 1.0, outputs=["Cl", "Cm"])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = identify(frf, 2)
    on, between, open_ = np.array([0.005, 1e-8]), np.array([0.02, 1e-4]), np.array([0.01, 0.2])
    object.__setattr__(res, "errors", dataclasses.replace(res.errors, max_rel_per_output=on))
    object.__setattr__(res, "max_error", 0.005)
    object.__setattr__(res, "_between_cache", (between, open_))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        _reported(res)
    msgs = [str(w.message) for w in caught]
    assert sum("leave Cm open between them" in m for m in msgs) == 1
    assert sum("not pinned down" in m and "(Cl, sysid.between)" in m for m in msgs) == 1
    assert not any("Cl open" in m or "(Cm, sysid.between)" in m for m in msgs)


def test_the_resonance_warning_advises_a_lower_order_only_when_it_helps():
    from sysid.between import BETWEEN_RATIO

    # (1) where it helps: the order-14 fit resonates between two samples, estimated 0.115 of the peak off there
    # (truth 0.121); the warning advises order 12, whose estimate is lower (0.068) and whose true error is 9 times
    # lower (0.0137). Measured 2026-12-04
    frf, dense, truth, peak = _resonating_twelve_states()
    with pytest.warns(RuntimeWarning, match=r"resonance at omega = .*Order 12 lowers that estimate to 0\.0\d"):
        res = identify(frf, 14, dc_gain="match", stable=True)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        low = identify(frf, 12, dc_gain="match", stable=True)
    assert low.between_error < 0.8 * res.between_error
    true_err = [np.abs(r.evaluate(dense)[0, 0] - truth).max() / peak for r in (res, low)]
    assert 0.5 * true_err[0] <= res.between_error <= 2.0 * true_err[0]
    assert true_err[1] < 0.2 * true_err[0]
    # (2) where it does not: another realisation's order-14 fit keeps a resonance at omega = 4.8 of 0.02 spacings,
    # estimated 0.36 of the peak off between the samples against 0.0051 on them; at order 12 the estimate is no lower
    # (0.37) and neither is the true error (0.0193 -> 0.0202), so the warning must not advise it (the old one said
    # 'lower the order'). The estimate is 19 times the truth here: the samples near omega = 4.8 are 0.33 apart and
    # their local readings disagree (measured 2026-12-04; of 360 fits of 60 realisations at orders 12, 14, 16 the
    # warnings named a resonance at 20, 6 of them where the subspace fit was returned instead, advised a lower order
    # at 6 and said it does not help at 8)
    frf, dense, truth, peak = _noisy_twelve_states(seed=54, noise=0.003)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = identify(frf, 14, dc_gain="match", stable=True)
    msgs = [str(w.message) for w in caught if "resonance" in str(w.message)]
    assert len(msgs) == 1 and "A lower order does not help" in msgs[0] and "lower the order" not in msgs[0]
    assert res.between_error > BETWEEN_RATIO * res.max_error
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        low = identify(frf, 12, dc_gain="match", stable=True)
    assert low.between_error >= 0.8 * res.between_error
    true_err = [np.abs(r.evaluate(dense)[0, 0] - truth).max() / peak for r in (res, low)]
    assert true_err[1] > 0.95 * true_err[0]   # not better: advice to lower the order would not have helped


@pytest.mark.parametrize("ignore, unrelated", [(True, False), (True, True), (False, False)])
def test_the_advice_fit_runs_only_when_the_warning_can_be_read(monkeypatch, ignore, unrelated):
    import importlib

    module = importlib.import_module("sysid.identify")
    orders = []
    advice = module._order_advice
    monkeypatch.setattr(module, "_order_advice", lambda res, refit_at: orders.append(res.order) or advice(res, refit_at))
    frf, *_ = _resonating_twelve_states()   # order 14 warns of a resonance and advises order 12 (test above)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("ignore" if ignore else "always")
        if unrelated:   # a filter for another message in front (as libraries add on import) does not apply
            warnings.filterwarnings("always", message="the matrix subclass is not")
        res = identify(frf, 14, dc_gain="match", stable=True)
    # the fit at order 12 behind the advice is a second identification: run only when the warning is not ignored;
    # the model is the same either way
    assert orders == ([] if ignore else [14])
    assert ignore or any("Order 12 lowers that estimate" in str(w.message) for w in caught)
    with warnings.catch_warnings(record=True):   # shown (the advice fit runs), and expected
        warnings.simplefilter("always")
        other = identify(frf, 14, dc_gain="match", stable=True)
    np.testing.assert_array_equal(res.matrices.C, other.matrices.C)


# ---------------------------------------------------------------------------- margins and DC gains at the edges
def _t4_32():
    return FrequencyResponse.load(Path(__file__).resolve().parents[2] / "docs" / "data" / "frf-T4.npz").subsample(32)


@pytest.mark.filterwarnings("ignore::RuntimeWarning")
def test_margin_zero_is_met_by_the_smallest_margin_the_relocation_resolves():
    # margin 0 ran the relocation at 1e-9, where its stability disc (radius ~ 2 / (T margin)) loses the digits of
    # its edge: max error 0.0088 against 0.0031 at 1e-3 .. 1e-8 (T4, order 8, 32 samples). The same fit as at 1e-6
    frf = _t4_32()
    zero = identify(frf, 8, dc_gain="match", stable=True, margin=0.0)
    usual = identify(frf, 8, dc_gain="match", stable=True, margin=1e-3)
    # the margin does not bind on these poles (spectral radius 0.995): every margin from 1e-3 down gives the same fit
    # to the refinement's round-off; 0.0088 (2.8 times) with the degenerate disc
    assert zero.max_error == pytest.approx(usual.max_error, rel=1e-6)
    assert zero.spectral_radius < 1.0 - 1e-6


def test_a_dc_gain_far_outside_the_data_is_refused():
    frf = _t4_32()
    with pytest.raises(ConstraintError, match=r"dc_gain\[0, 0\] = 1e\+300 is .* times the largest \|H\|"):
        identify(frf, 8, dc_gain=[[1e300], [1.0]], stable=True)


@pytest.mark.parametrize("call", [
    lambda: identify(None, 4), lambda: sysid.diagnose(np.ones(3)), lambda: sysid.c2d_bilinear(None, 1.0),
    lambda: sysid.rom_response(None, np.arange(3.0), np.zeros(3)),
])
def test_the_wrong_kind_of_object_is_an_argument_type_error(call):
    # a bare TypeError before: now the package's own, still a TypeError
    with pytest.raises(sysid.ArgumentTypeError, match="expects a"):
        call()
    assert issubclass(sysid.ArgumentTypeError, TypeError)
