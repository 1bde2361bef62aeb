"""Vector fitting's accuracy at the fewest states: the order and time the default identification needs to be at or
below stable vector fitting (VF) on both outputs, against VF's order and time.

Run: ``python bench/sysid_equal_error_bench.py`` (about a minute on the 2-core machine; ``--orders`` VF's state
counts, default ``10,15,25,40,55,60``; ``--data`` adds any ``sysid.FrequencyResponse`` ``.npz``, e.g. the held-out
FRFs of ``bench/heldout_frfs.py``; ``--cases ""`` leaves out the paper's). Prints one Markdown table and a summary.

``bench/sysid_peers_bench.py`` compares the two at *equal order*; a loads engineer asks the other question: what
does a ROM of a given accuracy cost, to identify and then to simulate (whose cost grows with the state count)?
For each case and VF order ``n``: VF as in ``sysid_peers_bench.run_vf`` (best stable fit of the log and linear
starts, ``enforce_dc``; its time includes both starts; "VF gain between": its largest gain on a grid 8 times
denser than the data's, in units of the output's data peak, as in ``sysid_peers_bench``: far above 1, the model
resonates where nothing was measured), then the smallest order ``m`` of :data:`LADDER` at which
``sysid.identify(frf, m, dc_gain="match", stable=True)`` has a max error (in % of each output's peak, over all
samples) at or below VF's on both outputs, and that fit's time. Both timed once after a warm-up fit; BLAS limited
to one thread. ``-`` when no order of the ladder up to 60 reaches VF's errors.
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import sys
import time
import warnings
from pathlib import Path

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "bench"))

import sysid  # noqa: E402
from sysid.metrics import max_relative_error  # noqa: E402
from sysid_peers_bench import CASES, label, load, run_vf  # noqa: E402

#: The orders tried for the default, smallest first.
LADDER = (4, 6, 8, 10, 12, 15, 20, 25, 30, 35, 40, 45, 50, 55, 60)


def default_fit(frf, m):
    """``(max error per output (p,), seconds)`` of the default identification at order ``m``."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t0 = time.perf_counter()
        res = sysid.identify(frf, m, dc_gain="match", stable=True)
        t = time.perf_counter() - t0
    return max_relative_error(res.evaluate(frf.omega_d), frf.H, per_output=True), t


def smallest_order(frf, target, cache):
    """The first order of :data:`LADDER` whose default fit is at or below ``target`` (p,) on every output, with
    its errors and time (``None`` when none is); fits are kept in ``cache`` (order -> (errors, seconds))."""
    for m in LADDER:
        if m not in cache:
            cache[m] = default_fit(frf, m)
        err, t = cache[m]
        if np.all(err <= target):
            return m, err, t
    return None


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--orders", default="10,15,25,40,55,60", help="VF's state counts")
    ap.add_argument("--cases", default=",".join(CASES))
    ap.add_argument("--data", default="", help="comma-separated FrequencyResponse .npz files to add")
    args = ap.parse_args(argv)
    orders = [int(x) for x in args.orders.split(",") if x]
    cases = [c for c in args.cases.split(",") if c] + [d for d in args.data.split(",") if d]

    print(f"# Default identification at VF's accuracy ({datetime.date.today()}, {platform.node()}, "
          f"{os.cpu_count()} CPUs)\n")
    print("| case | VF order | VF error per output (%) | VF gain between | VF s | default order | default error (%) | "
          "default s | time / VF | states / VF |")
    print("| --- | ---: | --- | ---: | ---: | ---: | --- | ---: | ---: | ---: |")
    ratios, state_ratios = {}, {}
    first = True
    for case in cases:
        frf = load(case)
        if first:   # warm-up of both methods (imports, caches)
            default_fit(frf, 10)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                run_vf(frf, 10)
            first = False
        cache = {}
        for n in orders:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                vf = run_vf(frf, n)
            ev = max_relative_error(vf["H"], frf.H, per_output=True)
            hit = smallest_order(frf, ev, cache)
            vf_err = " / ".join(f"{100 * e:.3g}" for e in ev) + f" | {np.max(vf['gain']):.3g}"
            if hit is None:
                print(f"| {label(case)} | {n} | {vf_err} | {vf['time']:.3f} | - | - | - | - | - |", flush=True)
                continue
            m, err, t = hit
            ratios.setdefault(n, []).append(t / vf["time"])
            state_ratios.setdefault(n, []).append(m / n)
            print(f"| {label(case)} | {n} | {vf_err} | {vf['time']:.3f} | {m} | "
                  f"{' / '.join(f'{100 * e:.3g}' for e in err)} | {t:.3f} | {t / vf['time']:.2f} | {m / n:.2f} |",
                  flush=True)
    print()
    allr = [r for v in ratios.values() for r in v]
    if allr:
        per = "; ".join(f"{n}: {np.median(v):.2f} ({min(v):.2f} - {max(v):.2f})" for n, v in sorted(ratios.items()))
        print(f"default / VF time at VF's accuracy, median per VF order (min - max): {per}; all: {np.median(allr):.2f}.")
        sr = [r for v in state_ratios.values() for r in v]
        print(f"states / VF's: median {np.median(sr):.2f} (min {min(sr):.2f}, max {max(sr):.2f}); reached at "
              f"{len(allr)} of {len(cases) * len(orders)} points.")


if __name__ == "__main__":
    main()
