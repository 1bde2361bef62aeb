"""Steady Euler solutions: Runge-Kutta start, then Newton with pseudo-transient continuation.

Strategy ``"classic"``
----------------------
1. ``n_rk`` steps of Jameson's 5-stage scheme (stage coefficients 1/4, 1/6, 3/8, 1/2, 1; the full
   residual, dissipation included, is re-evaluated at every stage) with local time steps
   ``dt = cfl_rk * area / sum(|u.S| + c|S|)`` from the free stream: this washes out the start-up
   transient cheaply.
2. Pseudo-transient continuation: ``(area / dt + J) dq = -R`` with the exact Jacobian ``J``
   (``cfd.jacobian``), local ``dt`` from a CFL number that grows as the residual falls (switched
   evolution relaxation, ``cfl = max(growth cfl, cfl0 (|R_0| / |R|)^1.5)`` after a full step that lowered
   the residual, at most ten times the last one, capped at ``cfl_max``) until the step is Newton's. A
   step is scaled back so that no cell's density or pressure changes by more than ``max_change``
   (50 %); a step that makes them non-positive or multiplies the residual by more than ``max_rise`` is
   rejected and retried from the same state with a quarter of the CFL number (the Jacobian is kept,
   only the diagonal changes). If the CFL number falls below ``cfl_min`` that way, 100 RK5 steps move
   the state on and the continuation restarts (at most three times). Linear systems are solved by SuperLU (``scipy.sparse.linalg.splu``) on a
   geometric nested-dissection ordering (``cfd.ordering``) without row pivoting (the pseudo-time
   diagonal keeps the pivots safe): on the 181 x 60 grid about 20x fill against 33x for COLAMD with
   partial pivoting, and 2.7x faster (bench/steady_bench.py); if that
   factorisation fails, COLAMD with partial pivoting is used.

Strategy ``"chord"`` (the default; ``strategy="classic"`` is the one above, kept for comparison)
-------------------------------------------------------------------------------------------------
The same continuation, cheaper: 200 RK steps instead of 500 (they cost about 1.5 factorisations' worth on
the paper grid), CFL growth x3 instead of x2, and after every accepted step **chord steps** with the frozen
factorisation (``dq = -(area/dt + J_old)^-1 R(q)``: one back-substitution, about 1/20 of a factorisation,
and one residual each), accepted while they lower the residual and repeated while each cuts it by at least
``chord_ratio`` (at most ``max_chord``). A step that is not admissible is first shortened along the same
direction (x1/4, twice) before the CFL number is cut and the matrix refactorised. With ``q0`` (a warm start
from a neighbouring converged flow) there is no RK start and the continuation starts at CFL 1000. Measured
side by side on T1-T6 (bench/steady_bench.py, docs/validation.md section 7): 4-6 factorisations and 6.3-9.0
LUs' worth of wall time against 9-13 and 12.6-18.6, the same solutions to 1e-11; warm starts (alpha + 0.1
deg, Mach - 0.01) in 1-6 factorisations.

Convergence is measured by the L2 norm of ``R`` over all cells and variables; the solver stops when it
falls by ``tol`` from its value for the free stream (the history's first entry when starting from it;
with ``q0`` the free-stream residual is evaluated once for the reference).
"""

import logging
import math
import time
import warnings
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from .checks import (callback, flag, kind_of, log_interval as check_log_interval, not_a_grid, real_array,
                     real_number, whole_number)
from .superlu import splu_nested, splu_pivoted
from .errors import ConvergenceError, FlowConditionError, MeshError, SolveInterrupted
from .euler import DEFAULT_SCHEME, Scheme, residual as _euler_residual, spectral_radius_sum
from .flow import LOW_MACH, NON_PHYSICAL, FlowCondition, is_physical, primitive
from .jacobian import jacobian
from .loads import force_coefficients, wall_cp
from .mesh import Grid
from .mesh.generation import MIN_FARFIELD
from .ordering import nested_dissection, unknown_permutation

__all__ = ["SteadySolution", "solve_steady", "factorise"]

log = logging.getLogger(__name__)

RK5 = (1.0 / 4.0, 1.0 / 6.0, 3.0 / 8.0, 1.0 / 2.0, 1.0)
_NEW = {"n_rk": 200, "cfl0": 10.0, "growth": 3.0, "cfl0_warm": 1e3}


@dataclass(frozen=True, eq=False)
class SteadySolution:
    """A converged steady Euler solution and its loads.

    Attributes
    ----------
    grid : Grid
    q : ndarray, shape (ni-1, nj-1, 4)
        Conserved variables per cell (nondimensional, see ``cfd.flow``).
    mach, alpha_deg, gamma : float
    cl, cd, cm : float
        Wind-axis lift and drag, pitching moment about the quarter chord (nose up positive).
    x_wall : ndarray, shape (n_surface,)
        Chordwise position of the wall faces.
    cp : ndarray, shape (n_surface,)
        Wall pressure coefficient.
    history : ndarray, shape (iterations + 1,)
        L2 norm of the residual per iteration (RK steps, then accepted Newton and chord steps).
    iterations : int
    converged : bool
    scheme : Scheme
    info : dict
        Solver statistics: timings (``t_rk``, ``t_jacobian``, ``t_factor``, ``t_solve``, ``wall_time``),
        counts (``newton_steps``, ``n_factor``, ``n_solve`` back-substitutions, ``n_chord`` accepted chord
        steps, ``n_jacobian``, ``n_residual``), ``fill``, ``strategy``, ``relative_drop``.
    """

    grid: Grid
    q: np.ndarray
    mach: float
    alpha_deg: float
    gamma: float
    cl: float
    cd: float
    cm: float
    x_wall: np.ndarray
    cp: np.ndarray
    history: np.ndarray
    iterations: int
    converged: bool
    scheme: object = DEFAULT_SCHEME
    info: dict = field(default_factory=dict)

    @property
    def flow(self):
        """The ``FlowCondition`` of this solution."""
        return FlowCondition(self.mach, self.alpha_deg, self.gamma)

    def fields(self):
        """Primitive fields per cell.

        Returns
        -------
        dict of ndarray, shape (ni-1, nj-1)
            ``rho``, ``u``, ``v``, ``p`` (nondimensional: a_inf = 1, rho_inf = 1) and ``mach``.
        """
        rho, u, v, p = primitive(self.q, self.gamma)
        c = np.sqrt(self.gamma * p / rho)
        return {"rho": rho, "u": u, "v": v, "p": p, "mach": np.hypot(u, v) / c}


def factorise(A, perm=None):
    """Sparse LU of ``A`` (csr or csc), nested dissection without pivoting, COLAMD as a fallback.

    Parameters
    ----------
    A : scipy.sparse matrix, shape (n, n)
    perm : ndarray of int, shape (n,), optional
        Symmetric fill-reducing permutation (``cfd.ordering``); if None, COLAMD with pivoting.

    Returns
    -------
    solve : callable
        ``solve(b)`` with ``b`` shape (n,) or (n, k).
    fill : float
        ``nnz(L + U) / nnz(A)``.
    """
    if perm is not None:
        Ap = sp.csr_matrix(A)[perm][:, perm].tocsc()
        try:
            lu = splu_nested(Ap)
            inv = np.empty_like(perm)
            inv[perm] = np.arange(perm.size)

            def solve(b):
                return lu.solve(b[perm])[inv]

            x = solve(np.ones(A.shape[0]))
            if np.all(np.isfinite(x)):
                return solve, (lu.L.nnz + lu.U.nnz) / A.nnz
        except RuntimeError:
            pass
    lu = splu_pivoted(A)
    return lu.solve, (lu.L.nnz + lu.U.nnz) / A.nnz


def _positive(q, gamma):
    return is_physical(q, gamma)


STRATEGIES = ("classic", "chord")


def _positive_setting(name, value, hint, upper=None):
    """``value`` as a float, or :class:`FlowConditionError` unless it is a finite number in ``(0, upper)``."""
    v = real_number(value)   # None for a bool and for text ("2.5" was parsed)
    if v is None or not (math.isfinite(v) and v > 0.0 and (upper is None or v < upper)):
        span = "positive and finite" if upper is None else f"a number in (0, {upper:g})"
        raise FlowConditionError(f"{name} must be {span} ({hint}); got {value!r}")
    return v


def _count_setting(name, value, hint, allow_inf=False):
    """``value`` as an int (or inf, a limit that never binds, with ``allow_inf``), or :class:`FlowConditionError`
    unless it is a whole number ``>= 0`` (``100.0`` is one)."""
    n = whole_number(value, allow_inf)
    if n is None or n < 0:
        raise FlowConditionError(f"{name} must be a whole number >= 0 ({hint}); got {value!r}")
    return n


def _check_continuation(cfl_rk, cfl_max, growth, cfl_min, max_change, max_rise, chord_ratio):
    """The CFL continuation and step-control settings of :func:`solve_steady`, checked before any work
    (``FlowConditionError``; ``cfl_rk = -1`` diverged after 90 Runge-Kutta steps, ``chord_ratio = 5`` was taken)."""
    _positive_setting("cfl_rk", cfl_rk, "CFL number of the Runge-Kutta start, e.g. 2.5")
    if not (isinstance(cfl_max, (int, float, np.integer, np.floating)) and not isinstance(cfl_max, bool)
            and cfl_max > 0.0):
        raise FlowConditionError(f"cfl_max must be a positive number (the cap of the CFL continuation, default 1e10; "
                                 f"inf: no cap); got {cfl_max!r}")
    if growth is not None:
        _positive_setting("growth", growth, "CFL factor after a good step, at least 1, e.g. 3")
        if growth < 1.0:
            raise FlowConditionError(f"growth = {growth} would lower the CFL number after every good step; give a "
                                     "factor >= 1 (e.g. 3), or None for the strategy's default")
    _positive_setting("cfl_min", cfl_min, "the smallest CFL number tried, e.g. 0.01")
    _positive_setting("max_change", max_change, "the largest relative change of density or pressure per step, "
                      "e.g. 0.5")
    _positive_setting("max_rise", max_rise, "the residual factor that rejects a step, e.g. 2")
    if isinstance(chord_ratio, bool) or not isinstance(chord_ratio, (int, float, np.integer, np.floating)) \
            or not 0.0 <= chord_ratio <= 1.0:
        raise FlowConditionError(f"chord_ratio must be a number in [0, 1] (the residual factor each chord step must "
                                 f"reach, e.g. 0.5; 0: no further chord steps); got {chord_ratio!r}")


def _check_settings(tol, scheme, strategy, n_rk, cfl0, max_newton, max_chord):
    """The solver settings of :func:`solve_steady`, checked before any work (``FlowConditionError``)."""
    tol = _positive_setting("tol", tol, "the required fall of the residual, e.g. 1e-10", upper=1.0)
    if not isinstance(scheme, Scheme):
        raise FlowConditionError(f"scheme must be a cfd.Scheme (or None for the default); got {scheme!r}")
    for name in ("k2", "k4"):
        k = getattr(scheme, name)
        if isinstance(k, bool) or not isinstance(k, (int, float, np.integer, np.floating)) or not (
                math.isfinite(k) and k >= 0.0):
            raise FlowConditionError(f"scheme.{name} must be a finite number >= 0 (default "
                                     f"{getattr(DEFAULT_SCHEME, name):g}); got {k!r}")
    if not isinstance(strategy, str) or strategy not in STRATEGIES:
        raise FlowConditionError(f"strategy must be one of {STRATEGIES}; got {strategy!r}")
    if n_rk is not None:
        n_rk = _count_setting("n_rk", n_rk, "Runge-Kutta start-up steps, or None for the strategy's default")
    if cfl0 is not None:
        cfl0 = _positive_setting("cfl0", cfl0, "CFL number of the first Newton step, e.g. 10, or None for the "
                                 "strategy's default")
    max_newton = _count_setting("max_newton", max_newton, "Newton steps allowed, e.g. 100", allow_inf=True)
    max_chord = _count_setting("max_chord", max_chord, "chord steps per factorisation, e.g. 30", allow_inf=True)
    return tol, n_rk, cfl0, max_newton, max_chord


def solve_steady(grid, mach, alpha_deg, *, gamma=1.4, tol=1e-10, scheme=None, q0=None, n_rk=None, cfl_rk=2.5,
                 cfl0=None, cfl_max=1e10, growth=None, cfl_min=0.01, max_change=0.5, max_rise=2.0, max_newton=100,
                 strategy="chord", chord_ratio=0.5, max_chord=30, verbose=False, progress=None,
                 log_interval=60.0):
    """Steady Euler flow about the aerofoil of ``grid``.

    Parameters
    ----------
    grid : Grid
        C-grid (``cfd.c_grid`` or ``cfd.grid_from_nodes``).
    mach : float
        Free-stream Mach number, ``0 < mach < 1``.
    alpha_deg : float
        Incidence, degrees.
    gamma : float
        Ratio of specific heats.
    tol : float
        Required fall of the residual L2 norm relative to the free-stream residual (also when ``q0`` is
        given).
    scheme : Scheme, optional
        Dissipation constants (``cfd.euler.Scheme``).
    q0 : ndarray, shape (ni-1, nj-1, 4), optional
        Initial state (free stream if None; then the RK start is skipped if ``n_rk = 0``).
    n_rk : int, optional
        Runge-Kutta start-up steps (default: see ``strategy``).
    cfl_rk, cfl0, cfl_max : float
        CFL numbers of the RK steps, of the first Newton step (default: see ``strategy``), and the cap of
        the continuation.
    growth : float, optional
        CFL factor after a full step that lowered the residual (halved after a step that raised it).
    cfl_min : float
        Smallest CFL number tried before giving up.
    max_change : float
        Largest relative change of density or pressure in any cell per step; longer steps are scaled
        back.
    max_rise : float
        A step that multiplies the residual norm by more than this (or makes density or pressure
        non-positive) is rejected and retried with a quarter of the CFL number.
    max_newton : int
        Newton / pseudo-transient steps allowed (rejected steps included; chord steps not counted).
    strategy : {"chord", "classic"}
        ``"chord"`` (default): chord steps with the frozen factorisation, backtracking before a new one,
        200 RK steps, growth 3, and with ``q0`` no RK start and ``cfl0 = 1000``. ``"classic"``: one
        factorisation per step, 500 RK steps, growth 2, cfl0 10 (the solver before 2026-12). ``n_rk``,
        ``cfl0`` and ``growth`` given explicitly override either strategy's defaults.
    chord_ratio : float
        Chord steps go on while each multiplies the residual norm by at most this.
    max_chord : int
        Chord steps per factorisation at most.
    verbose : bool
        Print the residual per Newton step.
    progress : callable, optional
        ``progress(step, residual, relative, cfl)`` after the Runge-Kutta start (``step = 0``, ``cfl`` the RK
        CFL number ``cfl_rk``) and after every Newton / pseudo-transient step (``step = 1, 2, ...``, rejected
        steps included, as ``max_newton`` counts them; ``cfl`` the CFL number the step was taken with, up to
        ``cfl_max``): ``residual`` the L2 norm of the residual of the current state (after the step's
        chord steps), ``relative`` that over the free stream's (the solve ends when it falls to ``tol``). Its
        return value is ignored; it does not change the solution.
    log_interval : float
        Seconds between progress lines on the ``cfd.steady`` logger (level INFO).

    Returns
    -------
    SteadySolution

    Raises
    ------
    FlowConditionError
        Mach out of [0.01, 1) (``cfd.flow.MIN_MACH``; a ``RuntimeWarning`` below 0.1), NaN or infinite input, or
        a ``q0`` not real (complex, text) or non-physical (NaN, inf, non-positive density or pressure); a bad setting: ``tol`` not in (0, 1), ``cfl0``, ``cfl_rk``, ``cfl_min``,
        ``max_change`` or ``max_rise`` not positive and finite, ``cfl_max`` not positive, ``growth`` below 1,
        ``chord_ratio`` not in [0, 1], ``n_rk``, ``max_newton`` or ``max_chord`` not a whole number >= 0,
        ``scheme`` not a ``cfd.Scheme`` with finite non-negative constants, an unknown ``strategy``, ``verbose``
        not a bool, ``progress`` not callable, ``log_interval`` negative.
    MeshError
        ``grid`` is not a :class:`cfd.Grid`.
    ConvergenceError
        If the iteration diverges (non-finite or non-physical state) or stalls before ``tol``; carries
        ``.history``.
    SolveInterrupted
        A ``KeyboardInterrupt`` (Ctrl-C, or raised by ``progress``) during the solve: re-raised as this subclass of
        ``KeyboardInterrupt``, carrying the last accepted state ``.q`` (``solve_steady(..., q0=e.q)`` goes on from
        it) and ``.history``.
    """
    flow = FlowCondition(mach, alpha_deg, gamma)
    gamma = flow.gamma  # the checked float (FlowCondition accepts any real number, e.g. numpy scalars)
    if flow.mach < LOW_MACH:
        warnings.warn(f"mach = {flow.mach:g} is below {LOW_MACH}: the scheme's low-Mach dissipation raises the "
                      "stagnation pressure and adds spurious drag (NACA 0012, paper grid: stagnation Cp 1.07 and 7 "
                      "drag counts at M = 0.05, 1.52 and 48 counts at M = 0.01; lift within about 1 %; "
                      "cfd.flow.MIN_MACH)", RuntimeWarning, stacklevel=2)
    scheme = DEFAULT_SCHEME if scheme is None else scheme
    tol, n_rk, cfl0, max_newton, max_chord = _check_settings(tol, scheme, strategy, n_rk, cfl0, max_newton,
                                                             max_chord)
    _check_continuation(cfl_rk, cfl_max, growth, cfl_min, max_change, max_rise, chord_ratio)
    verbose = flag("verbose", verbose, FlowConditionError)
    progress = callback("progress", progress, FlowConditionError)
    log_interval = check_log_interval(log_interval, FlowConditionError)
    chord = strategy == "chord"
    warm = chord and q0 is not None  # a neighbouring converged flow: no RK start, Newton at once
    if n_rk is None:
        n_rk = 0 if warm else _NEW["n_rk"] if chord else 500
    if cfl0 is None:
        cfl0 = _NEW["cfl0_warm"] if warm else _NEW["cfl0"] if chord else 10.0
    if growth is None:
        growth = _NEW["growth"] if chord else 2.0
    if not isinstance(grid, Grid):
        raise MeshError(not_a_grid(grid))
    reach = float(np.hypot(grid.x[:, -1] - 0.5, grid.y[:, -1]).min())   # the outer j-line from mid-chord
    if reach < MIN_FARFIELD:
        warnings.warn(f"the grid's far-field boundary comes within {reach:.3g} chords of mid-chord; the far-field "
                      f"condition takes the free stream there, so the loads will be off: use at least "
                      f"{MIN_FARFIELD:g} chords (c_grid's minimum; the paper's grid has 25)", RuntimeWarning,
                      stacklevel=2)
    t_start = time.perf_counter()
    area = grid.area[..., None]
    if q0 is None:
        q = np.broadcast_to(flow.q, grid.cell_shape + (4,)).copy()
    else:
        q = real_array(q0)   # a complex q0 lost its imaginary part with only a ComplexWarning
        if q is None:
            raise FlowConditionError(f"q0 must be an array of real conserved states (rho, rho u, rho v, rho E per "
                                     f"cell); got {kind_of(q0)}: pass a converged solution's q (real), or q0=None "
                                     "for the free stream")
        q = q.copy()
        if q.shape != grid.cell_shape + (4,):
            raise MeshError(f"q0 has shape {q.shape}; this grid needs {grid.cell_shape + (4,)}")
        if not _positive(q, gamma):
            raise FlowConditionError(
                f"q0 {NON_PHYSICAL}; start from the free stream (q0=None) or from a converged solution's q"
            )
    history = []
    info = {"t_jacobian": 0.0, "t_factor": 0.0, "t_solve": 0.0, "n_factor": 0, "n_solve": 0, "n_jacobian": 0,
            "n_residual": 0, "n_chord": 0, "t_rk": 0.0, "fill": None, "strategy": strategy}

    def residual(grid, q, flow, scheme):  # counted
        info["n_residual"] += 1
        return _euler_residual(grid, q, flow, scheme=scheme)

    def norm(R):
        return float(np.sqrt(np.sum(R * R)))

    def fail(why, advice="Try a smaller cfl0, more RK steps (n_rk) or a finer / smoother grid."):
        raise ConvergenceError(
            f"steady solve at M={mach}, alpha={alpha_deg} deg failed: {why}; residual history has "
            f"{len(history)} entries (last {history[-1]:.3e}). {advice}",
            history=np.array(history),
        )

    R = residual(grid, q, flow, scheme=scheme)
    r0 = norm(R)
    history.append(r0)
    if not np.isfinite(r0):
        fail("the initial residual is not finite")
    # The drop is measured from the free stream's residual, whatever the initial state, so that a
    # near-converged q0 does not ask for a fall below round-off.
    r_free = r0 if q0 is None else norm(residual(grid, np.broadcast_to(flow.q, q.shape).copy(), flow, scheme=scheme))
    target = tol * r_free if r_free > 0 else 0.0
    t_log = t_start

    def report(step, cfl_step):
        """``progress`` and the throttled log line after a step (see ``progress`` and ``log_interval``)."""
        nonlocal t_log
        r = history[-1]
        rel = r / r_free if r_free > 0 else 0.0
        if progress is not None:
            progress(step, r, rel, float(cfl_step))
        now = time.perf_counter()
        if now - t_log >= log_interval:
            t_log = now
            log.info("steady M=%g alpha=%g deg: step %d, |R| %.3e (%.2e of the free stream's, target %.0e), "
                     "CFL %.3g, %d factorisations, %.0f s", mach, alpha_deg, step, r, rel, tol, cfl_step,
                     info["n_factor"], now - t_start)

    def rk_steps(q, n):
        R = None
        for it in range(n):
            dt = (cfl_rk / spectral_radius_sum(grid, q, flow))[..., None]
            qs = q
            with np.errstate(invalid="ignore", divide="ignore", over="ignore"):  # failure is checked below
                for a in RK5:
                    qs = q - a * dt * residual(grid, qs, flow, scheme=scheme)
                q = qs
                R = residual(grid, q, flow, scheme=scheme)
            history.append(norm(R))
            if not (np.isfinite(history[-1]) and _positive(q, gamma)):
                # the advice was the Newton stage's (a smaller cfl0) also when cfl_rk = 1e6 diverged at step 1
                fail(f"Runge-Kutta steps diverged at step {it + 1} (cfl_rk = {cfl_rk:g})",
                     "Try a smaller cfl_rk (default 2.5) or a finer / smoother grid.")
            if history[-1] <= target:
                break
        return q, R

    n_newton = 0
    try:
        # 1. Runge-Kutta start.
        if n_rk > 0:
            t0 = time.perf_counter()
            q, R = rk_steps(q, n_rk)
            info["t_rk"] += time.perf_counter() - t0
            report(0, cfl_rk)

        # 2. Newton with pseudo-transient continuation.
        perm = unknown_permutation(nested_dissection(grid))
        rn = history[-1]
        r_ref = rn
        cfl = cfl0
        n_newton = 0
        n_escape = 0
        n_rk_escape = 100
        J = None
        solve = None
        while history[-1] > target:
            if n_newton >= max_newton:
                fail(f"no convergence in {max_newton} Newton steps")
            n_newton += 1
            t0 = time.perf_counter()
            if J is None:
                J = jacobian(grid, q, flow, scheme=scheme)
                info["t_jacobian"] += time.perf_counter() - t0
                info["n_jacobian"] += 1
            t1 = time.perf_counter()
            d = (area / (cfl / spectral_radius_sum(grid, q, flow))[..., None]) if np.isfinite(cfl) else 0 * area
            d = np.broadcast_to(d, q.shape).ravel()
            solve = None  # the previous factors go before the next ones are built (one factor less at the peak)
            solve, fill = factorise(J + sp.diags(d), perm)
            t2 = time.perf_counter()
            dq = -solve(R.ravel()).reshape(q.shape)
            info["t_factor"] += t2 - t1
            info["t_solve"] += time.perf_counter() - t2
            info["n_factor"] += 1
            info["n_solve"] += 1
            info["fill"] = fill
            # Limit the relative change of density and pressure per step (robust continuation through
            # the shock transient); a full step is a Newton step.
            rho, _, _, p = primitive(q, gamma)
            rho_n, _, _, p_n = primitive(q + dq, gamma)
            change = max(np.max(np.abs(rho_n - rho) / rho), np.max(np.abs(p_n - p) / p))
            step = min(1.0, max_change / change) if change > 0 else 1.0
            for _ in range(3 if chord else 1):
                qn = q + step * dq
                ok = _positive(qn, gamma)
                if ok:
                    Rn = residual(grid, qn, flow, scheme=scheme)
                    rn = norm(Rn)
                    ok = np.isfinite(rn) and rn < max_rise * history[-1]
                if ok:
                    break
                step *= 0.25  # chord strategy: backtrack along the same direction before a new factorisation
            if verbose:
                print(f"newton {n_newton:3d}  cfl {cfl:9.3g}  step {step:5.3f}  |R| {rn if ok else np.nan:.3e}  "
                      f"fill {fill:.1f}{'' if ok else '  rejected'}")
            cfl_step = cfl
            if not ok:
                # Reject: same state and Jacobian, smaller pseudo-time step.
                cfl *= 0.25
                if cfl < cfl_min:
                    # Escape: explicit steps from the current state, then restart the continuation.
                    n_escape += 1
                    if n_escape > 3:
                        fail(f"the pseudo-time step fell below cfl = {cfl_min} without an admissible step, "
                             "three times")
                    q, R = rk_steps(q, n_rk_escape)
                    J, cfl, r_ref = None, cfl0, history[-1]
                report(n_newton, cfl_step)
                continue
            ratio = rn / history[-1]
            if step == 1.0 and ratio < 1.0:
                cfl = min(max(growth * cfl, cfl0 * (r_ref / rn) ** 1.5), 10.0 * cfl, cfl_max)
            elif step < 1.0 and ratio > 1.0:
                cfl = max(0.5 * cfl, cfl_min)
            elif step == 1.0:
                cfl = min(1.25 * cfl, cfl_max)  # a transient may raise the residual: keep moving in pseudo-time
            q, R, J = qn, Rn, None
            history.append(rn)
            if chord and ratio < 1.0:
                # Chord (modified Newton) steps with the frozen factorisation while they converge fast: each
                # costs one back-substitution and one residual.
                n_c = 0
                while history[-1] > target and n_c < max_chord:
                    t2 = time.perf_counter()
                    dq = -solve(R.ravel()).reshape(q.shape)
                    info["t_solve"] += time.perf_counter() - t2
                    info["n_solve"] += 1
                    qn = q + dq
                    rho_n, _, _, p_n = primitive(qn, gamma)
                    rho, _, _, p = primitive(q, gamma)
                    if not (_positive(qn, gamma) and max(np.max(np.abs(rho_n - rho) / rho),
                                                         np.max(np.abs(p_n - p) / p)) <= max_change):
                        break
                    Rn = residual(grid, qn, flow, scheme=scheme)
                    rn = norm(Rn)
                    if not (np.isfinite(rn) and rn < history[-1]):
                        break
                    n_c += 1
                    info["n_chord"] += 1
                    r_prev = history[-1]
                    q, R = qn, Rn
                    history.append(rn)
                    if verbose:
                        print(f"chord  {n_c:3d}  |R| {rn:.3e}  ratio {rn / r_prev:.3f}")
                    if rn > chord_ratio * r_prev:
                        break
            report(n_newton, cfl_step)

    except KeyboardInterrupt as e:   # Ctrl-C or the progress callback: keep what was accepted
        raise SolveInterrupted(
            f"steady solve at M={mach}, alpha={alpha_deg} deg interrupted after {n_newton} Newton steps (residual "
            f"{history[-1]:.3e}, target {target:.1e}); continue with solve_steady(..., q0=e.q)",
            q=q.copy(), history=np.array(history), newton_steps=n_newton) from e

    info["newton_steps"] = n_newton
    info["wall_time"] = time.perf_counter() - t_start
    info["relative_drop"] = history[-1] / r0 if r0 > 0 else 0.0
    cl, cd, cm = force_coefficients(grid, q, flow)
    x_wall, cp = wall_cp(grid, q, flow)
    return SteadySolution(
        grid=grid, q=q, mach=flow.mach, alpha_deg=flow.alpha_deg, gamma=flow.gamma, cl=float(cl), cd=float(cd),
        cm=float(cm), x_wall=x_wall, cp=cp, history=np.array(history), iterations=len(history) - 1,
        converged=True, scheme=scheme, info=info,
    )
