"""Gust histories of the default ROMs against the LTD: the identification's price in the time domain.

For each paper case asked (``docs/data/frf-T*.npz``, T = 70/(2 pi)) and each order, the ROM of
``sysid.identify(frf, n, dc_gain="match", stable=True, algorithm=...)`` for each algorithm asked is driven by
the gust inputs of the LTD histories of a computed study (the paper study's: ``lfdrom run studies/paper.toml``
first; ``studies.store.results.load_results`` reads them) and compared with them: the load-envelope error (``sysid.history_metrics.envelope_errors``) and the RMS
error, both in % of the LTD's peak, Cl / Cm, per gust.

Run: .venv/bin/python bench/rom_vs_ltd_bench.py --cases T4,T5 --orders 15,25,55
"""

import argparse
import sys
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import sysid  # noqa: E402
from studies.store.results import load_results  # noqa: E402
from sysid.history_metrics import envelope_errors  # noqa: E402
from sysid.simulate import rom_simulation  # noqa: E402


def ltd_histories(study):
    """``{case: {gust: (t, u, cl, cm)}}``: the LTD references of a computed study (``studies.store.results.load_results``;
    entries of an older code version are not read)."""
    out = {}
    for (case, gust), ltd in load_results(study).ltd.items():
        out.setdefault(case, {})[gust] = (ltd.t, ltd.u, ltd.cl, ltd.cm)
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", default="T4,T5")
    ap.add_argument("--orders", default="15,25,55")
    ap.add_argument("--algorithms", default="relocation,subspace")
    ap.add_argument("--minimax-within", type=float, default=None,
                    help="sysid.identify(minimax_within=...): least squares within this fraction of the minimax level")
    ap.add_argument("--study", default=str(ROOT / "studies" / "paper.toml"), help="a computed study with these cases")
    args = ap.parse_args(argv)
    hist = ltd_histories(args.study)
    print("case N_r algorithm FRF_max_err_Cl/Cm [%] | per gust: envelope Cl/Cm, RMS Cl/Cm [% of LTD peak]")
    for case in args.cases.split(","):
        runs = hist.get(case)
        if not runs:
            raise SystemExit(f"no LTD histories of {case} in the store of {args.study}: run `lfdrom run {args.study}` "
                             "first")
        frf = sysid.FrequencyResponse.load(ROOT / "docs" / "data" / f"frf-{case}.npz")
        for n in map(int, args.orders.split(",")):
            for algorithm in args.algorithms.split(","):
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    res = sysid.identify(frf, n, dc_gain="match", stable=True, algorithm=algorithm,
                                         minimax_within=args.minimax_within)
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
