import meshio
import numpy as np
import pytest

from cfd import FlowConditionError, MeshError, c_grid, naca
from cfd.export import primitives, write_vtk


@pytest.fixture(scope="module")
def grid():
    return c_grid(naca("0012"), ni=61, nj=20, n_surface=40, farfield=10.0)


def freestream(shape, mach, alpha_deg, gamma=1.4):
    a = np.radians(alpha_deg)
    u, v = mach * np.cos(a), mach * np.sin(a)
    p = 1.0 / gamma
    q = np.empty(shape + (4,))
    q[..., 0] = 1.0
    q[..., 1] = u
    q[..., 2] = v
    q[..., 3] = p / (gamma - 1) + 0.5 * (u**2 + v**2)
    return q


def test_primitives_of_the_free_stream():
    f = primitives(freestream((3, 2), 0.735, 2.0), mach=0.735)
    assert f["rho"] == pytest.approx(np.ones((3, 2)))
    assert f["pressure"] == pytest.approx(np.full((3, 2), 1 / 1.4))
    assert f["mach"] == pytest.approx(np.full((3, 2), 0.735))
    assert f["cp"] == pytest.approx(np.zeros((3, 2)), abs=1e-14)
    assert f["velocity"][..., 1] == pytest.approx(np.full((3, 2), 0.735 * np.sin(np.radians(2.0))))


def test_primitives_of_a_stagnation_state_give_cp_above_one():
    # Isentropic stagnation at M0.5: p0/p = (1 + 0.2 M^2)^3.5, Cp0 = 2/(gamma M^2) (p0/p - 1) = 1.0641
    # (1 + M^2/4 + M^4/40 to fourth order).
    gamma, m = 1.4, 0.5
    p0 = (1 + 0.2 * m**2) ** 3.5 / gamma
    q = np.array([(1 + 0.2 * m**2) ** 2.5, 0.0, 0.0, p0 / (gamma - 1)])
    f = primitives(q, mach=m)
    assert f["cp"] == pytest.approx(1.0641, abs=1e-4) and f["mach"] == 0.0


def test_vtk_round_trip(grid, tmp_path):
    q = freestream(grid.cell_shape, 0.5, 1.0)
    q[..., 0] += 0.01 * grid.xc  # something that varies per cell
    f = primitives(q, 0.5)
    path = tmp_path / "flow.vtu"
    write_vtk(grid, path, {"rho": f["rho"], "velocity": f["velocity"], "cp": f["cp"]})
    m = meshio.read(path)
    assert m.points.shape == (grid.x.size, 3)
    quads = m.cells_dict["quad"]
    assert quads.shape == (grid.n_cells, 4)
    assert np.allclose(m.points[:, 0], grid.x.ravel()) and np.allclose(m.points[:, 1], grid.y.ravel())
    rho = m.cell_data["rho"][0].reshape(grid.cell_shape)
    assert np.allclose(rho, f["rho"])
    vel = m.cell_data["velocity"][0]
    assert vel.shape == (grid.n_cells, 3) and np.allclose(vel[:, 2], 0.0)
    assert np.allclose(vel[:, :2].reshape(grid.cell_shape + (2,)), f["velocity"])
    # Quads are counter-clockwise (positive area) as ParaView expects.
    p = m.points[quads]
    area = 0.5 * ((p[:, 2, 0] - p[:, 0, 0]) * (p[:, 3, 1] - p[:, 1, 1]) - (p[:, 3, 0] - p[:, 1, 0]) * (p[:, 2, 1] - p[:, 0, 1]))
    assert np.allclose(area, grid.area.ravel())


def test_legacy_vtk_and_bad_field_shape(grid, tmp_path):
    write_vtk(grid, tmp_path / "grid.vtk")
    assert meshio.read(tmp_path / "grid.vtk").cells_dict["quad"].shape == (grid.n_cells, 4)
    with pytest.raises(MeshError, match="expected"):
        write_vtk(grid, tmp_path / "bad.vtu", {"p": np.zeros((3, 3))})


# A complex q or field lost its imaginary part with only a ComplexWarning; text failed in NumPy ("could not convert
# string to float"), a None q with an IndexError.
NOT_REAL = [
    pytest.param(lambda a: a + 1j, "dtype complex128", id="complex"),
    pytest.param(lambda a: a.astype(np.complex64), "dtype complex64", id="complex64"),
    pytest.param(lambda a: "rho", "str", id="text"),
    pytest.param(lambda a: None, "NoneType", id="None"),
]


@pytest.mark.parametrize("make, kind", NOT_REAL)
def test_primitives_refuse_states_that_are_not_real(make, kind):
    q = freestream((3, 2), 0.5, 1.0)
    with pytest.raises(MeshError, match=f"q must be an array of real conserved states.*got {kind}"):
        primitives(make(q), 0.5)


# Before: a q whose last axis is not 4 raised a plain ValueError (a scalar q a bare IndexError), a mach given as text
# a bare TypeError, a NaN or negative one a plain ValueError.
@pytest.mark.parametrize("q", [np.ones((3, 3)), np.ones(5), np.float64(1.0)], ids=["(3, 3)", "(5,)", "scalar"])
def test_primitives_refuse_states_without_a_last_axis_of_4(q):
    with pytest.raises(MeshError, match=r"q must have a last axis of 4 .*got shape"):
        primitives(q, 0.5)


@pytest.mark.parametrize("mach", [0.0, -0.5, np.nan, np.inf, "0.5", None, 0.5j])
def test_primitives_refuse_a_mach_that_is_not_positive_and_finite(mach):
    with pytest.raises(FlowConditionError, match="mach must be a positive finite real number"):
        primitives(freestream((3, 2), 0.5, 1.0), mach)


@pytest.mark.parametrize("make, kind", NOT_REAL)
def test_write_vtk_refuses_fields_that_are_not_real(grid, tmp_path, make, kind):
    path = tmp_path / "bad.vtu"
    with pytest.raises(MeshError, match=f"cell field 'cp' must be an array of real numbers.*got {kind}"):
        write_vtk(grid, path, {"rho": np.ones(grid.cell_shape), "cp": make(np.zeros(grid.cell_shape))})
    assert not path.exists()


@pytest.mark.parametrize("convert", [lambda a: a.astype(int), lambda a: a.astype(np.float32), lambda a: a.tolist()],
                         ids=["int", "float32", "list"])
def test_real_states_and_fields_of_any_real_type_are_taken(grid, tmp_path, convert):
    q = np.array([[1.0, 1.0, 0.0, 3.0], [2.0, 1.0, 1.0, 5.0]])   # whole numbers: the int array is the same states
    ref = primitives(q, 0.5)
    f = primitives(convert(q), 0.5)
    for k in ref:
        assert np.allclose(f[k], ref[k], rtol=1e-6)
    write_vtk(grid, tmp_path / "ok.vtu", {"i": np.arange(grid.n_cells).reshape(grid.cell_shape),
                                          "f": convert(np.ones(grid.cell_shape))})
    assert np.array_equal(meshio.read(tmp_path / "ok.vtu").cell_data["i"][0], np.arange(grid.n_cells))
