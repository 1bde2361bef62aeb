"""Gust-solver validation on thin flat plates at low Mach (docs/gust_validation.md figures and numbers).

1. LFD lift of a flat plate at M0.3 on two parabolic C-grids against Amiet's compressible Sears function
   (leading-edge reference) and the incompressible Sears function.
2. LTD lift after a sharp-edged gust against the step response of the compressible Sears function and
   the Kussner function (R.T. Jones).
3. Phase change with Mach number (M0.2 -> M0.5), which fixes the sign convention of Amiet's factors.
4. (``--paper``) NACA0006 at M0.3 on the paper's 181 x 60 C-grid (``cfd.c_grid``) against Amiet's function.

Run: ``MPLBACKEND=Agg .venv/bin/python bench/gust_validation.py [--paper]`` (a few minutes on two cores;
``--paper`` runs only part 4).
"""

import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.append(str(ROOT / "tests" / "cfd"))

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from flowgrids import parabolic_c_grid  # noqa: E402

from cfd.analytic import kussner, sears, sears_compressible, step_response  # noqa: E402
from cfd.flow import FlowCondition  # noqa: E402
from cfd.gust import SharpEdged  # noqa: E402
from cfd.lfd import lfd_response  # noqa: E402
from cfd.linear import linearise_state  # noqa: E402
from cfd.ltd import ltd_response  # noqa: E402

GRIDS = {
    "73 x 17, far field 12c": dict(),
    "121 x 33, far field 25c": dict(n_surface=80, n_wake=20, nj=33, eta_max=5.0, xi_max=5.0),
}


def plate(mach, **args):
    grid = parabolic_c_grid(thickness=0.0, **args)
    flow = FlowCondition(mach)
    return linearise_state(grid, np.broadcast_to(flow.q, grid.cell_shape + (4,)).copy(), flow)


def paper_grid(mach=0.3):
    import cfd

    beta = np.sqrt(1 - mach**2)
    w = np.array([0.0, 0.1, 0.2, 0.5, 1.0, 2.0])
    t = time.perf_counter()
    sol = cfd.solve_steady(cfd.c_grid(cfd.naca("0006")), mach, 0.0)
    lin = cfd.linearise(sol)
    H = lfd_response(lin, w, outputs="Cl", method="direct").H[0, 0] / (2 * np.pi / beta)
    S = sears_compressible(w, mach, "leading_edge")
    print(f"4. NACA0006, M{mach}, 181 x 60 grid ({time.perf_counter() - t:.0f} s); thickness raises the slope by "
          f"about 1 + 0.77 t/c = {1 + 0.77 * 0.06:.3f}")
    print("    omega   k     |H|    |S_c|   |H|/|S_c|-1   arg H   arg S_c  diff (deg)")
    for k in range(w.size):
        print(f"    {w[k]:4.1f}  {w[k] / 2:4.2f}  {abs(H[k]):.3f}  {abs(S[k]):.3f}  {abs(H[k]) / abs(S[k]) - 1:+8.3f}"
              f"    {np.degrees(np.angle(H[k])):7.2f}  {np.degrees(np.angle(S[k])):7.2f}  "
              f"{np.degrees(np.angle(H[k] / S[k])):+6.2f}")


def main():
    figdir = ROOT / "docs" / "figures"
    figdir.mkdir(parents=True, exist_ok=True)
    mach = 0.3
    beta = np.sqrt(1 - mach**2)
    w = np.array([0.0, 0.1, 0.2, 0.5, 1.0, 2.0, 4.0])
    wf = np.linspace(0.0, 4.0, 200)
    S_c = sears_compressible(wf, mach, "leading_edge")
    S_0 = sears(wf, "leading_edge")
    fig, ax = plt.subplots(2, 1, figsize=(6, 6), sharex=True)
    ax[0].plot(wf / 2, np.abs(S_c), "k-", label=f"Amiet, M{mach}")
    ax[0].plot(wf / 2, np.abs(S_0), "k:", label="Sears, incompressible")
    ax[1].plot(wf / 2, np.degrees(np.angle(S_c)), "k-")
    ax[1].plot(wf / 2, np.degrees(np.angle(S_0)), "k:")
    lins = {}
    print(f"1. LFD flat plate, M{mach}: Cl / (2 pi / beta) per radian, leading-edge reference")
    for name, args in GRIDS.items():
        t = time.perf_counter()
        lin = plate(mach, **args)
        lins[name] = lin
        H = lfd_response(lin, w, outputs="Cl", method="direct").H[0, 0] / (2 * np.pi / beta)
        S = sears_compressible(w, mach, "leading_edge")
        print(f"  grid {name} ({time.perf_counter() - t:.0f} s)")
        print("    omega   k     |H|    |S_c|   |H|/|S_c|-1   arg H   arg S_c  diff (deg)")
        for k in range(w.size):
            print(f"    {w[k]:4.1f}  {w[k] / 2:4.2f}  {abs(H[k]):.3f}  {abs(S[k]):.3f}  {abs(H[k]) / abs(S[k]) - 1:+8.3f}"
                  f"    {np.degrees(np.angle(H[k])):7.2f}  {np.degrees(np.angle(S[k])):7.2f}  "
                  f"{np.degrees(np.angle(H[k] / S[k])):+6.2f}")
        ax[0].plot(w / 2, np.abs(H), "o--", label=f"LFD {name}")
        ax[1].plot(w / 2, np.degrees(np.angle(H)), "o--")
    ax[0].set_ylabel("|Cl| / (2 pi u / beta)")
    ax[1].set_ylabel("phase (deg)")
    ax[1].set_xlabel("reduced frequency k = omega c / (2 U)")
    ax[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(figdir / "gust-sears-flat-plate.png", dpi=120)

    print("2. LTD sharp-edged gust (front at the leading edge at s = 0), Cl / (2 pi u / beta)")
    s = np.linspace(0.05, 12.0, 120)
    ref = step_response(lambda x: sears_compressible(x, mach, "leading_edge"), s)
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(s, ref, "k-", label="step response of Amiet's function")
    ax.plot(s, kussner(s), "k:", label="Kussner (R.T. Jones)")
    for name, lin in lins.items():
        gust = SharpEdged(angle_deg=1.0, x0=-1.0)
        h = ltd_response(lin, gust, 0.05, 13.0, max_phase_error=1.0)
        cl = np.interp(s + 1.0, h.t, h.cl) / (gust.amplitude * 2 * np.pi / beta)
        ax.plot(s, cl, "--", label=f"LTD {name}")
        pick = [np.argmin(abs(s - v)) for v in (1.0, 2.5, 5.0, 10.0)]
        print(f"  {name}: s = {np.round(s[pick], 2)}: LTD {np.round(cl[pick], 3)}, Amiet step {np.round(ref[pick], 3)},"
              f" Kussner {np.round(kussner(s[pick]), 3)}")
    ax.set_xlabel("s = U t / c after the front passes the leading edge")
    ax.set_ylabel("Cl / (2 pi u / beta)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(figdir / "gust-kussner-flat-plate.png", dpi=120)

    print("3. Phase change M0.2 -> M0.5 (73 x 17 grid)")
    wm = np.array([0.1, 0.3, 0.6])
    H = {m: lfd_response(plate(m), wm, outputs="Cl", method="direct").H[0, 0] for m in (0.2, 0.5)}
    ref = np.degrees(np.angle(sears_compressible(wm, 0.5) / sears_compressible(wm, 0.2)))
    print(f"  omega {wm}: CFD {np.round(np.degrees(np.angle(H[0.5] / H[0.2])), 2)} deg, Amiet {np.round(ref, 2)} deg")


if __name__ == "__main__":
    if "--paper" in sys.argv:
        paper_grid()
    else:
        main()
