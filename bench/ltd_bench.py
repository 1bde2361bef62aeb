"""LTD benchmark: gust G3 (1-cosine, one chord, 5 deg) on case T2 (NACA0010, M0.735), 181 x 60 grid.

BDF2 at the validation time step dt = 0.02 (estimated phase-rate error (2 pi dt / L)^2 / 3 = 0.5 %) to
s = 20: prints the wall time of the march, the time of its one factorisation and of one step, and the total
as factorisations plus back-substitutions. Then gusts marched together (``cfd.ltd_responses``: one
factorisation, one block solve per step) against separate marches, side by side: G3 + G6 (the demo's
pair) and G1-G6 (a paper case's six: five columns, G2 and G3 differ only in angle and share one), with the
largest difference of their Cl histories.

Run: ``.venv/bin/python bench/ltd_bench.py [--lin FILE.pkl]`` (``--lin`` stores / reuses the T2 linear
system).
"""

import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout

import numpy as np
import scipy.sparse as sp

import cfd
from cfd.linear import factorise
from cfd.ltd import ltd_response, ltd_responses
from cfd.ordering import nested_dissection, unknown_permutation


def timed(f):
    t = time.perf_counter()
    out = f()
    return time.perf_counter() - t, out


def paper_gusts(names):
    from studies.config.cases import gust_case, to_gust

    return [to_gust(gust_case(n), x0=-2.0) for n in names]


def together_vs_separate(lin, names, dt, t_end):
    gusts = paper_gusts(names)
    t_sep, sep = timed(lambda: [ltd_response(lin, g, dt, t_end) for g in gusts])
    t_tog, tog = timed(lambda: ltd_responses(lin, gusts, dt, t_end))
    diff = max(np.abs(a.cl - b.cl).max() / np.abs(a.cl).max() for a, b in zip(sep, tog))
    print(f"  {'+'.join(names):18s} separate {t_sep:8.1f} s   together {t_tog:8.1f} s   "
          f"ratio {t_sep / t_tog:.2f}   max Cl difference {diff:.1e} (relative to the peak)")


def load_lin(path):
    import os
    import pickle

    if path and os.path.exists(path):
        with open(path, "rb") as f:
            return pickle.load(f)
    grid = cfd.c_grid(cfd.naca("0010"))
    lin = cfd.linearise(cfd.solve_steady(grid, 0.735, 0.0))
    if path:
        with open(path, "wb") as f:
            pickle.dump(lin, f)
    return lin


def main(dt=0.02, t_end=20.0, lin_path=None):
    lin = load_lin(lin_path)
    grid = lin.grid
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
    print(f"gusts marched together (cfd.ltd_responses) against separate marches, {n} steps each:")
    together_vs_separate(lin, ["G3", "G6"], dt, t_end)
    together_vs_separate(lin, ["G1", "G2", "G3", "G4", "G5", "G6"], dt, t_end)


if __name__ == "__main__":
    import argparse

    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--lin", default=None, help="pickle file to store / reuse the T2 linear system")
    main(lin_path=ap.parse_args().lin)
