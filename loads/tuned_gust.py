"""The tuned discrete gust of CS-25.341(a): the 1-cosine gust gradient that maximises each load.

For each gust gradient ``H`` the response to the design gust (amplitude ``U_ds(H) / U``, both TAS) is exact
(:mod:`loads.one_minus_cosine`); a negative gust gives the negative response, so over both signs the largest
load of an output is ``F(H) = max_s |y(s; H)|`` with the gust's sign that of ``y`` at the peak. The search:

1. time: ``y`` is sampled on a grid that resolves the gust (``H / 16``) and every lightly damped mode the gust
   excites (12 samples per period), over ``2 H`` plus a tail; the largest sample is refined by golden-section
   between its neighbours: the root of the exact slope ``dy/ds`` by regula falsi (12 Illinois steps), or
   golden-section search (24 steps: the time to ``1e-5`` of the step) where the slope does not change sign. The tail is certified: after the
   horizon ``S`` every mode decays (``Re lambda <= 0``), so ``|y(s)| <= sum_i |C_i z_i(S)|`` for ``s >= S``; the
   horizon is doubled until that bound is below the peak found (up to 5 times, else a ``RuntimeWarning``);
2. gradient: ``F`` on a geometric grid of ``n_grid`` values of ``H`` over the range, then golden-section search
   on each local maximum within 2 % of the best, until the bracket is below ``h_rtol`` (relative; default
   1e-4, which puts the load within about ``h_rtol^2`` of its maximum where ``F`` is smooth, and within
   ``h_rtol`` times ``|dF/dH| H`` at a kink, where the peak jumps between two times of the history).
   The largest value evaluated is the answer (a maximum at an end of the range is found as such).

Checked against brute force (the maximum over a dense grid of ``H`` and times) in the tests.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from typing import Any, Sequence

import numpy as np

from .atmosphere import FT, H_RANGE_FT, FlightPoint
from .errors import GustError, LoadsModelError
from .one_minus_cosine import outputs_at
from .system import GustSystem, check_distinct_outputs, gust_system

__all__ = ["TunedGustResult", "tuned_gust", "peak_over_time", "initial_tail", "GOLDEN_STEPS", "ILLINOIS_STEPS", "MAX_SAMPLES",
           "MAX_GRID"]

GOLDEN_STEPS = 24
"""Golden-section steps of the time refinement: the bracket of two samples shrinks by 0.618^24 = 1e-5, so the
peak value is within ``|y''| (1e-5 step)^2 / 2`` of the true one (about 1e-11 relative at 12 samples per period)."""
ILLINOIS_STEPS = 12
"""Regula-falsi (Illinois) steps on ``dy/ds = 0`` of the time refinement (superlinear: the peak time to round-off
for a smooth peak; brackets where the slope keeps its sign fall back to :data:`GOLDEN_STEPS` of golden section)."""
MAX_SAMPLES = 20000
"""Most time samples per gust (a finer need is capped, with a ``RuntimeWarning``)."""
MAX_GRID = 2000
"""Largest ``n_grid`` of :func:`tuned_gust` (the study files' limit too). The first grid only brackets each local
maximum of the load against ``H`` for the golden-section search, which refines it to ``h_rtol``; its gusts' time
responses are all held in memory at once (1000 points took 21 s and 3.4 GB with an order-8 ROM, two outputs;
``n_grid = 10**7`` asked for 107 GiB after 67 s)."""
_GR = (math.sqrt(5.0) - 1.0) / 2.0


@dataclass(frozen=True)
class TunedGustResult:
    """Tuned-gust loads of one flight point (model units unless ``dimensional``; dicts keyed by output name).

    Attributes
    ----------
    outputs : tuple of str
        The outputs searched.
    peak : dict
        Largest ``|load|`` over ``H`` and both gust signs (the increment over the 1 g load; the maximum is
        ``+peak`` and the minimum ``-peak``: a negative gust mirrors a positive one).
    critical_H : dict
        ``H`` (m) of the peak.
    gust_sign : dict
        +1 (up-gust) or -1 (down-gust) giving ``+peak``.
    peak_time : dict
        Time of the peak (s) from the gust's arrival at the leading edge.
    correlated : dict of dict
        ``correlated[x][y]``: output ``y`` at the time of ``x``'s peak, in the same gust (so
        ``correlated[x][x] == peak[x]``); all the system's outputs.
    dimensional, units : dict
        ``peak`` in SI at the flight point (N/m, N m/m, m, ...) and its unit.
    H_tolerance : dict
        Width (m) of the final bracket of ``H``.
    H_grid : ndarray, shape (K,)
        Every ``H`` evaluated (m), sorted.
    peak_vs_H : ndarray, shape (len(outputs), K)
        ``max_s |y|`` at each ``H_grid`` (the load-versus-H curve).
    times : dict
        Times (s) of the history at each output's critical gust, shape (N,).
    histories : dict
        Histories of all outputs at each output's critical gust (sign applied), shape (p, N).
    gust : dict
        Gust velocity (m/s TAS) of that history, shape (N,).
    all_outputs : tuple of str
        The system's outputs (rows of ``histories``, keys of ``correlated[x]``).
    n_gradients : int
        Distinct gust gradients evaluated by the search (each would be one march of a time-domain solver; one
        gust sign suffices, the response being linear).
    H_evaluated : ndarray, shape (n_gradients,)
        Those gradients (m), sorted.
    point : FlightPoint
    system : GustSystem
    """

    outputs: tuple
    peak: dict
    critical_H: dict
    gust_sign: dict
    peak_time: dict
    correlated: dict
    dimensional: dict
    units: dict
    H_tolerance: dict
    H_grid: np.ndarray = field(repr=False)
    peak_vs_H: np.ndarray = field(repr=False)
    times: dict = field(repr=False)
    histories: dict = field(repr=False)
    gust: dict = field(repr=False)
    all_outputs: tuple = ()
    n_gradients: int = 0
    H_evaluated: np.ndarray = field(default=None, repr=False)
    point: FlightPoint | None = field(default=None, repr=False)
    system: GustSystem | None = field(default=None, repr=False)

    @property
    def maximum(self) -> dict:
        """Largest load per output (``+peak``)."""
        return dict(self.peak)

    @property
    def minimum(self) -> dict:
        """Smallest load per output (``-peak``)."""
        return {k: -v for k, v in self.peak.items()}

    def summary(self) -> str:
        """One line per output: peak, dimensional peak, critical H, sign."""
        lines = [f"tuned gust at {self.point.summary()}"]
        for o in self.outputs:
            lines.append(f"  {o}: peak {self.peak[o]:.5g} ({self.dimensional[o]:.5g} {self.units[o]}) at H = "
                         f"{self.critical_H[o]:.4g} m ({self.critical_H[o] / FT:.4g} ft), "
                         f"{'up' if self.gust_sign[o] > 0 else 'down'}-gust, t = {self.peak_time[o]:.4g} s")
        return "\n".join(lines)


def _h_range(H_range: Any, outside_rule: bool, chord: float) -> tuple[float, float]:
    lo_r, hi_r = H_RANGE_FT[0] * FT, H_RANGE_FT[1] * FT
    if H_range is None:
        return lo_r, hi_r
    try:
        lo, hi = (float(x) for x in H_range)
    except (TypeError, ValueError):
        raise GustError(f"H_range must be two gust gradients (m), got {H_range!r}") from None
    if not (math.isfinite(lo) and math.isfinite(hi) and 0.0 < lo <= hi):
        raise GustError(f"H_range must hold 0 < H_min <= H_max (m), got {H_range!r}")
    if not outside_rule and (lo < lo_r * (1 - 1e-9) or hi > hi_r * (1 + 1e-9)):
        raise GustError(f"H_range {lo:g} .. {hi:g} m leaves the rule's 30 .. 350 ft ({lo_r:.4g} .. {hi_r:.4g} m); "
                        "pass outside_rule=True to search it anyway")
    return lo, hi


def _sample_step(system: GustSystem, Hc: np.ndarray) -> np.ndarray:
    """Time step (convective) per gust: ``H / 16`` and 12 samples per period of each lightly damped mode that the
    gust excites (frequency below 30 times the gust's ``pi / H``, damping ratio below 0.7). Faster modes that
    matter are added by :func:`_resolving_step` once the peak is known."""
    lam = system.lam
    step = Hc / 16.0
    osc = np.abs(lam.imag) > 1e-12
    if np.any(osc):
        w = np.abs(lam.imag[osc])
        zeta = -lam.real[osc] / np.abs(lam[osc])
        for i, wg in enumerate(np.pi / Hc):
            ww = w[(w < 30.0 * wg) & (zeta < 0.7)]
            if ww.size:
                step[i] = min(step[i], 2.0 * np.pi / ww.max() / 12.0)
    return step


def free_oscillation_amplitude(system: GustSystem, Hc: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """``|C_ji b_i| w^2 / (2 |lambda_i| |lambda_i^2 + w^2|)``, ``w = pi / H``, per gust and mode, shape (m, n): the
    amplitude of the free response of mode ``i`` in output ``rows[k]`` that each end of the gust starts (per unit
    gust angle).

    With ``u = (1 - cos w s) / 2`` on ``0 <= s <= 2 H``, the modal equation ``z' = lambda z + b u`` from rest has the
    forced part ``-b / (2 lambda) + b (lambda cos w s - w sin w s) / (2 (lambda^2 + w^2))`` and the free part
    ``c exp(lambda s)``, ``c = b w^2 / (2 lambda (lambda^2 + w^2))``; when the gust ends the forced part drops to 0
    by ``-c``, which starts ``-c exp(lambda (s - 2 H))``. For a mode much faster than the gust ``|c|`` is about
    ``|b| w^2 / (2 |lambda|^3)``: negligible unless the output weights the mode heavily (an acceleration: ``C``
    grows like ``lambda^2``).
    """
    lam = system.lam[None, :]
    w2 = (np.pi / Hc[:, None]) ** 2
    with np.errstate(divide="ignore", invalid="ignore"):
        out = np.abs(system.C[rows] * system.b[None, :]) * w2 / (2.0 * np.abs(lam) * np.abs(lam * lam + w2))
    return np.where(np.isfinite(out), out, 0.0)


def _resolving_step(system: GustSystem, Hc: np.ndarray, rows: np.ndarray, step: np.ndarray, peak: np.ndarray,
                    rtol: float = 1e-4) -> np.ndarray:
    """``step`` shortened to 12 samples per ``2 pi / |lambda|`` of the modes that the grid does not resolve where
    together they could lift the peak by more than ``rtol`` of it.

    Such a mode is faster than the grid (30 times the gust's frequency, or a heavily damped one, or a fast real
    pole) and weighted heavily by the output (an acceleration: a grid of ``H / 16`` aliased 27 % of one's peak at
    87 times the gust frequency). Its free responses (:func:`free_oscillation_amplitude`, one from each end of the
    gust, decaying from there) can change the response between two samples by at most twice their sum, so the peak
    found (``peak``) stands where ``|y(s_k)| + 2 sum_i |c_i| (e^(Re lambda_i s_k) + e^(Re lambda_i (s_k - 2H)))``
    stays below ``peak (1 + rtol)`` at every sample ``s_k``; elsewhere the step resolves the modes that carry it.
    """
    lam = system.lam
    speed = np.abs(lam)
    amp = free_oscillation_amplitude(system, Hc, rows)                     # (m, n): per end of the gust
    unresolved = (speed[None, :] * step[:, None] > 2.0 * np.pi / 12.0 * (1.0 + 1e-9)) & (amp > 0)
    out = step.copy()
    for k in np.flatnonzero(4.0 * np.where(unresolved, amp, 0.0).sum(axis=1) > rtol * peak):
        i = np.flatnonzero(unresolved[k])            # (few gusts: those with fast, heavily weighted modes)
        horizon = 2.0 * Hc[k] + float(initial_tail(system, Hc[k:k + 1])[0])
        s = np.linspace(0.0, horizon, int(min(np.ceil(horizon / step[k]) + 1, MAX_SAMPLES)))
        y = np.abs(_rowwise(system, np.full(s.size, Hc[k]), s, np.full(s.size, rows[k])))
        after = np.maximum(s - 2.0 * Hc[k], 0.0)    # (from the gust's end on)
        decay = np.exp(np.outer(s, lam.real[i])) + np.where(s[:, None] >= 2.0 * Hc[k],
                                                             np.exp(np.outer(after, lam.real[i])), 0.0)
        if np.max(y + 2.0 * decay @ amp[k, i]) > peak[k] * (1.0 + rtol):
            # the modes that matter: those whose share could reach rtol of the peak (their sum could)
            big = i[2.0 * amp[k, i] * 2.0 > rtol * peak[k] / i.size]
            out[k] = min(step[k], 2.0 * np.pi / 12.0 / speed[big if big.size else i].max())
    return out


def initial_tail(system: GustSystem, Hc: np.ndarray) -> np.ndarray:
    """The first tail after the gust (convective), shape of ``Hc`` (chords): ``2 H``, and at least two periods of
    the slowest oscillatory mode (doubled by :func:`peak_over_time` until its certificate holds)."""
    lam = system.lam
    tail = 2.0 * Hc
    osc = (np.abs(lam.imag) > 1e-12)
    if np.any(osc):
        tail = np.maximum(tail, 2.0 * 2.0 * np.pi / np.abs(lam.imag[osc]).min())
    return tail


def peak_over_time(system: GustSystem, Hc: Any, rows: Sequence[int], *, max_doublings: int = 5):
    """``max_s |y_j(s; H)|`` per unit gust angle for each gust ``H`` (chords) and output row ``rows[k]``.

    Parameters
    ----------
    system : GustSystem
    Hc : array_like, shape (m,)
        Gust gradients in chords.
    rows : sequence of int, length m
        The output row for each gust.

    Returns
    -------
    value : ndarray, shape (m,)
        The peak of ``|y|`` per unit gust angle.
    time : ndarray, shape (m,)
        Its convective time.
    signed : ndarray, shape (m,)
        ``y`` there (sign included).
    """
    Hc = np.asarray(Hc, dtype=float).reshape(-1)
    rows = np.asarray(rows, dtype=int).reshape(-1)
    step = _sample_step(system, Hc)
    value, time = _peaks(system, Hc, rows, step, max_doublings)
    # modes faster than the grid that could lift this peak by 1e-4 of it (their free responses): again, resolved
    finer = _resolving_step(system, Hc, rows, step, value)
    redo = np.flatnonzero(finer < step)
    if redo.size:
        v2, t2 = _peaks(system, Hc[redo], rows[redo], finer[redo], max_doublings)
        better = v2 >= value[redo]
        value[redo[better]], time[redo[better]] = v2[better], t2[better]
    signed = _rowwise(system, Hc, time, rows)
    return value, time, signed


def _peaks(system, Hc, rows, step, max_doublings):
    """The sampled-and-refined peak of :func:`peak_over_time` on time steps ``step`` (m,): ``(value, time)``."""
    m = Hc.size
    tail = initial_tail(system, Hc)
    value = np.zeros(m)
    time = np.zeros(m)
    todo = np.arange(m)
    C = system.C
    for attempt in range(max_doublings + 1):
        horizon = 2.0 * Hc[todo] + tail[todo]
        n = np.minimum(np.ceil(horizon / step[todo]).astype(int) + 1, MAX_SAMPLES)
        if np.any(np.ceil(horizon / step[todo]) + 1 > MAX_SAMPLES):
            warnings.warn(f"the time grid is capped at {MAX_SAMPLES} samples per gust; the peak search relies on the "
                          "golden-section refinement between coarser samples", RuntimeWarning, stacklevel=3)
        N = int(n.max())
        frac = np.linspace(0.0, 1.0, N)
        S = horizon[:, None] * frac[None, :]                      # (k, N)
        HH = np.repeat(Hc[todo], N)
        y = _rowwise(system, HH, S.ravel(), np.repeat(rows[todo], N)).reshape(todo.size, N)
        k = np.argmax(np.abs(y), axis=1)
        ds = horizon / (N - 1)
        lo = S[np.arange(todo.size), k] - ds
        hi = S[np.arange(todo.size), k] + ds
        lo = np.maximum(lo, 0.0)
        hi = np.minimum(hi, horizon)
        t_best, v_best = _golden_abs(system, Hc[todo], rows[todo], lo, hi)
        sampled = np.abs(y[np.arange(todo.size), k])
        better = sampled > v_best
        t_best = np.where(better, S[np.arange(todo.size), k], t_best)
        v_best = np.where(better, sampled, v_best)
        value[todo], time[todo] = v_best, t_best
        # certificate: |y(s)| <= sum_i |C_ji z_i(S)| for s >= S (every mode decays after the gust)
        from .one_minus_cosine import modal_states

        zS = modal_states(system.lam, system.b, Hc[todo], horizon)
        bound = np.abs(C[rows[todo]] * zS).sum(axis=1)
        ok = bound <= v_best * (1 + 1e-12) + 1e-300
        if ok.all():
            break
        if attempt == max_doublings:
            bad = todo[~ok]
            warnings.warn(f"{bad.size} gust response(s) may still peak after the horizon ({max_doublings} doublings of "
                          "the tail): a mode that barely decays (a free or undamped one) keeps the response near its "
                          "peak; the peak reported is the largest within the horizon", RuntimeWarning, stacklevel=3)
            break
        tail[todo[~ok]] = 2.0 * (tail[todo[~ok]] + 2.0 * Hc[todo[~ok]])
        todo = todo[~ok]
    return value, time


def _rowwise(system, H, s, rows):
    """Output ``rows[k]`` at query ``(H[k], s[k])``, shape (m,)."""
    from .one_minus_cosine import outputs_rowwise

    return outputs_rowwise(system, H, s, rows)


def golden_max(f, lo: np.ndarray, hi: np.ndarray, steps: int):
    """Vectorised golden-section maximisation of ``f`` (arrays of points -> values) on ``[lo, hi]`` per entry.

    Returns the best point evaluated and its value (shapes of ``lo``), and the final bracket width.
    """
    a, b = np.array(lo, dtype=float), np.array(hi, dtype=float)
    x1 = b - _GR * (b - a)
    x2 = a + _GR * (b - a)
    f1, f2 = f(x1), f(x2)
    for _ in range(steps):
        left = f1 >= f2                                  # the maximum lies in [a, x2]
        a_new = np.where(left, a, x1)
        b_new = np.where(left, x2, b)
        x1_new = np.where(left, b_new - _GR * (b_new - a_new), x2)
        x2_new = np.where(left, x1, a_new + _GR * (b_new - a_new))
        fe = f(np.where(left, x1_new, x2_new))
        f1, f2 = np.where(left, fe, f2), np.where(left, f1, fe)
        a, b, x1, x2 = a_new, b_new, x1_new, x2_new
    best = np.where(f1 >= f2, x1, x2)
    return best, np.maximum(f1, f2), b - a


def _golden_abs(system, H, rows, lo, hi):
    """Maximise ``|y_rows(s; H)|`` on ``[lo, hi]`` per query (vectorised): the root of ``dy/ds`` by regula falsi
    (Illinois) where the slope changes sign across the bracket, golden-section search elsewhere."""
    from .one_minus_cosine import slopes_rowwise

    fa = slopes_rowwise(system, H, lo, rows)
    fb = slopes_rowwise(system, H, hi, rows)
    root = fa * fb < 0.0
    best = np.empty(lo.shape)
    if np.any(root):
        i = np.flatnonzero(root)
        best[i] = _illinois(lambda x: slopes_rowwise(system, H[i], x, rows[i]), lo[i], hi[i], fa[i], fb[i])
    if np.any(~root):
        i = np.flatnonzero(~root)
        best[i], _, _ = golden_max(lambda x: np.abs(_rowwise(system, H[i], x, rows[i])), lo[i], hi[i], GOLDEN_STEPS)
    return best, np.abs(_rowwise(system, H, best, rows))


def _illinois(f, a, b, fa, fb, steps: int = ILLINOIS_STEPS):
    """Vectorised Illinois regula falsi for a root of ``f`` in ``[a, b]`` (``fa fb < 0``)."""
    a, b, fa, fb = (np.array(v, dtype=float) for v in (a, b, fa, fb))
    side = np.zeros(a.shape)
    for _ in range(steps):
        x = (a * fb - b * fa) / (fb - fa)
        x = np.where(np.isfinite(x), x, 0.5 * (a + b))
        fx = f(x)
        left = fx * fa > 0.0                          # root in [x, b]
        b_new = np.where(left, b, x)
        a_new = np.where(left, x, a)
        fb = np.where(left, np.where(side > 0, 0.5 * fb, fb), fx)
        fa = np.where(left, fx, np.where(side < 0, 0.5 * fa, fa))
        side = np.where(left, 1.0, -1.0)
        a, b = a_new, b_new
        done = fx == 0.0
        a, b = np.where(done, x, a), np.where(done, x, b)
    return np.where(np.abs(fa) < np.abs(fb), a, b)


def _check_count(name: str, v: Any, least: int, most: int, why: str) -> int:
    if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < least:
        raise GustError(f"{name} must be an integer >= {least}, got {v!r}")
    if v > most:
        raise GustError(f"{name} = {v} is more than {most}: {why}")
    return int(v)


def _check_rtol(v: Any) -> float:
    try:
        f = float(v)
    except (TypeError, ValueError):
        f = math.nan
    if isinstance(v, bool) or not (math.isfinite(f) and 1e-12 <= f < 0.5):
        raise GustError(f"h_rtol must be a relative tolerance in [1e-12, 0.5), got {v!r}")
    return f


def _select(system: GustSystem, outputs) -> list[int]:
    if outputs is None:
        return list(range(len(system.outputs)))
    if isinstance(outputs, str):
        outputs = [outputs]
    rows = [system.index(o) for o in outputs]
    if not rows:
        raise LoadsModelError("outputs is empty; name at least one of " + str(list(system.outputs)))
    check_distinct_outputs([system.outputs[r] for r in rows])
    return rows


def tuned_gust(model: Any, point: FlightPoint, *, outputs: Sequence[str] | None = None, H_range: Any = None,
               outside_rule: bool = False, n_grid: int = 24, h_rtol: float = 1e-4, moment_axes: Sequence[float] = (),
               moment_reference: float = 0.25) -> TunedGustResult:
    """Tuned 1-cosine gust loads of CS-25.341(a) at one flight point.

    Parameters
    ----------
    model : sysid.IdentificationResult, control.StateSpace, aeroelastic.MotionModel or loads.FlexibleSection
        A gust model with an input named ``"gust"`` (gust angle ``v_g / U`` at the leading edge, rad), in
        convective time ``c / U`` (a discrete one with ``dt = T``; see :func:`loads.system.gust_system`), at the
        point's Mach number.
    point : FlightPoint
    outputs : sequence of str, optional
        Outputs to search (default all); ``correlated`` holds all of them anyway.
    H_range : (float, float), optional
        Gust gradients (m); default the rule's 30 to 350 ft (9.144 to 106.68 m).
    outside_rule : bool
        Allow an ``H_range`` outside the rule's.
    n_grid : int
        Gradients of the first, geometric grid (default 24, 3 to :data:`MAX_GRID` = 2000).
    h_rtol : float
        Relative width of the final bracket of the critical ``H`` (default 1e-4).
    moment_axes : sequence of float
        Extra moment outputs about these axes (chords from the leading edge), see :func:`loads.system.gust_system`.
    moment_reference : float
        Axis of the model's ``Cm`` (default 0.25; a :class:`loads.FlexibleSection` uses its elastic axis).

    Returns
    -------
    TunedGustResult

    Raises
    ------
    GustError
        ``H_range`` outside the rule's without ``outside_rule=True``, or not ``0 < H_min <= H_max``; ``n_grid``
        not an integer in 3 .. :data:`MAX_GRID`; a bad ``h_rtol``; a flight point above 60 000 ft.
    LoadsModelError
        A model without a ``"gust"`` input, an unknown or repeated output, a NaN or inf in the model's matrices, an
        unstable model, a moment axis or ``moment_reference`` that is not a finite number, two moment axes that would
        share an output name.
    FlightPointError
        ``point`` not a :class:`FlightPoint`.

    Examples
    --------
    >>> tg = tuned_gust(rom, FlightPoint(mach=0.5, altitude_m=3000.0, chord_m=2.0))   # doctest: +SKIP
    >>> tg.peak["Cl"], tg.critical_H["Cl"]                                             # doctest: +SKIP
    """
    system = gust_system(model, point, moment_axes=moment_axes, moment_reference=moment_reference)
    n_grid = _check_count("n_grid", n_grid, 3, MAX_GRID,
                          "the first grid of H only brackets each local maximum for the golden-section search (which "
                          "refines it to h_rtol), and all its gusts' time responses are held in memory at once (1000 "
                          "took 3.4 GB with an order-8 ROM); the default 24, or a few hundred, suffices")
    h_rtol = _check_rtol(h_rtol)
    if not isinstance(outside_rule, (bool, np.bool_)):
        raise GustError(f"outside_rule must be True or False, got {outside_rule!r}")
    lo, hi = _h_range(H_range, bool(outside_rule), point.chord_m)
    point.reference_gust_velocity()                 # refuses a point above the rule's altitudes
    rows = _select(system, outputs)
    c = point.chord_m
    p = len(rows)

    def loads_at(H, r):
        v, _, _ = peak_over_time(system, H / c, r)
        return v * point.gust_angle(H)

    Hg = np.geomspace(lo, hi, n_grid) if hi > lo else np.full(1, lo)
    F = loads_at(np.repeat(Hg, p), np.tile(rows, Hg.size)).reshape(Hg.size, p)
    seen_H = [np.repeat(Hg, p)]
    seen_j = [np.tile(np.arange(p), Hg.size)]
    seen_F = [F.ravel()]
    # brackets around every local maximum within 2 % of the best
    b_lo, b_hi, b_j = [], [], []
    for j in range(p):
        f = F[:, j]
        if Hg.size == 1:
            break
        top = f.max()
        for k in range(Hg.size):
            left = f[k - 1] if k > 0 else -np.inf
            right = f[k + 1] if k < Hg.size - 1 else -np.inf
            if f[k] >= left and f[k] >= right and f[k] >= 0.98 * top:
                b_lo.append(Hg[max(k - 1, 0)])
                b_hi.append(Hg[min(k + 1, Hg.size - 1)])
                b_j.append(j)
    width = np.zeros(p)
    if b_j:
        b_lo, b_hi, b_j = np.array(b_lo), np.array(b_hi), np.array(b_j)
        need = np.log(h_rtol * b_lo / (b_hi - b_lo)) / np.log(_GR)
        steps = int(max(np.ceil(need.max()), 1))
        r_b = np.array(rows)[b_j]

        def f_H(x):
            v = loads_at(x, r_b)
            seen_H.append(x)
            seen_j.append(b_j)
            seen_F.append(v)
            return v

        _, _, w = golden_max(f_H, b_lo, b_hi, steps)
        for j in range(p):
            sel = b_j == j
            width[j] = w[sel].max() if sel.any() else 0.0
    allH, allj, allF = np.concatenate(seen_H), np.concatenate(seen_j), np.concatenate(seen_F)
    names = [system.outputs[r] for r in rows]
    peak, crit, sign, tpk, corr, dim, units, htol = {}, {}, {}, {}, {}, {}, {}, {}
    times, hist, gusts = {}, {}, {}
    for j, name in enumerate(names):
        sel = np.flatnonzero(allj == j)
        best = sel[np.argmax(allF[sel])]
        H = float(allH[best])
        amp = float(point.gust_angle(H))
        v, t_star, signed = peak_over_time(system, np.array([H / c]), [rows[j]])
        sgn = 1.0 if signed[0] >= 0 else -1.0
        yall = outputs_at(system, np.array([H / c]), t_star)[0] * amp * sgn
        peak[name] = float(v[0] * amp)
        crit[name] = H
        sign[name] = int(sgn)
        tpk[name] = float(t_star[0] * point.time_scale)
        corr[name] = {o: float(yall[i]) for i, o in enumerate(system.outputs)}
        dim[name] = peak[name] * float(system.scale[rows[j]])
        units[name] = system.units[rows[j]]
        htol[name] = float(width[j])
        s_end = max(2.0 * H / c + float(initial_tail(system, np.array([H / c]))[0]), 1.5 * float(t_star[0]))
        step = float(_sample_step(system, np.array([H / c]))[0])
        n = int(min(max(np.ceil(s_end / step) + 1, 400), 4000))
        s = np.linspace(0.0, s_end, n)
        from .one_minus_cosine import gust_input

        times[name] = _ro(s * point.time_scale)
        hist[name] = _ro((outputs_at(system, np.full(n, H / c), s) * amp * sgn).T)
        gusts[name] = _ro(gust_input(H / c, s) * amp * sgn * point.tas)
    return TunedGustResult(tuple(names), peak, crit, sign, tpk, corr, dim, units, htol, _ro(Hg), _ro(F.T), times,
                           hist, gusts, tuple(system.outputs), int(np.unique(allH).size), _ro(np.unique(allH)), point,
                           system)


def _ro(a):
    a = np.array(a)
    a.setflags(write=False)
    return a
