"""Paper FRFs side by side: sysid's paths against stable vector fitting and AAA, at equal state count.

Run: ``python bench/sysid_peers_bench.py`` (``--orders 9,15,25,35,55`` for more orders, ``--out FILE`` to also
write the Markdown). Prints one table and a summary.

Data: the six committed LFD frequency responses of the paper cases, ``docs/data/frf-T1..T6.npz`` (gust input,
outputs Cl and Cm, McKelvey's grid with M = 256 and T = 70 / (2 pi); the ``omega = inf`` sample holds the
feedthrough 0); `--data` adds any other `.npz` (e.g. the held-out FRFs of `bench/heldout_frfs.py`).

Methods, all with ``n`` states (``N_r``):

- ``paper``: ``sysid.identify(frf, n)`` - McKelvey subspace + least squares, no constraints (the paper's method).
- ``dc (subspace)``: ``identify(frf, n, dc_gain="match", algorithm="subspace")``.
- ``dc+stable (subspace)``: ``identify(frf, n, dc_gain="match", stable=True, algorithm="subspace")`` - the
  previous stable path (LMI stabilisation, alternating convex refits).
- ``default``: ``identify(frf, n, dc_gain="match", stable=True)`` - the pole relocation path
  (:mod:`sysid.relocation`), no other options (``effort="fast"``).
- ``thorough``: the same with ``effort="thorough"`` (more candidates: :data:`sysid.relocation.EFFORTS`).
- ``VF``: scikit-rf vector fitting with the poles common to Cl and Cm: each output scaled to unit peak, both
  placed in a 2-port network ``[[Cl, Cm], [Cm, Cl]]`` (skrf networks are square; every response is fitted
  twice with the same weight, which leaves the least-squares problem of ``[Cl, Cm]`` unchanged),
  ``n // 2`` complex pairs and ``n % 2`` real poles, constant term, ``enforce_dc=True``; best of the ``log`` and
  ``lin`` initial pole spacings among the fits whose poles are all stable (skrf flips unstable poles).
- ``AAA``: :class:`scipy.interpolate.AAA` per output in ``z`` on the conjugate-symmetric full circle,
  ``max_terms = n + 1`` (type ``(n, n)``: ``n`` poles per output, ``2 n`` in all); no DC or stability control.

Columns: max error per output over all 257 samples (``max_k |G - H| / max_k |H|``, the
:func:`sysid.metrics.frf_errors` definition), the discrete spectral radius (VF's continuous poles mapped by the
bilinear map with the same ``T``; AAA's largest ``|pole|``), the DC error ``max|G(0) - H(0)| / max|H(0)|``,
and seconds per ROM (one run after a warm-up fit of each method; BLAS limited to one thread).
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import sys
import time
import warnings
from pathlib import Path

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import sysid  # noqa: E402
from sysid.metrics import max_relative_error  # noqa: E402

CASES = [f"T{i}" for i in range(1, 7)]


def load(case):
    """A paper case (``T1`` .. ``T6``) or the path of any ``sysid.FrequencyResponse`` ``.npz`` file."""
    if case in CASES:
        return sysid.FrequencyResponse.load(ROOT / "docs" / "data" / f"frf-{case}.npz")
    return sysid.FrequencyResponse.load(case)


def label(case):
    """Table label: the paper case, or a file's stem (``frf-A.npz`` -> ``A``)."""
    return case if case in CASES else Path(case).stem.removeprefix("frf-")


def dense_omega_d(frf, refine=8):
    """``omega_d`` grid ``refine`` times denser than the data's, equispaced over [0, pi] (as
    :func:`sysid.identify.unobserved_gain`)."""
    return np.linspace(0.0, np.pi, refine * (len(frf.omega_d) - 1) + 1)


def gain_between(H_dense, frf):
    """Peak gain on the dense grid per output, in units of the data's peak on that output."""
    return np.abs(H_dense).max(axis=(1, 2)) / np.abs(np.asarray(frf.H)).max(axis=(1, 2))


def dc_rel(G0_model, H):
    G0 = np.asarray(H)[:, :, 0].real
    return float(np.abs(np.asarray(G0_model).real - G0).max() / np.abs(G0).max())


# ------------------------------------------------------------------------------------------- methods
def run_identify(frf, n, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t0 = time.perf_counter()
        res = sysid.identify(frf, n, **kw)
        t = time.perf_counter() - t0
    H = res.evaluate(frf.omega_d)
    with np.errstate(all="ignore"):
        gain = gain_between(res.evaluate(dense_omega_d(frf)), frf)
    return dict(H=H, rho=res.spectral_radius, dc=dc_rel(res.evaluate([0.0])[:, :, 0], frf.H), time=t,
                note=res.algorithm, gain=gain)


def run_vf(frf, n):
    import skrf
    from skrf.vectorFitting import VectorFitting

    omega = frf.omega
    fin = np.isfinite(omega)
    f = omega[fin] / (2 * np.pi)
    H = np.asarray(frf.H)[:, 0, :]
    p = H.shape[0]
    peak = np.abs(H).max(axis=1)
    S = np.zeros((int(fin.sum()), p, p), dtype=complex)
    for i in range(p):
        for j in range(p):
            S[:, i, j] = H[(i + j) % p, fin] / peak[(i + j) % p]
    nw = skrf.Network(frequency=skrf.Frequency.from_f(f, unit="hz"), s=S)
    best = None
    t0 = time.perf_counter()
    for spacing in ("log", "lin"):
        vf = VectorFitting(nw)
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                vf.vector_fit(n_poles_real=n % 2, n_poles_cmplx=n // 2, init_pole_spacing=spacing,
                              fit_constant=True, fit_proportional=False, enforce_dc=True)
        except Exception:  # a failed start is skipped, as a user would
            continue
        if not np.all(vf.poles.real < 0):
            continue
        Hm = np.zeros(frf.shape, dtype=complex)
        G0 = np.zeros((p, 1))
        for i in range(p):
            Hm[i, 0, fin] = vf.get_model_response(i, 0, f) * peak[i]
            Hm[i, 0, ~fin] = vf.constant_coeff[i * p] * peak[i]
            G0[i, 0] = np.real(vf.get_model_response(i, 0, np.array([0.0]))[0]) * peak[i]
        e = max_relative_error(Hm, frf.H, per_output=True)
        if best is None or e.max() < best[0].max():
            best = (e, Hm, G0, vf, spacing)
    t = time.perf_counter() - t0   # the fits and the pick of the better start; the dense check below is not VF's
    if best is None:
        raise RuntimeError("no stable VF fit from either start")
    vf = best[3]
    poles = np.concatenate([vf.poles, np.conj(vf.poles[vf.poles.imag != 0])])
    zp = (1 + poles * frf.T / 2) / (1 - poles * frf.T / 2)
    wd = dense_omega_d(frf)
    fd = (2.0 / frf.T) * np.tan(wd[:-1] / 2) / (2 * np.pi)
    Hd = np.zeros((p, 1, wd.size), dtype=complex)
    for i in range(p):
        Hd[i, 0, :-1] = vf.get_model_response(i, 0, fd) * peak[i]
        Hd[i, 0, -1] = vf.constant_coeff[i * p] * peak[i]
    best = (best[0], best[1], best[2], float(np.abs(zp).max()), best[4], Hd)
    return dict(H=best[1], rho=best[3], dc=dc_rel(best[2], frf.H), time=t, note=f"{best[4]} start",
                gain=gain_between(best[5], frf), H_dense=best[5])


def run_aaa(frf, n):
    from scipy.interpolate import AAA

    z = frf.z
    p = frf.shape[0]
    zf = np.concatenate([z, np.conj(z[1:-1])])
    Hm = np.zeros(frf.shape, dtype=complex)
    G0 = np.zeros((p, 1))
    gain = np.zeros(p)
    rho = 0.0
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for i in range(p):
            g = np.asarray(frf.H)[i, 0]
            r = AAA(zf, np.concatenate([g, np.conj(g[1:-1])]), max_terms=n + 1, rtol=1e-13)
            Hm[i, 0] = r(z)
            gain[i] = np.abs(r(np.exp(1j * dense_omega_d(frf)))).max() / np.abs(g).max()
            G0[i, 0] = np.real(r(np.array([1.0 + 0j]))[0])
            pl = r.poles()
            rho = max(rho, float(np.abs(pl).max()) if pl.size else 0.0)
    t = time.perf_counter() - t0
    return dict(H=Hm, rho=rho, dc=dc_rel(G0, frf.H), time=t, note="stable" if rho < 1 else "UNSTABLE", gain=gain)


METHODS = [
    ("paper", lambda f, n: run_identify(f, n)),
    ("dc (subspace)", lambda f, n: run_identify(f, n, dc_gain="match", algorithm="subspace")),
    ("dc+stable (subspace)", lambda f, n: run_identify(f, n, dc_gain="match", stable=True, algorithm="subspace")),
    ("default (relocation)", lambda f, n: run_identify(f, n, dc_gain="match", stable=True)),
    ("thorough (relocation)", lambda f, n: run_identify(f, n, dc_gain="match", stable=True, effort="thorough")),
    ("VF (skrf, stable)", run_vf),
    ("AAA (scipy, per output)", run_aaa),
]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--orders", default="15,25", help="comma-separated state counts (default 15,25)")
    ap.add_argument("--cases", default=",".join(CASES))
    ap.add_argument("--data", default="", help="comma-separated FrequencyResponse .npz files to add (e.g. the "
                    "held-out FRFs of bench/heldout_frfs.py); --cases '' runs them alone")
    ap.add_argument("--out", type=Path, default=None, help="also write the Markdown to this file")
    ap.add_argument("--methods", default="", help="comma-separated prefixes of the methods to run (e.g. "
                    "'default,VF'); default all")
    ap.add_argument("--perturb", action="store_true", help="multiply the data by 1 + 2 eps (one rounding): how "
                    "much the errors move under round-off")
    args = ap.parse_args(argv)
    orders = [int(x) for x in args.orders.split(",")]
    cases = [c for c in args.cases.split(",") + args.data.split(",") if c]
    global METHODS
    if args.methods:
        METHODS = [(name, fn) for name, fn in METHODS if any(name.startswith(m) for m in args.methods.split(","))]

    warm = load(cases[0])  # warm-up: imports, cvxpy compilation of the subspace path's refits
    for _, fn in METHODS:
        try:
            fn(warm, orders[0])
        except Exception:
            pass

    lines = [f"<!-- {datetime.date.today()}, {platform.machine()}, {os.cpu_count()} CPUs, "
             f"OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS')}, numpy {np.__version__} -->", "",
             "| case | N_r | method | Cl max err | Cm max err | spectral radius | DC err | gain between samples "
             "(Cl, Cm) | s / ROM | note |",
             "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    summary = []
    compact = []
    for path in cases:
        frf = load(path)
        if args.perturb:
            frf = sysid.FrequencyResponse(np.asarray(frf.H) * (1 + 2 * np.finfo(float).eps), frf.omega_d, frf.T,
                                          inputs=list(frf.inputs), outputs=list(frf.outputs))
        case = label(path)
        for n in orders:
            got = {}
            for name, fn in METHODS:
                try:
                    r = fn(frf, n)
                except Exception as exc:
                    lines.append(f"| {case} | {n} | {name} | failed: {type(exc).__name__}: {str(exc)[:60]} | | | | | |")
                    continue
                e = max_relative_error(r["H"], frf.H, per_output=True)
                got[name] = (e, r)
                lines.append(f"| {case} | {n} | {name} | {100 * e[0]:.3g} % | {100 * e[1]:.3g} % | {r['rho']:.5f} | "
                             f"{r['dc']:.1e} | {r['gain'][0]:.3g}, {r['gain'][1]:.3g} | {r['time']:.3f} | {r['note']} |")
            print("\n".join(lines[-len(METHODS):]), flush=True)
            compact.append((case, n, got))
            if "default (relocation)" in got and "VF (skrf, stable)" in got:
                summary.append((case, n, got["default (relocation)"][0], got["VF (skrf, stable)"][0],
                                got["dc+stable (subspace)"][0] if "dc+stable (subspace)" in got else None,
                                got["default (relocation)"][1]["time"], got["default (relocation)"][1]["gain"],
                                got["VF (skrf, stable)"][1]["gain"]))
    short = ["paper", "dc (subspace)", "dc+stable (subspace)", "default (relocation)", "thorough (relocation)",
             "VF (skrf, stable)", "AAA (scipy, per output)"]
    lines += ["", "Max error per output, Cl / Cm in % of each output's peak (AAA: * = unstable):", "",
              "| case | N_r | paper | dc (subspace) | dc+stable (old) | **default** | thorough | VF | AAA | default: radius, "
              "DC err, s | thorough s | VF s |",
              "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for case, n, got in compact:
        cells = []
        for name in short:
            if name not in got:
                cells.append("failed")
                continue
            e, r = got[name]
            star = "*" if name.startswith("AAA") and r["rho"] >= 1 else ""
            cell = f"{100 * e[0]:.3g} / {100 * e[1]:.3g}{star}"
            cells.append(f"**{cell}**" if name.startswith("default") else cell)
        d = got.get("default (relocation)")
        th = got.get("thorough (relocation)")
        v = got.get("VF (skrf, stable)")
        dcell = f"{d[1]['rho']:.4f}, {d[1]['dc']:.0e}, {d[1]['time']:.2f}" if d else ""
        tcell = f"{th[1]['time']:.2f}" if th else ""
        vcell = f"{v[1]['time']:.2f}" if v else ""
        lines.append(f"| {case} | {n} | " + " | ".join(cells) + f" | {dcell} | {tcell} | {vcell} |")
    lines += ["", "Error ratios to VF, and the largest gain between the samples (8 points per data interval, in units "
              "of the output's data peak; Cl, Cm):", "",
              "| case | N_r | default Cl / VF | default Cm / VF | old stable Cm / VF | default at or below VF | "
              "default gain | VF gain |",
              "| --- | --- | --- | --- | --- | --- | --- | --- |"]
    wins = 0
    for case, n, e, v, old, t, gd, gv in summary:
        ok = bool(np.all(e <= v))
        wins += int(np.sum(e <= v))
        lines.append(f"| {case} | {n} | {e[0] / v[0]:.2f} | {e[1] / v[1]:.2f} | "
                     f"{'' if old is None else f'{old[1] / v[1]:.2f}'} | {'yes' if ok else 'NO'} | "
                     f"{gd[0]:.3g}, {gd[1]:.3g} | {gv[0]:.3g}, {gv[1]:.3g} |")
    times = [t for _, _, _, _, _, t, _, _ in summary]
    if times:
        vf_times = [got["VF (skrf, stable)"][1]["time"] for _, _, got in compact
                    if "VF (skrf, stable)" in got and "default (relocation)" in got]
        lines += ["", f"default at or below VF on {wins} of {2 * len(summary)} (case, order, output) points; "
                  f"default s / ROM: max {max(times):.2f}, median {np.median(times):.2f}; default / VF time: "
                  f"median {np.median(np.array(times) / np.array(vf_times)):.1f}."]
        ratio = {}
        for (_, n, *_), t, tv in zip(summary, times, vf_times):
            ratio.setdefault(n, []).append(t / tv)
        lines += ["", "default / VF time per order, median over the cases (min - max): " + "; ".join(
            f"{n}: {np.median(r):.1f} ({min(r):.1f} - {max(r):.1f})" for n, r in sorted(ratio.items())) + "."]
        both = [(got["thorough (relocation)"], got["VF (skrf, stable)"]) for _, _, got in compact
                if "thorough (relocation)" in got and "VF (skrf, stable)" in got]
        if both:
            th_wins = sum(int(np.sum(t[0] <= v[0])) for t, v in both)
            lines += ["", f"thorough at or below VF on {th_wins} of {2 * len(both)} points; thorough / VF time: median "
                      f"{np.median([t[1]['time'] / v[1]['time'] for t, v in both]):.1f}, max "
                      f"{max(t[1]['time'] / v[1]['time'] for t, v in both):.1f}; default / VF time max "
                      f"{max(np.array(times) / np.array(vf_times)):.1f}."]
    text = "\n".join(lines)
    print(text)
    if args.out:
        args.out.write_text(text + "\n")


if __name__ == "__main__":
    main()
