"""Identification demo: a gust-response-like system, identified with and without exact DC gain and stability.

Run: ``python -m studies.cli.demo --out demo-output`` (``make demo``) or ``lfdrom demo --out demo-output``.

The "truth" is a synthetic continuous system with the ingredients of an aerofoil gust response, one input
``gust`` (gust angle, rad) and two outputs ``Cl`` and ``Cm`` (per radian), time in convective units
(``s = t U / c``):

- a two-lag Kussner-like indicial lift: the sharp-edged-gust step response
  ``psi(s) = 1 - 0.5 exp(-0.26 s) - 0.5 exp(-2 s)`` (Sears-Sparks, in chords), scaled to the
  Prandtl-Glauert slope ``2 pi / beta`` at M = 0.735 (docs/references.md, sections 2 and 3); its transfer
  function ``(2 pi / beta) (0.13 / (s + 0.26) + 1 / (s + 2))`` is strictly proper (zero feedthrough);
- two lightly damped modes (reduced frequencies k = 0.3 and 0.7, damping 4 % and 6 %), small in Cl,
  larger in Cm, standing in for the shock-motion dynamics of transonic flow.

It is sampled on McKelvey's grid ``sysid.mckelvey_grid(M, 70/(2 pi))`` with complex Gaussian noise
(``noise`` times each channel's peak; the ``omega = inf`` sample is the known feedthrough 0 and stays exact),
then identified by :func:`sysid.identify` at a few orders, plain, with the exact DC gain, and with exact
DC gain plus guaranteed stability. Outputs in ``out/``: ``frf.png`` (magnitude and phase against the reduced
frequency ``k = omega / 2``, data against ROMs), ``table.md`` and ``table.csv`` (errors, DC error, spectral
radius, time). Nothing here depends on the CFD package.
"""

from __future__ import annotations

import argparse
import csv
import io
import math
import sys
import time
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

import sysid

from ..store.files import atomic_write_text
from ..report.plots import save_figure

__all__ = ["gust_like_system", "continuous_frf", "make_data", "run_demo", "DemoResult", "main"]

T_DEMO = 70.0 / (2.0 * np.pi)
MACH = 0.735


def gust_like_system(mach: float = MACH):
    """Continuous ``(A, B, C, D)`` of the demo's truth: 6 states, input gust, outputs (Cl, Cm).

    Returns
    -------
    A : ndarray (6, 6); B : ndarray (6, 1); C : ndarray (2, 6); D : ndarray (2, 1) (zeros)
    """
    slope = 2.0 * np.pi / np.sqrt(1.0 - mach**2)
    lags = np.array([0.26, 2.0])  # 1/convective time
    lag_res = slope * np.array([0.5 * 0.26, 0.5 * 2.0])  # residues: psi(s) -> (2 pi/beta) sum a_i b_i / (s + b_i)
    modes = [(2 * 0.3, 0.04), (2 * 0.7, 0.06)]  # (omega_n = 2 k, zeta)
    n = 2 + 2 * len(modes)
    A = np.zeros((n, n))
    B = np.zeros((n, 1))
    C = np.zeros((2, n))
    A[0, 0], A[1, 1] = -lags
    B[:2, 0] = 1.0
    C[0, :2] = lag_res
    C[1, :2] = -0.05 * lag_res * np.array([1.0, -2.0])  # Cm about c/4: small, with its own lag mix
    mode_gain_cl = [0.25, 0.15]
    mode_gain_cm = [-0.5, 0.3]
    for i, (wn, zeta) in enumerate(modes):
        k = 2 + 2 * i
        A[k:k + 2, k:k + 2] = [[0.0, 1.0], [-wn * wn, -2.0 * zeta * wn]]
        B[k + 1, 0] = wn
        C[0, k:k + 2] = mode_gain_cl[i] * np.array([wn, 0.3])
        C[1, k:k + 2] = mode_gain_cm[i] * np.array([0.3 * wn, 0.2])
    return A, B, C, np.zeros((2, 1))


def continuous_frf(A, B, C, D, omega):
    """Frequency response ``C (i omega I - A)^-1 B + D`` of a continuous state-space model.

    Parameters
    ----------
    A, B, C, D : ndarray, shapes (n, n), (n, m), (p, n), (p, m)
    omega : ndarray, shape (K,)
        Angular frequencies (U/c units); ``inf`` gives ``D``.

    Returns
    -------
    ndarray, complex, shape (p, m, K)
    """
    H = np.zeros((C.shape[0], B.shape[1], omega.size), dtype=complex)
    fin = np.isfinite(omega)
    s = 1j * omega[fin]
    X = np.linalg.solve(s[:, None, None] * np.eye(A.shape[0]) - A, np.broadcast_to(B, (s.size,) + B.shape))
    H[:, :, fin] = np.moveaxis(C @ X + D, 0, -1)
    H[:, :, ~fin] = D[:, :, None]
    return H


def make_data(M: int = 256, T: float = T_DEMO, noise: float = 2e-3, seed: int = 0):
    """Noisy samples of the truth on McKelvey's grid.

    Returns
    -------
    frf : sysid.FrequencyResponse
        Noisy data, shape (2, 1, M + 1), outputs ("Cl", "Cm"), input "gust".
    H_true : ndarray, shape (2, 1, M + 1)
        Noise-free response on the same grid.
    """
    omega_d, omega = sysid.mckelvey_grid(M, T)
    A, B, C, D = gust_like_system()
    H_true = continuous_frf(A, B, C, D, omega)
    rng = np.random.default_rng(seed)
    peak = np.abs(H_true).max(axis=2, keepdims=True)
    H = H_true + noise * peak * (rng.standard_normal(H_true.shape) + 1j * rng.standard_normal(H_true.shape)) / np.sqrt(2)
    H[:, :, 0] = H[:, :, 0].real  # a steady solution gives a real DC gain
    H[:, :, -1] = H_true[:, :, -1]  # omega = inf: the feedthrough is known (0), not measured
    frf = sysid.FrequencyResponse(H, omega_d, T, inputs=["gust"], outputs=["Cl", "Cm"],
                                  metadata={"source": "studies.cli.demo", "noise": noise, "seed": seed})
    return frf, H_true


VARIANTS = {
    "plain": dict(),
    "dc": dict(dc_gain="match"),
    "dc+stable": dict(dc_gain="match", stable=True),
}


@dataclass(frozen=True)
class DemoResult:
    """What :func:`run_demo` produced: table rows (dicts) and the paths written."""

    rows: tuple
    figure: Path
    table_md: Path
    table_csv: Path


def _table_md(rows) -> str:
    head = ("| order | variant | max rel. err | RMS rel. err | RMS err vs truth | DC rel. err | spectral radius "
            "| stable | time [ms] |")
    lines = [head, "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for r in rows:
        lines.append(
            f"| {r['order']} | {r['variant']} | {r['max_rel_err']:.3e} | {r['rms_rel_err']:.3e} | "
            f"{r['rms_err_truth']:.3e} | {r['dc_rel_err']:.1e} | {r['spectral_radius']:.5f} | "
            f"{'yes' if r['stable'] else 'NO'} | {r['time_ms']:.1f} |"
        )
    return "\n".join(lines)


def _plot(path: Path, frf, H_true, models, title):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    k = frf.omega / 2.0
    sel = np.isfinite(k) & (k > 0)
    fig, axes = plt.subplots(2, 2, figsize=(11, 7), sharex=True)
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for i, name in enumerate(frf.outputs):
        ax_m, ax_p = axes[0, i], axes[1, i]
        d = frf.H[i, 0, sel]
        ax_m.semilogx(k[sel], np.abs(d), ".", color="0.55", ms=3.5, label="data (noisy)", zorder=1)
        ax_p.semilogx(k[sel], np.degrees(np.unwrap(np.angle(d))), ".", color="0.55", ms=3.5, zorder=1)
        ax_m.semilogx(k[sel], np.abs(H_true[i, 0, sel]), "-", color="k", lw=0.8, label="truth", zorder=2)
        ax_p.semilogx(k[sel], np.degrees(np.unwrap(np.angle(H_true[i, 0, sel]))), "-", color="k", lw=0.8, zorder=2)
        for c, (label, Hm, style) in zip(colours, models):
            ax_m.semilogx(k[sel], np.abs(Hm[i, 0, sel]), style, color=c, lw=1.4, label=label, zorder=3)
            ax_p.semilogx(k[sel], np.degrees(np.unwrap(np.angle(Hm[i, 0, sel]))), style, color=c, lw=1.4, zorder=3)
        ax_m.set_title(f"{name} / gust angle")
        ax_m.set_ylabel(f"|{name}| [1/rad]")
        ax_p.set_ylabel("phase [deg]")
        ax_p.set_xlabel("reduced frequency k = omega c / (2 U)")
        for ax in (ax_m, ax_p):
            ax.grid(True, which="both", alpha=0.3)
    axes[0, 0].legend(fontsize=8, loc="lower left")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    save_figure(fig, path, dpi=130)


def run_demo(out, *, M: int = 256, T: float = T_DEMO, noise: float = 2e-3, orders=(4, 6, 40),
             seed: int = 0, verbose: bool = True) -> DemoResult:
    """Identify the demo system at ``orders`` with the three variants and write figure and tables.

    Parameters
    ----------
    out : path-like
        Output folder (created).
    M : int
        Grid intervals (``M + 1`` frequencies); the paper uses 256.
    T : float
        Sampling period of the bilinear map (convective time units).
    noise : float
        Noise standard deviation relative to each channel's peak.
    orders : sequence of int
        Model orders identified (the truth has 6 states).

    Returns
    -------
    DemoResult
    """
    say = print if verbose else (lambda *a, **k: None)
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    frf, H_true = make_data(M, T, noise, seed)
    say(f"demo: truth has 6 states; data: {frf.shape[2]} frequencies on McKelvey's grid (M = {M}, "
        f"T = {T:.4f}), noise {noise:g} of peak")
    rows = []
    results = {}
    for n in orders:
        for variant, kw in VARIANTS.items():
            t0 = time.perf_counter()
            with warnings.catch_warnings(record=True) as caught:   # printed with the row, not as tracebacks
                warnings.simplefilter("always")
                res = sysid.identify(frf, n, **kw)
            dt = time.perf_counter() - t0
            Hm = res.evaluate(frf.omega_d)
            results[n, variant] = (res, Hm)
            row = dict(
                order=n, variant=variant, max_rel_err=res.max_error, rms_rel_err=res.rms_error,
                rms_err_truth=float(np.linalg.norm(Hm - H_true) / np.linalg.norm(H_true)),
                dc_rel_err=float(res.dc_error), spectral_radius=float(res.spectral_radius),
                stable=bool(res.spectral_radius < 1.0), time_ms=1e3 * dt,
            )
            rows.append(row)
            say(f"  order {n:3d} {variant:10s} max err {row['max_rel_err']:.3e}  DC err {row['dc_rel_err']:.1e}  "
                f"rho {row['spectral_radius']:.5f}{'' if row['stable'] else ' UNSTABLE'}  ({row['time_ms']:.0f} ms)")
            for w in caught:
                say(f"      {w.category.__name__}: {w.message}")
    md = _table_md(rows)
    table_md = out / "table.md"
    atomic_write_text(
        table_md,
        "# lfdrom identification demo\n\n"
        f"Gust-response-like truth (6 states, outputs Cl, Cm), {frf.shape[2]} samples on McKelvey's grid, "
        f"T = 70/(2 pi), noise {noise:g} of each channel's peak. Errors relative (sysid.metrics): against the "
        "noisy data, and RMS against the noise-free truth. DC error is relative to the data's omega = 0 sample.\n\n"
        + md + "\n"
    )
    table_csv = out / "table.csv"
    buf = io.StringIO(newline="")
    w = csv.DictWriter(buf, fieldnames=list(rows[0]))
    w.writeheader()
    w.writerows(rows)
    atomic_write_text(table_csv, buf.getvalue())
    n_show = 6 if 6 in orders else orders[len(orders) // 2]
    n_low = min(orders)
    models = [(f"ROM n={n_show}, DC + stable", results[n_show, "dc+stable"][1], "-")]
    if n_low != n_show:
        models.append((f"ROM n={n_low}, plain", results[n_low, "plain"][1], "--"))
        models.append((f"ROM n={n_low}, DC matched", results[n_low, "dc"][1], ":"))
    fig = out / "frf.png"
    _plot(fig, frf, H_true, models, f"Gust-like system: data vs ROMs (M = {M}, T = 70/(2 pi), noise {noise:g})")
    say("")
    say(md)
    say(f"\nwrote {fig}, {table_md}, {table_csv}")
    return DemoResult(rows=tuple(rows), figure=fig, table_md=table_md, table_csv=table_csv)


def build_parser(parser: argparse.ArgumentParser | None = None) -> argparse.ArgumentParser:
    """Arguments of the demo (shared with ``lfdrom demo``)."""
    p = parser or argparse.ArgumentParser(prog="python -m studies.cli.demo", description=__doc__.splitlines()[0])
    p.add_argument("--out", type=Path, default=Path("demo-output"), help="output folder (default demo-output)")
    p.add_argument("--M", type=int, default=256, help="grid intervals, M + 1 frequencies (default 256)")
    p.add_argument("--noise", type=float, default=2e-3, help="noise relative to channel peak (default 2e-3)")
    p.add_argument("--orders", type=int, nargs="+", default=[4, 6, 40], help="model orders (default 4 6 40)")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--quiet", action="store_true")
    return p


def check_args(args) -> str | None:
    """What is wrong with the demo's options (``None``: nothing), found before any computation: ``--M`` within
    McKelvey's grid's range, ``--orders`` that the grid supports, ``--noise`` a finite fraction >= 0, ``--seed``
    >= 0."""
    from sysid.grids import MAX_GRID_M
    from sysid.order_limits import max_order

    if not 2 <= args.M <= MAX_GRID_M:
        return f"--M: {args.M} grid intervals; give 2 .. {MAX_GRID_M} (the paper uses 256)"
    top = max_order(args.M, "auto", p=2, m=1)
    bad = [n for n in args.orders if not 1 <= n <= top]
    if bad:
        return f"--orders: {bad} outside 1 .. {top}, the orders M = {args.M} intervals support (a larger --M allows more)"
    if not (math.isfinite(args.noise) and args.noise >= 0):
        return f"--noise: {args.noise!r}; give the noise as a fraction of each channel's peak, >= 0 (e.g. 2e-3)"
    if args.seed < 0:
        return f"--seed: {args.seed}; give a whole number >= 0"
    return None


def cli(args) -> int:
    """``lfdrom demo``: check the options and the output folder (exit 2 / 4 before computing), then run."""
    from ..store.files import NotWritableError, probe_writable
    from .exit_codes import EXIT_NOT_WRITTEN, EXIT_OK, EXIT_UNAVAILABLE

    problem = check_args(args)
    if problem is not None:
        print(f"lfdrom demo: {problem}", file=sys.stderr)
        return EXIT_UNAVAILABLE
    try:
        probe_writable(args.out, what="demo output folder", fix="choose another --out")
    except NotWritableError as e:
        print(f"lfdrom demo: {e}", file=sys.stderr)
        return EXIT_NOT_WRITTEN
    run_demo(args.out, M=args.M, noise=args.noise, orders=tuple(args.orders), seed=args.seed, verbose=not args.quiet)
    return EXIT_OK


def main(argv=None) -> int:
    return cli(build_parser().parse_args(argv))


if __name__ == "__main__":
    raise SystemExit(main())
