import numpy as np
import pytest

from cfd import MeshError
from cfd.euler import Scheme, residual
from cfd.flow import FlowCondition, conserved, primitive
from flowgrids import parabolic_c_grid


def _uniform(grid, flow):
    return np.broadcast_to(flow.q, grid.cell_shape + (4,)).copy()


@pytest.mark.parametrize("vortex", [False, True])
def test_free_stream_is_preserved_to_round_off_on_a_curved_grid_with_wall_wake_and_far_field(vortex):
    # Flat plate (a slit along 0 <= x <= 1) on a skewed, curved parabolic C-grid: a stream along x is an
    # exact slip-wall solution, so every cell (wall, wake cut, far field) must stay at round-off.
    g = parabolic_c_grid(thickness=0.0, wiggle=0.3)
    flow = FlowCondition(0.7, 0.0)
    R = residual(g, _uniform(g, flow), flow, scheme=Scheme(vortex=vortex))
    assert np.max(np.abs(R)) < 1e-13


def test_free_stream_is_preserved_away_from_the_wall_at_incidence():
    g = parabolic_c_grid(thickness=0.12, wiggle=0.3)
    flow = FlowCondition(0.6, 3.0)
    R = residual(g, _uniform(g, flow), flow)
    # The wall ghosts reach two rows; beyond them the uniform state is an exact discrete solution.
    assert np.max(np.abs(R[:, 2:])) < 1e-13
    assert np.max(np.abs(R[g.wall, 0])) > 1e-4  # the wall does feel the flow through it


def _galilean(q, vg):
    rho, u, v, p = primitive(q)
    return conserved(rho, u + vg[0], v + vg[1], p)


def test_uniform_grid_velocity_is_a_galilean_change_of_frame():
    # A grid moving with V_g in a stream u_inf + V_g is the fixed-grid problem seen from another frame:
    # R' = T R with T the Galilean map of the conserved variables (mass, momentum, energy).
    g = parabolic_c_grid(thickness=0.12, wiggle=0.3)
    flow = FlowCondition(0.6, 2.0)
    rng = np.random.default_rng(1)
    q = _uniform(g, flow) * (1 + 0.02 * rng.standard_normal(g.cell_shape + (4,)))
    vg = np.array([0.13, -0.21])
    u_shift = flow.velocity + vg
    flow2 = FlowCondition(np.hypot(*u_shift), np.rad2deg(np.arctan2(u_shift[1], u_shift[0])))
    ni, nj = g.shape
    wi = np.broadcast_to(vg[:, None, None], (2, ni, nj - 1))
    wj = np.broadcast_to(vg[:, None, None], (2, ni - 1, nj))
    R2 = residual(g, _galilean(q, vg), flow2, face_velocity=(wi, wj))
    R = residual(g, q, flow)
    TR = R.copy()
    TR[..., 1:3] += vg * R[..., :1]
    TR[..., 3] += R[..., 1:3] @ vg + 0.5 * (vg @ vg) * R[..., 0]
    assert np.max(np.abs(R2 - TR)) < 1e-13 * max(1.0, np.max(np.abs(R)))


def test_source_is_subtracted_and_batches_are_independent():
    g = parabolic_c_grid(thickness=0.12)
    flow = FlowCondition(0.5, 1.0)
    rng = np.random.default_rng(2)
    q = _uniform(g, flow) * (1 + 0.01 * rng.standard_normal(g.cell_shape + (4,)))
    s = rng.standard_normal(q.shape)
    assert np.allclose(residual(g, q, flow, source=s), residual(g, q, flow) - s, rtol=0, atol=1e-15)
    batch = np.stack([q, _uniform(g, flow)])
    Rb = residual(g, batch, flow)
    assert np.array_equal(Rb[0], residual(g, q, flow))


def test_complex_state_with_zero_imaginary_part_gives_the_real_residual():
    g = parabolic_c_grid(thickness=0.12)
    flow = FlowCondition(0.8, 1.25)
    rng = np.random.default_rng(3)
    q = _uniform(g, flow) * (1 + 0.05 * rng.standard_normal(g.cell_shape + (4,)))
    Rc = residual(g, q.astype(complex), flow)
    # Complex products may round differently in the last bit; no imaginary part may appear.
    assert np.allclose(Rc.real, residual(g, q, flow), rtol=1e-13, atol=1e-13) and not np.any(Rc.imag)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(q=np.ones((3, 3, 4))), r"q has shape \(3, 3, 4\); this grid needs"),
        (dict(face_velocity=(np.zeros((2, 3, 3)), np.zeros((2, 3, 3)))), "face_velocity"),
        (dict(source=np.zeros((2, 2, 4))), "source has shape"),
    ],
)
def test_bad_shapes_raise_mesh_error(kwargs, match):
    g = parabolic_c_grid(thickness=0.12)
    flow = FlowCondition(0.5)
    q = kwargs.pop("q", _uniform(g, flow))
    with pytest.raises(MeshError, match=match):
        residual(g, q, flow, **kwargs)


# --- input checks (issue 34) ---------------------------------------------------------------------------------------

@pytest.mark.parametrize("kwargs, match", [
    (dict(k2=-1.0), r"Scheme.k2 must be a finite number >= 0 \(default 0.5\); got -1.0"),
    (dict(k4=float("nan")), r"Scheme.k4 must be a finite number >= 0"),
    (dict(k4="1/64"), r"Scheme.k4 must be a finite number >= 0"),
    (dict(vortex="no"), r"Scheme.vortex must be True or False; got 'no'"),   # 'no' turned the vortex on
])
def test_scheme_constants_are_checked_when_made(kwargs, match):
    from cfd import FlowConditionError

    with pytest.raises(FlowConditionError, match=match):
        Scheme(**kwargs)


def test_residual_checks_the_types_of_its_arguments():
    # a string for the grid or the flow raised Python's AttributeError
    from cfd import FlowConditionError

    g = parabolic_c_grid(thickness=0.12)
    flow = FlowCondition(0.5)
    q = _uniform(g, flow)
    with pytest.raises(MeshError, match="grid must be a cfd.Grid"):
        residual("grid", q, flow)
    with pytest.raises(FlowConditionError, match=r"flow must be a cfd.FlowCondition\(mach, alpha_deg\); got str"):
        residual(g, q, "M0.5")
    with pytest.raises(FlowConditionError, match=r"scheme must be a cfd.Scheme or None; got dict"):
        residual(g, q, flow, scheme={"k2": 0.5})
