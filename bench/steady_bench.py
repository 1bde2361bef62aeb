"""Steady-solver benchmark on the paper's 181 x 60 C-grid.

Default: the paper cases T1-T6 (alpha 0), each solved to a residual drop of 1e-10 by the old strategy
(``strategy="classic"``) and the new one (``strategy="chord"``) side by side in one run: Newton steps,
factorisations (LU), back-substitutions, residual evaluations, wall time in seconds and in units of one real
LU of the same matrix (``J + area/dt`` at the converged state, CFL 100, nested dissection, best of two,
measured in the same run right after the solves), the agreement of the two solutions (Cl, Cm, max |dq|), and
warm starts with the new strategy from the converged alpha 0 flow: to alpha 0.1 deg and to Mach - 0.01.

Run: ``.venv/bin/python bench/steady_bench.py [T1 T3 ...]``; ``--kernels`` prints the kernel table of T2
instead (residual, Jacobian, LU orderings; add ``--quick`` to skip the slow COLAMD ordering);
``--issue-warm`` adds the warm start of issue 15 (T3 to alpha 0.003 deg, 12 Newton steps at most).
"""

import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

import cfd
from cfd.euler import spectral_radius_sum
from cfd.jacobian import state_pattern
from cfd.ordering import nested_dissection, unknown_permutation
from cfd.steady import factorise


def best(f, n):
    ts = []
    for _ in range(n):
        t = time.perf_counter()
        out = f()
        ts.append(time.perf_counter() - t)
    return min(ts), out


def kernels(quick=False):
    rows = []
    t_grid, grid = best(lambda: cfd.c_grid(cfd.naca("0010")), 1)
    flow = cfd.FlowCondition(0.735, 0.0)
    rows.append(("grid 181 x 60 (cfd.c_grid)", f"{t_grid:.2f} s", f"{grid.n_cells} cells, {4 * grid.n_cells} unknowns"))

    # The full solve first (its solution is the state for the kernels below).
    t_solve, sol = best(lambda: cfd.solve_steady(grid, 0.735, 0.0, tol=1e-10), 1)
    q = sol.q
    info = sol.info

    t_res, _ = best(lambda: cfd.residual(grid, q, flow), 30)
    rows.append(("residual evaluation", f"{1e3 * t_res:.2f} ms", "best of 30"))
    _, colours = state_pattern(grid)
    t_jac, J = best(lambda: cfd.jacobian(grid, q, flow), 3)
    rows.append(("Jacobian assembly (complex step)", f"{t_jac:.3f} s",
                 f"{colours.max() + 1} colours, nnz {J.nnz}, best of 3"))
    area = np.repeat((grid.area / (100.0 / spectral_radius_sum(grid, q, flow))).ravel(), 4)
    A = (J + sp.diags(area)).tocsr()
    perm = unknown_permutation(nested_dissection(grid))
    t_nd, (_, fill_nd) = best(lambda: factorise(A, perm), 2)
    rows.append(("LU, nested dissection, no pivoting", f"{t_nd:.2f} s", f"fill nnz(L+U)/nnz(A) = {fill_nd:.1f}"))
    if not quick:
        for spec in ("COLAMD",):
            t = time.perf_counter()
            lu = spla.splu(A.tocsc(), permc_spec=spec)
            t = time.perf_counter() - t
            rows.append((f"LU, {spec}, partial pivoting", f"{t:.2f} s", f"fill {(lu.L.nnz + lu.U.nnz) / A.nnz:.1f}"))
        rows.append(("LU, MMD_AT_PLUS_A", "not run", "killed after > 60 s in a trial on this grid size"))

    rows.append(("steady solve T2 to 1e-10", f"{t_solve:.1f} s",
                 f"{t_solve / t_nd:.1f} factorisations' worth; {info['newton_steps']} Newton steps "
                 f"({info['n_factor']} LUs), {info['n_chord']} chord steps, {info['n_residual']} residuals"))
    rows.append(("  of which Jacobians / LU / solves", f"{info['t_jacobian']:.1f} / {info['t_factor']:.1f} / "
                 f"{info['t_solve']:.1f} s", ""))
    rows.append(("  residual drop, final |R|_2", f"{info['relative_drop']:.1e}", f"absolute {sol.history[-1]:.1e} (round-off floor about 1e-14)"))
    rows.append(("  Cl, Cd, Cm", f"{sol.cl:.2e}, {sol.cd:.5f}, {sol.cm:.2e}", "symmetric: Cl = Cm = 0"))

    w = max(len(r[0]) for r in rows)
    print(f"{'quantity':<{w}}  {'value':>22}  note")
    print("-" * (w + 50))
    for name, value, note in rows:
        print(f"{name:<{w}}  {value:>22}  {note}")


CASES = {"T1": ("0006", 0.85), "T2": ("0010", 0.735), "T3": ("0010", 0.85), "T4": ("0018", 0.25),
         "T5": ("2410", 0.25), "T6": ("2410", 0.735)}


def lu_time(grid, q, flow):
    J = cfd.jacobian(grid, q, flow)
    area = np.repeat((grid.area / (100.0 / spectral_radius_sum(grid, q, flow))).ravel(), 4)
    A = (J + sp.diags(area)).tocsr()
    perm = unknown_permutation(nested_dissection(grid))
    return best(lambda: factorise(A, perm), 2)[0]


def warm(grid, mach, alpha, q0, t_lu):
    t = time.perf_counter()
    try:
        s = cfd.solve_steady(grid, mach, alpha, q0=q0, strategy="chord", max_newton=12)
    except cfd.ConvergenceError as e:
        return f"fails (|R| {e.history[-1]:.1e}) {(time.perf_counter() - t) / t_lu:.1f}u", None
    i = s.info
    return f"{i['n_factor']} LU {i['n_solve']} bs {(time.perf_counter() - t) / t_lu:.1f}u", s


def cases(names, issue_warm=False):
    head = (f"{'case':<5} {'strategy':<8} {'Newton':>6} {'LU':>3} {'bs':>3} {'res':>5} {'wall s':>7} {'LU s':>5} "
            f"{'LU units':>8}  {'Cl':>15} {'Cm':>15}  warm alpha+0.1 / Mach-0.01")
    print(head)
    print("-" * len(head))
    for name in names:
        code, mach = CASES[name]
        grid = cfd.c_grid(cfd.naca(code))
        flow = cfd.FlowCondition(mach, 0.0)
        sols = {}
        for strategy in ("classic", "chord"):
            t = time.perf_counter()
            sols[strategy] = (cfd.solve_steady(grid, mach, 0.0, strategy=strategy), time.perf_counter() - t)
        new = sols["chord"][0]
        t_lu = lu_time(grid, new.q, flow)
        wa, _ = warm(grid, mach, 0.1, new.q, t_lu)
        wm, _ = warm(grid, mach - 0.01, 0.0, new.q, t_lu)
        for strategy, (s, t) in sols.items():
            i = s.info
            w = f"{wa} / {wm}" if strategy == "chord" else ""
            print(f"{name:<5} {strategy:<8} {i['newton_steps']:>6} {i['n_factor']:>3} {i['n_solve']:>3} "
                  f"{i['n_residual']:>5} {t:>7.1f} {t_lu:>5.2f} {t / t_lu:>8.1f}  {s.cl:>15.8e} {s.cm:>15.8e}  {w}")
        old = sols["classic"][0]
        scale = max(abs(old.cl), 1e-3)
        print(f"{'':<5} new - old: Cl {abs(new.cl - old.cl) / scale:.1e} (rel. to max(|Cl|, 1e-3)), "
              f"Cm {abs(new.cm - old.cm) / max(abs(old.cm), 1e-3):.1e}, max |dq| {np.abs(new.q - old.q).max():.1e}")
        if issue_warm and name == "T3":
            r, _ = warm(grid, mach, 0.003, new.q, t_lu)
            print(f"{'':<5} warm start to alpha 0.003 deg (issue 15): {r}")
        sys.stdout.flush()


if __name__ == "__main__":
    if "--kernels" in sys.argv:
        kernels(quick="--quick" in sys.argv)
    else:
        names = [a for a in sys.argv[1:] if not a.startswith("--")] or list(CASES)
        cases(names, issue_warm="--issue-warm" in sys.argv)
