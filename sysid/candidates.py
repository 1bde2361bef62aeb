"""The candidates of the relocation (:mod:`sysid.relocation`): their errors and score, the DC / feedthrough
equalities and the gap bounds they must meet when evaluated, the bounded minimax residues that bring a
candidate within the gap bounds, and the pick among the admissible ones."""

from __future__ import annotations

import numpy as np

from .errors import SolverError
from .residues import minimax_cd
from .state_space import evaluate_ss

__all__ = ["EQ_TOL", "channel_errors", "candidate_score", "bound_candidate_gaps", "pick_candidates", "gap_excess",
           "equality_residual"]

#: Accepted violation of the DC / feedthrough equalities, relative to each output's peak.
EQ_TOL = 1e-11


def channel_errors(A, B, C, D, z, G):
    """Max error per output over inputs and samples, relative to the output's data peak: shape (p,)."""
    Gm = evaluate_ss(A, B, C, D, z)
    peak = np.maximum(np.abs(G).max(axis=(1, 2)), np.finfo(float).tiny)
    return np.abs(Gm - G).max(axis=(1, 2)) / peak


def candidate_score(err):
    """Sort key of a candidate: the sum of the per-output peak-normalised max errors, then the largest."""
    return (float(np.sum(err)), float(np.max(err)))


def bound_candidate_gaps(c, z, G, dc, ft, weights, zb, ub, peak, rounds: int = 4, within=None):
    """Minimax residues of candidate ``c`` under the :func:`gap_bounds` (cutting planes: the bounds enter the
    cone programme where the gain is within 10 % of them, then where a solution came within 5 % of them or
    broke them); updates ``c`` when a solution meets every bound."""
    def ratio(C, D):
        with np.errstate(all="ignore"):
            return (np.abs(evaluate_ss(c["A"], c["B"], C, D, zb)) / ub).max(axis=(0, 1))

    active = ratio(c["C"], c["D"]) > 0.9
    for _ in range(rounds):
        try:
            C, D, _ = minimax_cd(c["A"], c["B"], z, G, dc_gain=dc, feedthrough=ft, weights=weights,
                                 bound=(zb[active], ub[:, :, active]), within=within)
        except SolverError:  # infeasible or numerically failed bounds: the candidate stays as it is (inadmissible)
            return
        if not np.all(np.isfinite(C)):
            return
        r = ratio(C, D)
        if r.max() <= 1.0 + 1e-6:
            trial = dict(c, C=C, D=D)
            c.update(C=C, D=D, err=channel_errors(c["A"], c["B"], C, D, z, G), residues="bounded minimax",
                     gap=float(r.max()), eq=equality_residual(trial, dc, ft, peak))
            return
        active |= r > 0.95


def pick_candidates(cands, trust=None):
    """Candidates, best first. Admissible: the equalities hold to 1e-11 of the peak when the model is evaluated
    (nearly coincident poles with huge cancelling residues can lose them to round-off even though the fit
    imposed them exactly) and the gain stays within the :func:`gap_bounds` between the samples - unless, with
    ``trust``, the candidate's worst peak-normalised error is ``trust`` times smaller than that of every
    candidate within the bounds: then the samples themselves determine the resonance (noise-free data of a
    lightly damped system: errors 1e-12 against 0.4). Among the admissible ones, the one whose worst output
    is closest to the best any of them reached on that output."""
    for c in cands:
        c["admissible"] = c["eq"] <= EQ_TOL and c["gap"] <= 1.0 + 1e-6
    if trust is not None:
        bounded = [float(np.max(c["err"])) for c in cands if c["admissible"]]
        limit = min(bounded, default=np.inf) / trust
        for c in cands:
            c["admissible"] |= c["eq"] <= EQ_TOL and float(np.max(c["err"])) <= limit
    ok = [c for c in cands if c["admissible"]]
    pool = ok if ok else sorted(cands, key=lambda c: (c["eq"] > EQ_TOL, c["gap"], c["eq"]))[:1]
    best_i = np.maximum(np.min([c["err"] for c in pool], axis=0), np.finfo(float).tiny)
    pool.sort(key=lambda c: (float(np.max(c["err"] / best_i)),) + candidate_score(c["err"]))
    return pool + [c for c in cands if not any(c is q for q in pool)]


def gap_excess(c, zb, ub) -> float:
    """Largest ratio of a candidate's gain to the :func:`gap_bounds` between the samples (<= 1: within)."""
    with np.errstate(all="ignore"):
        Gb = evaluate_ss(c["A"], c["B"], c["C"], c["D"], zb)
    r = float(np.max(np.abs(Gb) / ub)) if zb.size else 0.0
    return r if np.isfinite(r) else np.inf


def equality_residual(c, dc, ft, peak):
    """Largest violation of the DC / feedthrough equalities of a candidate, relative to each output's peak."""
    pts, vals = [], []
    if dc is not None:
        pts.append(1.0 + 0j)
        vals.append(dc)
    if ft is not None:
        pts.append(-1.0 + 0j)
        vals.append(ft)
    if not pts:
        return 0.0
    with np.errstate(all="ignore"):
        Gm = evaluate_ss(c["A"], c["B"], c["C"], c["D"], np.array(pts))
    r = max(float(np.max(np.abs(Gm[:, :, k] - v) / peak[:, None])) for k, v in enumerate(vals))
    return r if np.isfinite(r) else np.inf
