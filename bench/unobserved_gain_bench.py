"""Gain between the samples: the default identification on the six paper FRFs, and where it falls back.

For each paper case (docs/data/frf-T1..T6.npz, T = 70/(2 pi)), N_omega = 257 and 33, several orders:
``sysid.identify(frf, n, dc_gain="match", stable=True)`` (the default), which algorithm it returned, whether
it fell back from the pole relocation to the subspace model because the relocated model's gain between the
samples exceeded ``sysid.identify.UNOBSERVED_GAIN_LIMIT`` times the data's peak (``sysid.identify.
unobserved_gain``), that gain, the max FRF error on the 257 computed frequencies per output (peak-normalised;
for N_omega = 33 most of them were not fitted), and the seconds per ROM.

Run: .venv/bin/python bench/unobserved_gain_bench.py
"""

import sys
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import sysid  # noqa: E402
from sysid.identify import unobserved_gain  # noqa: E402
from sysid.subspace import evaluate_ss  # noqa: E402

DATA = Path(__file__).resolve().parents[1] / "docs" / "data"


def main():
    print("case M order algorithm fallback gain max_err_Cl max_err_Cm seconds")
    for case in ["T1", "T2", "T3", "T4", "T5", "T6"]:
        full = sysid.FrequencyResponse.load(DATA / f"frf-{case}.npz")
        H = np.asarray(full.H)
        for M, n in [(256, 9), (256, 15), (256, 25), (256, 35), (256, 55), (32, 9), (32, 15)]:
            frf = full if M == 256 else full.subsample(M)
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                t0 = time.perf_counter()
                res = sysid.identify(frf, n, dc_gain="match", stable=True)
                seconds = time.perf_counter() - t0
            fallback = any("instead" in str(w.message) for w in caught)
            m = res.model
            Gm = evaluate_ss(*(np.asarray(x, dtype=float) for x in (m.A, m.B, m.C, m.D)), full.z)
            err = np.abs(Gm - H).max(axis=(1, 2)) / np.abs(H).max(axis=(1, 2))
            print(f"{case} {M} {n} {res.algorithm} {'yes' if fallback else 'no'} "
                  f"{unobserved_gain(m, frf).max():.3g} {100 * err[0]:.3g}% {100 * err[1]:.3g}% {seconds:.1f}",
                  flush=True)


if __name__ == "__main__":
    main()
