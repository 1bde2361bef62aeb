"""Flutter and gust response of Hodges & Pierce's typical section from the CFD ROM of a thin section at low Mach.

Run from the repository root (a few minutes per grid on the shared two-core machine)::

    nice .venv/bin/python bench/cfd_flutter.py [--mach 0.2] [--grids 65x17x48,97x25x64] [--out docs/aeroelastic]

Part 1 (flutter). For each grid: steady Euler solution of the section at ``alpha = 0``, its linearisation, the
fast sweep of the gust, plunge and pitch responses (pitch about the quarter chord) on ``omega = 0`` and 24
frequencies up to ``omega = 2`` (``k = 1``), moved to the elastic axis (``aeroelastic.to_elastic_axis``), fitted
(``aeroelastic.fit_motion``, 4 lag roots) and ``aeroelastic.flutter``. Printed side by side with Theodorsen's
incompressible flat plate (the same fit and eigenvalue path) and two compressibility corrections of it:

- all loads divided by ``beta = sqrt(1 - M^2)`` (Prandtl-Glauert applied to everything; exactly the same as the
  incompressible section with the mass ratio ``mu beta``),
- the circulatory part only (``C(k) / beta``; the apparent mass kept incompressible), also by the k-method
  determinant (independent of the fit),
- all loads times the CFD's own steady lift slope over ``2 pi`` (compressibility and thickness as a uniform factor:
  the largest effect a steady correction can give);

and three hybrids (the CFD's lift with Theodorsen's moment about the elastic axis, the other way round, and
Theodorsen's loads with the CFD's moment due to pitch alone) that show which load moves the flutter speed and
which the frequency.

Part 2 (coupled time marching). On the last grid, the 1-cosine gust response of the flexible section at a speed
below flutter from ``cfd.ltd.coupled.coupled_ltd`` (the linear CFD and the structure in one BDF2 step) against
``aeroelastic.gust_response`` of the coupled ROM fitted from the same grid's frequency responses: plunge, pitch,
Cl and Cm, max difference over the history divided by the march's peak.

Figures (into ``--out``): ``cfd_flutter.png`` (root loci and V-g of the CFD ROM and of Theodorsen) and
``cfd_gust.png`` (coupled march against the coupled ROM).
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import aeroelastic as ae  # noqa: E402
import cfd  # noqa: E402
import sysid  # noqa: E402
from aeroelastic import theodorsen as th  # noqa: E402
from cfd.ltd.coupled import coupled_ltd  # noqa: E402

SECTION = dict(mu=20.0, a=-0.2, x_alpha=0.1, r_alpha2=0.24, omega_ratio=0.4)   # Hodges & Pierce
OMEGA = np.concatenate([[0.0], np.geomspace(0.02, 2.0, 24)])   # U/c: k up to 1 (flutter is near k = 0.3)
SPEEDS = np.linspace(0.05, 3.0, 300)
INPUTS = ("gust", "plunge", "pitch")


def _grid_spec(text):
    ni, nj, ns = (int(v) for v in text.lower().split("x"))
    return ni, nj, ns


def section_matrices(sec, speed):
    """``(M, K, L)`` of ``cfd.ltd.coupled`` for the typical section at the speed index ``V`` (convective time)."""
    return sec.mass_matrix, 4.0 / speed**2 * sec.stiffness_matrix, 4.0 * sec.load_matrix


def cfd_case(foil, mach, spec, cache):
    """Steady solution, linearisation and frequency response on one grid (FRF cached in ``cache`` if given)."""
    ni, nj, ns = spec
    times = {}
    t0 = time.perf_counter()
    grid = cfd.c_grid(cfd.naca(foil), ni=ni, nj=nj, n_surface=ns)
    sol = cfd.solve_steady(grid, mach=mach, alpha_deg=0.0)
    lin = cfd.linearise(sol)
    times["steady + linearise"] = time.perf_counter() - t0
    path = None if cache is None else Path(cache) / f"cfd_flutter_{foil}_M{mach:g}_{ni}x{nj}x{ns}.npz"
    if path is not None and path.exists():
        d = np.load(path)
        H, w = d["H"], d["omega"]
        times["sweep"] = float(d["seconds"])
    else:
        t0 = time.perf_counter()
        frf = cfd.lfd_response(lin, OMEGA, inputs=INPUTS, pivot=0.25, method="fast", tol=1e-6)
        times["sweep"] = time.perf_counter() - t0
        H, w = frf.H, frf.omega
        if path is not None:
            path.parent.mkdir(parents=True, exist_ok=True)
            np.savez(path, H=H, omega=w, seconds=times["sweep"])
    frf = sysid.FrequencyResponse.from_continuous(H, w, inputs=list(INPUTS), outputs=["Cl", "Cm"])
    return lin, frf, times


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--foil", default="0006", help="NACA 4-digit code of the section")
    p.add_argument("--mach", type=float, default=0.2)
    p.add_argument("--grids", default="65x17x48,97x25x64", help="comma-separated ni x nj x n_surface")
    p.add_argument("--order", type=int, default=4, help="lag roots of the motion fit")
    p.add_argument("--speed", type=float, default=1.5, help="speed index of the gust response (below flutter)")
    p.add_argument("--dt", type=float, default=0.05, help="convective time step of the coupled march")
    p.add_argument("--t-end", type=float, default=80.0, help="end of the coupled march (convective time)")
    p.add_argument("--no-ltd", action="store_true", help="skip part 2 (the coupled march)")
    p.add_argument("--cache", default=None, help="folder to keep the frequency responses in (reruns skip the sweep)")
    p.add_argument("--out", default="docs/aeroelastic", help="folder for the PNG figures")
    args = p.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    sec = ae.TypicalSection(**SECTION)
    beta = np.sqrt(1.0 - args.mach**2)

    # --- Theodorsen and its compressibility corrections (fast) --------------------------------------------
    rows = []

    def theo(name, circulation=None, factor=1.0, determinant=False):
        H = factor * th.theodorsen_motion(OMEGA, sec.a, circulation=circulation)
        data = sysid.FrequencyResponse.from_continuous(H, OMEGA, inputs=["plunge", "pitch"], outputs=["Cl", "Cm"])
        model = ae.fit_motion(data, args.order)
        res = ae.flutter(model, sec, SPEEDS)
        rows.append((name, res, model))
        if determinant:
            det = th.flutter_determinant(sec, circulation=circulation)
            rows.append((name + ", k-method determinant", det, None))
        return res

    ref = theo("Theodorsen (incompressible flat plate)", determinant=True)
    theo(f"Theodorsen, all loads / beta (PG, = mu beta), M = {args.mach:g}", factor=1.0 / beta)
    theo(f"Theodorsen, C(k) / beta (circulatory PG), M = {args.mach:g}",
         circulation=lambda k: th.theodorsen_function(k) / beta, determinant=True)

    # --- CFD on each grid ------------------------------------------------------------------------------------
    cases = []
    for spec in map(_grid_spec, args.grids.split(",")):
        t0 = time.perf_counter()
        lin, frf, times = cfd_case(args.foil, args.mach, spec, args.cache)
        ea = ae.to_elastic_axis(frf, sec)            # pivot and Cm at the quarter chord -> elastic axis
        model = ae.fit_motion(ea, args.order)
        res = ae.flutter(model, sec, SPEEDS)
        slope = float(frf.H[0, 2, 0].real)
        if model.poles.size and model.poles.max() > 10 * OMEGA.max():
            print(f"WARNING: a lag root ({model.poles.max():.3g}) lies far above the data band (omega <= {OMEGA.max():g}): "
                  "the data do not determine it, and it acts as a spurious apparent mass (the flutter result is not "
                  "to be trusted); try another --order", flush=True)
        name = f"CFD ROM NACA{args.foil} M{args.mach:g}, {spec[0]}x{spec[1]} grid ({spec[2]} on the wall)"
        rows.append((name, res, model))
        cases.append(dict(spec=spec, lin=lin, frf=frf, ea=ea, model=model, res=res, slope=slope, times=times,
                          total=time.perf_counter() - t0))
        print(f"{name}: Cl_alpha = {slope:.4f} (2 pi / beta = {2 * np.pi / beta:.4f}); motion fit max error "
              f"{model.max_error:.1e}, gust fit {model.gust_max_error:.1e}; lag roots "
              f"{np.array2string(model.poles, precision=3)}; steady+linearise {times['steady + linearise']:.0f} s, "
              f"sweep ({OMEGA.size} frequencies, 3 inputs) {times['sweep']:.0f} s", flush=True)
    fine = cases[-1]
    # which output moves what: the CFD's lift with Theodorsen's moment, and the other way round (finest grid)
    Ht = th.theodorsen_motion(OMEGA, sec.a)
    for name, (out_cfd, in_cfd) in (("CFD lift + Theodorsen moment", (0, slice(None))),
                                    ("Theodorsen lift + CFD moment", (1, slice(None))),
                                    ("Theodorsen, CFD moment due to pitch only", (1, slice(1, 2)))):
        H = Ht.copy()
        H[out_cfd, in_cfd] = fine["ea"].H[out_cfd, 1:][in_cfd]
        data = sysid.FrequencyResponse.from_continuous(H, OMEGA, inputs=["plunge", "pitch"], outputs=["Cl", "Cm"])
        model = ae.fit_motion(data, args.order)
        rows.append((f"{name} (about the elastic axis, {fine['spec'][0]}x{fine['spec'][1]})",
                     ae.flutter(model, sec, SPEEDS), model))
    theo(f"Theodorsen x CFD steady slope / 2 pi = {fine['slope'] / (2 * np.pi):.4f} (all loads)",
         factor=fine["slope"] / (2 * np.pi))

    print(f"\nFlutter of the typical section (mu = {sec.mu:g}, a = {sec.a:g}, x_alpha = {sec.x_alpha:g}, "
          f"r_alpha2 = {sec.r_alpha2:g}, omega_h/omega_alpha = {sec.omega_ratio:g}); {args.order} lag roots, "
          f"omega = 0 and 0.02 .. 2 (k <= 1)")
    print("| model | U/(b omega_alpha) | V_f = that / sqrt(mu) | omega/omega_alpha | k | speed vs Theodorsen |")
    print("| --- | --- | --- | --- | --- | --- |")
    for name, r, _ in rows:
        vf = r.speed_index / np.sqrt(sec.mu)
        k = getattr(r, "reduced_frequency", getattr(r, "k", np.nan))
        print(f"| {name} | {r.speed_index:.5f} | {vf:.5f} | {r.frequency_ratio:.5f} | {k:.5f} | "
              f"{r.speed_index / ref.speed_index - 1:+.2%} |")

    # --- figure: root loci and V-g, Theodorsen against the CFD ROM -----------------------------------------
    fig = plt.figure(figsize=(12.0, 5.5))
    gs = fig.add_gridspec(2, 2)
    ax_rl = fig.add_subplot(gs[:, 0])
    ax_g = fig.add_subplot(gs[0, 1])
    ax_f = fig.add_subplot(gs[1, 1], sharex=ax_g)
    drawn = [(ref, "Theodorsen", "-"), (fine["res"], f"CFD ROM {fine['spec'][0]}x{fine['spec'][1]}", "--")]
    for r, label, ls in drawn:
        for c, mode, j in zip(("tab:blue", "tab:red"), ("plunge branch", "pitch branch"), r.modes):
            lam = r.eigenvalues[:, j]
            lam = np.where(lam.imag < 0, lam.conj(), lam)
            ax_rl.plot(lam.real, lam.imag, ls, color=c, lw=1.5, label=f"{label}: {mode}")
            ax_g.plot(r.speeds, r.g[:, j], ls, color=c, lw=1.5)
            ax_f.plot(r.speeds, np.abs(r.eigenvalues[:, j].imag), ls, color=c, lw=1.5)
        mk = "*" if ls == "-" else "P"
        ax_rl.plot([0.0], [r.frequency_ratio], mk, color="k", ms=10, mfc="none" if ls == "--" else "k",
                   label=f"{label}: flutter V = {r.speed_index:.4f}, ω/ω_α = {r.frequency_ratio:.4f}")
        ax_f.plot([r.speed_index], [r.frequency_ratio], mk, color="k", ms=9, mfc="none" if ls == "--" else "k")
        for ax in (ax_g, ax_f):
            ax.axvline(r.speed_index, color="k", ls=ls, lw=0.7)
    ax_rl.axvline(0.0, color="k", lw=0.8)
    ax_rl.set_xlim(-0.35, 0.12)
    ax_rl.set_ylim(-0.02, 1.1)
    ax_rl.set_xlabel(r"Re $\lambda$ / $\omega_\alpha$")
    ax_rl.set_ylabel(r"Im $\lambda$ / $\omega_\alpha$")
    ax_rl.set_title(f"Root locus, V = {SPEEDS[0]:g} .. {SPEEDS[-1]:g} (solid: Theodorsen, dashed: CFD ROM)")
    ax_rl.legend(fontsize=7, loc="lower left")
    ax_g.axhline(0.0, color="k", lw=0.8)
    ax_g.set_ylim(-0.6, 0.15)
    ax_g.set_ylabel(r"g = 2 Re$\lambda$ / Im$\lambda$")
    ax_g.set_title(f"V-g: NACA{args.foil} M{args.mach:g} CFD ROM (dashed) and Theodorsen (solid)")
    ax_f.set_ylabel(r"$\omega / \omega_\alpha$")
    ax_f.set_xlabel(r"speed index V = U / (b $\omega_\alpha$)")
    for ax in (ax_rl, ax_g, ax_f):
        ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(out / "cfd_flutter.png", dpi=110)
    plt.close(fig)

    if args.no_ltd:
        print(f"figure written to {out}/cfd_flutter.png")
        return

    # --- coupled march against the coupled ROM, below flutter -------------------------------------------------
    V = args.speed
    M, K, L = section_matrices(sec, V)
    gust = cfd.OneMinusCosine(length=10.0, angle_deg=1.0, x0=-2.0)
    t0 = time.perf_counter()
    hist = coupled_ltd(fine["lin"], gust, args.dt, args.t_end, mass=M, stiffness=K, load=L, pivot=sec.elastic_axis)
    t_march = time.perf_counter() - t0
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        rom = ae.gust_response(fine["model"], sec, V, (hist.t, hist.u))
    t_rom = time.perf_counter() - t0
    march = ae.GustResponse(hist.t, 2.0 * hist.t / V, hist.u, hist.h, hist.alpha, hist.cl, hist.cm, V)
    errs = {k: float(np.abs(getattr(rom, k) - getattr(march, k)).max() / np.abs(getattr(march, k)).max())
            for k in ("plunge", "pitch", "Cl", "Cm")}
    peaks = {k: float(np.abs(getattr(march, k)).max()) for k in ("plunge", "pitch", "Cl", "Cm")}
    print(f"\nGust response at V = {V:g} ({V / fine['res'].speed_index:.0%} of the CFD ROM's flutter speed), "
          f"1-cosine gust 10 chords, 1 deg, front at x = -2; {fine['spec'][0]}x{fine['spec'][1]} grid; "
          f"coupled march dt = {args.dt:g} to s = {args.t_end:g}: {t_march:.0f} s; coupled ROM {t_rom:.2f} s")
    print("| channel | peak (coupled march) | max abs(ROM - march) / peak |")
    print("| --- | --- | --- |")
    for k in errs:
        print(f"| {k} | {peaks[k]:.4e} | {errs[k]:.2%} |")
    axs = ae.gust_response_plot(march, reference=rom, label="coupled CFD march (cfd.ltd.coupled, BDF2)",
                                reference_label=f"coupled ROM (aeroelastic.gust_response, {args.order} lags)")
    axs[0].set_title(f"NACA{args.foil} M{args.mach:g}, {fine['spec'][0]}x{fine['spec'][1]} grid, on springs at V = {V:g}: "
                     f"coupled LTD vs coupled ROM\nmax |ROM - LTD| / peak: h {errs['plunge']:.2%}, "
                     f"α {errs['pitch']:.2%}, Cl {errs['Cl']:.2%}, Cm {errs['Cm']:.2%}", fontsize=9)
    fig = axs[0].figure
    fig.tight_layout()
    fig.savefig(out / "cfd_gust.png", dpi=110)
    plt.close(fig)
    print(f"figures written to {out}/cfd_flutter.png, {out}/cfd_gust.png")


if __name__ == "__main__":
    main()
