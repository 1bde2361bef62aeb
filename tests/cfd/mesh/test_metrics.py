import numpy as np
import pytest

from cfd import MeshError, grid_from_nodes
from cfd.mesh.metrics import inverted_cells, signed_cell_areas


def _annulus(ni=41, nj=9, r0=1.0, r1=3.0):
    # Nodes ordered with i clockwise and j outward: right-handed (i, j) in the sense of cfd.mesh.
    theta = np.linspace(0.0, -1.5 * np.pi, ni)
    r = np.geomspace(r0, r1, nj)
    return np.outer(np.cos(theta), r), np.outer(np.sin(theta), r)


def test_metrics_close_every_cell_and_sum_to_the_exact_area():
    x, y = _annulus()
    g = grid_from_nodes(x, y, n_wake=0)
    closure = g.si[:, 1:, :] - g.si[:, :-1, :] + g.sj[:, :, 1:] - g.sj[:, :, :-1]
    assert np.max(np.abs(closure)) < 1e-14
    # Polygonal annulus sector area: sum of trapezoids between the polygonal arcs.
    chords = lambda j: 0.5 * np.abs(x[:-1, j] * y[1:, j] - x[1:, j] * y[:-1, j]).sum()
    assert g.area.sum() == pytest.approx(chords(-1) - chords(0), rel=1e-13)


@pytest.mark.parametrize(
    "mutate, match",
    [
        (lambda x, y: (x[:, ::-1], y[:, ::-1]), "inverted"),
        (lambda x, y: (x[:5], y[:5]), "too small"),
        (lambda x, y: (np.where(x > 2.5, np.nan, x), y), "NaN"),
        # strings raised NumPy's "could not convert string to float"; complex nodes lost their imaginary part
        (lambda x, y: ("a", "b"), r"x must be a 2-D array of real node coordinates .*got str"),
        (lambda x, y: (x, y + 0j), r"y must be a 2-D array of real node coordinates .*got dtype complex128"),
        (lambda x, y: (x, None), r"y must be a 2-D array of real node coordinates .*got NoneType"),
    ],
)
def test_bad_grids_raise_mesh_error(mutate, match):
    x, y = _annulus()
    with pytest.raises(MeshError, match=match):
        grid_from_nodes(*mutate(x, y), n_wake=0)


@pytest.fixture(scope="module")
def c_grid_nodes():
    from flowgrids import parabolic_c_grid

    g = parabolic_c_grid(thickness=0.1, n_surface=32, n_wake=8, nj=13)
    return g.x, g.y


@pytest.mark.parametrize("n_wake", [0, 3, 7, 9])
def test_n_wake_that_does_not_match_the_wake_cut_names_the_right_value(c_grid_nodes, n_wake):
    with pytest.raises(MeshError, match=rf"n_wake = {n_wake} does not match the grid.*n_wake should be 8"):
        grid_from_nodes(*c_grid_nodes, n_wake=n_wake)


@pytest.mark.parametrize("n_wake", [10.7, "8", None, True, float("inf")])
def test_n_wake_must_be_a_whole_number(c_grid_nodes, n_wake):
    with pytest.raises(MeshError, match="n_wake must be a whole number"):
        grid_from_nodes(*c_grid_nodes, n_wake=n_wake)


@pytest.mark.parametrize("n_wake", [-1, 23])
def test_n_wake_out_of_range_raises(c_grid_nodes, n_wake):
    with pytest.raises(MeshError, match=f"n_wake = {n_wake} leaves"):
        grid_from_nodes(*c_grid_nodes, n_wake=n_wake)


def test_grid_without_a_cut_needs_n_wake_zero():
    x, y = _annulus()
    with pytest.raises(MeshError, match="no wake cut; pass n_wake=0"):
        grid_from_nodes(x, y, n_wake=2)


def test_matching_n_wake_is_accepted_also_as_a_numpy_integer(c_grid_nodes):
    assert grid_from_nodes(*c_grid_nodes, n_wake=np.int64(8)).n_wake == 8
    assert grid_from_nodes(*c_grid_nodes, n_wake=8.0).n_wake == 8  # a whole-valued float, e.g. (ni - 1 - n) / 2


# signed_cell_areas (and inverted_cells, through it): complex nodes lost their imaginary part with only a
# ComplexWarning; text raised NumPy's "could not convert string to float", None an IndexError
@pytest.mark.parametrize("function", [signed_cell_areas, inverted_cells])
@pytest.mark.parametrize("which", ["x", "y"])
@pytest.mark.parametrize("make, kind", [
    (lambda a: a + 0.5j, "dtype complex128"),
    (lambda a: a.astype(np.complex64), "dtype complex64"),
    (lambda a: "a", "str"),
    (lambda a: None, "NoneType"),
])
def test_cell_areas_refuse_nodes_that_are_not_real(function, which, make, kind):
    x, y = _annulus(ni=5, nj=3)
    args = (make(x), y) if which == "x" else (x, make(y))
    with pytest.raises(MeshError, match=rf"{which} must be a 2-D array of real node coordinates .*got {kind}"):
        function(*args)


# Before: 1-D or scalar nodes raised a bare IndexError, nodes of two shapes NumPy's broadcasting ValueError, and 3-D
# nodes gave areas of shape (ni-1, nj-1, k) without a word.
@pytest.mark.parametrize("function", [signed_cell_areas, inverted_cells])
@pytest.mark.parametrize("make", [
    pytest.param(lambda x, y: (x[:, 0], y[:, 0]), id="1-D"),
    pytest.param(lambda x, y: (1.0, 2.0), id="scalars"),
    pytest.param(lambda x, y: (x, y[:, :-1]), id="two-shapes"),
    pytest.param(lambda x, y: (x[..., None], y[..., None]), id="3-D"),
])
def test_cell_areas_refuse_nodes_that_are_not_2d_arrays_of_one_shape(function, make):
    with pytest.raises(MeshError, match=r"x and y must be 2-D arrays of node coordinates of the same shape "
                                        r"\(ni, nj\); got shapes"):
        function(*make(*_annulus(ni=5, nj=3)))


def test_cell_areas_of_nodes_of_any_real_type_are_the_same():
    x, y = np.meshgrid([0.0, 1.0, 3.0], [0.0, 0.5, 2.0], indexing="ij")   # exact in float32 and as ints (x4)
    ref = signed_cell_areas(x, y)
    assert np.array_equal(ref, [[0.5, 1.5], [1.0, 3.0]])
    for convert in (lambda a: a.astype(np.float32), lambda a: a.tolist()):
        assert np.array_equal(signed_cell_areas(convert(x), convert(y)), ref)
    assert np.array_equal(signed_cell_areas((4 * x).astype(int), (4 * y).astype(int)), 16 * ref)
    assert inverted_cells(x[::-1], y).tolist() == [[0, 0], [0, 1], [1, 0], [1, 1]]
