"""Tests of the convex B/D and C/D refits (sysid.refit)."""

import warnings

import numpy as np
import pytest

import sysid

from sysid.errors import ConstraintError, FrequencyDataError
from sysid import refit, refit_solvers
from sysid.refit import BDFit, fit_alternating, fit_bd, fit_cd, frequency_response


def random_system(n, p, m, seed, radius=0.95):
    """A stable, non-normal real discrete system with distinct poles."""
    rng = np.random.default_rng(seed)
    blocks = []
    for _ in range(n // 2):
        r = radius * rng.uniform(0.6, 1.0)
        th = rng.uniform(0.05, 3.0)
        blocks.append(r * np.array([[np.cos(th), -np.sin(th)], [np.sin(th), np.cos(th)]]))
    if n % 2:
        blocks.append(np.array([[rng.uniform(-0.5, 0.8)]]))
    A0 = np.zeros((n, n))
    i = 0
    for b in blocks:
        k = b.shape[0]
        A0[i:i + k, i:i + k] = b
        i += k
    # a moderately conditioned similarity (singular values in [0.5, 2]): non-normal, yet well posed
    U = np.linalg.qr(rng.standard_normal((n, n)))[0]
    V = np.linalg.qr(rng.standard_normal((n, n)))[0]
    T = U @ np.diag(rng.uniform(0.5, 2.0, n)) @ V
    A = T @ A0 @ np.linalg.inv(T)
    return A, rng.standard_normal((n, m)), rng.standard_normal((p, n)), rng.standard_normal((p, m))


@pytest.fixture
def grid():
    return np.exp(1j * np.linspace(0.0, np.pi, 129))


def noisy(G, level, seed):
    rng = np.random.default_rng(seed)
    return G + level * (rng.standard_normal(G.shape) + 1j * rng.standard_normal(G.shape))


def dc_elimination_oracle(A, C, z, G, dc):
    """docs/references.md section 5: eliminate D. G(z) - G0 = (1 - z) C (zI - A)^-1 (I - A)^-1 B is plain LS in
    X = (I - A)^-1 B; then B = (I - A) X and D = G0 - C X. (Unweighted; stacked Re/Im; per input column.)"""
    n = A.shape[0]
    p, m, K = G.shape
    X = np.zeros((n, m))
    for j in range(m):
        rows = []
        rhs = []
        for k in range(K):
            F = C @ np.linalg.inv(z[k] * np.eye(n) - A) * (1 - z[k])  # (p, n)
            rows.append(F)
            rhs.append(G[:, j, k] - dc[:, j])
        Phi = np.vstack(rows)
        g = np.concatenate(rhs)
        X[:, j] = np.linalg.lstsq(np.vstack([Phi.real, Phi.imag]), np.concatenate([g.real, g.imag]), rcond=None)[0]
    B = (np.eye(n) - A) @ X
    D = dc - C @ X
    return B, D


@pytest.mark.parametrize("n,p,m", [(4, 1, 1), (8, 2, 1), (7, 2, 3), (20, 1, 1)])
def test_recovers_exact_system(n, p, m, grid):
    A, B, C, D = random_system(n, p, m, seed=n + 10 * p + 100 * m)
    G = frequency_response(A, B, C, D, grid)
    for solver in ("clarabel", "numpy"):
        r = fit_bd(A, C, grid, G, solver=solver)
        assert isinstance(r, BDFit)
        assert r.B.shape == (n, m) and r.D.shape == (p, m)
        assert np.allclose(r.B, B, atol=1e-8 * np.abs(B).max())
        assert np.allclose(r.D, D, atol=1e-9)
        assert r.residual < 1e-18
    # with the exact DC gain and Nyquist value imposed, the exact system is still the answer
    r = fit_bd(A, C, grid, G, dc_gain=G[:, :, 0].real, feedthrough=G[:, :, -1].real)
    assert r.solver == "clarabel"
    assert np.allclose(r.B, B, atol=1e-7 * np.abs(B).max()) and np.allclose(r.D, D, atol=1e-8)


@pytest.mark.parametrize("n,p,m", [(6, 1, 1), (10, 2, 1), (8, 2, 2), (30, 1, 1)])
def test_dc_constraint_exact_on_noisy_data_and_matches_oracles(n, p, m, grid):
    A, B, C, D = random_system(n, p, m, seed=3 * n + p + m)
    G = frequency_response(A, B, C, D, grid)
    Gn = noisy(G, 0.02 * np.abs(G).max(), seed=n)
    dc = G[:, :, 0].real + 0.05  # deliberately not the LS optimum
    r = fit_bd(A, C, grid, Gn, dc_gain=dc)
    achieved = C @ np.linalg.solve(np.eye(n) - A, r.B) + r.D
    assert np.abs(achieved - dc).max() < 1e-10
    assert r.constraint_residual < 1e-10
    # closed-form null-space oracle
    o = fit_bd(A, C, grid, Gn, dc_gain=dc, solver="numpy")
    assert o.solver == "numpy"
    scale = np.abs(o.B).max()
    assert np.abs(r.B - o.B).max() < 1e-8 * scale
    assert np.abs(r.D - o.D).max() < 1e-8 * max(1, np.abs(o.D).max())
    # eliminate-D oracle (docs/references.md section 5)
    Be, De = dc_elimination_oracle(A, C, grid, Gn, dc)
    assert np.abs(r.B - Be).max() < 1e-7 * scale
    assert np.abs(r.D - De).max() < 1e-7 * max(1, np.abs(De).max())
    # the constrained cost is at least the unconstrained one
    u = fit_bd(A, C, grid, Gn)
    assert r.residual >= u.residual - 1e-12


def test_feedthrough_fixed_exactly(grid):
    n, p, m = 9, 2, 1
    A, B, C, D = random_system(n, p, m, seed=5)
    Gn = noisy(frequency_response(A, B, C, D, grid), 0.05, seed=1)
    ft = np.zeros((p, m))  # continuous feedthrough 0, as for the aerofoil
    for kw in (dict(feedthrough=ft), dict(feedthrough=ft, dc_gain=np.ones((p, m)))):
        r = fit_bd(A, C, grid, Gn, **kw)
        at_nyquist = C @ np.linalg.solve(-np.eye(n) - A, r.B) + r.D
        assert np.abs(at_nyquist - ft).max() < 1e-10
        G_model = frequency_response(A, r.B, C, r.D, grid[-1:])
        assert np.abs(G_model[:, :, 0] - ft).max() < 1e-10
        if "dc_gain" in kw:
            assert np.abs(C @ np.linalg.solve(np.eye(n) - A, r.B) + r.D - 1.0).max() < 1e-10
        o = fit_bd(A, C, grid, Gn, solver="numpy", **kw)
        assert np.allclose(r.B, o.B, atol=1e-8 * np.abs(o.B).max())


def test_weights_pull_the_fit_towards_heavily_weighted_samples(grid):
    n, p, m = 6, 1, 1
    A, B, C, D = random_system(n, p, m, seed=7)
    G = frequency_response(A, B, C, D, grid)
    Gn = noisy(G, 0.05, seed=2)
    K = grid.size
    low = np.arange(K) < K // 4
    w = np.where(low, 1e4, 1.0)
    err = lambda r: np.abs(frequency_response(A, r.B, C, r.D, grid) - Gn)[0, 0]  # noqa: E731
    plain, weighted = fit_bd(A, C, grid, Gn), fit_bd(A, C, grid, Gn, weights=w)
    assert np.sum(err(weighted)[low] ** 2) < np.sum(err(plain)[low] ** 2)
    assert np.sum(err(weighted)[~low] ** 2) > np.sum(err(plain)[~low] ** 2)
    # uniform weights change nothing; (p, m, K) weights equal to (K,) weights give the same answer
    same = fit_bd(A, C, grid, Gn, weights=np.full(K, 3.0))
    assert np.allclose(same.B, plain.B, atol=1e-10) and np.isclose(same.residual, 3 * plain.residual)
    full = fit_bd(A, C, grid, Gn, weights=w[None, None, :], dc_gain=np.ones((1, 1)))
    flat = fit_bd(A, C, grid, Gn, weights=w, dc_gain=np.ones((1, 1)))
    assert np.allclose(full.B, flat.B, atol=1e-8 * np.abs(flat.B).max())
    # zero weight on a sample makes it irrelevant
    w0 = np.ones(K)
    w0[10] = 0.0
    G_bad = Gn.copy()
    G_bad[0, 0, 10] += 100.0
    assert np.allclose(fit_bd(A, C, grid, G_bad, weights=w0).B, fit_bd(A, C, grid, Gn, weights=w0).B, atol=1e-10)


def test_channel_weights_against_oracle(grid):
    n, p, m = 8, 2, 2
    A, B, C, D = random_system(n, p, m, seed=11)
    Gn = noisy(frequency_response(A, B, C, D, grid), 0.05, seed=3)
    w = np.random.default_rng(0).uniform(0.1, 5.0, size=(p, m, grid.size))
    dc = np.array([[1.0, -2.0], [0.5, 0.0]])
    r = fit_bd(A, C, grid, Gn, weights=w, dc_gain=dc)
    o = fit_bd(A, C, grid, Gn, weights=w, dc_gain=dc, solver="numpy")
    assert np.allclose(r.B, o.B, atol=1e-8 * np.abs(o.B).max())
    assert abs(r.residual - o.residual) <= 1e-9 * o.residual


def test_dpp_problem_is_compiled_once_and_reused(grid):
    refit.clear_refit_cache()
    n, p, m = 6, 1, 1
    A, B, C, D = random_system(n, p, m, seed=21)
    G = frequency_response(A, B, C, D, grid)
    r1 = fit_bd(A, C, grid, noisy(G, 0.01, 1), dc_gain=np.array([[1.0]]))
    assert not r1.reused_problem
    assert len(refit_solvers._PROBLEM_CACHE) == 1
    (compiled,) = refit_solvers._PROBLEM_CACHE.values()
    problem = compiled.problem
    assert problem.is_dpp()
    param_prog = problem._cache.param_prog  # cvxpy's compiled parametric program
    assert param_prog is not None
    # a different system of the same shape: new Parameter values, same compiled problem
    A2, B2, C2, D2 = random_system(n, p, m, seed=22)
    G2 = frequency_response(A2, B2, C2, D2, grid)
    r2 = fit_bd(A2, C2, grid, G2, dc_gain=G2[:, :, 0].real)
    assert r2.reused_problem
    assert len(refit_solvers._PROBLEM_CACHE) == 1
    assert next(iter(refit_solvers._PROBLEM_CACHE.values())).problem is problem
    assert problem._cache.param_prog is param_prog  # not recompiled
    assert compiled.n_solves == 2
    assert np.allclose(r2.B, B2, atol=1e-7 * np.abs(B2).max()) and np.allclose(r2.D, D2, atol=1e-8)
    # another constraint set is another problem
    fit_bd(A2, C2, grid, G2, dc_gain=G2[:, :, 0].real, feedthrough=G2[:, :, -1].real)
    assert len(refit_solvers._PROBLEM_CACHE) == 2


def test_dc_constraint_with_pole_at_one_raises(grid):
    A = np.diag([1.0, 0.5, -0.3])
    C = np.ones((1, 3))
    G = np.ones((1, 1, grid.size)) + 0j
    z = grid[1:]  # avoid evaluating at the pole itself
    with pytest.raises(ConstraintError, match=r"eigenvalue at z = 1.*drop dc_gain.*stable=True"):
        fit_bd(A, C, z, G[:, :, 1:], dc_gain=np.ones((1, 1)))
    A_near = np.diag([1.0 - 1e-10, 0.5, -0.3])
    with pytest.raises(ConstraintError, match="dc_gain cannot be imposed"):
        fit_bd(A_near, C, z, G[:, :, 1:], dc_gain=np.ones((1, 1)))
    with pytest.raises(ValueError):  # ConstraintError is a ValueError
        fit_cd(A, C.T, z, G[:, :, 1:], dc_gain=np.ones((1, 1)))
    A_nyq = np.diag([-1.0, 0.5, 0.2])
    with pytest.raises(ConstraintError, match=r"z = -1.*drop feedthrough"):
        fit_bd(A_nyq, C, grid[:-1], G[:, :, :-1], feedthrough=np.zeros((1, 1)))
    # without the constraint the same A is fine
    fit_bd(A, C, z, G[:, :, 1:])


def test_bad_inputs_raise_typed_errors(grid):
    A, B, C, D = random_system(4, 1, 1, seed=0)
    G = frequency_response(A, B, C, D, grid)
    with pytest.raises(FrequencyDataError, match="shape"):
        fit_bd(A, C, grid, G[:, :, :-1])
    with pytest.raises(FrequencyDataError, match="weights"):
        fit_bd(A, C, grid, G, weights=np.ones(3))
    with pytest.raises(FrequencyDataError, match="nonnegative"):
        fit_bd(A, C, grid, G, weights=-np.ones(grid.size))
    with pytest.raises(ConstraintError, match="shape"):
        fit_bd(A, C, grid, G, dc_gain=np.ones((2, 1)))
    G_nan = G.copy()
    G_nan[0, 0, 3] = np.nan
    with pytest.raises(FrequencyDataError, match="NaN"):
        fit_bd(A, C, grid, G_nan)
    with pytest.raises(ConstraintError, match="unknowns"):
        fit_bd(np.array([[0.5]]), np.ones((2, 1)), grid, np.ones((2, 1, grid.size)),
               dc_gain=np.ones((2, 1)), feedthrough=np.zeros((2, 1)))


def test_no_frequencies_is_a_typed_error():
    with pytest.raises(FrequencyDataError, match=r"no frequencies \(z is empty\)"):
        fit_bd(np.array([[0.5]]), np.array([[1.0]]), np.zeros(0, complex), np.zeros((1, 1, 0), complex))


@pytest.mark.parametrize("iterations", [2.5, 0, True, "3"])
def test_fit_alternating_iterations_must_be_a_positive_integer(grid, iterations):
    A, B, C, D = random_system(4, 1, 1, seed=0)
    with pytest.raises(sysid.OptionError, match="iterations must be an integer >= 1"):
        fit_alternating(A, C, grid, frequency_response(A, B, C, D, grid), iterations=iterations)


@pytest.mark.parametrize("p,m", [(1, 1), (2, 1), (2, 3)])
def test_fit_cd_recovers_and_constrains(p, m, grid):
    n = 7
    A, B, C, D = random_system(n, p, m, seed=40 + p + m)
    G = frequency_response(A, B, C, D, grid)
    r = fit_cd(A, B, grid, G)
    assert r.C.shape == (p, n) and r.D.shape == (p, m)
    assert np.allclose(r.C, C, atol=1e-8 * np.abs(C).max()) and np.allclose(r.D, D, atol=1e-9)
    Gn = noisy(G, 0.02, seed=p)
    dc = G[:, :, 0].real - 0.1
    r = fit_cd(A, B, grid, Gn, dc_gain=dc, feedthrough=np.zeros((p, m)))
    assert np.abs(r.C @ np.linalg.solve(np.eye(n) - A, B) + r.D - dc).max() < 1e-10
    assert np.abs(r.C @ np.linalg.solve(-np.eye(n) - A, B) + r.D).max() < 1e-10
    o = fit_cd(A, B, grid, Gn, dc_gain=dc, feedthrough=np.zeros((p, m)), solver="numpy")
    assert np.allclose(r.C, o.C, atol=1e-8 * np.abs(o.C).max())


def test_alternating_is_monotone_and_keeps_constraints(grid):
    n, p, m = 8, 2, 3
    A, B, C, D = random_system(n, p, m, seed=99)
    Gn = noisy(frequency_response(A, B, C, D, grid), 0.01, seed=5)
    C0 = C + 0.3 * np.random.default_rng(1).standard_normal(C.shape)
    dc = Gn[:, :, 0].real
    r = fit_alternating(A, C0, grid, Gn, iterations=6, dc_gain=dc)
    h = np.array(r.history)
    assert np.all(np.diff(h) <= 1e-9 * h[:-1])
    assert h[-1] < 0.5 * h[0]
    assert r.constraint_residual < 1e-10
    assert np.abs(r.C @ np.linalg.solve(np.eye(n) - A, r.B) + r.D - dc).max() < 1e-10


def test_unconstrained_fit_calls_no_solver(grid):
    A, B, C, D = random_system(5, 1, 1, seed=3)
    r = fit_bd(A, C, grid, frequency_response(A, B, C, D, grid))
    assert r.solver == "closed-form" and r.status == "optimal" and r.constraint_residual == 0.0
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        fit_bd(A, C, grid, frequency_response(A, B, C, D, grid), dc_gain=np.ones((1, 1)))


def _patch_status(monkeypatch, status):
    """Make the cached problem report ``status`` after a real solve (solver behaviour is not ours to test)."""
    comp = next(iter(refit_solvers._PROBLEM_CACHE.values()))
    real_solve = comp.problem.solve

    def fake_solve(*args, **kwargs):
        out = real_solve(*args, **kwargs)
        comp.problem._status = status
        return out

    monkeypatch.setattr(comp.problem, "solve", fake_solve)


def test_inaccurate_solve_warns_and_is_still_exact(grid, monkeypatch):
    from sysid.errors import SolverError

    refit.clear_refit_cache()
    A, B, C, D = random_system(5, 1, 1, seed=8)
    G = noisy(frequency_response(A, B, C, D, grid), 0.01, seed=0)
    dc = np.array([[0.7]])
    fit_bd(A, C, grid, G, dc_gain=dc)  # compiles and caches
    _patch_status(monkeypatch, "optimal_inaccurate")
    with pytest.warns(RuntimeWarning, match="optimal_inaccurate"):
        r = fit_bd(A, C, grid, G, dc_gain=dc)
    assert r.status == "optimal_inaccurate" and r.constraint_residual < 1e-10
    _patch_status(monkeypatch, "infeasible")
    with pytest.raises(SolverError, match="infeasible"):
        fit_bd(A, C, grid, G, dc_gain=dc)
    refit.clear_refit_cache()


def test_polishing_restores_the_constraints_exactly(grid, monkeypatch):
    """A solver answer off the constraint set by 1e-6 is projected back to round-off and reported."""
    refit.clear_refit_cache()
    A, B, C, D = random_system(6, 2, 1, seed=12)
    G = noisy(frequency_response(A, B, C, D, grid), 0.01, seed=4)
    dc = G[:, :, 0].real
    ft = np.zeros((2, 1))
    exact = fit_bd(A, C, grid, G, dc_gain=dc, feedthrough=ft)
    assert not exact.polished
    comp = next(iter(refit_solvers._PROBLEM_CACHE.values()))
    real_solve = comp.problem.solve

    def sloppy_solve(*args, **kwargs):
        out = real_solve(*args, **kwargs)
        comp.y[0].value = comp.y[0].value + 1e-6 * np.linspace(-1, 1, comp.y[0].size)
        return out

    monkeypatch.setattr(comp.problem, "solve", sloppy_solve)
    r = fit_bd(A, C, grid, G, dc_gain=dc, feedthrough=ft)
    assert r.polished and r.solver_constraint_residual > 1e-9
    assert r.constraint_residual < 1e-10
    assert np.abs(C @ np.linalg.solve(np.eye(6) - A, r.B) + r.D - dc).max() < 1e-10
    assert np.abs(C @ np.linalg.solve(-np.eye(6) - A, r.B) + r.D).max() < 1e-10
    assert np.abs(r.B - exact.B).max() < 1e-4 * np.abs(exact.B).max()
    refit.clear_refit_cache()


def test_pole_on_a_sample_point_is_a_typed_error(grid):
    A = np.diag([1.0, 0.5])  # z = 1 is grid[0]
    with pytest.raises(FrequencyDataError, match="unit circle"):
        fit_bd(A, np.ones((1, 2)), grid, np.ones((1, 1, grid.size)))


def test_a_pole_on_a_sample_point_off_z_1_is_a_typed_error(grid):
    # a rotation by the sixth sample's angle: eigenvalues exp(+-1j omega_d[5]) on the sample itself; the resolvent
    # there was huge but finite and B came out near 0 with status "optimal"
    w = np.angle(grid[5])
    A = np.array([[np.cos(w), -np.sin(w)], [np.sin(w), np.cos(w)]])
    with pytest.raises(FrequencyDataError, match="eigenvalue at .* one of the sample points"):
        fit_bd(A, np.eye(2), grid, np.ones((2, 1, grid.size)))


@pytest.mark.parametrize("call, error, match", [
    (lambda A, C, z, G: fit_bd(A, C, 2 * z, G), sysid.FrequencyGridError, r"is off the unit circle by \+1 \(\|z\| - 1"),
    (lambda A, C, z, G: fit_bd(A, C, z, G, tol=-1.0), sysid.OptionError, "tol must be a finite number > 0"),
    (lambda A, C, z, G: fit_cd(A, C.T, z, G, tol=np.nan), sysid.OptionError, "tol must be a finite number > 0"),
    (lambda A, C, z, G: fit_alternating(A, C, z, G, rtol=np.nan), sysid.OptionError, "rtol must be a finite number >= 0"),
    (lambda A, C, z, G: fit_alternating(A, C, z, G, rtol="1e-9"), sysid.OptionError, "rtol must be"),
])
def test_points_off_the_circle_and_bad_tolerances_are_refused(grid, call, error, match):
    # all accepted before: points off the circle fitted as if on it, tol=-1 polished every fit, rtol=nan never stopped
    A, B, C, D = random_system(4, 1, 1, seed=0)
    with pytest.raises(error, match=match):
        call(A, C, grid, frequency_response(A, B, C, D, grid))


def test_concurrent_refits_share_the_cached_problem_safely(grid):
    from concurrent.futures import ThreadPoolExecutor

    systems = [random_system(6, 1, 1, seed=200 + i) for i in range(8)]
    data = [(A, C, noisy(frequency_response(A, B, C, D, grid), 0.01, seed=i)) for i, (A, B, C, D) in enumerate(systems)]

    def job(item):
        A, C, G = item
        return fit_bd(A, C, grid, G, dc_gain=G[:, :, 0].real), fit_bd(A, C, grid, G, dc_gain=G[:, :, 0].real, solver="numpy")

    with ThreadPoolExecutor(4) as ex:
        for r, o in ex.map(job, data):
            assert np.allclose(r.B, o.B, atol=1e-8 * np.abs(o.B).max()) and r.constraint_residual < 1e-10
