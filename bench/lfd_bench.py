"""LFD benchmark: the direct (reference) path on case T2 (NACA0010, M0.735) on the paper's 181 x 60 grid.

Prints, measured side by side in one run: the steady solve (for context), ``linearise`` (Jacobian, face
operators, load operator), one real factorisation of ``J`` and one complex factorisation of
``i omega mach V + J`` (nested dissection without pivoting), ``cfd.linear.factorise`` of the same matrix (its real
2n form ``[[Ar, -Ai], [Ai, Ar]]``, checked: what the direct path uses), COLAMD with pivoting, their fill
``nnz(L + U) / nnz(A)``, and the full cost of one LFD frequency (forcing, checked factorisation, solve) as a
multiple of one ``factorise`` call and of one complex factorisation.

Run: ``.venv/bin/python bench/lfd_bench.py`` (``--quick`` skips COLAMD).
"""

import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

import cfd
from cfd.lfd import lfd_response
from cfd.linear import factorise
from cfd.ordering import nested_dissection, unknown_permutation
from cfd.superlu import splu_nested


def timed(f):
    t = time.perf_counter()
    out = f()
    return time.perf_counter() - t, out


def main(quick=False):
    rows = []
    t_grid, grid = timed(lambda: cfd.c_grid(cfd.naca("0010")))
    t_st, sol = timed(lambda: cfd.solve_steady(grid, 0.735, 0.0))
    rows.append(("steady solve (context)", f"{t_st:.1f} s", f"{grid.n_cells} cells, {4 * grid.n_cells} unknowns"))
    t_lin, lin = timed(lambda: cfd.linearise(sol))
    rows.append(("linearise (J, Bi, Bj, C)", f"{t_lin:.2f} s", f"nnz(J) = {lin.J.nnz}"))
    perm = unknown_permutation(nested_dissection(grid))
    omega = 1.0
    A = (lin.J + sp.diags(1j * lin.to_solver_frequency(omega) * lin.V)).tocsr()

    def nd(M):
        return splu_nested(M[perm][:, perm])

    t_real, lu_r = timed(lambda: nd(lin.J.tocsr()))
    rows.append(("factorise J (real, ND)", f"{t_real:.2f} s", f"fill {(lu_r.L.nnz + lu_r.U.nnz) / lin.J.nnz:.1f}"))
    t_cplx, lu_c = timed(lambda: nd(A))
    rows.append(("factorise i w V + J (complex, ND)", f"{t_cplx:.2f} s", f"fill {(lu_c.L.nnz + lu_c.U.nnz) / A.nnz:.1f}"))
    b = np.ones(A.shape[0], complex)
    t_bs, _ = timed(lambda: lu_c.solve(b[perm]))
    rows.append(("one complex back-substitution", f"{t_bs * 1e3:.0f} ms", f"{t_bs / t_cplx:.3f} factorisations"))
    t_fac, (solve, fill) = timed(lambda: factorise(A, perm))
    rows.append(("cfd.linear.factorise (real 2n form, ND + check)", f"{t_fac:.2f} s", f"fill {fill:.1f} (of the 2n form)"))
    if not quick:
        t_col, lu = timed(lambda: spla.splu(A.tocsc(), permc_spec="COLAMD"))
        rows.append(("factorise complex, COLAMD + pivoting", f"{t_col:.2f} s",
                     f"fill {(lu.L.nnz + lu.U.nnz) / A.nnz:.1f}"))
    w = np.array([0.5, 1.0, 2.0])
    t_f, _ = timed(lambda: lfd_response(lin, w, gust="svm"))
    per = t_f / w.size
    rows.append(("lfd_response per frequency (svm)", f"{per:.2f} s",
                 f"{per / t_fac:.2f} factorise calls, {per / t_cplx:.2f} complex factorisations"))
    width = max(len(r[0]) for r in rows)
    print("LFD direct path, T2 (NACA0010, M0.735, alpha 0), 181 x 60 grid")
    for name, val, note in rows:
        print(f"  {name:<{width}}  {val:>9}  {note}")


if __name__ == "__main__":
    main(quick="--quick" in sys.argv)
