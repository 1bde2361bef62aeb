"""SVM against FVM on the paper grid (181 x 60): cases T2 (NACA0010, M0.735) and T4 (NACA0018, M0.25).

The analogue of the paper's Figs. 9-10: LFD lift and moment per radian of gust angle (leading-edge
reference) by both gust methods; one factorisation per frequency serves both right-hand sides.
Writes docs/figures/gust-svm-fvm-<case>.png and docs/data/gust-svm-fvm-<case>.npz, prints a table.

Run: ``MPLBACKEND=Agg .venv/bin/python bench/gust_svm_fvm.py [T2] [T4] [--plot]`` (minutes per case;
``--plot`` re-draws the figures from the saved data).
"""

import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import scipy.sparse as sp  # noqa: E402

import cfd  # noqa: E402
from cfd.gust import face_gust_harmonic  # noqa: E402
from cfd.linear import factorise, grid_permutation  # noqa: E402

CASES = {"T2": ("0010", 0.735), "T4": ("0018", 0.25)}


def sweep(lin, omega):
    perm = grid_permutation(lin.grid)
    H = {m: np.zeros((2, omega.size), complex) for m in ("svm", "fvm")}
    for k, w in enumerate(omega):  # one factorisation per frequency, two solves
        solve, _ = factorise(lin.J + sp.diags(1j * lin.to_solver_frequency(w) * lin.V), perm)
        gi, gj = face_gust_harmonic(lin.grid, w)
        for m in H:
            H[m][:, k] = lin.C[:2] @ solve(-lin.forcing(gi, gj, m))
    return H


def main(cases):
    (ROOT / "docs" / "figures").mkdir(parents=True, exist_ok=True)
    (ROOT / "docs" / "data").mkdir(parents=True, exist_ok=True)
    omega = np.concatenate([[0.0], np.geomspace(0.02, 10.0, 11)])
    for case in cases:
        code, mach = CASES[case]
        t0 = time.perf_counter()
        grid = cfd.c_grid(cfd.naca(code))
        sol = cfd.solve_steady(grid, mach, 0.0)
        lin = cfd.linearise(sol)
        t1 = time.perf_counter()
        H = sweep(lin, omega)
        t2 = time.perf_counter()
        np.savez(ROOT / "docs" / "data" / f"gust-svm-fvm-{case}.npz", omega=omega, svm=H["svm"], fvm=H["fvm"],
                 mach=mach, naca=code)
        print(f"{case} NACA{code} M{mach}: steady + linearise {t1 - t0:.0f} s, {omega.size} frequencies "
              f"{t2 - t1:.0f} s ({(t2 - t1) / omega.size:.1f} s each)")
        print("   omega      |Cl| svm   |Cl| fvm   arg svm   arg fvm   |svm/fvm - 1|")
        for k, w in enumerate(omega):
            a, b = H["svm"][0, k], H["fvm"][0, k]
            print(f"  {w:7.3f}   {abs(a):8.4f}   {abs(b):8.4f}   {np.degrees(np.angle(a)):7.2f}   "
                  f"{np.degrees(np.angle(b)):7.2f}   {abs(a / b - 1):.4f}")
        plot(case)


def plot(case):
    """Bode-style figure from docs/data/gust-svm-fvm-<case>.npz (phase unwrapped)."""
    d = np.load(ROOT / "docs" / "data" / f"gust-svm-fvm-{case}.npz")
    omega = d["omega"]
    fig, ax = plt.subplots(2, 2, figsize=(9, 6), sharex=True)
    for m, style in (("svm", "o-"), ("fvm", "s--")):
        for r, name in enumerate(("Cl", "Cm")):
            h = d[m][r, 1:]
            ax[0, r].semilogx(omega[1:] / 2, np.abs(h), style, label=m.upper())
            ax[1, r].semilogx(omega[1:] / 2, np.degrees(np.unwrap(np.angle(h))), style)
            ax[0, r].set_title(f"{case} (NACA{d['naca']}, M{float(d['mach'])}): {name} per radian of gust angle",
                               fontsize=9)
    for a in ax[1]:
        a.set_xlabel("k = omega c / (2 U)")
    ax[0, 0].set_ylabel("magnitude")
    ax[1, 0].set_ylabel("phase (deg, unwrapped)")
    ax[0, 0].legend()
    fig.tight_layout()
    fig.savefig(ROOT / "docs" / "figures" / f"gust-svm-fvm-{case}.png", dpi=110)


if __name__ == "__main__":
    chosen = [a for a in sys.argv[1:] if a in CASES] or list(CASES)
    if "--plot" in sys.argv:  # re-draw from the saved data only
        for c in chosen:
            plot(c)
    else:
        main(chosen)
