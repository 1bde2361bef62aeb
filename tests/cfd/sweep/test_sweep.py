"""cfd.sweep: the fast LFD sweep against the direct per-frequency path (cfd.lfd), on coarse grids."""

import inspect
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("cfd.steady")
sys.path.append(str(Path(__file__).parents[1]))  # tests/cfd: flowgrids

from flowgrids import parabolic_c_grid  # noqa: E402

import cfd  # noqa: E402
import sysid  # noqa: E402
from cfd import gust as cgust  # noqa: E402
from cfd import solve_steady  # noqa: E402
from cfd.flow import FlowCondition  # noqa: E402
from cfd.lfd import lfd_response  # noqa: E402
from cfd.linear import LinearError, linearise, linearise_state  # noqa: E402
from cfd.sweep import SweepBasis, face_gust_vector, fast_sweep, gust_operator  # noqa: E402

T = 70 / (2 * np.pi)
M = 24  # 25 frequencies: 0 ... 2/T tan(23 pi / 48) ~ 4.3, and inf


def _system(mach):
    grid = parabolic_c_grid(thickness=0.12, n_surface=40, n_wake=10, nj=13, eta_max=4.0, xi_max=3.5)
    sol = solve_steady(grid, mach, 0.0, tol=1e-8)
    return linearise(sol)


@pytest.fixture(scope="module")
def systems():
    """NACA0012-like section on a 61 x 13 parabolic C-grid: subsonic M0.5 and transonic M0.8."""
    return {"M0.5": _system(0.5), "M0.8": _system(0.8)}


@pytest.fixture(scope="module")
def plate():
    grid = parabolic_c_grid(thickness=0.0, n_surface=24, n_wake=6, nj=9)
    flow = FlowCondition(0.3)
    q = np.broadcast_to(flow.q, grid.cell_shape + (4,)).copy()
    return linearise_state(grid, q, flow)


@pytest.fixture(scope="module")
def references(systems):
    """Direct sweeps (the reference path) on the McKelvey grid, both gusts, both flows."""
    grid_w = sysid.mckelvey_grid(M, T)
    return {(c, g): lfd_response(lin, grid_w, gust=g, method="direct") for c, lin in systems.items() for g in ("svm", "fvm")}


@pytest.mark.parametrize("gust", ["svm", "fvm"])
def test_gust_operator_equals_forcing(systems, gust):
    lin = systems["M0.8"]
    B = gust_operator(lin, gust)
    rng = np.random.default_rng(1)
    ni, nj = lin.grid.shape
    gi = rng.normal(size=(ni, nj - 1)) + 1j * rng.normal(size=(ni, nj - 1))
    gj = rng.normal(size=(ni - 1, nj)) + 1j * rng.normal(size=(ni - 1, nj))
    b = lin.forcing(gi, gj, gust)
    np.testing.assert_allclose(B @ np.concatenate([gi.ravel(), gj.ravel()]), b, rtol=0, atol=1e-13 * np.abs(b).max())
    gi, gj = cgust.face_gust_harmonic(lin.grid, 2.5, 0.3)
    np.testing.assert_array_equal(face_gust_vector(lin.grid, 2.5, 0.3), np.concatenate([gi.ravel(), gj.ravel()]))


# One combination runs in CI; the other three (transonic, FVM) take minutes each and are marked slow.
@pytest.mark.parametrize(
    "case, gust",
    [
        ("M0.5", "svm"),
        pytest.param("M0.5", "fvm", marks=pytest.mark.slow),
        pytest.param("M0.8", "svm", marks=pytest.mark.slow),
        pytest.param("M0.8", "fvm", marks=pytest.mark.slow),
    ],
)
def test_fast_equals_direct_with_trusted_estimate(systems, references, case, gust):
    lin, ref = systems[case], references[(case, gust)]
    grid_w = sysid.mckelvey_grid(M, T)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the tolerance must be met without a warning
        frf = fast_sweep(lin, grid_w, gust=gust, tol=1e-8, n_moments=8)
    assert frf.H.shape == ref.H.shape and frf.outputs == ("Cl", "Cm") and frf.T == pytest.approx(T)
    np.testing.assert_allclose(frf.omega_d, ref.omega_d)
    H, Hr = frf.H[:, 0], ref.H[:, 0]
    err = np.abs(H - Hr)
    fin = np.isfinite(frf.omega)
    rel = err[:, fin] / np.abs(Hr[:, fin])
    assert rel.max() < 1e-6
    est = np.asarray(frf.metadata["error_estimate"])
    assert est.shape == H.shape and frf.metadata["tol_met"] and frf.metadata["method"] == "fast"
    # the estimate bounds the true error (up to the direct path's own round-off)
    assert np.all(est[:, fin] + 1e-11 * np.abs(Hr[:, fin]) >= err[:, fin])
    assert np.all(np.asarray(frf.metadata["residual_norm"])[:, fin] < 1e-3)
    # the ends: omega = 0 is an ordinary (real) point, omega = inf is the feedthrough without a solve
    assert frf.omega[0] == 0.0 and abs(H[0, 0].imag) < 1e-9 * abs(H[0, 0])
    assert np.all(H[:, -1] == lin.D[:2, 0]) and np.all(est[:, -1] == 0.0)


@pytest.mark.parametrize("n_moments", [3, 4])
def test_estimate_flags_every_inaccurate_frequency_of_an_unconverged_basis(systems, references, n_moments):
    """A deliberately poor basis (one extra shift, three or four blocks): the warning names the frequencies,
    every frequency whose true error exceeds tol is flagged by its estimate (never a silently inaccurate
    value), and the estimate tracks the error (measured: at worst 0.52x and 1.2x of it, median 9x and
    12x above; it bounds the error once the basis is converged, see the test above)."""
    lin, ref = systems["M0.8"], references[("M0.8", "svm")]
    grid_w = sysid.mckelvey_grid(M, T)
    basis = SweepBasis(lin, n_moments=n_moments)
    with pytest.warns(RuntimeWarning, match=r"not met within max_shifts = 1 at \d+ frequencies \(omega = \["):
        frf = fast_sweep(lin, grid_w, basis=basis, tol=1e-8, max_shifts=1)
    assert not frf.metadata["tol_met"] and len(basis.shifts) == 2
    fin = np.isfinite(frf.omega)
    scale = np.abs(ref.H[:, 0, fin])
    err = np.abs(frf.H[:, 0] - ref.H[:, 0])[:, fin] / scale
    est = np.asarray(frf.metadata["error_estimate"])[:, fin] / scale
    big = err > 1e-8
    assert big.sum() > 10
    assert np.all(est[big] > 1e-8)
    eff = est[big] / err[big]
    assert eff.min() >= 0.3 and np.median(eff) < 1e3


def test_basis_reused_for_another_T_and_outputs(systems):
    lin = systems["M0.5"]
    basis = SweepBasis(lin, outputs=("Cl", "Cm", "Cd"), n_moments=8)
    fast_sweep(lin, sysid.mckelvey_grid(M, T), outputs=("Cl", "Cm", "Cd"), basis=basis)
    n_factor = basis.timings["n_factor"]
    T2 = 0.7 * T
    frf = fast_sweep(lin, sysid.mckelvey_grid(M, T2), outputs="Cm", gust="fvm", basis=basis)
    assert frf.T == pytest.approx(T2) and frf.outputs == ("Cm",)
    assert basis.timings["n_factor"] <= n_factor + 2  # the basis is reused (new shifts only where needed)
    ref = lfd_response(lin, frf.omega[[1, 12, 23]], outputs="Cm", gust="fvm", method="direct")
    np.testing.assert_allclose(frf.H[0, 0, [1, 12, 23]], ref.H[0, 0], rtol=1e-6)


def test_arbitrary_points(systems):
    lin = systems["M0.8"]
    w = np.array([np.inf, 2.0, 0.0, 0.37])
    frf = fast_sweep(lin, w, outputs=("Cl",), x_ref=0.25, n_moments=8)
    ref = lfd_response(lin, w, outputs=("Cl",), x_ref=0.25, method="direct")
    assert frf.T is None and frf.omega_d is None
    np.testing.assert_allclose(frf.H, ref.H, rtol=1e-6, atol=1e-12)


def test_bad_input(plate, systems):
    w = [0.0, 1.0]
    for tol in (0.0, -1e-8, np.nan, np.inf, "small"):
        with pytest.raises(LinearError, match="tol must be a positive finite number"):
            fast_sweep(plate, w, tol=tol)
    with pytest.raises(LinearError, match="max_shifts must be a positive integer"):
        fast_sweep(plate, w, max_shifts=0)
    with pytest.raises(LinearError, match=">= 0"):
        fast_sweep(plate, [-1.0])
    with pytest.raises(LinearError, match="gust method"):
        fast_sweep(plate, w, gust="fbc")
    with pytest.raises(LinearError, match="unknown output"):
        fast_sweep(plate, w, outputs=("Cl", "Cn"))
    with pytest.raises(LinearError, match="another LinearSystem"):
        fast_sweep(plate, w, basis=SweepBasis(systems["M0.5"]))
    with pytest.raises(LinearError, match="cannot give"):
        fast_sweep(plate, w, outputs="Cd", basis=SweepBasis(plate))
    with pytest.raises(LinearError, match="n_moments"):
        SweepBasis(plate, n_moments=1)



@pytest.fixture(scope="module")
def plate_basis(plate):
    basis = SweepBasis(plate, n_moments=2)
    basis.add_shift(0.5)
    return basis


# A complex frequency was cast to its real part with only a ComplexWarning (evaluate, and add_shift of a numpy
# complex); text failed in NumPy (or was parsed by float in add_shift), None with a TypeError.
NOT_REAL = [
    pytest.param(lambda w: np.asarray(w) + 1j, "dtype complex128", id="complex"),
    pytest.param(lambda w: "0.5", "str", id="text"),
    pytest.param(lambda w: None, "NoneType", id="None"),
]


@pytest.mark.parametrize("input", ["gust", "plunge"])
@pytest.mark.parametrize("make, kind", NOT_REAL)
def test_evaluate_refuses_frequencies_that_are_not_real(plate_basis, make, kind, input):
    with pytest.raises(LinearError, match=f"omega must be an array of real frequencies.*got {kind}"):
        plate_basis.evaluate(make([0.1, 0.5]), input=input)


@pytest.mark.parametrize("omega, kind", [(np.complex128(0.7 + 0.1j), "complex128"), (0.7 + 0.1j, "complex"),
                                         ("0.7", "str"), (None, "NoneType"), (True, "bool")])
def test_add_shift_refuses_a_frequency_that_is_not_real(plate_basis, omega, kind):
    shifts = list(plate_basis.shifts)
    with pytest.raises(LinearError, match=f"shift frequencies must be real numbers.*got {kind}"):
        plate_basis.add_shift(omega)
    with pytest.raises(LinearError, match=f"shift frequencies must be real numbers.*got {kind}"):
        plate_basis.add_shifts([0.9, omega])   # refused before the first shift is factorised
    assert plate_basis.shifts == shifts


# Before: a NaN or infinite shift failed in SuperLU with a bare RuntimeError ("Factor is exactly singular"), a
# negative one was factorised and kept; evaluate gave outputs of 0 at NaN and inf with only RuntimeWarnings.
@pytest.mark.parametrize("omega", [np.nan, np.inf, -np.inf, -1.0, np.float32(-0.5)])
def test_add_shift_refuses_a_frequency_that_is_not_finite_and_nonnegative(plate_basis, omega):
    shifts, size = list(plate_basis.shifts), plate_basis.size
    with pytest.raises(LinearError, match=r"shift frequencies must be finite and >= 0 .*got"):
        plate_basis.add_shift(omega)
    with pytest.raises(LinearError, match=r"shift frequencies must be finite and >= 0"):
        plate_basis.add_shifts([0.9, omega])   # refused before the first shift is factorised
    assert plate_basis.shifts == shifts and plate_basis.size == size


@pytest.mark.parametrize("omega", [[0.5, np.nan], [np.inf], [0.1, -1.0]])
def test_evaluate_refuses_frequencies_that_are_not_finite_and_nonnegative(plate_basis, omega):
    with pytest.raises(LinearError, match=r"omega must be finite frequencies >= 0 .*got \["):
        plate_basis.evaluate(omega)


@pytest.mark.parametrize("convert", [lambda w: np.asarray(w, np.float32), lambda w: w.tolist()],
                         ids=["float32", "list"])
def test_evaluate_takes_real_frequencies_of_any_real_type(plate_basis, convert):
    w = np.array([0.0, 0.5, 1.0])   # exact in float32
    y, est, res = plate_basis.evaluate(w)
    for a, b in zip(plate_basis.evaluate(convert(w)), (y, est, res)):
        np.testing.assert_array_equal(a, b)
    np.testing.assert_array_equal(plate_basis.evaluate([0, 1])[0], y[:, [0, 2]])


def test_vortex_far_field_system():
    """With the point-vortex far field the rank-one circulation term is in the sweep operator too."""
    from cfd.euler import Scheme

    grid = parabolic_c_grid(thickness=0.12, n_surface=24, n_wake=6, nj=9, eta_max=4.0, xi_max=3.5)
    scheme = Scheme(vortex=True)
    lin = linearise(solve_steady(grid, 0.5, 0.0, tol=1e-9, scheme=scheme), scheme=scheme)
    assert lin.vortex is not None
    w = np.array([0.0, 0.3, 1.0, 3.0])
    ref = lfd_response(lin, w, method="direct").H
    fast = lfd_response(lin, w, method="fast", tol=1e-9).H
    assert np.abs(fast - ref).max() <= 1e-7 * np.abs(ref).max()
    import dataclasses

    frozen = lfd_response(dataclasses.replace(lin, vortex=None), w[:1], method="direct").H
    assert np.abs(frozen[0, 0, 0] - ref[0, 0, 0]) > 1e-3 * np.abs(ref[0, 0, 0])  # the term matters here


@pytest.mark.parametrize("method, n, expected", [("auto", 8, "direct"), ("auto", 9, "fast"), ("direct", 12, "direct"),
                                                 ("fast", 2, "fast")])
def test_lfd_response_method_dispatch(plate, method, n, expected):
    w = np.linspace(0.0, 2.0, n)
    frf = lfd_response(plate, w, method=method)
    assert frf.metadata["method"] == expected
    if expected == "fast":
        ref = lfd_response(plate, w, method="direct").H
        assert np.abs(frf.H - ref).max() <= 1e-6 * np.abs(ref).max()
        assert np.asarray(frf.metadata["error_estimate"]).shape == (2, n)


@pytest.mark.parametrize("kwargs, match", [
    (dict(method="krylov"), "method must be one of"),
    (dict(method="fast", tol=0.0), "tol must be a positive finite"),
    (dict(method="fast", tol=np.nan), "tol must be a positive finite"),
    (dict(method="direct", max_shifts=3), "belong to the fast sweep"),
    (dict(method="fast", max_shift=3), r"unknown option\(s\) \['max_shift'\].*fast-sweep options are \('max_shifts'"),
    (dict(method="direct", max_shift=3), r"unknown option\(s\) \['max_shift'\]"),
    (dict(method="auto", nmoments=3, x=1), r"unknown option\(s\) \['nmoments', 'x'\]"),
    (dict(method="fast", max_shifts="a"), "max_shifts must be a positive integer"),
    (dict(method="fast", max_shifts=np.nan), "max_shifts must be a positive integer"),
    (dict(method="fast", max_shifts=np.inf), "max_shifts must be a positive integer"),
    (dict(method="fast", max_shifts=2.5), "max_shifts must be a positive integer"),
    (dict(method="fast", max_shifts=True), "max_shifts must be a positive integer"),
    (dict(method="fast", n_moments=None), "n_moments must be an integer >= 2"),
    (dict(method="fast", n_moments="4"), "n_moments must be an integer >= 2"),
    (dict(method="fast", basis="x"), "basis must be a cfd.sweep.SweepBasis"),
    (dict(method="fast", progress=5), "progress must be a callable"),
    (dict(method="fast", log_interval="a"), "log_interval must be a number of seconds"),
    (dict(method="fast", log_interval=np.nan), "log_interval must be a number of seconds"),
    (dict(outputs=None), "outputs must be a name or a sequence of names"),
    (dict(outputs=5), "outputs must be a name or a sequence of names"),
])
def test_lfd_response_method_bad_input(plate, kwargs, match):
    with pytest.raises(LinearError, match=match):
        lfd_response(plate, [0.5, 1.0], **kwargs)


def test_fast_options_are_the_keywords_fast_sweep_takes_beyond_lfd_response():
    from cfd.lfd import FAST_OPTIONS

    own = set(inspect.signature(lfd_response).parameters)
    assert set(FAST_OPTIONS) == set(inspect.signature(fast_sweep).parameters) - own


def test_an_interrupted_sweep_keeps_its_factorisations_and_goes_on_from_them(plate):
    # Ctrl-C (here: the progress callback, after the second shift) lost every factorisation before; now the
    # interrupt carries the basis, and a sweep from it gives the uninterrupted sweep's response
    grid_w = sysid.mckelvey_grid(M, T)

    def stop(basis, worst, failing):
        if len(basis.shifts) == 2:
            raise KeyboardInterrupt

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        full = fast_sweep(plate, grid_w, tol=1e-8, n_moments=3, max_shifts=12)
        with pytest.raises(cfd.SweepInterrupted, match=r"2 shifted factorisations .*basis=e\.basis") as e:
            fast_sweep(plate, grid_w, tol=1e-8, n_moments=3, max_shifts=12, progress=stop)
        kept = list(e.value.basis.shifts)
        assert isinstance(e.value, KeyboardInterrupt) and len(kept) == 2
        again = fast_sweep(plate, grid_w, tol=1e-8, n_moments=3, max_shifts=10, basis=e.value.basis)
    # the two factorisations are not made again; the sweep meets its tolerance from there, and both responses are
    # within it of each other (each estimated within 1e-8 of the exact one, relative to the output's scale)
    assert again.metadata["shifts"][:2] == kept and again.metadata["tol_met"] and full.metadata["tol_met"]
    np.testing.assert_allclose(again.H, full.H, rtol=0, atol=1e-7 * np.abs(full.H).max())


def test_progress_reports_every_shift_and_changes_nothing(plate, caplog):
    grid_w = sysid.mckelvey_grid(M, T)
    calls = []

    def progress(basis, worst, failing):
        calls.append((len(basis.shifts), basis.shifts[-1], basis.size, worst, np.array(failing)))

    with caplog.at_level("INFO", logger="cfd.sweep"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        frf = fast_sweep(plate, grid_w, tol=1e-8, n_moments=3, max_shifts=4, progress=progress, log_interval=0.0)
    n_shifts = len(frf.metadata["shifts"])
    assert [c[0] for c in calls] == list(range(1, len(calls) + 1)) and len(calls) in (n_shifts, n_shifts - 1)
    assert [c[1] for c in calls] == frf.metadata["shifts"][:len(calls)]
    sizes = [c[2] for c in calls]
    assert sizes == sorted(sizes) and sizes[0] > 0
    for _, _, _, worst, failing in calls:
        assert worst > 0 and (failing.size == 0) == (worst <= 1e-8)
        assert np.all(np.isin(failing, grid_w[1]))
    lines = [r.getMessage() for r in caplog.records if r.name == "cfd.sweep"]
    assert len(lines) == len(calls) and "fast sweep: 1 shift(s)" in lines[0] and "frequencies above tol" in lines[0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        plain = fast_sweep(plate, grid_w, tol=1e-8, n_moments=3, max_shifts=4)
    np.testing.assert_array_equal(plain.H, frf.H)


def test_plan_shifts_spreads_side_by_side_shifts_and_sizes_their_blocks():
    from cfd.sweep import MIN_MOMENTS, ADAPT_MOMENTS, _plan_shifts

    wf = np.array([0.0, 0.1, 0.2, 0.3, 0.4, 1.0, 1.5, 3.0, 8.0])
    ratio = np.array([0.0, 5.0, 6.0, 7.0, 1.0, 9.0, 8.0, 2.0, 3.0]) * 1e-6
    # the worst (1.0), then the worst more than a factor 2 from the chosen ones (0.3, 0.1), then beyond the
    # shift at 2.0: 8.0, then 3.0 (more than a factor 2 from 8.0); 0.2, 0.4 and 1.5 are too near a chosen one
    plan = _plan_shifts(wf, ratio, 1e-8, [0.0, 2.0], 6, 16)
    assert [w for w, _ in plan] == [1.0, 0.3, 0.1, 8.0, 3.0]
    # blocks: ADAPT_MOMENTS per failing frequency between the neighbouring shifts, within [MIN_MOMENTS, 16]
    assert plan[0][1] == min(16, max(MIN_MOMENTS, ADAPT_MOMENTS * 6))   # 0.1 ... 1.5 lie between 0 and 2
    assert plan[3][1] == MIN_MOMENTS                                    # 3.0 and 8.0 above 2
    assert _plan_shifts(wf, ratio, 1e-8, [0.0, 2.0], 1, 3)[0] == (1.0, 3)  # never more than n_moments
    # frequencies that are shifts already are never chosen again; none failing -> nothing
    assert [w for w, _ in _plan_shifts(wf, ratio, 1e-8, [0.0, 1.0, 2.0], 1, 16)] == [1.5]
    assert _plan_shifts(wf, np.zeros(wf.size), 1e-8, [0.0], 2, 16) == []


def test_worker_processes_give_a_sweep_as_accurate_as_one_process(systems, references):
    """Two shifts per greedy step, factorised in two forked processes: the same accuracy and a bounding
    estimate as the one-process sweep (the basis differs: the shifts are chosen two at a time)."""
    from cfd.sweep.workers import can_fork_workers

    if not can_fork_workers():
        pytest.skip("no 'fork' start method here")
    lin, ref = systems["M0.5"], references[("M0.5", "svm")]
    grid_w = sysid.mckelvey_grid(M, T)
    steps = []
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        frf = fast_sweep(lin, grid_w, tol=1e-8, n_moments=8, workers=2,
                         progress=lambda basis, worst, failing: steps.append(len(basis.shifts)))
    assert frf.metadata["tol_met"]
    assert len(steps) < len(frf.metadata["shifts"])  # some steps added two shifts
    fin = np.isfinite(frf.omega)
    err = np.abs(frf.H[:, 0] - ref.H[:, 0])[:, fin]
    est = np.asarray(frf.metadata["error_estimate"])[:, fin]
    assert np.max(err / np.abs(ref.H[:, 0, fin])) < 1e-6
    assert np.all(est + 1e-11 * np.abs(ref.H[:, 0, fin]) >= err)


def test_shift_workers_bad_input(plate):
    from cfd.sweep.workers import ShiftWorkers, shift_workers

    basis = SweepBasis(plate)
    assert shift_workers(basis, 1) is None
    with pytest.raises(LinearError, match="workers >= 2"):
        ShiftWorkers(basis, 1)
    with pytest.raises(LinearError, match="one integer >= 1 per shift"):
        basis.add_shifts([0.5, 1.0], [4])
    for workers in (0, 1.5, "2"):
        with pytest.raises(LinearError, match="workers must be a positive integer"):
            fast_sweep(plate, [0.0, 1.0], workers=workers)


@pytest.mark.parametrize("workers, match", [
    (True, r"workers must be a positive integer"),                      # was taken as 1
    (10**6, r"workers = 1000000 is more than cfd.sweep.MAX_WORKERS = 64"),  # would fork a million processes at once
])
def test_worker_counts_are_checked_before_any_process_starts(plate, workers, match):
    with pytest.raises(LinearError, match=match):
        fast_sweep(plate, np.linspace(0.1, 2.0, 12), workers=workers)
