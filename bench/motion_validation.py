"""Plunge and pitch inputs of the linearised solvers: validation (docs/motion_validation.md numbers).

Parts (each well under ten minutes on two busy cores; run one at a time with ``--part``):

A. NACA0012, M0.5, 2 deg: the zero-frequency pitch response against central differences of nonlinear steady
   solves (with the difference's truncation error), the plunge's low-frequency limit, the pivot identity.
B. NACA0006, M0.2, 0 deg: plunge and pitch (about the quarter chord) over k = 0.05 .. 1 against Theodorsen's
   loads, incompressible and with the Prandtl-Glauert factor.
C. NACA0012, M0.5, 2 deg: LTD from rest for a prescribed pitch oscillation against the LFD.
D. NACA0006, M0.2, 0 deg on a 97 x 25 grid: the fast sweep (one basis for gust, plunge and pitch) against the
   direct path.

Run: ``nice .venv/bin/python bench/motion_validation.py --part A`` (B, C). Grid: ``cfd.c_grid(foil, ni=129,
nj=33, n_surface=80)`` (far field 25 chords, 24 wake cells a side).
"""

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import numpy as np  # noqa: E402

import cfd  # noqa: E402
from aeroelastic.theodorsen import theodorsen_motion  # noqa: E402

GRID = dict(ni=129, nj=33, n_surface=80)


def setup(foil, mach, alpha_deg):
    t = time.perf_counter()
    grid = cfd.c_grid(cfd.naca(foil), **GRID)
    sol = cfd.solve_steady(grid, mach, alpha_deg)
    lin = cfd.linearise(sol)
    print(f"NACA{foil}, M{mach}, {alpha_deg} deg, grid {grid.shape[0]} x {grid.shape[1]}: Cl {sol.cl:.5f}, "
          f"Cm {sol.cm:.5f}, Cd {sol.cd:.6f} (steady + linearise {time.perf_counter() - t:.0f} s)")
    return sol, lin


def part_a():
    sol, lin = setup("0012", 0.5, 2.0)
    t = time.perf_counter()
    H0 = cfd.lfd_response(lin, [0.0], inputs=("pitch",), outputs=("Cl", "Cm", "Cd"), method="direct").H[:, 0, 0]
    print(f"LFD omega = 0 pitch ({time.perf_counter() - t:.0f} s): {np.round(H0.real, 6)}")
    slopes = {}
    for d in (0.2, 0.1, 0.05):
        loads = []
        for a in (sol.flow.alpha_deg - d, sol.flow.alpha_deg + d):
            s = cfd.solve_steady(lin.grid, sol.flow.mach, a, tol=1e-11, q0=sol.q, n_rk=0)
            loads.append(np.array([s.cl, s.cm, s.cd]))
        slopes[d] = (loads[1] - loads[0]) / np.radians(2 * d)
    print("| step d (deg) | dCl/da | dCm/da | dCd/da | truncation est. (S(d) - S(d/2)) 4/3, relative | LFD / S(d) - 1 |")
    print("| --- | --- | --- | --- | --- | --- |")
    for d in (0.2, 0.1):
        est = (slopes[d] - slopes[d / 2]) * 4 / 3 / slopes[d]
        gap = H0.real / slopes[d] - 1
        print(f"| {d} | {slopes[d][0]:.5f} | {slopes[d][1]:.5f} | {slopes[d][2]:.5f} | "
              f"{', '.join(f'{e:.1e}' for e in est)} | {', '.join(f'{g:.1e}' for g in gap)} |")
    rich = (4 * slopes[0.05] - slopes[0.1]) / 3
    print(f"Richardson (0.1, 0.05): {np.round(rich, 6)}; LFD / Richardson - 1 = {H0.real / rich - 1}")

    t = time.perf_counter()
    w = np.array([1e-3, 1e-2, 0.1])
    H = cfd.lfd_response(lin, w, inputs=("plunge", "pitch", "gust"), outputs=("Cl", "Cm", "Cd"), method="direct").H
    print(f"plunge low-frequency limit ({time.perf_counter() - t:.0f} s): H_h / (-i omega) against H_alpha(0) + "
          "(Cd0, 0, -Cl0) (wind axes fixed in a plunge)")
    expect = H0.real + np.array([sol.cd, 0.0, -sol.cl])
    for k, wk in enumerate(w):
        lim = H[:, 0, k] / (-1j * wk)
        print(f"  omega {wk:g}: Cl {lim[0]:.5f} ({abs(lim[0] / expect[0] - 1):.1e}), "
              f"Cm {lim[1]:.5f} ({abs(lim[1] / expect[1] - 1):.1e})")
    H2 = cfd.lfd_response(lin, w, inputs=("pitch",), pivot=0.6, outputs=("Cl", "Cm", "Cd"), method="direct").H
    err = np.abs(H2[:, 0] - (H[:, 1] + 0.35 * H[:, 0])).max() / np.abs(H2).max()
    print(f"pivot identity H_a(0.6) = H_a(0.25) + 0.35 H_h: max relative difference {err:.1e}")


def theodorsen_table(w, H, T, names):
    print("| output / input | k | abs(H_CFD) | abs(H_Th) | ratio to Th | ratio to Th-PG | arg H_CFD (deg) | "
          "arg H_Th (deg) | phase diff (deg) |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    beta = names["beta"]
    for i, out in enumerate(("Cl", "Cm")):
        for j, inp in enumerate(("plunge", "pitch")):
            for k, wk in enumerate(w):
                h, th = H[i, j, k], T[i, j, k]
                print(f"| {out} / {inp} | {wk / 2:g} | {abs(h):.4f} | {abs(th):.4f} | {abs(h) / abs(th):.4f} | "
                      f"{abs(h) / abs(th) * beta:.4f} | {np.angle(h, deg=True):.2f} | {np.angle(th, deg=True):.2f} | "
                      f"{np.angle(h / th, deg=True):+.2f} |")


def part_b():
    mach = 0.2
    beta = np.sqrt(1 - mach**2)
    sol, lin = setup("0006", mach, 0.0)
    k = np.array([0.05, 0.1, 0.2, 0.3, 0.5, 0.75, 1.0])
    w = np.concatenate([[0.0], 2 * k])
    t = time.perf_counter()
    frf = cfd.lfd_response(lin, w, inputs=("plunge", "pitch"), pivot=0.25, method="direct")
    t_direct = time.perf_counter() - t
    H = frf.H
    print(f"direct LFD, {w.size} frequencies, 2 inputs: {t_direct:.0f} s; pitch at omega = 0: Cl {H[0, 1, 0].real:.4f}"
          f" (2 pi / beta = {2 * np.pi / beta:.4f}, x (1 + 0.77 t/c) = {2 * np.pi / beta * (1 + 0.77 * 0.06):.4f}), "
          f"Cm {H[1, 1, 0].real:.5f}")
    T = theodorsen_motion(w, a=-0.5)
    theodorsen_table(w[1:], H[:, :, 1:], T[:, :, 1:], {"beta": beta})
    # normalised by the steady pitch slope: the unsteady dynamics without the steady-gain difference
    r = (H[0, :, 1:] / H[0, 1, 0].real) / (T[0, :, 1:] / T[0, 1, 0].real)
    print("Cl normalised by its own steady pitch slope, CFD / Theodorsen: magnitude - 1 and phase (deg)")
    for j, inp in enumerate(("plunge", "pitch")):
        print(f"  {inp}: " + ", ".join(f"k={kk:g}: {abs(x) - 1:+.3f} / {np.angle(x, deg=True):+.2f}"
                                       for kk, x in zip(k, r[j])))


def part_d():
    grid = cfd.c_grid(cfd.naca("0006"), ni=97, nj=25, n_surface=64)
    t = time.perf_counter()
    lin = cfd.linearise(cfd.solve_steady(grid, 0.2, 0.0))
    print(f"NACA0006, M0.2, 0 deg, grid 97 x 25: steady + linearise {time.perf_counter() - t:.0f} s")
    w = np.array([0.0, 0.1, 0.2, 0.4, 0.6, 1.0, 1.5, 2.0])
    inputs = ("gust", "plunge", "pitch")
    t = time.perf_counter()
    direct = cfd.lfd_response(lin, w, inputs=inputs, pivot=0.25, method="direct").H
    t_direct = time.perf_counter() - t
    t = time.perf_counter()
    fast = cfd.lfd_response(lin, w, inputs=inputs, pivot=0.25, method="fast", tol=1e-6, n_moments=8)
    t_fast = time.perf_counter() - t
    err = np.abs(fast.H - direct)
    est = np.asarray(fast.metadata["error_estimate"])
    for j, name in enumerate(inputs):
        print(f"  {name}: max |fast - direct| / max |H| = {err[:, j].max() / np.abs(direct[:, j]).max():.1e}, "
              f"max estimate / max |H| = {est[:, j].max() / np.abs(direct[:, j]).max():.1e}, "
              f"estimate >= error everywhere: {bool(np.all(est[:, j] >= err[:, j]))}")
    print(f"direct {t_direct:.0f} s ({w.size} factorisations), fast {t_fast:.0f} s ({len(fast.metadata['shifts'])} shifts,"
          f" basis {fast.metadata['basis_size']}) for all three inputs")


def harmonic(t, y, omega):
    M = np.stack([np.cos(omega * t), np.sin(omega * t), np.ones_like(t)], 1)
    c = np.linalg.lstsq(M, y, rcond=None)[0]
    return c[0] - 1j * c[1]


def part_c():
    sol, lin = setup("0012", 0.5, 2.0)
    w, A, s0 = 0.5, np.radians(0.5), 40.0
    H = cfd.lfd_response(lin, [w], inputs=("pitch",), method="direct").H[:, 0, 0]
    for dt in (0.1, 0.05):
        t = time.perf_counter()
        h = cfd.ltd_response(lin, None, dt, s0 + 2 * 2 * np.pi / w, pitch=lambda s: A * (1 - np.cos(w * s)))
        m = h.t >= s0
        r = np.array([harmonic(h.t[m], y[m], w) for y in (h.cl, h.cm)]) / harmonic(h.t[m], h.alpha[m], w)
        print(f"LTD dt = {dt} ({time.perf_counter() - t:.0f} s, BDF2 phase-rate error (omega dt)^2/3 = "
              f"{(w * dt) ** 2 / 3:.1e}): first harmonic over s >= {s0:g}")
        for i, out in enumerate(("Cl", "Cm")):
            print(f"  {out}: LTD {r[i]:.5f}, LFD {H[i]:.5f}: |LTD/LFD| - 1 = {abs(r[i] / H[i]) - 1:+.1e}, "
                  f"phase {np.angle(r[i] / H[i], deg=True):+.3f} deg")


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--part", choices=["A", "B", "C", "D"], required=True)
    part = ap.parse_args().part
    t0 = time.perf_counter()
    {"A": part_a, "B": part_b, "C": part_c, "D": part_d}[part]()
    print(f"part {part}: {time.perf_counter() - t0:.0f} s")
