"""Flutter and divergence of the typical section as an eigenvalue problem over speed.

At each speed index ``V`` the coupled model (:func:`aeroelastic.coupled_model`) is one LTI system; its
eigenvalues (computed from :func:`aeroelastic.coupling.state_matrix`, the same matrix in closed form, which is
cheaper to build than through python-control in a sweep; a test checks that the two agree) ``lambda`` (units of
``omega_alpha``) give the root locus. The section is stable while every ``Re lambda < 0``; flutter
(``Im lambda != 0``) or divergence (a real root) is the first speed where the largest real part crosses zero.
The crossing is bracketed on the speed grid and refined with :func:`scipy.optimize.brentq` on
``max Re lambda(V)`` -- no p-k iteration: the aerodynamic model is already a state-space model valid for any
``lambda``. The section's structural damping (:attr:`TypicalSection.damping`, modal ratios) enters the state
matrix, so a damped section flutters where a root's total damping (aerodynamic plus structural) reaches zero,
above the undamped speed when the flutter mode's aerodynamic damping falls with speed (the V-g reading: the
structural ``g = 2 zeta`` is what the aerodynamic ``g`` must exceed).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy import optimize

from sysid.arrays import read_only

from .coupling import MAX_SPEED, as_motion_model, check_axis, state_matrix
from .errors import SpeedError
from .fit import MotionModel
from .section import TypicalSection, check_section

__all__ = ["FlutterResult", "flutter", "divergence_speed", "root_locus_response", "MAX_SPEED_POINTS"]


@dataclass(frozen=True)
class FlutterResult:
    """Flutter of a typical section from a state-space aerodynamic model.

    Attributes
    ----------
    speed_index : float
        ``U / (b omega_alpha)`` at the first instability (``nan`` when none was found on the grid).
    flutter_speed_index : float
        ``speed_index / sqrt(mu)`` (Isogai's ``V_f``).
    frequency_ratio : float
        ``omega / omega_alpha`` of the critical root at the crossing (0 for divergence).
    kind : str
        ``"flutter"``, ``"divergence"`` or ``"none"``.
    found : bool
    reduced_frequency : float
        ``k = omega b / U = frequency_ratio / speed_index`` at flutter.
    speeds : ndarray, shape (N,)
        Speed indices of the root locus (arrays of the result are read-only).
    eigenvalues : ndarray, complex, shape (N, n)
        All eigenvalues per speed (``omega_alpha`` units), ordered along continuous branches (each column
        follows one root as the speed grows).
    modes : ndarray, int, shape (2,)
        Columns of ``eigenvalues`` that start (at the lowest speed) as the plunge-like and pitch-like
        structural modes (upper half plane).
    section : TypicalSection
    model : MotionModel
        The aerodynamic model used.
    """

    speed_index: float
    flutter_speed_index: float
    frequency_ratio: float
    kind: str
    found: bool
    reduced_frequency: float
    speeds: np.ndarray = field(repr=False)
    eigenvalues: np.ndarray = field(repr=False)
    modes: np.ndarray = field(repr=False)
    section: TypicalSection = field(repr=False)
    model: MotionModel = field(repr=False)

    @property
    def frequency(self) -> np.ndarray:
        """``Im lambda`` per speed and branch, shape (N, n) (``omega / omega_alpha``)."""
        return self.eigenvalues.imag

    @property
    def damping(self) -> np.ndarray:
        """Damping ratio ``zeta = -Re lambda / |lambda|`` per speed and branch, shape (N, n)."""
        lam = self.eigenvalues
        return -lam.real / np.maximum(np.abs(lam), np.finfo(float).tiny)

    @property
    def g(self) -> np.ndarray:
        """V-g damping ``g = 2 Re lambda / |Im lambda|`` (positive = unstable), shape (N, n); ``nan`` for real roots."""
        lam = self.eigenvalues
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(np.abs(lam.imag) > 1e-9, 2 * lam.real / np.abs(lam.imag), np.nan)

    def summary(self) -> str:
        """One line: kind, speed indices and frequency ratio."""
        if not self.found:
            return f"no instability for speed index {self.speeds[0]:.4g} .. {self.speeds[-1]:.4g}"
        return (f"{self.kind} at U/(b w_alpha) = {self.speed_index:.5f} (V_f = {self.flutter_speed_index:.5f}), "
                f"w/w_alpha = {self.frequency_ratio:.5f}, k = {self.reduced_frequency:.5f}")



def _eigs(model: MotionModel, section: TypicalSection, V: float) -> np.ndarray:
    return np.linalg.eigvals(state_matrix(model, section, V))


def _track(E: np.ndarray) -> np.ndarray:
    """Reorder each row of ``E`` (N, n) to follow continuous branches (Hungarian matching of successive rows)."""
    from scipy.optimize import linear_sum_assignment

    out = np.array(E, copy=True)
    for i in range(1, out.shape[0]):
        prev = out[i - 1]
        # predict linearly when possible
        pred = prev if i < 2 else 2 * prev - out[i - 2]
        cost = np.abs(pred[:, None] - out[i][None, :])
        _, col = linear_sum_assignment(cost)
        out[i] = out[i][col]
    return out


def root_locus_response(aero: Any, section: TypicalSection, speeds: Any, *, order: int = 4) -> tuple[np.ndarray, np.ndarray]:
    """Eigenvalues of the coupled model over speed.

    Parameters
    ----------
    aero : MotionModel or sysid.FrequencyResponse
    section : TypicalSection
    speeds : array_like, shape (N,)
        Positive, finite, strictly increasing speed indices ``U / (b omega_alpha)`` (at least 2, at most :data:`MAX_SPEED_POINTS`; one row or column).
    order : int
        Lag roots of the fit when ``aero`` is data (default 4).

    Returns
    -------
    speeds : ndarray, shape (N,)
    eigenvalues : ndarray, complex, shape (N, n)
        Tracked along branches (see :attr:`FlutterResult.eigenvalues`).

    Raises
    ------
    SpeedError
        Unusable speed grid.
    SectionError
        ``section`` not a :class:`TypicalSection`.
    AeroModelError
        ``aero`` neither a model nor data.
    FitError
        Data that cannot be fitted (see :func:`fit_motion`).
    """
    check_section(section)
    check_axis(aero, section)
    model = as_motion_model(aero, order)
    V = _check_speeds(speeds)
    E = np.array([_eigs(model, section, v) for v in V])
    return V, _track(E)


MAX_SPEED_POINTS = 100_000
"""Most speeds of a root locus: one eigenvalue problem and one assignment problem each (about 0.1 ms together
for the 8 - 12 states of a section with 4 lag roots), so a grid this size takes seconds; a larger one buys no
accuracy, since :func:`flutter` refines the crossing by root finding between two grid speeds."""


def _check_speeds(speeds: Any) -> np.ndarray:
    """``speeds`` as a 1-D float array, or :class:`SpeedError` saying what is wrong with it."""
    try:
        V = np.asarray(speeds, dtype=float)
    except (TypeError, ValueError):
        raise SpeedError(f"speeds must be an array of speed indices, got {speeds!r}") from None
    if V.ndim > 1 and sum(d > 1 for d in V.shape) > 1:
        raise SpeedError(f"speeds must be one-dimensional (a grid of speed indices), got an array of shape {V.shape}; "
                         "pass one row, or call flutter once per row")
    V = V.reshape(-1)
    if V.size > MAX_SPEED_POINTS:
        raise SpeedError(f"speeds has {V.size} points, more than MAX_SPEED_POINTS = {MAX_SPEED_POINTS}: the crossing "
                         "is refined by root finding between grid speeds, so a few hundred points suffice")
    if V.size < 2 or np.any(~np.isfinite(V)) or np.any(V <= 0) or np.any(np.diff(V) <= 0):
        raise SpeedError(
            "speeds must hold at least 2 positive, finite, strictly increasing speed indices U/(b omega_alpha), e.g. "
            "np.linspace(0.05, 3 * sqrt(mu), 200)"
        )
    if V[-1] > MAX_SPEED:
        raise SpeedError(f"speeds go up to {V[-1]:g}, above MAX_SPEED = {MAX_SPEED:g} (speed indices U/(b omega_alpha) "
                         "of real sections are of order 1 - 10)")
    return V


def _check_tol(tol: Any) -> float:
    """``tol`` of :func:`flutter` as a float, or :class:`SpeedError` unless it is positive and finite."""
    try:
        t = float(tol)
    except (TypeError, ValueError):
        t = math.nan
    if isinstance(tol, bool) or not (math.isfinite(t) and t > 0.0):
        raise SpeedError(f"tol must be a positive, finite growth rate (Re lambda above which a root counts as "
                         f"unstable, omega_alpha units; default 1e-9), got {tol!r}")
    return t


def flutter(aero: Any, section: TypicalSection, speeds: Any = None, *, order: int = 4, tol: float = 1e-9,
            **fit_kw) -> FlutterResult:
    """Flutter (or divergence) speed of the typical section from an aerodynamic model of its motion.

    Parameters
    ----------
    aero : sysid.FrequencyResponse or MotionModel
        Inputs ``["plunge", "pitch"]`` (``h / c`` up; rad nose up about the elastic axis), outputs ``["Cl", "Cm"]``
        (``Cm`` about the elastic axis), continuous ``omega`` in ``U / c``; fitted with
        :func:`aeroelastic.fit_motion` (``order`` lag roots, ``fit_kw``) when data are given.
    section : TypicalSection
    speeds : array_like, shape (N,), optional
        Speed indices ``U / (b omega_alpha)`` of the root locus (one row or column), 2 to :data:`MAX_SPEED_POINTS`, positive, finite and
        strictly increasing; default ``np.linspace(0.02, 3, 301) * sqrt(mu)`` (flutter speed indices ``V_f`` up
        to 3, ``N = 301``).
    order : int
        Number of lag roots of the fit (default 4; used only when ``aero`` is data).
    tol : float
        A root counts as unstable when ``Re lambda > tol`` (``omega_alpha`` units, default 1e-9); conservative
        models (no aerodynamic damping) keep ``Re lambda`` at round-off, not exactly 0.
    **fit_kw
        Options of :func:`aeroelastic.fit_motion` (``gust_order``, ``T``, ``optimise``, ``poles``: the names in
        :data:`aeroelastic.coupling.FIT_OPTIONS`), used when ``aero`` is data; checked against those names even
        when ``aero`` is a :class:`MotionModel` (then they are otherwise ignored).

    Returns
    -------
    FlutterResult
        ``found=False`` (with a ``RuntimeWarning``) when the section is stable over the whole grid, or already
        unstable at its first speed.

    Raises
    ------
    SpeedError
        Unusable speed grid, or ``tol`` not positive and finite.
    SectionError
        ``section`` not a :class:`TypicalSection`.
    AeroModelError
        ``aero`` neither a model nor data, or a fit option not in :data:`aeroelastic.coupling.FIT_OPTIONS`.
    FitError
        Data that cannot be fitted (see :func:`fit_motion`).
    """
    check_section(section)
    check_axis(aero, section)
    tol = _check_tol(tol)
    model = as_motion_model(aero, order, **fit_kw)
    if speeds is None:
        speeds = np.linspace(0.02, 3.0, 301) * math.sqrt(section.mu)
    V = _check_speeds(speeds)
    E = np.array([_eigs(model, section, v) for v in V])
    E = _track(E)
    # the structural branches: the two roots with Im > 0 closest to the in-vacuo frequencies at the first speed
    wn = section.natural_frequencies()
    first = E[0]
    modes = []
    for w in wn:
        cand = [j for j in np.argsort(np.abs(first - 1j * w)) if j not in modes]
        modes.append(int(cand[0]))
    modes = np.array(modes)

    fmax = E.real.max(axis=1) - tol
    unstable = np.flatnonzero(fmax > 0)
    nan = float("nan")
    if unstable.size == 0 or unstable[0] == 0:
        why = ("the section is stable over the whole grid; extend speeds" if unstable.size == 0 else
               "the section is already unstable at the first speed; start speeds lower")
        warnings.warn(f"no stability crossing found: {why}", RuntimeWarning, stacklevel=2)
        return FlutterResult(nan, nan, nan, "none", False, nan, read_only(V), read_only(E), read_only(modes), section,
                             model)
    i = unstable[0]

    def f(v):
        return _eigs(model, section, v).real.max() - tol

    Vf = optimize.brentq(f, V[i - 1], V[i], xtol=1e-12, rtol=1e-12)
    # the critical root: the most unstable one just past the crossing (at the crossing itself a divergent root and
    # an undamped oscillatory one can tie on Re = 0)
    lam = _eigs(model, section, Vf * (1 + 1e-8))
    crit = lam[np.argmax(lam.real)]
    fr = abs(crit.imag)
    kind = "flutter" if fr > 1e-6 else "divergence"
    if kind == "divergence":
        fr = 0.0
    _warn_extrapolation(model, 2.0 * fr / Vf if kind == "flutter" else None)
    return FlutterResult(float(Vf), float(Vf / math.sqrt(section.mu)), float(fr), kind, True, float(fr / Vf),
                         read_only(V), read_only(E), read_only(modes), section, model)


FIT_ERROR_WARNING = 0.1
"""Worst relative error of the motion fit over its data above which :func:`flutter` warns (an order-0 fit of
Theodorsen's function, 0.43 off, put the flutter speed 19 % low; the default 4 lag roots fit it to 2e-3)."""


def _warn_extrapolation(model, omega_f) -> None:
    """Warn when the flutter frequency ``omega_f`` (U/c) lies outside the fitted data's positive frequencies (the
    model is extrapolated there: data from omega 2 to 4 put the flutter speed 8.5 % low, measured) or the fit is
    poor (:data:`FIT_ERROR_WARNING`)."""
    w = np.asarray(getattr(model, "omega", np.zeros(0)), dtype=float)
    w = w[np.isfinite(w) & (w > 0)]
    if omega_f is not None and w.size and not (w.min() <= omega_f <= w.max()):
        warnings.warn(f"the flutter frequency omega = {omega_f:.4g} (U/c; k = {omega_f / 2:.4g}) lies outside the "
                      f"data's frequencies ({w.min():.4g} to {w.max():.4g}), where the motion model is extrapolated; "
                      "give data that bracket it", RuntimeWarning, stacklevel=3)
    err = float(getattr(model, "max_error", float("nan")))
    if np.isfinite(err) and err > FIT_ERROR_WARNING:
        warnings.warn(f"the motion fit is {err:.2g} off its data at worst (relative); the flutter speed inherits "
                      "that error: use more lag roots (order) or check the data", RuntimeWarning, stacklevel=3)


def divergence_speed(aero: Any, section: TypicalSection, *, order: int = 4) -> float:
    """Static divergence speed index from the static derivatives alone.

    Static equilibrium ``(Ks - V^2 diag(1, 2) / (pi mu) M0) q = 0``: ``V^2`` is an eigenvalue of the pencil
    ``(Ks, diag(1, 2) M0 / (pi mu))``; the smallest positive real one is returned (``inf`` if none). For a flat
    plate ``M0 = [[0, 2 pi], [0, pi (a + 1/2)]]`` and this is ``V_D = sqrt(mu r_alpha2 / (1 + 2 a))``.

    Parameters
    ----------
    aero : sysid.FrequencyResponse or MotionModel
        Aerodynamic model of the motion, as for :func:`flutter` (only its static matrix ``M0`` is used); data
        are fitted with :func:`aeroelastic.fit_motion` (``order`` lag roots, default options).
    section : TypicalSection
    order : int
        Number of lag roots of the fit when ``aero`` is data (default 4).

    Returns
    -------
    float
        Divergence speed index ``V_D = U / (b omega_alpha)``; ``inf`` when the pencil has no positive real
        eigenvalue (no static divergence).

    Raises
    ------
    SectionError
        ``section`` not a :class:`TypicalSection`.
    AeroModelError
        ``aero`` neither a model nor data, or data missing channels (see :func:`fit_motion`).
    FitError
        Data that cannot be fitted (see :func:`fit_motion`).
    """
    from scipy.linalg import eigvals

    check_section(section)
    check_axis(aero, section)
    model = as_motion_model(aero, order)
    lam = eigvals(section.stiffness_matrix, section.load_matrix @ model.M0)
    lam = lam[np.isfinite(lam)]
    pos = lam.real[(np.abs(lam.imag) <= 1e-9 * np.maximum(1.0, np.abs(lam))) & (lam.real > 0)]
    return float(np.sqrt(pos.min())) if pos.size else float("inf")
