"""Gust histories of the default ROMs against the LTD: the identification's price in the time domain.

For each paper case asked (``docs/data/frf-T*.npz``, T = 70/(2 pi)) and each order, the ROM of
``sysid.identify(frf, n, dc_gain="match", stable=True, algorithm=...)`` for each algorithm asked is driven by
the gust inputs of the LTD histories in a study store (the paper study's: ``lfdrom run studies/paper.toml``
first) and compared with them: the load-envelope error (``sysid.history_metrics.envelope_errors``) and the RMS
error, both in % of the LTD's peak, Cl / Cm, per gust.

Run: .venv/bin/python bench/rom_vs_ltd_bench.py --cases T4,T5 --orders 15,25,55
"""

import argparse
import glob
import json
import sys
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import sysid  # noqa: E402
from studies.cases import GUST_CASES, TEST_CASES  # noqa: E402
from sysid.history_metrics import envelope_errors  # noqa: E402
from sysid.simulate import rom_simulation  # noqa: E402


def ltd_histories(store):
    """``{(naca, mach): {gust name: (t, u, cl, cm)}}`` from the ``ltd`` entries of a study store."""
    names = {(g.kind, g.length, g.angle_deg): g.name for g in GUST_CASES.values()}
    out = {}
    for f in glob.glob(str(Path(store) / "ltd" / "*" / "*.json")):
        cfg = json.loads(Path(f).read_text())["body"]["config"]
        st, g = cfg["steady"], cfg["gust"]
        d = np.load(glob.glob(f[:-5] + "*.npz")[0])
        label = names.get((g["kind"], g["length"], g["angle_deg"]), f"{g['kind']} {g['length']}")
        out.setdefault((st["naca"], float(st["mach"])), {})[label] = (d["t"], d["u"], d["cl"], d["cm"])
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", default="T4,T5")
    ap.add_argument("--orders", default="15,25,55")
    ap.add_argument("--algorithms", default="relocation,subspace")
    ap.add_argument("--store", default=str(ROOT / "results" / "paper" / "store"))
    args = ap.parse_args(argv)
    hist = ltd_histories(args.store)
    print("case N_r algorithm FRF_max_err_Cl/Cm [%] | per gust: envelope Cl/Cm, RMS Cl/Cm [% of LTD peak]")
    for case in args.cases.split(","):
        spec = TEST_CASES[case]
        runs = hist.get((spec.naca, float(spec.mach)))
        if not runs:
            raise SystemExit(f"no LTD histories of {case} in {args.store}: run lfdrom run studies/paper.toml first")
        frf = sysid.FrequencyResponse.load(ROOT / "docs" / "data" / f"frf-{case}.npz")
        for n in map(int, args.orders.split(",")):
            for algorithm in args.algorithms.split(","):
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    res = sysid.identify(frf, n, dc_gain="match", stable=True, algorithm=algorithm)
                    A, B, C, D = (np.asarray(x, dtype=float) for x in (res.model.A, res.model.B, res.model.C,
                                                                        res.model.D))
                    cells = []
                    for label, (t, u, cl, cm) in sorted(runs.items()):
                        y = rom_simulation(A, B, C, D, frf.T, t, u)
                        env = [100 * envelope_errors(t, y[i], ref)[0] for i, ref in enumerate((cl, cm))]
                        rms = [100 * np.sqrt(np.mean((y[i] - ref) ** 2)) / np.abs(ref).max()
                               for i, ref in enumerate((cl, cm))]
                        cells.append(f"{label}: {env[0]:.1f}/{env[1]:.1f}, {rms[0]:.1f}/{rms[1]:.1f}")
                err = 100 * res.errors.max_rel_per_output
                print(f"{case} {n} {algorithm} {err[0]:.2f}/{err[1]:.2f} | " + " | ".join(cells), flush=True)


if __name__ == "__main__":
    main()
