"""Isogai's case A: the transonic dip of the flutter speed of a NACA 64A010 typical section (docs/isogai.md).

Section (Isogai 1979/1981, case A): NACA 64A010, elastic axis half a chord ahead of the leading edge
(``a = -2``), ``x_alpha = 1.8``, ``r_alpha^2 = 3.48``, ``omega_h / omega_alpha = 1``, ``mu = 60``, zero incidence.

Per Mach number: steady Euler flow at 0 deg (``cfd.solve_steady``), the plunge and pitch frequency responses about
the quarter chord (``cfd.lfd_response``; ``omega = 0`` and ``--n-freq`` points geometrically spaced over
``omega = 0.02 .. --omega-max``, default 6, i.e. ``k = 0.01 .. 3``), moved to the elastic axis
(``aeroelastic.to_elastic_axis``), fitted
(Roger form, ``--order`` lags) and solved for flutter as an eigenvalue problem over speed
(``aeroelastic.flutter``; speeds ``V_f = 0.2 .. 3``: below ``V_f = 0.2`` the structural frequencies reach
``k > 0.65``, near the top of the data). Every crossing of the imaginary axis on the speed grid is listed, so a
second (higher) flutter branch or a re-stabilisation shows.

Run: ``nice -n 15 .venv/bin/python bench/isogai.py --grid 97x25x64`` (about two to eight minutes per Mach on the
shared two-core machine). ``--cache DIR`` keeps each Mach's FRF (``.npz``) so that a rerun only refits;
``--plot PATH`` writes the V_f-vs-Mach figure (default ``docs/aeroelastic/isogai.png``).
"""

import argparse
import json
import sys
import time
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import numpy as np  # noqa: E402

import aeroelastic as ae  # noqa: E402
import cfd  # noqa: E402
import sysid  # noqa: E402

SECTION = dict(mu=60.0, a=-2.0, x_alpha=1.8, r_alpha2=3.48, omega_ratio=1.0)
MACHS = (0.70, 0.75, 0.80, 0.825, 0.85, 0.875, 0.90)

# Published flutter speed indices V_f = U / (b omega_alpha sqrt(mu)) for case A: see docs/isogai.md for where each
# comes from and how it was read. {label: [(Mach, V_f), ...]}; empty when nothing was at hand.
PUBLISHED = {}


def frequencies(n, omega_max):
    """``omega = 0`` and ``n`` points geometrically spaced over ``0.02 .. omega_max`` (U/c; ``k = omega / 2``)."""
    return np.concatenate([[0.0], np.geomspace(0.02, omega_max, n)])


def mach_frf(mach, grid_spec, n_freq, omega_max, method, cache):
    """Quarter-chord plunge/pitch FRF of the NACA 64A010 at ``mach``, 0 deg (from ``cache`` when there)."""
    ni, nj, ns = grid_spec
    name = f"isogai_M{mach:.3f}_{ni}x{nj}x{ns}_n{n_freq}_w{omega_max:g}_{method}.npz"
    path = None if cache is None else Path(cache) / name
    w = frequencies(n_freq, omega_max)
    failed = None if path is None else path.with_suffix(".failed")
    if failed is not None and failed.exists():
        raise cfd.ConvergenceError(f"{failed.read_text().strip()} (cached failure, delete {failed.name} to retry)")
    if path is not None and path.exists():
        d = np.load(path)
        info = json.loads(str(d["info"]))
        return sysid.FrequencyResponse.from_continuous(d["H"], d["omega"], inputs=["plunge", "pitch"],
                                                       outputs=["Cl", "Cm"], metadata={"pivot": 0.25}), info
    t0 = time.perf_counter()
    grid = cfd.c_grid(cfd.naca("64A010"), ni=ni, nj=nj, n_surface=ns)
    try:
        sol = cfd.solve_steady(grid, mach, 0.0)
    except cfd.ConvergenceError as err:
        if failed is not None:
            failed.parent.mkdir(parents=True, exist_ok=True)
            failed.write_text(str(err).split(";")[0])
        raise
    t1 = time.perf_counter()
    lin = cfd.linearise(sol)
    frf = cfd.lfd_response(lin, w, inputs=("plunge", "pitch"), pivot=0.25, method=method)
    t2 = time.perf_counter()
    cp = np.asarray(sol.cp)
    info = dict(steady_s=t1 - t0, lfd_s=t2 - t1, cd=float(sol.cd), cp_min=float(cp.min()),
                cp_star=float(cp_sonic(mach)), supersonic=bool(cp.min() < cp_sonic(mach)))
    if path is not None:
        path.parent.mkdir(parents=True, exist_ok=True)
        np.savez(path, H=frf.H, omega=w, info=json.dumps(info))
    return frf, info


def cp_sonic(mach, gamma=1.4):
    """Critical pressure coefficient ``Cp*`` (sonic) at free-stream Mach ``mach``."""
    return 2.0 / (gamma * mach**2) * (((2 + (gamma - 1) * mach**2) / (gamma + 1)) ** (gamma / (gamma - 1)) - 1.0)


def crossings(res):
    """All crossings of the imaginary axis along the tracked branches: list of (V_f, direction, w/w_alpha)."""
    lam = np.asarray(res.eigenvalues)
    V = np.asarray(res.speeds) / np.sqrt(res.section.mu)
    out = []
    tol = 1e-9
    for j in range(lam.shape[1]):
        re = lam[:, j].real - tol
        for i in np.nonzero(np.sign(re[:-1]) != np.sign(re[1:]))[0]:
            f = re[i] / (re[i] - re[i + 1])
            if lam[i, j].imag + f * (lam[i + 1, j].imag - lam[i, j].imag) < -1e-9:
                continue  # the conjugate of a root counted already
            out.append((float(V[i] + f * (V[i + 1] - V[i])), "unstable" if re[i] < 0 else "stable",
                        float(abs(lam[i, j].imag + f * (lam[i + 1, j].imag - lam[i, j].imag)))))
    return sorted(out)


def analyse(frf, order):
    """Elastic-axis data, fit, flutter result and the list of axis crossings."""
    sec = ae.TypicalSection(**SECTION)
    ea = ae.to_elastic_axis(frf, sec, pivot=0.25, moment_axis=0.25)
    model = ae.fit_motion(ea, order)
    speeds = np.linspace(0.2, 3.0, 561) * np.sqrt(sec.mu)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        res = ae.flutter(model, sec, speeds=speeds)
    return ea, model, res, crossings(res)


def sensitivity(frf):
    """``V_f`` and ``w/w_alpha`` for fits with 3, 4, 6 lags, and with the data cut at ``omega <= 2`` (4 lags)."""
    out = {}
    for order in (3, 4, 6):
        _, _, res, _ = analyse(frf, order)
        out[f"{order} lags"] = (float(res.flutter_speed_index), float(res.frequency_ratio))
    keep = frf.omega <= 2.0 + 1e-12
    cut = sysid.FrequencyResponse.from_continuous(frf.H[:, :, keep], frf.omega[keep], inputs=frf.inputs,
                                                  outputs=frf.outputs, metadata=frf.metadata)
    _, _, res, _ = analyse(cut, 4)
    out["omega <= 2, 4 lags"] = (float(res.flutter_speed_index), float(res.frequency_ratio))
    return out


def theodorsen_pg(mach, order=4):
    """Flat-plate reference: Theodorsen's loads divided by ``sqrt(1 - M^2)`` (Prandtl-Glauert), same fit/solver.

    Subsonic linear theory for a thin section: no thickness, no shock; it has no transonic dip (its ``V_f`` falls
    smoothly like ``beta``-scaled loads), so the gap to it is what the Euler data add.
    """
    from aeroelastic import theodorsen as th

    sec = ae.TypicalSection(**SECTION)
    w = np.concatenate([[0.0], np.geomspace(0.01, 6.0, 100)])
    base = th.theodorsen_frf(w, sec.a)
    frf = sysid.FrequencyResponse.from_continuous(base.H / np.sqrt(1.0 - mach**2), w, inputs=base.inputs,
                                                  outputs=base.outputs)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        res = ae.flutter(frf, sec, speeds=np.linspace(0.2, 3.0, 561) * np.sqrt(sec.mu), order=order)
    return float(res.flutter_speed_index), float(res.frequency_ratio)


def plot(rows, path, overlays=(), grid=""):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7.2, 5.6))
    m = [r["mach"] for r in rows]
    ax.plot(m, [r["V_f"] for r in rows], "o-", color="k", label=f"lfdrom: LFD Euler + Roger fit, grid {grid}")
    ax.plot(m, [r["V_f_theodorsen_pg"] for r in rows], ":", color="0.5",
            label="flat plate, Theodorsen / sqrt(1 - M^2) (same fit and solver)")
    for r in rows:  # higher branches / re-stabilisation
        for v, kind, _ in r["crossings"][1:]:
            ax.plot(r["mach"], v, "x" if kind == "unstable" else "+", color="k", ms=7)
        if r["kind"] == "no steady state":
            ax.axvline(r["mach"], color="0.7", ls="--", lw=0.8)
    ax.plot([], [], "x", color="k", label="further crossing to unstable (same run)")
    ax.plot([], [], "+", color="k", label="crossing back to stable (same run)")
    if any(r["kind"] == "no steady state" for r in rows):
        ax.plot([], [], "--", color="0.7", lw=0.8, label=f"no converged steady state (grid {grid})")
    for ov in overlays:  # other grids: {"grid": ..., "rows": [...]}
        pts = [(r["mach"], r["V_f"]) for r in ov["rows"] if np.isfinite(r["V_f"])]
        if pts:
            ax.plot(*zip(*pts), "s", mfc="none", color="tab:red", ms=8,
                    label=f"lfdrom, grid {ov['grid']} (first crossing; +, x as above in red)")
        for r in ov["rows"]:
            for v, kind, _ in r["crossings"][1:]:
                ax.plot(r["mach"], v, "x" if kind == "unstable" else "+", color="tab:red", ms=7)
    marks = iter("d^v<>o")
    for label, pts in PUBLISHED.items():
        if pts:
            pm, pv = zip(*pts)
            ax.plot(pm, pv, next(marks) + "--", mfc="none", label=label)
    ax.set_xlabel("Mach number")
    ax.set_ylabel(r"flutter speed index $V_f = U / (b\,\omega_\alpha \sqrt{\mu})$")
    ax.set_title("Isogai case A (NACA 64A010, a = -2, mu = 60)")
    top = [1.05 * v for r in rows for v in [r["V_f"]] + [c[0] for c in r["crossings"]] if np.isfinite(v)]
    ax.set_ylim(0, max([2.0] + top))
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=2)
    fig.tight_layout()
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=130)
    plt.close(fig)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--grid", default="97x25x64", help="ni x nj x n_surface of cfd.c_grid (default 97x25x64)")
    p.add_argument("--machs", default=",".join(str(m) for m in MACHS), help="comma-separated Mach numbers")
    p.add_argument("--n-freq", type=int, default=14, help="nonzero frequencies, 0.02 .. omega-max (default 14)")
    p.add_argument("--omega-max", type=float, default=6.0, help="highest omega in U/c (default 6, k = 3)")
    p.add_argument("--method", default="direct", choices=("direct", "fast", "auto"), help="cfd.lfd_response path")
    p.add_argument("--order", type=int, default=4, help="lag roots of the Roger fit (default 4)")
    p.add_argument("--cache", default=None, help="folder for the FRFs (.npz), reused when present")
    p.add_argument("--plot", default=str(ROOT / "docs" / "aeroelastic" / "isogai.png"), help="figure path ('' = none)")
    p.add_argument("--json", default=None, help="write the table as JSON here")
    p.add_argument("--sensitivity", action="store_true", help="also refit with 3/6 lags and omega <= 2")
    p.add_argument("--overlay", action="append", default=[], help="JSON of another run (--json) to add to the plot")
    a = p.parse_args(argv)
    try:
        grid_spec = tuple(int(v) for v in a.grid.lower().split("x"))
        machs = [float(v) for v in a.machs.split(",") if v.strip()]
    except ValueError:
        p.error("--grid is ni x nj x n_surface (e.g. 97x25x64); --machs comma-separated numbers (e.g. 0.8,0.85)")
    if len(grid_spec) != 3:
        p.error("--grid needs three numbers, ni x nj x n_surface, e.g. 97x25x64")
    rows = []
    print(f"grid {a.grid}, {a.n_freq + 1} frequencies 0, 0.02 .. {a.omega_max:g} ({a.method}), "
          f"Roger fit {a.order} lags")
    print(f"{'Mach':>6} {'V_f':>8} {'w/w_a':>7} {'k':>6} {'kind':>10}  other crossings (V_f, ->, w/w_a)    "
          f"{'Cp_min':>7} {'Cp*':>7} {'steady':>7} {'LFD':>6}")
    for mach in machs:
        try:
            frf, info = mach_frf(mach, grid_spec, a.n_freq, a.omega_max, a.method, a.cache)
        except cfd.ConvergenceError as err:  # no steady state to linearise about: say so, go on
            print(f"{mach:6.4g}  no result: {str(err).split(';')[0]}", flush=True)
            rows.append(dict(mach=mach, V_f=float("nan"), ratio=float("nan"), k=float("nan"), kind="no steady state",
                             crossings=[], V_f_theodorsen_pg=theodorsen_pg(mach, a.order)[0]))
            continue
        ea, model, res, cross = analyse(frf, a.order)
        fit_err = float(model.max_error)
        row = dict(mach=mach, V_f=float(res.flutter_speed_index), ratio=float(res.frequency_ratio),
                   k=float(res.reduced_frequency), kind=res.kind, crossings=cross, fit_err=fit_err,
                   Cl_alpha=float(ea.H[0, 1, 0].real), Cm_alpha_ea=float(ea.H[1, 1, 0].real), **info)
        row["V_f_theodorsen_pg"], row["ratio_theodorsen_pg"] = theodorsen_pg(mach, a.order)
        rows.append(row)
        if a.sensitivity:
            row["sensitivity"] = sensitivity(frf)
        pub = "; ".join(f"{lab.split(':')[0]} {v:.3f}" for lab, pts in PUBLISHED.items() for m, v in pts
                        if abs(m - mach) < 1e-6) or "n/a"
        row["published"] = pub
        others = "; ".join(f"{v:.3f} {'u' if d == 'unstable' else 's'} {f:.3f}" for v, d, f in cross[1:]) or "-"
        print(f"{mach:6.4g} {row['V_f']:8.4f} {row['ratio']:7.4f} {row['k']:6.3f} {res.kind:>10}  {others:<34} "
              f"{info['cp_min']:7.3f} {info['cp_star']:7.3f} {info['steady_s']:6.0f}s {info['lfd_s']:5.0f}s  "
              f"(fit {fit_err:.1e})  Th-PG {row['V_f_theodorsen_pg']:.3f} / {row['ratio_theodorsen_pg']:.3f}"
              f"  published: {pub}", flush=True)
        if a.sensitivity:
            print("        fit sensitivity (V_f, w/w_a): " + "; ".join(
                f"{k} {v[0]:.4f} {v[1]:.3f}" for k, v in row["sensitivity"].items()), flush=True)
    if a.json:
        Path(a.json).write_text(json.dumps(dict(grid=a.grid, n_freq=a.n_freq, omega_max=a.omega_max,
                                                method=a.method, order=a.order, rows=rows), indent=1))
    if a.plot:
        plot(rows, a.plot, [json.loads(Path(f).read_text()) for f in a.overlay], a.grid)
        print(f"figure: {a.plot}")
    return rows


if __name__ == "__main__":
    main()
