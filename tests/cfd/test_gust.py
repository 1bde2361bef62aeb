"""Gust shapes, exact face averages and cell integrals against independent quadrature."""

import math

import numpy as np
import pytest

from cfd import grid_from_nodes
from cfd.gust import (
    GustError,
    GustPositionError,
    OneMinusCosine,
    SharpEdged,
    SineGust,
    cell_x_gradient,
    edge_average,
    face_gust,
    face_gust_harmonic,
    gust_face_velocity,
    harmonic_edge_average,
    svm_source,
)


def random_grid(seed=0, ni=10, nj=7, jitter=0.3):
    """A Cartesian block with randomly moved interior nodes (all cells stay convex and positive)."""
    rng = np.random.default_rng(seed)
    x, y = np.meshgrid(np.linspace(-1.3, 1.9, ni), np.linspace(-0.7, 1.1, nj), indexing="ij")
    h = min(x[1, 0] - x[0, 0], y[0, 1] - y[0, 0])
    x = x + jitter * h * rng.uniform(-1, 1, x.shape)
    y = y + jitter * h * rng.uniform(-1, 1, y.shape)
    return grid_from_nodes(x, y, n_wake=0)


def quad_cell_integral(grid, func, n_sub=24, n_gauss=5):
    """int over each cell of func(x, y) by composite Gauss-Legendre on the bilinear map."""
    g, wg = np.polynomial.legendre.leggauss(n_gauss)
    t = (np.arange(n_sub)[:, None] + 0.5 * (g[None, :] + 1.0)).ravel() / n_sub
    w = np.tile(wg / (2.0 * n_sub), n_sub)
    a, b = np.meshgrid(t, t, indexing="ij")
    W = np.outer(w, w)
    X, Y = grid.x, grid.y
    c = [(X[:-1, :-1], Y[:-1, :-1]), (X[1:, :-1], Y[1:, :-1]), (X[1:, 1:], Y[1:, 1:]), (X[:-1, 1:], Y[:-1, 1:])]
    N = [(1 - a) * (1 - b), a * (1 - b), a * b, (1 - a) * b]
    dNa = [-(1 - b), (1 - b), b, -b]
    dNb = [-(1 - a), -a, a, (1 - a)]
    ex = lambda cc, NN: sum(ci[..., None, None] * Ni for ci, Ni in zip(cc, NN))  # noqa: E731
    xs, ys = ex([p[0] for p in c], N), ex([p[1] for p in c], N)
    xa, xb = ex([p[0] for p in c], dNa), ex([p[0] for p in c], dNb)
    ya, yb = ex([p[1] for p in c], dNa), ex([p[1] for p in c], dNb)
    jac = xa * yb - xb * ya
    return np.sum(func(xs, ys) * jac * W, axis=(-2, -1))


def clipped_area(grid, c):
    """Area of each cell left of the line x = c (Sutherland-Hodgman on the convex quadrilateral)."""
    X, Y = grid.x, grid.y
    px = np.stack([X[:-1, :-1], X[1:, :-1], X[1:, 1:], X[:-1, 1:]], -1).reshape(-1, 4)
    py = np.stack([Y[:-1, :-1], Y[1:, :-1], Y[1:, 1:], Y[:-1, 1:]], -1).reshape(-1, 4)
    out = []
    for xs, ys in zip(px, py):  # test oracle: a plain loop over a few dozen cells
        poly = []
        for k in range(4):
            x1, y1, x2, y2 = xs[k], ys[k], xs[(k + 1) % 4], ys[(k + 1) % 4]
            in1, in2 = x1 <= c, x2 <= c
            if in1:
                poly.append((x1, y1))
            if in1 != in2:
                t = (c - x1) / (x2 - x1)
                poly.append((c, y1 + t * (y2 - y1)))
        if len(poly) < 3:
            out.append(0.0)
            continue
        p = np.array(poly)
        out.append(0.5 * np.sum(p[:, 0] * np.roll(p[:, 1], -1) - np.roll(p[:, 0], -1) * p[:, 1]))
    return np.array(out).reshape(grid.area.shape)


GUSTS = [
    SineGust(angle_deg=2.0, omega=2.7),
    SineGust(angle_deg=2.0, wavelength=1.3, x0=-0.7),
    OneMinusCosine(length=0.9, angle_deg=3.0, x0=-1.0),
]


def test_definitions_paper_equations():
    g = OneMinusCosine(length=2.0, angle_deg=5.0, x0=-3.0)
    A = math.tan(math.radians(5.0))
    # Eq. 29-30: peak A at xi = -length/2, zero outside [-length, 0]
    assert g.velocity(-3.0 - 1.0 + 4.0, 4.0) == pytest.approx(A)
    assert g.velocity(0.1, 3.0) == 0.0 and g.velocity(-2.1, 0.0) == 0.0
    # front reaches x_ref at s = x_ref - x0
    assert g.arrival(0.0) == 3.0 and g.input(3.0) == 0.0 and g.input(4.0) == pytest.approx(A)
    s = SineGust(angle_deg=1.0, wavelength=4.0)
    assert s.omega == pytest.approx(2 * np.pi / 4.0)
    x, t = 0.3, 0.8
    assert s.velocity(x, t) == pytest.approx(math.tan(math.radians(1.0)) * math.sin(2 * math.pi * (x - t) / 4.0))
    e = SharpEdged(angle_deg=2.0, x0=-1.0)
    assert e.input(0.999) == 0.0 and e.input(1.0) == pytest.approx(math.tan(math.radians(2.0)))


@pytest.mark.parametrize("gust", GUSTS)
def test_derivatives_against_finite_differences(gust):
    x = np.linspace(-2.0, 2.0, 57) + 0.0123
    s, h = 0.37, 1e-6
    fd = (gust.velocity(x + h, s) - gust.velocity(x - h, s)) / (2 * h)
    np.testing.assert_allclose(gust.dvdx(x, s), fd, atol=1e-6)
    fd_t = (gust.velocity(x, s + h) - gust.velocity(x, s - h)) / (2 * h)
    np.testing.assert_allclose(gust.dvds(x, s), fd_t, atol=1e-6)


@pytest.mark.parametrize("gust", GUSTS + [SharpEdged(angle_deg=4.0, x0=-0.9)])
def test_edge_average_against_quadrature(gust):
    rng = np.random.default_rng(1)
    x1, x2 = rng.uniform(-2, 2, 40), rng.uniform(-2, 2, 40)
    x2[:3] = x1[:3]  # vertical edges
    s = 0.41
    t = np.linspace(0, 1, 200_001)
    xs = x1[:, None] + t[None, :] * (x2 - x1)[:, None]
    ref = np.trapezoid(gust.velocity(xs, s), t, axis=1)
    np.testing.assert_allclose(edge_average(gust, x1, x2, s), ref, atol=2e-5)


def test_harmonic_edge_average_against_quadrature():
    rng = np.random.default_rng(2)
    x1, x2 = rng.uniform(-2, 2, 30), rng.uniform(-2, 2, 30)
    x2[0] = x1[0]
    t = np.linspace(0, 1, 20_001)
    for omega in (0.0, 0.3, 7.0):
        xs = x1[:, None] + t[None, :] * (x2 - x1)[:, None]
        ref = np.trapezoid(np.exp(-1j * omega * (xs - 0.25)), t, axis=1)
        np.testing.assert_allclose(harmonic_edge_average(x1, x2, omega, 0.25), ref, atol=1e-7)



# A complex abscissa was cast to its real part with only a ComplexWarning, None to NaN (averages of NaN returned);
# text failed in NumPy ("could not convert string to float").
EDGE_FUNCTIONS = [
    pytest.param(lambda x1, x2: edge_average(OneMinusCosine(length=2.0, angle_deg=1.0, x0=-1.0), x1, x2, 0.3),
                 id="edge_average"),
    pytest.param(lambda x1, x2: harmonic_edge_average(x1, x2, 0.7, 0.25), id="harmonic_edge_average"),
]


@pytest.mark.parametrize("average", EDGE_FUNCTIONS)
@pytest.mark.parametrize("which", ["x1", "x2"])
@pytest.mark.parametrize("bad, kind", [(np.array([0.1, 0.5]) + 1j, "dtype complex128"),
                                       (np.complex64(0.5 + 1j), "complex64"), ("0.5", "str"), (None, "NoneType")])
def test_edge_averages_refuse_abscissae_that_are_not_real(average, which, bad, kind):
    good = np.array([0.2, 0.9])
    args = (bad, good) if which == "x1" else (good, bad)
    with pytest.raises(GustError, match=f"{which} must be a real number or an array of real end-point abscissae.*"
                                        f"got {kind}"):
        average(*args)


@pytest.mark.parametrize("average", EDGE_FUNCTIONS)
def test_edge_averages_take_real_abscissae_of_any_real_type(average):
    x1, x2 = np.array([-1.0, 0.0, 2.0]), np.array([0.5, 0.0, 3.0])   # exact in float32 and as ints (x1)
    ref = average(x1, x2)
    np.testing.assert_array_equal(average(x1.astype(np.float32), x2.astype(np.float32)), ref)
    np.testing.assert_array_equal(average(x1.astype(int).tolist(), list(x2)), ref)
    np.testing.assert_array_equal(average(2, 3), average(2.0, 3.0))

@pytest.mark.parametrize("gust", GUSTS)
@pytest.mark.parametrize("seed", [0, 1])
def test_cell_integral_against_quadrature(gust, seed):
    grid = random_grid(seed)
    s = 0.23
    gi, gj = face_gust(grid, gust, s)
    exact = cell_x_gradient(grid, gi, gj)
    smooth = isinstance(gust, SineGust) and gust.x0 is None
    ref = quad_cell_integral(grid, lambda x, y: gust.dvdx(x, s), n_sub=24 if smooth else 64)
    # smooth integrand: Gauss converges fast. A front where dv/dx jumps (sine train) or kinks
    # (1-cosine) limits the composite rule to O(h) or O(h^2): the quadrature, not the exact
    # integral, sets the tolerance there (the jump itself is checked in test_sharp_edge_...)
    tol = 1e-9 if smooth else (3e-4 if isinstance(gust, SineGust) else 2e-5)
    np.testing.assert_allclose(exact, ref, rtol=0, atol=tol * np.abs(ref).max())


@pytest.mark.parametrize("omega", [0.05, 1.0, 6.0])
def test_harmonic_cell_integral_against_quadrature(omega):
    grid = random_grid(3)
    gi, gj = face_gust_harmonic(grid, omega, x_ref=0.1)
    exact = cell_x_gradient(grid, gi, gj)
    ref = quad_cell_integral(grid, lambda x, y: -1j * omega * np.exp(-1j * omega * (x - 0.1)))
    np.testing.assert_allclose(exact, ref, rtol=0, atol=1e-9 + 1e-8 * np.abs(ref).max())


def test_sharp_edge_cell_integral_is_front_length():
    """int dv/dx dA = -A * (length of the front inside the cell) = -A d(area left of front)/dc."""
    grid = random_grid(4)
    gust = SharpEdged(angle_deg=3.0, x0=-0.8)
    s = 0.95
    c = gust.x0 + s
    gi, gj = face_gust(grid, gust, s)
    h = 1e-6
    length = (clipped_area(grid, c + h) - clipped_area(grid, c - h)) / (2 * h)
    assert length.max() > 0.05  # the front crosses some cells
    np.testing.assert_allclose(cell_x_gradient(grid, gi, gj), -gust.amplitude * length, atol=1e-7)


def test_uniform_gust_and_uniform_stream_give_zero_source():
    grid = random_grid(5)
    gi, gj = face_gust_harmonic(grid, 0.0)
    np.testing.assert_allclose(cell_x_gradient(grid, gi, gj), 0.0, atol=1e-14)
    # omega -> 0: the source vanishes linearly
    gi, gj = face_gust_harmonic(grid, 1e-6)
    assert np.abs(cell_x_gradient(grid, gi, gj)).max() < 1e-5 * grid.area.max()
    # a uniform stream at the gust speed gives no SVM source, for any gust
    mach = 0.5
    q = np.zeros(grid.area.shape + (4,))
    q[..., 0], q[..., 1], q[..., 3] = 1.0, mach, 1 / 0.56 + 0.5 * mach**2
    gi, gj = face_gust(grid, GUSTS[2], 0.4)
    src = svm_source(q, mach, cell_x_gradient(grid, gi, gj))
    assert np.abs(src).max() == 0.0


def test_face_velocity_layout_and_discrete_divergence():
    grid = random_grid(6)
    gi, gj = face_gust(grid, GUSTS[0], 0.1)
    wi, wj = gust_face_velocity(gi, gj, 0.4)
    ni, nj = grid.shape
    assert wi.shape == (2, ni, nj - 1) and wj.shape == (2, ni - 1, nj)
    assert np.all(wi[0] == 0) and np.allclose(wi[1], -0.4 * gi)
    # sum over the faces of v_g S_y vanishes for each cell (geometric conservation)
    fy = wi[1] * grid.si[1]
    gy = wj[1] * grid.sj[1]
    div = fy[1:] - fy[:-1] + gy[:, 1:] - gy[:, :-1]
    assert np.abs(div).max() < 1e-15


def test_svm_source_form():
    rng = np.random.default_rng(7)
    q = rng.uniform(0.5, 1.5, (3, 4, 4))
    d = rng.normal(size=(3, 4)) + 1j * rng.normal(size=(3, 4))
    mach = 0.3
    src = svm_source(q, mach, d)
    rho, u, v = q[..., 0], q[..., 1] / q[..., 0], q[..., 2] / q[..., 0]
    sm = rho * (u - mach) * mach * d
    np.testing.assert_allclose(src[..., 2], -sm)
    np.testing.assert_allclose(src[..., 3], -v * sm)
    assert np.all(src[..., :2] == 0)


def test_bad_input():
    with pytest.raises(GustError, match="length"):
        OneMinusCosine(length=0.0, angle_deg=1.0, x0=-2.0)
    with pytest.raises(GustError, match="angle_deg"):
        SharpEdged(angle_deg=np.nan)
    with pytest.raises(GustError, match="angle_deg"):
        SharpEdged(angle_deg=95.0)
    with pytest.raises(GustPositionError, match="x0"):
        OneMinusCosine(length=1.0, angle_deg=1.0, x0=0.0)
    with pytest.raises(GustError, match="exactly one of omega"):
        SineGust(angle_deg=1.0, omega=1.0, wavelength=2.0)
    with pytest.raises(GustError, match="omega = -1.0 must be positive"):
        SineGust(angle_deg=1.0, omega=-1.0)
    with pytest.raises(GustError, match="wavelength must be finite"):
        SineGust(angle_deg=1.0, wavelength=np.inf)


@pytest.mark.parametrize(
    "gust", [SharpEdged(angle_deg=3.0, x0=-1.0), OneMinusCosine(length=1.0, angle_deg=3.0, x0=-1.0),
             SineGust(angle_deg=2.0, omega=3.0)]
)
def test_residual_free_stream_preserved_under_gust(gust):
    """Uniform stream + gust is an exact discrete solution of the SVM residual away from the wall."""
    euler = pytest.importorskip("cfd.euler")
    from cfd.flow import FlowCondition

    import sys
    from pathlib import Path

    sys.path.append(str(Path(__file__).parent))
    from flowgrids import parabolic_c_grid

    grid = parabolic_c_grid(thickness=0.0)  # flat plate on 0 <= x <= 1
    flow = FlowCondition(0.5)
    q = np.broadcast_to(flow.q, grid.cell_shape + (4,)).copy()
    s = 0.7  # fronts at x = -0.3: the plate has not met the 1-cosine or sharp-edged gust yet
    gi, gj = face_gust(grid, gust, s)
    R = euler.residual(grid, q, flow, face_velocity=gust_face_velocity(gi, gj, flow.mach),
                       source=svm_source(q, flow.mach, cell_x_gradient(grid, gi, gj)))
    scale = flow.mach * np.abs(grid.si).max()
    np.testing.assert_allclose(R[:, 3:], 0.0, atol=1e-13 * scale)  # the sine train meets the plate
    if gust.x0 is not None:
        np.testing.assert_allclose(R, 0.0, atol=1e-13 * scale)


def test_sine_gust_face_values_are_the_real_part_of_the_harmonic_ones():
    """The LTD forcing of an endless sine train equals Re(U exp(i omega s) g_harmonic): LFD and LTD see one gust."""
    grid = random_grid(8)
    w, s, x_ref = 1.7, 0.6, 0.0
    gust = SineGust(angle_deg=3.0, omega=w)
    U = 1j * gust.amplitude * np.exp(-1j * w * x_ref)  # u(s) = A sin(omega (x_ref - s)) = Re(U exp(i omega s))
    assert gust.input(s, x_ref) == pytest.approx((U * np.exp(1j * w * s)).real)
    for a, b in zip(face_gust(grid, gust, s), face_gust_harmonic(grid, w, x_ref)):
        np.testing.assert_allclose(a, (U * np.exp(1j * w * s) * b).real, atol=1e-14)


# --- input checks (issue 34) ---------------------------------------------------------------------------------------

@pytest.mark.parametrize("make, match", [
    (lambda: OneMinusCosine(length=1e-12, angle_deg=1.0), r"length = 1e-12 chords is below 0.001 \(cfd.gust.MIN_LENGTH\)"),
    (lambda: OneMinusCosine(length=0.0, angle_deg=1.0), r"length = 0.0 chords is below 0.001"),
    (lambda: OneMinusCosine(length=-1.0, angle_deg=1.0), r"length = -1.0 chords is below 0.001"),
    (lambda: SineGust(angle_deg=1.0, wavelength=1e-12), r"wavelength = 1e-12 chords must be at least 0.001"),
    (lambda: SineGust(angle_deg=1.0, omega=1e12), r"omega = 1000000000000.0 .* use omega <= 6283"),
])
def test_gusts_shorter_than_any_grid_resolves_are_refused(make, match):
    with pytest.raises(GustError, match=match):
        make()


def test_the_shortest_gust_is_accepted():
    from cfd.gust import MIN_LENGTH

    assert OneMinusCosine(length=MIN_LENGTH, angle_deg=1.0).length == MIN_LENGTH
    assert SineGust(angle_deg=1.0, omega=2 * np.pi / MIN_LENGTH).wavelength == pytest.approx(MIN_LENGTH, rel=1e-15)


def test_the_study_gust_step_rule_is_the_marches():
    from cfd.gust import MIN_GUST_STEPS
    from studies.config.schema import MIN_GUST_STEPS as STUDY_MIN_GUST_STEPS

    assert STUDY_MIN_GUST_STEPS == MIN_GUST_STEPS


@pytest.mark.parametrize("gust", [OneMinusCosine(length=4.0, angle_deg=1.0, x0=-2.0), SineGust(1.0, omega=1.0)])
@pytest.mark.parametrize("s, kind", [("abc", "str"), (None, "NoneType"), (1.0 + 1.0j, "complex"),
                                     (np.array([np.nan, 1.0]), "dtype float64")])
def test_input_times_must_be_real_numbers(gust, s, kind):
    # "abc" raised NumPy's "could not convert string to float"; None and NaN times gave an input of 0
    with pytest.raises(GustError, match=rf"s must be a real number or an array of real convective times .*got {kind}"):
        gust.input(s)


@pytest.mark.parametrize("make, name", [
    (lambda: OneMinusCosine(length="4", angle_deg=1.0), "length"),     # strings were parsed
    (lambda: OneMinusCosine(length=4.0, angle_deg="1"), "angle_deg"),
    (lambda: SineGust(angle_deg=1.0, omega="1.0"), "omega"),
])
def test_gust_parameters_are_not_strings(make, name):
    with pytest.raises(GustError, match=rf"{name} must be a real number; got '"):
        make()
