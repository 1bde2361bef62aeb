"""Tests of sysid.relocation and of identify's default stable / DC-exact path (algorithm="relocation").

Synthetic continuous systems with known poles are sampled on McKelvey's grid; the bilinear map with the
same T carries them exactly into the model class of the relocation (n continuous poles <-> n discrete
states), so noise-free data must be fitted to round-off.
"""

from pathlib import Path

import numpy as np
import pytest
from sysid_synth import LIGHT, pole_mismatch

import sysid
from sysid import FrequencyDataError, FrequencyResponse, OrderError, identify, mckelvey_grid
from sysid.metrics import max_relative_error
from sysid.pole_refinement import derivative_columns, params_to_poles, refine_poles, stable_params
from sysid.poles import (discrete_basis, initial_poles, pair_poles, partial_fraction_basis, resolution_floor,
                         stability_region)
from sysid.relocation import fit_relocated
from sysid.residues import GAP_FLOOR, GAP_SLACK, gap_bounds, minimax_cd
from sysid.vector_fitting import relocate_poles
from sysid.refit import fit_cd

DATA = Path(__file__).resolve().parents[2] / "docs" / "data"


def continuous_system(poles, p=2, seed=0, d=0.0):
    """SIMO partial-fraction system with the given continuous poles (real, or pairs in canonical order)."""
    rng = np.random.default_rng(seed)
    res = []
    i = 0
    while i < len(poles):
        if poles[i].imag == 0:
            res.append(rng.standard_normal(p) + 0j)
            i += 1
        else:
            r = rng.standard_normal(p) + 1j * rng.standard_normal(p)
            res += [r, np.conj(r)]
            i += 2
    return np.array(poles), np.array(res).T, d  # residues (p, n)


def sample(poles, residues, d, omega):
    H = np.zeros((residues.shape[0], 1, omega.size), dtype=complex)
    fin = np.isfinite(omega)
    s = 1j * omega[fin]
    H[:, 0, fin] = residues @ (1.0 / (s[None, :] - poles[:, None])) + d
    H[:, 0, ~fin] = d
    return H


def frf_of(poles, T=1.0, M=128, p=2, seed=0, d=0.0):
    wd, w = mckelvey_grid(M, T)
    pl, r, d = continuous_system(poles, p, seed, d)
    return FrequencyResponse(sample(pl, r, d, w), wd, T, outputs=[f"y{i}" for i in range(p)]), pl


def to_continuous(A, T):
    lam = np.linalg.eigvals(A)
    return (2.0 / T) * (lam - 1.0) / (lam + 1.0)


# ---------------------------------------------------------------------------- exact recovery
NEAR_REAL = [-0.05, -0.0525, -0.4 + 0.02j, -0.4 - 0.02j, -2.0]  # two real poles 5 % apart, a pair nearly real


@pytest.mark.parametrize("poles", [LIGHT, NEAR_REAL], ids=["lightly-damped", "nearly-real"])
def test_exact_recovery_through_identify(poles):
    frf, true = frf_of(np.array(poles, dtype=complex))
    n = len(poles)
    res = identify(frf, n, dc_gain="match", stable=True)
    assert res.algorithm == "relocation" and res.model.nstates == n
    # noise-free data of a system in the model class: the fit is exact up to the conditioning of the partial
    # fraction basis (poles 5 % apart, cond ~1e4 at most) times round-off, far below 1e-7
    assert res.max_error < 1e-7
    # poles: a pole's sensitivity to a relative data perturbation eps is ~ eps / (residue size x separation);
    # with fit errors ~1e-10 and separations >= 2.5e-3 (NEAR_REAL) that is < 1e-6 relative
    assert pole_mismatch(to_continuous(np.asarray(res.model.A), frf.T), true) < 1e-5 * np.abs(true).max()
    assert res.dc_error < 1e-12 and res.spectral_radius < 1 - 1e-3


def test_exact_recovery_single_output_with_feedthrough():
    frf, true = frf_of(np.array(LIGHT[:4], dtype=complex), p=1, seed=3, d=0.7)
    res = identify(frf, 4, dc_gain="match", stable=True)
    assert res.max_error < 1e-7
    assert abs(res.evaluate([np.pi])[0, 0, 0] - 0.7) < 1e-12  # the omega = inf sample, imposed exactly


# ---------------------------------------------------------------------------- constraints and stability
def noisy_frf(seed=0, sigma=1e-3):
    frf, _ = frf_of(np.array(LIGHT, dtype=complex), M=64, seed=seed)
    rng = np.random.default_rng(100 + seed)
    H = np.array(frf.H)
    H[:, :, 1:-1] += sigma * (rng.standard_normal(H[:, :, 1:-1].shape) + 1j * rng.standard_normal(H[:, :, 1:-1].shape))
    return FrequencyResponse(H, frf.omega_d, frf.T)


@pytest.mark.filterwarnings("ignore:the order-.* model has a resonance")   # overfitted noise: asserted elsewhere
@pytest.mark.parametrize("order", [3, 6, 11])
def test_dc_and_feedthrough_exact_on_noisy_data(order):
    frf = noisy_frf()
    res = identify(frf, order, dc_gain="match", stable=True)
    G0 = res.evaluate([0.0])[:, :, 0]
    Gpi = res.evaluate([np.pi])[:, :, 0]
    peak = np.abs(frf.H).max()
    # equalities imposed in closed form / by exact projection; the only error is round-off in evaluating
    # C (zI - A)^-1 B + D in the input-normal basis (|C| ~ |H|), i.e. a few eps times the peak
    assert np.abs(G0 - frf.H[:, :, 0]).max() <= 1e-10 * peak
    assert np.abs(Gpi - frf.H[:, :, -1]).max() <= 1e-10 * peak
    assert res.enforced == {"dc_gain": True, "feedthrough": True, "stable": True}


def test_stable_where_the_best_unconstrained_fit_is_not():
    # a response with an unstable (right-half-plane, nearly real) pole, as the aerofoil data's negative-time
    # content suggests: the exact unconstrained fit is unstable, the relocation's is stable with the margin
    poles = np.array([0.3, -0.2 + 1.0j, -0.2 - 1.0j, -1.0], dtype=complex)
    wd, w = mckelvey_grid(128, 1.0)
    pl, r, d = continuous_system(poles, 2, 1)
    frf = FrequencyResponse(sample(pl, r, d, w), wd, 1.0)
    plain = identify(frf, 4)
    assert plain.spectral_radius > 1.0 and plain.max_error < 1e-8  # the best fit is unstable
    for margin in (1e-3, 0.05):
        res = identify(frf, 4, dc_gain="match", stable=True, margin=margin)
        assert res.spectral_radius <= 1 - margin
        assert res.dc_error < 1e-12
        # a stable model cannot be exact here, but must not be useless either
        assert res.max_error < 1.0


def test_relocated_poles_stay_in_the_region():
    frf = noisy_frf(seed=2, sigma=3e-2)
    s = 1j * frf.omega[:-1]
    H = np.asarray(frf.H)[:, 0, :-1]
    reg = stability_region(frf.T, 1 - 1e-2) + (1e3,)
    pl, _ = relocate_poles(s, H, initial_poles(frf.omega, 9), region=reg, lawson=3)
    A, _ = discrete_basis(pl, frf.T)
    assert np.abs(np.linalg.eigvals(A)).max() <= 1 - 1e-2
    assert np.all(pl.real < 0)


# ---------------------------------------------------------------------------- never worse than the start
def test_refinement_never_increases_the_cost():
    frf = noisy_frf(seed=4, sigma=1e-2)
    s = 1j * frf.omega[:-1]
    H = np.asarray(frf.H)[:, 0, :-1]
    true = np.array(LIGHT, dtype=complex)
    p0 = true.real * 1.5 + 1j * true.imag * 1.03  # the true poles, 3 % off in frequency, 50 % in damping

    def cost(pl):
        Phi = np.hstack([partial_fraction_basis(s, pl), np.ones((s.size, 1))])
        A = np.vstack([Phi.real, Phi.imag])
        return sum(np.linalg.lstsq(A, np.concatenate([h.real, h.imag]), rcond=None)[1].sum() for h in H)

    pr = refine_poles(s, H, p0, max_nfev=30)
    assert np.all(pr.real < 0)
    assert cost(pr) <= cost(p0)
    # and it gets to the noise level: the start's misfit is dominated by the shifted resonances (cost ~1e4);
    # at the true poles only the noise remains (2 x 2K samples of variance 1e-4: cost ~ 0.05)
    assert cost(pr) < 1e-3 * cost(p0)
    assert pole_mismatch(pr, true) < 1e-2


def test_minimax_residues_never_worse_than_least_squares():
    frf = noisy_frf(seed=5, sigma=1e-2)
    z, G = frf.z, np.asarray(frf.H)
    pl = initial_poles(frf.omega, 6, "log")
    A, B = discrete_basis(pl, frf.T)
    dc, ft = G[:, :, 0].real, G[:, :, -1].real
    ls = fit_cd(A, B, z, G, dc_gain=dc, feedthrough=ft, solver="numpy")
    C, D, status = minimax_cd(A, B, z, G, dc_gain=dc, feedthrough=ft, start=(ls.C, ls.D))
    from sysid.subspace import evaluate_ss

    e_ls = max_relative_error(evaluate_ss(A, B, ls.C, ls.D, z), G, per_output=True)
    e_mm = max_relative_error(evaluate_ss(A, B, C, D, z), G, per_output=True)
    assert np.all(e_mm <= e_ls * (1 + 1e-12))
    Gc = evaluate_ss(A, B, C, D, np.array([1.0, -1.0], dtype=complex))
    assert np.abs(Gc[:, :, 0] - dc).max() < 1e-10 * np.abs(G).max()
    assert np.abs(Gc[:, :, 1] - ft).max() < 1e-10 * np.abs(G).max()


@pytest.mark.parametrize("within", [0.02, 0.1])
def test_minimax_then_least_squares_within_the_minimax_level(within):
    # the lexicographic second stage: max error at most (1 + within) of the minimax level (the solver's
    # tolerance is 1e-9 of the unit-scaled data, far below the 1e-6 margin asked here), the equalities still
    # exact, and a sum of squared errors no larger than the minimax answer's (it is feasible for stage two)
    from sysid.subspace import evaluate_ss

    frf = noisy_frf(seed=5, sigma=1e-2)
    z, G = frf.z, np.asarray(frf.H)
    dc, ft = G[:, :, 0].real, G[:, :, -1].real
    A, B = discrete_basis(fit_relocated(frf.omega, z, G, frf.T, 6, dc_gain=dc, feedthrough=ft).poles, frf.T)
    C0, D0, _ = minimax_cd(A, B, z, G, dc_gain=dc, feedthrough=ft)
    C, D, status = minimax_cd(A, B, z, G, dc_gain=dc, feedthrough=ft, within=within)
    assert status.startswith("optimal")
    E0 = evaluate_ss(A, B, C0, D0, z) - G
    E = evaluate_ss(A, B, C, D, z) - G
    for i in range(G.shape[0]):
        assert np.abs(E[i]).max() <= (1 + within) * np.abs(E0[i]).max() * (1 + 1e-6)
        assert np.sum(np.abs(E[i]) ** 2) <= np.sum(np.abs(E0[i]) ** 2) * (1 + 1e-6)
    # the second stage has room here (fitted poles, noise 1e-2: the minimax error is flat at 0.027; least
    # squares within 2 % of it lowers the sum of squares by 11 %)
    assert np.sum(np.abs(E) ** 2) < 0.95 * np.sum(np.abs(E0) ** 2)
    Gc = evaluate_ss(A, B, C, D, np.array([1.0, -1.0], dtype=complex))
    assert np.abs(Gc[:, :, 0] - dc).max() < 1e-10 * np.abs(G).max()
    assert np.abs(Gc[:, :, 1] - ft).max() < 1e-10 * np.abs(G).max()


@pytest.mark.parametrize("bad", [-0.1, 0.0, float("nan"), "0.1"])
def test_minimax_within_must_be_a_positive_fraction(bad):
    with pytest.raises(sysid.OptionError, match="minimax_within must be a positive fraction"):
        identify(noisy_frf(seed=5), 4, dc_gain="match", stable=True, minimax_within=bad)


def test_result_never_worse_than_its_candidates():
    # every candidate (plain relocation from each start, Lawson, Gauss-Newton, least-squares or minimax
    # residues) is a feasible model; the pick minimises the worst ratio of an output's error to the best
    # error any admissible candidate reached on that output, so no admissible candidate beats it on that
    frf = noisy_frf(seed=6, sigma=1e-2)
    G = np.asarray(frf.H)
    rl = fit_relocated(frf.omega, frf.z, G, frf.T, 6, dc_gain=G[:, :, 0].real, feedthrough=G[:, :, -1].real)
    ok = [e for _, e, adm in rl.candidates if adm]
    assert len(ok) >= 2  # (starts that relocate to the same poles as an earlier one are not repeated)
    best = np.min(ok, axis=0)
    ratio = lambda e: np.max(e / best)  # noqa: E731
    assert ratio(rl.max_error_per_output) <= min(ratio(e) for e in ok) * (1 + 1e-12)


# ---------------------------------------------------------------------------- identify options and paths
# expected: the lightly damped test system's own resonance (0.5 % damping) lies between the samples
@pytest.mark.filterwarnings("ignore:the order-6 model has a resonance:RuntimeWarning")
def test_unconstrained_identify_is_the_subspace_method():
    frf = noisy_frf(seed=7)
    a = identify(frf, 6)
    b = identify(frf, 6, algorithm="subspace")
    assert a.algorithm == "subspace" and a.relocation is None
    # the same computation twice; not bitwise: a multithreaded BLAS may sum in another order from one call to
    # the next (B differed by 1e-14 relative on a loaded 2-core machine), so equal to a few hundred eps
    for X, Y in [(a.model.A, b.model.A), (a.model.B, b.model.B), (a.model.C, b.model.C), (a.model.D, b.model.D)]:
        np.testing.assert_allclose(np.asarray(X), np.asarray(Y), rtol=0, atol=1e-13 * max(np.abs(Y).max(), 1.0))


@pytest.mark.filterwarnings("ignore:the order-.* model has a resonance")   # order 20 on noisy data
def test_old_stable_path_reachable():
    frf = noisy_frf(seed=8, sigma=3e-2)
    res = identify(frf, 20, dc_gain="match", stable=True, algorithm="subspace")
    assert res.algorithm == "subspace" and res.stabilisation.method in ("lmi", "none")
    new = identify(frf, 20, dc_gain="match", stable=True)
    assert new.algorithm == "relocation" and "pole relocation" in new.summary()
    assert new.relocation is not None and new.relocation.seconds > 0


def test_mimo_auto_keeps_the_subspace_algorithm():
    from sysid_synth import freqresp, random_system

    A, B, C, D, _ = random_system(6, 2, 2, 0)
    wd, _ = mckelvey_grid(64, 1.0)
    frf = FrequencyResponse(freqresp(A, B, C, D, np.exp(1j * wd)), wd, 1.0)
    assert identify(frf, 6, dc_gain="match").algorithm == "subspace"
    # explicitly: the states are split between the input columns (3 + 3), each with poles of its own; the
    # order-12 subspace start is twice the true order, which identify reports
    with pytest.warns(RuntimeWarning, match="the data support order 6"):
        res = identify(frf, 12, dc_gain="match", stable=True, algorithm="relocation")
    assert res.model.nstates == 12 and res.max_error < 1e-6 and res.dc_error < 1e-10


# expected: the paper data are sparse above k ~ 3 (docs/sysid.md, between the samples)
@pytest.mark.filterwarnings("ignore:the order-15 model is not pinned down:RuntimeWarning")
def test_paper_data_beats_the_old_stable_path():
    # T4 (the hardest paper case for Cm): the old stable path's Cm error at N_r = 15 was 0.55 of Cm's peak;
    # stable vector fitting (scikit-rf) at equal order on these data, the peer: 0.0538 (Cl) and 0.0216 (Cm)
    # (docs/sysid.md, bench/sysid_peers_bench.py); the relocation must be below it on both outputs (between
    # the samples it resonates, so the default falls back there: test_identify.py)
    frf = FrequencyResponse.load(DATA / "frf-T4.npz")
    res = identify(frf, 15, dc_gain="match", stable=True, algorithm="relocation")
    assert res.spectral_radius < 1 - 1e-3 and res.dc_error < 1e-10
    assert res.errors.max_rel_per_output[0] < 0.0538 and res.errors.max_rel_per_output[1] < 0.0216


# ---------------------------------------------------------------------------- between the samples
def test_resolution_floor_is_half_the_local_spacing():
    w = np.array([0.0, 1.0, 1.5, 3.5, np.inf])
    xp, fp = resolution_floor(w, 0.5)
    # midpoints of the intervals carry half their width; above the top sample the floor grows with the distance
    np.testing.assert_allclose(xp[:3], [0.5, 1.25, 2.5])
    np.testing.assert_allclose(fp[:3], [0.5, 0.25, 1.0])
    assert np.interp(3.5 + 10.0, xp, fp) == pytest.approx(0.5 * (2.0 + 10.0))
    xp0, fp0 = resolution_floor(w, 0.0)
    assert np.all(fp0 == 0)


def test_pair_poles_moves_unresolved_pairs_left_onto_the_floor():
    w = np.linspace(0.0, 10.0, 11)  # spacing 1: floor 0.5 everywhere inside
    floor = resolution_floor(w, 0.5)
    lam = np.array([-0.01 + 4.2j, -0.01 - 4.2j, -2.0 + 6.0j, -2.0 - 6.0j, -0.05])
    out = pair_poles(lam, 10.0, (-1e6, 1e6 - 1e-6, 1e3, floor))
    np.testing.assert_allclose(out, [-0.05, -0.5 + 4.2j, -0.5 - 4.2j, -2.0 + 6.0j, -2.0 - 6.0j])


def test_floored_parametrisation_derivatives_match_finite_differences():
    # the Gauss-Newton Jacobian with the floor (Re = -(f(Im) + exp(u))) against central differences; the
    # step 1e-7 leaves truncation ~1e-14 and round-off ~1e-9 relative, hence the 1e-6 tolerance
    w = np.concatenate([[0.0], 3.0 * np.tan(np.linspace(0.0, 1.5, 30))[1:]])
    s = 1j * w
    floor = resolution_floor(w, 0.5)
    poles = pair_poles(np.array([-0.5, -0.3 + 1j, -0.3 - 1j, -2 + 9j, -2 - 9j]), 10.0, (-1e3, 1e3 - 1e-3, 1e3, floor))
    theta = np.random.default_rng(0).standard_normal(poles.size)
    x = stable_params(poles, floor)
    J = derivative_columns(s, poles, theta, floor)
    for q in range(x.size):
        e = np.zeros_like(x)
        e[q] = 1e-7
        fd = (partial_fraction_basis(s, params_to_poles(x + e, poles, floor)) @ theta
              - partial_fraction_basis(s, params_to_poles(x - e, poles, floor)) @ theta) / 2e-7
        assert np.abs(fd - J[:, q]).max() <= 1e-6 * np.abs(J[:, q]).max()


def test_gap_bounds_follow_the_neighbouring_samples():
    wd = np.array([0.0, 1.0, 2.0])
    G = np.array([[[1.0, 3.0, 2.0]]], dtype=complex)
    zb, ub = gap_bounds(np.exp(1j * wd), G, refine=2)
    np.testing.assert_allclose(np.angle(zb), [0.5, 1.5, 0.5 * (2.0 + np.pi)])
    np.testing.assert_allclose(ub[0, 0], GAP_SLACK * np.array([3.0, 3.0, 2.0]) + GAP_FLOOR * 3.0)


def test_bounded_minimax_residues_meet_the_bounds():
    # the true poles of a lightly damped system on sparse noisy data (M = 64, noise 1 % of the peak): the free
    # minimax residues overshoot the gap bounds between the samples (5x); the bounded cone programme keeps
    # every dense point within its bound and the equalities exact; a bound below what the poles allow is
    # infeasible and said so
    from sysid import SolverError
    from sysid.subspace import evaluate_ss

    frf = noisy_frf(seed=5, sigma=1e-2)
    z, G = frf.z, np.asarray(frf.H)
    A, B = discrete_basis(np.array(LIGHT, dtype=complex), frf.T)
    dc, ft = G[:, :, 0].real, G[:, :, -1].real
    zb, ub = gap_bounds(z, G)
    C0, D0, _ = minimax_cd(A, B, z, G, dc_gain=dc, feedthrough=ft)
    assert np.max(np.abs(evaluate_ss(A, B, C0, D0, zb)) / ub) > 2.0
    C, D, status = minimax_cd(A, B, z, G, dc_gain=dc, feedthrough=ft, bound=(zb, ub))
    assert status.startswith("optimal")
    # the solver's feasibility tolerance is 1e-9 relative to the unit-scaled data
    assert np.all(np.abs(evaluate_ss(A, B, C, D, zb)) <= ub * (1 + 1e-6))
    Gc = evaluate_ss(A, B, C, D, np.array([1.0, -1.0], dtype=complex))
    assert np.abs(Gc[:, :, 0] - dc).max() < 1e-10 * np.abs(G).max()
    assert np.abs(Gc[:, :, 1] - ft).max() < 1e-10 * np.abs(G).max()
    with pytest.raises(SolverError, match="minimax residue fit failed .*Infeasible"):
        minimax_cd(A, B, z, G, dc_gain=dc, feedthrough=ft, bound=(zb, 0.1 * ub))
    C2, _, _ = minimax_cd(A, B, z, G, dc_gain=dc, feedthrough=ft, bound=(zb, 0.1 * ub), start=(C0, D0))
    assert np.all(np.isnan(C2))  # the start breaks the bound: no model rather than a wrong one


def test_polish_restores_the_equalities_with_the_minimum_norm_change_of_C():
    # an exactly DC- and feedthrough-consistent model whose C is perturbed by 1e-9: the residual is far above
    # EQ_TOL; one polish brings it to round-off, and the change of each row of C is the minimum-norm one that
    # cancels the perturbation's effect at z = +1 and z = -1 (the perturbation's projection onto the span of
    # x_dc = (I - A)^-1 B and x_ft = (-I - A)^-1 B); D, the errors and the gap follow
    from sysid.candidates import EQ_TOL, channel_errors, equality_residual, polish_equalities, with_resonances
    from sysid.subspace import evaluate_ss

    frf, poles = frf_of(LIGHT, T=1.0, M=64)
    z, G = frf.z, np.asarray(frf.H)
    A, B = discrete_basis(np.array(LIGHT, dtype=complex), frf.T)
    dc, ft = G[:, :, 0].real, G[:, :, -1].real
    C0, D0, _ = minimax_cd(A, B, z, G, dc_gain=dc, feedthrough=ft)
    peak = np.abs(G[:, 0]).max(axis=1)
    dC = 1e-9 * np.random.default_rng(3).standard_normal(C0.shape) * np.abs(C0).max()
    c = dict(A=A, B=B, C=C0 + dC, D=D0.copy())
    c["eq"] = equality_residual(c, dc, ft, peak)
    c["err"] = channel_errors(A, B, c["C"], c["D"], z, G)
    assert c["eq"] > 2 * EQ_TOL
    zb, ub = gap_bounds(z, G)
    assert polish_equalities(c, z, G, dc, ft, peak, zb, ub)
    assert c["eq"] < 1e-13 and c["eq"] == equality_residual(c, dc, ft, peak)
    X = np.hstack([np.linalg.solve(np.eye(A.shape[0]) - A, B), np.linalg.solve(-np.eye(A.shape[0]) - A, B)])
    P = X @ np.linalg.pinv(X)  # projector onto span(x_dc, x_ft)
    change = c["C"] - (C0 + dC)
    np.testing.assert_allclose(change, -dC @ P.T, rtol=0, atol=1e-6 * np.abs(dC).max())
    np.testing.assert_array_equal(c["D"], D0)
    np.testing.assert_allclose(c["err"], channel_errors(A, B, c["C"], D0, z, G), rtol=0, atol=0)
    zr, ur = with_resonances(c, zb, ub)   # the bounds' points and the peaks of the model's resonances
    assert zr.size > zb.size
    assert c["gap"] == pytest.approx(float(np.max(np.abs(evaluate_ss(A, B, c["C"], D0, zr)) / ur)))
    assert not polish_equalities(dict(c, eq=0.0), z, G, dc, ft, peak)  # nothing to gain: unchanged


def test_equalities_are_checked_on_the_model_and_against_the_roundoff_of_its_evaluation():
    # adding to C a huge component orthogonal to x_dc and x_ft keeps the equalities in exact arithmetic, but a
    # double evaluation of the DC gain is then uncertain by eps sum |C_ij x_j| >> ROUNDOFF_TOL (and storing C
    # alone loses about as much): inadmissible, whatever its errors
    from sysid.candidates import ROUNDOFF_TOL, check_equalities, pick_candidates

    frf, _ = frf_of(LIGHT, T=1.0, M=64)
    z, G = frf.z, np.asarray(frf.H)
    A, B = discrete_basis(np.array(LIGHT, dtype=complex), frf.T)
    dc, ft = G[:, :, 0].real, G[:, :, -1].real
    C0, D0, _ = minimax_cd(A, B, z, G, dc_gain=dc, feedthrough=ft)
    peak = np.abs(G[:, 0]).max(axis=1)
    n = A.shape[0]
    X = np.hstack([np.linalg.solve(np.eye(n) - A, B), np.linalg.solve(-np.eye(n) - A, B)])  # (n, 2)
    w = np.random.default_rng(4).standard_normal(n)
    w -= X @ np.linalg.lstsq(X, w, rcond=None)[0]  # orthogonal to x_dc and x_ft
    good = dict(A=A, B=B, C=C0, D=D0, err=np.array([0.2, 0.2]), gap=0.5)
    bad = dict(A=A, B=B, C=C0 + 1e7 * peak[:, None] * w / np.abs(w).max(), D=D0, err=np.array([0.1, 0.1]), gap=0.5)
    for c in (good, bad):
        check_equalities(c, dc, ft, peak)
    assert good["eq"] < 1e-13 and good["eq_roundoff"] < 1e-14
    assert bad["eq_roundoff"] > 10 * ROUNDOFF_TOL
    picked = pick_candidates([bad, good])
    assert picked[0] is good and not bad["admissible"]


# expected: the paper data are sparse above k ~ 3 (docs/sysid.md, between the samples)
@pytest.mark.filterwarnings("ignore:the order-.* model is not pinned down between the samples:RuntimeWarning")
@pytest.mark.parametrize("case, order", [("T4", 25), ("T4", 55), ("T5", 55)])
def test_paper_data_default_stays_within_the_gap_bounds(case, order):
    # without the floor and the bounds these relocations resonated between omega = 14.6 and 29.2 (gain 28 x,
    # 29 x and 12 x the output's data peak), and stable vector fitting's N_r = 55 models of T4 and T5 do
    # (888 x and 3e4 x, bench/sysid_peers_bench.py); the default now stays within the gap bounds, below VF's
    # sample errors on T4 (N_r 25: 5.5 % / 3.9 %; N_r 55: 0.87 % / 1.6 %, ibid.; ours 0.4-1.8 %) and within
    # 0.5 % on T5 N_r 55 (measured 0.22 % / 0.18 %; VF's 0.22 % / 0.25 % come with its 3e4 x resonance between
    # the samples). Before the balanced coordinates of sysid.candidates.settle_equalities, T5 N_r 55 returned
    # 1.84 % / 0.99 % on one machine and 0.27 % / 0.20 % on another: its best candidates sat at the round-off
    # bound of the DC equality; the 2x margin here is for the round-off-level choices that remain
    from sysid.identify import UNOBSERVED_GAIN_LIMIT, unobserved_gain

    frf = FrequencyResponse.load(DATA / f"frf-{case}.npz")
    res = identify(frf, order, dc_gain="match", stable=True)
    assert res.algorithm == "relocation" and res.spectral_radius < 1.0 and res.dc_error < 1e-10
    zb, ub = gap_bounds(frf.z, np.asarray(frf.H))
    assert np.all(np.abs(res.evaluate(np.angle(zb))) <= ub * (1 + 1e-6))
    assert unobserved_gain(res.model, frf).max() < UNOBSERVED_GAIN_LIMIT
    limit = {("T4", 25): (0.055, 0.039), ("T4", 55): (0.0087, 0.016), ("T5", 55): (0.005, 0.005)}[(case, order)]
    assert np.all(res.errors.max_rel_per_output <= limit)


@pytest.mark.filterwarnings("ignore:the order-.* model is not pinned down between the samples:RuntimeWarning")
@pytest.mark.parametrize("case, order, skipped", [("T4", 25, 1), ("T1", 25, 0)])
def test_free_minimax_skipped_only_where_the_floored_pass_follows(case, order, skipped, monkeypatch):
    # T4 at N_r = 25: the best free least-squares fit breaks the gap bounds 23 times over, the floored pass follows
    # and returns the model, so the free pass's minimax fit is not made; T1 at 25 (within 0.77 of the bounds)
    # keeps it. Either way the model is the one made with that fit (the same arithmetic)
    import sysid.relocation as relocation

    frf = FrequencyResponse.load(DATA / f"frf-{case}.npz")
    calls = []
    monkeypatch.setattr(relocation, "minimax_cd", lambda *a, **k: calls.append(1) or minimax_cd(*a, **k))
    res = identify(frf, order, dc_gain="match", stable=True)
    n_skipping = len(calls)
    monkeypatch.setattr(relocation, "_FLOORED_SURE", np.inf)   # the free minimax fit always made
    ref = identify(frf, order, dc_gain="match", stable=True)
    assert len(calls) - n_skipping == n_skipping + skipped
    np.testing.assert_array_equal(res.matrices.A, ref.matrices.A)
    np.testing.assert_array_equal(res.matrices.C, ref.matrices.C)


# ---------------------------------------------------------------------------- bad input
def test_order_too_large():
    frf = noisy_frf()
    with pytest.raises(OrderError, match="order"):
        identify(frf, 200, dc_gain="match", stable=True)
    G = np.asarray(frf.H)[:, :, :5]
    with pytest.raises(OrderError, match="real data per output"):
        fit_relocated(frf.omega[:5], frf.z[:5], G, frf.T, 9)
    with pytest.raises(OrderError, match="positive integer"):
        fit_relocated(frf.omega, frf.z, np.asarray(frf.H), frf.T, 0)


def test_nan_data():
    frf = noisy_frf()
    G = np.array(frf.H)
    G[1, 0, 7] = np.nan
    with pytest.raises(FrequencyDataError, match="NaN"):
        fit_relocated(frf.omega, frf.z, G, frf.T, 4)
    with pytest.raises(FrequencyDataError, match="NaN"):
        FrequencyResponse(G, frf.omega_d, frf.T)


def siso_frf():
    wd, w = mckelvey_grid(32, 1.0)
    s = 1j * np.where(np.isfinite(w), w, 0.0)
    return FrequencyResponse(np.where(np.isfinite(w), 1.0 / (s ** 2 + 0.4 * s + 1.0), 0.0).reshape(1, 1, -1), wd, 1.0)


def _with(a, k, v):
    a = np.array(a)
    a[k] = v
    return a


@pytest.mark.parametrize("change, error, what", [
    (dict(T=0.0), sysid.FrequencyGridError, "T must be positive and finite"),
    (dict(T=-1.0), sysid.FrequencyGridError, "T must be positive and finite"),
    (dict(omega=lambda w: _with(w, 3, np.nan)), sysid.FrequencyGridError, r"omega\[3\] = nan"),
    (dict(omega=lambda w: _with(w, 3, -5.0)), sysid.FrequencyGridError, r"omega\[3\] = -5.0"),
    (dict(omega=lambda w: _with(w, 4, w[3])), sysid.FrequencyGridError, r"omega\[3\] and omega\[4\] are the same"),
    (dict(weights=np.ones(5)), FrequencyDataError, r"weights must have shape \(K,\) = \(33,\)"),
    (dict(weights=-np.ones(33)), FrequencyDataError, "finite and nonnegative"),
    (dict(dc_gain=np.ones(2)), sysid.ConstraintError, r"dc_gain must have shape \(p, m\) = \(1, 1\)"),
    (dict(feedthrough=1j), sysid.ConstraintError, "feedthrough must be real"),
    (dict(G=lambda G: 0 * G), FrequencyDataError, "output 0 is zero at every frequency"),
    # counts and budgets: a negative iteration count ran no relocation (error 2e-15 -> 0.08, no complaint)
    (dict(iterations=-1), sysid.OptionError, "iterations must be a whole number >= 0"),
    (dict(lawson=-1), sysid.OptionError, "lawson must be a whole number >= 0"),
    (dict(refine=1.5), sysid.OptionError, "refine must be a whole number >= 0"),
    (dict(minimax_rounds=-1), sysid.OptionError, "minimax_rounds must be a whole number >= 0"),
    (dict(budget=-1.0), sysid.OptionError, "budget must be a positive number of seconds"),
    (dict(start_poles="x"), sysid.OptionError, "start_poles must be a dict"),
])
def test_fit_relocated_bad_arguments(change, error, what):
    frf = siso_frf()
    args = dict(omega=np.array(frf.omega), z=frf.z, G=np.asarray(frf.H), T=1.0)
    for k, v in change.items():
        args[k] = v(args[k]) if callable(v) else v
    with pytest.raises(error, match=what):
        fit_relocated(args.pop("omega"), args.pop("z"), args.pop("G"), args.pop("T"), 2, **args)


def test_fit_relocated_scalar_dc_gain_and_vector_weights():
    # (K,) weights and a scalar DC gain of a one-input one-output system, as refit.fit_bd accepts them
    frf = siso_frf()
    G = np.asarray(frf.H)
    ref = fit_relocated(frf.omega, frf.z, G, 1.0, 2, dc_gain=np.ones((1, 1)), weights=np.ones((1, 1, 33)))
    rl = fit_relocated(frf.omega, frf.z, G, 1.0, 2, dc_gain=1.0, weights=np.ones(33))
    np.testing.assert_allclose(np.sort_complex(rl.poles), np.sort_complex(ref.poles), rtol=1e-12)
    np.testing.assert_allclose(rl.max_error_per_output, ref.max_error_per_output, rtol=1e-9, atol=1e-14)


def test_fit_relocated_zero_pair_of_a_two_input_fit():
    frf = siso_frf()
    h = np.asarray(frf.H)[0, 0]
    G = np.stack([np.stack([h, 0 * h]), np.stack([h, 2 * h])])  # (2, 2, K): output 0 does not see input 1
    with pytest.raises(FrequencyDataError, match="response of output 0 to input 1 is zero at every frequency"):
        fit_relocated(frf.omega, frf.z, G, 1.0, 4)


def test_bad_algorithm_and_margin():
    frf = noisy_frf()
    with pytest.raises(sysid.OptionError, match="algorithm"):
        identify(frf, 4, algorithm="vf")
    with pytest.raises(sysid.OptionError, match="margin"):
        fit_relocated(frf.omega, frf.z, np.asarray(frf.H), frf.T, 4, margin=0.0)
    with pytest.raises(sysid.OptionError, match="rho"):
        stability_region(1.0, 1.0)
    for bad in (-0.5, np.nan, np.inf):
        with pytest.raises(sysid.OptionError, match="resolution must be a finite number >= 0"):
            fit_relocated(frf.omega, frf.z, np.asarray(frf.H), frf.T, 4, resolution=bad)
    with pytest.raises(sysid.OptionError, match=r"effort must be one of \('fast', 'thorough'\)"):
        fit_relocated(frf.omega, frf.z, np.asarray(frf.H), frf.T, 4, effort=None)


@pytest.mark.parametrize("case, order", [("T1", 15), ("T4", 25), ("T6", 40)])
def test_both_efforts_give_stable_dc_exact_models_that_beat_the_relocation_alone(case, order):
    # the paper's LFD data: either effort ends stable with the DC gain exact, and its error is below that of the
    # relaxed vector-fitting iterations alone (the "log" start's relocated poles with least-squares residues,
    # i.e. what vector fitting would give), which both efforts start from; "thorough" builds a superset of
    # "fast"'s first-pass candidates but may pick differently, so neither is asserted better than the other
    frf = sysid.FrequencyResponse.load(Path(__file__).resolve().parents[2] / "docs" / "data" / f"frf-{case}.npz")
    G = np.asarray(frf.H)
    dc, ft = frf.dc_gain.real, frf.feedthrough.real
    for effort in ("fast", "thorough"):
        rl = fit_relocated(frf.omega, frf.z, G, frf.T, order, dc_gain=dc, feedthrough=ft, effort=effort)
        assert np.abs(np.linalg.eigvals(rl.A)).max() <= 1 - 1e-3 + 1e-12
        model_dc = (rl.C @ np.linalg.solve(np.eye(order) - rl.A, rl.B) + rl.D)
        assert np.abs(model_dc - dc).max() <= 1e-9 * np.abs(dc).max()   # the equality, to round-off of the solve
        relocated = dict((label, err) for label, err, _ in rl.candidates)["log"]
        assert rl.max_error_per_output.max() < relocated.max()


# expected: the lightly damped test system's own resonance (0.5 % damping) lies between the samples
@pytest.mark.filterwarnings("ignore:the order-6 model has a resonance:RuntimeWarning")
def test_weights_reach_the_relocation():
    # the studies' "inverse_magnitude" weights (squared-residual weights, shape (p, m, K)) go through the
    # relocation path: the fit still holds the equalities and is stable, and the weights change it
    frf = noisy_frf(seed=9, sigma=1e-2)
    H = np.asarray(frf.H)
    a = np.abs(H)
    w = 1.0 / np.maximum(a, 1e-3 * a.max(axis=-1, keepdims=True)) ** 2
    plain = identify(frf, 6, dc_gain="match", stable=True)
    weighted = identify(frf, 6, dc_gain="match", stable=True, weights=w)
    assert weighted.algorithm == "relocation" and weighted.dc_error < 1e-10
    assert weighted.spectral_radius < 1 - 1e-3
    assert not np.allclose(weighted.evaluate(frf.omega_d), plain.evaluate(frf.omega_d), rtol=0, atol=1e-12)
    with pytest.raises(sysid.FrequencyDataError, match="weights"):
        identify(frf, 6, dc_gain="match", stable=True, weights=-w)


def test_result_pickles_and_data_without_constraint_samples():
    import pickle

    # data on an arbitrary grid without omega = 0 and omega = inf: no equality is imposed, the fit is exact
    pl, r, d = continuous_system(np.array(LIGHT[:4], dtype=complex), 2, 11)
    w = np.geomspace(0.05, 20.0, 60)
    frf = FrequencyResponse.from_continuous(sample(pl, r, d, w), w, 1.0)
    res = identify(frf, 4, stable=True)
    assert res.algorithm == "relocation" and res.enforced["dc_gain"] is False and res.enforced["feedthrough"] is False
    assert res.max_error < 1e-7  # exact data in the model class, as in test_exact_recovery_through_identify
    back = pickle.loads(pickle.dumps(res))  # process pools (studies.run.runner) ship results
    assert back.algorithm == "relocation" and back.relocation.start == res.relocation.start
    np.testing.assert_array_equal(np.asarray(back.model.A), np.asarray(res.model.A))


def test_two_inputs_one_output_fitted_through_the_transpose():
    from sysid_synth import freqresp, random_system

    # p < m: the relocation fits G^T (common poles for the two input columns) and transposes back, so a
    # 6-state MISO system is recovered with 6 states (round-off level, as for the SIMO systems above)
    A, B, C, D, poles = random_system(6, 1, 2, 3)
    wd, _ = mckelvey_grid(64, 1.0)
    frf = FrequencyResponse(freqresp(A, B, C, D, np.exp(1j * wd)), wd, 1.0)
    res = identify(frf, 6, dc_gain="match", stable=True)
    assert res.algorithm == "relocation" and res.model.nstates == 6
    assert res.max_error < 1e-8 and res.dc_error < 1e-12
    assert pole_mismatch(np.linalg.eigvals(np.asarray(res.model.A)), poles) < 1e-6


@pytest.mark.parametrize("kw, error, match", [
    # the imaginary part of the weights was dropped with a ComplexWarning, text raised a bare ValueError
    (dict(weights=np.ones(33) * (1 + 1j)), FrequencyDataError, "weights must be real and nonnegative"),
    (dict(dc_gain=[["a"], ["b"]]), sysid.ConstraintError, r"dc_gain must be an array of real numbers of shape \(p, m\)"),
])
def test_identify_refuses_complex_weights_and_text_constraints(kw, error, match):
    wd, _ = mckelvey_grid(32, 1.0)
    frf = FrequencyResponse.from_model(__import__("control").ss([[0.9, 0.1], [-0.1, 0.8]], [[1.0], [0.5]], np.eye(2),
                                                                [[0.1], [0.0]], 1.0), wd)
    with pytest.raises(error, match=match):
        identify(frf, 2, stable=True, **kw)


def test_fit_relocated_refuses_points_z_of_other_frequencies_than_omega():
    wd, w = mckelvey_grid(32, 1.0)
    G = (1.0 / (np.exp(1j * wd) - 0.5)).reshape(1, 1, -1)
    with pytest.raises(sysid.FrequencyGridError, match=r"z\[1\] = .* is not the point of omega\[1\] = 0.294761 with T = 1"):
        fit_relocated(3 * w, np.exp(1j * wd), G, 1.0, 2)


def test_fit_relocated_takes_z_and_omega_as_close_as_a_frequency_response_does():
    # FrequencyResponse lets omega_d and omega disagree by rtol 1e-9 (on omega_d); so does fit_relocated
    wd, w = mckelvey_grid(64, 1.0)
    frf = FrequencyResponse((1.0 / (1j * w[:-1] + 1.0)).reshape(1, 1, -1), wd[:-1] * (1 + 9e-10), 1.0, omega=w[:-1])
    assert identify(frf, 1, algorithm="relocation").max_error < 1e-6


def test_complex_weights_of_zero_imaginary_part_are_taken():
    # e.g. |H|^2 written as H * H.conj(): complex type, real values (as dc_gain takes them)
    wd, _ = mckelvey_grid(32, 1.0)
    H = (1.0 / (np.exp(1j * wd) - 0.5)).reshape(1, 1, -1)
    frf = FrequencyResponse(H, wd, 1.0)
    a = identify(frf, 1, stable=True, weights=(H * H.conj()).ravel())
    b = identify(frf, 1, stable=True, weights=np.abs(H).ravel() ** 2)
    # the two weights agree to round-off (1e-16 relative), the exact order-1 fit is well conditioned
    np.testing.assert_allclose(a.matrices.A, b.matrices.A, rtol=1e-12)
