"""Scaling of the steady solve, the fast LFD sweep and the LTD march with the grid (docs/performance.md).

Case T2 (NACA0010, M0.735, alpha 0) on C-grids refined by two in each direction from the paper's 181 x 60
(``n_surface``, wall and trailing-edge spacing scaled with the cell size), each level in its own process so
that its memory peak is its own. Per level it measures:

- ``components`` (every level): one residual evaluation, the Jacobian (``cfd.linearise_state``), one real LU
  of the LTD matrix ``J + 1.5 V / dt`` and one complex LU of a sweep shift ``J + i w V`` (nested dissection, no
  pivoting, as the code's factorisations), each with its fill and the bytes of its factors, and the
  back-substitutions (one column, and the block of six columns of a case's six gusts); the complex LU is skipped,
  with its estimated size, when its factors and SuperLU's work space would not fit in the memory available;
- ``full`` (the levels named in ``--full``): the steady solve to 1e-10 (Newton steps, factorisations, peak
  resident memory), the fast sweep on the paper's McKelvey grid (M = 256, T = 70 / (2 pi), tol 1e-8; shifts,
  basis size, peak memory) and the LTD of the six paper gusts marched together (BDF2, dt 0.02) over
  ``--ltd-steps`` steps, from which the cost of the study's 2000 steps is extrapolated: the march's first
  step (which includes its factorisation) plus 1999 times the mean of the others (every step after the first
  does the same work).

On levels without ``full`` no steady flow is computed: the matrices are those of the finest full level's
steady flow carried to the finer grid cell by cell (nearest cell centre), a state with the same structure
(shock, wall layer of the scheme), so the factorisations meet the same pattern and similar values; only the
components are measured there. The peak memory of a piece is the process's high-water mark (``VmHWM``) reset before it
(``/proc/self/clear_refs``), so it includes what the process already holds (the grid, the linear system).

Run: ``.venv/bin/python bench/scaling_bench.py [--levels 91x30,181x60,361x120,721x240]
[--full 91x30,181x60,361x120] [--ltd-steps 100] [--out docs/performance]``; writes ``scaling.json`` (one
record per level, merged into an existing file so that levels can be run separately) and ``scaling.png``
(``--plot-only`` redraws it from the JSON).
"""

import argparse
import json
import math
import os
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # run from a checkout

import numpy as np

T0 = 70 / (2 * np.pi)
PAPER = (181, 60)


def log(msg):
    print(f"[{time.strftime('%H:%M:%S')}] {msg}", file=sys.stderr, flush=True)


def parse_level(text):
    ni, nj = (int(v) for v in text.lower().split("x"))
    return ni, nj


def reset_peak():
    """Reset the process's resident-memory high-water mark (Linux); False where that is not possible."""
    try:
        with open("/proc/self/clear_refs", "w") as f:
            f.write("5")
        return True
    except OSError:
        return False


def _proc_bytes(path, key, missing):
    """A ``key: <n> kB`` line of a /proc file, in bytes (``missing`` where the file or the line is absent)."""
    try:
        with open(path) as f:
            for line in f:
                if line.startswith(key + ":"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    return missing


def peak_bytes():
    """This process's resident-memory high-water mark."""
    return _proc_bytes("/proc/self/status", "VmHWM", float("nan"))


def available_bytes():
    """Memory the system can give without swapping."""
    return _proc_bytes("/proc/meminfo", "MemAvailable", float("inf"))


def timed(f, repeat=1):
    best, out = math.inf, None
    for _ in range(repeat):
        t = time.perf_counter()
        out = f()
        best = min(best, time.perf_counter() - t)
    return best, out


def make_grid(ni, nj):
    import cfd

    r = (ni - 1) / (PAPER[0] - 1)
    return cfd.c_grid(cfd.naca("0010"), ni=ni, nj=nj, n_surface=2 * int(round(50 * r)), wall_spacing=0.004 / r,
                      te_spacing=0.006 / r)


def factor_record(A, perm):
    """Time, fill and factor bytes of one nested-dissection LU of ``A`` (no pivoting, as ``cfd.superlu``)."""
    from cfd.superlu import splu_nested

    Ap = A.tocsr()[perm][:, perm].tocsc()
    reset_peak()
    t, lu = timed(lambda: splu_nested(Ap))
    nnz = lu.L.nnz + lu.U.nnz
    value = 16 if np.iscomplexobj(Ap.data) else 8
    rng = np.random.default_rng(0)
    r1 = rng.standard_normal(A.shape[0]).astype(Ap.dtype)
    r6 = rng.standard_normal((A.shape[0], 6)).astype(Ap.dtype)
    t1, _ = timed(lambda: lu.solve(r1), 3)
    t6, _ = timed(lambda: lu.solve(r6), 3)
    return dict(seconds=t, fill=nnz / A.nnz, factor_bytes=nnz * (value + 4), peak_bytes=peak_bytes(),
                solve_1=t1, solve_6=t6)


def carried_state(grid, states):
    """The steady state of the finest level in ``states`` (npz files) at the cells of ``grid`` (nearest centre)."""
    from scipy.spatial import cKDTree

    src = max(states, key=lambda p: np.load(p)["q"].size)
    data = np.load(src)
    tree = cKDTree(np.column_stack([data["xc"].ravel(), data["yc"].ravel()]))
    _, idx = tree.query(np.column_stack([grid.xc.ravel(), grid.yc.ravel()]))
    return data["q"].reshape(-1, 4)[idx].reshape(grid.cell_shape + (4,)), Path(src).stem


def measure_level(ni, nj, full, ltd_steps, state_dir):
    import scipy.sparse as sp

    import cfd
    import sysid
    from cfd.euler import residual
    from cfd.flow import FlowCondition
    from cfd.linear import grid_permutation, linearise_state

    mach = 0.735
    rec = dict(level=f"{ni}x{nj}", cells=(ni - 1) * (nj - 1), unknowns=4 * (ni - 1) * (nj - 1), full=full)
    t, grid = timed(lambda: make_grid(ni, nj))
    rec["grid_s"] = t
    flow = FlowCondition(mach, 0.0)
    if full:
        log(f"{ni}x{nj}: steady")
        reset_peak()
        t, sol = timed(lambda: cfd.solve_steady(grid, mach, 0.0))
        info = sol.info
        rec["steady"] = dict(seconds=t, newton_steps=info.get("newton_steps"), factorisations=info.get("n_factor"),
                             back_substitutions=info.get("n_solve"), converged=bool(sol.converged),
                             cl=sol.cl, peak_bytes=peak_bytes())
        q = sol.q
        np.savez(Path(state_dir) / f"state-{ni}x{nj}.npz", q=q, xc=grid.xc, yc=grid.yc)
    else:
        states = sorted(Path(state_dir).glob("state-*.npz"))
        if not states:
            raise SystemExit("no steady state of a full level to carry over: run a --full level first")
        q, rec["state_from"] = carried_state(grid, states)
    t, _ = timed(lambda: residual(grid, q, flow), 3)
    rec["residual_s"] = t
    t, lin = timed(lambda: linearise_state(grid, q, flow))
    rec["linearise_s"] = t
    rec["nnz_J"] = int(lin.J.nnz)
    perm = grid_permutation(grid)
    h = lin.to_solver_time(0.02)
    log(f"{ni}x{nj}: real LU (LTD matrix)")
    rec["real_lu"] = factor_record(lin.J + sp.diags(1.5 * lin.V / h), perm)
    # complex factors: 16 + 4 bytes an entry; the process's peak was 2.1 - 3.4 times them (361 x 120 - 91 x 30),
    # and a complex LU of 721 x 240 attempted under a 1.5x estimate was killed at 24.4 GB resident
    need = 2.2 * rec["real_lu"]["factor_bytes"] * 20 / 12
    if need > available_bytes():
        log(f"{ni}x{nj}: complex LU skipped: its factors need about {need / 2**30:.1f} GiB with SuperLU's work "
            f"space, {available_bytes() / 2**30:.1f} GiB available")
        rec["complex_lu"] = dict(skipped=True, estimated_bytes=need)
    else:
        log(f"{ni}x{nj}: complex LU (a sweep shift, omega = 1)")
        rec["complex_lu"] = factor_record(lin.J + sp.diags(1j * lin.to_solver_frequency(1.0) * lin.V), perm)
    if full:
        log(f"{ni}x{nj}: fast sweep (M = 256)")
        reset_peak()
        t, frf = timed(lambda: cfd.lfd_response(lin, sysid.mckelvey_grid(256, T0), method="fast"))
        md = frf.metadata
        rec["sweep"] = dict(seconds=t, shifts=len(md.get("shifts", [])), basis=md.get("basis_size"),
                            max_estimate=float(np.max(md["error_estimate"]) / np.max(np.abs(frf.H))),
                            peak_bytes=peak_bytes())
        log(f"{ni}x{nj}: LTD, six gusts, {ltd_steps} steps")
        from studies.config.cases import gust_case, to_gust

        gusts = [to_gust(gust_case(n), x0=-2.0) for n in ("G1", "G2", "G3", "G4", "G5", "G6")]
        reset_peak()
        stamps = {}

        def progress(k, n, s):
            stamps[k] = time.perf_counter()

        t, _ = timed(lambda: cfd.ltd_responses(lin, gusts, 0.02, 0.02 * ltd_steps, max_phase_error=1.0,
                                                progress=progress))
        step = (stamps[ltd_steps] - stamps[1]) / (ltd_steps - 1)     # steps 2 .. n: no factorisation in them
        rec["ltd"] = dict(seconds=t, steps=ltd_steps, step_s=step, first_step_s=t - (ltd_steps - 1) * step,
                          study_2000_s=t + (2000 - ltd_steps) * step, peak_bytes=peak_bytes())
    return rec


def fit_exponent(n, t):
    n, t = np.asarray(n, float), np.asarray(t, float)
    ok = np.isfinite(t) & (t > 0)
    if ok.sum() < 2:
        return float("nan")
    return float(np.polyfit(np.log(n[ok]), np.log(t[ok]), 1)[0])


def series(records, *path):
    out = []
    for r in records:
        v = r
        for p in path:
            v = v.get(p) if isinstance(v, dict) else None
        out.append(np.nan if v is None else float(v))
    return np.array(out)


def plot(records, png):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    records = sorted(records, key=lambda r: r["unknowns"])
    n = np.array([r["unknowns"] for r in records], float)
    fig, (ax_t, ax_m) = plt.subplots(1, 2, figsize=(12, 6.0))
    for label, path, style in [
        ("steady solve", ("steady", "seconds"), "o-"),
        ("fast sweep, 257 frequencies", ("sweep", "seconds"), "s-"),
        ("LTD, 6 gusts x 2000 steps", ("ltd", "study_2000_s"), "^-"),
        ("real LU (LTD matrix)", ("real_lu", "seconds"), "o--"),
        ("complex LU (one shift)", ("complex_lu", "seconds"), "s--"),
        ("back-substitution, 6 columns", ("real_lu", "solve_6"), "^:"),
    ]:
        y = series(records, *path)
        if np.isfinite(y).any():
            ax_t.loglog(n, y, style, label=f"{label} (N^{fit_exponent(n, y):.2f})")
    ax_t.set_xlabel("unknowns N (4 per cell)")
    ax_t.set_ylabel("seconds (one process, one BLAS thread)")
    ax_t.set_title("cost")
    for label, path, style in [
        ("real LU factors", ("real_lu", "factor_bytes"), "o--"),
        ("complex LU factors", ("complex_lu", "factor_bytes"), "s--"),
        ("peak, steady solve", ("steady", "peak_bytes"), "o-"),
        ("peak, fast sweep", ("sweep", "peak_bytes"), "s-"),
    ]:
        y = series(records, *path) / 2**30
        if np.isfinite(y).any():
            ax_m.loglog(n, y, style, label=f"{label} (N^{fit_exponent(n, y):.2f})")
    ax_m.set_xlabel("unknowns N (4 per cell)")
    ax_m.set_ylabel("GiB")
    ax_m.set_title("memory")
    for ax in (ax_t, ax_m):
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=2)
        for r, x in zip(records, n):
            ax.annotate(r["level"], (x, ax.get_ylim()[0]), textcoords="offset points", xytext=(0, 4),
                        ha="center", fontsize=7, color="0.4")
    fig.suptitle("T2 (NACA0010, M0.735): cost and memory against grid size")
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--levels", default="91x30,181x60,361x120,721x240")
    ap.add_argument("--full", default="91x30,181x60,361x120", help="levels with the steady, sweep and LTD runs")
    ap.add_argument("--ltd-steps", type=int, default=100)
    ap.add_argument("--out", default=str(ROOT / "docs" / "performance"))
    ap.add_argument("--plot-only", action="store_true")
    ap.add_argument("--state-dir", default="/tmp/lfdrom-scaling", help="steady states of the full levels (npz)")
    ap.add_argument("--one", default=None, help=argparse.SUPPRESS)
    args = ap.parse_args()
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    if args.one:
        ni, nj = parse_level(args.one)
        full = args.one in args.full.split(",")
        print(json.dumps(measure_level(ni, nj, full, args.ltd_steps, args.state_dir)))
        return
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    Path(args.state_dir).mkdir(parents=True, exist_ok=True)
    path = out / "scaling.json"
    records = {r["level"]: r for r in json.loads(path.read_text())["levels"]} if path.exists() else {}
    if not args.plot_only:
        env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", MKL_NUM_THREADS="1")
        for level in args.levels.split(","):
            log(f"level {level}")
            run = subprocess.run([sys.executable, __file__, "--one", level, "--full", args.full, "--ltd-steps",
                                  str(args.ltd_steps), "--state-dir", args.state_dir], env=env,
                                 capture_output=True, text=True)
            sys.stderr.write(run.stderr)
            if run.returncode != 0:
                log(f"level {level} failed (exit {run.returncode}); kept the levels measured so far")
                continue
            records[level] = json.loads(run.stdout.strip().splitlines()[-1])
            records[level]["measured"] = time.strftime("%Y-%m-%d")
            path.write_text(json.dumps({"case": "T2", "levels": list(records.values())}, indent=1))
    recs = sorted(records.values(), key=lambda r: r["unknowns"])
    plot(recs, out / "scaling.png")
    n = [r["unknowns"] for r in recs]
    print("| grid | unknowns | nnz(J) | real LU s (fill, GiB) | complex LU s (fill, GiB) | solve 1 / 6 cols ms "
          "| steady s (LU) | sweep s (shifts) | LTD 2000 steps s | peak GiB steady / sweep |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in recs:
        rl, cl = r["real_lu"], r["complex_lu"]
        if cl.get("skipped"):
            cl = dict(seconds=float("nan"), fill=float("nan"), factor_bytes=cl["estimated_bytes"] / 1.5)
        st, sw, lt = r.get("steady"), r.get("sweep"), r.get("ltd")
        print(f"| {r['level']} | {r['unknowns']:,} | {r['nnz_J']:,} | {rl['seconds']:.2f} ({rl['fill']:.1f}, "
              f"{rl['factor_bytes'] / 2**30:.2f}) | {cl['seconds']:.2f} ({cl['fill']:.1f}, "
              f"{cl['factor_bytes'] / 2**30:.2f}) | {1e3 * rl['solve_1']:.0f} / {1e3 * rl['solve_6']:.0f} | "
              + (f"{st['seconds']:.1f} ({st['factorisations']}) | " if st else "- | ")
              + (f"{sw['seconds']:.1f} ({sw['shifts']}) | " if sw else "- | ")
              + (f"{lt['study_2000_s']:.0f} | " if lt else "- | ")
              + (f"{st['peak_bytes'] / 2**30:.2f} / {sw['peak_bytes'] / 2**30:.2f} |" if st and sw else "- |"))
    for label, path_ in [("real LU", ("real_lu", "seconds")), ("complex LU", ("complex_lu", "seconds")),
                         ("back-substitution (6 columns)", ("real_lu", "solve_6")),
                         ("real LU factor bytes", ("real_lu", "factor_bytes")),
                         ("complex LU factor bytes", ("complex_lu", "factor_bytes")),
                         ("steady", ("steady", "seconds")), ("sweep", ("sweep", "seconds")),
                         ("LTD (2000 steps)", ("ltd", "study_2000_s"))]:
        print(f"exponent of N, {label}: {fit_exponent(n, series(recs, *path_)):.2f}")


if __name__ == "__main__":
    main()
