"""cfd.motion: plunge and pitch inputs of the linearised solvers, against exact identities and steady solves.

The grids are the small parabolic C-grids of ``flowgrids`` (49 x 13 nodes); docs/motion_validation.md holds the
checks on finer grids (steady slopes, Theodorsen, LTD against LFD).
"""

import numpy as np
import pytest

pytest.importorskip("cfd.steady")

from flowgrids import parabolic_c_grid  # noqa: E402

import sysid  # noqa: E402
from cfd import lfd_response, solve_steady  # noqa: E402
from cfd.flow import FlowCondition  # noqa: E402
from cfd.linear import LinearError, linearise, linearise_state  # noqa: E402
from cfd.motion import _stepped, load_incidence_derivative, motion_forcing  # noqa: E402

SMALL = dict(n_surface=32, n_wake=8, nj=13)
OUT3 = ("Cl", "Cm", "Cd")


@pytest.fixture(scope="module")
def plate():
    """Flat plate at zero incidence, M0.3: the free stream is the exact steady state."""
    grid = parabolic_c_grid(thickness=0.0, **SMALL)
    flow = FlowCondition(0.3)
    return linearise_state(grid, np.broadcast_to(flow.q, grid.cell_shape + (4,)).copy(), flow)


@pytest.fixture(scope="module")
def lifting():
    """NACA0010-like section at M0.3 and 2 deg: lift, moment and drag all nonzero (no symmetric ties)."""
    grid = parabolic_c_grid(thickness=0.1, **SMALL)
    sol = solve_steady(grid, 0.3, 2.0, tol=1e-12)
    assert sol.converged
    return sol, linearise(sol)


def _direct(lin, w, inputs, pivot=0.25, outputs=OUT3):
    return lfd_response(lin, w, inputs=inputs, pivot=pivot, outputs=outputs, method="direct").H


@pytest.mark.parametrize("omega", [0.0, 0.7])
def test_uniform_stream_under_pitch_is_exact_away_from_the_wall(plate, omega):
    """A uniform stream turned with the pitch solves the linearised equations wherever the wall is not seen.

    For the flat plate the free stream at incidence ``alpha`` is the exact discrete solution of every cell whose
    stencil does not reach the wall ghosts (rows ``jc >= 2``, and the wake cut): the free-stream derivative, the
    rotation's face velocities (geometric conservation) and the frame-rotation term must cancel there exactly.
    A sign error in any of them leaves an O(1) residual.
    """
    lin = plate
    f = motion_forcing(lin, "pitch", 0.25)
    dq = _stepped(lin.flow).q.imag / 1e-30                         # d(free stream)/d alpha
    qp = np.broadcast_to(dq, lin.grid.cell_shape + (4,)).ravel()
    r = lin.J @ qp + 1j * omega * lin.mach * lin.V * qp + f.at(omega)
    r = r.reshape(lin.grid.cell_shape + (4,))
    assert np.abs(r[:, 2:]).max() < 1e-13
    assert np.abs(r[:lin.grid.n_wake]).max() < 1e-13 and np.abs(r[-lin.grid.n_wake:]).max() < 1e-13
    assert np.abs(r[:, :2]).max() > 1e-2                            # the wall is what the pitch acts on


def test_default_inputs_are_the_gust_column(lifting):
    """``inputs=("gust",)`` (the default) is today's gust response; the gust column is the same among motions."""
    lin = lifting[1]
    w = [0.0, 0.4]
    a = lfd_response(lin, w, method="direct")
    b = lfd_response(lin, w, method="direct", inputs=("pitch", "gust", "plunge"))
    assert a.inputs == ("gust",) and b.inputs == ("pitch", "gust", "plunge")
    assert b.H.shape == (2, 3, 2) and b.metadata["pivot"] == 0.25 and "pivot" not in a.metadata
    np.testing.assert_array_equal(a.H[:, 0], b.H[:, 1])


@pytest.mark.parametrize("p1, p2", [(0.25, 0.5), (0.0, 1.0), (-0.5, 0.35)])
def test_pivots_differ_by_the_plunge_of_the_offset(lifting, p1, p2):
    """Rotation about x2 = rotation about x1 plus a plunge (x2 - x1) alpha of the section: exact."""
    lin = lifting[1]
    w = [0.0, 0.3, 1.5]
    H1 = _direct(lin, w, ("plunge", "pitch"), p1)
    H2 = _direct(lin, w, ("pitch",), p2)
    np.testing.assert_allclose(H2[:, 0], H1[:, 1] + (p2 - p1) * H1[:, 0], rtol=0, atol=1e-12 * np.abs(H1).max())


def test_plunge_is_a_uniform_gust_of_minus_the_plunge_velocity(lifting):
    """H_plunge(omega) = -i omega H_uniform(omega), H_uniform the response to v/U = exp(i omega s) everywhere."""
    lin = lifting[1]
    w = np.array([0.2, 1.0])
    Hp = _direct(lin, w, ("plunge",))[:, 0]
    ni, nj = lin.grid.shape
    b = lin.forcing(np.ones((ni, nj - 1)), np.ones((ni - 1, nj)), "fvm")
    Hu = np.stack([lin.C @ lin.solver(1j * lin.to_solver_frequency(wk) * lin.V)(-b) for wk in w], axis=1)
    np.testing.assert_allclose(Hp, -1j * w * Hu, rtol=1e-10)


def test_explicit_load_derivative_turns_the_wind_axes(lifting):
    """At a fixed state, d(Cl, Cm, Cd)/d alpha = (-Cd, 0, Cl): lift and drag turn with the free stream."""
    sol, lin = lifting
    np.testing.assert_allclose(load_incidence_derivative(lin), [-sol.cd, 0.0, sol.cl], atol=1e-14)


def test_zero_frequency_pitch_equals_steady_slopes(lifting):
    """omega = 0: the lift, moment and drag slopes of central differences of nonlinear steady solves.

    Step 0.05 deg. The central difference's truncation error, estimated as (S(d) - S(d/2)) 4/3, is 6e-6 (Cl),
    1.7e-4 (Cm) and 1.1e-3 (Cd) relative on this grid, and the measured gaps to the LFD are that (5e-6, 1.4e-4,
    8.8e-4): the LFD is the exact derivative. At d = 0.25 deg the truncation error alone is 1 % in Cm.
    """
    sol, lin = lifting
    H0 = _direct(lin, [0.0], ("pitch",))[:, 0, 0]
    assert np.all(H0.imag == 0.0)
    d = 0.05
    loads = []
    for a in (sol.flow.alpha_deg - d, sol.flow.alpha_deg + d):
        s = solve_steady(lin.grid, sol.flow.mach, a, tol=1e-11, q0=sol.q, n_rk=0)
        loads.append(np.array([s.cl, s.cm, s.cd]))
    slope = (loads[1] - loads[0]) / np.radians(2 * d)
    gap = np.abs(H0.real / slope - 1)
    print("relative gaps (Cl, Cm, Cd):", gap)
    assert np.all(gap < [2e-5, 5e-4, 3e-3])


def test_plunge_at_low_frequency_is_an_incidence_without_pitch_rate(lifting):
    """H_h(omega) -> -i omega H_alpha(0) as omega -> 0, up to the wind axes.

    A plunge velocity h' tilts the relative wind by -h'/U but not the lift axis (the inertial free stream keeps
    its direction), so the exact limit is ``H_h / (-i omega) -> H_alpha(0) + (Cd0, 0, -Cl0)``. What remains is the
    JST dissipation, which acts on absolute momentum and enthalpy (not Galilean invariant): measured 0.15 % (Cl),
    0.15 % (Cm) here, and the O(omega) lag of the wake.
    """
    sol, lin = lifting
    w = np.array([1e-4, 1e-3])
    H = _direct(lin, np.concatenate([[0.0], w]), ("plunge", "pitch", "gust"))
    limit = H[:, 0, 1:] / (-1j * w)
    expect = H[:, 1, 0].real + np.array([sol.cd, 0.0, -sol.cl])
    np.testing.assert_allclose(limit[:2, 0], expect[:2], rtol=3e-3)
    # the limit itself is the uniform gust's steady gain (omega = 0: the gust is uniform), approached as O(omega)
    remainder = np.abs(limit - H[:, 2, :1])
    np.testing.assert_allclose(remainder[:, 1] / remainder[:, 0], 10.0, rtol=1e-3)
    assert np.all(remainder[:2, 0] < 1e-3 * np.abs(expect[:2]))   # omega = 1e-4


def test_fast_sweep_serves_all_inputs_from_one_basis(lifting):
    """The fast sweep's one dual basis gives gust, plunge and pitch as the direct path does."""
    from cfd.sweep import SweepBasis

    lin = lifting[1]
    w = np.array([0.0, 0.1, 0.6, 1.2])
    inputs = ("gust", "plunge", "pitch")
    basis = SweepBasis(lin, n_moments=6)
    fast = lfd_response(lin, w, inputs=inputs, pivot=0.4, method="fast", tol=1e-7, basis=basis)
    ref = _direct(lin, w, inputs, 0.4, outputs=("Cl", "Cm"))
    assert fast.inputs == inputs and fast.metadata["method"] == "fast"
    est = np.asarray(fast.metadata["error_estimate"])
    assert est.shape == (2, 3, 4)
    err = np.abs(fast.H - ref)
    assert np.all(err <= np.maximum(est, 1e-12 * np.abs(ref).max()))   # the estimate bounds the error
    assert err.max() < 1e-6 * np.abs(ref).max()


def test_theodorsen_limit_on_a_flat_plate(plate):
    """Flat plate at M0.3 against Theodorsen's loads (Prandtl-Glauert factor 1/beta), pitch about the quarter chord.

    A loose check of the lift on this 49 x 13 grid (far field 12 chords; the gust's steady gain is 2 % high on it);
    docs/motion_validation.md compares a thin section on a finer grid over k = 0.05 .. 1. Measured here at
    omega = 0.2 and 1: |Cl| 5.5 and 9.8 % (plunge), 5.4 and 6.7 % (pitch) high, phases within 2.2 deg.
    """
    from aeroelastic.theodorsen import theodorsen_motion

    w = np.array([0.2, 1.0])
    H = _direct(plate, w, ("plunge", "pitch"), 0.25, outputs=("Cl", "Cm"))
    T = theodorsen_motion(w, a=-0.5) / np.sqrt(1 - 0.3**2)
    np.testing.assert_allclose(np.abs(H[0]), np.abs(T[0]), rtol=0.1)
    np.testing.assert_allclose(np.angle(H[0], deg=True), np.angle(T[0], deg=True), atol=4.0)


@pytest.mark.parametrize("kwargs, match", [
    (dict(inputs=("heave",)), "unknown input"),
    (dict(inputs=()), "unknown input"),
    (dict(inputs=("pitch", "pitch")), "twice"),
    (dict(inputs=("pitch",), pivot=np.nan), "pivot"),
    (dict(inputs=("pitch",), pivot="LE"), "pivot"),
    (dict(inputs=("gust", "plunge"), omega=[0.5, np.inf]), "omega = inf"),
    (dict(inputs=("pitch",), omega=[0.5, np.inf], method="fast"), "omega = inf"),
])
def test_bad_motion_arguments(plate, kwargs, match):
    omega = kwargs.pop("omega", [0.5])
    with pytest.raises(LinearError, match=match):
        lfd_response(plate, omega, **kwargs)


def test_mckelvey_grid_without_infinity(plate):
    """The motion columns on a McKelvey grid: the finite points with T given; the inf point is refused."""
    T = 2.0
    omega_d, omega = sysid.mckelvey_grid(4, T)
    with pytest.raises(LinearError, match="finite frequencies"):
        lfd_response(plate, (omega_d, omega), inputs=("plunge", "pitch"))
    frf = lfd_response(plate, omega[:-1], T=T, inputs=("plunge", "pitch"))
    assert frf.H.shape == (2, 2, 4) and np.allclose(frf.omega_d, omega_d[:-1])


# ---------------------------------------------------------------------------------------------------------------
# LTD: prescribed motion histories
# ---------------------------------------------------------------------------------------------------------------

def _harmonic(t, y, omega):
    """Complex amplitude Y of y ~ Re(Y exp(i omega t)) + c by least squares."""
    M = np.stack([np.cos(omega * t), np.sin(omega * t), np.ones_like(t)], 1)
    c = np.linalg.lstsq(M, y, rcond=None)[0]
    return c[0] - 1j * c[1]


@pytest.mark.parametrize("name", ["pitch", "plunge"])
def test_ltd_motion_from_rest_becomes_periodic_and_matches_lfd(lifting, name):
    """x(s) = A (1 - cos(omega s)) from rest: past s = 30 the first harmonic of the loads is the LFD's.

    Measured (omega = 1, dt = 0.05): magnitudes within 0.02 % (Cl) and 0.08 % (Cm) for the pitch, 0.08 % and
    0.16 % for the plunge, phases within 0.04 deg: what is left is the start-up transient (the BDF2 phase-rate
    error (omega dt)^2 / 3 is 0.08 %).
    """
    from cfd import ltd_response

    lin = lifting[1]
    w, A = 1.0, 0.01
    hist = ltd_response(lin, None, 0.05, 30 + 2 * np.pi / w, **{name: lambda s: A * (1 - np.cos(w * s))}, pivot=0.4)
    H = _direct(lin, [w], (name,), 0.4, outputs=("Cl", "Cm"))[:, 0, 0]
    x = hist.alpha if name == "pitch" else hist.h
    assert np.abs(x - A * (1 - np.cos(w * hist.t))).max() == 0.0
    m = hist.t >= 30
    r = np.array([_harmonic(hist.t[m], y[m], w) for y in (hist.cl, hist.cm)]) / _harmonic(hist.t[m], x[m], w)
    np.testing.assert_allclose(np.abs(r / H), 1.0, rtol=3e-3)
    np.testing.assert_allclose(np.angle(r / H, deg=True), 0.0, atol=0.2)


def test_ltd_motion_is_linear_and_pivots_shift_by_the_plunge(lifting):
    """Gust and pitch marched together are the sum of the two marches; pitch about x2 = pitch about x1 plus the
    plunge (x2 - x1) alpha, in time too (to round-off)."""
    from cfd import SharpEdged, ltd_response

    lin = lifting[1]
    t = 0.1 * np.arange(41)
    alpha = 0.01 * np.sin(0.5 * t) ** 2
    gust = SharpEdged(1.0, x0=-1.0)
    both = ltd_response(lin, gust, 0.1, 4.0, pitch=alpha, pivot=0.1, max_phase_error=1.0)
    g = ltd_response(lin, gust, 0.1, 4.0, max_phase_error=1.0)
    p1 = ltd_response(lin, None, 0.1, 4.0, pitch=alpha, pivot=0.1)
    p2 = ltd_response(lin, None, 0.1, 4.0, pitch=alpha, pivot=0.6)
    h = ltd_response(lin, None, 0.1, 4.0, plunge=0.5 * alpha)
    scale = np.abs(p1.cl).max()
    np.testing.assert_allclose(both.cl, g.cl + p1.cl, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(p2.cl, p1.cl + h.cl, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(p2.cm, p1.cm + h.cm, rtol=0, atol=1e-12 * scale)
    assert both.pivot == 0.1 and np.all(both.h == 0.0) and np.all(p1.u == 0.0) and g.pivot is None


@pytest.mark.parametrize("kwargs, match", [
    (dict(), "nothing to march"),
    (dict(pitch=np.zeros(5)), "samples"),
    (dict(plunge=[0.0] * 10 + [np.nan]), "NaN"),
    (dict(pitch=lambda s: s[:3]), "samples"),
    (dict(pitch=np.zeros(11), pivot=np.inf), "pivot"),
])
def test_ltd_motion_bad_input(plate, kwargs, match):
    from cfd import ltd_response

    with pytest.raises(LinearError, match=match):
        ltd_response(plate, None, 0.1, 1.0, **kwargs)
