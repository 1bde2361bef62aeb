"""LTD gust responses on the paper grid: case T2 (NACA0010, M0.735), gust G3 (1-cosine, one chord, 5 deg,
front at x0 = -2) and a sharp-edged gust (1 deg).

1. Time-step convergence of the G3 response (SVM): peak Cl, its time and the largest difference from the
   finest history at dt = 0.04, 0.02, 0.01.
2. SVM against FVM for both gusts. Figure docs/figures/gust-ltd-T2.png.

Run: ``MPLBACKEND=Agg .venv/bin/python bench/ltd_gusts.py`` (several minutes on two cores).
"""

import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import cfd  # noqa: E402


def main(t_end=20.0):
    sol = cfd.solve_steady(cfd.c_grid(cfd.naca("0010")), 0.735, 0.0)
    lin = cfd.linearise(sol)
    g3 = cfd.OneMinusCosine(length=1.0, angle_deg=5.0, x0=-2.0)
    print("1. G3 (SVM): dt, peak Cl, at s, max |Cl - Cl(dt = 0.01)| on the coarse samples, wall time")
    runs = {}
    for dt in (0.04, 0.02, 0.01):
        t0 = time.perf_counter()
        runs[dt] = cfd.ltd_response(lin, g3, dt, t_end, max_phase_error=1.0)
        runs[dt] = (runs[dt], time.perf_counter() - t0)
    fine = runs[0.01][0]
    for dt, (h, wall) in runs.items():
        ref = np.interp(h.t, fine.t, fine.cl)
        print(f"   {dt:5.2f}   {h.cl.max():.5f}   {h.t[np.argmax(h.cl)]:.2f}   {np.abs(h.cl - ref).max():.2e}   {wall:.0f} s")
    fig, ax = plt.subplots(2, 2, figsize=(10, 6), sharex="col")
    sharp = cfd.SharpEdged(angle_deg=1.0, x0=-2.0)
    print("2. SVM against FVM, dt = 0.02: peak |Cl| and |Cm| (and the final Cl for the sharp-edged gust)")
    for col, gust, name in ((0, g3, "G3: 1-cosine, 1 chord, 5 deg"), (1, sharp, "sharp-edged, 1 deg")):
        for m, style in (("svm", "-"), ("fvm", "--")):
            h = runs[0.02][0] if (gust is g3 and m == "svm") else cfd.ltd_response(lin, gust, 0.02, t_end, method=m,
                                                                                   max_phase_error=1.0)
            ax[0, col].plot(h.t, h.cl, style, label=m.upper())
            ax[1, col].plot(h.t, h.cm, style)
            print(f"   {name:30s} {m}: max Cl {h.cl.max():.5f} at s = {h.t[np.argmax(h.cl)]:.2f}, "
                  f"min Cm {h.cm.min():.5f}, Cl(end) {h.cl[-1]:.5f}")
        ax[0, col].set_title(f"T2, {name}", fontsize=9)
        ax[1, col].set_xlabel("s = U t / c (front at x = -2 at s = 0)")
    ax[0, 0].set_ylabel("Cl perturbation")
    ax[1, 0].set_ylabel("Cm perturbation")
    ax[0, 0].legend()
    fig.tight_layout()
    fig.savefig(ROOT / "docs" / "figures" / "gust-ltd-T2.png", dpi=110)


if __name__ == "__main__":
    main()
