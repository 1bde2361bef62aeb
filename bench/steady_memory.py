"""Peak memory of a steady solve: ``cfd.solve_steady`` on T2 (NACA0010, M0.735), max RSS of the process.

Run: ``.venv/bin/python bench/steady_memory.py [--checkout DIR] [--ni 181 --nj 60 --n-surface 100]`` (about
30 s on the paper grid). ``--checkout`` measures another checkout's code (e.g. a ``git worktree`` of an older commit) side by side.
"""

import argparse
import resource
import sys
import time
from pathlib import Path


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--checkout", default=str(Path(__file__).resolve().parents[1]))
    ap.add_argument("--ni", type=int, default=181)
    ap.add_argument("--nj", type=int, default=60)
    ap.add_argument("--n-surface", type=int, default=100)
    args = ap.parse_args()
    sys.path.insert(0, args.checkout)
    import cfd

    grid = cfd.c_grid(cfd.naca("0010"), ni=args.ni, nj=args.nj, n_surface=args.n_surface)
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20   # KiB -> GiB (Linux)
    t = time.perf_counter()
    sol = cfd.solve_steady(grid, 0.735, 0.0)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20
    print(f"{args.checkout}: {args.ni} x {args.nj}, steady {time.perf_counter() - t:.1f} s, "
          f"{sol.info['n_factor']} factorisations, peak RSS {peak:.2f} GiB (before the solve {before:.2f}), "
          f"Cl {sol.cl:.12f}")


if __name__ == "__main__":
    main()
