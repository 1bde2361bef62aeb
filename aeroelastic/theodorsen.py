"""Analytic references: incompressible thin-aerofoil theory (Theodorsen, Sears, Wagner, Kussner).

Everything here is textbook material, written out so that the package's coupled state-space path can be
checked against something it does not share code with:

- :func:`theodorsen_function` and :func:`sears_function` (frequency domain, from Hankel/Bessel functions);
- :func:`theodorsen_motion` / :func:`theodorsen_frf`: loads of a plunging and pitching flat plate in the
  project's conventions (the ``aero`` data :func:`aeroelastic.flutter` and :func:`aeroelastic.gust_response`
  take);
- :func:`flutter_determinant`: the classical flutter solution of Theodorsen's equations (k-method: the
  determinant root in ``(k, omega)``), written in Theodorsen's own notation (h positive down);
- :func:`jones_section_model`: the flexible section driven by a gust in the time domain, with R. T. Jones'
  exponential approximations of Wagner's and Kussner's indicial functions (a textbook model that does not
  go through any frequency fit).

Conventions of the project (see ``docs/aeroelastic.md``): lengths in chords, convective time ``s = t U / c``,
``omega`` in ``U / c``, ``exp(+i omega t)``, so the reduced frequency is ``k = omega b / U = omega / 2``
(``b = c / 2``). Plunge ``h / c`` positive UP, pitch ``alpha`` nose up about the elastic axis at ``a``
semichords aft of mid-chord, ``Cl`` up, ``Cm`` nose up about the elastic axis, ``Cl = L / (q c)``,
``Cm = M / (q c^2)``, ``q = rho U^2 / 2``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy import optimize, special

from .errors import AeroModelError, SectionError, SpeedError
from .section import TypicalSection, check_section

MAX_K_POINTS = 100_000
"""Most grid points ``n_k`` of :func:`flutter_determinant`'s search (one quadratic solve each)."""

__all__ = [
    "theodorsen_function",
    "sears_function",
    "theodorsen_motion",
    "theodorsen_gust",
    "theodorsen_frf",
    "flutter_determinant",
    "MAX_K_POINTS",
    "DeterminantFlutter",
    "theodorsen_jones",
    "sears_jones",
    "jones_frf",
    "wagner_jones",
    "kussner_jones",
    "jones_section_model",
    "WAGNER_JONES",
    "KUSSNER_JONES",
]

#: R. T. Jones' approximation of Wagner's function, ``phi(tau) = 1 - sum A_i exp(-b_i tau)``, ``tau = U t / b``
#: (semichords): ``((A_1, b_1), (A_2, b_2))``.
WAGNER_JONES = ((0.165, 0.0455), (0.335, 0.3))
#: R. T. Jones' approximation of Kussner's function, ``psi(tau) = 1 - sum A_i exp(-b_i tau)``, ``tau = U t / b``.
KUSSNER_JONES = ((0.236, 0.058), (0.513, 0.364), (0.171, 2.42))


def _as_k(k: Any) -> np.ndarray:
    try:
        kk = np.asarray(k, dtype=float)
    except (TypeError, ValueError):
        raise SpeedError(f"reduced frequencies k must be real numbers, got {k!r}") from None
    if np.any(~np.isfinite(kk)) or np.any(kk < 0):
        raise SpeedError(f"reduced frequencies k must be finite and >= 0, got {k!r}")
    return kk


def theodorsen_function(k: Any) -> np.ndarray:
    """Theodorsen's function ``C(k) = H1(2)(k) / (H1(2)(k) + i H0(2)(k))`` for ``exp(+i omega t)``.

    Parameters
    ----------
    k : array_like, shape (...)
        Reduced frequency ``k = omega b / U >= 0`` (``= omega / 2`` with ``omega`` in ``U / c``), finite; any shape.

    Returns
    -------
    C : ndarray, complex, shape (...)
        The shape of ``k``. ``C(0) = 1`` (the limit), ``C -> 1/2`` as ``k -> inf``; ``Im C < 0`` for ``k > 0``.

    Raises
    ------
    SpeedError
        A ``k`` that is negative, not finite or not numeric.
    """
    kk = _as_k(k)
    out = np.ones(kk.shape, dtype=complex)
    pos = kk > 0
    h1 = special.hankel2(1, kk[pos])
    h0 = special.hankel2(0, kk[pos])
    out[pos] = h1 / (h1 + 1j * h0)
    return out


def sears_function(k: Any, reference: str = "midchord") -> np.ndarray:
    """Sears' function: lift of a flat plate in a sinusoidal vertical gust, ``Cl = 2 pi (w / U) S``.

    ``S(k) = [J0(k) - i J1(k)] C(k) + i J1(k)`` (Sears 1941; Bisplinghoff, Ashley & Halfman, Aeroelasticity,
    1955, sec. 5-7), with the gust velocity ``w`` measured at mid-chord.

    Parameters
    ----------
    k : array_like, shape (...)
        Reduced frequency ``omega b / U >= 0``, finite; any shape.
    reference : {"midchord", "leading_edge"}
        Where the gust is measured. The project's gust input is at the leading edge (``x_ref = 0``); the
        gust reaches mid-chord ``b / U`` later, so ``S_le = S exp(-i k)``.

    Returns
    -------
    S : ndarray, complex, shape (...)
        The shape of ``k``; ``S(0) = 1``.

    Raises
    ------
    SpeedError
        A ``k`` that is negative, not finite or not numeric.
    AeroModelError
        ``reference`` not ``"midchord"`` or ``"leading_edge"``.
    """
    kk = _as_k(k)
    S = (special.j0(kk) - 1j * special.j1(kk)) * theodorsen_function(kk) + 1j * special.j1(kk)
    if reference == "midchord":
        return S
    if reference == "leading_edge":
        return S * np.exp(-1j * kk)
    raise AeroModelError(f"reference must be 'midchord' or 'leading_edge', got {reference!r}")


def _flag(name: str, value: Any) -> bool:
    """``value`` if it is a bool, else :class:`AeroModelError` (a truthy string such as ``"no"`` would turn it on)."""
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    raise AeroModelError(f"{name} must be True or False, got {value!r}")


def _circulation(circulation: Any):
    """``circulation`` if it is None or callable, else :class:`AeroModelError`."""
    if circulation is None or callable(circulation):
        return circulation
    raise AeroModelError(f"circulation must be a callable k -> C(k) (e.g. theodorsen_jones) or None, got "
                         f"{circulation!r}")


def _check_a(a: Any) -> float:
    try:
        af = float(a)
    except (TypeError, ValueError):
        raise SectionError(f"a (elastic axis aft of mid-chord, semichords) must be a number, got {a!r}") from None
    if not np.isfinite(af):
        raise SectionError(f"a must be finite, got {a!r}")
    return af


def _as_omega(omega: Any) -> np.ndarray:
    try:
        w = np.asarray(omega, dtype=float)
    except (TypeError, ValueError):
        raise AeroModelError(f"omega must be an array of real frequencies (U/c units), got {omega!r}") from None
    if w.ndim > 1:
        raise AeroModelError(f"omega must be 1-D (one frequency grid), got shape {w.shape}; flatten it yourself if "
                             "that is what you mean")
    w = w.reshape(-1)
    if w.size == 0 or np.any(~np.isfinite(w)) or np.any(w < 0):
        raise AeroModelError(
            "omega must be a non-empty 1-D array of finite frequencies >= 0 (U/c units); the motion response is "
            f"infinite at omega = inf, got {omega!r}"
        )
    return w


def theodorsen_motion(omega: Any, a: float, quasi_steady: bool = False, circulation: Any = None) -> np.ndarray:
    """Lift and moment of a plunging and pitching flat plate (Theodorsen), per unit ``h / c`` and ``alpha``.

    Theodorsen's loads (NACA Report 496, 1935; Bisplinghoff, Ashley & Halfman 1955, Eqs. 5-308, 5-309;
    Hodges & Pierce, Introduction to Structural Dynamics and Aeroelasticity, 2011, Eqs. 5.319-5.320), with
    Theodorsen's plunge ``h_T`` positive DOWN and pitch ``theta`` nose up about ``x = a b``::

        L = pi rho b^2 (h_T'' + U theta' - b a theta'') + 2 pi rho U b C(k) [h_T' + U theta + b (1/2 - a) theta']
        M = pi rho b^2 [b a h_T'' - U b (1/2 - a) theta' - b^2 (1/8 + a^2) theta'']
            + 2 pi rho U b^2 (a + 1/2) C(k) [h_T' + U theta + b (1/2 - a) theta']

    In the project's variables ``h / c`` (UP, so ``h_T = -2 b (h / c)``), ``alpha = theta``, convective time
    (``d/dt = (U / c) d/ds``), ``Cl = L / (rho U^2 b)``, ``Cm = M / (2 rho U^2 b^2)`` and the reduced Laplace
    variable ``p = s_c / 2 = i k`` (``s_c = i omega``, ``omega`` in ``U / c``)::

        Cl_h = -2 pi p^2 - 4 pi C p
        Cl_a =  pi (p - a p^2) + 2 pi C (1 + (1/2 - a) p)
        Cm_h = -pi a p^2 - 2 pi (a + 1/2) C p
        Cm_a = -(pi / 2) [(1/2 - a) p + (1/8 + a^2) p^2] + pi (a + 1/2) C (1 + (1/2 - a) p)

    Checks: ``Cl_a(0) = 2 pi``, ``Cm_a(0) = pi (a + 1/2)`` (lift at the quarter chord), and a plunge velocity
    up acts as an incidence ``-d(h/c)/ds`` (``Cl_h ~ -2 pi s_c`` as ``omega -> 0``).

    Parameters
    ----------
    omega : array_like, shape (K,)
        Frequencies in ``U / c`` (finite, ``>= 0``).
    a : float
        Elastic axis aft of mid-chord, semichords.
    quasi_steady : bool
        Use ``C(k) = 1`` (quasi-steady circulatory loads, apparent mass kept).
    circulation : callable, optional
        ``k -> C`` replacing Theodorsen's function (e.g. :func:`theodorsen_jones`).

    Returns
    -------
    H : ndarray, complex, shape (2, 2, K)
        Outputs ``[Cl, Cm]`` (``Cm`` about the elastic axis), inputs ``[plunge, pitch]``.
    """
    a = _check_a(a)
    w = _as_omega(omega)
    quasi_steady = _flag("quasi_steady", quasi_steady)
    circulation = _circulation(circulation)
    p = 0.5j * w
    if quasi_steady:
        C = np.ones_like(p)
    elif circulation is not None:
        C = np.asarray(circulation(w / 2.0), dtype=complex)
    else:
        C = theodorsen_function(w / 2.0)
    H = np.empty((2, 2, w.size), dtype=complex)
    H[0, 0] = -2 * np.pi * p**2 - 4 * np.pi * C * p
    H[0, 1] = np.pi * (p - a * p**2) + 2 * np.pi * C * (1 + (0.5 - a) * p)
    H[1, 0] = -np.pi * a * p**2 - 2 * np.pi * (a + 0.5) * C * p
    H[1, 1] = -0.5 * np.pi * ((0.5 - a) * p + (0.125 + a**2) * p**2) + np.pi * (a + 0.5) * C * (1 + (0.5 - a) * p)
    return H


def theodorsen_gust(omega: Any, a: float) -> np.ndarray:
    """Sears gust loads per unit gust angle ``u = v_g(x = 0) / U`` (gust at the leading edge), about ``a``.

    ``Cl = 2 pi S(k) exp(-i k)``; the gust lift of a flat plate acts at the quarter chord, so
    ``Cm_ea = Cl (a + 1/2) / 2`` (the elastic axis is ``(a + 1/2) / 2`` chords aft of it).

    Parameters
    ----------
    omega : array_like, shape (K,)
        Frequencies in ``U / c`` (finite, ``>= 0``, at least one; flattened), so ``k = omega / 2``.
    a : float
        Elastic axis aft of mid-chord, semichords (the moment axis of ``Cm``).

    Returns
    -------
    H : ndarray, complex, shape (2, 1, K)
        Outputs ``[Cl, Cm]``, input ``[gust]`` (per unit gust angle, rad).

    Raises
    ------
    AeroModelError
        ``omega`` empty, not finite or negative.
    SectionError
        ``a`` not a finite number.
    """
    a = _check_a(a)
    w = _as_omega(omega)
    cl = 2 * np.pi * sears_function(w / 2.0, reference="leading_edge")
    return np.stack([cl, cl * (a + 0.5) / 2.0])[:, None, :]


def theodorsen_frf(omega: Any, a: float, gust: bool = False, quasi_steady: bool = False, T: float | None = None):
    """Theodorsen (and Sears) loads as a :class:`sysid.FrequencyResponse` in the ``aero`` layout.

    Parameters
    ----------
    omega : array_like, shape (K,)
        Frequencies in ``U / c`` (finite, ``>= 0``; include ``0`` so that a fit keeps the static derivatives).
    a : float
        Elastic axis (semichords aft of mid-chord); ``Cm`` is about it and pitch is about it.
    gust : bool
        Prepend the ``"gust"`` input (Sears, gust angle at the leading edge).
    quasi_steady : bool
        ``C(k) = 1`` for the motion columns.
    T : float, optional
        Sampling period passed to :meth:`sysid.FrequencyResponse.from_continuous`.

    Returns
    -------
    sysid.FrequencyResponse
        Outputs ``["Cl", "Cm"]``; inputs ``["plunge", "pitch"]`` or ``["gust", "plunge", "pitch"]``.
    """
    import sysid

    gust = _flag("gust", gust)
    H = theodorsen_motion(omega, a, quasi_steady=quasi_steady)
    inputs = ["plunge", "pitch"]
    if gust:
        H = np.concatenate([theodorsen_gust(omega, a), H], axis=1)
        inputs = ["gust"] + inputs
    md = {"source": "aeroelastic.theodorsen", "a": float(a), "quasi_steady": bool(quasi_steady)}
    return sysid.FrequencyResponse.from_continuous(H, _as_omega(omega), T, inputs=inputs, outputs=["Cl", "Cm"],
                                                   metadata=md)


# --------------------------------------------------------------------------------------------------
# classical flutter determinant
# --------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class DeterminantFlutter:
    """Classical flutter solution of Theodorsen's equations.

    Attributes
    ----------
    speed_index : float
        ``U / (b omega_alpha)`` at flutter.
    flutter_speed_index : float
        ``speed_index / sqrt(mu)``.
    frequency_ratio : float
        ``omega / omega_alpha`` at flutter.
    k : float
        Reduced frequency ``omega b / U`` at flutter.
    """

    speed_index: float
    flutter_speed_index: float
    frequency_ratio: float
    k: float


def _theodorsen_det_quadratic(k: float, sec, C: complex) -> np.ndarray:
    """Roots ``X = (omega_alpha / omega)^2`` of the flutter determinant at reduced frequency ``k``.

    Theodorsen's notation: ``h_T / b`` (DOWN) and ``theta``; both equations divided by ``pi rho b^3 omega^2``
    (lift) and ``pi rho b^4 omega^2`` (moment); ``U / (b omega) = 1 / k``.
    """
    mu, a, xa, r2, sig = sec.mu, sec.a, sec.x_alpha, sec.r_alpha2, sec.omega_ratio
    ik = 1j / k
    w = (2 * C / k)  # circulatory factor
    # aerodynamic matrix (lift row positive up, moment row nose up), acting on [h_T/b, theta]
    Lh = -1.0 + w * 1j
    La = ik + a + w * (1.0 / k + (0.5 - a) * 1j)
    Mh = -a + w * (a + 0.5) * 1j
    Ma = -ik * (0.5 - a) + (0.125 + a**2) + w * (a + 0.5) * (1.0 / k + (0.5 - a) * 1j)
    # structure:  mu [-h - xa th + sig^2 X h] = -L ;  mu [-r2 th - xa h + r2 X th] = M
    # rows: [mu(sig^2 X - 1) + Lh, -mu xa + La ; -mu xa - Mh, mu r2 (X - 1) - Ma] (h, th) = 0
    # determinant as a quadratic in X: (p1 X + p0)(q1 X + q0) - c12 c21
    p1, p0 = mu * sig**2, -mu + Lh
    q1, q0 = mu * r2, -mu * r2 - Ma
    c12, c21 = -mu * xa + La, -mu * xa - Mh
    return np.roots([p1 * q1, p1 * q0 + p0 * q1, p0 * q0 - c12 * c21])


def flutter_determinant(section, quasi_steady: bool = False, k_range: tuple[float, float] = (0.02, 3.0),
                        n_k: int = 400, circulation: Any = None) -> DeterminantFlutter:
    """Flutter of the typical section from Theodorsen's equations by the classical k-method.

    At each reduced frequency ``k`` the 2x2 flutter determinant (Theodorsen's notation, h positive down,
    see :func:`theodorsen_motion` for the loads) is a quadratic in ``X = (omega_alpha / omega)^2 (1 + i g)``;
    flutter is where a root is real (``g = 0``). The sign changes of ``Im X`` over a ``k`` grid are refined with
    :func:`scipy.optimize.brentq`; the lowest speed ``U / (b omega_alpha) = 1 / (k sqrt(X))`` is returned.

    Parameters
    ----------
    section : TypicalSection
    quasi_steady : bool
        ``C(k) = 1``.
    circulation : callable, optional
        ``k -> C`` replacing Theodorsen's function (e.g. :func:`theodorsen_jones`).
    k_range : (float, float)
        Reduced-frequency interval searched.
    n_k : int
        Grid points (geometric) for bracketing.

    Returns
    -------
    DeterminantFlutter

    Raises
    ------
    SpeedError
        No flutter in ``k_range``; ``k_range`` not two positive finite reduced frequencies or ``n_k`` not a whole
        number >= 2.
    SectionError
        ``section`` not a :class:`TypicalSection`.
    """
    check_section(section)
    try:
        k_lo, k_hi = (float(k) for k in k_range)
        ok = all(np.isfinite(k) and k > 0.0 for k in (k_lo, k_hi)) and k_lo != k_hi
    except (TypeError, ValueError):
        ok = False
    if not ok:
        raise SpeedError(f"k_range must be two distinct positive finite reduced frequencies (the search grid is "
                         f"geometric; k = 0 is the steady limit, start at a small k such as 0.02), got {k_range!r}")
    if isinstance(n_k, bool) or not isinstance(n_k, (int, np.integer)) or n_k < 2:
        raise SpeedError(f"n_k must be a whole number >= 2 (grid points in k_range; default 400), got {n_k!r}")
    if n_k > MAX_K_POINTS:
        raise SpeedError(f"n_k = {n_k} grid points is more than MAX_K_POINTS = {MAX_K_POINTS} (one root solve each, "
                         "0.06 ms measured: n_k = 1e10 would run for a week); the crossing is refined by a root finder, so "
                         "the default 400 suffices")
    quasi_steady = _flag("quasi_steady", quasi_steady)
    Cfun = theodorsen_function if _circulation(circulation) is None else circulation

    def C_of(k):
        return 1.0 + 0j if quasi_steady else complex(np.asarray(Cfun(np.array([k])), dtype=complex).reshape(-1)[0])

    def roots(k):
        X = _theodorsen_det_quadratic(k, section, C_of(k))
        return X[np.argsort(X.real)]

    ks = np.geomspace(k_lo, k_hi, n_k)
    R = np.array([roots(k) for k in ks])
    best = None
    for j in range(2):
        im = R[:, j].imag
        for i in np.flatnonzero(np.sign(im[:-1]) * np.sign(im[1:]) < 0):
            kf = optimize.brentq(lambda k: roots(k)[j].imag, ks[i], ks[i + 1], xtol=1e-14, rtol=1e-13)
            X = roots(kf)[j].real
            if X <= 0:
                continue
            V = 1.0 / (kf * np.sqrt(X))
            if best is None or V < best[0]:
                best = (V, 1.0 / np.sqrt(X), kf)
    if best is None:
        raise SpeedError(f"no flutter root of the determinant for k in {k_range}; widen k_range")
    V, fr, kf = best
    return DeterminantFlutter(float(V), float(V / np.sqrt(section.mu)), float(fr), float(kf))


# --------------------------------------------------------------------------------------------------
# time domain: Jones' indicial approximations
# --------------------------------------------------------------------------------------------------
def _lag_sum(k: Any, table) -> np.ndarray:
    """``1 - sum A i k / (i k + b)`` over the ``(A, b)`` pairs of ``table``: the frequency response of an indicial
    function ``1 - sum A exp(-b tau)`` (its Laplace transform times ``s``)."""
    p = 1j * _as_k(k)
    return 1.0 - sum(A * p / (p + b) for A, b in table)


def _exponential_sum(tau: Any, table) -> np.ndarray:
    """``1 - sum A exp(-b tau)`` over the ``(A, b)`` pairs of ``table``, 0 for ``tau < 0``; :class:`AeroModelError`
    for a ``tau`` that is not real numbers or holds NaN (``+-inf`` are the limits: 1 and 0)."""
    try:
        t = np.asarray(tau, dtype=float)
    except (TypeError, ValueError):
        raise AeroModelError(f"tau (semichords travelled) must be a number or an array of numbers, got {tau!r}") from None
    if np.any(np.isnan(t)):
        raise AeroModelError("tau (semichords travelled) contains NaN; repair or drop those times")
    with np.errstate(over="ignore"):                     # exp of a large negative tau: masked below
        value = 1.0 - sum(A * np.exp(-b * t) for A, b in table)
    return np.where(t < 0.0, 0.0, value)[()]


def theodorsen_jones(k: Any) -> np.ndarray:
    """Theodorsen's function as implied by Jones' Wagner approximation: ``1 - sum A_i i k / (i k + b_i)``.

    Differs from :func:`theodorsen_function` by up to about 2.3 % in magnitude for ``k`` in ``0.05 .. 1``.

    Parameters
    ----------
    k : array_like, shape (...)
        Reduced frequency ``k = omega b / U >= 0`` (``= omega / 2`` with ``omega`` in ``U / c``), finite; any shape.

    Returns
    -------
    ndarray, complex, shape (...)
        The shape of ``k``; 1 at ``k = 0``. ``(A_i, b_i)`` from :data:`WAGNER_JONES`.

    Raises
    ------
    SpeedError
        A ``k`` that is negative, not finite or not numeric.
    """
    return _lag_sum(k, WAGNER_JONES)


def sears_jones(k: Any) -> np.ndarray:
    """Sears' function (gust at the leading edge) as implied by Jones' Kussner approximation.

    ``S_le(k) ~= 1 - sum G_i i k / (i k + g_i)`` (the Laplace transform of ``d psi / d tau`` plus ``psi(0)``),
    ``(G_i, g_i)`` from :data:`KUSSNER_JONES`.

    Parameters
    ----------
    k : array_like, shape (...)
        Reduced frequency ``k = omega b / U >= 0`` (``= omega / 2`` with ``omega`` in ``U / c``), finite; any shape.

    Returns
    -------
    ndarray, complex, shape (...)
        The shape of ``k``; 1 at ``k = 0``.

    Raises
    ------
    SpeedError
        A ``k`` that is negative, not finite or not numeric.
    """
    return _lag_sum(k, KUSSNER_JONES)


def jones_frf(omega: Any, a: float, T: float | None = None):
    """Frequency response of Jones' approximations in the ``aero`` layout (inputs gust, plunge, pitch).

    The exact frequency-domain image of :func:`jones_section_model`'s aerodynamics: :func:`theodorsen_motion`
    with :func:`theodorsen_jones` and the gust column ``2 pi sears_jones(k)`` (``Cm = Cl (a + 1/2) / 2``).
    Fitting these data and coupling them must reproduce :func:`jones_section_model` up to the fit error.

    Parameters
    ----------
    omega : array_like, shape (K,)
        Frequencies in ``U / c`` (finite, ``>= 0``, at least one; flattened).
    a : float
        Elastic axis aft of mid-chord, semichords; ``Cm`` and pitch are about it.
    T : float, optional
        Sampling period (convective time c / U) passed to :meth:`sysid.FrequencyResponse.from_continuous`.

    Returns
    -------
    sysid.FrequencyResponse
        ``H`` of shape ``(2, 3, K)``: outputs ``["Cl", "Cm"]``, inputs ``["gust", "plunge", "pitch"]`` (gust angle
        at the leading edge in rad, ``h / c`` up, rad nose up); metadata ``source`` and ``a``.

    Raises
    ------
    AeroModelError
        ``omega`` empty, not finite or negative.
    SectionError
        ``a`` not a finite number.
    sysid.FrequencyGridError
        ``T`` given but not positive and finite.
    """
    import sysid

    w = _as_omega(omega)
    a = _check_a(a)
    Hm = theodorsen_motion(w, a, circulation=theodorsen_jones)
    cl = 2 * np.pi * sears_jones(w / 2.0)
    Hg = np.stack([cl, cl * (a + 0.5) / 2.0])[:, None, :]
    return sysid.FrequencyResponse.from_continuous(np.concatenate([Hg, Hm], axis=1), w, T,
                                                   inputs=["gust", "plunge", "pitch"], outputs=["Cl", "Cm"],
                                                   metadata={"source": "aeroelastic.theodorsen.jones_frf", "a": a})


def wagner_jones(tau: Any) -> np.ndarray:
    """Wagner's function (lift build-up after a step in incidence), R. T. Jones' approximation.

    ``phi(tau) = 1 - 0.165 exp(-0.0455 tau) - 0.335 exp(-0.3 tau)``, ``tau = U t / b`` (semichords travelled);
    ``phi = 0`` for ``tau < 0`` (before the step), as :func:`cfd.wagner`.

    Parameters
    ----------
    tau : array_like, shape (...)
        Time since the step, in semichords travelled ``U t / b`` (twice the convective time ``t U / c``); any shape.

    Returns
    -------
    ndarray, shape (...)
        ``phi`` (fraction of the steady lift), of the shape of ``tau`` (a NumPy float for a scalar ``tau``).
    """
    return _exponential_sum(tau, WAGNER_JONES)


def kussner_jones(tau: Any) -> np.ndarray:
    """Kussner's function (lift on entering a sharp-edged gust), R. T. Jones' approximation.

    ``psi(tau) = 1 - 0.236 exp(-0.058 tau) - 0.513 exp(-0.364 tau) - 0.171 exp(-2.42 tau)``, ``tau = U t / b``
    measured from the gust front reaching the leading edge; ``psi = 0`` for ``tau < 0`` (before it), as
    :func:`cfd.kussner`.

    Parameters
    ----------
    tau : array_like, shape (...)
        Time since the gust front reached the leading edge, in semichords travelled ``U t / b`` (twice the
        convective time ``t U / c``); any shape.

    Returns
    -------
    ndarray, shape (...)
        ``psi`` (fraction of the steady gust lift), of the shape of ``tau`` (a NumPy float for a scalar ``tau``).
    """
    return _exponential_sum(tau, KUSSNER_JONES)


def jones_section_model(section, speed: float):
    """The flexible section in a gust, in the time domain, from Jones' indicial approximations.

    Written in Theodorsen's notation and units ``b = 1``, ``omega_alpha = 1``, ``m = 1`` (so ``U = speed``,
    ``rho = 1 / (pi mu)``, ``S = x_alpha``, ``I = r_alpha2``, ``k_h = omega_ratio^2``, ``k_theta = r_alpha2``),
    time ``t`` in ``1 / omega_alpha``:

    - structure: ``h_T'' + x_a theta'' + w_h^2 h_T = -L``, ``r2 theta'' + x_a h_T'' + r2 theta = M`` (per unit m);
    - motion loads: Theodorsen's non-circulatory terms (see :func:`theodorsen_motion`) and the circulatory
      lift ``2 pi rho U b [w(0) phi(tau) + int phi(tau - sigma) w'(sigma) d sigma]`` on the three-quarter-chord
      downwash ``w = h_T' + U theta + b (1/2 - a) theta'``, Wagner's ``phi`` from :data:`WAGNER_JONES`, realised
      with states ``z_i' = (U / b) (-b_i z_i + w)``:
      ``L_c = 2 pi rho U b [(1 - sum A_i) w + sum A_i b_i z_i]``;
    - gust: ``L_g = 2 pi rho U b [(1 - sum G_i) w_g + sum G_i g_i y_i]`` with ``y_i' = (U / b)(-g_i y_i + w_g)``
      (Kussner's ``psi`` from :data:`KUSSNER_JONES`), ``w_g = U u`` the gust velocity at the leading edge
      (up), acting at the quarter chord: ``M_g = b (a + 1/2) L_g``.

    No frequency-domain data or fit enters this model.

    Parameters
    ----------
    section : TypicalSection
    speed : float
        Speed index ``V = U / (b omega_alpha) > 0``.

    Returns
    -------
    control.StateSpace
        Continuous, time in ``1 / omega_alpha`` (``t omega_alpha = 2 s / V`` with ``s`` convective); input
        ``["gust"]`` (gust angle at the leading edge, rad); outputs ``["plunge", "pitch", "Cl", "Cm"]``
        (``h / c`` UP, rad, coefficients with ``Cm`` about the elastic axis). States:
        ``[h_T, theta, h_T', theta', z1, z2, y1, y2, y3]``.

    Raises
    ------
    SectionError
        ``section`` not a :class:`TypicalSection`.
    SpeedError
        ``speed`` not a positive finite number.
    """
    import control

    check_section(section)
    try:
        V = float(speed)
    except (TypeError, ValueError):
        V = float("nan")
    if not np.isfinite(V) or V <= 0:
        raise SpeedError(f"speed index must be positive and finite, got {speed!r}")
    mu, a, xa, r2, sig = section.mu, section.a, section.x_alpha, section.r_alpha2, section.omega_ratio
    rho, U, b = 1.0 / (np.pi * mu), V, 1.0
    nW, nG = len(WAGNER_JONES), len(KUSSNER_JONES)
    n = 4 + nW + nG
    sumA = sum(A for A, _ in WAGNER_JONES)
    sumG = sum(G for G, _ in KUSSNER_JONES)

    # Loads as linear forms in (x, qdd, u): L = Lx x + Lq qdd + Lu u, M likewise; qdd = [h_T'', theta''].
    def w_row():
        r = np.zeros(n)
        r[2] = 1.0                   # h_T'
        r[1] = U                     # U theta
        r[3] = b * (0.5 - a)         # b (1/2 - a) theta'
        return r

    w = w_row()
    circ = 2 * np.pi * rho * U * b
    Lc_x = circ * ((1 - sumA) * w)
    for i, (A, bb) in enumerate(WAGNER_JONES):
        Lc_x[4 + i] += circ * A * bb
    Lg_x = np.zeros(n)
    for i, (G, g) in enumerate(KUSSNER_JONES):
        Lg_x[4 + nW + i] += circ * G * g
    Lg_u = circ * (1 - sumG) * U
    nc = np.pi * rho * b**2
    # circulatory and gust lift act at the quarter chord, b (a + 1/2) ahead of the elastic axis
    M_x = b * (a + 0.5) * (Lc_x + Lg_x)
    M_x[3] += -nc * U * b * (0.5 - a)         # non-circulatory  -pi rho b^2 U b (1/2 - a) theta'
    L_x = Lc_x + Lg_x
    L_x[3] += nc * U                          # non-circulatory   pi rho b^2 U theta'
    L_q = nc * np.array([1.0, -b * a])        # non-circulatory   pi rho b^2 (h_T'' - b a theta'')
    M_q = nc * np.array([b * a, -b**2 * (0.125 + a**2)])
    L_u = Lg_u
    M_u = b * (a + 0.5) * Lg_u

    # structure: Ms qdd + Ks q = [-L, M]
    Ms = np.array([[1.0, xa], [xa, r2]])
    Ks = np.diag([sig**2, r2])
    # move apparent mass to the left: (Ms + [[L_q], [-M_q]]) qdd = -Ks q + [-L_x x - L_u u, M_x x + M_u u]
    Mt = Ms + np.vstack([L_q, -M_q])
    Fx = np.vstack([-L_x, M_x])
    Fx[:, 0:2] -= Ks
    Fu = np.array([[-L_u], [M_u]])
    Qx = np.linalg.solve(Mt, Fx)
    Qu = np.linalg.solve(Mt, Fu)

    A = np.zeros((n, n))
    B = np.zeros((n, 1))
    A[0, 2] = A[1, 3] = 1.0
    A[2:4] = Qx
    B[2:4] = Qu
    for i, (_, bb) in enumerate(WAGNER_JONES):
        A[4 + i] += (U / b) * w
        A[4 + i, 4 + i] += -(U / b) * bb
    for i, (_, g) in enumerate(KUSSNER_JONES):
        A[4 + nW + i, 4 + nW + i] = -(U / b) * g
        B[4 + nW + i, 0] = (U / b) * U

    # outputs: h/c up = -h_T / (2b); theta; Cl = L / (rho U^2 b); Cm = M / (2 rho U^2 b^2)
    Lfull_x = L_x + L_q @ Qx
    Lfull_u = L_u + L_q @ Qu[:, 0]
    Mfull_x = M_x + M_q @ Qx
    Mfull_u = M_u + M_q @ Qu[:, 0]
    C = np.zeros((4, n))
    D = np.zeros((4, 1))
    C[0, 0] = -1.0 / (2 * b)
    C[1, 1] = 1.0
    C[2] = Lfull_x / (rho * U**2 * b)
    D[2, 0] = Lfull_u / (rho * U**2 * b)
    C[3] = Mfull_x / (2 * rho * U**2 * b**2)
    D[3, 0] = Mfull_u / (2 * rho * U**2 * b**2)
    return control.ss(A, B, C, D, inputs=["gust"], outputs=["plunge", "pitch", "Cl", "Cm"],
                      states=["h_T", "theta", "h_T'", "theta'"] + [f"z{i + 1}" for i in range(nW)]
                      + [f"y{i + 1}" for i in range(nG)])
