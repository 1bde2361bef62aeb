"""Validation runs of the steady Euler solver behind docs/validation.md (figures in docs/figures/steady-*.png).

Run: ``MPLBACKEND=Agg .venv/bin/python bench/steady_validation.py`` (about 10 minutes on 2 cores).
Writes ``docs/figures/steady-validation.json`` with every number quoted in the report.
"""

import json
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests" / "cfd"))

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import cfd  # noqa: E402
from cfd.plots import plot_cp, plot_mach  # noqa: E402
from flowgrids import parabolic_c_grid  # noqa: E402

FIG = ROOT / "docs" / "figures"
PAPER = dict(ni=181, nj=60, n_surface=100)
CASES = {  # paper Table 1, all at alpha 0
    "T1": ("0006", 0.85), "T2": ("0010", 0.735), "T3": ("0010", 0.85),
    "T4": ("0018", 0.25), "T5": ("2410", 0.25), "T6": ("2410", 0.735),
}


def solve(grid, mach, alpha):
    t = time.perf_counter()
    sol = cfd.solve_steady(grid, mach, alpha, tol=1e-10)
    return sol, {"cl": sol.cl, "cd": sol.cd, "cm": sol.cm, "newton": sol.info["newton_steps"],
                 "iterations": sol.iterations, "drop": sol.info["relative_drop"], "abs_res": sol.history[-1],
                 "time_s": time.perf_counter() - t}


def main():
    FIG.mkdir(parents=True, exist_ok=True)
    out = {}
    grids = {}

    def grid(code, ni=181, nj=60, n_surface=100):
        key = (code, ni, nj, n_surface)
        if key not in grids:
            grids[key] = cfd.c_grid(cfd.naca(code), ni=ni, nj=nj, n_surface=n_surface)
        return grids[key]

    # A. Free-stream preservation.
    flat = parabolic_c_grid(thickness=0.0, n_surface=100, n_wake=40, nj=60, wiggle=0.3)
    f = cfd.FlowCondition(0.7, 0.0)
    r = cfd.residual(flat, np.broadcast_to(f.q, flat.cell_shape + (4,)), f)
    g = grid("0012")
    f2 = cfd.FlowCondition(0.8, 1.25)
    r2 = cfd.residual(g, np.broadcast_to(f2.q, g.cell_shape + (4,)), f2)
    out["free_stream"] = {
        "flat_plate_all_cells": float(np.abs(r).max()),
        "naca0012_rows_jc>=2": float(np.abs(r2[:, 2:]).max()),
        "naca0012_far_field_cells": float(max(np.abs(r2[:, -1]).max(), np.abs(r2[0]).max(), np.abs(r2[-1]).max())),
    }
    print(out["free_stream"], flush=True)

    # B. Subsonic symmetric flow, grid refinement.
    out["m05"] = []
    for ni, nj, ns in ((65, 17, 40), (97, 25, 64), (181, 60, 100), (257, 86, 144)):
        sol, res = solve(grid("0012", ni, nj, ns), 0.5, 0.0)
        res["grid"] = f"{ni}x{nj} ({ns} wall)"
        out["m05"].append(res)
        print("M0.5", res, flush=True)

    # C. Transonic NACA0012 (AGARD AR-211).
    out["agard"] = {}
    sols = {}
    for name, (m, a) in {"M0.80 a1.25": (0.8, 1.25), "M0.85 a1.00": (0.85, 1.0)}.items():
        for ni, nj, ns in ((97, 25, 64), (181, 60, 100)):
            sol, res = solve(grid("0012", ni, nj, ns), m, a)
            out["agard"][f"{name} {ni}x{nj}"] = res
            sols[(name, ni)] = sol
            print(name, ni, res, flush=True)
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    for ax, name in zip(axes, ("M0.80 a1.25", "M0.85 a1.00")):
        plot_cp(sols[(name, 97)], ax=ax, label="97 x 25")
        plot_cp(sols[(name, 181)], ax=ax, label="181 x 60")
        ax.set_title(f"NACA0012 {name.replace('a', 'alpha ')} deg")
        ax.legend()
    fig.tight_layout()
    fig.savefig(FIG / "steady-agard-cp.png", dpi=120)
    plt.close(fig)
    fig, ax = plt.subplots(figsize=(7, 5))
    plot_mach(sols[("M0.80 a1.25", 181)], ax=ax)
    fig.savefig(FIG / "steady-m080-mach.png", dpi=120)
    plt.close(fig)

    # D. Lift slope at M0.25 (symmetric: Cl(0) = 0).
    sol, res = solve(grid("0012"), 0.25, 1.0)
    slope = sol.cl / np.deg2rad(1.0)
    ref = 2 * np.pi / np.sqrt(1 - 0.25**2) * (1 + 0.77 * 0.12)
    out["lift_slope_m025"] = {"slope_per_rad": slope, "pg_thickness": ref, "rel_err": slope / ref - 1, **res}
    print(out["lift_slope_m025"], flush=True)

    # E. Paper cases T1-T6 at alpha 0.
    out["paper"] = {}
    fig, axes = plt.subplots(2, 3, figsize=(14, 8))
    hist = {}
    for ax, (case, (code, m)) in zip(axes.ravel(), CASES.items()):
        sol, res = solve(grid(code), m, 0.0)
        res["max_mach"] = float(sol.fields()["mach"].max())
        out["paper"][case] = res
        hist[case] = sol.history
        print(case, res, flush=True)
        plot_cp(sol, ax=ax)
        ax.set_title(f"{case}: NACA{code} M{m} alpha 0")
        f1, a1 = plt.subplots(figsize=(6, 5))
        plot_cp(sol, ax=a1)
        a1.set_title(f"{case}: NACA{code} M{m}, alpha 0 (181 x 60)")
        f1.savefig(FIG / f"steady-{case}-cp.png", dpi=120)
        plt.close(f1)
    fig.tight_layout()
    fig.savefig(FIG / "steady-paper-cases-cp.png", dpi=110)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    for case, h in hist.items():
        ax.semilogy(h / h[0], label=case)
    ax.set_xlabel("iteration (500 RK5 steps, then Newton)")
    ax.set_ylabel("|R|_2 / |R_0|_2")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(FIG / "steady-convergence.png", dpi=120)
    plt.close(fig)

    (FIG / "steady-validation.json").write_text(json.dumps(out, indent=1, default=float))


def refinement():
    """M0.5 NACA0012 on a grid family with every spacing scaled with the cell count (h, h/2, h/4 of 91 x 31)."""
    res = []
    for k, (ni, nj, ns) in enumerate(((91, 31, 50), (181, 61, 100), (361, 121, 200))):
        s = 2.0 ** -k
        g = cfd.c_grid(cfd.naca("0012"), ni=ni, nj=nj, n_surface=ns, wall_spacing=0.008 * s,
                       te_spacing=0.012 * s, le_spacing=0.008 * s)
        _, r = solve(g, 0.5, 0.0)
        r["grid"] = f"{ni}x{nj} ({ns} wall), wall/TE/LE spacing {0.008 * s:g}/{0.012 * s:g}/{0.008 * s:g}"
        res.append(r)
        print("refinement", r, flush=True)
    path = FIG / "steady-validation.json"
    data = json.loads(path.read_text()) if path.exists() else {}
    data["m05_refinement"] = res
    path.write_text(json.dumps(data, indent=1, default=float))


if __name__ == "__main__":
    if "--refinement" in sys.argv:
        refinement()
    else:
        main()
