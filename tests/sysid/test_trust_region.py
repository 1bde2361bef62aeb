"""sysid.trust_region.least_squares_trf: the bounded Trust Region Reflective solver behind the pole refinement,
against analytic minima and against SciPy's least_squares (whose algorithm it repeats: the same iterates)."""

import numpy as np
import pytest
from scipy.optimize import least_squares

from sysid.trust_region import least_squares_trf


def rosenbrock(x):
    return np.array([10.0 * (x[1] - x[0] ** 2), 1.0 - x[0]])


def rosenbrock_jac(x):
    return np.array([[-20.0 * x[0], 10.0], [-1.0, 0.0]])


@pytest.mark.parametrize("lb, ub, expected", [
    ([-np.inf, -np.inf], [np.inf, np.inf], [1.0, 1.0]),   # the unconstrained minimum
    ([-2.0, -2.0], [0.5, 2.0], [0.5, 0.25]),              # x0 <= 0.5 active: x1 = x0^2 on the bound
    ([1.5, -np.inf], [3.0, np.inf], [1.5, 2.25]),         # x0 >= 1.5 active
])
def test_bounded_rosenbrock_reaches_its_analytic_minimum(lb, ub, expected):
    sol = least_squares_trf(rosenbrock, rosenbrock_jac, np.array([-1.2, 1.0]) if lb[0] < 0 else np.array([2.0, 1.0]),
                            np.array(lb), np.array(ub), ftol=1e-15, xtol=1e-15, gtol=1e-15, max_nfev=500)
    # the minimiser of a smooth problem is determined to about sqrt(eps) by the cost; here the residual is
    # linear near the constrained minimum, so to well below that
    np.testing.assert_allclose(sol.x, expected, rtol=0, atol=1e-9)
    assert sol.status > 0


def _exponentials(t, y):
    """Residual and Jacobian of y ~ a exp(-b t) + c exp(-d t), parameters (a, log b, c, log d)."""
    def fun(x):
        return x[0] * np.exp(-np.exp(x[1]) * t) + x[2] * np.exp(-np.exp(x[3]) * t) - y

    def jac(x):
        b, d = np.exp(x[1]), np.exp(x[3])
        e1, e2 = np.exp(-b * t), np.exp(-d * t)
        return np.column_stack([e1, -x[0] * b * t * e1, e2, -x[2] * d * t * e2])
    return fun, jac


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("max_nfev", [5, 25, 200])
def test_the_iterates_are_scipys(seed, max_nfev):
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 4.0, 60)
    y = 2.0 * np.exp(-0.7 * t) - 0.5 * np.exp(-3.0 * t) + 1e-3 * rng.standard_normal(t.size)
    fun, jac = _exponentials(t, y)
    x0 = np.array([1.0, 0.0, 1.0, 0.5]) + 0.1 * rng.standard_normal(4)
    lb, ub = np.array([-5.0, -3.0, -5.0, -3.0]), np.array([5.0, 0.6, 5.0, 3.0])   # an active bound on log b
    ours = least_squares_trf(fun, jac, x0, lb, ub, ftol=1e-12, xtol=1e-12, gtol=1e-12, max_nfev=max_nfev)
    ref = least_squares(fun, x0, jac=jac, bounds=(lb, ub), method="trf", x_scale="jac", ftol=1e-12, xtol=1e-12,
                        gtol=1e-12, max_nfev=max_nfev)
    # the same operations in the same order: the same numbers (a tolerance of a few ulps for other BLAS builds)
    np.testing.assert_allclose(ours.x, ref.x, rtol=1e-13, atol=1e-15)
    np.testing.assert_allclose(ours.fun, ref.fun, rtol=1e-12, atol=1e-15)
    assert (ours.nfev, ours.status) == (ref.nfev, ref.status)


def test_bad_start_is_refused():
    with pytest.raises(ValueError, match="infeasible"):
        least_squares_trf(rosenbrock, rosenbrock_jac, np.array([3.0, 0.0]), np.array([-1.0, -1.0]),
                          np.array([1.0, 1.0]))
    with pytest.raises(ValueError, match="not finite"):
        least_squares_trf(lambda x: np.array([np.nan, 0.0]), rosenbrock_jac, np.zeros(2), np.full(2, -1.0),
                          np.full(2, 1.0))
