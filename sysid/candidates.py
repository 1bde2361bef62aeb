"""The candidates of the relocation (:mod:`sysid.relocation`): their errors and score, the DC / feedthrough
equalities and the gap bounds they must meet when evaluated, the bounded minimax residues that bring a
candidate within the gap bounds, and the pick among the admissible ones."""

from __future__ import annotations

import numpy as np

from .errors import SolverError
from .poles import balanced_coordinates
from .residues import bounds_at, minimax_cd, resonance_points
from .state_space import eigen_parts, evaluate_ss

__all__ = ["EQ_TOL", "channel_errors", "rms_errors", "candidate_score", "bound_candidate_gaps", "pick_candidates",
           "gap_excess", "equality_residual", "equality_gaps", "polish_equalities", "POLISH_FROM", "candidate_eig",
           "ROUNDOFF_TOL", "equality_roundoff", "check_equalities", "constrained_responses", "settle_equalities",
           "NOISE_TRUST", "NOISE_TRUST_GAP", "NOISE_RMS_TIE"]

#: Accepted violation of the DC / feedthrough equalities by the model (:func:`equality_residual`), relative to
#: each output's peak.
EQ_TOL = 1e-11
#: Largest round-off that a double-precision evaluation of an admissible model's gain at ``z = +-1`` may add
#: (:func:`equality_roundoff`, relative to the peak): the DC-exactness asked of every ROM. Huge cancelling
#: residues of nearly coincident poles otherwise make the evaluated DC gain wander (|C| ~ 1e10 seen on T4 at
#: N_r = 25 cost 8 digits); the T5 N_r = 55 fits reach 1.2e-11.
ROUNDOFF_TOL = 1e-10
#: Candidates whose equality residual exceeds this (relative to the peak) get :func:`polish_equalities`.
POLISH_FROM = 1e-13
#: With noisy data, a candidate that breaks the gap bounds by at most :data:`NOISE_TRUST_GAP` times is still taken
#: when its errors are at the noise level (``c["at_noise"]``, :func:`sysid.relocation.at_noise_level`) and every
#: candidate within the bounds is more than ``NOISE_TRUST`` times less accurate (:func:`pick_candidates`): the
#: samples then show a resonance narrower than their spacing (its peak between two samples is above the bound
#: built from them), which a model within the bounds can only miss. A model consistent with the samples is at their
#: noise level too, within the scatter of the largest of ``K`` noise samples (a factor of about 1.5 between
#: realisations). Larger excesses are not taken on noisy data: a fit at the noise level with more states than the
#: data need can resonate between the samples (3.7 times the bound, 27 % off the true response between them, on a
#: 12-state system with 1 % noise at order 18; ``bench/sysid_truth_between_bench.py --seeds``, seed 15).
NOISE_TRUST = 3.0
NOISE_TRUST_GAP = 2.0
#: Candidates at the noise level whose rms errors are within this factor of the best one's explain the samples
#: equally well (the rms of K complex noise samples scatters by about 1 / sqrt(2 K) relative: 6 % for K = 65), and
#: :func:`pick_candidates` orders them by their estimate between the samples (``c["between"]``).
NOISE_RMS_TIE = 1.1


def candidate_eig(c):
    """The :func:`sysid.state_space.eigen_parts` of a candidate's ``A`` (False: no modal form), computed once
    and kept in ``c["eig"]`` (its ``A`` never changes)."""
    if "eig" not in c:
        c["eig"] = eigen_parts(c["A"]) or False
    return c["eig"]


def channel_errors(A, B, C, D, z, G, eig=None):
    """Max error per output over inputs and samples, relative to the output's data peak: shape (p,).
    ``eig``: :func:`sysid.state_space.eigen_parts` of ``A`` precomputed (optional)."""
    err, peak = _errors_and_peaks(A, B, C, D, z, G, eig)
    return err.max(axis=(1, 2)) / peak


def rms_errors(A, B, C, D, z, G, eig=None):
    """Root-mean-square error per output over inputs and samples, relative to the output's data peak: shape (p,)
    (as :func:`channel_errors`, with the mean square instead of the max)."""
    err, peak = _errors_and_peaks(A, B, C, D, z, G, eig)
    return np.sqrt(np.mean(err ** 2, axis=(1, 2))) / peak


def _errors_and_peaks(A, B, C, D, z, G, eig):
    """``|G_model(z_k) - G_k|`` (p, m, K) and each output's data peak (p,) (at least the smallest float)."""
    err = np.abs(evaluate_ss(A, B, C, D, z, eig) - G)
    return err, np.maximum(np.abs(G).max(axis=(1, 2)), np.finfo(float).tiny)


def candidate_score(err):
    """Sort key of a candidate: the sum of the per-output peak-normalised max errors, then the largest."""
    return (float(np.sum(err)), float(np.max(err)))


def bound_candidate_gaps(c, z, G, dc, ft, weights, zb, ub, peak, rounds: int = 4, within=None):
    """Minimax residues of candidate ``c`` under the :func:`gap_bounds` (cutting planes: the bounds enter the
    cone programme where the gain is within 10 % of them, then where a solution came within 5 % of them or
    broke them); updates ``c`` when a solution meets every bound (checked at the candidate's resonances too)."""
    eig = candidate_eig(c)
    zb_all, ub_all = zb, ub
    zb, ub = with_resonances(c, zb, ub)

    def ratio(C, D):
        with np.errstate(all="ignore"):
            return (np.abs(evaluate_ss(c["A"], c["B"], C, D, zb, eig)) / ub).max(axis=(0, 1))

    active = ratio(c["C"], c["D"]) > 0.9
    for _ in range(rounds):
        try:
            C, D, _ = minimax_cd(c["A"], c["B"], z, G, dc_gain=dc, feedthrough=ft, weights=weights,
                                 bound=(zb[active], ub[:, :, active]), within=within, eig=eig)
        except SolverError:  # infeasible or numerically failed bounds: the candidate stays as it is (inadmissible)
            return
        if not np.all(np.isfinite(C)):
            return
        r = ratio(C, D)
        if r.max() <= 1.0 + 1e-6:
            c.update(C=C, D=D, err=channel_errors(c["A"], c["B"], C, D, z, G, eig), residues="bounded minimax",
                     gap=float(r.max()))
            settle_equalities(c, z, G, dc, ft, peak, zb_all, ub_all)
            return
        active |= r > 0.95


def pick_candidates(cands, trust=None):
    """Candidates, best first. Admissible: the model meets the equalities to ``EQ_TOL`` of the peak
    (:func:`equality_residual`, after :func:`polish_equalities`), a double-precision evaluation of its gain at
    ``z = +-1`` cannot add more than ``ROUNDOFF_TOL`` (nearly coincident poles with huge cancelling residues
    lose the equalities to round-off), and the gain stays within the :func:`gap_bounds` between the samples - unless, with
    ``trust``, the candidate's worst peak-normalised error is ``trust`` times smaller than that of every
    candidate within the bounds, or its errors are at the data's noise level (``c["at_noise"]``), its gain at most
    :data:`NOISE_TRUST_GAP` times the bounds and its error :data:`NOISE_TRUST` times smaller than theirs: then the
    samples themselves determine the resonance (noise-free data of a lightly damped system: errors 1e-12 against
    0.4; noisy data of a resonance narrower than the spacing: errors at the noise level against 8 times it). An
    admissible candidate at the noise level estimated far off between the samples gives way to those without that
    fault that come close (:func:`_prefer_near`), and candidates whose rms errors tie are ordered by their estimate
    between the samples (:func:`_tied_by_between`).
    Among the admissible ones, the one whose worst output is closest to the best any of them reached on that
    output, by the max errors ``c["err"]``, or by the rms errors ``c["rms"]`` when every one of them is at the
    noise level (``c["at_noise"]``: the least-squares criterion is the likelihood of Gaussian noise, where the
    largest error is that of one noise sample)."""
    _admit(cands, trust)
    _prefer_near(cands)
    ok = [c for c in cands if c["admissible"]]
    pool = ok if ok else sorted(cands, key=lambda c: (not _equalities_hold(c), c["gap"], c["eq"]))[:1]
    # errors at the noise level (every candidate's): by their rms, the likelihood of Gaussian noise (sysid.relocation)
    key = "rms" if all(c.get("at_noise", False) and "rms" in c for c in pool) else "err"
    best_i = np.maximum(np.min([c[key] for c in pool], axis=0), np.finfo(float).tiny)
    pool.sort(key=lambda c: (float(np.max(c[key] / best_i)),) + candidate_score(c[key]))
    if key == "rms":
        pool = _tied_by_between(pool, best_i)
    return pool + [c for c in cands if not any(c is q for q in pool)]


def _prefer_near(cands):
    """Where admissible candidates are estimated far off between the samples (``c["far_between"]``,
    :func:`sysid.relocation._fit_simo`), admit instead the candidates at the noise level without that fault whose
    equalities hold, whose error is within :data:`NOISE_TRUST` of the best far one's and whose gain is admissible
    or within :data:`NOISE_TRUST_GAP` of the gap bounds (the margin the noise-level rule allows); the far ones
    stay admissible only where there is none."""
    far = [c for c in cands if c["admissible"] and c.get("far_between", False)]
    if not far:
        return
    e_far = min(float(np.max(c["err"])) for c in far)
    near = [c for c in cands if c.get("at_noise", False) and "between" in c and not c["far_between"]
            and _equalities_hold(c) and (c["admissible"] or c["gap"] <= NOISE_TRUST_GAP)
            and float(np.max(c["err"])) < NOISE_TRUST * e_far]
    if near:
        for c in far:
            c["admissible"] = False
        for c in near:
            c["admissible"] = True


def _tied_by_between(pool, best_i):
    """``pool`` (sorted by rms error ratio to ``best_i``) with the candidates whose rms errors are within
    :data:`NOISE_RMS_TIE` of the leader's - they explain the noisy samples equally well - ordered by their
    estimate between the samples (``c["between"]``; NaN last), when every one has it."""
    if not all("between" in c for c in pool):
        return pool
    lead = float(np.max(pool[0]["rms"] / best_i))
    tied = [c for c in pool if float(np.max(c["rms"] / best_i)) <= NOISE_RMS_TIE * lead]
    tied.sort(key=lambda c: float(np.nan_to_num(np.max(c["between"]), nan=np.inf)))
    return tied + pool[len(tied):]


def _admit(cands, trust):
    """Set ``c["admissible"]`` by the equalities, the gap bounds and, with ``trust``, the trust rules
    (:func:`pick_candidates`)."""
    for c in cands:
        c["admissible"] = _equalities_hold(c) and c["gap"] <= 1.0 + 1e-6
    if trust is None:
        return
    bounded = [float(np.max(c["err"])) for c in cands if c["admissible"]]
    # no candidate within the bounds: nothing to be 100 times better than, so nothing is trusted (the vacuous
    # rule admitted a fit 1.4e5 times over the bounds on T4 at N_r = 55)
    limit = min(bounded) / trust if bounded else -np.inf
    for c in cands:
        e = float(np.max(c["err"]))
        explained = (c.get("at_noise", False) and c["gap"] <= NOISE_TRUST_GAP and bool(bounded)
                     and min(bounded) > NOISE_TRUST * e)
        c["admissible"] |= _equalities_hold(c) and (e <= limit or explained)


def _equalities_hold(c) -> bool:
    """The equality part of admissibility (:func:`pick_candidates`)."""
    return c["eq"] <= EQ_TOL and c.get("eq_roundoff", 0.0) <= ROUNDOFF_TOL


def with_resonances(c, zb, ub):
    """The :func:`gap_bounds` points ``zb`` and bounds ``ub`` with the peaks of the candidate's own resonances
    added (:func:`sysid.residues.resonance_points`): a resonance narrower than the fixed points' spacing would
    pass between them."""
    if not zb.size:
        return zb, ub
    eig = candidate_eig(c)
    lam = eig[0] if eig else np.linalg.eigvals(c["A"])
    zr = resonance_points(lam)
    if not zr.size:
        return zb, ub
    return np.concatenate([zb, zr]), np.concatenate([ub, bounds_at(zr, zb, ub)], axis=2)


def gap_excess(c, zb, ub) -> float:
    """Largest ratio of a candidate's gain to the :func:`gap_bounds` between the samples (<= 1: within), at the
    bounds' points and at the peaks of the candidate's resonances."""
    zb, ub = with_resonances(c, zb, ub)
    with np.errstate(all="ignore"):
        Gb = evaluate_ss(c["A"], c["B"], c["C"], c["D"], zb, candidate_eig(c))
    r = float(np.max(np.abs(Gb) / ub)) if zb.size else 0.0
    return r if np.isfinite(r) else np.inf


def _equality_points(dc, ft):
    """The constrained points of the unit circle and their targets: ``(pts (k,), vals (k, p, m))``."""
    pairs = [(1.0, dc), (-1.0, ft)]
    pts = np.array([zz for zz, v in pairs if v is not None])
    vals = np.array([np.asarray(v, dtype=float) for _, v in pairs if v is not None])
    return pts, vals


def constrained_responses(A, B, pts):
    """``X_l = (pts_l I - A)^-1 B`` at real points, refined once against a residual in extended precision.

    Parameters
    ----------
    A : ndarray, shape (n, n); B : ndarray, shape (n, m)
    pts : ndarray, shape (k,), real
        Points of the real axis (``+1``: DC, ``-1``: ``omega = inf``), not eigenvalues of ``A``.

    Returns
    -------
    ndarray, shape (k, n, m), ``np.longdouble``
        Accurate to about ``cond(pts I - A)`` times the extended precision's epsilon (where ``np.longdouble``
        is the double, as on Windows, to that of a double).
    """
    L = np.longdouble
    M = pts[:, None, None] * np.eye(A.shape[0]) - A  # (k, n, n)
    X = np.linalg.solve(M, np.broadcast_to(B, (pts.size,) + B.shape))
    res = B.astype(L)[None] - M.astype(L) @ X.astype(L)
    return X.astype(L) + np.linalg.solve(M, res.astype(float)).astype(L)


def equality_gaps(A, B, C, D, dc, ft, X=None):
    """The model's gain minus the DC / feedthrough targets, without the round-off of a double evaluation.

    The gain ``C X_l + D`` at ``z = +-1`` is formed in extended precision from :func:`constrained_responses`:
    with nearly coincident poles the terms ``C_ij X_jl`` cancel (their sum is 1e5 times the peak on T5 at
    ``N_r = 55``), and a double-precision evaluation is then uncertain by ``eps sum_j |C_ij X_jl|`` (1e-11 of
    the peak there) whatever the model; this function sees the model's own residual.

    Parameters
    ----------
    A : ndarray, shape (n, n); B : ndarray, shape (n, m); C : ndarray, shape (p, n); D : ndarray, shape (p, m)
    dc, ft : ndarray, shape (p, m), or None
        Targets at ``z = 1`` and ``z = -1`` (None: not constrained).
    X : ndarray, shape (k, n, m), optional
        :func:`constrained_responses` at the constrained points, precomputed.

    Returns
    -------
    R : ndarray, shape (k, p, m)
        One slice per constrained point (DC first), ``k`` = 0, 1 or 2.
    bound : ndarray, shape (k, p, m)
        ``eps sum_j |C_ij X_jl|``: the round-off a double-precision evaluation of the gain may add.
    """
    pts, vals = _equality_points(dc, ft)
    if not pts.size:
        return np.zeros((0,) + np.shape(D)), np.zeros((0,) + np.shape(D))
    if X is None:
        try:
            X = constrained_responses(A, B, pts)
        except np.linalg.LinAlgError:  # a pole on a constrained point
            inf = np.full((pts.size,) + np.shape(D), np.inf)
            return inf, inf
    L = np.longdouble
    with np.errstate(all="ignore"):
        R = (C.astype(L)[None] @ X + D.astype(L)[None] - vals.astype(L)).astype(float)
        bound = np.finfo(float).eps * (np.abs(C)[None] @ np.abs(X.astype(float)))
    return R, bound


def equality_residual(c, dc, ft, peak):
    """Largest violation of the DC / feedthrough equalities of a candidate, relative to each output's peak
    (:func:`equality_gaps`: the model's residual, without the round-off of its evaluation)."""
    return _relative_gap(equality_gaps(c["A"], c["B"], c["C"], c["D"], dc, ft)[0], peak)


def equality_roundoff(c, dc, ft, peak):
    """Largest round-off a double-precision evaluation of a candidate's gain at the constrained points may add,
    relative to each output's peak (:func:`equality_gaps`' ``bound``)."""
    return _relative_gap(equality_gaps(c["A"], c["B"], c["C"], c["D"], dc, ft)[1], peak)


def check_equalities(c, dc, ft, peak):
    """Set ``c["eq"]`` (:func:`equality_residual`) and ``c["eq_roundoff"]`` (:func:`equality_roundoff`)."""
    R, bound = equality_gaps(c["A"], c["B"], c["C"], c["D"], dc, ft)
    c["eq"], c["eq_roundoff"] = _relative_gap(R, peak), _relative_gap(bound, peak)


def settle_equalities(c, z, G, dc, ft, peak, zb, ub):
    """Check a candidate's equalities and make them hold in double precision where the model allows it.

    Sets ``c["eq"]`` and ``c["eq_roundoff"]`` (:func:`check_equalities`); a residual above ``POLISH_FROM`` gets
    :func:`polish_equalities`; a possible round-off above ``ROUNDOFF_TOL`` (cancelling terms of nearly
    coincident poles) moves the candidate to :func:`sysid.poles.balanced_coordinates`, polished again there,
    and the balanced form is kept when its round-off bound is lower (``A``, ``B``, ``C``, ``err`` and ``gap``
    updated: the same model up to the transformation's round-off). Measured on T5 at ``N_r = 55``: the two
    bounded minimax candidates had bounds of 1.1e-10 and 1.4e-10 in input-normal coordinates (so whether
    they were admissible depended on the machine's round-off), 6e-16 balanced.
    """
    check_equalities(c, dc, ft, peak)
    if c["eq"] > POLISH_FROM:
        polish_equalities(c, z, G, dc, ft, peak, zb, ub)
    if c["eq_roundoff"] <= ROUNDOFF_TOL or not np.all(np.isfinite(c["C"])):
        return
    bal = balanced_coordinates(c["A"], c["B"], c["C"])
    if bal is None:
        return
    A_b, B_b, C_b, T, T_inv = bal
    eig = candidate_eig(c)  # the modal form carried over (C V is invariant): as accurate as it was
    trial = dict(c, A=A_b, B=B_b, C=C_b, eig=(eig[0], T_inv @ eig[1], eig[2] @ T) if eig else False)
    check_equalities(trial, dc, ft, peak)
    if trial["eq"] > POLISH_FROM:
        polish_equalities(trial, z, G, dc, ft, peak)
    if trial["eq_roundoff"] < c["eq_roundoff"] and trial["eq"] <= max(c["eq"], EQ_TOL):
        trial["err"] = channel_errors(trial["A"], trial["B"], trial["C"], trial["D"], z, G, candidate_eig(trial))
        trial["gap"] = gap_excess(trial, zb, ub)
        c.clear()
        c.update(trial)


def _relative_gap(R, peak):
    """``max |R| / peak`` of an (k, p, m) array (0 when nothing is constrained, inf when not finite)."""
    if not R.size:
        return 0.0
    with np.errstate(all="ignore"):
        r = float(np.max(np.abs(R) / peak[None, :, None]))
    return r if np.isfinite(r) else np.inf


def polish_equalities(c, z, G, dc, ft, peak, zb=None, ub=None, steps: int = 3):
    """Minimum-norm corrections of a candidate's ``C`` onto its DC / feedthrough equalities.

    The fits impose the equalities exactly in exact arithmetic, but with nearly coincident poles and large
    cancelling residues the model's gain at ``z = +-1`` differs from the fit's by round-off (1e-11 of the peak
    on T5 at ``N_r = 55``). The responses ``X`` (k, n, m) at the constrained points are solved once
    (:func:`constrained_responses`); each step takes the residual ``R`` (k, p, m) of :func:`equality_gaps` and
    applies the least-squares minimum-norm correction ``dC_i = -pinv(E) r_i`` per output, ``E`` (k m, n) the
    rows ``X[l, :, j]^T``, ``r_i`` (k m,) the residuals of output ``i`` (``D`` is kept). The iterate with the
    smallest residual is kept when it is below the candidate's ``eq``; ``c`` is then updated in place (``C``,
    ``eq``, ``err`` and, with ``zb`` and ``ub``, ``gap``).

    Parameters
    ----------
    c : dict
        Candidate with ``A`` (n, n), ``B`` (n, m), ``C`` (p, n), ``D`` (p, m) and ``eq``.
    z : ndarray, shape (K,), complex; G : ndarray, shape (p, m, K), complex
        The data (``err`` is recomputed on them).
    dc, ft : ndarray, shape (p, m), or None
    peak : ndarray, shape (p,)
        Each output's data peak (the scale of ``eq``).
    zb, ub : ndarray, shapes (J,) and (p, m, J), optional
        The :func:`sysid.residues.gap_bounds`: ``gap`` is recomputed for the polished ``C``.
    steps : int
        Most correction steps; they stop once the residual is below ``POLISH_FROM``.

    Returns
    -------
    bool
        True when ``c`` was updated.
    """
    pts, _ = _equality_points(dc, ft)
    A, B = c["A"], c["B"]
    n, m = B.shape
    if not pts.size or not np.all(np.isfinite(c["C"])):
        return False
    try:
        X = constrained_responses(A, B, pts)
    except np.linalg.LinAlgError:  # a pole on a constrained point: nothing to polish
        return False
    E = np.swapaxes(X.astype(float), 1, 2).reshape(pts.size * m, n)  # rows (point, input)
    pinv = np.linalg.pinv(E)  # (n, k m): minimum-norm solutions, computed once
    best_C, best_eq, C = c["C"], c["eq"], c["C"]
    R = equality_gaps(A, B, C, c["D"], dc, ft, X)[0]  # (k, p, m)
    for _ in range(steps):
        if not np.all(np.isfinite(R)) or best_eq <= POLISH_FROM:
            break
        C = C - (pinv @ np.swapaxes(R, 0, 1).reshape(R.shape[1], -1).T).T  # r_i ordered (point, input)
        R = equality_gaps(A, B, C, c["D"], dc, ft, X)[0]
        eq = _relative_gap(R, peak)
        if eq < best_eq:
            best_C, best_eq = C, eq
    if best_C is c["C"]:
        return False
    c.update(C=best_C, eq=best_eq, err=channel_errors(A, B, best_C, c["D"], z, G, candidate_eig(c)))
    if zb is not None:
        c["gap"] = gap_excess(c, zb, ub)
    return True
