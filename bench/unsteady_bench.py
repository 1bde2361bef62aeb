"""Cost of one gust by the nonlinear march (cfd.unsteady_response) against the LTD, side by side in one run.

Same steady state, grid, gust shape, dt and t_end. The LTD costs the linearisation (Jacobian, gust and output
operators; once per case, shared by all its gusts) and a march of one factorisation and one back-substitution per
step. The nonlinear march costs the steady Jacobian and its factorisation, then per step a few chord-Newton
iterations (one residual and one back-substitution each) and a refactorisation when an iteration stalls. Printed
per amplitude: seconds, factorisations, Newton iterations per step (mean and largest), residuals and
back-substitutions, the ratio to the LTD march, and the largest ``Cl`` difference from the LTD (relative to the
LTD's peak; the linear model's error at that amplitude). Times are CPU seconds of the process
(``time.process_time``), which a busy machine disturbs less than wall time.

Run: ``nice -n 15 .venv/bin/python bench/unsteady_bench.py [--case T2|T3] [--grid ni,nj,n_surface,farfield]
[--dt 0.02] [--t-end 10] [--amplitudes 0.1,1,5] [--krylov]``.
"""

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout

import numpy as np  # noqa: E402

import cfd  # noqa: E402

CASES = {"T2": ("0010", 0.735), "T3": ("0010", 0.85), "T4": ("0018", 0.25)}


def timed(f):
    """CPU seconds of the process (steadier than wall time on a shared machine) and the result."""
    t = time.process_time()
    out = f()
    return time.process_time() - t, out


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--case", default="T2", choices=sorted(CASES))
    p.add_argument("--grid", default="97,25,64,15", help="ni,nj,n_surface,farfield")
    p.add_argument("--dt", type=float, default=0.02)
    p.add_argument("--t-end", type=float, default=10.0)
    p.add_argument("--length", type=float, default=1.0, help="1-cosine gust length (chords); G3 is 1")
    p.add_argument("--amplitudes", default="0.1,1,5")
    p.add_argument("--krylov", action="store_true", help="also the GMRES variant")
    a = p.parse_args(argv)
    code, mach = CASES[a.case]
    ni, nj, ns, R = (float(v) for v in a.grid.split(","))
    grid = cfd.c_grid(cfd.naca(code), ni=int(ni), nj=int(nj), n_surface=int(ns), farfield=R)
    t_st, sol = timed(lambda: cfd.solve_steady(grid, mach, 0.0, tol=1e-12))
    n = int(round(a.t_end / a.dt))
    print(f"{a.case} NACA{code} M{mach}, grid {int(ni)} x {int(nj)} ({4 * grid.n_cells} unknowns), 1-cosine gust "
          f"L = {a.length}, x0 = -2, dt = {a.dt}, {n} steps to s = {a.t_end}; steady solve {t_st:.1f} s")
    t_lin, lin = timed(lambda: cfd.linearise(sol))
    ref = cfd.OneMinusCosine(length=a.length, angle_deg=1.0, x0=-2.0)
    t_ltd, h = timed(lambda: cfd.ltd_response(lin, ref, a.dt, a.t_end))
    peak = np.abs(h.cl).max() / ref.amplitude
    print(f"  LTD        linearise {t_lin:6.1f} s   march {t_ltd:7.1f} s (CPU)   1 factorisation, 1 back-substitution "
          f"per step   (peak Cl / A = {peak:.3f})")
    print("  nonlinear  amplitude   CPU s     / LTD march   / (linearise + LTD)   factorisations   it/step (max)   "
          "residuals   solves   Cl diff / peak")
    variants = [False, True] if a.krylov else [False]
    for amp in (float(v) for v in a.amplitudes.split(",")):
        for kry in variants:
            g = cfd.OneMinusCosine(length=a.length, angle_deg=amp, x0=-2.0)
            t_nl, u = timed(lambda: cfd.unsteady_response(sol, g, a.dt, a.t_end, krylov=kry))
            err = np.abs(u.cl / g.amplitude - h.cl / ref.amplitude).max() / peak
            solves = u.info["n_gmres"] if kry else u.info["n_solve"]
            print(f"  {'gmres' if kry else 'chord':9s}  {amp:9.3g}   {t_nl:7.1f}   {t_nl / t_ltd:11.2f}   "
                  f"{t_nl / (t_lin + t_ltd):19.2f}   {u.n_factorisations:14d}   {u.iterations[1:].mean():5.2f} "
                  f"({u.iterations.max():2d})   {u.info['n_residual']:9d}   {solves:6d}   {err:.2e}")


if __name__ == "__main__":
    main()
