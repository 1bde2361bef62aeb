"""Gust loads from a ROM: the tuned-gust search against the LTD marches it replaces, and a whole flight point.

Measured side by side in one run (CPU time, ``time.process_time``; best of ``--repeat``):

1. the tuned-gust search of one output (Cl) over H = 30 .. 350 ft, both signs, from the paper's T2 ROM (the
   docs/data FRF, NACA 0010 at M 0.735, identified at order 12, stable, DC matched) at M 0.735, 7000 m, c = 2 m;
2. the LTD marches the same search would need: one per gust gradient it evaluated (a negative gust is the
   negative response), each as long as the search's horizon for that H (2H plus the tail). The LTD cost is not
   re-measured here: docs/performance.md and docs/paper-reproduction.md measured, on the paper grid (181 x 60),
   one Radau IIA march of 286 steps of 0.14 (40 convective units) carrying the six paper gusts as five columns
   in 80 - 82 s on this machine; counted here as 80 s / 5 = 16 s per gust per 40 units of time (the most
   favourable reading for the LTD: a lone gust costs the whole 80 s), scaled by each march's length;
3. a whole flight point: the tuned-gust search of every output and the continuous turbulence of every output.

Usage::

    python bench/loads_bench.py [--repeat 5]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

import loads
import sysid
from loads.atmosphere import FT
from loads.tuned_gust import initial_tail

ROOT = Path(__file__).resolve().parents[1]
LTD_SECONDS_PER_GUST = 80.0 / 5     # docs/performance.md: six gusts (five columns) in one 80 s Radau march
LTD_MARCH_LENGTH = 286 * 0.14       # convective units of that march


def _cpu(fn, repeat):
    best = np.inf
    out = None
    for _ in range(repeat):
        t0 = time.process_time()
        out = fn()
        best = min(best, time.process_time() - t0)
    return best, out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args(argv)
    frf = sysid.FrequencyResponse.load(ROOT / "docs/data/frf-T2.npz")
    rom = sysid.identify(frf, 12, dc_gain="match", stable=True)
    pt = loads.FlightPoint(0.735, 7000.0, 2.0)       # T2's Mach (NACA 0010, M 0.735)
    print(f"ROM: T2 order 12, max FRF error {rom.max_error:.3g}; point: {pt.summary()}")

    t_search, tg = _cpu(lambda: loads.tuned_gust(rom, pt, outputs=["Cl"]), args.repeat)
    c = pt.chord_m
    # every gradient the search evaluated, with its march length (2H + tail, convective units)
    n = tg.n_gradients
    Hs = tg.H_evaluated
    length = 2 * Hs / c + initial_tail(tg.system, Hs / c)
    ltd = float(np.sum(LTD_SECONDS_PER_GUST * length / LTD_MARCH_LENGTH))
    print(f"tuned-gust search of Cl, both signs, H 30 .. 350 ft: {n} gust gradients, {t_search * 1e3:.1f} ms CPU; "
          f"peak Cl {tg.peak['Cl']:.5g} at H = {tg.critical_H['Cl'] / FT:.1f} ft")
    print(f"LTD marches for the same search: {n} marches of {length.min():.0f} .. {length.max():.0f} convective units "
          f"= {ltd:.0f} s at {LTD_SECONDS_PER_GUST:.0f} s per {LTD_MARCH_LENGTH:.0f} units (docs/performance.md)")
    print(f"ratio LTD / ROM search: {ltd / t_search:.3g}")

    def whole():
        a = loads.tuned_gust(rom, pt, moment_axes=[0.4])
        b = loads.continuous_turbulence(rom, pt, moment_axes=[0.4])
        return a, b

    t_point, (a, b) = _cpu(whole, args.repeat)
    print(f"whole flight point (tuned gust of {len(a.outputs)} outputs, {a.n_gradients} gradients; continuous "
          f"turbulence of {len(b.outputs)}): {t_point:.3f} s CPU")


if __name__ == "__main__":
    main()
