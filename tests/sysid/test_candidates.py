"""The relocation's candidates (:mod:`sysid.candidates`): equalities that hold when the model is evaluated."""

import numpy as np
import pytest
import scipy.linalg
from sysid_synth import LIGHT, freqresp

from sysid import mckelvey_grid
from sysid.candidates import (EQ_TOL, NOISE_RMS_TIE, NOISE_TRUST, NOISE_TRUST_GAP, ROUNDOFF_TOL, channel_errors,
                              check_equalities, gap_excess, pick_candidates, rms_errors, settle_equalities)
from sysid.poles import balanced_coordinates, discrete_basis
from sysid.residues import gap_bounds, minimax_cd



def light_model(T=1.0, M=64, seed=0):
    """Data of a lightly damped 2-output system on the McKelvey grid and its DC-exact minimax realisation on
    the true poles: ``(z, G, dc, ft, peak, A, B, C, D)``."""
    rng = np.random.default_rng(seed)
    A, B = discrete_basis(np.array(LIGHT, dtype=complex), T)
    C = rng.standard_normal((2, A.shape[0]))
    wd, _ = mckelvey_grid(M, T)
    z = np.exp(1j * wd)
    G = freqresp(A, B, C, np.zeros((2, 1)), z)
    dc, ft = G[:, :, 0].real, G[:, :, -1].real
    C0, D0, _ = minimax_cd(A, B, z, G, dc_gain=dc, feedthrough=ft)
    peak = np.abs(G[:, 0]).max(axis=1)
    return z, G, dc, ft, peak, A, B, C0, D0


def test_balanced_coordinates_equalise_the_gramians_and_keep_the_model():
    z, G, dc, ft, peak, A, B, C, D = light_model()
    A_b, B_b, C_b, T, T_inv = balanced_coordinates(A, B, C)
    np.testing.assert_allclose(T @ T_inv, np.eye(A.shape[0]), atol=1e-10)
    P = scipy.linalg.solve_discrete_lyapunov(A_b, B_b @ B_b.T)
    Q = scipy.linalg.solve_discrete_lyapunov(A_b.T, C_b.T @ C_b)
    hsv = np.diag(P)
    # both Gramians diag(hsv), hsv the Hankel singular values (square roots of eig(P Q) in any coordinates);
    # the solves are accurate to about cond(A) eps relative to the largest
    np.testing.assert_allclose(P, np.diag(hsv), atol=1e-9 * hsv.max())
    np.testing.assert_allclose(Q, np.diag(hsv), atol=1e-9 * hsv.max())
    P0 = scipy.linalg.solve_discrete_lyapunov(A, B @ B.T)
    Q0 = scipy.linalg.solve_discrete_lyapunov(A.T, C.T @ C)
    np.testing.assert_allclose(np.sort(hsv), np.sort(np.sqrt(np.linalg.eigvals(P0 @ Q0).real)), rtol=1e-7)
    np.testing.assert_allclose(channel_errors(A_b, B_b, C_b, D, z, G), 0.0, atol=1e-10)


def test_settle_moves_a_cancelling_realisation_to_balanced_coordinates():
    # the lightly damped system plus a pair of real poles 1e-11 apart with residues +-r, r = 1e8 (what the
    # relocation's T5 N_r = 55 fits hold): the pair adds -r 1e-9 / ((z - a)(z - a - 1e-9)), 0.1 at DC, but
    # its terms r / (1 - a) = 1e9 cancel in the DC gain, so a double-precision evaluation may be off by
    # eps sum |C_ij x_j| ~ 5e-9 of the peak (check_equalities' bound, above ROUNDOFF_TOL). The data are
    # computed from the closed form, so the realisation is exact. settle_equalities returns it balanced, where
    # the bound is at round-off, the equalities hold and the fit is as exact as before (to the balancing
    # transformation's round-off: its condition number is ~1e7 here)
    z, G, dc, ft, peak, A, B, C, D = light_model()
    a, r = 0.9, 1e8
    a2 = a + 1e-11
    gap = a2 - a  # exact (Sterbenz): the data below are the model's response to round-off
    pair = -r * gap / ((z - a) * (z - a2))  # (K,): the pair's response to the single input
    G = G + np.array([1.0, -0.5])[:, None, None] * pair[None, None, :]
    dc, ft = G[:, :, 0].real, G[:, :, -1].real
    peak = np.abs(G[:, 0]).max(axis=1)
    A2 = scipy.linalg.block_diag(A, a, a2)
    B2 = np.vstack([B, [[1.0], [1.0]]])
    C2 = np.hstack([C, np.array([[r, -r], [-0.5 * r, 0.5 * r]])])
    zb, ub = gap_bounds(z, G)
    c = dict(A=A2, B=B2, C=C2, D=D, residues="minimax", label="pair")
    c["err"] = channel_errors(A2, B2, C2, D, z, G)
    c["gap"] = gap0 = gap_excess(c, zb, ub)  # the light resonances peak between the samples: above 1
    check_equalities(c, dc, ft, peak)
    assert c["eq_roundoff"] > 10 * ROUNDOFF_TOL and c["eq"] <= EQ_TOL
    assert np.all(c["err"] < 1e-6)
    settle_equalities(c, z, G, dc, ft, peak, zb, ub)
    assert c["eq_roundoff"] < 1e-13 and c["eq"] <= EQ_TOL
    assert np.all(c["err"] < 1e-6) and np.abs(c["C"]).max() < 1e-3 * r
    assert c["label"] == "pair" and c["residues"] == "minimax" and c["gap"] == pytest.approx(gap0, rel=1e-6)


def test_settle_leaves_a_well_conditioned_realisation_alone():
    z, G, dc, ft, peak, A, B, C, D = light_model()
    zb, ub = gap_bounds(z, G)
    c = dict(A=A, B=B, C=C, D=D, err=channel_errors(A, B, C, D, z, G), gap=0.5)
    settle_equalities(c, z, G, dc, ft, peak, zb, ub)
    assert c["A"] is A and c["B"] is B and c["eq_roundoff"] <= ROUNDOFF_TOL and c["eq"] <= EQ_TOL


def _cand(label, err, gap, at_noise=False, rms=None):
    """A candidate as pick_candidates sees it (its equalities hold)."""
    c = dict(label=label, err=np.array(err, dtype=float), gap=gap, eq=0.0, eq_roundoff=0.0, at_noise=at_noise)
    if rms is not None:
        c["rms"] = np.array(rms, dtype=float)
    return c


@pytest.mark.parametrize("free_err, free_gap, at_noise, taken", [
    (0.01, 1.05, True, True),                      # at the noise level, a little over the bounds, 8x better: taken
    (0.01, NOISE_TRUST_GAP + 0.1, True, False),    # far over the bounds: a resonance the samples need not hold
    (0.08 / (NOISE_TRUST - 0.5), 1.05, True, False),   # not NOISE_TRUST times better than the bounded fit
    (0.01, 1.05, False, False),                    # noise-free data: only the 100x rule of `trust` applies
    (0.0005, 1.05, False, True),                   # ... which this one meets
])
def test_pick_takes_a_fit_over_the_gap_bounds_only_where_the_samples_demand_it(free_err, free_gap, at_noise, taken):
    bounded = _cand("bounded", [0.08], 0.95, at_noise)
    free = _cand("free", [free_err], free_gap, at_noise)
    best = pick_candidates([bounded, free], trust=100.0)[0]
    assert best["label"] == ("free" if taken else "bounded")
    assert free["admissible"] is taken


def test_pick_ranks_fits_at_the_noise_level_by_their_rms_error():
    # at the noise level the largest error is that of one noise sample: the rms decides (the likelihood of
    # Gaussian noise); as soon as one candidate is not at the noise level, the max errors decide as before
    a = _cand("a", [0.030], 0.5, True, rms=[0.012])
    b = _cand("b", [0.031], 0.5, True, rms=[0.010])
    assert pick_candidates([a, b])[0]["label"] == "b"
    a2, b2 = dict(a, at_noise=False), dict(b)
    assert pick_candidates([a2, b2])[0]["label"] == "a"


def _noisy(label, err, gap, rms, between, far):
    """A candidate at the noise level with its estimate between the samples (sysid.relocation._fit_simo)."""
    return dict(_cand(label, [err], gap, True, rms=[rms]), between=np.array([between]), far_between=far)


@pytest.mark.parametrize("near_err, near_rms, near_gap, taken", [
    (0.005, 0.0021, 0.9, "near"),                   # as good on the samples: the fit that does not resonate
    (0.012, 0.0030, 1.5, "near"),                   # 2.4x worse, over the bounds within the noise margin: still
    (0.005 * NOISE_TRUST + 1e-4, 0.0030, 0.9, "far"),   # more than NOISE_TRUST times worse: the samples want the far one
    (0.005, 0.0021, NOISE_TRUST_GAP + 0.1, "far"),  # far over the bounds: not a candidate either
])
def test_a_fit_estimated_far_off_between_the_samples_gives_way_to_one_that_is_not(near_err, near_rms, near_gap,
                                                                                    taken):
    # the first candidate follows the noise with a resonance between two samples (estimated 0.1 off there against
    # 0.005 on them); the second explains the samples nearly as well without it
    far = _noisy("far", 0.005, 0.9, 0.002, 0.1, True)
    near = _noisy("near", near_err, near_gap, near_rms, 0.006, False)
    assert pick_candidates([far, near], trust=100.0)[0]["label"] == taken


def test_fits_that_explain_noisy_samples_equally_well_are_ordered_by_their_estimate_between_them():
    # rms errors within NOISE_RMS_TIE of the best tie; the estimate between the samples decides among them, a NaN
    # estimate last; a fit outside the tie stays behind whatever its estimate
    a = _noisy("a", 0.005, 0.9, 0.0020, 0.030, False)
    b = _noisy("b", 0.005, 0.9, 0.0021, 0.010, False)
    c = _noisy("c", 0.005, 0.9, 0.0020 * NOISE_RMS_TIE * 1.01, 0.001, False)
    d = _noisy("d", 0.005, 0.9, 0.0020, np.nan, False)
    assert [x["label"] for x in pick_candidates([a, b, c, d])] == ["b", "a", "d", "c"]


def test_rms_errors_are_relative_to_each_outputs_peak():
    z, G, dc, ft, peak, A, B, C, D = light_model()
    np.testing.assert_allclose(rms_errors(A, B, C, D, z, G), 0.0, atol=1e-10)
    bias = np.array([[0.01], [0.002]])   # a constant error on each output
    got = rms_errors(A, B, C, D + bias, z, G)
    np.testing.assert_allclose(got, bias[:, 0] / peak, rtol=1e-8)
