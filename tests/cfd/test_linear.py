"""cfd.linear: every operator is a derivative of the one residual (checked against it)."""

import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("cfd.loads")
sys.path.append(str(Path(__file__).parent))

from flowgrids import parabolic_c_grid  # noqa: E402

import cfd  # noqa: E402

from cfd.euler import lift_coefficient, residual  # noqa: E402
from cfd.flow import FlowCondition  # noqa: E402
from cfd.gust import OneMinusCosine, cell_x_gradient, face_gust, gust_face_velocity, svm_source  # noqa: E402
from cfd.jacobian import residual_derivative  # noqa: E402
from cfd.loads import force_coefficients  # noqa: E402
from cfd.linear import LinearError, check_outputs, linearise, linearise_state, wall_loads  # noqa: E402
from cfd.sweep import fast_sweep  # noqa: E402

GUST = OneMinusCosine(length=1.0, angle_deg=1.0, x0=-2.0)


@pytest.fixture(scope="module")
def perturbed():
    """A thick-aerofoil grid and a randomly perturbed (non-uniform) state: all branches active."""
    grid = parabolic_c_grid(thickness=0.1, n_surface=24, n_wake=6, nj=9)
    flow = FlowCondition(0.4, 1.0)
    rng = np.random.default_rng(0)
    q = np.broadcast_to(flow.q, grid.cell_shape + (4,)).copy()
    q *= 1.0 + 0.02 * rng.normal(size=q.shape)
    return grid, flow, q, linearise_state(grid, q, flow)


def test_mass_matrix_and_shapes(perturbed):
    grid, flow, q, lin = perturbed
    N = grid.n_cells
    ni, nj = grid.shape
    assert lin.J.shape == (4 * N, 4 * N)
    assert lin.Bi.shape == (4 * N, ni * (nj - 1)) and lin.Bj.shape == (4 * N, (ni - 1) * nj)
    np.testing.assert_array_equal(lin.V.reshape(grid.cell_shape + (4,))[..., 2], grid.area)
    assert lin.C.shape == (3, 4 * N)
    assert lin.to_solver_time(2.0) == pytest.approx(2.0 / 0.4)
    assert lin.to_solver_frequency(2.0) == pytest.approx(0.8)


def test_face_operators_against_residual_directional_derivative(perturbed):
    grid, flow, q, lin = perturbed
    ni, nj = grid.shape
    rng = np.random.default_rng(1)
    di, dj = rng.normal(size=(ni, nj - 1)), rng.normal(size=(ni - 1, nj))
    zi, zj = np.zeros_like(di), np.zeros_like(dj)
    ref = residual_derivative(grid, q, flow, (np.stack([zi, di]), np.stack([zj, dj])))
    mine = lin.Bi @ di.ravel() + lin.Bj @ dj.ravel()
    np.testing.assert_allclose(mine, ref.ravel(), rtol=0, atol=1e-12 * np.abs(ref).max())
    # and against a central finite difference of the residual itself
    h = 1e-6
    wp = (np.stack([zi, h * di]), np.stack([zj, h * dj]))
    wm = (np.stack([zi, -h * di]), np.stack([zj, -h * dj]))
    fd = (residual(grid, q, flow, face_velocity=wp) - residual(grid, q, flow, face_velocity=wm)) / (2 * h)
    np.testing.assert_allclose(mine, fd.ravel(), rtol=0, atol=1e-6 * np.abs(ref).max())


def test_forcing_is_the_residual_derivative_with_respect_to_the_gust(perturbed):
    """b = d/d(eps) R(q, w = -eps mach g, source = eps svm_source(g)), by complex step through the residual."""
    grid, flow, q, lin = perturbed
    gust = OneMinusCosine(length=1.5, angle_deg=1.0, x0=-1.0)
    gi, gj = face_gust(grid, gust, 1.3)
    for method in ("svm", "fvm"):
        b = lin.forcing(gi, gj, method)

        def R(eps):
            qc = q.astype(complex)
            src = svm_source(qc, flow.mach, eps * cell_x_gradient(grid, gi, gj)) if method == "svm" else None
            return residual(grid, qc, flow, face_velocity=gust_face_velocity(eps * gi, eps * gj, flow.mach),
                            source=src)

        h = 1e-30
        cs = R(1j * h).imag.ravel() / h
        np.testing.assert_allclose(b, cs, rtol=0, atol=1e-12 * np.abs(cs).max())
        assert np.abs(cs).max() > 0
    # batched forcing
    B = lin.forcing(np.stack([gi, 2 * gi]), np.stack([gj, 2 * gj]), "svm")
    np.testing.assert_allclose(B[1], 2 * B[0], rtol=1e-13)


def test_output_operator(perturbed):
    grid, flow, q, lin = perturbed
    g = flow.gamma
    p = (g - 1) * (q[..., 3] - 0.5 * (q[..., 1] ** 2 + q[..., 2] ** 2) / q[..., 0])
    assert wall_loads(grid, q, flow)[0] == pytest.approx(lift_coefficient(grid, p, flow), rel=1e-13)
    rng = np.random.default_rng(2)
    d = rng.normal(size=q.shape)
    h = 1e-6

    def loads(x):
        cl, cd, cm = force_coefficients(grid, x, flow)
        return np.array([cl, cm, cd])

    fd = (loads(q + h * d) - loads(q - h * d)) / (2 * h)
    np.testing.assert_allclose(lin.C @ d.ravel(), fd, rtol=1e-7, atol=1e-9)
    # moment about the quarter chord: a load at x = 0.25 gives no moment (flat-plate coefficients)
    plate = parabolic_c_grid(thickness=0.0, n_surface=24, n_wake=6, nj=9)
    from cfd.linear import _load_coefficients

    c = _load_coefficients(plate, FlowCondition(0.4))
    xf = 0.5 * (plate.x[:-1, 0] + plate.x[1:, 0])[plate.wall]
    # Cm = -(x - 1/4) * dCl for a flat plate at zero incidence (nose up positive)
    np.testing.assert_allclose(c[1], -(xf - 0.25) * c[0], atol=1e-12)


def test_linearise_from_solution_object(perturbed):
    grid, flow, q, _ = perturbed

    class Sol:
        pass

    sol = Sol()
    sol.grid, sol.q, sol.mach, sol.alpha_deg = grid, q, flow.mach, flow.alpha_deg
    lin = linearise(sol)
    assert lin.flow == flow
    with pytest.raises(LinearError):
        linearise_state(grid, q[:-1], flow)


def _solution_like(grid, q, flow):
    class Sol:
        pass

    sol = Sol()
    sol.grid, sol.q, sol.mach, sol.alpha_deg = grid, q, flow.mach, flow.alpha_deg
    return sol


@pytest.mark.parametrize("make, match", [
    (lambda grid, q, flow: None, "sol must be a steady solution with grid and q; got NoneType"),
    (lambda grid, q, flow: grid, r"got Grid: solve the flow first: cfd.linearise\(cfd.solve_steady"),
    (lambda grid, q, flow: _solution_like(grid, np.full_like(q, np.nan), flow), "q contains NaN, inf or non-pos"),
    # a negative density or pressure was linearised (solve_steady refuses such a q0)
    (lambda grid, q, flow: _solution_like(grid, q * [-1.0, 1.0, 1.0, 1.0], flow),
     "q contains NaN, inf or non-positive density or pressure"),
    (lambda grid, q, flow: _solution_like(grid, q * [1.0, 1.0, 1.0, 0.0], flow),
     "q contains NaN, inf or non-positive density or pressure"),
    (lambda grid, q, flow: _solution_like(grid, q[:-1], flow), "steady state has shape"),
    (lambda grid, q, flow: _solution_like(grid, np.full(q.shape, "a"), flow), "array of real numbers"),
])
def test_linearise_refuses_what_is_not_a_steady_solution(perturbed, make, match):
    grid, flow, q, _ = perturbed
    with pytest.raises(LinearError, match=match):
        linearise(make(grid, q, flow))


def test_linearise_state_checks_its_arguments(perturbed):
    grid, flow, q, _ = perturbed
    with pytest.raises(LinearError, match="scheme must be a cfd.Scheme"):
        linearise(_solution_like(grid, q, flow), scheme="jst")
    with pytest.raises(LinearError, match="grid must be a cfd.Grid"):
        linearise_state(None, q, flow)
    with pytest.raises(LinearError, match="flow must be a cfd.FlowCondition"):
        linearise_state(grid, q, 0.4)
    # a complex state lost its imaginary part with only a ComplexWarning
    with pytest.raises(LinearError, match=r"the steady state q must be an array of real numbers; got dtype complex"):
        linearise_state(grid, q + 1e-3j, flow)


@pytest.mark.parametrize("call", [
    lambda lin: cfd.lfd_response(lin, [0.5]),
    lambda lin: cfd.lfd_response(lin, [0.5], method="fast"),
    lambda lin: fast_sweep(lin, [0.5]),
    lambda lin: cfd.ltd_response(lin, GUST, 0.1, 1.0),
    lambda lin: cfd.ltd_responses(lin, [GUST], 0.1, 1.0),
    lambda lin: cfd.coupled_ltd(lin, GUST, 0.1, 1.0, mass=np.eye(2), stiffness=np.eye(2), load=np.eye(2),
                                pivot=0.25),
])
def test_linear_solvers_refuse_a_steady_solution(perturbed, call):
    grid, flow, q, _ = perturbed
    with pytest.raises(LinearError, match=r"expected a LinearSystem as lin, got Sol; pass cfd.linearise\(sol\)"):
        call(_solution_like(grid, q, flow))
    with pytest.raises(LinearError, match="expected a LinearSystem as lin, got NoneType; build it with"):
        call(None)


def test_output_names():
    assert check_outputs("Cl") == (("Cl",), [0])
    with pytest.raises(LinearError, match="Cy"):
        check_outputs(("Cl", "Cy"))
