"""Tests of sysid.levenberg_marquardt against references nobody here wrote.

The references are ``numpy.linalg.lstsq`` (linear least squares), scipy's ``lsq_linear`` and ``least_squares``
(bounded and nonlinear least squares), and problems with an analytic minimiser (Rosenbrock's (1, 1), a
noise-free exponential decay, the root of an arctangent). Each tolerance is derived from the problem's
conditioning in a comment next to it.
"""

import numpy as np
import pytest
import scipy.optimize

from sysid.levenberg_marquardt import LMResult, bounded_levenberg_marquardt

EPS = np.finfo(float).eps


class Recorder:
    """Wraps a residual and a Jacobian and logs every call in order as ``(kind, x copy, value)``."""

    def __init__(self, residual, jacobian):
        self._residual, self._jacobian = residual, jacobian
        self.calls = []

    def residual(self, x):
        r = np.asarray(self._residual(np.array(x, copy=True)), dtype=float)
        self.calls.append(("r", np.array(x, copy=True), r))
        return r

    def jacobian(self, x):
        J = np.asarray(self._jacobian(np.array(x, copy=True)), dtype=float)
        self.calls.append(("j", np.array(x, copy=True), J))
        return J

    def points(self, kind="r"):
        return np.array([x for k, x, _ in self.calls if k == kind])

    def costs(self):
        return np.array([float(v @ v) if np.all(np.isfinite(v)) else np.inf for k, _, v in self.calls if k == "r"])


# ------------------------------------------------------------------------------------------------- problems
def rosenbrock(x):
    return np.array([10.0 * (x[1] - x[0] ** 2), 1.0 - x[0]])


def rosenbrock_jac(x):
    return np.array([[-20.0 * x[0], 10.0], [-1.0, 0.0]])


ROSENBROCK_START = np.array([-1.2, 1.0])

T_SAMPLES = np.linspace(0.0, 4.0, 30)
A_TRUE, B_TRUE = 2.5, 1.3


def decay(y):
    """Residual and Jacobian of fitting ``a exp(-b t)`` to the samples ``y`` at :data:`T_SAMPLES`."""

    def residual(p):
        return p[0] * np.exp(-p[1] * T_SAMPLES) - y

    def jacobian(p):
        e = np.exp(-p[1] * T_SAMPLES)
        return np.column_stack([e, -p[0] * T_SAMPLES * e])

    return residual, jacobian


EXACT_DECAY = decay(A_TRUE * np.exp(-B_TRUE * T_SAMPLES))

#: the arctangent problem: root at X_ROOT, residual non-finite for x > X_WALL. From X_START (u = x - X_ROOT = -1.4)
#: the Gauss-Newton step -atan(u) (1 + u^2) = +2.8 overshoots to 12.9 (Newton diverges on atan for |u| > 1.39),
#: and it lies within the first trust radius |D x0| = 10.1 / (1 + 1.4^2) = 3.4 > |D dx| = 0.95, so the first
#: trial probes the non-finite region.
X_ROOT, X_WALL, X_START = 11.5, 12.0, 10.1


def walled_atan(bad=np.nan, all_rows=True):
    def residual(x):
        u = np.arctan(x[0] - X_ROOT)
        if x[0] <= X_WALL:
            return np.array([u, 0.0])
        return np.array([bad, bad]) if all_rows else np.array([u, bad])

    def jacobian(x):
        return np.array([[1.0 / (1.0 + (x[0] - X_ROOT) ** 2)], [0.0]])

    return residual, jacobian


def linear_problem(seed, consistent):
    rng = np.random.default_rng(seed)
    A = rng.standard_normal((40, 6))
    b = A @ rng.standard_normal(6) if consistent else rng.standard_normal(40)
    return A, b


# ------------------------------------------------------------------------------------- 1. linear least squares
@pytest.mark.parametrize("consistent", [False, True], ids=["residual", "zero-residual"])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_linear_least_squares_equals_lstsq_in_one_gauss_newton_step(seed, consistent):
    A, b = linear_problem(seed, consistent)
    cond = np.linalg.cond(A)
    assert cond < 10   # a 40 x 6 Gaussian matrix: singular values sqrt(40) +- sqrt(6)
    x_ref = np.linalg.lstsq(A, b, rcond=None)[0]
    # start where the Gauss-Newton step fits the first trust radius |D x0| (D = A's column norms):
    # |D (x_ref - x0)| = |D x_ref| = |D x0| / 2
    x0 = 2.0 * x_ref
    sol = bounded_levenberg_marquardt(lambda x: A @ x - b, lambda x: A, x0)
    assert isinstance(sol, LMResult)
    # Gauss-Newton is exact in one step on a linear problem: the start and that step are the only evaluations
    # (the stop is then decided by the gradient or step test, which need no evaluation)
    assert sol.nfev == 2
    assert sol.status in ("gtol", "xtol", "ftol")
    # QR least squares is backward stable: relative error <~ eps (cond + cond^2 tan(theta)) < 100 eps = 2e-14
    # for cond < 10 (measured <= 1.2e-15); 1e-10 leaves four orders for the step's accumulation
    np.testing.assert_allclose(sol.x, x_ref, rtol=1e-10, atol=1e-10 * np.linalg.norm(x_ref))
    np.testing.assert_allclose(sol.fun, A @ sol.x - b)
    assert sol.cost == pytest.approx(float(sol.fun @ sol.fun))


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_linear_least_squares_from_zero_doubles_the_radius_to_the_solution(seed):
    A, b = linear_problem(seed, consistent=False)
    x_ref = np.linalg.lstsq(A, b, rcond=None)[0]
    sol = bounded_levenberg_marquardt(lambda x: A @ x - b, lambda x: A, np.zeros(6))
    np.testing.assert_allclose(sol.x, x_ref, rtol=1e-10, atol=1e-10 * np.linalg.norm(x_ref))   # as above
    # from x0 = 0 the radius starts at 1 (scaled units). On a linear problem every step's gain ratio is exactly
    # 1, so a step that reaches the trust boundary doubles the radius, and the scaled distance to x_ref never
    # grows (an LM step contracts it: x_ref - x+ = lam (H + lam)^-1 (x_ref - x)). After k = ceil(log2 |D x_ref|)
    # doublings the Gauss-Newton step fits: at most k partial steps + the exact one + the start.
    k = int(np.ceil(np.log2(max(np.linalg.norm(np.linalg.norm(A, axis=0) * x_ref), 1.0))))
    assert sol.nfev <= k + 2


# ----------------------------------------------------------------------------------------------- 2. Rosenbrock
def test_rosenbrock_reaches_one_one():
    sol = bounded_levenberg_marquardt(rosenbrock, rosenbrock_jac, ROSENBROCK_START, max_nfev=200)
    assert sol.status != "max_nfev"
    # a zero-residual problem with a nonsingular Jacobian at (1, 1) (cond 22.4): Gauss-Newton converges
    # quadratically there and the attainable accuracy is ~cond eps = 5e-15; 1e-8 is far above both
    np.testing.assert_allclose(sol.x, [1.0, 1.0], rtol=0, atol=1e-8)
    assert sol.cost < 1e-20
    assert sol.nfev <= 200


# ------------------------------------------------------------------------------------ 3. exponential decay fit
@pytest.mark.parametrize("off", [(1.5, 0.5), (0.5, 1.5), (1.5, 1.5), (0.5, 0.5)])
def test_exponential_decay_recovered_from_fifty_percent_off(off):
    residual, jacobian = EXACT_DECAY
    sol = bounded_levenberg_marquardt(residual, jacobian, [A_TRUE * off[0], B_TRUE * off[1]])
    # noise-free samples: zero residual at (a, b), Jacobian there of cond 2.2, so the attainable relative error
    # is a few eps and Gauss-Newton's quadratic convergence reaches it before the xtol / gtol stop
    np.testing.assert_allclose(sol.x, [A_TRUE, B_TRUE], rtol=1e-9)


def test_exponential_decay_with_misfit_matches_scipy_least_squares():
    residual, jacobian = decay(A_TRUE * np.exp(-B_TRUE * T_SAMPLES) + 0.05 * np.sin(7.0 * T_SAMPLES))
    x0 = [1.5 * A_TRUE, 0.5 * B_TRUE]
    ref = scipy.optimize.least_squares(residual, x0, jacobian, method="lm", xtol=1e-15, ftol=1e-15, gtol=1e-15)
    sol = bounded_levenberg_marquardt(residual, jacobian, x0)
    # a nonzero residual (|r| = 0.2): both stop at the stationary point J^T r = 0, determined to
    # ~eps |J| |r| / sigma_min^2 ~ 1e-15 relative (cond(J) = 2.2, curvature term |r| small against sigma_min^2)
    np.testing.assert_allclose(sol.x, ref.x, rtol=1e-10)
    assert sol.cost <= float(ref.fun @ ref.fun) * (1 + 1e-12)


# -------------------------------------------------------------------------------------- 4. units invariance
@pytest.mark.parametrize("factor", [1e6, 1e-6])
@pytest.mark.parametrize("problem", ["rosenbrock", "decay"])
def test_a_parameter_in_other_units_gives_the_same_iterates(problem, factor):
    f, jac, x0 = {"rosenbrock": (rosenbrock, rosenbrock_jac, ROSENBROCK_START),
                  "decay": (*EXACT_DECAY, np.array([1.5 * A_TRUE, 0.5 * B_TRUE]))}[problem]
    c = np.array([1.0, factor])   # z = x / c: the second parameter in units `factor` times larger
    plain, scaled = Recorder(f, jac), Recorder(lambda z: f(z * c), lambda z: jac(z * c) * c)
    s1 = bounded_levenberg_marquardt(plain.residual, plain.jacobian, x0, max_nfev=200)
    s2 = bounded_levenberg_marquardt(scaled.residual, scaled.jacobian, x0 / c, max_nfev=200)
    assert (s1.nfev, s1.njev) == (s2.nfev, s2.njev)
    # with D the Jacobian's column norms, every step is computed from column-scaled data by operations that
    # commute with the scaling (Householder QR of [J r], the SVD of R D^-1, elementwise clipping), so the two
    # runs differ by round-off alone: a few eps per operation over <= 13 steps of subproblems with cond <= 25,
    # <~ 1e-13 (measured <= 4.5e-16). A step that depended on the units would differ by ~cond(R) eps, which
    # the factor 1e6 makes ~1e-11 (measured 1.6e-11 when Q^T r was solved from R^T (Q^T r) = J^T r)
    p1, p2 = plain.points(), scaled.points() * c
    np.testing.assert_allclose(p2, p1, rtol=0, atol=1e-13 * np.abs(p1).max())
    np.testing.assert_allclose(s2.x * c, s1.x, rtol=1e-13)


# --------------------------------------------------------------------------------------------------- 5. bounds
def _bounded_linear():
    rng = np.random.default_rng(1)
    A = rng.standard_normal((20, 3))
    b = A @ np.array([2.0, -1.0, 0.5]) + 0.1 * rng.standard_normal(20)   # unconstrained minimum outside the box
    lo, hi = np.array([-1.0, -0.5, -1.0]), np.array([1.0, 1.0, 1.0])
    ref = scipy.optimize.lsq_linear(A, b, bounds=(lo, hi), method="bvls", tol=1e-14).x
    return (lambda x: A @ x - b), (lambda x: A), np.zeros(3), lo, hi, ref


def _bounded_rosenbrock(lo, hi):
    def case():
        ref = scipy.optimize.least_squares(rosenbrock, ROSENBROCK_START, rosenbrock_jac,
                                           bounds=(np.where(np.isfinite(lo), lo, -np.inf), hi),
                                           xtol=1e-15, ftol=1e-15, gtol=1e-15).x
        return rosenbrock, rosenbrock_jac, ROSENBROCK_START, lo, hi, ref
    return case


BOUNDED = {
    "linear-two-active": _bounded_linear,
    "rosenbrock-x1<=0.5": _bounded_rosenbrock(np.array([-2.0, -2.0]), np.array([0.5, 2.0])),
    "rosenbrock-x1<=0.5-infinite-others": _bounded_rosenbrock(np.array([-np.inf, -np.inf]),
                                                              np.array([0.5, np.inf])),
}


@pytest.mark.parametrize("case", list(BOUNDED))
def test_bounds_iterates_strictly_inside_and_approach_the_bounded_minimum(case):
    f, jac, x0, lo, hi, ref = BOUNDED[case]()
    assert np.any(np.isclose(ref, lo) | np.isclose(ref, hi))   # the box is active at the reference solution
    rec = Recorder(f, jac)
    sol = bounded_levenberg_marquardt(rec.residual, rec.jacobian, x0, lo, hi, max_nfev=200)
    pts = rec.points()
    assert np.all(pts > lo) and np.all(pts < hi)   # every evaluation strictly inside
    assert np.all(sol.x > lo) and np.all(sol.x < hi)
    costs = rec.costs()
    assert sol.cost <= costs[0] and sol.cost == costs.min()   # never above the start; the best point is returned
    # By design the solver clips the unconstrained trust-region step short of the box (sysid.levenberg_marquardt,
    # "bounds by projection") and does not re-solve the free parameters with the clipped ones held: on an active
    # bound it approaches the bounded minimum slowly (measured: cost 4.3e-7 and 1.4e-5 above the reference's
    # after 19 and 200 evaluations, the parameters 1.5e-3 and 1.9e-4 off). Re-solving reaches the references to
    # 1e-12 but drove the pole refinement's poles onto the stability region's edges: on the paper data (T1-T6,
    # N_r 10-60) the default's error / VF's geometric mean went 0.449 -> 0.548, T5 N_r = 60 to 37 times VF's.
    # What is asserted: the cost within 1e-4 relative of the bounded minimum's (a bound with 7x margin over the
    # worst measured, which a solver that stalled at the bound's first contact, 1e-1 - 1e0 here, would break).
    r_ref = f(ref)
    assert sol.cost <= (1 + 1e-4) * float(r_ref @ r_ref)


def test_a_start_outside_the_box_is_clipped_into_it():
    rec = Recorder(rosenbrock, rosenbrock_jac)
    sol = bounded_levenberg_marquardt(rec.residual, rec.jacobian, [3.0, 1.0], [-2.0, -2.0], [0.5, 2.0],
                                      max_nfev=200)
    assert np.all(rec.points() <= [0.5, 2.0]) and np.all(rec.points() >= [-2.0, -2.0])
    # the bounded minimum is x1 = 0.5, x2 = x1^2 with cost 0.25 (the previous test says how close it gets)
    assert sol.cost <= (1 + 1e-4) * 0.25


# ----------------------------------------------------------------------------------- 6. non-finite residuals
@pytest.mark.parametrize("all_rows", [True, False], ids=["all-rows", "one-row"])
@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_non_finite_trial_points_are_rejected(bad, all_rows):
    rec = Recorder(*walled_atan(bad, all_rows))
    sol = bounded_levenberg_marquardt(rec.residual, rec.jacobian, [X_START])
    assert np.any(rec.points()[:, 0] > X_WALL)   # the run did probe the non-finite region
    assert np.isfinite(sol.cost) and np.all(np.isfinite(sol.fun)) and np.all(np.isfinite(sol.x))
    assert sol.cost < rec.costs()[0]
    # the root of atan(x - 11.5) with unit slope there: Newton converges quadratically to ~eps x
    np.testing.assert_allclose(sol.x, [X_ROOT], rtol=1e-12)


@pytest.mark.parametrize("bad", [np.nan, np.inf])
def test_non_finite_start_returns_damping_after_one_evaluation(bad):
    rec = Recorder(*walled_atan(bad))
    sol = bounded_levenberg_marquardt(rec.residual, rec.jacobian, [X_WALL + 1.0])
    assert sol.status == "damping"
    assert (sol.nfev, sol.njev) == (1, 0)
    assert [k for k, _, _ in rec.calls] == ["r"]
    np.testing.assert_array_equal(sol.x, [X_WALL + 1.0])


# ------------------------------------------------------------------------------ 7. the Jacobian's contract
CONTRACT_CASES = {
    "linear": lambda: (*(lambda A, b: (lambda x: A @ x - b, lambda x: A))(*linear_problem(0, False)),
                       np.zeros(6), None, None),
    "rosenbrock": lambda: (rosenbrock, rosenbrock_jac, ROSENBROCK_START, None, None),
    "rosenbrock-bounded": lambda: (rosenbrock, rosenbrock_jac, ROSENBROCK_START, [-2.0, -2.0], [0.5, 2.0]),
    "walled-atan": lambda: (*walled_atan(), [X_START], None, None),
}


@pytest.mark.parametrize("max_nfev", [3, 200])
@pytest.mark.parametrize("case", list(CONTRACT_CASES))
def test_jacobian_only_right_after_a_residual_at_the_same_point(case, max_nfev):
    f, jac, x0, lo, hi = CONTRACT_CASES[case]()
    rec = Recorder(f, jac)
    sol = bounded_levenberg_marquardt(rec.residual, rec.jacobian, x0, lo, hi, max_nfev=max_nfev)
    kinds = [k for k, _, _ in rec.calls]
    assert kinds[0] == "r"
    for i, (kind, x, _) in enumerate(rec.calls):
        if kind == "j":   # sysid.pole_refinement._Projection reuses that residual's factorisation
            prev_kind, prev_x, prev_r = rec.calls[i - 1]
            assert prev_kind == "r"
            np.testing.assert_array_equal(x, prev_x)
            assert np.all(np.isfinite(prev_r))   # and only at accepted (finite) points
    assert sol.nfev == kinds.count("r") and sol.njev == kinds.count("j")


def test_the_contract_case_with_rejections_does_reject():
    # the walled-atan case above exercises the contract across rejected trials: some residual calls are not
    # followed by a Jacobian call
    rec = Recorder(*walled_atan())
    bounded_levenberg_marquardt(rec.residual, rec.jacobian, [X_START])
    kinds = [k for k, _, _ in rec.calls]
    assert any(a == "r" and b == "r" for a, b in zip(kinds, kinds[1:]))


# --------------------------------------------------------------------------------------------- 8. max_nfev
@pytest.mark.parametrize("max_nfev", [1, 2, 3, 5, 8, 13, 40])
@pytest.mark.parametrize("case", list(CONTRACT_CASES))
def test_max_nfev_is_respected_and_the_best_point_is_returned(case, max_nfev):
    f, jac, x0, lo, hi = CONTRACT_CASES[case]()
    rec = Recorder(f, jac)
    sol = bounded_levenberg_marquardt(rec.residual, rec.jacobian, x0, lo, hi, max_nfev=max_nfev)
    assert sol.nfev <= max_nfev
    assert sol.nfev == len(rec.points())
    if max_nfev == 1:
        assert (sol.nfev, sol.njev, sol.status) == (1, 0, "max_nfev")
    # the returned point is the best one evaluated, with its own residual
    costs = rec.costs()
    assert sol.cost == costs.min()
    best = rec.points()[int(np.argmin(costs))]
    np.testing.assert_array_equal(sol.x, best)
    np.testing.assert_array_equal(sol.fun, np.asarray(f(sol.x), dtype=float))
