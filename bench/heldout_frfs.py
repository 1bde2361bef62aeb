"""Two aerofoil gust frequency responses outside the paper's cases, for the identification benchmarks.

The identification layer was tuned on the six paper FRFs (``docs/data/frf-T1..T6.npz``); these two check it
on data it never saw: **A**, a thick symmetric section at low Mach (NACA0021, M 0.2, alpha 0) and **B**, a
cambered section at incidence in transonic flow (NACA4410, M 0.72, alpha 1 deg). Same grid and sampling as
the paper study (181 x 60 C-grid, 100 surface cells, far field 25 chords; McKelvey's grid with M = 256,
T = 70 / (2 pi); SVM gust, leading-edge reference; Cl and Cm per radian of gust angle). The files are
written outside the repository by default (``results/heldout/``, ignored by git) so that no fit is tuned on
them; ``bench/sysid_peers_bench.py --data results/heldout/frf-A.npz,results/heldout/frf-B.npz`` adds them to
its table.

Run: ``.venv/bin/python bench/heldout_frfs.py [--out results/heldout]`` (about 3 - 6 minutes per case on the
2-core machine).
"""

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout

import numpy as np  # noqa: E402

import cfd  # noqa: E402
import sysid  # noqa: E402
from studies.config.grid_spec import PAPER_GRID  # noqa: E402
from studies.config.schema import T_PAPER, CFDOptions  # noqa: E402
from studies.sections.gust_rom.tasks import lfd_on_mckelvey_grid  # noqa: E402

#: name -> (NACA code, Mach, incidence in degrees, description)
CASES = {
    "A": ("0021", 0.2, 0.0, "thick symmetric section at low Mach"),
    "B": ("4410", 0.72, 1.0, "cambered section at incidence, transonic"),
}
M = 256


def heldout_frf(name: str) -> sysid.FrequencyResponse:
    """The gust FRF of held-out case ``name`` (a key of :data:`CASES`), shape (2, 1, M + 1), ``T`` set: the
    paper study's grid and path (``studies.sections.gust_rom.tasks.lfd_on_mckelvey_grid``)."""
    code, mach, alpha, _ = CASES[name]
    sol = cfd.solve_steady(cfd.c_grid(cfd.naca(code), **PAPER_GRID.kwargs()), mach, alpha)
    return lfd_on_mckelvey_grid(cfd.linearise(sol), T_PAPER, M, CFDOptions())[0]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=Path("results/heldout"))
    ap.add_argument("--cases", default="A,B")
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    for name in args.cases.split(","):
        t0 = time.perf_counter()
        frf = heldout_frf(name)
        path = args.out / f"frf-{name}.npz"
        frf.save(path)
        H = np.asarray(frf.H)[:, 0]
        code, mach, alpha, what = CASES[name]
        print(f"{name} (NACA{code}, M {mach}, alpha {alpha} deg: {what}): DC Cl {H[0, 0].real:.4f} Cm "
              f"{H[1, 0].real:.4f} per rad, peak |Cl| {np.abs(H[0]).max():.4f} |Cm| {np.abs(H[1]).max():.4f}; "
              f"{time.perf_counter() - t0:.0f} s -> {path}", flush=True)


if __name__ == "__main__":
    main()
