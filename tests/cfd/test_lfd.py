"""cfd.lfd: the direct LFD gust response against independent references."""

import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("cfd.steady")
sys.path.append(str(Path(__file__).parent))

from flowgrids import parabolic_c_grid  # noqa: E402

import sysid  # noqa: E402
from cfd import solve_steady  # noqa: E402
from cfd.analytic import sears_compressible  # noqa: E402
from cfd.flow import FlowCondition  # noqa: E402
from cfd.lfd import lfd_response  # noqa: E402
from cfd.linear import LinearError, linearise, linearise_state  # noqa: E402


def plate_system(**grid_args):
    """Flat plate at zero incidence, M0.3: the free stream is the exact steady state."""
    grid = parabolic_c_grid(thickness=0.0, **grid_args)
    flow = FlowCondition(0.3)
    q = np.broadcast_to(flow.q, grid.cell_shape + (4,)).copy()
    return linearise_state(grid, q, flow)


@pytest.fixture(scope="module")
def plate():
    return plate_system(n_surface=32, n_wake=8, nj=13)


@pytest.fixture(scope="module")
def thick():
    grid = parabolic_c_grid(thickness=0.1, n_surface=32, n_wake=8, nj=13)
    sol = solve_steady(grid, 0.3, 0.0, tol=1e-12)
    assert sol.converged
    return grid, sol.flow, sol.q, linearise(sol)


def test_feedthrough_and_mckelvey_grid(plate):
    T = 70 / (2 * np.pi)
    omega_d, omega = sysid.mckelvey_grid(2, T)
    frf = lfd_response(plate, (omega_d, omega), method="direct")
    assert frf.H.shape == (2, 1, 3) and frf.outputs == ("Cl", "Cm") and frf.inputs == ("gust",)
    assert frf.T == pytest.approx(T) and np.allclose(frf.omega_d, omega_d)
    assert np.all(frf.H[:, 0, -1] == 0.0)  # omega = inf: the feedthrough, no solve
    # omega = 0 is real (steady gain) and positive for the lift
    assert abs(frf.H[0, 0, 0].imag) < 1e-12 and frf.H[0, 0, 0].real > 5.0
    f2 = lfd_response(plate, [omega[1]], outputs="Cd", T=T)
    assert f2.H.shape == (1, 1, 1)


def test_bad_input(plate):
    with pytest.raises(LinearError, match=">= 0"):
        lfd_response(plate, [-1.0])
    with pytest.raises(LinearError, match="NaN"):
        lfd_response(plate, [np.nan])
    with pytest.raises(LinearError, match="method"):
        lfd_response(plate, [1.0], gust="fbc")
    with pytest.raises(LinearError, match="output"):
        lfd_response(plate, [1.0], outputs=("Cl", "Cn"))
    with pytest.raises(LinearError, match="x_ref"):
        lfd_response(plate, [1.0], x_ref=np.inf)


def test_steady_gain_equals_lift_slope_of_nonlinear_steady_solves(thick):
    """omega -> 0: a uniform gust of angle u is an incidence change u (paper Eq. 18)."""
    grid, flow, q, lin = thick
    H0 = lfd_response(lin, [0.0], outputs=("Cl", "Cm"), gust="svm").H[:, 0, 0]
    d = 0.25  # deg
    loads = []
    for a in (-d, d):
        sol = solve_steady(grid, flow.mach, a, tol=1e-9, q0=q, n_rk=0)  # tol relative to |R(q0)| ~ 1e-3
        assert sol.converged
        loads.append(np.array([sol.cl, sol.cm, sol.cd]))
    slope = (loads[1] - loads[0]) / np.radians(2 * d)
    # the gust gain is in the axes of the unperturbed stream; dCl/dalpha also rotates the drag force
    # into the lift: dCl/dalpha = dCl_body/dalpha - Cd0 (Cd0 ~ 1e-3 here)
    cl_gain = H0[0].real - lin.loads[2]
    assert abs(H0[0].imag) < 1e-12
    assert cl_gain == pytest.approx(slope[0], rel=5e-3)
    # Cm: 1.5 % on this 49 x 13 grid (4e-5 on the paper grid, bench/gust_steady_gain.py). The nonlinear
    # slopes from the left and right agree exactly here, so the gap is most likely in the linearisation at
    # the symmetric state: exact ties of the JST max(nu_L, nu_R) across the wake cut make cfd.jacobian take
    # one branch per tie (a one-sided mixture), which the small Cm of a symmetric aerofoil feels most; at
    # alpha = 1 deg, with no ties, the gains agree to 1.4e-3 (test_cm_gain_off_the_symmetric_state_...).
    assert H0[1].real == pytest.approx(slope[1], rel=0.025)
    # Prandtl-Glauert with thickness (docs/references.md section 2) is a loose sanity range on this coarse grid
    assert 0.8 < slope[0] / (2 * np.pi / np.sqrt(1 - 0.09) * (1 + 0.77 * 0.1)) < 1.2


def test_cm_gain_off_the_symmetric_state_equals_the_nonlinear_slope():
    """At alpha = 1 deg no JST switch sits on an exact tie, and the linearised Cm gain matches the central
    difference of nonlinear steady solves as closely as Cl does at alpha = 0 (measured 1.4e-3; the difference's
    own O(d^2) error is of that order on this coarse grid, so 5e-3)."""
    grid = parabolic_c_grid(thickness=0.1, n_surface=32, n_wake=8, nj=13)
    sol = solve_steady(grid, 0.3, 1.0, tol=1e-12)
    H0 = lfd_response(linearise(sol), [0.0], outputs=("Cm",), gust="svm").H[0, 0, 0]
    cm = [solve_steady(grid, 0.3, 1.0 + d, tol=1e-9, q0=sol.q, n_rk=0).cm for d in (-0.25, 0.25)]
    assert H0.real == pytest.approx((cm[1] - cm[0]) / np.radians(0.5), rel=5e-3)


def test_svm_equals_fvm_on_uniform_base_and_differs_on_thick(plate, thick):
    w = [0.0, 0.8]
    a = lfd_response(plate, w[1:], gust="svm", method="direct").H
    b = lfd_response(plate, w[1:], gust="fvm", method="direct").H
    np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-12)  # u_bar = U: no SVM source
    lin = thick[3]
    a = lfd_response(lin, w, gust="svm", method="direct").H
    b = lfd_response(lin, w, gust="fvm", method="direct").H
    np.testing.assert_allclose(a[..., 0], b[..., 0], rtol=1e-12)  # omega = 0: no source either
    assert 1e-4 < abs(a[0, 0, 1] - b[0, 0, 1]) / abs(a[0, 0, 1]) < 0.2


def test_flat_plate_against_compressible_sears():
    """Thin aerofoil at M0.3 against Amiet's compressible Sears function (leading-edge reference).

    Tolerance: the 73 x 17 grid has its far field 12 chords away and about 25 cells per chord on
    the plate; on the 121 x 33 grid (far field 25 chords) the gaps at omega = 0.1 and 0.2 were 1.3 %
    and 2.7 % in magnitude, 0.5 and 1.5 deg in phase, shrinking with refinement. Allow 6 % and 3 deg
    at omega <= 0.2 here (the steady gain itself is 2 % high on this grid).
    """
    w = np.array([0.1, 0.2])
    H = lfd_response(plate_system(), w, outputs="Cl", method="direct").H[0, 0] / (2 * np.pi / np.sqrt(1 - 0.09))
    S = sears_compressible(w, 0.3, "leading_edge")
    np.testing.assert_allclose(np.abs(H), np.abs(S), rtol=0.06)
    np.testing.assert_allclose(np.degrees(np.angle(H)), np.degrees(np.angle(S)), atol=3.0)


@pytest.mark.slow
def test_mach_trend_of_phase_confirms_compressible_sears_convention():
    """Phase change from M0.2 to M0.5 (grid errors largely cancel) against Amiet's low-frequency factor.

    Measured: CFD -2.2, -4.1 deg at omega = 0.1, 0.3; Amiet (exp(+i omega t) form) -2.4, -3.7 deg; the
    published exp(-i omega t) factors taken literally would give 0.0 and +3.4 deg.
    """
    grid = parabolic_c_grid(thickness=0.0)
    w = np.array([0.1, 0.3])
    H = {}
    for m in (0.2, 0.5):
        flow = FlowCondition(m)
        q = np.broadcast_to(flow.q, grid.cell_shape + (4,)).copy()
        H[m] = lfd_response(linearise_state(grid, q, flow), w, outputs="Cl", method="direct").H[0, 0]
    cfd_change = np.degrees(np.angle(H[0.5] / H[0.2]))
    ref = np.degrees(np.angle(sears_compressible(w, 0.5) / sears_compressible(w, 0.2)))
    np.testing.assert_allclose(cfd_change, ref, atol=1.0)


def test_mckelvey_sweep_feeds_identification(plate):
    """End to end: the LFD on the McKelvey grid (omega = inf included) identifies a small accurate ROM."""
    T = 70 / (2 * np.pi)
    frf = lfd_response(plate, sysid.mckelvey_grid(16, T), method="direct")
    assert frf.is_equispaced and frf.M == 16
    res = sysid.identify(frf, 6)
    fit = sysid.FrequencyResponse.from_model(res.model, frf.omega_d)
    assert np.abs(fit.H - frf.H).max() < 0.01 * np.abs(frf.H).max()


def test_vortex_far_field_rank_one_term(thick):
    """With the point-vortex far field the circulation feedback (frozen in cfd.jacobian) is added back.

    Measured on this grid: LFD gain within 3.7e-4 of the steady-solve slope with the rank-one term, 2.1 %
    off without it.
    """
    import dataclasses

    from cfd.euler import Scheme

    grid, flow, _, _ = thick
    scheme = Scheme(vortex=True)
    sol = solve_steady(grid, flow.mach, 0.0, tol=1e-12, scheme=scheme)
    lin = linearise(sol, scheme=scheme)
    assert lin.vortex is not None
    H0 = lfd_response(lin, [0.0], outputs="Cl").H[0, 0, 0].real - sol.cd
    frozen = lfd_response(dataclasses.replace(lin, vortex=None), [0.0], outputs="Cl").H[0, 0, 0].real - sol.cd
    cl = [solve_steady(grid, flow.mach, a, tol=1e-9, q0=sol.q, n_rk=0, scheme=scheme).cl for a in (-0.25, 0.25)]
    slope = (cl[1] - cl[0]) / np.radians(0.5)
    assert H0 == pytest.approx(slope, rel=2e-3)
    assert abs(frozen / slope - 1) > 5e-3  # the term matters
    # the full Jacobian's product (LinearSystem.apply_jacobian) is the operator the solver inverts (Sherman-
    # Morrison there, an explicit rank-one product here); its transpose is the adjoint: z.(A x) = (A^T z).x.
    # Round-off of a solve with cond(3 V + J) below 1e8 on this grid: tolerance 1e-8.
    rng = np.random.default_rng(1)
    x, z = rng.normal(size=(lin.n, 2)), rng.normal(size=lin.n)
    d = 3.0 * lin.V
    np.testing.assert_allclose(lin.solver(d)(d[:, None] * x + lin.apply_jacobian(x)), x, rtol=0, atol=1e-8)
    assert z @ lin.apply_jacobian(x[:, 0]) == pytest.approx(lin.apply_jacobian(z, transpose=True) @ x[:, 0], rel=1e-12)


@pytest.mark.parametrize("T", [0.0, -1.0, np.nan, "x", "1"])
@pytest.mark.parametrize("method", ["direct", "fast"])
def test_bad_sampling_period_is_refused_up_front(plate, T, method):
    # checked with the frequencies, before any solve (it used to fail only when the response was assembled)
    with pytest.raises(LinearError, match="T \\(sampling period"):
        lfd_response(plate, [0.5, 1.0], T=T, method=method)


@pytest.mark.parametrize("tol", [-1.0, 0.0, np.nan, np.inf, "1e-8", True])
@pytest.mark.parametrize("method", ["direct", "fast"])
def test_tol_is_checked_on_both_paths(plate, tol, method):
    # lfd_response(tol=-1) was accepted by the direct path (which does not use it)
    with pytest.raises(LinearError, match=r"tol must be a positive finite number"):
        lfd_response(plate, [0.5, 1.0], tol=tol, method=method)


def test_absurd_frequency_counts_are_refused_before_any_solve(plate):
    from cfd.frequencies import MAX_FREQUENCIES

    with pytest.raises(LinearError, match=r"omega holds 100001 frequencies, more than "
                                          r"cfd.frequencies.MAX_FREQUENCIES = 100000"):
        lfd_response(plate, np.zeros(MAX_FREQUENCIES + 1))


@pytest.mark.parametrize("omega", [np.array([1.0 + 1.0j]), "1.0", ["0.5", "1.0"], None,
                                   (np.array([0.1, 0.2]), np.array([0.5j, 1.0]))])
def test_frequencies_that_are_not_real_numbers_are_refused(plate, omega):
    # a complex omega was cast to its real part with only a ComplexWarning, "1.0" parsed as a frequency
    with pytest.raises(LinearError, match=r"must be an array of real frequencies"):
        lfd_response(plate, omega)
