"""Fast LFD frequency sweep: a reduced adjoint (dual) basis from a few shifted factorisations.

The LFD response to the unit harmonic gust (``cfd.lfd``) is

    y(omega) = C q,      (J + i w V) q = -b(omega),      w = mach * omega   (solver units)

for many frequencies. The forcing ``b(omega) = B g(omega)`` is a fixed sparse operator ``B`` (``gust
operator``: face velocities and, for the SVM, sources; probed from ``LinearSystem.forcing``) applied to the
face averages ``g(omega)`` of ``exp(-i omega (x - x_ref))`` (``cfd.gust.face_gust_harmonic``), a field whose
phase varies across the whole grid: the primal solutions ``q(omega)`` span a large space. The outputs are
few, so the sweep is done on the dual (adjoint) side instead:

    y(omega) = -Z(omega)^T b(omega),      (J + i w V)^T Z(omega) = C^T      (Z: n x p, one column per output)

whose right-hand side does not depend on ``omega``. ``Z`` is approximated in a basis ``W`` (orthonormal,
n x m) built by rational Krylov from a few shifts ``sigma``: one sparse LU of ``(J + i sigma V)^T`` per shift
(the same nested-dissection ordering as the direct path), then the blocks ``Z(sigma)`` and
``((J + i sigma V)^-T V)^k Z(sigma)`` (the derivatives of ``Z`` in ``omega`` at the shift), orthonormal among
themselves, then orthonormalised against the basis in one block pass, block by block in their order. At
every frequency the small Galerkin system ``W^H (J + i w V)^T W Y = W^H C^T`` is solved through one Schur
form of the Cholesky-scaled projected operator (a triangular solve of ``p`` columns per frequency,
``O(m^2 p)``), and its residual ``C^T - (J + i w V)^T W Y`` is evaluated in the coordinates of an
orthonormal basis of ``[C^T, J^T W, V W]``, so the residual norms are exact (no normal equations, no
cancellation), and ``y = -Y^T (W^T B) g(omega)`` costs one product with an ``m x n_faces`` matrix. Shifts
are added greedily at the frequency with the largest estimated error until every frequency meets ``tol``
(with ``workers`` > 1, that many per step, spread apart, factorised side by side in forked processes).

Error estimate
--------------
The basis is nested: ``W_`` is ``W`` without the last Krylov block of every shift. The output error of the
reduced solution is ``e = r^T q`` (``r`` its dual residual, ``q`` the primal state), and the difference of
the two reduced outputs is ``y - y_ = (r_ - r)^T q``: the primal state seen along the residual change. With
the exact residuals of both models (vectors in the small orthonormal basis) the error of ``y`` is estimated as

    est = SAFETY |y - y_| |r| / |r_ - r|,

reported per output and frequency in ``metadata["error_estimate"]`` (absolute, per radian of gust angle),
next to the relative dual residual norms ``metadata["residual_norm"]``. The estimate is checked against the
direct path in ``tests/cfd/sweep/test_sweep.py`` (measured effectivities in docs/lfd-sweep.md).

``omega = inf`` is the feedthrough ``D`` without a solve (estimate 0); ``omega = 0`` is an ordinary point.

The sub-package: this module drives the greedy choice of shifts (:func:`fast_sweep`); :mod:`cfd.sweep.basis`
holds the reduced basis (:class:`SweepBasis`: the gust operator, the shifted factorisations, the reduced
evaluation and its error estimate) with the block orthonormalisation of :mod:`cfd.sweep.orthonormal`;
:mod:`cfd.sweep.workers` factorises several shifts in forked processes.
"""

import logging
import time
import warnings

import numpy as np

from sysid import FrequencyResponse

from ..frequencies import check_motion_frequencies, check_pivot, check_tol, check_x_ref, frequency_grid
from ..linear import LinearError, check_gust_method, check_linear_system, check_outputs
from ..motion import check_inputs
from ..checks import whole_number
from ..errors import SweepInterrupted
from .basis import SAFETY, SweepBasis, face_gust_vector, gust_operator  # noqa: F401
from .workers import shift_workers

__all__ = ["SweepBasis", "fast_sweep", "gust_operator", "face_gust_vector", "SAFETY"]  # (all but fast_sweep
# from cfd.sweep.basis)

log = logging.getLogger(__name__)

MAX_WORKERS = 64
"""Most worker processes :func:`fast_sweep` starts (``workers``): a fork-context ``ProcessPoolExecutor`` starts all of
them at its first task, each holding its own factorisations, so ``workers = 10**6`` would fork a million processes
at once."""


def _evaluate_inputs(basis, wf, gust, x_ref, inputs, pivot, caches, sel):
    """Every input's reduced outputs and estimates, shapes (p, m, K), the dual residuals (p, K) (input
    independent), and the worst ratio of estimate to allowance per frequency, shape (K,)."""
    out = [basis.evaluate(wf, gust, x_ref, caches[name], input=name, pivot=pivot) for name in inputs]
    y = np.stack([o[0][sel] for o in out], axis=1)
    est = np.stack([o[1][sel] for o in out], axis=1)
    scale = np.maximum(np.abs(y), 1e-3 * np.abs(y).max(axis=-1, keepdims=True)) + 1e-300
    return y, est, out[0][2][sel], (est / scale).max(axis=(0, 1))


ADAPT_MOMENTS = 2
MIN_MOMENTS = 8


def _plan_shifts(wf, ratio, tol, shifts, count, n_moments):
    """The next shifts of the greedy search and their Krylov block counts.

    The first is the frequency with the largest estimate over its allowance (as ever); each further one the
    worst failing frequency more than a factor 2 away from the chosen ones or beyond a shift between them, so
    that shifts factorised side by side do not serve the same frequencies. A shift's block count is
    ``ADAPT_MOMENTS`` per failing frequency between its neighbouring shifts, between ``MIN_MOMENTS`` and
    ``n_moments``.

    Parameters
    ----------
    wf : ndarray, shape (K,)
        Finite frequencies (U/c).
    ratio : ndarray, shape (K,)
        Worst estimate over allowance per frequency.
    tol : float
    shifts : sequence of float
        Existing shifts.
    count : int
        Shifts wanted.
    n_moments : int
        Most blocks per shift.

    Returns
    -------
    list of (float, int)
        ``(omega, blocks)`` per shift; empty when every failing frequency is a shift already.
    """
    bad = ratio > tol
    cand = np.where(bad, ratio, -np.inf)
    for s in shifts:  # never refactorise at an existing shift
        cand[np.isclose(wf, s, rtol=1e-12, atol=1e-14)] = -np.inf
    edges = np.asarray(sorted(shifts), float)
    plan = []
    while len(plan) < count and np.any(np.isfinite(cand)):
        j = int(np.argmax(cand))
        below, above = edges[edges < wf[j]], edges[edges > wf[j]]
        lo = below.max() if below.size else -np.inf
        hi = above.min() if above.size else np.inf
        gap = (wf > lo) & (wf < hi)
        blocks = min(n_moments, max(MIN_MOMENTS, ADAPT_MOMENTS * int(np.count_nonzero(bad & gap))))
        plan.append((float(wf[j]), blocks))
        near = gap if wf[j] == 0.0 else gap & (wf > 0.5 * wf[j]) & (wf < 2.0 * wf[j])
        cand[near] = -np.inf
        edges = np.sort(np.append(edges, wf[j]))
    return plan


def _greedy(basis, wf, gust, x_ref, inputs, pivot, caches, sel, tol, max_shifts, pool, progress, log_interval,
            t_start):
    """The greedy loop of :func:`fast_sweep`: evaluate, add shifts where the estimate fails, until ``tol``
    (as many per step as ``pool`` has worker processes, one without it).

    Returns the last evaluation ``(y, est, res, ratio)`` and the frequencies that missed ``tol`` with the reason.
    """
    added, t_log = 0, t_start
    per_step = 1 if pool is None else pool.workers
    missed, why = np.zeros(0), ""
    while True:
        y, est, res, ratio = _evaluate_inputs(basis, wf, gust, x_ref, inputs, pivot, caches, sel)
        bad = ratio > tol
        if progress is not None:
            progress(basis, float(ratio.max()), wf[bad])
        now = time.perf_counter()
        if now - t_log >= log_interval:
            t_log = now
            log.info("fast sweep: %d shift(s) (last at omega = %.4g), basis %d, worst estimate %.2e of the "
                     "allowance (tol %.0e), %d / %d frequencies above tol, %.0f s", len(basis.shifts),
                     basis.shifts[-1], basis.size, ratio.max(), tol, int(bad.sum()), wf.size,
                     now - t_start)
        if not np.any(bad):
            break
        if added >= max_shifts:
            missed, why = wf[bad], f"max_shifts = {max_shifts} used"
            break
        plan = _plan_shifts(wf, ratio, tol, basis.shifts, min(per_step, max_shifts - added), basis.n_moments)
        if not plan:
            missed, why = wf[bad], "every failing frequency is a shift already"
            break
        new = basis.add_shifts([w_ for w_, _ in plan], [k for _, k in plan], pool)
        added += len(plan)
        n_new = max(new)
        if n_new < 2 * len(basis.rows):  # the new shift's space is (nearly) in the basis already: the
            # remaining estimates are at the round-off floor
            y, est, res, ratio = _evaluate_inputs(basis, wf, gust, x_ref, inputs, pivot, caches, sel)
            missed = wf[ratio > tol]
            why = f"the basis stopped growing (round-off floor of the estimate, about {tol:g} here)"
            break
    return y, est, res, ratio, missed, why


def fast_sweep(lin, omega, gust="svm", outputs=("Cl", "Cm"), tol=1e-8, max_shifts=24, x_ref=0.0, T=None,
               basis=None, n_moments=16, progress=None, inputs=("gust",), pivot=0.25, log_interval=60.0,
               workers=1):
    """Frequency response to a gust and rigid motions over many frequencies from a few factorisations (see the
    module docstring).

    Parameters
    ----------
    lin : LinearSystem
    omega : array_like, shape (K,), or tuple (omega_d, omega)
        As :func:`cfd.lfd.lfd_response`: U/c units, ``>= 0``, ``inf`` allowed for the gust alone (feedthrough,
        no solve); the pair from ``sysid.mckelvey_grid`` is accepted and gives ``T``.
    gust : {"svm", "fvm"}
    outputs : sequence of {"Cl", "Cm", "Cd"}
    tol : float
        Target relative error of every output at every frequency and for every input: the estimate must satisfy
        ``est <= tol * max(|y(omega)|, 1e-3 max_omega |y|)``.
    max_shifts : int
        Budget of shifted factorisations in this call (the basis may already hold some).
    x_ref : float
        Gust reference point (chords).
    T : float, optional
        Sampling period for the discrete frequencies of the result.
    basis : SweepBasis, optional
        A basis from an earlier sweep of the same ``lin`` (and outputs); it is reused and extended in
        place. Without it a new one is built (pass one to reuse it for another ``T``).
    n_moments : int
        Most Krylov blocks per shift for a new basis: a shift gets ``ADAPT_MOMENTS`` (2) blocks per failing
        frequency between its neighbouring shifts, at least ``MIN_MOMENTS`` (8; fewer made the estimate fall
        below the true error on the coarse test case) and at most ``n_moments``.
    progress : callable, optional
        Called after every evaluation of the reduced model as ``progress(basis, worst, failing)``: ``worst``
        the largest ratio of the error estimate to its allowance (``<= tol`` when done), ``failing`` the
        frequencies above ``tol``. The last shift is ``basis.shifts[-1]`` (omega, U/c units) and the
        basis size ``basis.size``; one call per shift (the first after the first shift). Its return value is
        ignored; it does not change the result.
    log_interval : float
        Seconds between progress lines on the ``cfd.sweep`` logger (level INFO).
    inputs : sequence of {"gust", "plunge", "pitch"}
        As :func:`cfd.lfd.lfd_response`. The dual basis depends on the outputs only, so one basis serves every
        input: a motion's forcing ``b0 + i omega b1`` is two more projected vectors.
    pivot : float
        Pitch axis, chords from the leading edge.
    workers : int
        Shifts added per greedy step, factorised side by side in that many forked processes
        (:mod:`cfd.sweep.workers`); where a process cannot fork (e.g. inside a study worker), one shift per
        step in this process, as with 1. The basis differs from the one-process sweep (its shifts are chosen
        several at a time), the accuracy does not. Each worker holds one factorisation (about 0.5 GB on the
        181 x 60 grid). Measured on the paper grid (T2) on the 2-core machine: 1 worker 101 - 106 s, 2 workers
        65 - 70 s (docs/lfd-sweep.md).

    Returns
    -------
    sysid.FrequencyResponse
        As ``lfd_response``; ``metadata`` adds ``"method": "fast"``, ``"error_estimate"`` absolute, shape (p, K)
        for one input and (p, m, K) for several, ``"residual_norm"`` (p, K) relative dual residuals (the same
        for every input), ``"shifts"``, ``"basis_size"``, ``"tol"``.

    Raises
    ------
    LinearError
        Bad tolerance, ``workers``, frequencies (``inf`` with a motion input), gust, input or output names, a
        basis of another system, or ``lin`` not a ``LinearSystem``.
    SweepInterrupted
        A ``KeyboardInterrupt`` (Ctrl-C, or raised by ``progress``) during the sweep: re-raised as this subclass of
        ``KeyboardInterrupt``, carrying ``.basis`` with every factorisation made (``basis=e.basis`` goes on).

    Warns
    -----
    RuntimeWarning
        When ``tol`` is not met within ``max_shifts``; the message names the frequencies.
    """
    check_linear_system(lin)
    tol = check_tol(tol)
    check_gust_method(gust)
    names, rows = check_outputs(outputs)
    inputs = check_inputs(inputs)
    pivot = check_pivot(pivot)
    n_shifts = whole_number(max_shifts)
    if n_shifts is None or n_shifts < 1:
        raise LinearError(f"max_shifts must be a positive integer (factorisations allowed); got {max_shifts!r}")
    max_shifts = n_shifts
    if basis is not None and not isinstance(basis, SweepBasis):
        raise LinearError(f"basis must be a cfd.sweep.SweepBasis from an earlier sweep of this lin, or None; got "
                          f"{type(basis).__name__}")
    if progress is not None and not callable(progress):
        raise LinearError(f"progress must be a callable progress(basis, worst, failing) or None; got {progress!r}")
    if isinstance(log_interval, bool) or not isinstance(log_interval, (int, float, np.integer, np.floating)) or \
            not log_interval >= 0.0:
        raise LinearError(f"log_interval must be a number of seconds >= 0 (default 60); got {log_interval!r}")
    if isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or workers < 1:
        raise LinearError(f"workers must be a positive integer (processes for the shifts, 1: this one); got "
                          f"{workers!r}")
    if workers > MAX_WORKERS:
        raise LinearError(f"workers = {workers} is more than cfd.sweep.MAX_WORKERS = {MAX_WORKERS}: each worker is a "
                          "forked process holding its own factorisations, and all are started at once; use at most "
                          "the machine's cores (os.cpu_count())")
    w, T = frequency_grid(omega, T)
    x_ref = check_x_ref(x_ref)
    check_motion_frequencies(inputs, w)
    if basis is None:
        basis = SweepBasis(lin, names, n_moments=n_moments)
    elif basis.lin is not lin:
        raise LinearError("basis was built for another LinearSystem; build a new SweepBasis(lin)")
    if not set(names) <= set(basis.outputs):
        raise LinearError(f"basis holds outputs {basis.outputs}; it cannot give {names}: build a new SweepBasis")
    sel = [basis.outputs.index(o) for o in names]
    t_start = t_log = time.perf_counter()
    finite = np.isfinite(w)
    wf = w[finite]
    m = len(inputs)
    H = np.zeros((len(rows), m, w.size), complex)
    H[:, 0, ~finite] = lin.D[rows, 0][:, None]  # the gust alone reaches here (check_motion_frequencies)
    est_all = np.zeros((len(rows), m, w.size))
    res_all = np.zeros((len(rows), w.size))
    missed, why = np.zeros(0), ""
    if wf.size:
        if basis.size == 0:
            basis.add_shift(0.0 if wf.min() == 0.0 else float(wf.min()))
        caches = {name: {} for name in inputs}
        pool = shift_workers(basis, workers)
        try:
            y, est, res, ratio, missed, why = _greedy(basis, wf, gust, x_ref, inputs, pivot, caches, sel, tol,
                                                      max_shifts, pool, progress, log_interval, t_start)
        except KeyboardInterrupt as e:   # Ctrl-C or the progress callback: the factorisations made are kept
            raise SweepInterrupted(
                f"fast_sweep interrupted with {len(basis.shifts)} shifted factorisations in its basis (size "
                f"{basis.size}); continue with fast_sweep(..., basis=e.basis) (or lfd_response(..., basis=e.basis))",
                basis=basis) from e
        finally:
            if pool is not None:
                pool.close()
        H[:, :, finite] = y
        est_all[:, :, finite] = est
        res_all[:, finite] = res
    if missed.size:
        warnings.warn(
            f"fast_sweep: tol = {tol:g} not met within max_shifts = {max_shifts} at {missed.size} frequencies "
            f"(omega = {np.array2string(missed, precision=4, threshold=12)}): {why}; raise max_shifts or "
            "n_moments, loosen tol, or use method='direct' there", RuntimeWarning, stacklevel=2)
    meta = {"gust": gust, "x_ref": x_ref, "mach": lin.mach, "alpha_deg": lin.flow.alpha_deg,
            "grid": list(map(int, lin.grid.shape)), "method": "fast", "tol": tol,
            "error_estimate": (est_all[:, 0] if m == 1 else est_all).tolist(), "residual_norm": res_all.tolist(),
            "shifts": list(basis.shifts), "basis_size": int(basis.size),
            "tol_met": bool(missed.size == 0), "seconds": time.perf_counter() - t_start}
    if "pitch" in inputs:
        meta["pivot"] = pivot
    return FrequencyResponse.from_continuous(H, w, T, inputs=list(inputs), outputs=list(names), metadata=meta)
