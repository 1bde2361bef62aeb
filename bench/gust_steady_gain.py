"""The omega -> 0 limit of the LFD against finite differences of nonlinear steady solves, paper grid.

For cases T4 (NACA0018, M0.25), T5 (NACA2410, M0.25, lifting at alpha 0) and T2 (NACA0010, M0.735): the LFD
gain at omega = 0 (SVM; a uniform gust of angle u) against (Cl(+d) - Cl(-d)) / 2d from ``cfd.solve_steady`` at
alpha = +-0.25 deg. The gust gain is in the axes of the unperturbed stream, while dCl/dalpha also turns the
drag force into the lift: the comparison is H0(Cl) - Cd0 against dCl/dalpha (and H0(Cd) + Cl0 against dCd/dalpha).

Run: ``.venv/bin/python bench/gust_steady_gain.py [T2] [T4] [T5]``.
"""

import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import numpy as np  # noqa: E402

import cfd  # noqa: E402

CASES = {"T2": ("0010", 0.735), "T4": ("0018", 0.25), "T5": ("2410", 0.25)}


def main(cases, d=0.25):
    print("case   H0(Cl)-Cd0   dCl/da (FD)   rel. diff    H0(Cm)    dCm/da (FD)   rel. diff   time")
    for case in cases:
        code, mach = CASES[case]
        t0 = time.perf_counter()
        grid = cfd.c_grid(cfd.naca(code))
        sol = cfd.solve_steady(grid, mach, 0.0, tol=1e-11)
        lin = cfd.linearise(sol)
        H0 = cfd.lfd_response(lin, [0.0], outputs=("Cl", "Cm", "Cd")).H[:, 0, 0].real
        loads = []
        for a in (-d, d):
            s = cfd.solve_steady(grid, mach, a, tol=1e-9, q0=sol.q, n_rk=0)  # relative to |R(q0)|
            loads.append(np.array([s.cl, s.cm, s.cd]))
        slope = (loads[1] - loads[0]) / np.radians(2 * d)
        gl = H0[0] - sol.cd
        print(f"{case:4s}   {gl:10.5f}   {slope[0]:11.5f}   {gl / slope[0] - 1:+.2e}   {H0[1]:8.5f}   {slope[1]:10.5f}"
              f"   {H0[1] / slope[1] - 1:+.2e}   {time.perf_counter() - t0:.0f} s   (Cl0 {sol.cl:.4f}, Cd0 {sol.cd:.2e})")


if __name__ == "__main__":
    main([a for a in sys.argv[1:] if a in CASES] or list(CASES))
