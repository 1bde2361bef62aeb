import numpy as np
import pytest

from cfd.euler import residual
from cfd.flow import FlowCondition
from cfd.jacobian import jacobian, residual_derivative
from cfd.steady import solve_steady
from flowgrids import parabolic_c_grid


@pytest.fixture(scope="module")
def transonic():
    # NACA0012 at M0.8, 1.25 deg on a coarse grid: a shock, the wall, the wake cut and the far field.
    g = parabolic_c_grid(thickness=0.12, n_surface=40, n_wake=10, nj=13, eta_max=4.0, xi_max=3.5)
    sol = solve_steady(g, 0.8, 1.25, tol=1e-6)
    return g, sol.flow, sol.q


def test_the_coarse_transonic_state_has_a_shock(transonic):
    g, flow, q = transonic
    rho, u, v = q[..., 0], q[..., 1] / q[..., 0], q[..., 2] / q[..., 0]
    p = 0.4 * (q[..., 3] - 0.5 * rho * (u * u + v * v))
    assert np.max(np.hypot(u, v) / np.sqrt(1.4 * p / rho)) > 1.05


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_jacobian_matches_central_differences_at_several_steps(transonic, seed):
    # The JST switches (abs of the sensor's second difference, max of the sensor pair, max(0, k4 - eps2))
    # are piecewise: a finite difference whose step crosses a switch is not a derivative. The state is
    # moved off the near-ties of the converged far field (second differences ~ 0) by a 1e-3 perturbation;
    # then every row must match for some step, and almost every row for every step.
    g, flow, q = transonic
    q = q * (1 + 1e-3 * np.random.default_rng(9).standard_normal(q.shape))
    J = jacobian(g, q, flow)
    rng = np.random.default_rng(seed)
    v = rng.standard_normal(q.shape) * np.abs(q).mean(axis=(0, 1))
    Jv = J @ v.ravel()
    errs = []
    for eps in (1e-6, 1e-7, 1e-8):
        fd = (residual(g, q + eps * v, flow) - residual(g, q - eps * v, flow)).ravel() / (2 * eps)
        errs.append(np.abs(fd - Jv) / np.max(np.abs(Jv)))
        assert np.mean(errs[-1] < 1e-7) > 0.98, eps
    assert np.max(np.min(errs, axis=0)) < 1e-7


def test_coloured_jacobian_equals_column_by_column_complex_step():
    # Exactness of the colouring: every column from its own complex-step evaluation.
    g = parabolic_c_grid(thickness=0.12, n_surface=16, n_wake=5, nj=6, xi_max=2.0, eta_max=2.0)
    flow = FlowCondition(0.8, 1.25)
    rng = np.random.default_rng(5)
    q = np.broadcast_to(flow.q, g.cell_shape + (4,)) * (1 + 0.05 * rng.standard_normal(g.cell_shape + (4,)))
    n = q.size
    E = 1e-30j * np.eye(n).reshape((n,) + q.shape)
    dense = (residual(g, q + E, flow).imag / 1e-30).reshape(n, n).T
    J = jacobian(g, q, flow).toarray()
    assert np.max(np.abs(J - dense)) < 1e-13 * np.max(np.abs(dense))


def test_face_velocity_derivative_matches_central_differences(transonic):
    g, flow, q = transonic
    ni, nj = g.shape
    rng = np.random.default_rng(7)
    dwi = rng.standard_normal((2, ni, nj - 1))
    dwj = rng.standard_normal((2, ni - 1, nj))
    d = residual_derivative(g, q, flow, (dwi, dwj))
    eps = 1e-6
    fd = (residual(g, q, flow, face_velocity=(eps * dwi, eps * dwj))
          - residual(g, q, flow, face_velocity=(-eps * dwi, -eps * dwj))) / (2 * eps)
    assert np.max(np.abs(fd - d)) < 1e-7 * np.max(np.abs(d))


@pytest.mark.parametrize("chunk", [0, -1, 2.5, "8", True])
def test_chunk_must_be_a_whole_number_of_colours(transonic, chunk):
    # chunk=0 raised Python's "range() arg 3 must not be zero"
    from cfd import FlowConditionError

    grid, flow, q = transonic
    with pytest.raises(FlowConditionError, match=r"chunk must be a whole number >= 1"):
        jacobian(grid, q, flow, chunk=chunk)


def test_a_state_with_nan_is_refused(transonic):
    # returned a NaN matrix with hundreds of NumPy RuntimeWarnings
    from cfd import FlowConditionError

    grid, flow, q = transonic
    q = np.array(q)
    q[3, 2, 1] = np.nan
    with pytest.raises(FlowConditionError, match=r"q contains NaN or inf"):
        jacobian(grid, q, flow)


@pytest.mark.parametrize("q", ["state", None, "complex"])
def test_a_state_that_is_not_real_is_refused(q):
    # a complex q lost its imaginary part with only a ComplexWarning
    from cfd import FlowCondition, FlowConditionError

    grid = parabolic_c_grid(thickness=0.1, n_surface=32, n_wake=8, nj=13)
    flow = FlowCondition(0.5)
    if q == "complex":
        q = np.broadcast_to(flow.q, grid.cell_shape + (4,)) + 1e-3j
    with pytest.raises(FlowConditionError, match=r"q must be an array of real conserved states; got "):
        jacobian(grid, q, flow)


@pytest.mark.parametrize("args, error, match", [
    # a state of the wrong shape raised NumPy's "operands could not be broadcast" from the colouring
    (lambda g, q, flow: (g, np.zeros((3, 3, 4)), flow), "MeshError", r"q has shape \(3, 3, 4\); this grid needs"),
    (lambda g, q, flow: (g, np.stack([q, q]), flow), "MeshError", r"the Jacobian is of one state"),
    (lambda g, q, flow: (None, q, flow), "MeshError", r"grid must be a cfd.Grid"),
    (lambda g, q, flow: (g, q, "M0.8"), "FlowConditionError", r"flow must be a cfd.FlowCondition"),
])
def test_arguments_are_checked_as_the_residual_checks_them(transonic, args, error, match):
    import cfd

    grid, flow, q = transonic
    with pytest.raises(getattr(cfd, error), match=match):
        jacobian(*args(grid, q, flow))
