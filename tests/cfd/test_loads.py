import numpy as np
import pytest

from cfd import FlowConditionError, MeshError
from cfd.flow import FlowCondition, conserved
from cfd.loads import force_coefficients, wall_cp
from flowgrids import parabolic_c_grid


def _hydrostatic(grid, flow, G):
    # Fluid at rest with p = p_inf - G y: the pressure force on the body is the buoyancy G * area, up.
    p = flow.p - G * grid.yc
    return conserved(np.ones_like(p), 0.0, 0.0, p, flow.gamma)


def _body_area_and_centroid(grid):
    x, y = grid.x[grid.wall.start:grid.wall.stop + 1, 0], grid.y[grid.wall.start:grid.wall.stop + 1, 0]
    cross = x[:-1] * y[1:] - x[1:] * y[:-1]
    a = 0.5 * cross.sum()  # the wall runs clockwise (lower surface TE -> LE -> upper): a < 0
    xc = ((x[:-1] + x[1:]) * cross).sum() / (6 * a)
    return abs(a), xc


def test_uniform_pressure_gives_no_load():
    g = parabolic_c_grid(thickness=0.12)
    flow = FlowCondition(0.5, 3.0)
    q = np.broadcast_to(flow.q, g.cell_shape + (4,))
    cl, cd, cm = force_coefficients(g, q, flow)
    _, cp = wall_cp(g, q, flow)
    assert np.max(np.abs(cp)) < 1e-13
    assert max(abs(cl), abs(cd), abs(cm)) < 1e-13


@pytest.mark.parametrize("alpha", [0.0, 5.0])
def test_buoyancy_is_archimedes_in_wind_axes_and_acts_at_the_centroid(alpha):
    g = parabolic_c_grid(thickness=0.12, n_surface=96, n_wake=16, nj=33)
    flow = FlowCondition(0.5, alpha)
    G = 0.01
    cl, cd, cm = force_coefficients(g, _hydrostatic(g, flow, G), flow)
    area, xc = _body_area_and_centroid(g)
    lift = G * area / flow.dynamic_pressure  # vertical force coefficient (body axes)
    a = np.deg2rad(alpha)
    assert cl == pytest.approx(lift * np.cos(a), rel=2e-3)
    assert cd == pytest.approx(lift * np.sin(a), rel=2e-3, abs=1e-12)
    # An upward force behind the quarter chord pitches the nose down.
    assert cm == pytest.approx(-(xc - 0.25) * lift, rel=1e-2)


def test_wall_positions_follow_the_c_grid_order():
    g = parabolic_c_grid(thickness=0.12)
    x_wall, _ = wall_cp(g, np.broadcast_to(FlowCondition(0.5).q, g.cell_shape + (4,)), FlowCondition(0.5))
    assert x_wall.shape == (g.n_surface,)
    assert x_wall[0] > 0.9 and x_wall[-1] > 0.9 and x_wall.min() < 0.01


@pytest.mark.parametrize("load", [wall_cp, force_coefficients])
@pytest.mark.parametrize("bad, match", [
    (lambda q: q.transpose(1, 0, 2), r"q has shape \(12, 48, 4\); this grid needs \(\.\.\., 48, 12, 4\)"),
    (lambda q: q[..., :3], r"q has shape \(48, 12, 3\)"),
    (lambda q: q[0], r"q has shape \(12, 4\)"),
])
def test_state_of_the_wrong_shape_is_refused_as_residual_does(load, bad, match):
    g = parabolic_c_grid(thickness=0.1, n_surface=32, n_wake=8, nj=13)
    flow = FlowCondition(0.5)
    q = np.broadcast_to(flow.q, g.cell_shape + (4,))
    with pytest.raises(MeshError, match=match):
        load(g, bad(q), flow)


@pytest.mark.parametrize("load", [wall_cp, force_coefficients])
def test_flow_and_grid_types_are_checked(load):
    g = parabolic_c_grid(thickness=0.1, n_surface=32, n_wake=8, nj=13)
    flow = FlowCondition(0.5)
    q = np.broadcast_to(flow.q, g.cell_shape + (4,))
    with pytest.raises(FlowConditionError, match="flow must be a cfd.FlowCondition"):
        load(g, q, 0.5)
    with pytest.raises(MeshError, match="grid must be a cfd.Grid"):
        load(None, q, flow)


@pytest.mark.parametrize("x_ref", [(np.nan, 0.0), (0.25, 0.0, 0.0), (0.25,), "quarter", (0.25 + 1j, 0.0)])
def test_moment_reference_must_be_a_finite_point(x_ref):
    # (nan, 0) gave a NaN cm, (0.25, 0, 0) was taken as (0.25, 0)
    g = parabolic_c_grid(thickness=0.1, n_surface=32, n_wake=8, nj=13)
    flow = FlowCondition(0.5)
    q = np.broadcast_to(flow.q, g.cell_shape + (4,))
    with pytest.raises(FlowConditionError, match=r"x_ref must be a finite point \(x, y\) in chords"):
        force_coefficients(g, q, flow, x_ref=x_ref)


def _negative_density(q):
    q[..., 0] = -1.0   # every cell: loads of no flow, returned as numbers before


def _negative_pressure(q):
    q[3, 0, 3] = 0.0   # energy 0 under a moving fluid: p < 0 in one cell


def _infinite(q):
    q[0, 0, 3] = np.inf


@pytest.mark.parametrize("load", [wall_cp, force_coefficients])
@pytest.mark.parametrize("spoil", [_infinite, _negative_density, _negative_pressure])
def test_loads_of_a_state_that_is_not_a_flow_are_refused(load, spoil):
    # as solve_steady refuses such a q0; a negative density gave loads as numbers
    g = parabolic_c_grid(thickness=0.1, n_surface=32, n_wake=8, nj=13)
    flow = FlowCondition(0.5)
    q = np.array(np.broadcast_to(flow.q, g.cell_shape + (4,)))
    spoil(q)
    with pytest.raises(FlowConditionError, match=r"q contains NaN, inf or non-positive density or pressure: it is "
                                                 r"not a flow"):
        load(g, q, flow)
