"""The figures and numbers of docs/loads.md: a rigid section from a CFD ROM and a flexible one.

1. Rigid: the paper's T4 LFD gust data (NACA 0018, M 0.25; docs/data/frf-T4.npz) identified at order 12 (stable,
   DC matched), at its Mach number, 1000 m, chord 2 m: tuned gusts and continuous turbulence of Cl, Cm (quarter
   chord) and Cm about 40 % chord.
2. Flexible: Theodorsen's loads with Jones' Wagner and Kussner functions (aeroelastic.theodorsen.jones_frf, fitted
   exactly) on a section of 2 m chord, 150 kg/m, a = -0.2, x_alpha = 0.1, r_alpha2 = 0.24, 2 Hz plunge and 8 Hz
   pitch, 2 % modal damping, at M 0.3, 2000 m.

Usage::

    python bench/loads_example.py [--out docs/loads]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import aeroelastic as ae
import loads
import sysid
from aeroelastic.theodorsen import WAGNER_JONES, jones_frf

ROOT = Path(__file__).resolve().parents[1]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(ROOT / "docs/loads"))
    out = Path(ap.parse_args(argv).out)
    out.mkdir(parents=True, exist_ok=True)

    frf = sysid.FrequencyResponse.load(ROOT / "docs/data/frf-T4.npz")
    rom = sysid.identify(frf, 12, dc_gain="match", stable=True)
    pt = loads.FlightPoint(0.25, 1000.0, 2.0)
    tg = loads.tuned_gust(rom, pt, moment_axes=[0.4])
    ct = loads.continuous_turbulence(rom, pt, moment_axes=[0.4])
    print(f"rigid, T4 ROM (max FRF error {rom.max_error:.3g})")
    print(tg.summary())
    print(ct.summary())
    print("correlation Cl, Cm:", f"{ct.rho('Cl', 'Cm'):+.4f}", " Cl, Cm@0.400:", f"{ct.rho('Cl', 'Cm@0.400'):+.4f}")
    fig, axs = plt.subplots(2, 2, figsize=(11, 8), layout="constrained")
    loads.correlated_loads_plot(tg, ct, x="Cl", y="Cm", ax=axs[0, 0])
    loads.load_vs_H_plot(tg, ax=axs[0, 1])
    loads.psd_plot(ct, ax=axs[1, 0])
    loads.gust_history_plot(tg, "Cl", others=["Cm", "Cm@0.400"], ax=axs[1, 1])
    fig.suptitle("rigid NACA 0018 section, T4 LFD ROM, M 0.25, 1000 m, c = 2 m")
    fig.savefig(out / "rigid.png", dpi=80)
    plt.close(fig)

    a = -0.2
    data = jones_frf(np.concatenate([[0.0], np.geomspace(1e-3, 20.0, 120)]), a)
    aero = ae.fit_motion(data, 2, poles=[2 * b for _, b in WAGNER_JONES], optimise=False, gust_order=3)
    sec = loads.FlexibleSection(aero, mass=150.0, a=a, x_alpha=0.1, r_alpha2=0.24, omega_h=2 * np.pi * 2.0,
                                omega_alpha=2 * np.pi * 8.0, damping=0.02)
    fp = loads.FlightPoint(0.3, 2000.0, 2.0)
    ts = sec.typical_section(fp)
    fl = ae.flutter(aero, ts)
    print(f"\nflexible: mu = {ts.mu:.3g}, speed index {sec.speed_index(fp):.3g}; {fl.summary()}")
    outs = ["load_factor", "plunge_spring", "pitch_spring", "Cl", "Cm"]
    tf = loads.tuned_gust(sec, fp, outputs=outs)
    # Jones' Kussner approximation jumps to 0.08 at the gust front (a feedthrough): N0 needs a cut-off
    cf = loads.continuous_turbulence(sec, fp, outputs=outs, f_max_hz=20.0)
    print(tf.summary())
    print(cf.summary())
    fig, axs = plt.subplots(2, 2, figsize=(11, 8), layout="constrained")
    loads.correlated_loads_plot(tf, cf, x="plunge_spring", y="pitch_spring", ax=axs[0, 0])
    loads.load_vs_H_plot(tf, ax=axs[0, 1])
    loads.psd_plot(cf, ax=axs[1, 0])
    loads.gust_history_plot(tf, "pitch_spring", others=["plunge_spring", "load_factor"], ax=axs[1, 1])
    fig.suptitle("flexible section (Theodorsen-Jones loads), 2 / 8 Hz, 2 % damping, M 0.3, 2000 m")
    fig.savefig(out / "flexible.png", dpi=80)
    plt.close(fig)


if __name__ == "__main__":
    main()
