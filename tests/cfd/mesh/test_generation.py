import numpy as np
import pytest

from cfd import MeshError, c_grid, grid_quality, naca


@pytest.fixture(scope="module", params=["0010", "2410"])
def paper(request):
    foil = naca(request.param)
    return foil, c_grid(foil)  # 181 x 60 nodes, 100 wall cells, R = 25 chords


def test_paper_grid_shapes(paper):
    _, g = paper
    assert g.shape == (181, 60)
    assert g.cell_shape == (180, 59) and g.n_cells == 10620
    assert g.n_wake == 40 and g.n_surface == 100
    assert g.wall == slice(40, 140)


def test_wall_nodes_lie_on_the_aerofoil_from_lower_te_to_upper_te(paper):
    foil, g = paper
    xw, yw = g.x[40:141, 0], g.y[40:141, 0]
    dx, dy = foil.surface(np.linspace(0.0, 1.0, 200001))
    k = np.clip(np.hypot(xw[:, None] - dx[None], yw[:, None] - dy[None]).argmin(axis=1), 1, dx.size - 2)

    def seg_dist(a):  # distance from each wall node to the dense segment (a, a + 1)
        ex, ey = dx[a + 1] - dx[a], dy[a + 1] - dy[a]
        t = np.clip(((xw - dx[a]) * ex + (yw - dy[a]) * ey) / (ex**2 + ey**2), 0, 1)
        return np.hypot(xw - dx[a] - t * ex, yw - dy[a] - t * ey)

    assert np.minimum(seg_dist(k - 1), seg_dist(k)).max() < 1e-8
    assert (xw[0], yw[0]) == (1.0, 0.0) == (xw[-1], yw[-1])
    # Lower surface first (i increasing towards the leading edge), then the upper surface.
    assert np.all(np.diff(xw[:50]) < 0) and np.all(np.diff(xw[51:]) > 0)
    assert np.mean(yw[1:50]) < np.mean(yw[51:-1])


def test_wake_cut_nodes_coincide_pairwise_and_follow_the_te_bisector(paper):
    foil, g = paper
    ni = g.shape[0]
    i = np.arange(41)
    assert np.array_equal(g.x[i, 0], g.x[ni - 1 - i, 0])
    assert np.array_equal(g.y[i, 0], g.y[ni - 1 - i, 0])
    # A straight line from the trailing edge, along the bisector of the TE wedge.
    xs, ys = g.x[:41, 0], g.y[:41, 0]
    angle = np.degrees(np.arctan2(ys[:-1], xs[:-1] - 1.0))
    assert np.ptp(angle) < 1e-9
    # The bisector of the wedge is along the camber line at the trailing edge (thickness is applied
    # symmetrically about it): 0 for symmetric sections, atan(-2 m / (1 - p)) = -3.81 deg for 2410.
    assert angle[0] == pytest.approx(np.degrees(np.arctan(foil.camber(1.0)[1])), abs=1e-3)
    assert np.all(np.diff(xs) < 0)  # i runs from the outflow towards the trailing edge


def test_far_field_radius_and_outflow_plane(paper):
    _, g = paper
    xo, yo = g.x[:, -1], g.y[:, -1]
    r = np.hypot(xo - 0.5, yo)
    assert r.min() == pytest.approx(25.0, rel=1e-12)
    front = xo < 0.5
    assert np.allclose(r[front], 25.0, rtol=1e-12)
    assert np.allclose(g.x[0], 25.5) and np.allclose(g.x[-1], 25.5)  # outflow plane x = 0.5 + R
    assert np.abs(yo).max() == pytest.approx(25.0)


def test_areas_positive_and_metrics_close(paper):
    _, g = paper
    assert np.all(g.area > 0)
    closure = g.si[:, 1:, :] - g.si[:, :-1, :] + g.sj[:, :, 1:] - g.sj[:, :, :-1]
    assert np.abs(closure).max() < 1e-12
    # The cells tile the annulus between the far field and the aerofoil.
    # Boundary loop: j = 0 (cut and wall), i = ni-1 outward, far field backwards, i = 0 inward.
    bx = np.concatenate([g.x[:, 0], g.x[-1, 1:], g.x[-2::-1, -1], g.x[0, -2:0:-1]])
    by = np.concatenate([g.y[:, 0], g.y[-1, 1:], g.y[-2::-1, -1], g.y[0, -2:0:-1]])
    enclosed = 0.5 * np.sum(bx * np.roll(by, -1) - np.roll(bx, -1) * by)
    assert g.area.sum() == pytest.approx(enclosed, rel=1e-12)


def test_near_orthogonal_at_wall_with_the_requested_first_height(paper):
    _, g = paper
    q = grid_quality(g)
    # The first j-edge is along the node normal (tangent from central differences). A cell corner
    # angle then differs from 90 deg by about half the surface turning over one cell: at most about
    # 8 deg on the 100-cell nose (15-20 deg of turning per cell), well under 1 deg over most of the chord.
    assert q.max_wall_nonorthogonality < 10.0
    assert q.max_cut_nonorthogonality < 7.0
    assert q.min_wall_height == pytest.approx(0.004, rel=1e-9)
    assert q.max_wall_height == pytest.approx(0.004, rel=1e-9)


def test_quality_figures_are_sane(paper):
    _, g = paper
    q = grid_quality(g)
    assert q.shape == (181, 60) and q.n_cells == 10620
    assert q.min_area > 1e-6
    assert 30.0 < q.min_angle and q.max_angle < 150.0 and q.max_skewness < 0.7
    assert q.max_stretch_i < 2.0 and q.max_stretch_j < 1.25
    assert q.max_aspect_ratio < 200.0
    assert "max_skewness" in str(q) and set(q.as_dict()) >= {"min_area", "max_aspect_ratio"}


def test_other_sizes_far_fields_and_the_transfinite_grid():
    foil = naca("0012")
    g = c_grid(foil, ni=121, nj=40, n_surface=64, farfield=10.0)
    assert g.shape == (121, 40) and g.n_wake == 28
    assert np.hypot(g.x[:, -1] - 0.5, g.y[:, -1]).min() == pytest.approx(10.0)
    t = c_grid(foil, ni=121, nj=40, n_surface=64, farfield=10.0, smooth=False)
    assert np.all(t.area > 0)
    assert np.array_equal(t.x[:, 0], g.x[:, 0]) and np.array_equal(t.x[:, -1], g.x[:, -1])
    assert grid_quality(t).max_wall_nonorthogonality > grid_quality(g).max_wall_nonorthogonality


@pytest.mark.parametrize("ni, nj, n_surface, farfield", [(61, 20, 40, 10.0), (121, 40, 64, 50.0), (201, 16, 120, 5.0)])
def test_small_and_large_grids_keep_the_far_field_and_cut(ni, nj, n_surface, farfield):
    g = c_grid(naca("2410"), ni=ni, nj=nj, n_surface=n_surface, farfield=farfield)
    assert g.shape == (ni, nj) and np.all(g.area > 0)
    r = np.hypot(g.x[:, -1] - 0.5, g.y[:, -1])
    assert r.min() == pytest.approx(farfield, rel=1e-12) and np.abs(g.y[:, -1]).max() == pytest.approx(farfield)
    assert np.allclose(g.x[0], 0.5 + farfield) and np.allclose(g.x[-1], 0.5 + farfield)
    nw = g.n_wake
    assert np.array_equal(g.x[: nw + 1, 0], g.x[: ni - 2 - nw : -1, 0])
    assert grid_quality(g).max_wall_nonorthogonality < 15.0


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(n_surface=99), "must be even"),
        (dict(n_surface=4), "at least 8"),
        (dict(ni=101, n_surface=100), "wake branches"),
        (dict(ni=182), "it must be even"),
        (dict(nj=15), "nj >= 16"),
        (dict(farfield=1.0), "too close"),
        (dict(ni=181.0), "must be an integer"),
        (dict(wall_spacing=0.0), "wall_spacing"),
        (dict(te_spacing=0.5), "te_spacing"),
        (dict(le_spacing=-1.0), "le_spacing"),
        (dict(farfield="far"), "finite number of chords"),
        (dict(wall_spacing="a"), "wall_spacing must be a number of chords; got 'a'"),
        (dict(te_spacing=None), "te_spacing must be a number of chords; got None"),
        (dict(march_distance=float("nan")), r"march_distance must be a number of chords with 0 <= march_distance < "
                                             r"farfield = 25 .*got nan"),
        (dict(march_distance=-1.0), r"march_distance must be a number of chords with 0 <= march_distance"),
        (dict(march_distance="a"), r"march_distance must be a number of chords with 0 <= march_distance"),
        # 0 and a distance past the far field both marched 2 layers and failed as a fold "around strongly cambered
        # sections" (here on a NACA0012)
        (dict(march_distance=100.0), r"0 <= march_distance < farfield = 25 .*got 100.0"),
        (dict(march_distance=5.0, farfield=5.0), r"0 <= march_distance < farfield = 5 "),
        (dict(tol=float("nan")), "tol must be a positive finite number"),
        (dict(tol=0.0), "tol must be a positive finite number"),
        (dict(max_iter=-1), "max_iter must be a whole number >= 0"),
        (dict(max_iter=2.5), "max_iter must be a whole number >= 0"),
        (dict(max_iter="x"), "max_iter must be a whole number >= 0"),
        (dict(n_layers=-3), "n_layers must be a whole number >= 0"),
        (dict(n_layers=2.5), "n_layers must be a whole number >= 0"),
    ],
)
def test_bad_sizes_raise_mesh_error_saying_what_to_do(kwargs, match):
    with pytest.raises(MeshError, match=match):
        c_grid(naca("0012"), **kwargs)


def test_foil_must_be_an_aerofoil():
    with pytest.raises(MeshError, match="cfd.naca"):
        c_grid("0012")


def test_a_folded_c_grid_says_what_helps_the_generator():
    # NACA 4912 folds on a coarse grid (and meshes on the paper's 181 x 60): the message is about c_grid's
    # settings, not "check the node ordering" (the user gave no nodes)
    with pytest.raises(MeshError, match=r"c_grid folded the grid around NACA4912: \d+ inverted cells, first at "
                                        r"cell \(\d+, \d+\)\. .*use more nodes") as info:
        c_grid(naca("4912"), ni=81, nj=16, n_surface=60, farfield=10.0)
    assert "node ordering" not in str(info.value) and "np.int64" not in str(info.value)


def test_inverted_grid_is_refused():
    g = c_grid(naca("0012"), ni=121, nj=40, n_surface=64, smooth=False)
    from cfd import grid_from_nodes

    with pytest.raises(MeshError, match="inverted"):
        grid_from_nodes(g.x[::-1], g.y[::-1], g.n_wake)


@pytest.mark.parametrize("not_a_grid", [None, np.zeros((3, 3)), "grid"])
def test_grid_quality_names_what_it_got(not_a_grid):
    with pytest.raises(MeshError, match=rf"grid must be a cfd.Grid .*got {type(not_a_grid).__name__}"):
        grid_quality(not_a_grid)


# --- input checks (issue 34) ---------------------------------------------------------------------------------------

@pytest.mark.parametrize("kwargs, match", [
    (dict(smooth="no"), r"smooth must be True or False; got 'no'"),               # 'no' smoothed
    (dict(farfield=1e300), r"farfield = 1e\+300 chords is beyond cfd.mesh.generation.MAX_FARFIELD = 10000"),
    (dict(ni=2001, nj=2001, n_surface=1000), r"ni \* nj = 2001 \* 2001 = 4004001 nodes is more than "
                                             r"cfd.mesh.generation.MAX_NODES = 4e\+06"),
])
def test_c_grid_refuses_absurd_settings_before_any_work(kwargs, match):
    # farfield=1e300 failed in SuperLU ("Factor is exactly singular") after overflows
    args = dict(ni=81, nj=16, n_surface=40)
    args.update(kwargs)
    with pytest.raises(MeshError, match=match):
        c_grid(naca("0012"), **args)


def test_march_distance_zero_marches_the_least_block():
    # 0 marches two layers: a valid grid at the default size (refused for a while, as "0 < march_distance")
    g = c_grid(naca("0012"), march_distance=0.0)
    assert np.all(np.isfinite(g.x)) and g.x.shape == c_grid(naca("0012")).x.shape


def test_a_fold_of_a_thin_marched_block_names_march_distance():
    with pytest.raises(MeshError, match=r"folded the grid around NACA0012.*march_distance = 0.01 chords is below the "
                                        r"default 0.3"):
        c_grid(naca("0012"), ni=65, nj=17, n_surface=48, march_distance=0.01)


def test_a_march_distance_beyond_every_i_line_marches_the_most_layers():
    # 24.9 chords reaches no layer of the shortest i-line (the far field is 24.5 chords from the leading edge):
    # it marched 2 layers and folded; now nj // 2, the same grid as any distance past the last marched layer
    a = c_grid(naca("0012"), ni=65, nj=17, n_surface=48, march_distance=24.9)
    b = c_grid(naca("0012"), ni=65, nj=17, n_surface=48, march_distance=10.0)
    np.testing.assert_array_equal(a.x, b.x)
    np.testing.assert_array_equal(a.y, b.y)
