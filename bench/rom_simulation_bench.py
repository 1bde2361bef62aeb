"""ROM gust histories: ``sysid.simulate.rom_simulation`` by FFT convolution against ``control.forced_response``.

The study runner drives every ROM with every gust (198 histories in the paper study), so the simulation is
on its inner loop. Side by side in one run, on the same re-discretised models: the default path (Markov
parameters by doubling, then an FFT convolution; ``method="convolution"``) and python-control's step-by-step
recursion (``method="control"``, what a user of python-control would call), both from the continuous-time
map and re-discretisation of a discrete ROM (paper Eqs. 26, 31) included. The ROMs are random stable
discrete systems (eigenvalues of modulus 0.3 - 0.98, seeded), one input (the gust angle) and two outputs
(Cl, Cm), sampling period ``T = 70 / (2 pi)`` re-discretised at ``dt = 0.02`` (2000 steps: the BDF2 LTD's
step and length in the studies).

Prints per order: the median of ``--repeat`` timings of each path, their ratio, and the largest difference of
the two outputs relative to the peak output (both compute the same linear recursion; the FFT's round-off is a
few ulps of the peak times log2 N). Run: ``.venv/bin/python bench/rom_simulation_bench.py [--orders 9,15,25,55]
[--steps 2000] [--repeat 21]``; BLAS is limited to one thread (small dense products).
"""

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout

import numpy as np  # noqa: E402
from threadpoolctl import threadpool_limits  # noqa: E402

from sysid.simulate import rom_simulation  # noqa: E402

T = 70 / (2 * np.pi)


def random_rom(n, rng):
    """A stable discrete ROM of order ``n``: real block-diagonal ``A`` (moduli 0.3 - 0.98) in a random basis."""
    blocks, k = [], 0
    while k < n:
        r = rng.uniform(0.3, 0.98)
        if n - k >= 2:
            th = rng.uniform(0.05, 3.0)
            blocks.append(r * np.array([[np.cos(th), -np.sin(th)], [np.sin(th), np.cos(th)]]))
            k += 2
        else:
            blocks.append(np.array([[r]]))
            k += 1
    A0 = np.zeros((n, n))
    i = 0
    for b in blocks:
        A0[i:i + b.shape[0], i:i + b.shape[0]] = b
        i += b.shape[0]
    Q, _ = np.linalg.qr(rng.normal(size=(n, n)))
    return Q @ A0 @ Q.T, rng.normal(size=(n, 1)), rng.normal(size=(2, n)), rng.normal(size=(2, 1))


def median_time(fn, repeat):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return float(np.median(times)), out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--orders", default="9,15,25,55")
    ap.add_argument("--steps", type=int, default=2000)
    ap.add_argument("--dt", type=float, default=0.02)
    ap.add_argument("--repeat", type=int, default=21)
    args = ap.parse_args()
    rng = np.random.default_rng(7)
    t = args.dt * np.arange(args.steps)
    u = np.where(t > 1.0, 0.5 * (1 - np.cos(2 * np.pi * np.clip(t - 1.0, 0, 2.0) / 2.0)), 0.0)  # 1-cosine gust
    print(f"{time.strftime('%Y-%m-%d %H:%M')} UTC, {args.steps} steps of dt = {args.dt}, T = {T:.4f}, "
          f"median of {args.repeat}")
    print("| order | FFT convolution (ms) | control.forced_response (ms) | ratio | max diff / peak |")
    print("|---|---|---|---|---|")
    with threadpool_limits(1):
        for n in (int(v) for v in args.orders.split(",")):
            A, B, C, D = random_rom(n, rng)
            t_fft, y_fft = median_time(lambda: rom_simulation(A, B, C, D, T, t, u, method="convolution"),
                                       args.repeat)
            t_ctl, y_ctl = median_time(lambda: rom_simulation(A, B, C, D, T, t, u, method="control"), args.repeat)
            diff = float(np.max(np.abs(y_fft - y_ctl)) / np.max(np.abs(y_ctl)))
            print(f"| {n} | {1e3 * t_fft:.2f} | {1e3 * t_ctl:.2f} | {t_ctl / t_fft:.1f}x | {diff:.1e} |")


if __name__ == "__main__":
    main()
