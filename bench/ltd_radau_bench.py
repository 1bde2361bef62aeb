"""LTD time schemes side by side on a paper case: BDF2 at dt 0.02 against Radau IIA (``scheme="radau5"``).

1. Sine gusts at the paper's gust frequency scales (omega = 0.2 pi: G4's, 2 pi: G2/G3's, 4 pi: G1's), each
   started on the LFD periodic state (the exact linear answer, ``cfd.lfd.lfd_state``) and marched two periods:
   the relative error of the complex amplitude of Cl and Cm fitted on the second period, against the LFD.
2. The case's six paper gusts G1-G6 marched together to s = 40 (the paper study's LTD piece): wall time of
   each scheme with its factorisations, per gust, and the max error of each history (relative to its peak)
   against a reference march (Radau IIA with step 0.04, whose error is about (0.04 / 0.14)^5 ~ 2e-3 of the
   default step's).

Both schemes write the loads on the same dt = 0.02 grid (Radau IIA through its collocation polynomial).
BLAS runs one thread (as in the study's workers and inside ``cfd.ltd``).

Run: ``.venv/bin/python bench/ltd_radau_bench.py [--case T2] [--lin FILE.pkl] [--skip-reference]``
(about 15 min for T2 on the 2-core machine).
"""

import argparse
import os
import pickle
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout

import numpy as np  # noqa: E402
from threadpoolctl import threadpool_limits  # noqa: E402

import cfd  # noqa: E402
from cfd.lfd import lfd_state  # noqa: E402
from cfd.ltd import ltd_response, ltd_responses, radau_steps, radau_substeps  # noqa: E402

SCHEMES = [("BDF2", "bdf2", None), ("Radau IIA, step 0.14", "radau5", 0.14), ("Radau IIA, step 0.1", "radau5", 0.1)]
DT = 0.02


def load_lin(case, path):
    from studies.config.cases import flow_case

    if path and os.path.exists(path):
        with open(path, "rb") as f:
            return pickle.load(f)
    c = flow_case(case)
    grid = cfd.c_grid(c.foil())
    lin = cfd.linearise(cfd.solve_steady(grid, c.mach, c.alpha_deg))
    if path:
        with open(path, "wb") as f:
            pickle.dump(lin, f)
    return lin


def harmonic(t, y, omega):
    """Complex amplitude ``a`` of ``Re(a exp(i omega t))`` fitted (with a constant) to ``y(t)``."""
    M = np.stack([np.cos(omega * t), np.sin(omega * t), np.ones_like(t)], 1)
    c = np.linalg.lstsq(M, y, rcond=None)[0]
    return c[0] - 1j * c[1]


def sine_errors(lin, omega, scheme, step):
    """Relative errors of the Cl and Cm amplitudes after two periods started on the LFD state; wall time."""
    gust = cfd.SineGust(angle_deg=1.0, omega=omega)
    qh = (1j * gust.amplitude) * lfd_state(lin, omega)        # u(s) = Re(i A exp(i omega s)) at x_ref = 0
    exact = lin.C[:2] @ qh
    period = 2.0 * np.pi / omega
    t_end = DT * round(2.0 * period / DT)
    q_prev = np.real(qh * np.exp(-1j * omega * DT))
    t0 = time.perf_counter()
    h = ltd_response(lin, gust, DT, t_end, initial=(q_prev, qh.real), max_phase_error=1.0, scheme=scheme,
                     step=step)
    seconds = time.perf_counter() - t0
    last = h.t >= h.t[-1] - DT * round(period / DT) - 1e-9
    got = [harmonic(h.t[last], y[last], omega) for y in (h.cl, h.cm)]
    return [abs(g - e) / abs(e) for g, e in zip(got, exact)], seconds


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--case", default="T2")
    ap.add_argument("--lin", default=None, help="pickle file to store / reuse the case's linear system")
    ap.add_argument("--skip-reference", action="store_true", help="no reference march (no history errors)")
    args = ap.parse_args()
    from studies.config.cases import gust_case, to_gust

    with threadpool_limits(limits=1, user_api="blas"):
        t0 = time.perf_counter()
        lin = load_lin(args.case, args.lin)
        print(f"{args.case}, 181 x 60, {lin.n} unknowns (linear system {time.perf_counter() - t0:.0f} s)")
        print("\n1. Sine gust started on the LFD periodic state, two periods: |a - a_LFD| / |a_LFD| of Cl / Cm "
              "(wall s)\n")
        omegas = [0.2 * np.pi, 2.0 * np.pi, 4.0 * np.pi]
        print("| scheme | " + " | ".join(f"omega = {w / np.pi:g} pi" for w in omegas) + " |")
        print("|---|" + "---|" * len(omegas))
        for name, scheme, step in SCHEMES:
            cells = []
            for w in omegas:
                (e_cl, e_cm), s = sine_errors(lin, w, scheme, step)
                cells.append(f"{e_cl:.1e} / {e_cm:.1e} ({s:.0f} s)")
            print(f"| {name} | " + " | ".join(cells) + " |", flush=True)

        names = ["G1", "G2", "G3", "G4", "G5", "G6"]
        gusts = [to_gust(gust_case(n), x0=-2.0) for n in names]
        t_end = 40.0
        print(f"\n2. Six gusts G1-G6 marched together to s = {t_end} (five columns: G2 and G3 share one), "
              f"loads every dt = {DT}\n")
        runs = {}
        for name, scheme, step in SCHEMES:
            t0 = time.perf_counter()
            runs[name] = ltd_responses(lin, gusts, DT, t_end, max_phase_error=1.0, scheme=scheme, step=step)
            seconds = time.perf_counter() - t0
            n = round(t_end / DT)
            steps = n if scheme == "bdf2" else radau_steps(n, radau_substeps(DT, step))
            print(f"  {name:22s} {seconds:7.1f} s  ({steps} steps, {seconds / len(gusts):.1f} s per gust)",
                  flush=True)
        if args.skip_reference:
            return
        t0 = time.perf_counter()
        ref = ltd_responses(lin, gusts, DT, t_end, max_phase_error=1.0, scheme="radau5", step=0.04)
        print(f"  reference (Radau IIA, step 0.04) {time.perf_counter() - t0:.1f} s")
        print("\nMax error of each history against the reference, in % of its peak, Cl / Cm:\n")
        print("| scheme | " + " | ".join(names) + " |")
        print("|---|" + "---|" * len(names))
        for name, _, _ in SCHEMES:
            cells = []
            for h, r in zip(runs[name], ref):
                e = [100 * np.abs(a - b).max() / np.abs(b).max() for a, b in ((h.cl, r.cl), (h.cm, r.cm))]
                cells.append(f"{e[0]:.2g} / {e[1]:.2g}")
            print(f"| {name} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
