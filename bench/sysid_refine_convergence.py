"""How far the default identification's Gauss-Newton pole refinements are from converged when they stop.

Run: ``python bench/sysid_refine_convergence.py`` (about a minute on the 2-core machine; ``--points T5:55,T1:55``
chooses the paper cases and orders, ``--nfev 80`` the longer budget, ``--unbounded`` drops the box bounds of the
poles' parameters). Prints one line per refinement.

Each ``sysid.identify(frf, n, dc_gain="match", stable=True)`` runs one or two refinements
(:func:`sysid.pole_refinement.refine_poles`, capped at ``sysid.relocation._REFINE_NFEV`` = 25 residual
evaluations). This bench records their arguments, runs each again with ``--nfev`` evaluations, and prints the best
cost (sum of squared residuals) after 5, 10, 15, 20, 25, 40, 60 and 80 evaluations relative to the start's, and
how many parameters end within 1e-3 of a bound. A refinement still falling at 25 is stopped by the cap, not by
convergence: its time is the cap's.
"""

from __future__ import annotations

import argparse
import os
import sys
import warnings
from pathlib import Path
from unittest import mock

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import sysid  # noqa: E402
import sysid.pole_refinement as pole_refinement  # noqa: E402
import sysid.relocation as relocation  # noqa: E402

CHECKPOINTS = (5, 10, 15, 20, 25, 40, 60, 80)


def refinements_of(frf, n):
    """The ``(args, kwargs)`` of every :func:`refine_poles` call of the default fit of ``frf`` at order ``n``."""
    calls = []
    original = relocation.refine_poles

    def recording(*args, **kwargs):
        calls.append((args, kwargs))
        return original(*args, **kwargs)

    with mock.patch.object(relocation, "refine_poles", recording), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sysid.identify(frf, n, dc_gain="match", stable=True)
    return calls


def cost_history(args, kwargs, nfev, unbounded):
    """The costs of every residual evaluation of one refinement run with ``nfev`` evaluations, and the number of
    parameters within 1e-3 (relative) of a bound at its end (None when unbounded)."""
    costs, near = [], [None]
    solver = pole_refinement.bounded_levenberg_marquardt

    def traced(residual, jacobian, x0, lower, upper, **kw):
        def recorded(x):
            r = residual(x)
            costs.append(float(r @ r))
            return r

        if unbounded:
            lower = upper = None
        out = solver(recorded, jacobian, x0, lower, upper, **kw)
        if lower is not None:
            gap = np.minimum(out.x - lower, upper - out.x)
            near[0] = int(np.sum(gap < 1e-3 * np.maximum(1.0, np.abs(out.x))))
        return out

    with mock.patch.object(pole_refinement, "bounded_levenberg_marquardt", traced):
        pole_refinement.refine_poles(*args, **dict(kwargs, max_nfev=nfev))
    return np.array(costs), near[0]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--points", default="T5:55,T1:55,T4:25,T2:15", help="comma-separated CASE:ORDER")
    ap.add_argument("--nfev", type=int, default=80)
    ap.add_argument("--unbounded", action="store_true")
    args = ap.parse_args(argv)
    print("case order run | best cost / start cost after " + ", ".join(map(str, CHECKPOINTS)) + " evaluations | "
          "parameters near a bound")
    for point in args.points.split(","):
        case, n = point.split(":")
        frf = sysid.FrequencyResponse.load(ROOT / "docs" / "data" / f"frf-{case}.npz")
        for i, (a, kw) in enumerate(refinements_of(frf, int(n)), start=1):
            costs, near = cost_history(a, kw, args.nfev, args.unbounded)
            best = np.minimum.accumulate(costs) / costs[0]
            cells = " ".join(f"{best[min(k, best.size) - 1]:.3g}" for k in CHECKPOINTS)
            print(f"{case} {n} {i} | {cells} | {'-' if near is None else near}", flush=True)


if __name__ == "__main__":
    main()
