"""Flutter and gust response of Hodges & Pierce's typical section from Theodorsen's aerodynamics as data.

Run from the repository root::

    .venv/bin/python bench/flutter_example.py [--out docs/aeroelastic]

It builds Theodorsen's and Sears' frequency responses as ``sysid.FrequencyResponse`` data (the form a CFD
sweep gives), fits them (:func:`aeroelastic.fit_motion`), finds flutter as an eigenvalue problem over speed,
compares with the classical k-method determinant, simulates a 1-cosine gust on the flexible section below
flutter against Jones' time-domain model, prints the numbers quoted in docs/aeroelastic.md and writes the
figures ``fit.png``, ``root_locus.png``, ``vg.png`` and ``gust_response.png``.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import aeroelastic as ae  # noqa: E402
from aeroelastic import theodorsen as th  # noqa: E402
from aeroelastic.gust import simulate  # noqa: E402


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", default="docs/aeroelastic", help="folder for the PNG figures")
    p.add_argument("--speed", type=float, default=1.5, help="speed index of the gust response (below flutter)")
    args = p.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    sec = ae.TypicalSection(mu=20, a=-0.2, x_alpha=0.1, r_alpha2=0.24, omega_ratio=0.4)
    omega = np.concatenate([[0.0], np.geomspace(0.01, 4.0, 100)])  # U/c; k = omega/2 up to 2
    data = th.theodorsen_frf(omega, sec.a, gust=True)

    t0 = time.perf_counter()
    model = ae.fit_motion(data, 4)
    t_fit = time.perf_counter() - t0
    print(f"fit (4 lag roots, gust order 8): motion max error {model.max_error:.2e}, RMS {model.rms_error:.2e}; "
          f"gust max error {model.gust_max_error:.2e}; lag roots {np.array2string(model.poles, precision=4)}; "
          f"{t_fit:.2f} s")

    speeds = np.linspace(0.05, 3.0, 300)
    t0 = time.perf_counter()
    res = ae.flutter(model, sec, speeds)
    t_fl = time.perf_counter() - t0
    det = th.flutter_determinant(sec)
    detj = th.flutter_determinant(sec, circulation=th.theodorsen_jones)
    print(f"state-space eigenvalues ({speeds.size} speeds, {t_fl:.2f} s): {res.summary()}")
    print(f"k-method determinant, exact C(k):  U/(b w_a) = {det.speed_index:.5f}, V_f = {det.flutter_speed_index:.5f}, "
          f"w/w_a = {det.frequency_ratio:.5f}, k = {det.k:.5f}")
    print(f"k-method determinant, Jones' C(k): U/(b w_a) = {detj.speed_index:.5f}, w/w_a = {detj.frequency_ratio:.5f}")
    print(f"relative differences: speed {res.speed_index / det.speed_index - 1:+.2e}, "
          f"frequency {res.frequency_ratio / det.frequency_ratio - 1:+.2e}; against 2.17: "
          f"{res.speed_index / 2.17 - 1:+.2e}")
    print(f"divergence speed index (static derivatives): {ae.divergence_speed(model, sec):.5f}")

    # --- fit figure: data and model magnitudes, and the relative error of each motion entry -----------------
    wf = np.geomspace(0.01, 4.0, 300)
    Hd = th.theodorsen_motion(wf, sec.a)
    Hm = model.evaluate(wf)
    fig, (ax_m, ax_e) = plt.subplots(1, 2, figsize=(11, 4.5))
    names = [["Cl/(h/c)", "Cl/α"], ["Cm/(h/c)", "Cm/α"]]
    colours = [["tab:blue", "tab:orange"], ["tab:green", "tab:red"]]
    for i in range(2):
        for j in range(2):
            c = colours[i][j]
            ax_m.loglog(wf / 2, np.abs(Hd[i, j]), "-", color=c, lw=3, alpha=0.35)
            ax_m.loglog(wf / 2, np.abs(Hm[i, j]), "--", color=c, lw=1.2, label=names[i][j])
            floor = 0.01 * np.abs(Hd[i, j]).max()
            ax_e.semilogx(wf / 2, np.abs(Hm[i, j] - Hd[i, j]) / np.maximum(np.abs(Hd[i, j]), floor), color=c,
                          lw=1.2, label=names[i][j])
    ax_m.plot([], [], "-", color="0.5", lw=3, alpha=0.35, label="Theodorsen (data)")
    ax_m.plot([], [], "--", color="0.3", lw=1.2, label="fit (dashed)")
    ax_m.set_title("|H|: data (thick) and fit M0 + M1 s + M2 s² + 4 lags")
    ax_m.set_xlabel("reduced frequency k = ωb/U")
    ax_m.legend(fontsize=8, ncol=2)
    ax_e.set_title(f"relative fit error (max {model.max_error:.1e})")
    ax_e.set_xlabel("reduced frequency k = ωb/U")
    ax_e.set_ylabel("|fit - data| / max(|data|, 1% of peak)")
    ax_e.legend(fontsize=8)
    for ax in (ax_m, ax_e):
        ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(out / "fit.png", dpi=110)
    plt.close(fig)

    # --- root locus and V-g -----------------------------------------------------------------------------------
    fig, ax = plt.subplots(figsize=(7, 5))
    ae.root_locus_plot(res, ax)
    ax.set_xlim(-0.35, 0.12)
    ax.set_ylim(-0.02, 1.1)
    fig.tight_layout()
    fig.savefig(out / "root_locus.png", dpi=110)
    plt.close(fig)

    fig, axs = plt.subplots(2, 1, sharex=True, figsize=(7, 6))
    ae.vg_plot(res, axs)
    axs[1].axhline(det.frequency_ratio, color="0.5", lw=0.6)
    axs[0].plot([det.speed_index], [0.0], "o", mfc="none", color="k", ms=9, label="k-method determinant")
    vd = ae.divergence_speed(model, sec)
    for ax in axs:
        ax.axvline(vd, color="tab:purple", ls=":", lw=1.2)
    axs[0].plot([], [], ":", color="tab:purple", label=f"divergence V = {vd:.3f}")
    axs[0].legend(fontsize=8, loc="lower left")
    fig.tight_layout()
    fig.savefig(out / "vg.png", dpi=110)
    plt.close(fig)

    # --- gust response below flutter ------------------------------------------------------------------------
    V = args.speed
    t = np.linspace(0.0, 80.0, 1601)
    u = np.where(t < 10.0, 0.5 * (1 - np.cos(2 * np.pi * t / 10.0)), 0.0) * np.radians(1.0)
    t0 = time.perf_counter()
    g = ae.gust_response(model, sec, V, (t, u))
    t_g = time.perf_counter() - t0
    ref = simulate(th.jones_section_model(sec, V), sec, V, t, u)
    diffs = {k: np.abs(getattr(g, k) - getattr(ref, k)).max() / np.abs(getattr(ref, k)).max()
             for k in ("plunge", "pitch", "Cl", "Cm")}
    print(f"gust response at V = {V} ({V / res.speed_index:.0%} of flutter), 1-cos gust 10 chords 1 deg, {t_g:.3f} s: "
          "max |ROM - Jones| / peak: " + ", ".join(f"{k} {v:.1%}" for k, v in diffs.items()))
    axs = ae.gust_response_plot(g, reference=ref, label="Theodorsen/Sears data, fitted and coupled",
                                reference_label="Jones' indicial model (time domain)")
    fig = axs[0].figure
    fig.tight_layout()
    fig.savefig(out / "gust_response.png", dpi=110)
    plt.close(fig)
    print(f"figures written to {out}/")


if __name__ == "__main__":
    main()
