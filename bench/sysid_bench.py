"""Identification benchmark: sysid against scipy AAA and scikit-rf vector fitting, plus performance targets.

Run: ``python bench/sysid_bench.py`` (``make bench``). Prints Markdown tables; ``--out FILE`` also writes them.

Data: a synthetic 40-state, lightly damped (zeta 0.5-5 %), 2-input 2-output continuous system with zero
feedthrough, sampled on McKelvey's grid ``sysid.mckelvey_grid(256, 70/(2 pi))`` (257 points, the
``omega_d = pi`` point is ``omega = inf`` and holds the feedthrough 0), noise-free and with small complex
Gaussian noise (1e-3 of each channel's peak).

Methods, all at order n = 40 (the true order), and on the noisy data also at n = 70 (``--over-order``), where
noise modes push the subspace model's spectral radius past 1 - margin = 0.999 (so ``stable=True`` acts):

- ``sysid plain / dc / stable / stable+dc``: :func:`sysid.identify` (McKelvey algorithm 1, 40 states shared by
  all channels; ``dc_gain="match"``, ``stable=True`` as named). The feedthrough sample is imposed by identify.
- ``AAA (per channel)``: :class:`scipy.interpolate.AAA` in the discrete variable z, per channel (it is scalar),
  on the conjugate-symmetric extension of the data to the full unit circle, with ``max_terms = n + 1`` so that
  every channel has a rational function of type (n, n): n poles per channel, as many as the ROM has, but not
  shared (4 x 40 poles in all). AAA offers no DC or stability control.
- ``VF (skrf)``: :class:`skrf.vectorFitting.VectorFitting` on an ``skrf.Network`` built from the continuous
  data (``omega = inf`` dropped, frequencies in ``omega / 2 pi``), ``n/2`` complex pole pairs shared by all
  channels (n poles, like the ROM), constant term fitted, ``enforce_dc=True`` (skrf's own DC option).

Metrics (the :mod:`sysid.metrics` definitions, over all 257 points incl. ``omega = inf``): max and RMS
relative FRF error, relative DC error ``max|G(0) - H(0)| / max|H(0)|`` against the data's DC sample,
stability (discrete spectral radius < 1, resp. continuous poles in the left half plane), wall time (best of
``--repeat`` runs, after one warm-up run that compiles the cvxpy problems).
"""

from __future__ import annotations

import argparse
import os
import sys
import time
import warnings
from pathlib import Path

# The problems here are small and dense: BLAS threads add only overhead, and on a shared machine an
# oversubscribed OpenBLAS makes timings meaningless (a 500 x 40 QR measured 0.24 s instead of 0.3 ms).
# One thread unless the environment says otherwise; the setting is printed with the tables.
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import sysid  # noqa: E402
from sysid.metrics import frf_errors  # noqa: E402
from sysid.refit import fit_bd  # noqa: E402
from sysid.stability import stabilise  # noqa: E402

T_PAPER = 70.0 / (2.0 * np.pi)
M_PAPER = 256


# ------------------------------------------------------------------------------------------------ data
def lightly_damped_system(n_modes=20, p=2, m=2, seed=0):
    """Continuous modal system: (A, B, C) with ``n = 2 n_modes`` states, D = 0.

    Natural frequencies log-spaced in [0.02, 2] (U/c units, i.e. reduced frequency k = 0.01..1), damping
    ratios log-uniform in [0.005, 0.05].
    """
    rng = np.random.default_rng(seed)
    wn = np.geomspace(0.02, 2.0, n_modes) * rng.uniform(0.95, 1.05, n_modes)
    zeta = np.exp(rng.uniform(np.log(0.005), np.log(0.05), n_modes))
    n = 2 * n_modes
    A = np.zeros((n, n))
    for i, (w, z) in enumerate(zip(wn, zeta)):
        A[2 * i:2 * i + 2, 2 * i:2 * i + 2] = [[0.0, 1.0], [-w * w, -2.0 * z * w]]
    B = rng.standard_normal((n, m)) * np.repeat(wn, 2)[:, None]
    C = rng.standard_normal((p, n)) * 0.1
    return A, B, C


def continuous_frf(A, B, C, omega):
    """``C (j omega I - A)^-1 B`` (D = 0), shape (p, m, K); ``omega = inf`` gives 0."""
    out = np.zeros((C.shape[0], B.shape[1], omega.size), dtype=complex)
    fin = np.isfinite(omega)
    s = 1j * omega[fin]
    X = np.linalg.solve(s[:, None, None] * np.eye(A.shape[0]) - A, np.broadcast_to(B, (s.size,) + B.shape))
    out[:, :, fin] = np.moveaxis(C @ X, 0, -1)
    return out


def make_data(noise, M=M_PAPER, T=T_PAPER, seed=0):
    A, B, C = lightly_damped_system(seed=seed)
    omega_d, omega = sysid.mckelvey_grid(M, T)
    H = continuous_frf(A, B, C, omega)
    if noise:
        rng = np.random.default_rng(seed + 1)
        peak = np.abs(H).max(axis=2, keepdims=True)
        H = H + noise * peak * (rng.standard_normal(H.shape) + 1j * rng.standard_normal(H.shape)) / np.sqrt(2)
        H[:, :, -1] = 0.0  # omega = inf: the feedthrough is supplied (0), not measured
        H[:, :, 0] = H[:, :, 0].real  # a real system's DC gain is real
    frf = sysid.FrequencyResponse(H, omega_d, T, inputs=["u1", "u2"], outputs=["y1", "y2"])
    return frf, omega


# ------------------------------------------------------------------------------------------------ methods
def best_time(fn, repeat):
    fn()  # warm-up (cvxpy compilation, imports)
    times = []
    out = None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return out, min(times)


def dc_rel(G0_model, G0_data):
    return float(np.abs(G0_model - G0_data).max() / np.abs(G0_data).max())


def run_sysid(frf, order, repeat, **kw):
    res, t = best_time(lambda: sysid.identify(frf, order, **kw), repeat)
    Hm = res.evaluate(frf.omega_d)
    G0 = res.evaluate(np.array([0.0]))[:, :, 0].real
    return dict(H=Hm, dc=dc_rel(G0, frf.H[:, :, 0].real), stable=res.spectral_radius < 1.0,
                stab_info=f"rho = {res.spectral_radius:.5f}", time=t)


def run_aaa(frf, order, repeat):
    from scipy.interpolate import AAA

    z = frf.z
    p, m, K = frf.shape
    zf = np.concatenate([z, np.conj(z[1:-1])])

    def fit():
        models = {}
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # AAA warns when it reaches max_terms before rtol
            for i in range(p):
                for j in range(m):
                    g = frf.H[i, j]
                    gf = np.concatenate([g, np.conj(g[1:-1])])
                    models[i, j] = AAA(zf, gf, max_terms=order + 1, rtol=1e-13)
        return models

    models, t = best_time(fit, repeat)
    Hm = np.zeros(frf.shape, dtype=complex)
    G0 = np.zeros((p, m))
    radii = []
    degrees = []
    for (i, j), r in models.items():
        Hm[i, j] = r(z)
        G0[i, j] = np.real(r(np.array([1.0 + 0j]))[0])
        poles = r.poles()
        degrees.append(poles.size)
        radii.append(np.max(np.abs(poles)) if poles.size else 0.0)
    rho = max(radii)
    return dict(H=Hm, dc=dc_rel(G0, frf.H[:, :, 0].real), stable=rho < 1.0,
                stab_info=f"max |pole| = {rho:.3f}; degrees {min(degrees)}-{max(degrees)}", time=t)


def run_vf(frf, omega, order, repeat):
    import skrf
    from skrf.vectorFitting import VectorFitting

    p, m, K = frf.shape
    if p != m:
        raise ValueError("skrf networks are square (p == m)")
    fin = np.isfinite(omega)
    f = omega[fin] / (2 * np.pi)
    nw = skrf.Network(frequency=skrf.Frequency.from_f(f, unit="hz"), s=np.moveaxis(frf.H[:, :, fin], -1, 0))

    def fit():
        vf = VectorFitting(nw)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            vf.vector_fit(n_poles_real=order % 2, n_poles_cmplx=order // 2, init_pole_spacing="log",
                          fit_constant=True, fit_proportional=False, enforce_dc=True)
        return vf

    vf, t = best_time(fit, repeat)
    Hm = np.zeros(frf.shape, dtype=complex)
    G0 = np.zeros((p, m))
    for i in range(p):
        for j in range(m):
            Hm[i, j, fin] = vf.get_model_response(i, j, f)
            Hm[i, j, ~fin] = vf.constant_coeff[i * m + j]
            G0[i, j] = np.real(vf.get_model_response(i, j, np.array([0.0]))[0])
    re = np.max(vf.poles.real)
    return dict(H=Hm, dc=dc_rel(G0, frf.H[:, :, 0].real), stable=re < 0,
                stab_info=f"max Re(pole) = {re:.2e}", time=t)


# ------------------------------------------------------------------------------------------------ tables
def comparison_table(order, repeat, over_order=None):
    lines = [
        f"### Identification at equal order (40-state lightly damped 2x2 system, M = {M_PAPER}, T = 70/(2 pi))",
        "",
        "| data | n | method | max rel. err | RMS rel. err | DC rel. err | stable | stability detail | time [s] |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    cases = [("noise-free", 0.0, order), ("noise 1e-3", 1e-3, order)]
    if over_order:
        cases.append(("noise 1e-3", 1e-3, over_order))
    for label, noise, n in cases:
        frf, omega = make_data(noise)
        runs = [
            ("sysid plain", lambda: run_sysid(frf, n, repeat)),
            ("sysid dc", lambda: run_sysid(frf, n, repeat, dc_gain="match")),
            ("sysid stable", lambda: run_sysid(frf, n, repeat, stable=True)),
            ("sysid stable+dc", lambda: run_sysid(frf, n, repeat, stable=True, dc_gain="match")),
            ("AAA (per channel)", lambda: run_aaa(frf, n, repeat)),
            ("VF (skrf)", lambda: run_vf(frf, omega, n, repeat)),
        ]
        for name, fn in runs:
            try:
                r = fn()
            except Exception as exc:  # a peer failing is a result, not a crash of the benchmark
                lines.append(f"| {label} | {n} | {name} | failed: {type(exc).__name__}: {exc} | | | | | |")
                continue
            e = frf_errors(r["H"], frf.H)
            lines.append(
                f"| {label} | {n} | {name} | {e.max_rel:.2e} | {e.rms_rel:.2e} | {r['dc']:.1e} | "
                f"{'yes' if r['stable'] else 'NO'} | {r['stab_info']} | {r['time']:.3f} |"
            )
    return lines


def performance_table(full_sdp):
    lines = ["", "### Performance targets", "", "| measurement | value | target |", "| --- | --- | --- |"]
    frf, _ = make_data(1e-3)
    siso = sysid.FrequencyResponse(frf.H[:1, :1], frf.omega_d, frf.T)
    # order sweep N_r = 1..80 on a 257-point SISO response
    t0 = time.perf_counter()
    sw = sysid.order_sweep(siso, max_order=80)
    t_sweep = time.perf_counter() - t0
    lines.append(f"| order sweep N_r = 1..80, 257-point SISO (with hold-out) | {t_sweep:.3f} s "
                 f"(suggested order {sw.suggested}) | |")
    # one constrained refit after the first compile
    sub = sysid.subspace_identify(siso, 40)
    z, G = siso.z, np.asarray(siso.H)
    dc, ft = G[:, :, 0].real, G[:, :, -1].real
    first = fit_bd(sub.A, sub.C, z, G, dc_gain=dc, feedthrough=ft)
    times, res = [], []
    for _ in range(20):
        r = fit_bd(sub.A, sub.C, z, G * (1 + 1e-3 * np.random.default_rng(len(times)).standard_normal()),
                   dc_gain=dc, feedthrough=ft)
        times.append(r.solve_time)
        res.append(r.constraint_residual)
    lines.append(f"| constrained refit (DC + feedthrough), n = 40, 257-point SISO, first call (compiles) | "
                 f"{first.solve_time * 1e3:.1f} ms | |")
    lines.append(f"| constrained refit after the first compile (median of 20; reused = {r.reused_problem}) | "
                 f"{np.median(times) * 1e3:.1f} ms | < 50 ms |")
    lines.append(f"| refit constraint residual (max abs over 20 solves, polished: {r.polished}) | "
                 f"{max(res):.1e} | <= 1e-10 |")
    # stability SDP for N_r = 55
    sub55 = sysid.subspace_identify(siso, 55)
    rho55 = sysid.spectral_radius(sub55.A)
    A55, g1, g2, how = sub55.A, sub55.gamma1, sub55.gamma2, "identified A"
    if rho55 < 1 - 1e-3:  # make it need stabilising: push the outermost mode out (documented in the table)
        A55 = sub55.A * (1.01 / rho55)
        g2 = g1 @ A55
        how = "identified A scaled to radius 1.01"
    t0 = time.perf_counter()
    st = stabilise(A55, method="lmi", margin=1e-3, gamma1=g1, gamma2=g2)
    t_lmi = time.perf_counter() - t0
    lines.append(f"| stability SDP (LMI on the unstable invariant subspace), N_r = 55 ({how}, rho {st.spectral_radius_before:.4f} -> "
                 f"{st.spectral_radius_after:.4f}) | {t_lmi:.3f} s | < 2 s |")
    rr = stabilise(A55, method="reflect", margin=1e-3, gamma1=g1, gamma2=g2)
    lines.append(f"| shift-equation residual ||G1 A - G2||_F after LMI vs reflection, N_r = 55 | "
                 f"{st.objective:.3e} vs {rr.objective:.3e} | |")
    if full_sdp:
        t0 = time.perf_counter()
        try:
            sf = stabilise(A55, method="lmi", margin=1e-3, gamma1=g1, gamma2=g2, subspace=False)
            what = f"rho -> {sf.spectral_radius_after:.4f}, residual {sf.objective:.3e}"
        except sysid.SolverError as exc:
            what = f"failed: {str(exc)[:60]}..."
        lines.append(f"| full n x n Lacy-Bernstein SDP, N_r = 55 ({what}) | {time.perf_counter() - t0:.1f} s | (< 2 s) |")
    return lines


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--order", type=int, default=40)
    ap.add_argument("--over-order", type=int, default=70,
                    help="also fit the noisy data at this (too high) order, where stability matters; 0 to skip")
    ap.add_argument("--repeat", type=int, default=3, help="timed runs per method (best is reported)")
    ap.add_argument("--full-sdp", action="store_true", help="also time the full n x n SDP at N_r = 55 (~1 min)")
    ap.add_argument("--out", type=Path, default=None, help="also write the Markdown to this file")
    args = ap.parse_args(argv)
    import platform

    lines = [f"<!-- {platform.processor() or platform.machine()}, {os.cpu_count()} CPUs, "
             f"OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS')}, numpy {np.__version__} -->", ""]
    lines += comparison_table(args.order, args.repeat, args.over_order)
    lines += [
        "",
        "Equal order: sysid has n states shared by all 4 channels; VF has n poles shared by all channels "
        "(n/2 complex pairs); AAA is scalar, so each channel gets its own type (n, n) rational function "
        "(n poles per channel, 4n in all) fitted in z on the conjugate-symmetric full circle. DC error is "
        "relative to the data's omega = 0 sample; sysid 'dc' imposes it exactly (convex equality), skrf's "
        "enforce_dc sets its constant term. Times: best of --repeat runs after a warm-up.",
    ]
    lines += performance_table(args.full_sdp)
    text = "\n".join(lines)
    print(text)
    if args.out:
        args.out.write_text(text + "\n")


if __name__ == "__main__":
    main()
