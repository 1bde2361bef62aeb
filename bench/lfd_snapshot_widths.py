"""How many directions the primal and the dual LFD solutions span on the paper grid: a lower bound on the size
of any reduced basis that reproduces them, for choosing what the fast sweep (``cfd.sweep``) should reduce.

For the frequencies of the paper's McKelvey grid (M = 256, T = 70 / (2 pi); every ``--every``-th finite one,
``omega = 0`` excluded) it solves, with one complex nested-dissection LU per frequency,

- the **primal** ``(J + i w V) q = -b(omega)`` for the unit harmonic SVM gust (one column; ``x_ref`` only
  multiplies it by ``exp(i omega x_ref)``, so it does not change the span), and
- the **dual** ``(J + i w V)^T Z = C^T`` for Cl and Cm (two columns, what ``cfd.sweep`` reduces today),

scales every snapshot to unit norm and prints, for each relative level ``t``, the number of singular values of
the snapshot matrix above ``t`` times the largest.

Run: ``.venv/bin/python bench/lfd_snapshot_widths.py --case T2 [--every 4] [--lin DIR]`` (``--lin`` reuses the
``LinearSystem`` stored by ``bench/lfd_sweep_bench.py --lin DIR``; 64 frequencies take about 4 minutes on the
2-core machine, plus the steady solve without ``--lin``).
"""

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout

import numpy as np  # noqa: E402
import scipy.sparse as sp  # noqa: E402
import scipy.sparse.linalg as spla  # noqa: E402

import sysid  # noqa: E402
from bench.lfd_sweep_bench import CASES, linear_system  # noqa: E402
from cfd.gust import face_gust_harmonic  # noqa: E402
from cfd.linear import check_outputs  # noqa: E402
from cfd.ordering import nested_dissection, unknown_permutation  # noqa: E402

LEVELS = (1e-2, 1e-4, 1e-6, 1e-8, 1e-10)


def snapshots(lin, omegas):
    """Primal (n, K) and dual (n, 2K) solutions at ``omegas`` (U/c units, finite, > 0)."""
    perm = unknown_permutation(nested_dissection(lin.grid))
    inv = np.argsort(perm)
    _, rows = check_outputs(("Cl", "Cm"))
    Ct = np.asarray(lin.C[rows], dtype=complex).T
    X, Z = [], []
    t0 = time.perf_counter()
    for k, om in enumerate(omegas):
        A = (lin.J + sp.diags(1j * lin.to_solver_frequency(om) * lin.V)).tocsr()[perm][:, perm].tocsc()
        lu = spla.splu(A, permc_spec="NATURAL", diag_pivot_thresh=0.0, options=dict(SymmetricMode=True))
        gi, gj = face_gust_harmonic(lin.grid, float(om), 0.0)
        X.append(lu.solve(-lin.forcing(gi, gj, "svm")[perm])[inv])
        Z.append(lu.solve(Ct[perm], trans="T")[inv])
        print(f"  {k + 1}/{len(omegas)}: omega {om:.4g}, {time.perf_counter() - t0:.0f} s", flush=True)
    return np.array(X).T, np.concatenate(Z, axis=1)


def widths(S):
    """Singular values of the column-normalised ``S`` above each of :data:`LEVELS` times the largest."""
    s = np.linalg.svd(S / np.linalg.norm(S, axis=0), compute_uv=False)
    return [int(np.sum(s > t * s[0])) for t in LEVELS]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--case", default="T2", choices=sorted(CASES))
    ap.add_argument("--every", type=int, default=4, help="every k-th finite frequency of the grid (default 4)")
    ap.add_argument("--lin", default=None, help="directory of stored LinearSystem pickles")
    args = ap.parse_args()
    lin = linear_system(args.case, args.lin)
    _, w = sysid.mckelvey_grid(256, 70 / (2 * np.pi))
    w = w[np.isfinite(w)][::args.every]
    w = w[w > 0]
    X, Z = snapshots(lin, w)
    print(f"\n{args.case}: {w.size} frequencies, omega {w.min():.3g} - {w.max():.3g}\n")
    print("| snapshots | columns | " + " | ".join(f"> {t:g}" for t in LEVELS) + " |")
    print("| --- | --- |" + " --- |" * len(LEVELS))
    for label, S in (("primal (gust)", X), ("dual (Cl, Cm)", Z), ("dual Cl", Z[:, 0::2]), ("dual Cm", Z[:, 1::2])):
        print(f"| {label} | {S.shape[1]} | " + " | ".join(str(v) for v in widths(S)) + " |")


if __name__ == "__main__":
    main()
