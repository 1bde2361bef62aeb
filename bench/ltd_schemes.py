"""Time schemes for the LTD against BDF2 at dt 0.02: phase and amplitude error at the paper's gust frequencies.

For ``y' = i omega y`` a scheme advances one step of ``h`` by a factor ``z`` (the principal root for a multistep
scheme, the stability function ``R(i omega h)`` for a Runge-Kutta one). Per radian of the harmonic, its relative
phase-rate error is ``arg(z) / (omega h) - 1`` and its amplitude error ``ln|z| / (omega h)`` (negative: damped,
positive: amplified). The frequency scale of a 1-cosine gust of length ``L`` chords is ``omega = 2 pi / L``
(convective units): G1 (L = 0.5) 4 pi, G2 and G3 (L = 1) 2 pi, G4 (L = 10) 0.2 pi. The cost of a scheme is
counted in sparse back-substitutions per unit of convective time (a complex one as ``--complex-cost`` real
ones; ``bench/scaling_bench.py`` measured complex over real back-substitution 1.5 - 2.5 on 91 x 30 - 361 x 120).

Schemes: BDF2 (the code's), BDF3 and BDF4 (one real factorisation, one solve per step; not A-stable: the
printout gives the part of the imaginary axis they amplify), Alexander's three-stage L-stable SDIRK3 (one real
factorisation, three solves per step) and the three-stage Radau IIA (order 5, L-stable; its stage system
splits into one real and one complex solve per step).

Run: ``.venv/bin/python bench/ltd_schemes.py [--complex-cost 2.0]`` (a second; the Radau IIA tableau and
stability function are ``cfd.ltd.radau``'s).
"""

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout
from cfd.ltd.radau import RADAU_A, stability_function  # noqa: E402

BDF = {2: [1.5, -2.0, 0.5], 3: [11 / 6, -3.0, 1.5, -1 / 3], 4: [25 / 12, -4.0, 3.0, -4 / 3, 0.25]}
GAMMA = 0.435866521508459  # Alexander's SDIRK3 (L-stable, stiffly accurate)
SDIRK3 = np.array([[GAMMA, 0.0, 0.0],
                   [(1 - GAMMA) / 2, GAMMA, 0.0],
                   [-1.5 * GAMMA**2 + 4 * GAMMA - 0.25, 1.5 * GAMMA**2 - 5 * GAMMA + 1.25, GAMMA]])
GUSTS = {"G1 (L 0.5)": 4 * np.pi, "G2/G3 (L 1)": 2 * np.pi, "G4 (L 10)": 0.2 * np.pi}


def bdf_factor(k, wh):
    p = np.array(BDF[k], complex)
    p[0] -= 1j * wh
    roots = np.roots(p)
    return roots[np.argmin(np.abs(roots - np.exp(1j * wh)))]


def rk_factor(A, wh):
    return stability_function(1j * wh, A)  # both Runge-Kutta schemes here are stiffly accurate: b = A[-1]


def errors(z, wh):
    return np.angle(z) / wh - 1, np.log(abs(z)) / wh


def amplified_axis(k):
    """The part ``0 < omega h < top`` of the imaginary axis that BDF``k`` amplifies (its unstable lobe)."""
    th = np.linspace(1e-6, np.pi, 200001)
    z = sum(a * np.exp(-1j * j * th) for j, a in enumerate(BDF[k]))
    left = z.real < 0
    return float(z.imag[left].max()) if left.any() else 0.0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--complex-cost", type=float, default=2.0, help="a complex back-substitution in real ones")
    c = ap.parse_args().complex_cost
    schemes = [("BDF2", 0.02, lambda wh: bdf_factor(2, wh), 1.0)]
    schemes += [(f"BDF{k}", h, (lambda wh, k=k: bdf_factor(k, wh)), 1.0) for k in (3, 4) for h in (0.02, 0.04)]
    schemes += [("SDIRK3", h, lambda wh: rk_factor(SDIRK3, wh), 3.0) for h in (0.04, 0.06, 0.08)]
    schemes += [("Radau IIA 5", h, lambda wh: rk_factor(RADAU_A, wh), 1.0 + c) for h in (0.1, 0.15, 0.2)]
    head = " | ".join(f"{g}: phase / amplitude" for g in GUSTS)
    print(f"| scheme | dt | solves per unit time | {head} |")
    print("|---|---|---|" + "---|" * len(GUSTS))
    for name, h, factor, solves in schemes:
        cells = []
        for w in GUSTS.values():
            p, a = errors(factor(w * h), w * h)
            cells.append(f"{p:+.1e} / {a:+.1e}")
        print(f"| {name} | {h:g} | {solves / h:.0f} | " + " | ".join(cells) + " |")
    for k in (3, 4):
        print(f"BDF{k} amplifies undamped modes with 0 < omega h < {amplified_axis(k):.3f} (and damped ones near them)")


if __name__ == "__main__":
    main()
