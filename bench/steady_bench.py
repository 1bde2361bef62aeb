"""Steady-solver benchmark: case T2 (NACA0010, M0.735, alpha 0) on the paper's 181 x 60 C-grid.

Measures, side by side in one run: one residual evaluation, one exact-Jacobian assembly (coloured
complex step), one sparse LU factorisation of the Newton matrix with three orderings (fill-in and time),
and the full steady solve to a residual drop of 1e-10 (also as a multiple of one factorisation).

Run: ``.venv/bin/python bench/steady_bench.py`` (add ``--quick`` to skip the slow COLAMD orderings).
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
from cfd.jacobian import _state_pattern
from cfd.ordering import nested_dissection, unknown_permutation
from cfd.steady import factorise


def best(f, n):
    ts = []
    for _ in range(n):
        t = time.perf_counter()
        out = f()
        ts.append(time.perf_counter() - t)
    return min(ts), out


def main(quick=False):
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
    _, colours = _state_pattern(grid)
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
                 f"{t_solve / t_nd:.1f} factorisations; {info['newton_steps']} Newton steps after "
                 f"{sol.iterations - info['newton_steps']} RK5 steps"))
    rows.append(("  of which Jacobians / LU / solves", f"{info['t_jacobian']:.1f} / {info['t_factor']:.1f} / "
                 f"{info['t_solve']:.1f} s", ""))
    rows.append(("  residual drop, final |R|_2", f"{info['relative_drop']:.1e}", f"absolute {sol.history[-1]:.1e} (round-off floor about 1e-14)"))
    rows.append(("  Cl, Cd, Cm", f"{sol.cl:.2e}, {sol.cd:.5f}, {sol.cm:.2e}", "symmetric: Cl = Cm = 0"))

    w = max(len(r[0]) for r in rows)
    print(f"{'quantity':<{w}}  {'value':>22}  note")
    print("-" * (w + 50))
    for name, value, note in rows:
        print(f"{name:<{w}}  {value:>22}  {note}")


if __name__ == "__main__":
    main(quick="--quick" in sys.argv)
