"""Fast LFD sweep benchmark: ``cfd.sweep.fast_sweep`` against the direct path (``cfd.lfd.lfd_response``).

Cases T2 (NACA0010, M0.735) and T5 (NACA2410, M0.25), alpha 0, on the paper's 181 x 60 grid, SVM gust,
McKelvey grid M = 256, T = 70 / (2 pi) (257 frequencies, the last one omega = inf). Measured side by side
in one run, per case:

- one complex factorisation of ``J + i w V`` (nested dissection, as the direct path): the cost unit, and the
  speed-up against the best direct path a user could write with SciPy, one such complex factorisation per
  finite frequency (``vs complex-LU direct``: K - 1 times this LU over the fast sweep's time; the ``direct``
  column is the reference path's real 2n form, about 2x slower again); and, for each worker count k > 1 of
  ``--workers``, k complex factorisations side by side in k forked processes (one BLAS thread each), whose
  wall time over k is the per-frequency cost of a complex-LU direct path spread over k processes (``vs direct
  on as many processes``: the fair ratio for a sweep that uses k processes);
- the fast sweep from scratch (new basis), once per worker-process count of ``--workers`` (default ``1,2``:
  one process, then two shifts per greedy step factorised side by side in two forked processes): time,
  shifts, basis size, multiple of one factorisation;
- a second fast sweep with another T (``--T2-factor`` times T) reusing the basis: time, new shifts;
- the direct sweep, one ``lfd_response`` call per frequency (progress printed), over all frequencies or
  every k-th one (``--direct-every k``; its time is then scaled to the full grid and marked ``~``);
- the max relative error of Cl and Cm over the frequencies solved directly, and the error estimate's
  effectivity (estimate / true error; >= 1 means the estimate bounds the error).

Prints a Markdown table. Run: ``.venv/bin/python bench/lfd_sweep_bench.py [--case T2|T5|all]
[--direct-every 1] [--reference DIR]``; ``--reference DIR`` stores (and reuses) the direct values in
``DIR/ref_<case>.npz`` so that a rerun measures the fast path against the same reference (the table then
reports the direct time of the frequencies solved in this run only); ``--lin DIR`` likewise stores and reuses
the steady solution's ``LinearSystem`` (``DIR/<case>.pkl``), which the stored reference belongs to.
"""

import argparse
import os
import pickle
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

import cfd
import sysid
from cfd.lfd import lfd_response
from cfd.ordering import nested_dissection, unknown_permutation
from cfd.sweep import SweepBasis, fast_sweep

CASES = {"T2": ("0010", 0.735), "T5": ("2410", 0.25)}
T0 = 70 / (2 * np.pi)


def log(msg):
    print(f"[{time.strftime('%H:%M:%S')}] {msg}", flush=True)


def one_factorisation(lin, omega=1.0):
    perm = unknown_permutation(nested_dissection(lin.grid))
    A = (lin.J + sp.diags(1j * lin.to_solver_frequency(omega) * lin.V)).tocsr()
    t = time.perf_counter()
    spla.splu(A[perm][:, perm].tocsc(), permc_spec="NATURAL", diag_pivot_thresh=0.0,
              options=dict(SymmetricMode=True))
    return time.perf_counter() - t


def factorisations_side_by_side(lin, workers):
    """Wall time of ``workers`` complex factorisations in as many forked processes (one BLAS thread each),
    divided by ``workers``: the per-frequency cost of a direct path spread over that many processes."""
    from concurrent.futures import ProcessPoolExecutor
    import multiprocessing as mp

    from threadpoolctl import threadpool_limits

    with ProcessPoolExecutor(workers, mp_context=mp.get_context("fork"),
                             initializer=threadpool_limits, initargs=(1,)) as pool:
        list(pool.map(int, range(workers)))          # start the processes first
        times = list(pool.map(one_factorisation, [lin] * workers, [1.0 + k for k in range(workers)]))
        return max(times) / workers                  # each timed in its process, all running together


def direct(lin, w, every, ref_path, deadline=None):
    """Direct values (Cl, Cm) at every ``every``-th frequency; returns H (2, K) with NaN where not solved."""
    H = np.full((2, w.size), np.nan, complex)
    if ref_path and os.path.exists(ref_path):
        d = np.load(ref_path)
        if d["H"].shape[1] == w.size and np.allclose(d["omega"], w):
            H = d["H"][:2].copy()
            log(f"  reference: {np.sum(~np.isnan(H[0]))} stored direct values from {ref_path}")
    todo = [k for k in range(0, w.size, every) if np.isnan(H[0, k])]
    t_total, n = 0.0, 0
    for i, k in enumerate(todo):
        if deadline and time.time() > deadline:
            log(f"  direct: deadline reached after {i} of {len(todo)} frequencies")
            break
        t = time.perf_counter()
        H[:, k] = lfd_response(lin, [w[k]]).H[:, 0, 0]
        t_total += time.perf_counter() - t
        n += 0 if np.isinf(w[k]) else 1
        if i % 8 == 0 or i == len(todo) - 1:
            log(f"  direct {i + 1}/{len(todo)}: omega = {w[k]:.4g}, {t_total / max(n, 1):.1f} s per frequency")
        if ref_path:
            np.savez(ref_path, H=H, omega=w)
    return H, t_total, n


def linear_system(name, lin_dir=None, ni=181, nj=60, n_surface=100):
    """The ``LinearSystem`` of case ``name`` (alpha 0): loaded from ``lin_dir/<name>.pkl`` when there, else from a
    steady solve to 1e-10 on the ``ni`` x ``nj`` C-grid (stored there when ``lin_dir`` is given)."""
    foil, mach = CASES[name]
    cached = os.path.join(lin_dir, f"{name}.pkl") if lin_dir else None
    if cached and os.path.exists(cached):
        with open(cached, "rb") as f:
            lin = pickle.load(f)
        log(f"{name}: NACA{foil} M{mach}, linear system loaded from {cached} (grid {lin.grid.shape})")
        return lin
    log(f"{name}: NACA{foil} M{mach}, grid {ni} x {nj}, steady solve ...")
    grid = cfd.c_grid(cfd.naca(foil), ni=ni, nj=nj, n_surface=n_surface)
    lin = cfd.linearise(cfd.solve_steady(grid, mach, 0.0, tol=1e-10))
    if cached:
        with open(cached, "wb") as f:
            pickle.dump(lin, f)
    return lin


def run_case(name, args):
    foil, mach = CASES[name]
    lin = linear_system(name, args.lin, args.ni, args.nj, args.n_surface)
    omega_d, w = sysid.mckelvey_grid(args.M, T0)
    t_lu = one_factorisation(lin)
    log(f"  one complex factorisation: {t_lu:.2f} s ({lin.n} unknowns)")
    t_lu_par = {k: factorisations_side_by_side(lin, k) for k in args.workers if k > 1}
    for k, t in t_lu_par.items():
        log(f"  {k} complex factorisations side by side in {k} processes: {t:.2f} s per factorisation")

    fast = [fast_sweeps(lin, omega_d, w, args, workers) for workers in args.workers]

    ref_path = os.path.join(args.reference, f"ref_{name}.npz") if args.reference else None
    Hd, t_direct, n_direct = direct(lin, w, args.direct_every, ref_path, args.deadline)
    solved = ~np.isnan(Hd[0]) & np.isfinite(w)
    n_fin = int(np.isfinite(w).sum())
    full = n_direct == n_fin
    t_direct_full = t_direct / max(n_direct, 1) * n_fin
    rows = []
    for f in fast:
        H = f["frf"].H[:, 0]
        err = np.abs(H - Hd)[:, solved]
        rel = err / np.abs(Hd[:, solved])
        est = np.asarray(f["frf"].metadata["error_estimate"])[:, solved]
        sig = err > 1e-13 * np.abs(Hd[:, solved])
        eff = est[sig] / err[sig] if np.any(sig) else np.array([np.inf])
        frf2 = f["frf2"]
        est_rel2 = np.max(np.asarray(frf2.metadata["error_estimate"])[:, :-1] / np.abs(frf2.H[:, 0, :-1]))
        rows.append({
            "case": f"{name} NACA{foil} M{mach}", "workers": f["workers"], "n": lin.n, "lu": t_lu,
            "lu_par": t_lu_par.get(f["workers"], t_lu),
            "fast": f["t_fast"], "direct": t_direct_full, "direct_full": full, "n_direct": int(solved.sum()),
            "shifts": f["shifts"], "m": f["m"], "n_bs": f["n_bs"], "rel_cl": rel[0].max(), "rel_cm": rel[1].max(),
            "est_max": np.max(est / np.abs(Hd[:, solved])), "eff_min": eff.min(), "eff_med": np.median(eff),
            "second": f["t_second"], "new_shifts": f["new_shifts"], "est2": est_rel2, "K": w.size,
            "tol_met": f["frf"].metadata["tol_met"] and frf2.metadata["tol_met"], "timings": f["timings"]})
    return rows


def fast_sweeps(lin, omega_d, w, args, workers):
    """The fast sweep from a new basis, then a second one at another T on the same basis."""
    basis = SweepBasis(lin, outputs=("Cl", "Cm"), n_moments=args.n_moments)
    t0 = time.perf_counter()

    def progress(b, worst, failing):
        log(f"  fast ({workers} worker(s)): {len(b.shifts)} shifts, m = {b.size}, worst est/allowance = "
            f"{worst:.2e}, {failing.size} frequencies above tol")

    frf = fast_sweep(lin, (omega_d, w), basis=basis, tol=args.tol, max_shifts=args.max_shifts, progress=progress,
                     workers=workers)
    t_fast = time.perf_counter() - t0
    n_shifts, n_bs, m = len(basis.shifts), basis.timings["n_back_substitute"], basis.size
    timings = dict(basis.timings)
    log(f"  fast sweep ({workers} worker(s)): {t_fast:.1f} s, shifts {np.round(basis.shifts, 3).tolist()}, "
        f"m = {basis.size}; seconds (summed over processes) {({k: round(v, 1) for k, v in timings.items()})}")
    T2 = args.T2_factor * T0
    t0 = time.perf_counter()
    frf2 = fast_sweep(lin, sysid.mckelvey_grid(args.M, T2), basis=basis, tol=args.tol, max_shifts=args.max_shifts,
                      workers=workers)
    t_second = time.perf_counter() - t0
    new_shifts = len(basis.shifts) - n_shifts
    log(f"  second sweep (T = {T2:.3f}): {t_second:.1f} s, {new_shifts} new shifts")
    return {"workers": workers, "frf": frf, "frf2": frf2, "t_fast": t_fast, "t_second": t_second,
            "shifts": n_shifts, "m": m, "n_bs": n_bs, "new_shifts": new_shifts, "timings": timings}


def table(rows):
    out = ["| case | workers | 1 LU (s) | direct (s) | fast (s) | speed-up | vs complex-LU direct | fast / LU "
           "| per freq. / LU | vs direct on as many processes | shifts | m | max rel err Cl | max rel err Cm "
           "| max est/|H| | est/err min (median) | 2nd T (s) | 2nd T new shifts |",
           "|---" * 18 + "|"]
    for r in rows:
        d = ("" if r["direct_full"] else "~") + f"{r['direct']:.0f}"
        out.append(
            f"| {r['case']} | {r['workers']} | {r['lu']:.2f} | {d} | {r['fast']:.1f} "
            f"| {r['direct'] / r['fast']:.0f}x "
            f"| {(r['K'] - 1) * r['lu'] / r['fast']:.1f}x "
            f"| {r['fast'] / r['lu']:.1f} | {r['fast'] / r['lu'] / (r['K'] - 1):.3f} "
            f"| {(r['K'] - 1) * r['lu_par'] / r['fast']:.1f}x | {r['shifts']} | {r['m']} "
            f"| {r['rel_cl']:.1e} | {r['rel_cm']:.1e} | {r['est_max']:.1e} | {r['eff_min']:.1f} ({r['eff_med']:.0f}) "
            f"| {r['second']:.1f} | {r['new_shifts']} |")
    return "\n".join(out)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--case", default="all", choices=["T2", "T5", "all"])
    ap.add_argument("--M", type=int, default=256)
    ap.add_argument("--tol", type=float, default=1e-8)
    ap.add_argument("--max-shifts", type=int, default=16)
    ap.add_argument("--n-moments", type=int, default=16)
    ap.add_argument("--T2-factor", type=float, default=0.5, help="second sweep at T2 = factor * 70 / (2 pi)")
    ap.add_argument("--direct-every", type=int, default=1, help="solve directly every k-th frequency only")
    ap.add_argument("--ni", type=int, default=181)
    ap.add_argument("--nj", type=int, default=60)
    ap.add_argument("--n-surface", type=int, default=100)
    ap.add_argument("--workers", type=lambda v: [int(x) for x in v.split(",")], default=[1, 2],
                    help="comma-separated worker-process counts of the fast sweep, each run from a new basis")
    ap.add_argument("--deadline", type=float, default=None, help="stop the direct solves at this Unix time")
    ap.add_argument("--lin", default=None, help="directory to store / reuse the linear systems (<case>.pkl)")
    ap.add_argument("--reference", default=None, help="directory to store / reuse the direct values")
    args = ap.parse_args(argv)
    log(f"load average at start: {os.getloadavg()}")
    rows = [row for c in (["T2", "T5"] if args.case == "all" else [args.case]) for row in run_case(c, args)]
    log(f"load average at end: {os.getloadavg()}")
    print()
    print(table(rows))
    print()
    for r in rows:
        print(f"{r['case']} ({r['workers']} worker(s)): direct solved at {r['n_direct']} of {r['K'] - 1} finite "
              "frequencies"
              f"{'' if r['direct_full'] else ' (direct time scaled to all)'}; {r['n_bs']} back-substitutions; "
              f"tol met: {r['tol_met']}; second sweep max est/|H| = {r['est2']:.1e}")


if __name__ == "__main__":
    main()
