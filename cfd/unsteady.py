"""Nonlinear time-domain gust response: the Euler equations with the gust, BDF2, chord-Newton per step.

Equations
---------
The same residual as everything else (``cfd.euler.residual``) with the gust of ``cfd.gust``: the face
velocities ``w = (0, -mach g)`` from the exact face averages ``g`` of ``v_g / U`` (both methods) and, for the
split velocity method, the source ``cfd.gust.svm_source`` evaluated with the **current** state. For a
vertical gust ``v_g(x - U s)`` the exact SVM source is ``rho (d v_g/dt + u d v_g/dx)`` in the y-momentum and
``v`` times that in the energy (``u``, ``v`` the disturbance velocity, which the conserved variables hold;
``div u_g = 0``), and ``svm_source`` evaluates exactly that when given the current state instead of the
steady one: the LTD (``cfd.ltd``) is this system linearised about the steady state, with no other change.
In solver time ``t = s / mach`` the semi-discrete system is ``V dq/dt + R(q, t) = 0``, marched by BDF2::

    F(x) = V (3 x - 4 q^n + q^{n-1}) / (2 h) + R(x, t^{n+1}) - R(q_bar, 0) = 0,    h = dt / mach

from rest (``q^{-1} = q^0 = q_bar``, the steady state, as the LTD; the gust front starts upstream of the
aerofoil's region of influence, ``x0 <= cfd.gust.X0_MAX``). The constant ``R(q_bar, 0)`` (the steady state's
own residual, of the order of the steady tolerance) is subtracted so that ``q_bar`` is an exact discrete
steady solution: without it the state would drift by ``J^-1 R(q_bar)`` during the march, which at gusts of
0.01 deg is not negligible against the response; ``info["steady_residual"]`` says how large it was.

Per step: inexact (chord) Newton
--------------------------------
``x <- x - M^-1 F(x)`` from the predictor ``x_0 = 2 q^n - q^{n-1}``, with ``M = 3 V / (2 h) + J`` factorised
once (``J`` the exact Jacobian of the steady state, ``cfd.jacobian``; nested dissection, ``cfd.linear``'s
checked ``factorise``). Each iteration costs one residual and one back-substitution. The step has converged
when ``|F(x)| <= max(rtol |F(x_0)|, atol r_free, 16 eps |3 V x / (2 h)|)`` (L2 norms over all cells and
variables; ``r_free`` the residual norm of the free stream on this grid, the reference of
``cfd.solve_steady``'s ``tol``; the last term is the round-off level of ``F``, whose largest term is the mass
term). When an
iteration does not cut ``|F|`` by ``stall_ratio`` (1/3), ``M`` is refactorised with the Jacobian at the
current iterate (gust face velocities and SVM source included) and that factorisation is kept for the
following steps. ``krylov=True`` solves each Newton correction by GMRES instead (matrix-free products
``J(x) v`` by complex step through the residual, ``M^-1`` as the preconditioner): fewer iterations at large
amplitudes, but each GMRES vector costs a complex residual and a back-substitution (2.6-3.3x the chord
iteration's cost in ``bench/unsteady_bench.py``).

Failures
--------
A step that does not converge in ``max_iter`` iterations and ``max_refactor`` refactorisations, a state with
non-positive density or pressure, or a local Mach number (total velocity, gust included) above
``max_local_mach`` raises a subclass of :class:`UnsteadyStepError` that names the step, the time and the
gust amplitude and carries the history so far (``.partial``); an interrupt (Ctrl-C) is re-raised as
:class:`cfd.errors.MarchInterrupted`, a ``KeyboardInterrupt`` that carries it the same way. A gust that raises
the peak local Mach number above ``separation_mach`` (1.3 by default: about the pre-shock Mach number at which a
turbulent boundary layer separates) and by more than 0.01 above its steady value gives a ``RuntimeWarning``: the
Euler equations cannot separate, so the response past that point is that of an attached flow that a real aerofoil
would not have. Measurements against the LTD and the cost: ``docs/nonlinear.md``.
"""

import logging
import math
import time
import warnings
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from .errors import (LocalMachError, MarchInterrupted, NonPhysicalStateError, UnsteadyError,  # noqa: F401 (re-exported)
                     UnsteadyStepError)
from .checks import callback, flag, log_interval as check_log_interval, whole_number
from .euler import residual
from .flow import FlowCondition, is_physical, primitive
from .frequencies import check_x_ref
from .gust import (OneMinusCosine, SharpEdged, SineGust, cell_x_gradient, check_gust_step, face_gust,
                   gust_face_velocity, svm_source, warn_unseen)
from .jacobian import H_STEP, jacobian
from .linear import METHODS, factorise, grid_permutation, wall_loads
from .ltd import LTDHistory, check_times, phase_error_estimate

__all__ = [
    "UnsteadyError",
    "UnsteadyStepError",
    "NonPhysicalStateError",
    "LocalMachError",
    "UnsteadyHistory",
    "unsteady_response",
    "MAX_SNAPSHOT_BYTES",
]

log = logging.getLogger(__name__)


@dataclass(frozen=True, eq=False, kw_only=True)  # its fields follow the base class defaults (h, alpha, pivot)
class UnsteadyHistory(LTDHistory):
    """Nonlinear gust response: an :class:`cfd.ltd.LTDHistory` (same fields, same meaning) with more fields.

    Attributes
    ----------
    t : ndarray, shape (n + 1,)
        Convective time ``s = t U / c``, from 0 (``n`` steps of ``dt``).
    u : ndarray, shape (n + 1,)
        Gust input ``v_g(x_ref, s) / U`` (dimensionless: the tangent of the local gust angle).
    cl, cm, cd : ndarray, shape (n + 1,)
        Load coefficient perturbations about the steady loads (``cm`` about the quarter chord, nose up
        positive; wind axes of the steady free stream), at the gust's amplitude, as the LTD's: compare
        ``cl / gust.amplitude`` with the LTD's ``cl / amplitude`` of the same gust shape at any angle.
    method : str
        ``"svm"`` or ``"fvm"``.
    dt : float
        Convective time step.
    q : ndarray, shape (4N,)
        Final state minus the steady state (solver units, flat order of ``cfd.linear``), as ``LTDHistory.q``.
    steady_loads : ndarray, shape (3,)
        Steady ``(Cl, Cm, Cd)``.
    amplitude_deg : float
        The gust's ``angle_deg``.
    iterations : ndarray of int, shape (n + 1,)
        Newton iterations per step (0 at ``t = 0``).
    residual : ndarray, shape (n + 1,)
        Final ``|F|`` per step over ``r_free`` (the free-stream residual norm of the grid).
    max_mach : ndarray, shape (n + 1,)
        Peak local Mach number in the field per step (velocity of the fluid, gust included).
    n_factorisations : int
        LU factorisations of the march (1 when nothing stalled).
    refactorised_at : tuple of int
        Steps at which the matrix was refactorised.
    snapshots : dict of float to ndarray, shape (ni-1, nj-1, 4)
        Full conserved state (solver units) at the requested times (rounded to the nearest step); export
        with ``cfd.export.write_vtk(grid, path, cfd.export.primitives(q, mach))``.
    complete : bool
        False for the partial history carried by an :class:`UnsteadyStepError`.
    h, alpha, pivot : None
        Inherited from :class:`cfd.ltd.LTDHistory`; None here: the nonlinear march prescribes no motion.
    info : dict
        ``wall_time``, ``t_jacobian``, ``t_factor``, ``t_solve``, ``t_residual`` (seconds), ``n_residual``,
        ``n_solve``, ``n_gmres``, ``steady_residual`` (``|R(q_bar)| / r_free``), ``steady_max_mach`` (peak local
        Mach number of the steady flow), ``r_free``, ``krylov``, ``rtol``, ``atol``.
    """

    steady_loads: np.ndarray
    amplitude_deg: float
    iterations: np.ndarray
    residual: np.ndarray
    max_mach: np.ndarray
    n_factorisations: int
    refactorised_at: tuple
    snapshots: dict = field(default_factory=dict)
    complete: bool = True
    info: dict = field(default_factory=dict)

    @property
    def cl_total(self):
        """Total lift coefficient, shape (n + 1,)."""
        return self.steady_loads[0] + self.cl

    @property
    def cm_total(self):
        """Total quarter-chord moment coefficient, shape (n + 1,)."""
        return self.steady_loads[1] + self.cm

    @property
    def cd_total(self):
        """Total (pressure) drag coefficient, shape (n + 1,)."""
        return self.steady_loads[2] + self.cd


MAX_SNAPSHOT_BYTES = 4 * 2**30
"""Most memory the full-state snapshots of :func:`unsteady_response` may take (``snapshot_times``, one state per
distinct step): 4 GiB, some 12 000 states of the paper grid."""


_SNAPSHOT_SLACK = 1e-9
"""Round-off allowed (in steps) on a snapshot time at either end of the march (``3 * 0.1`` for a ``t_end`` of 0.3)."""


def _check_input(gust, method, dt, t_end):
    if method not in METHODS:
        raise UnsteadyError(f"method must be one of {METHODS} (split or field velocity method); got {method!r}")
    if not isinstance(gust, (SineGust, OneMinusCosine, SharpEdged)):
        raise UnsteadyError(f"gust must be a cfd.SineGust, OneMinusCosine or SharpEdged; got {type(gust).__name__}")
    dt, t_end = check_times(dt, t_end, UnsteadyError)   # the LTD's step limit, cfd.ltd.MAX_STEPS, before any work
    check_gust_step(gust, dt, UnsteadyError)
    return dt, t_end


def _check_settings(rtol, atol, max_iter, stall_ratio, max_refactor, snapshot_times, max_phase_error,
                    max_local_mach, separation_mach, steady_tol, dt, t_end):
    """The iteration and monitoring settings of :func:`unsteady_response` (UnsteadyError naming the argument);
    returns ``snapshot_times`` as a list of floats."""
    def real(v):
        return isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, bool) and not np.isnan(v)

    for name, v, default in (("rtol", rtol, "1e-6"), ("atol", atol, "1e-12")):
        if not (real(v) and np.isfinite(v) and v >= 0.0):
            raise UnsteadyError(f"{name} must be a finite number >= 0 (default {default}); got {v!r}")
    if not (real(stall_ratio) and 0.0 < stall_ratio <= 1.0):
        raise UnsteadyError(f"stall_ratio must be a number in (0, 1] (default 1/3); got {stall_ratio!r}")
    for name, v, low, default in (("max_iter", max_iter, 1, 25), ("max_refactor", max_refactor, 0, 3)):
        n = whole_number(v, allow_inf=True)
        if n is None or n < low:
            raise UnsteadyError(f"{name} must be a whole number >= {low} (default {default}; inf: no limit); "
                                f"got {v!r}")
    for name, v, default in (("max_phase_error", max_phase_error, 0.01), ("max_local_mach", max_local_mach, 2.0),
                             ("separation_mach", separation_mach, 1.3), ("steady_tol", steady_tol, 1e-8)):
        if not (real(v) and v > 0.0):
            raise UnsteadyError(f"{name} must be a positive number (default {default}; inf turns the check off); "
                                f"got {v!r}")
    try:
        times = [float(s) for s in snapshot_times]
    except (TypeError, ValueError):
        times = None
    if times is None or not all(np.isfinite(times)):
        raise UnsteadyError(f"snapshot_times must be a sequence of finite convective times, e.g. (1.0, 2.5); got "
                            f"{snapshot_times!r}")
    end = max(t_end, round(t_end / dt) * dt)   # the march's last step (t_end = 0.37, dt = 0.1: 0.4)
    outside = [s for s in times if not -_SNAPSHOT_SLACK * dt <= s <= end + _SNAPSHOT_SLACK * dt]
    if outside:   # a time past the end was clamped to it: the state asked for was silently not stored
        raise UnsteadyError(f"snapshot_times must lie in the march, 0 <= s <= {end:g} (its last step); got "
                            f"{outside[0]!r}: give times inside it (or march to a later t_end)")
    return times


def _steady_state(sol, steady_tol):
    """grid, q_bar, flow, scheme of ``sol``; refuses a steady state that is not converged."""
    flow = getattr(sol, "flow", None)
    if flow is None:
        flow = FlowCondition(sol.mach, getattr(sol, "alpha_deg", 0.0))
    grid, scheme = sol.grid, getattr(sol, "scheme", None)
    q = np.asarray(sol.q, dtype=float)
    if q.shape != grid.cell_shape + (4,):
        raise UnsteadyError(f"sol.q has shape {q.shape}; its grid needs {grid.cell_shape + (4,)}")
    R0 = residual(grid, q, flow, scheme=scheme)
    free = np.broadcast_to(flow.q, q.shape)
    r_free = float(np.linalg.norm(residual(grid, free, flow, scheme=scheme)))
    drop = float(np.linalg.norm(R0)) / r_free
    if getattr(sol, "converged", True) is False or not drop <= steady_tol:
        raise UnsteadyError(
            f"the steady solution is not converged: |R(q)| / |R(free stream)| = {drop:.2e} > steady_tol = "
            f"{steady_tol:.0e}; the march would follow its drift, not the gust. Re-solve with "
            "cfd.solve_steady(..., tol=1e-10) (or pass it as q0 to continue)"
        )
    return grid, q, flow, scheme, R0, r_free, drop


def _cell_centres_x(grid):
    x = grid.x
    return 0.25 * (x[:-1, :-1] + x[1:, :-1] + x[:-1, 1:] + x[1:, 1:])


def _source_jacobian(q, mach, dgdx, gamma):
    """Block-diagonal ``d(-svm_source)/dq`` (the residual subtracts the source), by complex step per variable."""
    n = q.size
    cells = np.arange(n // 4)
    rows, cols, data = [], [], []
    for k in range(4):
        qc = q.astype(complex)
        qc[..., k] += 1j * H_STEP
        d = -svm_source(qc, mach, dgdx, gamma).imag.reshape(-1, 4) / H_STEP
        for r in (2, 3):  # only the y-momentum and energy sources
            rows.append(4 * cells + r)
            cols.append(4 * cells + k)
            data.append(d[:, r])
    return sp.csr_matrix((np.concatenate(data), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n))


def unsteady_response(sol, gust, dt, t_end, method="svm", x_ref=0.0, *, rtol=1e-6, atol=1e-12, max_iter=25,
                      stall_ratio=1.0 / 3.0, max_refactor=3, krylov=False, snapshot_times=(), progress=None,
                      log_interval=60.0, max_phase_error=0.01, max_local_mach=2.0, separation_mach=1.3,
                      steady_tol=1e-8):
    """Nonlinear Euler response to a gust (SVM or FVM), BDF2 in time, chord-Newton per step.

    See the module docstring for the equations and the iteration. The loads are perturbations about the steady
    loads, as in :func:`cfd.ltd_response`; at small amplitudes ``history.cl / gust.amplitude`` equals the LTD of
    the same gust divided by its amplitude (``docs/nonlinear.md``).

    Parameters
    ----------
    sol : SteadySolution
        Converged steady flow (``cfd.solve_steady``; anything with ``grid``, ``q`` of shape (ni-1, nj-1, 4),
        ``flow`` or ``mach`` and ``alpha_deg``, and optionally ``scheme``).
    gust : SineGust, OneMinusCosine or SharpEdged
        At its physical amplitude (``angle_deg``).
    dt : float
        Convective time step (chords / U), ``> 0``.
    t_end : float
        Final convective time, ``>= dt``; ``round(t_end / dt)`` steps.
    method : {"svm", "fvm"}
    x_ref : float
        Where the input signal ``u`` is measured (chords).
    rtol : float
        Convergence of a step: ``|F|`` below ``rtol`` times its value at the predictor, or below ``atol`` times
        the free-stream residual norm ``r_free``, or below the round-off level of ``F`` (the largest of the
        three).
    atol : float
        See ``rtol``.
    max_iter : int
        Newton iterations per step at most (over all its refactorisations).
    stall_ratio : float
        An iteration that multiplies ``|F|`` by more than this triggers a refactorisation at the current iterate.
    max_refactor : int
        Refactorisations per step at most before the step is declared failed.
    krylov : bool
        Newton corrections by preconditioned GMRES (matrix-free ``J(x) v``) instead of chord steps.
    snapshot_times : sequence of float
        Convective times at which to store the full state (nearest step), each in ``[0, t_end]``.
    progress : callable, optional
        ``progress(step, n_steps, t, iterations)`` after every step (``t`` convective, ``iterations`` of the
        step); its return value is ignored.
    log_interval : float
        Seconds between progress lines on the ``cfd.unsteady`` logger (level INFO).
    max_phase_error : float
        Warn when the BDF2 phase-rate error at the gust's frequency scale (``cfd.ltd.phase_error_estimate``)
        exceeds this.
    max_local_mach : float
        Stop with :class:`LocalMachError` when the local Mach number exceeds this anywhere.
    separation_mach : float
        Warn (once) when the gust raises the peak local Mach number above this (and 0.01 above its steady
        value): a viscous flow would separate behind the shock.
    steady_tol : float
        Refuse ``sol`` when ``|R(q_bar)| / r_free`` exceeds this.

    Returns
    -------
    UnsteadyHistory

    Raises
    ------
    UnsteadyError
        Unknown method, not a gust, bad ``dt`` or ``t_end``, more than ``cfd.ltd.MAX_STEPS`` steps or a ``t_end`` beyond
        ``cfd.ltd.MAX_TIME`` (refused before any work, as the LTD), a gust that passes in fewer than
        ``cfd.gust.MIN_GUST_STEPS`` steps, a ``krylov`` that is not a bool, a ``progress`` that is not callable, a
        negative ``log_interval``, snapshots of more than :data:`MAX_SNAPSHOT_BYTES` or at times outside ``[0, t_end]``,
        a non-finite ``x_ref``, a setting out of range (``rtol``, ``atol`` negative; ``max_iter``, ``max_refactor`` not
        whole numbers; ``stall_ratio`` outside (0, 1]; a limit or ``steady_tol`` not positive; any of them NaN), a
        non-converged ``sol``.
    UnsteadyStepError
        A step did not converge (``.partial`` holds the history so far); subclasses
        :class:`NonPhysicalStateError` (non-positive density or pressure) and :class:`LocalMachError`.
    MarchInterrupted
        A ``KeyboardInterrupt`` (Ctrl-C, or raised by ``progress``) during the march: re-raised as this subclass of
        ``KeyboardInterrupt``, with the history up to the last completed step in ``.partial`` (``complete`` False).

    Warns
    -----
    RuntimeWarning
        ``dt`` too large for the gust; a local Mach number above ``separation_mach``; a march that ends before the
        gust reaches ``x_ref``.
    """
    dt, t_end = _check_input(gust, method, dt, t_end)
    x_ref = check_x_ref(x_ref, UnsteadyError)
    snapshot_times = _check_settings(rtol, atol, max_iter, stall_ratio, max_refactor, snapshot_times,
                                     max_phase_error, max_local_mach, separation_mach, steady_tol, dt, t_end)
    krylov = flag("krylov", krylov, UnsteadyError)
    progress = callback("progress", progress, UnsteadyError)
    log_interval = check_log_interval(log_interval, UnsteadyError)
    warn_unseen(gust, t_end, x_ref)
    err = phase_error_estimate(gust, dt)
    if err > max_phase_error:
        warnings.warn(
            f"dt = {dt} gives an estimated BDF2 phase-rate error of {100 * err:.2g} % at the gust's frequency "
            f"scale (limit {100 * max_phase_error:.2g} %); reduce dt by {math.sqrt(err / max_phase_error):.2g}x",
            RuntimeWarning, stacklevel=2)
    grid, qbar, flow, scheme, R0, r_free, drop = _steady_state(sol, steady_tol)
    snap_steps = {int(round(s / dt)) for s in snapshot_times}   # (_check_settings keeps them within the march)
    if len(snap_steps) * qbar.nbytes > MAX_SNAPSHOT_BYTES:
        raise UnsteadyError(f"snapshot_times asks for {len(snap_steps)} full states of {qbar.nbytes / 2**20:.3g} MiB, "
                            f"{len(snap_steps) * qbar.nbytes / 2**30:.3g} GiB, more than MAX_SNAPSHOT_BYTES = "
                            f"{MAX_SNAPSHOT_BYTES / 2**30:g} GiB: keep the times you will look at (the loads are kept "
                            "at every step anyway)")
    march = _March(grid, qbar, flow, scheme, R0, r_free, gust, method, dt, rtol, atol, max_iter, stall_ratio,
                   max_refactor, krylov)
    march.info["steady_residual"] = drop
    n = int(round(t_end / dt))
    t = dt * np.arange(n + 1)
    loads = np.zeros((n + 1, 3))
    iters = np.zeros(n + 1, dtype=int)
    res = np.zeros(n + 1)
    mmax = np.zeros(n + 1)
    loads0 = wall_loads(grid, qbar, flow)
    loads[0] = loads0
    mmax[0] = march.local_mach(qbar, 0.0).max()
    steady_mach = float(march.local_mach(qbar, None).max())
    march.info["steady_max_mach"] = steady_mach
    snaps = {0.0: qbar.copy()} if 0 in snap_steps else {}
    q_prev, q = qbar, qbar
    done = (0, qbar)   # the last completed step and its state: what an interrupt keeps
    warned = False
    t_start = t_log = time.perf_counter()

    def history(k, complete, q_k):
        arrays = [t[:k + 1], gust.input(t[:k + 1], x_ref), *(loads[:k + 1] - loads0).T, iters[:k + 1],
                  res[:k + 1], mmax[:k + 1], (q_k - qbar).ravel()]
        arrays = [np.ascontiguousarray(a) for a in arrays]
        for a in arrays:
            a.setflags(write=False)
        info = dict(march.info, wall_time=time.perf_counter() - t_start, r_free=r_free, krylov=krylov, rtol=rtol,
                    atol=atol)
        return UnsteadyHistory(t=arrays[0], u=arrays[1], cl=arrays[2], cm=arrays[3], cd=arrays[4], method=method,
                               dt=dt, q=arrays[8], steady_loads=loads0, amplitude_deg=gust.angle_deg,
                               iterations=arrays[5], residual=arrays[6], max_mach=arrays[7],
                               n_factorisations=march.info["n_factor"], refactorised_at=tuple(march.refactored),
                               snapshots={s: v for s, v in snaps.items() if s <= t[k]}, complete=complete,
                               info=info)

    for k in range(1, n + 1):
        try:
            try:
                q_new, iters[k], res[k] = march.step(k, t[k], q, q_prev)
                m = march.local_mach(q_new, t[k])
                mmax[k] = m.max()
                if mmax[k] > max_local_mach:
                    i, j = np.unravel_index(np.argmax(m), m.shape)
                    raise LocalMachError(
                        f"step {k} (s = {t[k]:.4g}) of the {gust.angle_deg:g} deg gust: local Mach number "
                        f"{mmax[k]:.3f} at cell ({i}, {j}) exceeds max_local_mach = {max_local_mach:g}. A shock this "
                        "strong would separate a real boundary layer and is far outside the linear range; use a "
                        "smaller amplitude (or raise max_local_mach if this is meant)")
            except UnsteadyStepError as e:
                e.partial = history(k - 1, False, q)
                e.step, e.time, e.amplitude_deg = k, t[k], gust.angle_deg
                raise
            q_prev, q = q, q_new
            loads[k] = wall_loads(grid, q, flow)
            if k in snap_steps:
                snaps[float(t[k])] = q.copy()
            done = (k, q)
            if not warned and mmax[k] > separation_mach and mmax[k] > steady_mach + 0.01:
                warned = True
                warnings.warn(
                    f"the {gust.angle_deg:g} deg gust raises the peak local Mach number from {steady_mach:.3f} "
                    f"(steady) to {mmax[k]:.3f} at s = {t[k]:.3g}, above separation_mach = {separation_mach:g}: a "
                    "boundary layer would likely separate behind a shock this strong, which the Euler equations "
                    "cannot show. Look at history.max_mach (the pre-shock Mach number) and the shock position in "
                    "the snapshots; past that point the loads are those of an attached flow only", RuntimeWarning,
                    stacklevel=2)
            if progress is not None:
                progress(k, n, float(t[k]), int(iters[k]))
            now = time.perf_counter()
            if now - t_log >= log_interval:
                t_log = now
                log.info("unsteady %s: step %d / %d (s = %.3f), %d iterations, %d factorisations, %.0f s",
                         method, k, n, t[k], iters[k], march.info["n_factor"], now - t_start)
        except KeyboardInterrupt as e:
            k_done, q_done = done
            raise MarchInterrupted(
                f"the {gust.angle_deg:g} deg {method} gust response was interrupted at step {k} of {n}; the history "
                f"up to step {k_done} (s = {t[k_done]:.4g}) is in .partial", partial=history(k_done, False, q_done),
                step=k_done, time=float(t[k_done])) from e
    return history(n, True, q)


class _March:
    """The BDF2 step of :func:`unsteady_response` and its factorisation (state in shape (ni-1, nj-1, 4))."""

    def __init__(self, grid, qbar, flow, scheme, R0, r_free, gust, method, dt, rtol, atol, max_iter, stall_ratio,
                 max_refactor, krylov):
        self.grid, self.qbar, self.flow, self.scheme, self.R0 = grid, qbar, flow, scheme, R0
        self.gust, self.method, self.dt = gust, method, dt
        self.mach = flow.mach
        self.h = dt / flow.mach
        self.rtol, self.floor, self.max_iter = rtol, atol * r_free, max_iter
        self.r_free = r_free
        self.stall_ratio, self.max_refactor, self.krylov = stall_ratio, max_refactor, krylov
        self.V = grid.area[..., None]
        self.diag = np.broadcast_to(1.5 * self.V / self.h, qbar.shape).ravel()
        self.perm = grid_permutation(grid)
        self.xc = _cell_centres_x(grid)
        self.refactored = []
        self.info = {"t_jacobian": 0.0, "t_factor": 0.0, "t_solve": 0.0, "t_residual": 0.0, "n_factor": 0,
                     "n_residual": 0, "n_solve": 0, "n_gmres": 0}
        self._factorise(qbar, None)

    def _forcing(self, s):
        """Face velocities and SVM cell gradient of the gust at convective time ``s``."""
        gi, gj = face_gust(self.grid, self.gust, s)
        return gust_face_velocity(gi, gj, self.mach), cell_x_gradient(self.grid, gi, gj)

    def _residual(self, x, w, dgdx):
        """``R(x, gust) - R(q_bar, 0)`` (real or complex ``x``)."""
        src = svm_source(x, self.mach, dgdx, self.flow.gamma) if self.method == "svm" else None
        return residual(self.grid, x, self.flow, face_velocity=w, source=src, scheme=self.scheme) - self.R0

    def _factorise(self, x, forcing):
        t0 = time.perf_counter()
        w = None if forcing is None else forcing[0]
        J = jacobian(self.grid, x, self.flow, face_velocity=w, scheme=self.scheme)
        if forcing is not None and self.method == "svm":
            J = J + _source_jacobian(x, self.mach, forcing[1], self.flow.gamma)
        t1 = time.perf_counter()
        self.J = J
        self.solve, _ = factorise(J + sp.diags(self.diag), self.perm)
        self.info["t_jacobian"] += t1 - t0
        self.info["t_factor"] += time.perf_counter() - t1
        self.info["n_factor"] += 1

    def local_mach(self, q, s):
        """Local Mach number of the fluid velocity (disturbance plus the gust at ``s``; none if ``s`` is None)."""
        rho, u, v, p = primitive(q, self.flow.gamma)
        if s is not None:
            v = v + self.mach * self.gust.velocity(self.xc, s)
        return np.hypot(u, v) / np.sqrt(self.flow.gamma * np.maximum(p, 1e-300) / rho)

    def _correction(self, x, F, fun):
        t0 = time.perf_counter()
        if not self.krylov:
            d = -self.solve(F.ravel())
            self.info["n_solve"] += 1
        else:
            n = F.size

            def jv(v):  # J(x) v by complex step through the residual (exact, no cancellation)
                self.info["n_gmres"] += 1
                return fun(x + 1j * H_STEP * v.reshape(x.shape)).imag.ravel() / H_STEP

            A = spla.LinearOperator((n, n), matvec=jv, dtype=float)
            P = spla.LinearOperator((n, n), matvec=lambda r: self.solve(r), dtype=float)
            d, _ = spla.gmres(A, -F.ravel(), M=P, rtol=1e-2, atol=0.0, restart=10, maxiter=1)
        self.info["t_solve"] += time.perf_counter() - t0
        return d.reshape(x.shape)

    def step(self, k, s, q, q_prev):
        """One BDF2 step to convective time ``s``; returns ``(q_new, iterations, |F| / r_free)``."""
        forcing = self._forcing(s)
        w, dgdx = forcing
        rhs = self.V * (4.0 * q - q_prev) / (2.0 * self.h)

        def fun(x):
            return 1.5 * self.V * x / self.h - rhs + self._residual(x, w, dgdx)

        def evaluate(x):
            t0 = time.perf_counter()
            with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
                F = fun(x)
            self.info["t_residual"] += time.perf_counter() - t0
            self.info["n_residual"] += 1
            return F, float(np.linalg.norm(F))

        x = 2.0 * q - q_prev
        if not is_physical(x, self.flow.gamma):
            x = q
        F, r = evaluate(x)
        norms = [r]
        if not math.isfinite(r):   # NaN > target is False: the step was accepted at its predictor, NaN and all
            self._fail(NonPhysicalStateError, k, s, norms,
                       "the residual at the step's predictor is not finite (the gust's forcing or the state "
                       "overflowed); reduce the amplitude or dt")
        # Round-off level of F: its largest term is the mass term 3 V x / (2 h).
        roundoff = 16.0 * np.finfo(float).eps * float(np.linalg.norm(1.5 * self.V * x / self.h))
        target = max(self.rtol * r, self.floor, roundoff)
        n_refactor = 0
        iters = 0
        fresh = False  # is the factorisation at the current iterate?
        while r > target:
            if iters >= self.max_iter:
                self._fail(UnsteadyStepError, k, s, norms, f"no convergence in {self.max_iter} iterations")
            iters += 1
            x_new = x + self._correction(x, F, fun)
            ok = is_physical(x_new, self.flow.gamma)
            if ok:
                F_new, r_new = evaluate(x_new)
                ok = math.isfinite(r_new)
            norms.append(r_new if ok else math.nan)
            if ok and r_new < r:  # progress: take it
                x, F, r_old, r = x_new, F_new, r, r_new
                fresh = False
                if r <= target or r <= self.stall_ratio * r_old:
                    continue
            elif not ok and (fresh or n_refactor >= self.max_refactor):
                self._fail(NonPhysicalStateError, k, s, norms,
                           "the Newton iterate has non-positive density or pressure (or NaN) even with a fresh "
                           "Jacobian: the gust is too strong for this grid and time step; reduce the amplitude "
                           "or dt")
            # Stalled, diverged or non-physical: refactorise at the best iterate (x) and go on.
            if fresh and not r_new < r:
                self._fail(UnsteadyStepError, k, s, norms,
                           "|F| did not fall even with the Jacobian at the current iterate (Newton's method is "
                           "outside its range: reduce dt or the amplitude)")
            if n_refactor >= self.max_refactor:
                self._fail(UnsteadyStepError, k, s, norms,
                           f"stalled after {n_refactor} refactorisations (|F| ratio above {self.stall_ratio:.2g}; "
                           "reduce dt or the amplitude, or allow more with max_refactor)")
            n_refactor += 1
            self.refactored.append(k)
            self._factorise(x, forcing)
            fresh = True
        return x, iters, r / self.r_free

    def _fail(self, kind, k, s, norms, why):
        raise kind(
            f"step {k} (s = {s:.4g}) of the {self.gust.angle_deg:g} deg {self.method} gust response failed: {why}. "
            f"|F| per iteration: {', '.join(f'{v:.2e}' for v in norms)} (target "
            f"max({self.rtol:.0e} x first, {self.floor:.2e})). The history up to step {k - 1} is in .partial",
            history=np.array(norms))

