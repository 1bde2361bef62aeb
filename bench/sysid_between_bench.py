"""The ROMs between the samples: fits on the paper's grid against an LFD eight times denser.

The identification sees the 257 samples of McKelvey's grid (M = 256, T = 70 / (2 pi)); only 8 of them lie above
k = 2. This benchmark asks what the fitted models do between them, against the truth: the same LFD on the grid
with M = 2048 (every 8th point is a sample of the M = 256 grid), computed by ``--compute`` from the paper
study's cases (``cfd.lfd_response``'s fast sweep, about 7 min per case on the 2-core machine on 2026-12-04, two cases at
once) into ``results/dense/frf-<case>-M2048.npz`` (outside git).

For each case and order it fits ``sysid.identify(frf, n, dc_gain="match", stable=True)`` (the default) and
stable vector fitting (``bench/sysid_peers_bench.py``'s ``run_vf``) on the M = 256 subsample, and prints the
max error per output on the samples and between them (the dense points that are not samples) in three bands of
reduced frequency, ``k < 2``, ``2 <= k < 7`` and ``k >= 7``, all in % of the output's peak; ``--resolution``
adds the default with other ``sysid.relocation.fit_relocated(resolution=...)`` values. Two interpolants of the
samples (no model: real and imaginary parts linear in ``omega_d``; magnitude monotone-cubic and unwrapped phase
cubic) show what the samples alone say between them. ``--figure CASE:N``
draws the dense LFD, the samples and the default ROM (real and imaginary parts of Cl and Cm).

Run: .venv/bin/python bench/sysid_between_bench.py --compute T4,T5       (once; the truth)
     .venv/bin/python bench/sysid_between_bench.py --cases T4,T5 --orders 25,55 --figure T5:55
"""

import argparse
import functools
import sys
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "bench"))

import sysid  # noqa: E402

DENSE = ROOT / "results" / "dense"
T_PAPER = 70 / (2 * np.pi)
BANDS = ((0.0, 2.0), (2.0, 7.0), (7.0, np.inf))


def compute(case_name, study=ROOT / "studies" / "paper.toml", M=2048):
    """The LFD of a paper case on McKelvey's grid with ``M`` intervals, as the study computes it."""
    import cfd
    from studies.config import load_study
    from studies.sections.gust_rom.tasks import lfd_on_mckelvey_grid

    cfg = load_study(study)
    case = next(cs.case for cs in cfg.cases if cs.case.name == case_name)
    steady = cfd.solve_steady(cfd.c_grid(cfd.naca(case.naca), **case.grid.kwargs()), case.mach, case.alpha_deg)
    frf, _ = lfd_on_mckelvey_grid(cfd.linearise(steady), T_PAPER, M, cfg.cfd)
    DENSE.mkdir(parents=True, exist_ok=True)
    frf.save(DENSE / f"frf-{case_name}-M{M}.npz")
    return frf


def band_errors(H_model, dense, refine=8):
    """Max error per output between the samples, per band of ``k``: shape (len(BANDS), p), in % of the peak."""
    D = np.asarray(dense.H)
    k = np.asarray(dense.omega) / 2
    between = np.arange(k.size) % refine != 0
    peak = np.abs(D).max(axis=(1, 2))
    out = []
    for lo, hi in BANDS:
        sel = between & (k >= lo) & (k < hi)
        out.append(100 * np.abs(H_model[:, 0, sel] - D[:, 0, sel]).max(axis=1) / peak)
    return np.array(out)


def interpolants(frf, dense):
    """What the samples alone say between them: interpolants of the M = 256 samples on the dense grid, in
    ``omega_d`` (the uniform variable of McKelvey's grid). Returns ``[(name, H (p, 1, K_dense))]``."""
    from scipy.interpolate import CubicSpline, PchipInterpolator

    ws, wd = np.asarray(frf.omega_d), np.asarray(dense.omega_d)
    S = np.asarray(frf.H)[:, 0]
    linear = np.array([np.interp(wd, ws, h.real) + 1j * np.interp(wd, ws, h.imag) for h in S])
    polar = np.array([PchipInterpolator(ws, np.abs(h))(wd) * np.exp(1j * CubicSpline(ws, np.unwrap(np.angle(h)))(wd))
                      for h in S])
    return [("interpolant: Re, Im linear", linear[:, None]), ("interpolant: |H| pchip, phase spline", polar[:, None])]


def figure(case, n, dense, frf, H_model, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    k, ks = np.asarray(dense.omega) / 2, np.asarray(frf.omega) / 2
    D, S = np.asarray(dense.H), np.asarray(frf.H)
    fig, ax = plt.subplots(2, 2, figsize=(12, 7))
    for j, name in enumerate(frf.outputs[:2]):
        for row, part in enumerate((np.real, np.imag)):
            a = ax[row, j]
            a.plot(k, part(D[j, 0]), "k-", lw=1, label="LFD, M = 2048 (the truth)")
            a.plot(k, part(H_model[j, 0]), "r--", lw=1, label=f"default ROM, N_r = {n}")
            a.plot(ks, part(S[j, 0]), "bo", ms=3, label="the 257 samples it was fitted to")
            a.set_xscale("log")
            a.set_xlim(0.05, 40)
            a.grid(True, which="both", color="0.9")
            a.set_title(f"{case} {name}: {'real' if row == 0 else 'imaginary'} part")
        ax[1, j].set_xlabel("reduced frequency k")
    ax[0, 0].legend()
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--compute", default="", help="cases whose M = 2048 LFD to compute first (e.g. T4,T5)")
    ap.add_argument("--cases", default="T4,T5")
    ap.add_argument("--orders", default="25,55")
    ap.add_argument("--resolution", default="", help="more resolution floors to try, e.g. 1,2")
    ap.add_argument("--figure", default="", help="CASE:N, e.g. T5:55")
    ap.add_argument("--figure-path", default=str(ROOT / "docs" / "figures" / "sysid-between-samples.png"))
    args = ap.parse_args(argv)
    for case in filter(None, args.compute.split(",")):
        compute(case)
    import sysid.relocation as relocation
    from sysid_peers_bench import run_vf

    default_fit = relocation.fit_relocated
    print("case N_r method | samples Cl/Cm | between, k < 2 | 2 <= k < 7 | k >= 7 | between, all | estimate | left open "
          "(max error, % of peak; estimate and left open: result.between_error_per_output and "
          "between_uncertainty_per_output, no truth used)")
    for case in args.cases.split(","):
        dense = sysid.FrequencyResponse.load(DENSE / f"frf-{case}-M2048.npz")
        frf = dense.subsample(256)
        wd = np.asarray(dense.omega_d)
        for name, Hi in interpolants(frf, dense):
            b = band_errors(Hi, dense)
            print(f"| {case} | - | {name} | 0 / 0 | " + " | ".join(f"{x[0]:.3g} / {x[1]:.3g}" for x in b) + " | | | |",
                  flush=True)
        for n in map(int, args.orders.split(",")):
            rows = []
            for r in [None] + [float(x) for x in filter(None, args.resolution.split(","))]:
                # identify takes no resolution option: the floor is swapped in for this fit only
                relocation.fit_relocated = default_fit if r is None else functools.partial(default_fit, resolution=r)
                try:
                    with warnings.catch_warnings():
                        warnings.simplefilter("ignore")
                        res = sysid.identify(frf, n, dc_gain="match", stable=True)
                finally:
                    relocation.fit_relocated = default_fit
                Hm = res.evaluate(wd)
                rows.append(("default" if r is None else f"resolution {r:g}", 100 * res.errors.max_rel_per_output, Hm,
                             (100 * res.between_error_per_output, 100 * res.between_uncertainty_per_output)))
                if r is None and args.figure == f"{case}:{n}":
                    figure(case, n, dense, frf, Hm, args.figure_path)
            vf = run_vf(frf, n)
            rows.append(("VF", 100 * sysid.metrics.max_relative_error(vf["H"], frf.H, per_output=True), vf["H_dense"],
                         None))
            for name, e, Hm, est in rows:
                b = band_errors(Hm, dense)
                between = 100 * np.abs(Hm[:, 0] - np.asarray(dense.H)[:, 0])[:, np.arange(wd.size) % 8 != 0].max(axis=1) \
                    / np.abs(np.asarray(dense.H)).max(axis=(1, 2))
                print(f"| {case} | {n} | {name} | {e[0]:.3g} / {e[1]:.3g} | " +
                      " | ".join(f"{x[0]:.3g} / {x[1]:.3g}" for x in b) + f" | {between[0]:.3g} / {between[1]:.3g} | " +
                      ("- | -" if est is None else f"{est[0][0]:.3g} / {est[0][1]:.3g} | {est[1][0]:.3g} / {est[1][1]:.3g}")
                      + " |", flush=True)
    if args.figure:
        print(f"wrote {args.figure_path}")


if __name__ == "__main__":
    main()
