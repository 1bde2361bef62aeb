"""cfd.unsteady: the nonlinear gust response against the LTD at small amplitudes, and its bad inputs."""

import warnings
from dataclasses import replace

import numpy as np
import pytest

from flowgrids import parabolic_c_grid

import cfd
from cfd import (LocalMachError, MarchInterrupted, NonPhysicalStateError, OneMinusCosine, SharpEdged, UnsteadyError,
                 UnsteadyStepError, linearise, ltd_response, solve_steady, unsteady_response)
from cfd.unsteady import _source_jacobian
from cfd.gust import cell_x_gradient, face_gust, svm_source

# Many tests here march a few steps only (bad input, options, progress counts), ending before the gust front
# reaches the aerofoil on purpose; the march's warning about that is expected in them (tests of the warning
# itself use pytest.warns, which sees it regardless).
pytestmark = pytest.mark.filterwarnings("ignore:the march ends at t_end:RuntimeWarning")


@pytest.fixture(scope="module")
def subsonic():
    """NACA0012-like parabolic grid (97 x 17 nodes), M0.5, alpha 1 deg (lifting: no far-field tie, see docs)."""
    grid = parabolic_c_grid(thickness=0.12, n_surface=48, n_wake=12, nj=17)
    sol = solve_steady(grid, 0.5, 1.0, tol=1e-12)
    return sol, linearise(sol)


@pytest.fixture(scope="module")
def coarse():
    grid = parabolic_c_grid(thickness=0.1, n_surface=32, n_wake=8, nj=13)
    return solve_steady(grid, 0.5, 0.0, tol=1e-12)


def gust(angle_deg):
    return OneMinusCosine(length=2.0, angle_deg=angle_deg, x0=-1.0)


def test_small_amplitudes_follow_the_ltd_and_the_difference_is_linear(subsonic):
    """Cl / A and Cm / A within 0.5 % of the LTD's peak at 0.01 and 0.1 deg; the difference grows 10x per decade."""
    sol, lin = subsonic
    dt, t_end = 0.1, 5.0
    h = ltd_response(lin, gust(1.0), dt, t_end, max_phase_error=1.0)
    A1 = gust(1.0).amplitude
    err = {}
    for a in (0.01, 0.1):
        g = gust(a)
        u = unsteady_response(sol, g, dt, t_end, max_phase_error=1.0)
        assert u.complete and u.n_factorisations == 1 and u.iterations.max() <= 3
        np.testing.assert_array_equal(u.t, h.t)
        np.testing.assert_allclose(u.u / g.amplitude, h.u / A1, rtol=1e-12, atol=1e-15)
        err[a] = [np.abs(y / g.amplitude - yl / A1).max() / np.abs(yl / A1).max()
                  for y, yl in ((u.cl, h.cl), (u.cm, h.cm))]
    # Measured: Cl 6.5e-6 and 6.6e-5 of the peak, Cm 2.6e-5 and 2.6e-4 (the criterion is 5e-3).
    assert err[0.01][0] < 2e-5 and err[0.1][0] < 2e-4, err
    assert err[0.01][1] < 1e-4 and err[0.1][1] < 1e-3, err
    for k in (0, 1):
        assert 8.0 < err[0.1][k] / err[0.01][k] < 12.0, err  # measured 10.13 and 10.03


def test_history_fields_totals_and_snapshots(coarse):
    g = gust(0.5)
    # 1 + 1e-12: round-off past t_end is the last step (a time well past it is refused: test_bad_arguments)
    u = unsteady_response(coarse, g, 0.1, 1.0, snapshot_times=(0.0, 0.52, 1.0 + 1e-12), max_phase_error=1.0)
    assert u.t.shape == u.cl.shape == u.cd.shape == u.iterations.shape == u.max_mach.shape == (11,)
    assert u.cl[0] == u.cm[0] == u.cd[0] == 0.0 and u.iterations[0] == 0
    np.testing.assert_allclose(u.cl_total, coarse.cl + u.cl)
    np.testing.assert_allclose(u.cd_total - u.cd, coarse.cd, atol=1e-14)
    assert sorted(u.snapshots) == [0.0, 0.5, 1.0]
    np.testing.assert_allclose(u.snapshots[1.0].ravel() - coarse.q.ravel(), u.q, atol=1e-15)
    assert u.amplitude_deg == 0.5 and u.method == "svm" and u.dt == 0.1
    assert np.all(u.residual[1:] <= 1e-8) and u.info["steady_residual"] < 1e-10
    with pytest.raises(ValueError, match="read-only"):
        u.cl[0] = 1.0  # as the LTD's


def test_a_snapshot_at_the_marchs_last_step_past_t_end_is_kept(coarse):
    # t_end = 0.97 with dt = 0.1 marches 10 steps, to 1.0: a snapshot there is the march's last state (it was refused
    # once times past t_end were)
    u = unsteady_response(coarse, gust(0.5), 0.1, 0.97, snapshot_times=(1.0,), max_phase_error=1.0)
    assert u.t[-1] == pytest.approx(1.0) and sorted(u.snapshots) == [pytest.approx(1.0)]


def test_zero_gust_stays_steady_and_progress_is_called(coarse):
    calls = []
    u = unsteady_response(coarse, gust(1e-9), 0.1, 0.5, progress=lambda *a: calls.append(a), max_phase_error=1.0)
    assert [c[0] for c in calls] == [1, 2, 3, 4, 5] and calls[-1][1] == 5 and calls[-1][2] == pytest.approx(0.5)
    assert np.abs(u.cl).max() < 1e-12


def test_fvm_and_krylov_agree_with_their_references(coarse):
    """FVM against the FVM LTD at 0.01 deg; GMRES corrections give the chord result to the tolerance."""
    lin = linearise(coarse)
    g = gust(0.01)
    h = ltd_response(lin, g, 0.1, 3.0, method="fvm", max_phase_error=1.0)
    u = unsteady_response(coarse, g, 0.1, 3.0, method="fvm", max_phase_error=1.0)
    assert np.abs(u.cl - h.cl).max() < 2e-3 * np.abs(h.cl).max()
    k = unsteady_response(coarse, g, 0.1, 3.0, method="fvm", krylov=True, max_phase_error=1.0)
    assert k.info["n_gmres"] > 0
    np.testing.assert_allclose(k.cl, u.cl, atol=1e-6 * np.abs(h.cl).max())


def test_svm_source_jacobian_matches_complex_step_of_the_source(coarse):
    grid = coarse.grid
    gi, gj = face_gust(grid, gust(3.0), 1.5)
    dgdx = cell_x_gradient(grid, gi, gj)
    J = _source_jacobian(coarse.q, 0.5, dgdx, 1.4)
    rng = np.random.default_rng(1)
    v = rng.normal(size=coarse.q.shape)
    e = 1e-7
    fd = -(svm_source(coarse.q + e * v, 0.5, dgdx) - svm_source(coarse.q - e * v, 0.5, dgdx)) / (2 * e)
    np.testing.assert_allclose(J @ v.ravel(), fd.ravel(), atol=1e-9 * np.abs(fd).max())


def test_stalled_steps_refactorise_and_large_gusts_warn(coarse):
    """A strong gust makes the frozen Jacobian stall: the matrix is refactorised and the march completes."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        u = unsteady_response(coarse, gust(15.0), 0.1, 2.5, max_phase_error=1.0, stall_ratio=0.05)
    assert u.complete and u.n_factorisations > 1 and len(u.refactorised_at) == u.n_factorisations - 1


def test_dt_too_large_for_the_gust_warns(coarse):
    with pytest.warns(RuntimeWarning, match=r"phase-rate error .* reduce dt"):
        unsteady_response(coarse, gust(0.1), 0.5, 0.5)


def test_local_mach_beyond_the_limit_is_a_typed_error_with_the_history(coarse):
    with pytest.raises(LocalMachError, match=r"step \d+ \(s = .*\) of the 30 deg gust: local Mach number") as e:
        unsteady_response(coarse, gust(30.0), 0.1, 4.0, max_phase_error=1.0, max_local_mach=0.9)
    err = e.value
    assert isinstance(err, UnsteadyStepError) and isinstance(err, RuntimeError)
    assert not err.partial.complete and err.partial.t[-1] == pytest.approx((err.step - 1) * 0.1)
    assert err.amplitude_deg == 30.0 and err.partial.cl.size == err.step


def test_separation_warning(coarse):
    with pytest.warns(RuntimeWarning, match=r"raises the peak local Mach number .* separate"):
        unsteady_response(coarse, gust(30.0), 0.1, 2.0, max_phase_error=1.0, separation_mach=0.9)


def test_non_physical_state_is_a_typed_error_naming_step_and_amplitude(coarse):
    """An 89 deg gust (v_g = 57 U): the Newton iterate has negative pressure at step 6."""
    g = OneMinusCosine(length=2.0, angle_deg=89.0, x0=-1.0)
    with pytest.raises(NonPhysicalStateError, match=r"step 6 \(s = 1.2\) of the 89 deg svm gust .* non-positive"):
        unsteady_response(coarse, g, 0.2, 4.0, max_phase_error=np.inf, max_local_mach=np.inf, separation_mach=np.inf)


def test_a_residual_that_is_not_finite_at_a_step_is_a_typed_error(coarse, monkeypatch):
    # a NaN residual at a step's predictor (an overflowed forcing) compared False with the target and the step was
    # taken as converged, NaN and all; now NonPhysicalStateError names the step, with the history before it
    import cfd.unsteady as unsteady

    real = unsteady._March._forcing

    def nan_like(v):
        return tuple(nan_like(x) for x in v) if isinstance(v, (tuple, list)) else np.asarray(v) * np.nan

    def forcing(self, s):   # the gust's face velocities overflow from s = 1 on
        out = real(self, s)
        return nan_like(out) if s >= 1.0 else out

    monkeypatch.setattr(unsteady._March, "_forcing", forcing)
    with pytest.raises(NonPhysicalStateError, match=r"step 10 \(s = 1\) .* residual at the step's predictor is not finite") as e:
        unsteady_response(coarse, gust(1.0), 0.1, 2.0, max_phase_error=1.0)
    assert e.value.partial is not None and np.all(np.isfinite(e.value.partial.cl))


def test_non_converged_steady_solution_is_refused(coarse):
    rng = np.random.default_rng(0)
    rough = replace(coarse, q=coarse.q * (1.0 + 1e-6 * rng.normal(size=coarse.q.shape)))
    with pytest.raises(UnsteadyError, match=r"not converged: \|R\(q\)\| / \|R\(free stream\)\| = .* Re-solve"):
        unsteady_response(rough, gust(0.1), 0.1, 1.0, max_phase_error=1.0)
    with pytest.raises(UnsteadyError, match=r"not converged"):
        unsteady_response(replace(coarse, converged=False), gust(0.1), 0.1, 1.0, max_phase_error=1.0)


@pytest.mark.parametrize("kwargs, match", [
    (dict(method="xyz"), "method must be one of"),
    (dict(dt=0.0), "dt = 0.0 must be positive"),
    (dict(t_end=0.01), "at least one time step"),
    (dict(gust="1-cos"), "gust must be a cfd"),
    (dict(x_ref=float("nan")), "x_ref must be finite"),
    (dict(x_ref=float("inf")), "x_ref must be finite"),
    (dict(x_ref="a"), "x_ref must be a real number"),
    (dict(rtol=-1.0), "rtol must be a finite number >= 0"),
    (dict(atol=np.nan), "atol must be a finite number >= 0"),
    (dict(max_iter=0), "max_iter must be a whole number >= 1"),
    (dict(max_iter=2.5), "max_iter must be a whole number >= 1"),
    (dict(max_refactor=-1), "max_refactor must be a whole number >= 0"),
    (dict(stall_ratio=0.0), r"stall_ratio must be a number in \(0, 1\]"),
    (dict(steady_tol=np.nan), "steady_tol must be a positive number"),
    (dict(max_phase_error="a"), "max_phase_error must be a positive number"),
    (dict(max_local_mach=0.0), "max_local_mach must be a positive number"),
    (dict(separation_mach=np.nan), "separation_mach must be a positive number"),
    (dict(snapshot_times=5), "snapshot_times must be a sequence of finite convective times"),
    (dict(snapshot_times=[1.0, np.nan]), "snapshot_times must be a sequence"),
    # a time past t_end stored the state of t_end (under t_end's key): the asked-for state was silently missing
    (dict(snapshot_times=(0.5, 100.0)), r"snapshot_times must lie in the march, 0 <= s <= 1 \(its last step\); got 100.0"),
    (dict(snapshot_times=(-1.0,)), r"snapshot_times must lie in the march, 0 <= s <= 1 \(its last step\); got -1.0"),
])
def test_bad_arguments(coarse, kwargs, match):
    args = dict(gust=gust(0.1), dt=0.1, t_end=1.0)
    args.update(kwargs)
    with pytest.raises(UnsteadyError, match=match):
        unsteady_response(coarse, **args)


def test_linearity_returns_peak_ratios_near_one_at_small_amplitudes(coarse):
    res = cfd.linearity(coarse, gust(1.0), [0.01, 1.0], 0.1, 3.0, max_phase_error=1.0)
    assert res.cl_peak_ratio.shape == (2,) and len(res.histories) == 2
    assert abs(res.cl_peak_ratio[0] - 1) < 1e-3 and res.cl_error[0] < 1e-3
    with pytest.raises(UnsteadyError, match="nonzero"):
        cfd.linearity(coarse, gust(1.0), [0.0], 0.1, 3.0)


@pytest.mark.parametrize("amplitudes, kwargs, match", [
    ([1.0], dict(max_iters=5), r"unknown keyword\(s\) \['max_iters'\] for unsteady_response; it takes .*'max_iter'"),
    (["one"], {}, r"finite, nonzero gust angles .*'one'"),
    ([1.0, np.nan], {}, r"finite, nonzero gust angles"),
])
def test_linearity_refuses_bad_input_before_the_ltd(coarse, monkeypatch, amplitudes, kwargs, match):
    # refused before any march: the LTD would otherwise run first and the typo fail only after it
    def no_march(*args, **kw):
        raise AssertionError("the LTD was computed before the input was checked")
    monkeypatch.setattr("cfd.ltd.ltd_response", no_march)
    with pytest.raises(UnsteadyError, match=match):
        cfd.linearity(coarse, gust(1.0), amplitudes, 0.1, 3.0, lin=object(), **kwargs)


def test_a_stalled_step_says_what_to_change(coarse):
    # a strong sharp-edged gust and no refactorisation allowed: the chord-Newton step stalls at once
    with pytest.raises(UnsteadyStepError, match=r"stalled after 0 refactorisations .*reduce dt or the amplitude, "
                                                r"or allow more with max_refactor") as info:
        unsteady_response(coarse, SharpEdged(angle_deg=20.0, x0=-1.0), 0.2, 3.0, max_refactor=0, max_phase_error=1.0)
    assert info.value.partial is not None


# --- input checks (issue 34): the LTD's step limit, gusts shorter than the step, flags and callbacks --------------

def test_the_step_count_is_limited_before_any_work(coarse, monkeypatch):
    # unsteady_response(sol, gust, 1e-9, 40) tried to allocate 298 GiB of histories: now cfd.ltd.MAX_STEPS, as the LTD
    from cfd.ltd import MAX_STEPS

    monkeypatch.setattr("cfd.unsteady.residual", lambda *a, **k: (_ for _ in ()).throw(AssertionError("work done")))
    with pytest.raises(UnsteadyError, match=r"t_end / dt = 40 / 1e-09 = 4e\+10 steps, more than cfd.ltd.MAX_STEPS = "
                                            r"1e\+06: .*march a longer history in pieces"):
        unsteady_response(coarse, gust(1.0), 1e-9, 40.0)
    with pytest.raises(UnsteadyError, match="MAX_STEPS"):     # one step over the limit
        unsteady_response(coarse, gust(1.0), 1.0, float(MAX_STEPS + 1))


# Before: t_end = 1e301 (dt = 1e300) failed in the phase-error estimate with a bare OverflowError; the LTD's
# Radau IIA march at such times gave zero loads without a word (the gust's face averages are round-off there).
@pytest.mark.parametrize("dt, t_end", [(1e300, 1e301), (1e5, 2e6)])
def test_a_march_beyond_max_time_is_refused_before_any_work(coarse, monkeypatch, dt, t_end):
    monkeypatch.setattr("cfd.unsteady.residual", lambda *a, **k: (_ for _ in ()).throw(AssertionError("work done")))
    with pytest.raises(UnsteadyError, match=r"t_end = .* is beyond cfd.ltd.MAX_TIME = 1e\+06: .*check dt"):
        unsteady_response(coarse, SharpEdged(angle_deg=1.0, x0=-1.0), dt, t_end)


@pytest.mark.parametrize("kwargs, match", [
    (dict(gust=OneMinusCosine(length=2.0, angle_deg=1.0), dt=5.0), r"passes a point in 0.4 time steps of dt = 5, "
                                                                   r"fewer than 2 .*Use dt <= 1 "),
    (dict(krylov="no"), r"krylov must be True or False; got 'no'"),
    (dict(krylov=1), r"krylov must be True or False; got 1"),
    (dict(progress="print"), r"progress must be a callable or None"),
    (dict(log_interval=-5), r"log_interval must be a number of seconds >= 0"),
])
def test_bad_march_settings_are_refused_before_any_work(coarse, monkeypatch, kwargs, match):
    monkeypatch.setattr("cfd.unsteady.residual", lambda *a, **k: (_ for _ in ()).throw(AssertionError("work done")))
    args = dict(gust=gust(1.0), dt=0.1, t_end=10.0)
    args.update(kwargs)
    with pytest.raises(UnsteadyError, match=match):
        unsteady_response(coarse, **args)


def test_a_march_that_ends_before_the_gust_arrives_warns(coarse):
    with pytest.warns(RuntimeWarning, match=r"ends at t_end = 0.5, before the gust front \(x0 = -1\) reaches"):
        h = unsteady_response(coarse, gust(1.0), 0.25, 0.5)
    assert not np.any(h.u)


@pytest.mark.parametrize("amplitudes, error, match", [
    ([[0.5, 1.0]], UnsteadyError, r"amplitudes must be a 1-D list .*got shape \(1, 2\)"),
    ([1.0, 95.0], cfd.GustError, r"angle_deg = 95.0 is not a gust angle"),
    (["1"], UnsteadyError, r"amplitudes must be a non-empty list of finite, nonzero gust angles"),   # parsed before
])
def test_linearity_refuses_2d_and_impossible_amplitudes_before_the_ltd(coarse, monkeypatch, amplitudes, error, match):
    # a 2-D list was flattened silently; a 95 deg amplitude failed only after the LTD and the first amplitudes
    def no_march(*args, **kw):
        raise AssertionError("the LTD was computed before the input was checked")
    monkeypatch.setattr("cfd.ltd.ltd_response", no_march)
    with pytest.raises(error, match=match):
        cfd.linearity(coarse, gust(1.0), amplitudes, 0.1, 3.0, lin=object())


def test_snapshots_that_cannot_fit_in_memory_are_refused(coarse, monkeypatch):
    # a snapshot at every one of a million steps: 18 KiB states of this grid, 17 GiB, refused before the march
    monkeypatch.setattr("cfd.unsteady._March", lambda *a, **k: (_ for _ in ()).throw(AssertionError("marched")))
    with pytest.raises(UnsteadyError, match=r"snapshot_times asks for 1000000 full states .* more than "
                                            r"MAX_SNAPSHOT_BYTES = 4 GiB"):
        unsteady_response(coarse, gust(1.0), 1e-3, 1000.0, snapshot_times=np.arange(1_000_000) * 1e-3)


def interrupt_at(step):
    """A ``progress`` callback that raises KeyboardInterrupt (Ctrl-C) at ``step``."""
    def progress(k, *args):
        if k == step:
            raise KeyboardInterrupt
    return progress


def test_an_interrupt_keeps_the_history_so_far(coarse):
    # Ctrl-C lost the march; now the KeyboardInterrupt carries it (.partial), as an UnsteadyStepError does
    with pytest.raises(KeyboardInterrupt) as info:
        unsteady_response(coarse, gust(0.5), 0.1, 1.0, snapshot_times=(0.2, 0.8), progress=interrupt_at(5),
                          max_phase_error=1.0)
    e = info.value
    assert isinstance(e, MarchInterrupted) and e.step == 5 and e.time == pytest.approx(0.5)
    assert "interrupted at step 5 of 10" in str(e)
    p = e.partial
    assert not p.complete and p.t.shape == p.cl.shape == p.iterations.shape == (6,)
    assert sorted(p.snapshots) == [pytest.approx(0.2)]
    full = unsteady_response(coarse, gust(0.5), 0.1, 0.5, max_phase_error=1.0)  # the same march, ended there
    np.testing.assert_array_equal(p.cl, full.cl)
    np.testing.assert_array_equal(p.q, full.q)
