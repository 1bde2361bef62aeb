"""Export the six paper cases' LFD gust frequency responses (issue 4 item 6) from a paper study's store.

Reads ``studies.load_results(studies/paper.toml)`` (run ``lfdrom run studies/paper.toml`` first: this script
computes nothing), writes ``docs/data/frf-<case>.npz`` (``sysid.FrequencyResponse.save``: M = 256,
T = 70 / (2 pi), outputs Cl and Cm per radian of gust angle, input v_g / U at the leading edge, SVM) and a
Bode-style figure of all six cases against the reduced frequency ``k = omega / 2``:
``docs/figures/lfd-paper-cases.png``. Prints one line per case (DC gain, peak |H|, method and time).

Run: ``.venv/bin/python bench/paper_frfs.py [--study studies/paper.toml] [--out docs]``.
"""

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from studies import load_results  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--study", default="studies/paper.toml")
    ap.add_argument("--out", default="docs")
    args = ap.parse_args(argv)
    res = load_results(args.study)
    out = Path(args.out)
    (out / "data").mkdir(parents=True, exist_ok=True)
    (out / "figures").mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(2, 2, figsize=(11, 7), sharex=True)
    for (case, T), rec in sorted(res.frf.items()):
        frf = rec.frf
        frf.save(out / "data" / f"frf-{case}.npz")
        w = np.asarray(frf.omega)
        ok = np.isfinite(w) & (w > 0)
        k = w[ok] / 2
        H = frf.H[:, 0, :]
        for j, name in enumerate(frf.outputs[:2]):
            ax[0, j].loglog(k, np.abs(H[j, ok]), label=case)
            ax[1, j].semilogx(k, np.degrees(np.unwrap(np.angle(H[j, ok]))), label=case)
        est = frf.metadata.get("error_estimate")
        worst = np.nanmax(np.asarray(est, dtype=float)[:, ok] / np.abs(H[:, ok])) if est is not None else float("nan")
        print(f"{case}: T = {T:.4f}, DC gain Cl {H[0, 0].real:.4f} Cm {H[1, 0].real:.4f} per rad, peak |Cl| "
              f"{np.abs(H[0]).max():.4f}, method {frf.metadata.get('method')}, {rec.seconds:.0f} s, worst est/|H| "
              f"{worst:.1e}")
    for j, name in enumerate(["Cl", "Cm"]):
        ax[0, j].set_title(f"{name} per radian of gust angle (LFD, SVM, x_ref = leading edge)")
        ax[0, j].set_ylabel(f"|{name}|")
        ax[1, j].set_ylabel(f"phase of {name} [deg]")
        ax[1, j].set_xlabel("reduced frequency k = omega c / (2 U)")
        for a in ax[:, j]:
            a.grid(True, which="both", color="0.88")
    ax[0, 0].legend()
    fig.suptitle("Gust frequency responses of the paper's cases T1-T6 (181 x 60, M = 256, T = 70/(2 pi))")
    fig.tight_layout()
    fig.savefig(out / "figures" / "lfd-paper-cases.png", dpi=110)
    print(f"wrote {out / 'data'}/frf-*.npz and {out / 'figures' / 'lfd-paper-cases.png'}")


if __name__ == "__main__":
    main()
