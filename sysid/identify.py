"""The identification pipeline: frequency response -> stable, constrained discrete state-space model.

Two algorithms (``algorithm=``):

- ``"relocation"`` (the default when ``stable=True`` or a DC gain is imposed on data with one input or
  one output): the McKelvey subspace
  step below gives the Hankel singular values and one set of starting poles; the poles are then fitted to
  the frequency samples by relaxed vector-fitting iterations in ``s = i omega`` with every pole kept stable,
  refined by Gauss-Newton in a stable parametrisation, and the residues and feedthrough by convex fits
  (least squares and minimax, Clarabel) with the exact DC and ``omega = inf`` equalities; the model is mapped
  to discrete time by the bilinear map with period ``T`` (:mod:`sysid.relocation`). On the paper's six LFD
  data sets its max error per output is below stable vector fitting's at every tested order
  (docs/sysid.md).
- ``"subspace"`` (the default without constraints; the paper's method): the steps below.

Subspace steps:

1. Subspace step (:mod:`sysid.subspace`): ``A``, ``C`` by McKelvey's Algorithm 1 (equispaced grid) or 2
   (arbitrary frequencies), from one SVD.
2. Optional stability enforcement (:mod:`sysid.stability`): when ``stable=True`` and the spectral radius
   of ``A`` is ``>= 1 - margin``, ``A`` is replaced by the closest stable matrix for the shift equation
   ``Gamma1 A ~= Gamma2`` (LMI, Lacy & Bernstein) or by eigenvalue reflection.
3. Convex refit of ``B``, ``D`` (:func:`sysid.refit.fit_bd`), with exact equality constraints:

   - DC gain ``G(z=1) = dc`` (``dc_gain="match"`` uses the data's ``omega = 0`` sample, or give an array);
   - feedthrough: when the data contain the ``omega_d = pi`` (``omega = inf``) sample, its value is the
     continuous model's feedthrough and is imposed as ``G(z=-1) = H(pi)`` -- never solved for.

   When stabilisation changed ``A``, the subspace ``C`` no longer matches it, so by default (``refit_c=
   "auto"``) ``C`` is refitted too: alternating B/D and C/D refits (:func:`sysid.refit.fit_alternating`,
   each half step convex with the same equalities, the cost never increases). Measured on the paper's
   LFD data (M = 256, DC + stability): the Cm error (max over frequency / max |H|) of T4 at N_r = 25 falls
   from 1.79 to 0.13, of T5 from 2.53 to 0.10 (N_r = 25) and from 0.89 to 0.009 (N_r = 55).

The result carries the model (``control.StateSpace`` with ``dt = T``), its errors on the data, which
constraints were enforced, and what the stabilisation cost.
"""

from __future__ import annotations

import contextvars
import warnings
from typing import Any

import numpy as np

from .data_checks import check_constraint, check_fit_data, check_flag, check_weights
from .errors import ConstraintError, FrequencyDataError, OptionError
from .frd import FrequencyResponse
from .between import BETWEEN_MIN_ERROR, BETWEEN_RATIO
from .identification_result import IdentificationResult, ModelMatrices, StabilisationReport
from .metrics import dc_error, frf_errors, spectral_radius
from .residues import resonance_points
from .state_space import evaluate_ss
from .subspace import from_basis, hankel_svd, order_hint

__all__ = ["identify", "IdentificationResult", "StabilisationReport", "unobserved_gain", "UNOBSERVED_GAIN_LIMIT",
           "resolve_algorithm", "unresolved_resonances", "UNRESOLVED_WIDTH", "UNRESOLVED_MIN_ERROR", "data_use",
           "INTERPOLATION_RATIO", "BETWEEN_RATIO", "BETWEEN_MIN_ERROR"]


def _resolve_dc(dc_gain: Any, frf: FrequencyResponse, dc_data: np.ndarray | None) -> np.ndarray | None:
    p, m, _ = frf.shape
    if dc_gain is None:   # identify has turned True / False into "match" / None
        return None
    if isinstance(dc_gain, str):   # "match": identify refuses any other string before any work
        dc = dc_data
        if dc is None:
            raise ConstraintError(
                "dc_gain='match' needs a sample at omega = 0 (omega_d = 0) in the data; add that frequency "
                "(the steady solution) or pass the DC gain as a (p, m) array"
            )
        return np.array(dc, dtype=float)
    dc = check_constraint(dc_gain, "dc_gain", p, m, 1.0)
    peak = np.abs(np.asarray(frf.H)).max(axis=2)   # (p, m)
    ratio = np.abs(dc) / np.where(peak > 0, peak, np.inf)
    if np.any(ratio > DC_GAIN_SCALE_LIMIT):
        i, j = (int(x) for x in np.unravel_index(int(np.argmax(ratio)), ratio.shape))
        raise ConstraintError(
            f"dc_gain[{i}, {j}] = {dc[i, j]:.3g} is {ratio[i, j]:.2g} times the largest |H| of the data for that "
            f"output and input ({peak[i, j]:.3g}); above {DC_GAIN_SCALE_LIMIT:g} times no model follows both (the fit "
            "fails or misses the samples by as much): check the DC gain's units and scale")
    return dc


#: The largest ``|dc_gain|`` accepted, in units of the data's peak for the same output and input (``lfdrom fit
#: --dc-gain 1e300,1`` wrote a ROM 1.6e301 % off with a warning; on T4 it failed as "rows coincide").
DC_GAIN_SCALE_LIMIT = 1e6


def identify(
    frf: FrequencyResponse,
    order: int,
    dc_gain: Any = None,
    stable: bool = False,
    weights: Any = None,
    method: str = "auto",
    margin: float = 1e-3,
    *,
    q: int | None = None,
    r: int | None = None,
    stabilise_method: str = "lmi",
    fix_feedthrough: bool = True,
    solver: str = "clarabel",
    refit_c: Any = "auto",
    algorithm: str = "auto",
    minimax_within: float | None = None,
    effort: str = "fast",
) -> IdentificationResult:
    """Identify a discrete state-space model from frequency-response data.

    Parameters
    ----------
    frf : FrequencyResponse
        Data with a sampling period ``T`` (so that ``omega_d`` is known).
    order : int
        Model order ``n`` (number of states).
    dc_gain : None, "match", bool or array_like (p, m)
        ``None``: no DC constraint. ``"match"``: impose the data's ``omega = 0`` value exactly (the data
        must contain that sample). ``True`` means ``"match"`` and ``False`` means no constraint (as
        ``dc_gain = true | false`` in a study file). Array: impose that real DC gain.
    stable : bool
        Enforce spectral radius ``< 1 - margin`` (only acts when the subspace ``A`` violates it).
    weights : array_like, shape (K,) or (p, m, K), optional
        Nonnegative weights of the squared residuals in the B/D refit (e.g. ``1/sigma^2``). The subspace
        step is unweighted.
    method : {"auto", "mckelvey1", "mckelvey2"}
        Subspace algorithm; ``"auto"`` uses Algorithm 1 on the equispaced grid, else Algorithm 2.
    margin : float
        Stability margin (discrete spectral radius ``< 1 - margin``). The relocation path keeps at least 1e-6
        (a smaller margin, 0 included, is met by it): below that its stability disc loses the digits of its edge.
    q, r : int, optional
        Hankel sizes; default ``q = min(M, 2 order + 2)``, ``r = 2M - q`` for Algorithm 1 and
        ``q = min(q_max, 2 order + 2)`` for Algorithm 2 (see :func:`sysid.subspace.default_q`).
    stabilise_method : {"lmi", "reflect"}
        Passed to :func:`sysid.stability.stabilise`.
    minimax_within : float, optional
        Relocation path only: least-squares residues within ``1 + minimax_within`` of the minimax level
        (:func:`sysid.relocation.fit_relocated`; favours low frequencies, i.e. long gusts). Default off.
    effort : {"fast", "thorough"}
        Relocation path only: how many candidate models the fit builds (:data:`sysid.relocation.EFFORTS`).
        ``"fast"`` (default) about 2.5 times stable vector fitting's time at equal order (median), ``"thorough"``
        about 6.5 times, for errors about equal on the paper data (docs/sysid.md, "Where the time goes").
    fix_feedthrough : bool
        Impose ``G(z=-1) = H(omega_d = pi)`` when the data contain that sample (default True).
    solver : {"clarabel", "numpy"}
        Refit solver (see :func:`sysid.refit.fit_bd`).
    refit_c : {"auto", True, False}
        Subspace algorithm only. Also refit ``C`` (alternating B/D and C/D refits,
        :func:`sysid.refit.fit_alternating`): ``"auto"`` when stabilisation changed ``A`` (the paper's
        unconstrained path keeps the subspace ``C``), ``True`` always, ``False`` never.
    algorithm : {"auto", "relocation", "subspace"}
        ``"relocation"``: poles fitted to the data by relaxed vector-fitting iterations in ``s = i omega``
        (stable at every iterate, common to all outputs, each output scaled to unit peak), Gauss-Newton
        refinement in a stable parametrisation, convex least-squares and minimax residue fits with the exact
        DC / feedthrough equalities, bilinear map to discrete time (:func:`sysid.relocation.fit_relocated`);
        the model is always stable with spectral radius ``<= 1 - margin``, whatever ``stable`` says.
        ``"subspace"``: McKelvey subspace + optional stabilisation + convex refits (the paper's method and
        the previous stable path; ``stabilise_method`` and ``refit_c`` apply to it only). ``"auto"``
        (default): ``"relocation"`` when ``stable=True`` or ``dc_gain`` is given and the data have one
        input or one output (the aerofoil gust response: 1 input, Cl and Cm), else ``"subspace"``; so
        ``identify(frf, order)`` is exactly the paper's method. With several inputs and outputs the
        relocation splits the states between the input columns (each column its own poles, common to all
        outputs), which needs ``min(p, m)`` times the states of a subspace model of common poles, so
        ``"auto"`` keeps the subspace algorithm there. When ``"auto"`` chose the relocation and its model's
        gain between the data's frequencies exceeds :data:`UNOBSERVED_GAIN_LIMIT` times the data's peak (a
        resonance where the grid has no samples, :func:`unobserved_gain`) while the stable subspace model's
        gain is lower, the subspace model is returned instead, with a ``RuntimeWarning``: check
        ``result.algorithm``.

    Returns
    -------
    IdentificationResult
        ``result.algorithm`` says which path produced the model.

    Raises
    ------
    TypeError
        ``frf`` is not a :class:`FrequencyResponse`.
    OptionError
        An unknown ``algorithm``, ``method``, ``solver``, ``stabilise_method`` or ``dc_gain`` string, ``refit_c``
        not ``"auto"`` / True / False, ``stable`` or ``fix_feedthrough`` not a bool (``stable="no"`` imposed
        stability), ``margin`` outside ``[0, 1)``, ``minimax_within`` not a positive number (all checked before
        any work, whether the path taken uses them or not).
    FrequencyGridError
        ``frf.T`` is None or does not resolve the data's frequencies (:func:`sysid.grids.check_period_resolves`:
        ``2 / T`` more than 100 times outside them; a ``RuntimeWarning`` beyond 10), a frequency appears twice, or
        the grid does not suit ``method``.
    FrequencyDataError
        An output is zero at every frequency or its peak is outside ``1e-150 .. 1e150``
        (:func:`sysid.data_checks.check_data_scale`), or ``weights`` of the wrong shape, negative, not finite,
        or zero at every frequency (of all outputs or of one).
    OrderError
        Order outside what the data support.
    ConstraintError
        Impossible constraint, e.g. a DC constraint when the model has a pole at ``z = 1``.
    SolverError
        A convex solver failed.
    """
    from .refit import fit_alternating, fit_bd

    for name, value, allowed in (("algorithm", algorithm, ("auto", "relocation", "subspace")),
                                 ("effort", effort, ("fast", "thorough")),
                                 ("method", method, ("auto", "mckelvey1", "mckelvey2")),
                                 ("solver", solver, ("clarabel", "numpy")),
                                 ("stabilise_method", stabilise_method, ("lmi", "reflect"))):
        if not isinstance(value, str) or value not in allowed:   # checked before any work, used or not
            raise OptionError(f"{name} must be one of {allowed}; got {value!r}")
    if isinstance(dc_gain, str) and dc_gain != "match":
        raise OptionError(f"dc_gain must be None, 'match' or a (p, m) array, got {dc_gain!r}")
    if minimax_within is not None and not (isinstance(minimax_within, (int, float)) and np.isfinite(minimax_within)
                                           and minimax_within > 0):
        raise OptionError(f"minimax_within must be a positive fraction (e.g. 0.1) or None; got {minimax_within!r}")
    stable = check_flag(stable, "stable")
    fix_feedthrough = check_flag(fix_feedthrough, "fix_feedthrough")
    if isinstance(dc_gain, (bool, np.bool_)):
        dc_gain = "match" if dc_gain else None  # not the array [[1.0]]: True is the study file's "match"; False,
        # like None, imposes nothing (and so leaves "auto" on the subspace fit when stability is not imposed)
    auto_algorithm = algorithm == "auto"
    if algorithm == "auto" and isinstance(frf, FrequencyResponse):
        algorithm = resolve_algorithm(algorithm, frf.shape[0], frf.shape[1], stable=stable, dc_gain=dc_gain is not None)
    elif algorithm == "auto":
        algorithm = "subspace"  # not a FrequencyResponse: rejected below
    if not (isinstance(refit_c, (bool, np.bool_)) or (isinstance(refit_c, str) and refit_c == "auto")):
        raise OptionError(f"refit_c must be 'auto', True or False; got {refit_c!r}")
    check_fit_data(frf, "identify")
    if isinstance(margin, (bool, np.bool_)) or np.ndim(margin) != 0 \
            or np.asarray(margin).dtype.kind not in "iuf" or not (0.0 <= float(margin) < 1.0):
        raise OptionError(f"margin must be a number in [0, 1), got {margin!r}")
    weights = check_weights(weights, *frf.shape, outputs=frf.outputs)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        dc_data = frf.dc_gain
        ft_data = frf.feedthrough
    for w in caught:  # report each once, from here
        warnings.warn(str(w.message), w.category, stacklevel=2)
    frf = frf.with_real_ends()   # an imaginary part at omega = 0 or inf (warned just above) is not fitted
    T = frf.T
    G = np.asarray(frf.H)
    z = frf.z

    if algorithm == "relocation":
        # small dense problems: one BLAS thread (threaded BLAS made the subspace step alone 0.55 s instead of
        # 0.05 s on a loaded 2-core machine, measured)
        from threadpoolctl import threadpool_limits

        with threadpool_limits(limits=1, user_api="blas"):
            svd = hankel_svd(frf, method=method, q=q, r=r, order=order_hint(order))
            sub = from_basis(svd, order)
    else:
        svd = hankel_svd(frf, method=method, q=q, r=r, order=order_hint(order))
        sub = from_basis(svd, order)
    dc = _resolve_dc(dc_gain, frf, dc_data)
    ft = ft_data if fix_feedthrough else None
    if ft is not None:
        ft = np.array(ft, dtype=float)

    def refit_at(n):   # the same fit at another order (the warnings' advice, _reported)
        return identify(frf, n, dc_gain=dc_gain, stable=stable, weights=weights, method=method, margin=margin,
                        q=q, r=r, stabilise_method=stabilise_method, fix_feedthrough=fix_feedthrough, solver=solver,
                        refit_c=refit_c, algorithm="auto" if auto_algorithm else algorithm,
                        minimax_within=minimax_within, effort=effort)

    if algorithm == "relocation":
        res = _identify_relocation(frf, sub, svd, dc, ft, dc_data, weights, margin, stable, minimax_within, effort)
        if not auto_algorithm:
            return _reported(res, refit_at)
        gain = unobserved_gain(res.matrices, frf)
        if gain.max() <= UNOBSERVED_GAIN_LIMIT:
            return _reported(res, refit_at)
        # the relocated poles found a resonance where the grid has no samples: compare with the subspace path
        token = _ADVISING.set(True)   # (no advice on a model that is only compared)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            alt = identify(frf, order, dc_gain=dc_gain, stable=True, margin=margin, weights=weights, method=method,
                           q=q, r=r, fix_feedthrough=fix_feedthrough, solver=solver,
                           stabilise_method=stabilise_method, refit_c=refit_c, algorithm="subspace")
        _ADVISING.reset(token)
        alt_gain = unobserved_gain(alt.matrices, frf)
        # the subspace model only when it resonates less AND is not estimated farther off between the samples (the
        # truth itself may peak above the samples: a noisy 12-state system's relocated model at 2.3 times the data's
        # peak was 0.077 off the truth, the subspace model it was swapped for, at 1.95 times, 1.18; sysid.between
        # estimated them 0.16 and 0.35). A NaN estimate (too few samples) leaves the gains to decide
        if alt_gain.max() >= gain.max() or alt.between_error >= res.between_error:
            return _reported(res, refit_at)
        i = int(np.argmax(gain))
        warnings.warn(
            f"the pole-relocation model's gain between the data's frequencies reaches {gain[i]:.3g} times the data's "
            f"peak ({list(frf.outputs)[i]}), a resonance where the grid has no samples; the subspace model "
            f"({alt_gain.max():.3g} times; estimated {alt.between_error:.2g} of the peak off between the samples "
            f"against {res.between_error:.2g}) is returned instead. Sample that band more densely (a smaller T puts "
            "more frequencies at high omega) or pass algorithm='relocation' to keep the relocated model",
            RuntimeWarning, stacklevel=2)
        return _reported(alt, refit_at)

    def refit(A, with_c=False):
        """``(fit, C, errors)``: the constrained refit of B, D (and C when ``with_c``) for this ``A``."""
        kw = dict(weights=weights, dc_gain=dc, feedthrough=ft, solver=solver)
        fit = fit_alternating(A, sub.C, z, G, **kw) if with_c else fit_bd(A, sub.C, z, G, **kw)
        C = fit.C if with_c else sub.C
        return fit, C, frf_errors(evaluate_ss(A, fit.B, C, fit.D, z), G)

    A = sub.A
    report = None
    if stable:
        from .stability import stabilise

        rho0 = spectral_radius(A)
        if rho0 >= 1.0 - margin:
            _, _, err0 = refit(A, refit_c is True) if not _has_pole_at_constraint(A, dc, ft) else (None, None, None)
            st = stabilise(A, method=stabilise_method, margin=margin, gamma1=sub.gamma1, gamma2=sub.gamma2)
            A = np.asarray(st.A, dtype=float)
            fit, C, err = refit(A, refit_c in ("auto", True))
            report = StabilisationReport(
                method=st.method, status=st.status, spectral_radius_before=st.spectral_radius_before,
                spectral_radius_after=st.spectral_radius_after, relative_change=st.relative_change,
                rms_error_before=err0.rms_rel if err0 else float("nan"),
                max_error_before=err0.max_rel if err0 else float("nan"),
                rms_error_after=err.rms_rel, max_error_after=err.max_rel,
            )
        else:
            fit, C, err = refit(A, refit_c is True)
            report = StabilisationReport(
                method="none", status="already_stable", spectral_radius_before=rho0, spectral_radius_after=rho0,
                relative_change=0.0, rms_error_before=err.rms_rel, rms_error_after=err.rms_rel,
                max_error_before=err.max_rel, max_error_after=err.max_rel,
            )
    else:
        fit, C, err = refit(A, refit_c is True)

    model = ModelMatrices(A, fit.B, C, fit.D, T, tuple(frf.inputs), tuple(frf.outputs))
    dc_err = None
    if dc_data is not None:
        with np.errstate(all="ignore"):
            dc_model = evaluate_ss(A, fit.B, C, fit.D, np.array([1.0 + 0j]))[:, :, 0]
        dc_err = dc_error(dc_model.real, dc_data) if np.isfinite(dc_model).all() else float("inf")
    enforced = {"dc_gain": dc is not None, "feedthrough": ft is not None, "stable": bool(stable)}
    return _reported(IdentificationResult(
        model=model, order=sub.order, method=sub.method, hankel_sv=svd.sv, errors=err, max_error=err.max_rel,
        rms_error=err.rms_rel, dc_error=dc_err, enforced=enforced, spectral_radius=spectral_radius(A),
        stabilisation=report, subspace=sub, refit=fit, T=T, q=svd.q, r=svd.r, data=frf,
    ), refit_at)


#: The smallest margin the relocation runs with (a smaller ``margin``, 0 included, is met by it): its stability disc
#: has radius ``~ 2 / (T margin)`` and its right edge, ``-(2 / T) margin / 2``, is the difference of two numbers that
#: large, which loses the digits of the edge below it (margin 1e-9 on T4 at order 8, 32 samples: max error 0.0088
#: against 0.0031 from 1e-3 down to 1e-8).
_MIN_RELOCATION_MARGIN = 1e-6


def _identify_relocation(frf, sub, svd, dc, ft, dc_data, weights, margin, stable, minimax_within=None, effort="fast"):
    """The ``algorithm="relocation"`` branch of :func:`identify` (see :mod:`sysid.relocation`)."""
    from .relocation import fit_relocated

    T = frf.T
    G = np.asarray(frf.H)
    z = frf.z
    p, m, K = G.shape
    w = None
    if weights is not None:
        w = np.asarray(weights, dtype=float)
        w = np.broadcast_to(w if w.ndim == 3 else w.reshape(1, 1, -1), (p, m, K))
        if not (np.all(np.isfinite(w)) and np.all(w >= 0)):
            raise FrequencyDataError("weights must be finite and nonnegative")
    starts = None
    lam = np.linalg.eigvals(sub.A)
    ok = np.abs(lam + 1.0) > 1e-8
    if ok.all():  # the subspace poles, mapped to s (paper Eq. 26): one more start for the relocation
        starts = {"subspace": (2.0 / T) * (lam - 1.0) / (lam + 1.0)}
    mg = max(float(margin), _MIN_RELOCATION_MARGIN)
    rl = fit_relocated(frf.omega, z, G, T, sub.order, dc_gain=dc, feedthrough=ft, weights=w, start_poles=starts,
                       margin=mg, minimax_within=minimax_within, effort=effort)
    A, B, C, D = rl.A, rl.B, rl.C, rl.D
    model = ModelMatrices(A, B, C, D, T, tuple(frf.inputs), tuple(frf.outputs))
    Gm = evaluate_ss(A, B, C, D, z)
    err = frf_errors(Gm, G)
    dc_err = None
    if dc_data is not None:
        dc_model = evaluate_ss(A, B, C, D, np.array([1.0 + 0j]))[:, :, 0]
        dc_err = dc_error(dc_model.real, dc_data)
    rho = spectral_radius(A)
    report = None
    if stable:
        report = StabilisationReport(
            method="relocation", status="stable_by_construction", spectral_radius_before=rho,
            spectral_radius_after=rho, relative_change=0.0, rms_error_before=err.rms_rel,
            rms_error_after=err.rms_rel, max_error_before=err.max_rel, max_error_after=err.max_rel,
        )
    enforced = {"dc_gain": dc is not None, "feedthrough": ft is not None, "stable": True}
    return IdentificationResult(
        model=model, order=A.shape[0], method=sub.method, hankel_sv=svd.sv, errors=err, max_error=err.max_rel,
        rms_error=err.rms_rel, dc_error=dc_err, enforced=enforced, spectral_radius=rho, stabilisation=report,
        subspace=sub, refit=None, T=T, q=svd.q, r=svd.r, data=frf, algorithm="relocation", relocation=rl,
    )


def resolve_algorithm(algorithm: str, p: int, m: int, *, stable: bool, dc_gain: bool) -> str:
    """What :func:`identify` runs for ``algorithm`` on data with ``p`` outputs and ``m`` inputs.

    ``"auto"``: ``"relocation"`` when stability or a DC gain is imposed and ``min(p, m) == 1`` (the relocation
    gives each input column its own poles, so with several inputs and outputs it needs more states than a
    subspace model of common poles), else ``"subspace"``. Other values are returned as they are. The default's
    fallback to the subspace model (see :data:`UNOBSERVED_GAIN_LIMIT`) happens after fitting and is not
    decided here.

    Returns
    -------
    {"relocation", "subspace"}
    """
    if algorithm != "auto":
        return algorithm
    return "relocation" if (stable or dc_gain) and min(p, m) == 1 else "subspace"


UNOBSERVED_GAIN_LIMIT = 1.5
"""Largest gain, in units of each output's data peak, that the default (``algorithm="auto"``) accepts from the
pole-relocation model between the data's frequencies before it compares with the subspace model (returned instead
only when its gain there is lower and its estimated error between the samples, :mod:`sysid.between`, too)."""


def unobserved_gain(model, frf: FrequencyResponse, refine: int = 8) -> np.ndarray:
    """Peak gain of ``model`` on a grid ``refine`` times denser than the data's and at the peaks of its own
    resonances (:func:`sysid.residues.resonance_points`), per output, in units of the data's peak on that output.

    A fit can match every sample and still resonate between two of them: on the paper's grid (T = 70/(2 pi))
    the samples at omega = 14.6 and 29.2 have none between them, and the relocation fit of the low-Mach T4
    put a resonance of 28 times Cm's data peak at omega = 15.5 there (its gust histories missed by 3x). Values
    near 1 mean no unobserved gain.

    Parameters
    ----------
    model : control.StateSpace
        Discrete, ``dt = frf.T``.
    frf : FrequencyResponse
        The data (on ``omega_d``).
    refine : int
        Points of the dense grid per data interval (equispaced in ``omega_d`` over ``[0, pi]``).

    Returns
    -------
    ndarray, shape (p,)
    """
    G = np.asarray(frf.H)
    peak = np.maximum(np.abs(G).max(axis=(1, 2)), np.finfo(float).tiny)
    n_dense = refine * max(len(frf.omega_d) - 1, 1) + 1
    A, B, C, D = (np.asarray(x, dtype=float) for x in (model.A, model.B, model.C, model.D))
    # and at the peaks of the model's own resonances, which a resonance narrower than the grid's spacing hides
    z = np.concatenate([np.exp(1j * np.linspace(0.0, np.pi, n_dense)), resonance_points(np.linalg.eigvals(A))])
    with np.errstate(all="ignore"):
        Gm = evaluate_ss(A, B, C, D, z)
    return np.abs(Gm).max(axis=(1, 2)) / peak


UNRESOLVED_WIDTH = 0.05
"""Half-width of a resonance, in local sample spacings, below which :func:`identify` reports it: a pole pair that
narrow is invisible at the samples, so the model's response between them (height and phase of the resonance) is
not determined by the data. The paper's six LFD data sets fitted at N_r = 9 - 55 have no resonance below 0.17
spacings (measured on 2026-12-03); a fit of 1 % noisy data at twice the true order put one at 0.02 spacings and
was 35 % of the peak off between the samples while matching every sample to 1.6 %."""

UNRESOLVED_MIN_ERROR = 1e-9
"""Largest error on the samples (fraction of the peak) at which an unresolved resonance is not reported: noise-free
samples of a lightly damped system fitted to round-off determine its resonance however sparse the grid."""


def unresolved_resonances(model, frf: FrequencyResponse, width: float = UNRESOLVED_WIDTH) -> np.ndarray:
    """Stable resonances of ``model`` narrower than ``width`` local sample spacings of the data.

    Parameters
    ----------
    model : control.StateSpace
        Discrete, ``dt = frf.T``.
    frf : FrequencyResponse
        The data (their continuous frequencies ``omega`` set the local spacing,
        :func:`sysid.poles.resolution_floor`).
    width : float
        Half-width threshold in local sample spacings.

    Returns
    -------
    ndarray, shape (k, 3)
        One row per pole pair (upper half-plane), ``(omega_p, sigma, spacing)``: the pole ``-sigma + i omega_p``
        of the continuous model (bilinear map with ``T``; U/c units) and the local sample spacing there; empty
        when every resonance is at least ``width`` spacings wide.
    """
    from .poles import resolution_floor

    lam = np.linalg.eigvals(np.asarray(model.A, dtype=float))
    with np.errstate(all="ignore"):
        s = (2.0 / float(model.dt)) * (lam - 1.0) / (lam + 1.0)
    xp, fp = resolution_floor(np.asarray(frf.omega, dtype=float), 1.0)   # the local spacing itself
    s = s[np.isfinite(s) & (s.real < 0) & (s.imag >= 0)]
    spacing = np.interp(s.imag, xp, fp)
    narrow = -s.real < width * spacing
    return np.column_stack([s.imag[narrow], -s.real[narrow], spacing[narrow]])


INTERPOLATION_RATIO = 0.5
"""Share of the data's real values that a model's parameters may reach before :func:`identify` warns that it
nearly interpolates them (then its errors on the samples say little of the response between them: five samples
fitted at order 3, 7 parameters for 8 values, reported 1e-3 and were 25 % off between the samples, measured).
The paper's own fits use at most 0.23 (N_r = 55 on 257 frequencies 0.16, N_r = 9 on 33 frequencies 0.23); the
paper study's extra T2 fit at N_r = 25 on 33 frequencies uses 0.60 and is warned about, rightly: matching its 33
samples to 0.03 % (DC + stable) it is 44 % off on Cm at the 257 frequencies of the full grid (measured on
2026-12-03 from docs/data/frf-T2.npz subsampled to M = 32)."""


def data_use(order: int, frf: FrequencyResponse) -> float:
    """Parameters of an order-``order`` model over the real values of the data.

    Parameters
    ----------
    order : int
    frf : FrequencyResponse

    Returns
    -------
    float
        ``(order (p + m) + p m) / (2 K p m - k_real p m)``: the dimension of the order-``order`` ``p x m`` systems
        over the real values of ``K`` complex samples, of which ``k_real`` (the samples at ``omega = 0`` and
        ``inf``) are real.
    """
    p, m, K = frf.shape
    wd = np.asarray(frf.omega_d)
    k_real = int(np.count_nonzero((wd == 0.0) | np.isclose(wd, np.pi, rtol=0.0, atol=1e-12)))
    return (order * (p + m) + p * m) / max(2 * K * p * m - k_real * p * m, 1)


_ADVISING = contextvars.ContextVar("sysid_identify_advising", default=False)


def _reported(res: IdentificationResult, refit_at=None) -> IdentificationResult:
    """Warn when the model nearly interpolates the data (:data:`INTERPOLATION_RATIO`) or has a resonance the data
    cannot resolve (:data:`UNRESOLVED_WIDTH`), or its estimated error between the samples is far above the error
    on them (:data:`BETWEEN_RATIO`); return ``res``. ``refit_at(n)``: the same fit at order ``n``, tried before the
    warning advises a lower order (the advice is given only when that order's estimate between the samples is
    lower)."""
    if res.data is None or _ADVISING.get():
        return res
    use = data_use(res.order, res.data)
    if use > INTERPOLATION_RATIO:
        warnings.warn(
            f"the order-{res.order} model has {use:.0%} as many parameters as the data have real values: it nearly "
            "interpolates them, so its errors on the samples say little about its response between them; lower "
            "the order, add frequencies, or choose the order on held-out samples (sysid.order_sweep, lfdrom fit "
            "--order auto)", RuntimeWarning, stacklevel=3)
    if not np.isfinite(res.max_error) or res.max_error <= UNRESOLVED_MIN_ERROR:
        return res
    narrow = unresolved_resonances(res.matrices, res.data, width=2 * UNRESOLVED_WIDTH)
    between = res.between_error_per_output
    on = np.asarray(res.errors.max_rel_per_output)
    far_per_output = (between > BETWEEN_RATIO * on) & (between > BETWEEN_MIN_ERROR)
    far = bool(np.any(far_per_output))
    _warn_open(res, on, between, skip=far_per_output)   # outputs whose estimate itself is low but says little
    if not far:   # a narrow resonance that the estimate does not see between the samples is no cause for alarm
        return res
    i = int(np.argmax(np.where(far_per_output, between / np.maximum(on, np.finfo(float).tiny), -np.inf)))
    est = (f"its error between the samples is estimated at {between[i]:.2g} of the peak against {on[i]:.2g} on them "
           f"({list(res.data.outputs)[i]}, sysid.between)")
    if narrow.size:
        w, sigma, spacing = narrow[np.argmin(narrow[:, 1] / narrow[:, 2])]
        text = (f"the order-{res.order} model has a resonance at omega = {w:.4g} of half-width {sigma:.3g}, "
                f"{sigma / spacing:.2g} of the data's spacing there ({spacing:.3g}): invisible at the samples, so its "
                f"response between them is not determined by the data; {est}.")
        # a lower order may remove the resonance: tried before advised (a second fit; skipped when nobody can
        # read the advice: the warning is ignored)
        advice = _order_advice(res, refit_at) if not _ignored(RuntimeWarning, text) else ""
        warnings.warn(f"{text} {advice}", RuntimeWarning, stacklevel=3)
    else:   # no resonance to blame: the data are sparse for what the response does there (e.g. a fast phase)
        from .between import between_deviation

        m = res.matrices
        pts, dev = between_deviation(m.A, m.B, m.C, m.D, res.data.omega_d, res.data.H)
        wd = pts[int(np.argmax(dev[i].max(axis=0)))]
        where = 2.0 / res.T * np.tan(wd / 2.0)
        warnings.warn(f"the order-{res.order} model is not pinned down between the samples: {est}. The samples are "
                      f"sparse for what the response does between them: sample more densely (worst at omega = "
                      f"{where:.4g}; with the bilinear grid a smaller T puts more samples at high omega)",
                      RuntimeWarning, stacklevel=3)
    return res


def _warn_open(res: IdentificationResult, on: np.ndarray, between: np.ndarray, skip: np.ndarray) -> None:
    """Warn where the samples leave an output open between them
    (:attr:`IdentificationResult.between_uncertainty_per_output`) by more than :data:`BETWEEN_RATIO` times both the error on them and the estimate between them, and by more than
    :data:`sysid.between.READING_FLOOR` of the peak: the estimate is then a lower bound that says little. Outputs
    in ``skip`` (their estimate already warns) are left out."""
    from .between import READING_FLOOR, between_points, sample_readings

    open_ = res.between_uncertainty_per_output
    wide = (open_ > BETWEEN_RATIO * np.maximum(on, between)) & (open_ > READING_FLOOR) & ~np.asarray(skip)
    if not np.any(wide):
        return
    i = int(np.argmax(np.where(wide, open_ / np.maximum(np.maximum(on, between), np.finfo(float).tiny), -np.inf)))
    pts = between_points(res.data.omega_d, np.linalg.eigvals(res.matrices.A))   # where the uncertainty was taken
    _, spread, _ = sample_readings(res.data.omega_d, res.data.H, pts)
    wd = pts[int(np.argmax(spread[i].max(axis=0)))]
    warnings.warn(
        f"the samples leave {list(res.data.outputs)[i]} open between them: local readings of them disagree by up to "
        f"{open_[i]:.2g} of the peak (worst at omega = {2.0 / res.T * np.tan(wd / 2.0):.4g}), against an error of "
        f"{on[i]:.2g} on them and an estimated {between[i]:.2g} between them (sysid.between), so the order-{res.order} "
        "model may be that far off there and no fit of these samples can tell. Sample more densely there (with the "
        "bilinear grid a smaller T puts more samples at high omega)", RuntimeWarning, stacklevel=4)


def _ignored(category: type[Warning], text: str) -> bool:
    """True when a warning of ``category`` whose message starts with ``text`` would be ignored wherever it is issued:
    the first entry of :data:`warnings.filters` that applies to the category and message (filters match a message
    from its start) is an ``"ignore"`` without a module or line condition (e.g. ``warnings.simplefilter("ignore")``).
    A first applicable filter with such a condition, or any other action (``"error"``, ``"always"``), gives False."""
    for action, message, cat, module, lineno in warnings.filters:
        if issubclass(category, cat) and (message is None or message.match(text)):
            return action == "ignore" and module is None and not lineno
    return False


def _order_advice(res: IdentificationResult, refit_at) -> str:
    """What to do about an error between the samples far above the error on them: a lower order when the fit at
    ``order - 2`` has a lower estimate between the samples (tried here), else denser sampling."""
    dense = "sample that band more densely"
    if refit_at is None or res.order <= 2:
        return dense[0].upper() + dense[1:]
    token = _ADVISING.set(True)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            low = refit_at(res.order - 2)
        e_low = low.between_error
    except Exception:   # the lower order does not fit these data (order limits, constraints): no advice on it
        return dense[0].upper() + dense[1:]
    finally:
        _ADVISING.reset(token)
    e = res.between_error
    if e_low < 0.8 * e:   # a material improvement (a fifth), not a reshuffle of the same miss
        return (f"Order {low.order} lowers that estimate to {e_low:.2g} (on the samples {low.max_error:.2g}): lower "
                f"the order, or {dense}")
    return (f"A lower order does not help (order {low.order}: {e_low:.2g} between the samples); {dense} (or choose "
            "the order with sysid.order_sweep)")


def _has_pole_at_constraint(A: np.ndarray, dc, ft) -> bool:
    """True when a constraint point (z = 1 for DC, z = -1 for feedthrough) is (nearly) a pole of A."""
    lam = np.linalg.eigvals(A)
    bad = False
    if dc is not None:
        bad |= bool(np.any(np.abs(lam - 1.0) < 1e-8))
    if ft is not None:
        bad |= bool(np.any(np.abs(lam + 1.0) < 1e-8))
    return bad
