"""Trial of a primal reduced basis for the LFD sweep: how many vectors a rational Krylov basis of the gust
response needs where ``cfd.sweep`` (which reduces the dual, Cl and Cm) needs 335 - 375.

Not a solver: it measures. On the paper grid (case T2 or T5, SVM gust, ``x_ref = 0``, McKelvey's grid
M = 256, T = 70 / (2 pi)) it

1. runs ``cfd.sweep.fast_sweep`` (the dual basis) as the reference (its errors against the direct path are
   1e-13 - 3e-11, docs/lfd-sweep.md) and keeps its shifts;
2. at the same shifts, in the same order, factorises ``J + i mach sigma V`` (nested dissection, no pivoting,
   one step of iterative refinement per solve) and generates the Taylor moments of the primal solution,
   ``A(sigma) x_k = -b_k - i mach V x_(k-1)`` with ``b_k = B g^(k)(sigma) / k!``: the omega-derivatives of the
   gust's face averages, averages of ``(-i x)^k / k! exp(-i sigma x)`` along each face by 32-point
   Gauss-Legendre quadrature (checked against ``cfd.gust.face_gust_harmonic`` for ``k = 0``);
3. orthonormalises them into ``W``, nested as in the dual sweep (``cfd.sweep.orthonormal.nested_extension``), and
   evaluates the Galerkin outputs ``C W (W^H (J + i mach omega V) W)^-1 (-W^H b(omega))`` at every finite
   frequency after each shift, with the residual-free nested estimate ``10 |y - y_|`` (``y_``: the model without
   each shift's last moment) and its ratio to the true error;
4. then adds shifts at the worst frequency that is not a shift (true error against the reference, a trial's
   privilege) while the error there exceeds ``1e-8`` relative (``max(|H|, 1e-3 max |H|)`` per output, the
   sweep's criterion), at most ``--extra`` of them. At a shift frequency the dual sweep returns the shift's
   direct output; the trial prints the reduced solve's error there separately. With ``--greedy`` the shifts
   are chosen from scratch the same way (``omega = 0`` first), e.g. to see whether more moments per shift
   (``--n-moments 32``) need fewer shifts.

Prints per shift: basis size, worst error per output, failing frequencies and the time in factorisations,
solves and orthonormalisation. Run: ``.venv/bin/python bench/lfd_primal_basis_trial.py --case T2 --lin DIR``
(``--lin`` as in ``bench/lfd_sweep_bench.py``; about 4 minutes on the 2-core machine). At the end it prints the
primal residuals ``|b + A W y| / |b|`` (what a residual-norm estimate would have to resolve).
"""

import argparse
import math
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout

import numpy as np  # noqa: E402
import scipy.sparse as sp  # noqa: E402
import scipy.sparse.linalg as spla  # noqa: E402

import sysid  # noqa: E402
from bench.lfd_sweep_bench import linear_system  # noqa: E402
from cfd.gust import face_gust_harmonic  # noqa: E402
from cfd.linear import check_outputs  # noqa: E402
from cfd.ordering import nested_dissection, unknown_permutation  # noqa: E402
from cfd.sweep.orthonormal import nested_extension  # noqa: E402
from cfd.sweep import SweepBasis, fast_sweep  # noqa: E402

TOL = 1e-8
NODES, WEIGHTS = np.polynomial.legendre.leggauss(32)


def edge_moments(x1, x2, sigma, n):
    """``avg over each edge of (-i x)^k / k! exp(-i sigma x)`` for k < n: list of arrays of the edges' shape."""
    xs = (0.5 * (x1 + x2))[..., None] + (0.5 * (x2 - x1))[..., None] * NODES
    e = np.exp(-1j * sigma * xs)
    return [np.sum(0.5 * WEIGHTS * ((-1j * xs) ** k / math.factorial(k)) * e, axis=-1) for k in range(n)]


def forcing_moments(lin, sigma, n):
    """Taylor coefficients ``b_k`` (k < n) of the SVM gust forcing ``b(omega)`` at ``sigma``, each (4N,)."""
    x = lin.grid.x
    gi = edge_moments(x[:, :-1], x[:, 1:], sigma, n)
    gj = edge_moments(x[:-1, :], x[1:, :], sigma, n)
    return [lin.forcing(a, b, "svm") for a, b in zip(gi, gj)]


def shift_moments(lin, perm, sigma, n):
    """The ``n`` primal Taylor moments at ``sigma``, shape (4N, n); seconds in factorisation and solves."""
    inv = np.argsort(perm)
    t0 = time.perf_counter()
    A = (lin.J + sp.diags(1j * lin.to_solver_frequency(sigma) * lin.V)).tocsr()[perm][:, perm].tocsc()
    lu = spla.splu(A, permc_spec="NATURAL", diag_pivot_thresh=0.0, options=dict(SymmetricMode=True))
    t_lu = time.perf_counter() - t0
    t0 = time.perf_counter()
    dV = 1j * lin.to_solver_frequency(1.0) * lin.V
    xs, prev = [], None
    for bk in forcing_moments(lin, sigma, n):
        rhs = (-bk - (0.0 if prev is None else dV * prev))[perm]
        y = lu.solve(rhs)
        y = y + lu.solve(rhs - A @ y)
        prev = y[inv]
        xs.append(prev)
    return np.array(xs).T, t_lu, time.perf_counter() - t0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--case", default="T2", choices=["T2", "T5"])
    ap.add_argument("--lin", default=None, help="directory of stored LinearSystem pickles")
    ap.add_argument("--n-moments", type=int, default=16, help="Taylor moments per shift (default 16)")
    ap.add_argument("--extra", type=int, default=3, help="most shifts added beyond the dual's (default 3)")
    ap.add_argument("--greedy", action="store_true",
                    help="choose the shifts from scratch instead (omega = 0, then the worst frequency each time)")
    args = ap.parse_args()
    lin = linear_system(args.case, args.lin)
    omega_d, w = sysid.mckelvey_grid(256, 70 / (2 * np.pi))
    t0 = time.perf_counter()
    dual = SweepBasis(lin)
    ref = np.asarray(fast_sweep(lin, (omega_d, w), basis=dual).H)[:, 0, :]
    print(f"{args.case}: dual reference sweep {time.perf_counter() - t0:.1f} s, {len(dual.shifts)} shifts, "
          f"m = {dual.size}", flush=True)
    fin = np.isfinite(w)
    wf, ref = w[fin], ref[:, fin]
    scale = np.maximum(np.abs(ref), 1e-3 * np.abs(ref).max(axis=1, keepdims=True))
    _, rows = check_outputs(("Cl", "Cm"))
    C = lin.C[rows]
    perm = unknown_permutation(nested_dissection(lin.grid))
    x = lin.grid.x
    g_check = np.abs(edge_moments(x[:, :-1], x[:, 1:], 3.0, 1)[0] - face_gust_harmonic(lin.grid, 3.0, 0.0)[0]).max()
    print(f"quadrature check (k = 0, omega = 3): {g_check:.1e}")
    B = np.array([lin.forcing(*face_gust_harmonic(lin.grid, float(om), 0.0), "svm") for om in wf])  # (K, 4N)
    solver_w = np.array([lin.to_solver_frequency(float(om)) for om in wf])
    W, last = None, np.zeros(0, bool)
    start = [0.0] if args.greedy else list(dual.shifts)
    todo, used, added = list(start), list(start), []
    t_lu = t_solve = t_orth = 0.0
    t0 = time.perf_counter()
    while todo:
        sigma = todo.pop(0)
        added.append(sigma)
        X, a, b = shift_moments(lin, perm, sigma, args.n_moments)
        t_lu, t_solve = t_lu + a, t_solve + b
        t = time.perf_counter()
        Q, kept = nested_extension(np.linalg.qr(X / np.linalg.norm(X, axis=0))[0], [1] * X.shape[1], W)
        W = Q if W is None else np.hstack([W, Q])
        last = np.concatenate([last, np.arange(Q.shape[1]) == Q.shape[1] - 1])  # each shift's last moment
        t_orth += time.perf_counter() - t
        Jr = W.conj().T @ lin.apply_jacobian(W, transpose=False)
        Vr = W.conj().T @ (lin.V[:, None] * W)
        Wb = W.conj().T @ B.T
        Y = np.stack([np.linalg.solve(Jr + 1j * sw * Vr, -Wb[:, k]) for k, sw in enumerate(solver_w)], 1)
        H = C @ (W @ Y)
        err = np.abs(H - ref) / scale
        worst = err.max(axis=0)
        # the nested estimate without residuals: the model without each shift's last moment, est = 10 |y - y_|
        keep = ~last
        Jc, Vc = Jr[np.ix_(keep, keep)], Vr[np.ix_(keep, keep)]
        Yc = np.stack([np.linalg.solve(Jc + 1j * sw * Vc, -Wb[keep, k]) for k, sw in enumerate(solver_w)], 1)
        est = 10.0 * np.abs(H - C @ (W[:, keep] @ Yc)) / scale
        print(f"  shift omega {sigma:.4g}: m = {W.shape[1]}, max rel err Cl {err[0].max():.1e} "
              f"Cm {err[1].max():.1e}, {int(np.sum(worst > TOL))} frequencies above {TOL:g} "
              f"[{time.perf_counter() - t0:.0f} s: LU {t_lu:.0f}, solves {t_solve:.0f}, "
              f"orthonormalisation {t_orth:.0f}]", flush=True)
        at_shift = np.isin(wf, added)
        big = ~at_shift[None, :] & (err > 1e-12)
        eff = est[big] / err[big]
        print(f"    nested estimate 10 |y - y_|: {int(np.sum((est.max(axis=0) > TOL) & ~at_shift))} frequencies above "
              f"{TOL:g}; estimate / error min {eff.min():.2g}, median {np.median(eff):.2g}" if eff.size else
              "    nested estimate: no errors above 1e-12", flush=True)
        if at_shift.any():
            print(f"    at the shift frequencies: worst {worst[at_shift].max():.1e} (their solutions are in the "
                  "basis; the reduced solve's own error - the dual sweep returns the shift's direct output there)")
        rest = np.where(at_shift, 0.0, worst)
        if not todo and rest.max() > TOL and len(used) < len(start) + args.extra:
            k = int(np.argmax(rest))
            print(f"    worst elsewhere: omega {wf[k]:.4g}: {rest[k]:.1e} -> new shift")
            todo.append(float(wf[k]))
            used.append(todo[-1])
    # the primal residuals at the end: what an error estimate built on their norms would have to resolve
    X = W @ Y
    r = np.array([np.linalg.norm(B[k] + lin.apply_jacobian(X[:, k], transpose=False) + 1j * sw * lin.V * X[:, k])
                  / np.linalg.norm(B[k]) for k, sw in enumerate(solver_w)])
    ok = ~np.isin(wf, added)
    q = np.quantile(r[ok], [0.0, 0.5, 1.0])
    print(f"relative primal residual |b + A W y| / |b| away from the shifts: min {q[0]:.1e}, median {q[1]:.1e}, "
          f"max {q[2]:.1e}; output error there: max {err[:, ok].max():.1e}")
    for lo, hi in ((0.0, 1e-9), (1e-9, 1e-8), (1e-8, np.inf)):
        sel = ok & (err.max(axis=0) >= lo) & (err.max(axis=0) < hi)
        if sel.any():
            print(f"  output error in [{lo:g}, {hi:g}): {int(sel.sum())} frequencies, relative residual "
                  f"{r[sel].min():.1e} - {r[sel].max():.1e}")

if __name__ == "__main__":
    main()
