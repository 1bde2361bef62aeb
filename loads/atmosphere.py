"""Flight points: the ICAO standard atmosphere and the gust velocities of CS-25.341 / 14 CFR 25.341.

The atmosphere is the ICAO standard atmosphere of 1993 (identical to the US Standard Atmosphere 1976 up to
32 km) from the ``ambiance`` package (:class:`ambiance.Atmosphere`); nothing of it is written here.

Gust velocities (CS-25.341, amendment 2014 text; the numbers are the rule's, in feet per second):

- discrete gust, 25.341(a)(5): reference gust velocity ``U_ref`` at V_B to V_C, 56.0 ft/s EAS at sea level,
  reduced linearly to 44.0 ft/s EAS at 15 000 ft and linearly again to 20.86 ft/s EAS at 60 000 ft; half of it
  at V_D; the design gust velocity ``U_ds = U_ref F_g (H / 350 ft)^(1/6)``;
- continuous turbulence, 25.341(b)(3): ``U_sigma_ref`` 90 ft/s TAS at sea level, linearly to 79 ft/s TAS at
  24 000 ft, constant above; half of it at V_D; ``U_sigma = U_sigma_ref F_g``;
- the flight profile alleviation factor, 25.341(a)(6): at sea level ``F_g = (F_gz + F_gm) / 2`` with
  ``F_gz = 1 - Z_mo / 250 000 ft``, ``F_gm = sqrt(R2 tan(pi R1 / 4))``, ``R1 = MLW / MTOW``,
  ``R2 = MZFW / MTOW``, increasing linearly to 1.0 at the maximum operating altitude ``Z_mo``.

Below sea level (allowed by the atmosphere down to -5004 m) the sea-level gust velocities are used; above
60 000 ft the rule gives no discrete-gust velocity and :meth:`FlightPoint.reference_gust_velocity` refuses.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .checks import real_values
from .errors import FlightPointError, GustError

__all__ = ["FlightPoint", "alleviation_factor", "check_point", "FT", "G0", "ALTITUDE_RANGE", "H_RANGE_FT",
           "RULE_MAX_ALTITUDE"]

FT = 0.3048
"""One foot in metres (exact)."""
G0 = 9.80665
"""Standard gravity, m/s^2."""
ALTITUDE_RANGE = (-5000.0, 80000.0)
"""Geopotential altitudes (m) the ICAO atmosphere of ``ambiance`` covers (its geometric -5004 .. 81020 m);
outside it :class:`FlightPointError`."""
RULE_MAX_ALTITUDE = 60000.0 * FT
"""The discrete-gust reference velocity is defined up to 60 000 ft (18 288 m)."""
H_RANGE_FT = (30.0, 350.0)
"""Gust gradients the rule asks for, ft (9.144 m to 106.68 m)."""
_U_REF = ((0.0, 56.0), (15000.0, 44.0), (60000.0, 20.86))      # ft, ft/s EAS
_U_SIGMA = ((0.0, 90.0), (24000.0, 79.0))                       # ft, ft/s TAS, constant above


def _real(name: str, v: Any) -> float:
    """``v`` as a finite float, else :class:`FlightPointError` naming ``name``; a bool or a string is refused, not
    converted (as :class:`cfd.FlowCondition` does: ``"0.5"`` was parsed)."""
    if isinstance(v, (bool, np.bool_, str, bytes)):
        raise FlightPointError(f"{name} must be a real number, got {v!r}")
    try:
        f = float(v)
    except (TypeError, ValueError):
        raise FlightPointError(f"{name} must be a real number, got {v!r}") from None
    if not math.isfinite(f):
        raise FlightPointError(f"{name} must be finite, got {v!r}")
    return f


def _check_fg(F_g: Any) -> float:
    f = _real("F_g", F_g)
    if not 0.0 < f <= 1.0:
        raise FlightPointError(f"F_g (flight profile alleviation factor) must lie in (0, 1], got {F_g!r}; 1.0 is no "
                               "alleviation, loads.alleviation_factor() computes it from Z_mo, MLW/MTOW, MZFW/MTOW")
    return f


def alleviation_factor(altitude_m: float, z_mo_m: float, mlw_over_mtow: float, mzfw_over_mtow: float) -> float:
    """Flight profile alleviation factor ``F_g`` of CS-25.341(a)(6) at an altitude.

    Parameters
    ----------
    altitude_m : float
        Altitude (m); below sea level the sea-level value is used.
    z_mo_m : float
        Maximum operating altitude ``Z_mo`` (m), > 0.
    mlw_over_mtow, mzfw_over_mtow : float
        ``R1 = MLW / MTOW`` and ``R2 = MZFW / MTOW``, in (0, 1].

    Returns
    -------
    float
        ``F_g`` in (0, 1]: ``(F_gz + F_gm) / 2`` at sea level, rising linearly to 1 at ``Z_mo`` and 1 above.

    Raises
    ------
    FlightPointError
        A value not a finite real number (a string or bool is refused, not converted), ``Z_mo <= 0`` or above
        250 000 ft, a ratio outside (0, 1], ``MZFW > MLW``.
    """
    h = _real("altitude_m", altitude_m)
    z = _real("z_mo_m", z_mo_m)
    r1, r2 = _real("mlw_over_mtow", mlw_over_mtow), _real("mzfw_over_mtow", mzfw_over_mtow)
    if not 0.0 < z < 250000.0 * FT:
        raise FlightPointError(f"z_mo_m must lie in (0, 76 200) m (F_gz = 1 - Z_mo / 250 000 ft), got {z_mo_m!r}")
    for name, r in (("mlw_over_mtow", r1), ("mzfw_over_mtow", r2)):
        if not 0.0 < r <= 1.0:
            raise FlightPointError(f"{name} must lie in (0, 1], got {r!r}")
    if r2 > r1:
        raise FlightPointError(f"mzfw_over_mtow ({r2!r}) must not exceed mlw_over_mtow ({r1!r}): MZFW <= MLW <= MTOW "
                               "(the arguments may be swapped: alleviation_factor(altitude_m, z_mo_m, MLW/MTOW, "
                               "MZFW/MTOW))")
    fgz = 1.0 - z / (250000.0 * FT)
    fgm = math.sqrt(r2 * math.tan(math.pi * r1 / 4.0))
    f0 = 0.5 * (fgz + fgm)
    frac = min(max(h, 0.0) / z, 1.0)
    return float(min(f0 + (1.0 - f0) * frac, 1.0))


@dataclass(frozen=True)
class FlightPoint:
    """A flight point: Mach number, altitude and chord, with the standard atmosphere there.

    Parameters
    ----------
    mach : float
        Flight Mach number, ``0 < mach < 1`` (the ROMs are subsonic; the model must have been built at it).
    altitude_m : float
        Geopotential (pressure) altitude (m), the altitude of the ICAO tables and of the rule, within
        :data:`ALTITUDE_RANGE`.
    chord_m : float
        Chord ``c`` (m), > 0.
    F_g : float
        Flight profile alleviation factor in (0, 1] (default 1.0: none); see :func:`alleviation_factor`.
    design_speed : {"VC", "VD"}
        ``"VD"`` halves the reference gust velocities (25.341(a)(5)(iii), (b)(3)(iii)); default ``"VC"``.

    Attributes (properties)
    -----------------------
    rho (kg/m^3), speed_of_sound (m/s), tas (m/s), eas (m/s), q (Pa), time_scale (``c / U``, s).

    Raises
    ------
    FlightPointError
        Mach, altitude, chord or F_g out of range or not a finite real number (a string such as ``"0.5"`` or a bool
        is refused, not converted); an unknown ``design_speed``.

    Examples
    --------
    >>> pt = FlightPoint(mach=0.5, altitude_m=3000.0, chord_m=2.0)
    >>> round(pt.rho, 4), round(pt.tas, 2)
    (0.9093, 164.29)
    """

    mach: float
    altitude_m: float
    chord_m: float
    F_g: float = 1.0
    design_speed: str = "VC"

    def __post_init__(self) -> None:
        sa = object.__setattr__
        m = _real("mach", self.mach)
        if not 0.0 < m < 1.0:
            raise FlightPointError(f"mach must lie in (0, 1) (subsonic flight), got {self.mach!r}")
        h = _real("altitude_m", self.altitude_m)
        lo, hi = ALTITUDE_RANGE
        if not lo <= h <= hi:
            raise FlightPointError(f"altitude_m = {self.altitude_m!r} is outside the ICAO standard atmosphere's range "
                                   f"{lo:g} .. {hi:g} m (ambiance.Atmosphere)")
        c = _real("chord_m", self.chord_m)
        if c <= 0.0:
            raise FlightPointError(f"chord_m must be > 0 (metres), got {self.chord_m!r}")
        if self.design_speed not in ("VC", "VD"):
            raise FlightPointError(f"design_speed must be 'VC' (V_B to V_C) or 'VD', got {self.design_speed!r}")
        from ambiance import Atmosphere

        atm = Atmosphere(Atmosphere.geop2geom_height(h))   # ambiance takes geometric heights
        sa(self, "mach", m)
        sa(self, "altitude_m", h)
        sa(self, "chord_m", c)
        sa(self, "F_g", _check_fg(self.F_g))
        sa(self, "_rho", float(atm.density[0]))
        sa(self, "_a", float(atm.speed_of_sound[0]))

    @property
    def rho(self) -> float:
        """Air density, kg/m^3."""
        return self._rho

    @property
    def speed_of_sound(self) -> float:
        """m/s."""
        return self._a

    @property
    def tas(self) -> float:
        """True airspeed ``U = M a``, m/s."""
        return self.mach * self._a

    @property
    def eas(self) -> float:
        """Equivalent airspeed ``U sqrt(rho / rho_0)``, m/s."""
        return self.tas * math.sqrt(self._rho / RHO0)

    @property
    def q(self) -> float:
        """Dynamic pressure ``rho U^2 / 2``, Pa."""
        return 0.5 * self._rho * self.tas**2

    @property
    def time_scale(self) -> float:
        """``c / U`` (s): convective time ``s = t U / c``, so ``t = s c / U``."""
        return self.chord_m / self.tas

    @property
    def _speed_factor(self) -> float:
        return 0.5 if self.design_speed == "VD" else 1.0

    def reference_gust_velocity(self) -> float:
        """``U_ref`` (m/s EAS) at this altitude (times 1/2 at V_D), without ``F_g``.

        Raises
        ------
        GustError
            Above 60 000 ft, where the rule gives none.
        """
        if self.altitude_m > RULE_MAX_ALTITUDE * (1 + 1e-12):
            raise GustError(f"the discrete-gust reference velocity is defined up to 60 000 ft (18 288 m); the flight "
                            f"point is at {self.altitude_m:g} m")
        return _interp(self.altitude_m, _U_REF) * self._speed_factor

    def turbulence_intensity(self) -> float:
        """``U_sigma = U_sigma_ref F_g`` (m/s TAS) at this altitude, 25.341(b)(3) (times 1/2 at V_D).

        Raises
        ------
        GustError
            Above 60 000 ft, where the rule gives none (``U_sigma_ref`` is constant from 24 000 ft "up to
            60 000 ft").
        """
        if self.altitude_m > RULE_MAX_ALTITUDE * (1 + 1e-12):
            raise GustError(f"the continuous-turbulence intensity U_sigma_ref is defined up to 60 000 ft (18 288 m); "
                            f"the flight point is at {self.altitude_m:g} m")
        return _interp(min(self.altitude_m, 24000.0 * FT), _U_SIGMA) * self._speed_factor * self.F_g

    def design_gust_velocity(self, H_m: Any) -> np.ndarray:
        """``U_ds = U_ref F_g (H / 350 ft)^(1/6)`` in m/s **TAS** (the rule's EAS times ``sqrt(rho_0 / rho)``).

        Parameters
        ----------
        H_m : array_like, shape (...)
            Gust gradients (m), finite and > 0. Gradients outside the rule's 30 .. 350 ft (:data:`H_RANGE_FT`) are
            evaluated by the same formula; :func:`loads.tuned_gust` keeps its search within the rule's range unless
            ``outside_rule=True``.

        Returns
        -------
        ndarray, shape (...)

        Raises
        ------
        GustError
            ``H_m`` not real numbers (a string, a complex number), or a gradient that is not finite and > 0 (a
            negative one gave NaN); a flight point above 60 000 ft.
        """
        H = _gradients(H_m)
        u_eas = self.reference_gust_velocity() * self.F_g * (H / (350.0 * FT)) ** (1.0 / 6.0)
        return u_eas * math.sqrt(RHO0 / self._rho)

    def gust_angle(self, H_m: Any) -> np.ndarray:
        """Peak gust angle ``U_ds / U`` (rad, both TAS) of the design gust of gradient ``H_m`` (m), shape of ``H_m``.

        Raises
        ------
        GustError
            As :meth:`design_gust_velocity`: ``H_m`` not real, finite gradients > 0; a point above 60 000 ft.
        """
        return self.design_gust_velocity(H_m) / self.tas

    def summary(self) -> str:
        """One line: Mach, altitude, TAS, EAS, q, rho."""
        return (f"M {self.mach:.3g}, {self.altitude_m:.0f} m: rho {self.rho:.4g} kg/m^3, TAS {self.tas:.4g} m/s, "
                f"EAS {self.eas:.4g} m/s, q {self.q:.5g} Pa, c {self.chord_m:.3g} m, F_g {self.F_g:.3g}")


RHO0 = 1.225
"""Sea-level density of the ICAO atmosphere, kg/m^3 (the EAS reference)."""


def check_point(point: Any) -> FlightPoint:
    """``point`` itself if it is a :class:`FlightPoint`, else :class:`FlightPointError` naming what it got (the one
    check of every loads entry point that takes a flight point)."""
    if not isinstance(point, FlightPoint):
        raise FlightPointError(f"point must be a loads.FlightPoint(mach, altitude_m, chord_m), got "
                               f"{type(point).__name__}")
    return point


def _gradients(H_m: Any) -> np.ndarray:
    """``H_m`` as a float array of gust gradients (m), each finite and > 0, else :class:`GustError`."""
    H = real_values(H_m)
    if H is None:
        raise GustError(f"the gust gradient H_m must be a real number of metres or an array of them, got {H_m!r}")
    wrong = ~(np.isfinite(H) & (H > 0.0))
    if wrong.any():
        got = (repr(float(H)) if H.ndim == 0
               else f"{float(H[wrong][0])!r} (the first of {np.count_nonzero(wrong)} bad values among {H.size})")
        lo, hi = H_RANGE_FT
        raise GustError(f"the gust gradient H_m must be finite and > 0 m (the rule's range is {lo:g} .. {hi:g} ft, "
                        f"{lo * FT:.5g} .. {hi * FT:.5g} m), got {got}")
    return H


def _interp(h_m: float, table) -> float:
    """Piecewise-linear table ``((ft, ft/s), ...)`` at ``h_m`` metres (clamped at its ends), in m/s."""
    ft = np.array([p[0] for p in table])
    v = np.array([p[1] for p in table])
    return float(np.interp(max(h_m, 0.0) / FT, ft, v)) * FT
