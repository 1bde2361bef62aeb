"""The dedicated minimax cone solver (:mod:`sysid.minimax_socp`) against Clarabel on the programmes that
:func:`sysid.residues.socp_minimax` receives during ``identify(frf, n, dc_gain="match", stable=True)``.

Run: ``python bench/minimax_socp_bench.py`` (``--cases T1,T4 --orders 10,25,55 --per-fit 6 --repeats 5``).

For every paper case and order the fit runs once (Clarabel path) with the programmes recorded (``socp_minimax``
wrapped);
up to ``--per-fit`` of them are kept (spread over the fit, the bounded ones included). Each kept programme is
then solved ``--repeats`` times by each solver, alternating (the machine may be loaded: ratios side by side),
and the table gives per order the median time of each and the median of the per-programme ratios
Clarabel / dedicated, the worst relative difference of the levels ``max_k |Q_k y - g_k|`` and the number of
programmes the dedicated solver returned None on (Clarabel's fallback in ``socp_minimax``). BLAS one thread.

Measured 2026-12-04 on the loaded 2-core machine (``--orders 10,15,20,25,40,55``, 5 repeats), median
Clarabel / dedicated time per programme: N = 11 1.18, 16 1.33, 21 1.48, 26 1.62, 41 2.31, 56 2.71 (hence
:data:`sysid.residues.DEDICATED_MIN_UNKNOWNS` = 24); all 94 programmes 0.95 s against 1.90 s; no fallbacks;
levels equal to 1.3e-8 relative or better (Clarabel's round-off on the bounds).

The whole identification (``python bench/sysid_peers_bench.py --methods default,VF --orders
10,15,25,40,55,60``, this solver against Clarabel alone in alternate runs, three each, same day and machine):
default / VF time, median over all points 2.3-2.5 against 2.7-2.9; per order (median over the cases) N_r 40
2.5-2.8 against 3.3-3.4, 55 3.5-3.9 against 3.9-4.4, 60 2.6-2.9 against 3.4-3.8, 10-25 unchanged. Errors
(max relative, per output) moved by at most 9e-7 relative (T5 N_r 40), 5 of 36 points by more than 1e-9.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
import warnings
from pathlib import Path

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import sysid  # noqa: E402
from sysid import residues  # noqa: E402
from sysid.minimax_socp import minimax_socp  # noqa: E402


def capture(case, n, per_fit=6):
    """The ``(Q, g, E, f, Qb, ub)`` programmes of one default stable fit (``per_fit`` of them, spread, with
    every bounded one's share kept: half the picks from the bounded ones when there are any)."""
    frf = sysid.FrequencyResponse.load(str(ROOT / "docs" / "data" / f"frf-{case}.npz"))
    seen = []
    original = residues.socp_minimax

    def record(Q, g, E, f, tol=1e-9, Qb=None, ub=None, within=None):
        seen.append((Q.copy(), g.copy(), E.copy(), f.copy(), None if Qb is None else Qb.copy(),
                     None if ub is None else ub.copy()))
        return original(Q, g, E, f, tol=tol, Qb=Qb, ub=ub, within=within)

    residues.socp_minimax = record
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            sysid.identify(frf, n, dc_gain="match", stable=True)
    finally:
        residues.socp_minimax = original
    bounded = [p for p in seen if p[4] is not None and p[4].shape[0]]
    free = [p for p in seen if not (p[4] is not None and p[4].shape[0])]

    def spread(ps, k):
        if len(ps) <= k:
            return ps
        return [ps[i] for i in np.unique(np.linspace(0, len(ps) - 1, k).round().astype(int))]

    kb = min(len(bounded), per_fit // 2)
    return spread(free, per_fit - kb) + spread(bounded, kb), len(seen)


def level(Q, g, y):
    return float(np.abs(Q @ y - g).max())


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", default="T1,T2,T3,T4,T5,T6")
    ap.add_argument("--orders", default="10,25,55")
    ap.add_argument("--per-fit", type=int, default=6)
    ap.add_argument("--repeats", type=int, default=5)
    a = ap.parse_args(argv)
    residues.DEDICATED_SOLVER = False  # the fits and the reference solves by Clarabel (the previous path)
    rows = []
    for n in [int(v) for v in a.orders.split(",")]:
        for case in a.cases.split(","):
            progs, total = capture(case, n, a.per_fit)
            for Q, g, E, f, Qb, ub in progs:
                tn, tc = [], []
                for _ in range(a.repeats):
                    t0 = time.perf_counter()
                    y1, info = minimax_socp(Q, g, E, f, Qb=Qb, ub=ub)
                    t1 = time.perf_counter()
                    y2, _ = residues.socp_minimax(Q, g, E, f, Qb=Qb, ub=ub)  # Clarabel: flag off
                    t2 = time.perf_counter()
                    tn.append(t1 - t0)
                    tc.append(t2 - t1)
                rel = np.nan
                if y1 is not None and y2 is not None:
                    l1, l2 = level(Q, g, y1), level(Q, g, y2)
                    rel = abs(l1 - l2) / max(l2, 1e-300)
                rows.append(dict(n=n, case=case, N=Q.shape[1], K=Q.shape[0], J=0 if Qb is None else Qb.shape[0],
                                 tn=np.median(tn), tc=np.median(tc), it=info["iterations"], none=y1 is None,
                                 rel=rel, total=total))
            print(f"# {case} N_r {n}: {total} programmes in the fit, {len(progs)} kept", flush=True)
    print("\n| N_r | programmes | N | bounded | dedicated median ms | Clarabel median ms | ratio median "
          "(Clarabel / dedicated) | ratio min | iterations median | fell back | max level rel diff |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for n in sorted({r["n"] for r in rows}):
        rs = [r for r in rows if r["n"] == n]
        ratio = np.array([r["tc"] / r["tn"] for r in rs])
        rel = np.array([r["rel"] for r in rs])
        print(f"| {n} | {len(rs)} | {min(r['N'] for r in rs)}-{max(r['N'] for r in rs)} | "
              f"{sum(r['J'] > 0 for r in rs)} | {1e3 * np.median([r['tn'] for r in rs]):.2f} | "
              f"{1e3 * np.median([r['tc'] for r in rs]):.2f} | {np.median(ratio):.2f} | {ratio.min():.2f} | "
              f"{np.median([r['it'] for r in rs]):.0f} | {sum(r['none'] for r in rs)} | "
              f"{np.nanmax(rel) if np.isfinite(rel).any() else np.nan:.1e} |")
    ratio = np.array([r["tc"] / r["tn"] for r in rows])
    print(f"\nall: {len(rows)} programmes, ratio median {np.median(ratio):.2f}, "
          f"total time dedicated {sum(r['tn'] for r in rows):.3f} s, Clarabel {sum(r['tc'] for r in rows):.3f} s")


if __name__ == "__main__":
    main()
