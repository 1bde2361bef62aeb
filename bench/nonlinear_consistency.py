"""The nonlinear gust response at small amplitudes against the LTD, and the steady lift slope against the step.

``consistency``: for one case, a 1-cosine gust (length 2 chords, front at x0 = -2) marched by
``cfd.unsteady_response`` at the given amplitudes and by ``cfd.ltd_response``, same grid, dt and t_end (SVM);
prints per amplitude the largest difference of ``Cl / A`` and ``Cm / A`` (``A = tan(angle)``) over the history
relative to the LTD's peak, the ratio of those differences between consecutive amplitudes (10 per decade when
the difference is the second-order term of a smooth response, 100 when it is the third-order one), and the
cost.

``alpha-sweep``: ``Cl`` of T3 at alpha = 0, d, 2d, ... (warm-started steady solves), the slope of each interval and
the shock positions (where the wall ``Cp`` rises through the critical ``Cp*``, linear interpolation, and the wall
cell it falls in) on both surfaces: how the lift slope changes as the shocks move across the cells.

``fd-slope``: the steady lift slope by central differences ``(Cl(alpha + d) - Cl(alpha - d)) / 2d`` of
warm-started ``cfd.solve_steady`` at several steps ``d`` against the LFD's zero-frequency gain minus Cd0 (the gust
gain is in the axes of the unperturbed stream, see bench/gust_steady_gain.py), for one case (T3 by default).

Run (docs/nonlinear.md quotes these)::

    nice -n 15 .venv/bin/python bench/nonlinear_consistency.py consistency S1 --amplitudes 0.01,0.1
    nice -n 15 .venv/bin/python bench/nonlinear_consistency.py fd-slope T3 --grid 97,25,64,15 [--vortex]
    nice -n 15 .venv/bin/python bench/nonlinear_consistency.py alpha-sweep --steps 0.01 --n 30
"""

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout

import numpy as np  # noqa: E402

import cfd  # noqa: E402

CASES = {  # name: (NACA code, Mach, alpha in deg)
    "S0": ("0012", 0.5, 0.0),
    "S1": ("0012", 0.5, 1.0),
    "TR0": ("0010", 0.8, 0.0),
    "TR1": ("0010", 0.8, 1.0),
    "T3": ("0010", 0.85, 0.0),
}


def steady(case, grid_args, scheme=None):
    code, mach, alpha = CASES[case]
    ni, nj, ns, R = grid_args
    grid = cfd.c_grid(cfd.naca(code), ni=int(ni), nj=int(nj), n_surface=int(ns), farfield=float(R))
    t0 = time.perf_counter()
    sol = cfd.solve_steady(grid, mach, alpha, tol=1e-12, scheme=scheme)
    return sol, time.perf_counter() - t0


def consistency(case, grid_args, amplitudes, dt, t_end, length):
    sol, t_steady = steady(case, grid_args)
    t0 = time.perf_counter()
    lin = cfd.linearise(sol)
    t_lin = time.perf_counter() - t0
    gust = cfd.OneMinusCosine(length=length, angle_deg=1.0, x0=-2.0)
    t0 = time.perf_counter()
    res = cfd.linearity(sol, gust, amplitudes, dt, t_end, lin=lin)
    t_all = time.perf_counter() - t0
    code, mach, alpha = CASES[case]
    print(f"{case}: NACA{code} M{mach} alpha {alpha} deg, grid {grid_args}, Cl0 {sol.cl:.4f}, steady {t_steady:.0f} s, "
          f"linearise {t_lin:.1f} s; 1-cosine L = {length}, dt = {dt}, t_end = {t_end}; {t_all:.0f} s in all")
    print("  amplitude   Cl diff / peak   Cm diff / peak   Cl peak ratio   max Mach   it/step   factorisations")
    for k, a in enumerate(res.amplitudes):
        h = res.histories[k]
        print(f"  {a:9.3g}   {res.cl_error[k]:14.3e}   {res.cm_error[k]:14.3e}   {res.cl_peak_ratio[k]:13.6f}   "
              f"{h.max_mach.max():8.3f}   {h.iterations[1:].mean():7.2f}   {h.n_factorisations:14d}")
    for k in range(1, res.amplitudes.size):
        print(f"  difference ratio {res.amplitudes[k]:g} / {res.amplitudes[k - 1]:g} deg: "
              f"Cl {res.cl_error[k] / res.cl_error[k - 1]:.2f}, Cm {res.cm_error[k] / res.cm_error[k - 1]:.2f}")
    return res


def fd_slope(case, grid_args, steps, scheme=None):
    sol, t_steady = steady(case, grid_args, scheme)
    lin = cfd.linearise(sol)
    H0 = cfd.lfd_response(lin, [0.0], outputs=("Cl",)).H[0, 0, 0].real
    gain = H0 - sol.cd
    code, mach, alpha = CASES[case]
    print(f"{case} NACA{code} M{mach} alpha {alpha}, grid {grid_args}, {sol.scheme}: steady {t_steady:.0f} s, Cd0 "
          f"{sol.cd:.5f}; LFD H0(Cl) - Cd0 = {gain:.3f} per rad")
    print("  step (deg)   Cl(+d)        Cl(-d)        dCl/dalpha (per rad)   / LFD")
    for d in steps:
        cl = []
        for a in (alpha + d, alpha - d):
            s = cfd.solve_steady(sol.grid, sol.mach, a, tol=1e-12, q0=sol.q, scheme=sol.scheme, max_newton=30)
            cl.append(s.cl)
        slope = (cl[0] - cl[1]) / np.radians(2 * d)
        print(f"  {d:10.3g}   {cl[0]:+.6e}  {cl[1]:+.6e}  {slope:20.3f}   {slope / gain:.4f}")


def shock_positions(sol):
    """x of the shocks on the lower and upper surface (Cp rising through Cp* downstream) and their wall cells."""
    g, m = sol.gamma, sol.mach
    cp_star = 2.0 / (g * m * m) * (((2.0 + (g - 1.0) * m * m) / (g + 1.0)) ** (g / (g - 1.0)) - 1.0)
    n = sol.cp.size // 2
    out = []
    for x, cp, cells in ((sol.x_wall[:n][::-1], sol.cp[:n][::-1], np.arange(n)[::-1]),
                         (sol.x_wall[n:], sol.cp[n:], np.arange(n, 2 * n))):  # both from the leading edge aft
        k = np.nonzero((cp[:-1] < cp_star) & (cp[1:] >= cp_star))[0]
        if k.size == 0:
            out += [np.nan, -1]
            continue
        k = k[-1]
        f = (cp_star - cp[k]) / (cp[k + 1] - cp[k])
        out += [x[k] + f * (x[k + 1] - x[k]), int(cells[k + 1] if f >= 0.5 else cells[k])]
    return out


def alpha_sweep(grid_args, d, n):
    sol, _ = steady("T3", grid_args)
    print(f"T3 NACA0010 M0.85, grid {grid_args}: alpha from 0 in steps of {d} deg")
    print("  alpha (deg)   Cl              slope of the step (per rad)   x shock lower (cell)   x shock upper (cell)")
    prev = sol
    for k in range(n + 1):
        try:  # warm start from alpha = 0 (from the previous alpha the chord-Newton may cycle, see docs)
            s = sol if k == 0 else cfd.solve_steady(sol.grid, sol.mach, k * d, tol=1e-12, q0=sol.q, max_newton=30)
        except cfd.ConvergenceError as e:
            print(f"  {k * d:11.3f}   no convergence: Newton cycles at |R| = {e.history[-1]:.2e}")
            continue
        xl, cl_, xu, cu = shock_positions(s)
        slope = "" if k == 0 else f"{(s.cl - prev.cl) / np.radians(d):26.3f}"
        print(f"  {k * d:11.3f}   {s.cl:+.8e}   {slope:>26s}   {xl:13.5f} ({cl_:3d})   {xu:13.5f} ({cu:3d})")
        prev = s


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("what", choices=("consistency", "fd-slope", "alpha-sweep"))
    p.add_argument("case", nargs="?", default="S1", choices=sorted(CASES))
    p.add_argument("--grid", default="97,25,64,15", help="ni,nj,n_surface,farfield (default 97,25,64,15)")
    p.add_argument("--amplitudes", default="0.01,0.1", help="gust angles in deg (consistency)")
    p.add_argument("--steps", default="0.01,0.03,0.1,0.3", help="alpha steps in deg (fd-slope)")
    p.add_argument("--vortex", action="store_true", help="point-vortex far field (fd-slope)")
    p.add_argument("--n", type=int, default=30, help="number of alpha steps (alpha-sweep)")
    p.add_argument("--dt", type=float, default=0.05)
    p.add_argument("--t-end", type=float, default=8.0)
    p.add_argument("--length", type=float, default=2.0)
    a = p.parse_args(argv)
    grid_args = tuple(float(v) for v in a.grid.split(","))
    if a.what == "consistency":
        consistency(a.case, grid_args, [float(v) for v in a.amplitudes.split(",")], a.dt, a.t_end, a.length)
    elif a.what == "fd-slope":
        fd_slope(a.case, grid_args, [float(v) for v in a.steps.split(",")], cfd.Scheme(vortex=a.vortex))
    else:
        alpha_sweep(grid_args, float(a.steps.split(",")[0]), a.n)


if __name__ == "__main__":
    main()
