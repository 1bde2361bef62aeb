"""ROM against LTD: the 1-cosine gust G3 (one chord, 5 deg) on case T2 (NACA0010, M0.735), timed side by side.

The ROM is identified from the LFD response on McKelvey's grid (M = 32 by default, T = 70 / (2 pi)), mapped to
continuous time (paper Eq. 26), re-discretised at the LTD step by Tustin and simulated with python-control
(``sysid.rom_simulation``, exactly what a study does); the LTD response is the BDF2 march of
``cfd.ltd_response`` at the same step. Both start from rest with the gust front at x0 = -2. Prints a table:
the wall time of each (the ROM's best of ``--repeat`` runs), their ratio (target >= 1e4), and the peak Cl
and Cm of both. The identification and the LFD sweep are one-off costs and are printed for context.

Run: ``.venv/bin/python bench/rom_bench.py`` (paper grid 181 x 60, a few minutes on two cores) or
``--coarse`` (81 x 20, seconds). ``--order``, ``--M``, ``--dt``, ``--t-end`` change the setting.
"""

import argparse
import sys
import time
import warnings
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout

import numpy as np

import cfd
import sysid
from studies.config.cases import flow_case, gust_case, to_gust
from studies.config.schema import T_PAPER, CFDOptions
from studies.sections.gust_rom.tasks import lfd_on_mckelvey_grid
from sysid import peak, rom_simulation


def timed(f):
    t = time.perf_counter()
    out = f()
    return time.perf_counter() - t, out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--coarse", action="store_true", help="81 x 20 grid (48 cells on the aerofoil) instead of 181 x 60")
    ap.add_argument("--order", type=int, default=15, help="ROM order N_r (default 15)")
    ap.add_argument("--M", type=int, default=32, help="LFD grid intervals, N_omega = M + 1 (default 32)")
    ap.add_argument("--dt", type=float, default=0.02, help="time step (convective, default 0.02)")
    ap.add_argument("--t-end", type=float, default=40.0, help="final time (convective, default 40)")
    ap.add_argument("--repeat", type=int, default=5, help="ROM simulations timed (best kept, default 5)")
    args = ap.parse_args(argv)

    case = flow_case("T2")
    sizes = dict(ni=81, nj=20, n_surface=48) if args.coarse else case.grid.kwargs()
    grid = cfd.c_grid(cfd.naca(case.naca), **sizes)
    t_steady, sol = timed(lambda: cfd.solve_steady(grid, case.mach, case.alpha_deg))
    t_lin, lin = timed(lambda: cfd.linearise(sol))
    gust = to_gust(gust_case("G3"), x0=-2.0)

    t_ltd, hist = timed(lambda: cfd.ltd_response(lin, gust, args.dt, args.t_end))
    t_frf, (frf, how) = timed(lambda: lfd_on_mckelvey_grid(lin, T_PAPER, args.M, CFDOptions()))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        t_id, res = timed(lambda: sysid.identify(frf, args.order))
    m = res.model
    A, B, C, D = (np.asarray(x) for x in (m.A, m.B, m.C, m.D))
    times = []
    for _ in range(max(1, args.repeat)):
        t, Y = timed(lambda: rom_simulation(A, B, C, D, T_PAPER, hist.t, hist.u, "tustin"))
        times.append(t)
    t_rom = min(times)

    n = hist.t.size - 1
    print(f"T2 + G3, grid {sizes['ni']} x {sizes['nj']} ({lin.n} unknowns), dt = {args.dt}, {n} steps to s = "
          f"{args.t_end}; ROM N_r = {args.order} from M = {args.M} ({how} LFD), Tustin at dt")
    print()
    print("| | wall time (s) | peak Cl | at s | peak Cm | at s |")
    print("| --- | ---: | ---: | ---: | ---: | ---: |")
    for name, secs, cl, cm in (("LTD (BDF2 march)", t_ltd, hist.cl, hist.cm),
                               ("ROM (re-discretise + simulate)", t_rom, Y[0], Y[1])):
        (pl, tl), (pm, tm) = peak(hist.t, cl), peak(hist.t, cm)
        print(f"| {name} | {secs:.4g} | {pl:.4f} | {tl:.2f} | {pm:.5f} | {tm:.2f} |")
    print(f"| ratio LTD / ROM | {t_ltd / t_rom:.3g} | | | | |")
    print()
    err = abs(peak(hist.t, Y[0])[0] - peak(hist.t, hist.cl)[0]) / abs(peak(hist.t, hist.cl)[0])
    print(f"peak Cl error of the ROM {100 * err:.2f} %; FRF max error {res.max_error:.3g} on the M + 1 points")
    print(f"one-off costs: steady {t_steady:.1f} s, linearise {t_lin:.2f} s, LFD sweep {t_frf:.1f} s "
          f"({args.M + 1} frequencies), identification {t_id:.2f} s")
    ratio = t_ltd / t_rom
    print(f"speed-up {ratio:.3g} ({'meets' if ratio >= 1e4 else 'misses'} the 1e4 target)")
    return ratio


if __name__ == "__main__":
    main()
