"""Classical unsteady thin-aerofoil gust references: Sears, compressible Sears (Amiet), Kussner, Wagner.

These are the independent references against which the linearised CFD (``cfd.lfd``, ``cfd.ltd``) is
validated at low Mach number. Everything is vectorised over its first argument.

Units and conventions (those of the project, docs/conventions.md)
-------------------------------------------------------------------
- ``omega`` is the angular frequency in units of ``U / c`` (c the chord); the classical reduced
  frequency on the semi-chord ``b = c / 2`` is ``k = omega b / U = omega / 2``.
- Time dependence ``exp(+i omega t)``; a vertical gust convected downstream,
  ``w(x, t) = w0 exp(i omega (t - x / U))``.
- Transfer functions are normalised lift: ``Cl = 2 pi (w_ref / U) S`` where ``w_ref`` is the gust
  velocity at the reference point, i.e. ``Cl / (2 pi)`` per radian of gust angle measured there.
  ``reference="midchord"`` (x = c/2, the classical form) or ``reference="leading_edge"`` (x = 0, the
  project's default gust input point ``x_ref = 0``); the two differ by the factor ``exp(-i k)``
  (the gust reaches mid-chord ``c / (2 U)`` after the leading edge).
- Indicial functions take the convective time ``s = t U / c`` in chords by default
  (``unit="semichord"`` for the classical ``s_b = U t / b = 2 s``). The Kussner function is the
  lift build-up after a sharp-edged gust's front passes the leading edge; it is the step response of
  the leading-edge-referenced Sears function.

Large frequencies. The Bessel-function forms are evaluated with the exponentially scaled functions
(``K_nu(i k) e^{i k}``, ``H_nu^(2)(k) e^{i k}``), whose factors ``e^{i k}`` cancel in Theodorsen's ratio and are
put back exactly (``np.exp(1j k)``) in the Sears function. From ``k = K_ASYMPTOTIC`` on (SciPy's AMOS routines
return NaN above ``k ~ 1e9`` for ``K_nu(i k)`` and ``k ~ 1e16`` for ``H_nu^(2)(k)``) the scaled functions are
Hankel's expansion (DLMF 10.17.6; 10.40.2 with ``z = i k`` is the same series term by term)::

    H_nu^(2)(k) e^{i k} = sqrt(2 / (pi k)) e^{i (nu pi / 2 + pi / 4)} sum_{m < 6} (-i)^m a_m(nu) / k^m

For real ``k > 0`` and ``nu = 0, 1`` the remainder is at most the first neglected term (DLMF 10.17(iii)), a
relative ``|a_6(nu)| / k^6 <= 6.8e-25`` at ``k >= 1e4``, far below round-off. So every function here is finite
for every finite ``omega >= 0``. At large ``k``, ``S = e^{i (k - pi / 4)} / sqrt(2 pi k) (1 + O(1 / k))`` at
mid-chord (``e^{-i pi / 4} / sqrt(2 pi k)`` at the leading edge) and ``C = 1 / 2 + O(1 / k)``.
"""

import numpy as np
from scipy import special

from .checks import kind_of, real_array, real_number

__all__ = [
    "AnalyticError",
    "sears",
    "sears_hankel",
    "theodorsen",
    "sears_compressible",
    "kussner",
    "wagner",
    "step_response",
]


class AnalyticError(ValueError):
    """Bad argument to an analytic reference function (unknown option, negative frequency...)."""


_REFERENCES = ("midchord", "leading_edge")


def _omega(omega):
    w = real_array(omega)   # (None for text: its dtype is not numeric)
    if w is None:   # a complex omega was cast to its real part (ComplexWarning), "1" parsed
        raise AnalyticError(f"omega must be a real number or an array of real numbers (U/c units); got "
                            f"{kind_of(omega)} {omega!r:.80}")
    if np.any(~np.isfinite(w)) or np.any(w < 0.0):
        raise AnalyticError(
            "omega must be finite and >= 0 (U/c units; the response at -omega is the complex conjugate)"
        )
    return w


def _shift(S, k, reference):
    if reference not in _REFERENCES:
        raise AnalyticError(f"reference must be one of {_REFERENCES}, got {reference!r}")
    return S if reference == "midchord" else S * np.exp(-1j * k)


K_ASYMPTOTIC = 1.0e4
"""Reduced frequency ``k = omega / 2`` from which the scaled Bessel functions are Hankel's expansion (module
docstring); its truncation error there is below 1e-24, relative."""

_N_TERMS = 6


def _hankel_series(nu, k):
    """``sum_{m < 6} (-i)^m a_m(nu) / k^m`` (DLMF 10.17.1, 10.17.6) for ``k > 0``, by Horner's rule in ``1 / k``
    (no overflow of ``k^m``)."""
    a = [1.0]
    for m in range(1, _N_TERMS):
        a.append(a[-1] * (4.0 * nu * nu - (2 * m - 1) ** 2) / (8.0 * m))
    u = 1.0 / k
    total = np.zeros(np.shape(k), dtype=complex)
    for m in range(_N_TERMS - 1, -1, -1):
        total = total * u + (-1j) ** m * a[m]
    return total


def _scaled(nu, k, exact, prefactor):
    """``exact(nu, k)`` below :data:`K_ASYMPTOTIC`, ``prefactor(k) * _hankel_series(nu, k)`` from there on
    (``k > 0``, an array)."""
    out = np.empty(k.shape, dtype=complex)
    low = k < K_ASYMPTOTIC
    out[low] = exact(nu, k[low])
    out[~low] = prefactor(k[~low]) * _hankel_series(nu, k[~low])
    return out


def _kv_imaginary_scaled(nu, k):
    """``K_nu(i k) e^{i k}`` for ``k > 0``: ``special.kve``, or DLMF 10.40.2, ``sqrt(pi / (2 i k))`` times the
    Hankel series."""
    return _scaled(nu, k, lambda n, x: special.kve(n, 1j * x),
                   lambda x: np.sqrt(0.5 * np.pi / x) * np.exp(-0.25j * np.pi))


def _hankel2_scaled(nu, k):
    """``H_nu^(2)(k) e^{i k}`` for ``k > 0``: ``special.hankel2e``, or DLMF 10.17.6."""
    phase = np.exp(1j * (0.5 * nu * np.pi + 0.25 * np.pi))
    return _scaled(nu, k, special.hankel2e, lambda x: np.sqrt(2.0 / np.pi / x) * phase)


def sears(omega, reference="midchord"):
    """Sears function, modified-Bessel form ``S = 1 / (i k (K0(i k) + K1(i k)))``, ``k = omega / 2``.

    Parameters
    ----------
    omega : array_like, shape (...)
        Angular frequency in ``U / c`` units, ``>= 0``. ``omega = 0`` gives exactly 1.
    reference : {"midchord", "leading_edge"}
        Point where the gust velocity is measured.

    Returns
    -------
    S : ndarray, complex, shape (...)
        ``Cl / (2 pi w_ref / U)``; finite for every finite ``omega`` (module docstring, "Large frequencies").

    Raises
    ------
    AnalyticError
        ``omega`` not real numbers (complex, text, None), negative or not finite; an unknown ``reference``.
    """
    w = _omega(omega)
    k = 0.5 * w
    return _shift(_sears_midchord(k), k, reference)


def _sears_midchord(k):
    """:func:`sears` (mid-chord) at reduced frequencies ``k >= 0`` (finite), an array."""
    kk = np.where(k > 0.0, k, 1.0)
    # K_nu(i k) = e^{-i k} (K_nu(i k) e^{i k}): the scaled functions are finite at any k (module docstring)
    S = np.exp(1j * kk) / (1j * kk * (_kv_imaginary_scaled(0, kk) + _kv_imaginary_scaled(1, kk)))
    return np.where(k > 0.0, S, 1.0 + 0j)


def sears_hankel(omega, reference="midchord"):
    """Sears function, Hankel form ``S = 2 / (pi k (H0^(2)(k) - i H1^(2)(k)))``, ``k = omega / 2``.

    Same parameters and result as :func:`sears` (an independent evaluation for cross-checks).
    """
    w = _omega(omega)
    k = 0.5 * w
    kk = np.where(k > 0.0, k, 1.0)
    S = 2.0 * np.exp(1j * kk) / (np.pi * (kk * (_hankel2_scaled(0, kk) - 1j * _hankel2_scaled(1, kk))))
    S = np.where(k > 0.0, S, 1.0 + 0j)
    return _shift(S, k, reference)


def theodorsen(omega):
    """Theodorsen's function ``C = H1^(2)(k) / (H1^(2)(k) + i H0^(2)(k))``, ``k = omega / 2``.

    Parameters
    ----------
    omega : array_like, shape (...)
        ``U / c`` units, ``>= 0``; ``C(0) = 1``.

    Returns
    -------
    ndarray, complex, shape (...)
    """
    w = _omega(omega)
    k = 0.5 * w
    kk = np.where(k > 0.0, k, 1.0)
    h1, h0 = _hankel2_scaled(1, kk), _hankel2_scaled(0, kk)   # the factors e^{i k} cancel in the ratio
    return np.where(k > 0.0, h1 / (h1 + 1j * h0), 1.0 + 0j)


def sears_compressible(omega, mach, reference="midchord"):
    """Amiet's low-frequency compressible Sears function, normalised by the slope ``2 pi / beta``.

    With ``beta = sqrt(1 - M^2)``, ``x = k / beta^2`` and
    ``f(M) = (1 - beta) ln M + beta ln(1 + beta) - ln 2``::

        S_c = S(x) [J0(M^2 x) - i J1(M^2 x)] exp(+i x f(M))       (exp(+i omega t) convention)

    so that ``Cl = (2 pi / beta) (w_ref / U) S_c``. The form quoted in docs/references.md,
    ``S(x) [J0 + i J1] exp(-i x f)``, fits the ``exp(-i omega t)`` convention; here the two correction
    factors are conjugated (confirmed by the CFD: the phase change of the LFD lift with Mach number
    follows this form, docs/gust_validation.md): the Bessel factor is then the chordwise integral of the
    flat-plate loading ``sqrt((1 - xi) / (1 + xi))`` against the phase ``exp(+i M^2 x xi)`` that
    the Prandtl-Glauert-type transformation of the convected wave equation puts on the pressure in
    the ``exp(+i omega t)`` convention (``Phi = Psi exp(+i k M^2 xi / beta^2)``), which gives
    ``pi (J0 - i J1)``. Both factors are then phase *lags* that grow with Mach number, as expected
    of the slower compressible lift build-up, and both tend to 1 as ``M -> 0`` (``f -> 0``), where
    ``S_c -> S(k)``. Valid for ``M^2 x`` small (low frequency); ``x f`` need not be small.

    Parameters
    ----------
    omega : array_like, shape (...)
        ``U / c`` units, ``>= 0``.
    mach : float
        Free-stream Mach number, ``0 <= mach < 1`` (0 gives the incompressible function).
    reference : {"midchord", "leading_edge"}
        Where the gust is measured; ``leading_edge`` multiplies by ``exp(-i k)`` with the physical
        ``k = omega / 2`` (the convection delay over the half chord is unchanged by compressibility).

    Returns
    -------
    ndarray, complex, shape (...)

    Raises
    ------
    AnalyticError
        As :func:`sears`; ``mach`` not a number in ``[0, 1)``; ``omega / (2 beta^2)`` beyond the largest float.
    """
    m = real_number(mach)   # None for a bool, text, None: refused just below, with the value as given
    if m is None or not (np.isfinite(m) and 0.0 <= m < 1.0):
        raise AnalyticError(f"mach = {mach!r} must be in [0, 1) for the subsonic compressible Sears function")
    w = _omega(omega)
    k = 0.5 * w
    beta = np.sqrt(1.0 - m * m)
    with np.errstate(over="ignore"):
        x = k / beta**2
    if not np.all(np.isfinite(x)):
        raise AnalyticError(f"omega / (2 beta^2) overflows at mach = {m!r} (beta = {beta:.3g}): the largest omega "
                            f"is {np.finfo(float).max * beta**2:.3g}, and the function is a low-frequency one "
                            "(valid for mach^2 omega / (2 beta^2) small)")
    f = (1.0 - beta) * np.log(m) + beta * np.log1p(beta) - np.log(2.0) if m > 0.0 else 0.0
    a = m * m * x
    S = _sears_midchord(x) * (special.j0(a) - 1j * special.j1(a)) * np.exp(1j * x * f)
    return _shift(S, k, reference)


def _time(s, unit):
    v = real_array(s)
    if v is None:   # None became NaN and was refused as "time contains NaN"; "1" was parsed
        raise AnalyticError(f"s must be a real number or an array of real times (convective s = U t / c, or U t / b "
                            f"with unit='semichord'); got {kind_of(s)} {s!r:.80}")
    s = v
    if unit == "chord":
        sb = 2.0 * s
    elif unit == "semichord":
        sb = s
    else:
        raise AnalyticError(f"unit must be 'chord' (s = U t / c, the project's time) or 'semichord'; got {unit!r}")
    if np.any(np.isnan(sb)):
        raise AnalyticError("s (time) contains NaN; give real times (psi = 0 before s = 0)")
    return sb


def kussner(s, approximation="jones", unit="chord"):
    """Kussner function (lift build-up after a sharp-edged gust front passes the leading edge).

    ``Cl(s) = 2 pi (w / U) psi(s)``; ``psi = 0`` for ``s < 0``.

    Parameters
    ----------
    s : array_like, shape (...)
        Time since the front reached the leading edge: convective ``s = U t / c`` (``unit="chord"``,
        the project's time) or ``s_b = U t / b = 2 s`` (``unit="semichord"``, the classical one).
    approximation : {"jones", "sears-sparks"}
        R.T. Jones ``1 - 0.236 e^{-0.058 s_b} - 0.513 e^{-0.364 s_b} - 0.171 e^{-2.42 s_b}`` or
        Sears-Sparks ``1 - 0.5 e^{-0.13 s_b} - 0.5 e^{-s_b}``.
    unit : {"chord", "semichord"}

    Returns
    -------
    ndarray, shape (...)
    """
    sb = _time(s, unit)
    sp = np.maximum(sb, 0.0)   # psi = 0 for s < 0: exp(-c s_b) there would overflow at s_b ~ -300 / c
    if approximation == "jones":
        psi = 1.0 - 0.236 * np.exp(-0.058 * sp) - 0.513 * np.exp(-0.364 * sp) - 0.171 * np.exp(-2.42 * sp)
    elif approximation == "sears-sparks":
        psi = 1.0 - 0.5 * np.exp(-0.13 * sp) - 0.5 * np.exp(-sp)
    else:
        raise AnalyticError(f"approximation must be 'jones' or 'sears-sparks'; got {approximation!r}")
    return np.where(sb >= 0.0, psi, 0.0)


def wagner(s, unit="chord"):
    """Wagner function (R.T. Jones): ``phi = 1 - 0.165 e^{-0.0455 s_b} - 0.335 e^{-0.3 s_b}``.

    Lift build-up after a step change of incidence, ``Cl = 2 pi alpha phi`` (``phi(0+) = 1/2``);
    the step response of Theodorsen's function. ``phi = 0`` for ``s < 0``.

    Parameters
    ----------
    s : array_like, shape (...)
        Convective time (``unit="chord"``) or semi-chords travelled (``unit="semichord"``).
    unit : {"chord", "semichord"}

    Returns
    -------
    ndarray, shape (...)
    """
    sb = _time(s, unit)
    sp = np.maximum(sb, 0.0)   # phi = 0 for s < 0 (no overflow of the exponentials there)
    phi = 1.0 - 0.165 * np.exp(-0.0455 * sp) - 0.335 * np.exp(-0.3 * sp)
    return np.where(sb >= 0.0, phi, 0.0)


def step_response(transfer, s, omega_max=4000.0, n=400_001, high_value=0.0):
    """Step response of a causal, real-impulse-response transfer function by Fourier inversion.

    For ``G(omega) = G_inf + G_r(omega)`` with ``G_r`` the transform of a causal real function,
    ``y(s) = G_inf + (2 / pi) int_0^inf Re(G_r(omega)) sin(omega s) / omega d omega`` for ``s > 0``.
    The integral is truncated at ``omega_max`` and done by the trapezoidal rule on a grid uniform in
    ``sqrt(omega)`` (dense near 0, where ``sin(omega s) / omega`` is largest). Used to check the
    indicial functions against the frequency-domain ones; accuracy about 1e-3 for the Sears function.

    Parameters
    ----------
    transfer : callable
        ``transfer(omega) -> complex array``, ``omega`` in ``U / c`` units.
    s : array_like, shape (n_s,)
        Convective times, ``> 0``.
    omega_max : float
        Truncation frequency.
    n : int
        Number of quadrature points.
    high_value : float
        ``G_inf``, the (real) limit of ``G`` at infinite frequency.

    Returns
    -------
    ndarray, shape (n_s,)

    Raises
    ------
    AnalyticError
        ``s`` not real numbers (a complex ``s`` was cast to its real part with only a ``ComplexWarning``).
    """
    v = real_array(s)
    if v is None:
        raise AnalyticError(f"s must be a real number or an array of real convective times (> 0); got "
                            f"{kind_of(s)} {s!r:.80}")
    s = np.atleast_1d(v)
    r = np.linspace(0.0, np.sqrt(omega_max), n)[1:]
    w = r * r
    g = (np.real(transfer(w)) - high_value) * 2.0 * r / w  # d omega = 2 r dr
    out = np.empty(s.shape)
    dr = r[1] - r[0]
    for idx, si in enumerate(s):  # a handful of times; each is one vectorised quadrature
        f = g * np.sin(w * si)
        # limit at r -> 0: Re G_r(0) * 2 r sin(r^2 s) / r^2 -> 0
        out[idx] = dr * (np.sum(f) - 0.5 * f[-1])
    return high_value + (2.0 / np.pi) * out
