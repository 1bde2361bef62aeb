"""Where a nonlinear march stalls: the cells that hold the residual of a step that Newton cannot converge.

Run: ``.venv/bin/python bench/nonlinear_stall.py [--case T4] [--gust G2] [--angle 0.5] [--t-end 12]`` after
``lfdrom run studies/linearity.toml`` (it takes the case's steady flow from that study's store). It marches
``cfd.unsteady_response`` with the study's ``dt`` and ``x0`` until a step fails, then repeats the failed step's
chord-Newton iterations from the predictor and prints, per iteration, ``|F|``, the cell that holds most of it and the
share of ``|F|^2`` in the ten largest cells (indices ``(i, j)`` of the ``(ni - 1, nj - 1)`` cell array: ``i = 0`` and
``i = ni - 2`` are the downstream boundary cells of the C-grid's lower and upper wake, ``j = nj - 2`` the far-field
row); it prints "no step failed" when the march runs to ``--t-end``.

It found why T4's marches stopped in the linearity study: with a hard inflow/outflow switch in the Riemann far
field, the failed step (T4, G2/G3, 0.5 deg, step 324) stalled at |F| = 2.075e-6 with all of it in the corner cells
where the downstream boundary meets the far-field line y = -R, where the normal velocity crosses zero. The switch
is now a smooth blend (``cfd.boundary.outflow_weight``, docs/equations.md) and the same march runs to its end.
"""

from __future__ import annotations

import argparse
from dataclasses import replace

import numpy as np

import cfd
import cfd.unsteady as unsteady
from studies.config.cases import to_gust
from studies.config import load_study
from studies.sections.gust_rom.pieces import open_store
from studies.sections.gust_rom.tasks import load_steady_solution


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--study", default="studies/linearity.toml")
    p.add_argument("--case", default="T4")
    p.add_argument("--gust", default="G2")
    p.add_argument("--angle", type=float, default=0.5)
    p.add_argument("--t-end", type=float, default=12.0)
    args = p.parse_args(argv)

    config = load_study(args.study)
    case = config.case(args.case).case
    sol = load_steady_solution(open_store(config), case)
    gust_case = next(g for g in config.gusts if g.name.casefold() == args.gust.casefold())
    gust = replace(to_gust(gust_case, x0=config.simulation.x0), angle_deg=args.angle)
    shape = sol.q.shape
    original = unsteady._March.step

    def step(self, k, s, q, q_prev):
        try:
            return original(self, k, s, q, q_prev)
        except unsteady.UnsteadyStepError:
            w, dgdx = self._forcing(s)
            rhs = self.V * (4.0 * q - q_prev) / (2.0 * self.h)
            x = 2.0 * q - q_prev
            print(f"step {k} (s = {s:g}) failed; its chord-Newton iterations from the predictor:")
            for it in range(4):
                F = 1.5 * self.V * x / self.h - rhs + self._residual(x, w, dgdx)
                per_cell = np.linalg.norm(F.reshape(shape), axis=2)
                top = np.argsort(per_cell.ravel())[::-1][:10]
                share = float(np.sum(per_cell.ravel()[top] ** 2) / np.sum(per_cell ** 2))
                cells = [tuple(int(v) for v in np.unravel_index(t, per_cell.shape)) for t in top[:4]]
                print(f"  iteration {it}: |F| = {np.linalg.norm(F):.6e}; largest cells {cells} of {per_cell.shape}; "
                      f"share of |F|^2 in the ten largest: {share:.8f}")
                x = x + self._correction(x, F, None)
            raise

    unsteady._March.step = step
    try:
        cfd.unsteady_response(sol, gust, config.simulation.dt, args.t_end, method=config.cfd.gust_method)
        print("no step failed")
    except unsteady.UnsteadyStepError as e:
        print(f"{type(e).__name__}: {str(e)[:160]}")
    finally:
        unsteady._March.step = original
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
