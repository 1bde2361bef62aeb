"""LTD benchmark: gust G3 (1-cosine, one chord, 5 deg) on case T2 (NACA0010, M0.735), 181 x 60 grid.

BDF2 at the validation time step dt = 0.02 (estimated phase-rate error (2 pi dt / L)^2 / 3 = 0.5 %) to
s = 20: prints the wall time of the march, the time of its one factorisation and of one step, and the total
as factorisations plus back-substitutions.

Run: ``.venv/bin/python bench/ltd_bench.py``.
"""

import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout

import numpy as np
import scipy.sparse as sp

import cfd
from cfd.linear import factorise
from cfd.ltd import ltd_response
from cfd.ordering import nested_dissection, unknown_permutation


def timed(f):
    t = time.perf_counter()
    out = f()
    return time.perf_counter() - t, out


def main(dt=0.02, t_end=20.0):
    grid = cfd.c_grid(cfd.naca("0010"))
    sol = cfd.solve_steady(grid, 0.735, 0.0)
    lin = cfd.linearise(sol)
    gust = cfd.OneMinusCosine(length=1.0, angle_deg=5.0, x0=-2.0)
    h = lin.to_solver_time(dt)
    A = lin.J + sp.diags(1.5 * lin.V / h)
    perm = unknown_permutation(nested_dissection(grid))
    t_fac, (solve, fill) = timed(lambda: factorise(A, perm))
    r = np.ones(lin.n)
    t_bs, _ = timed(lambda: [solve(r) for _ in range(10)])
    t_bs /= 10
    t_all, hist = timed(lambda: ltd_response(lin, gust, dt, t_end))
    n = hist.t.size - 1
    t_step = (t_all - t_fac) / n
    print(f"LTD BDF2, T2 + G3, 181 x 60, dt = {dt}, {n} steps to s = {t_end}")
    print(f"  factorisation             {t_fac:8.2f} s")
    print(f"  back-substitution         {t_bs * 1e3:8.1f} ms")
    print(f"  one step (with forcing)   {t_step * 1e3:8.1f} ms  = {t_step / t_bs:.2f} back-substitutions")
    print(f"  whole march               {t_all:8.2f} s  = 1 factorisation + {n} steps "
          f"= {t_all / t_fac:.1f} factorisations")
    print(f"  peak Cl perturbation      {hist.cl.max():.4f} at s = {hist.t[np.argmax(hist.cl)]:.2f}")


if __name__ == "__main__":
    main()
