"""The flexible section at a flight point: a dimensional typical section coupled with a motion/gust model.

A flight point fixes ``rho`` and ``U``, so a section for loads is dimensional (mass per unit span, frequencies
in rad/s); its mass ratio ``mu = m / (pi rho b^2)`` and speed index ``V = U / (b omega_alpha)`` follow and
change with altitude and Mach. :meth:`FlexibleSection.state_space` builds :func:`aeroelastic.coupled_model` at
the point (time ``tau = omega_alpha t``) and rescales it to convective time ``s = t U / c``
(``d/ds = (2 / V) d/dtau``), the time base of every other gust model here.

Outputs (model units; the factor to SI at the point in brackets): ``plunge`` ``h / c`` up (``c``: m), ``pitch``
rad nose up (1), ``plunge_rate``, ``pitch_rate`` per unit ``tau`` (``c omega_alpha``: m/s; ``omega_alpha``:
rad/s), ``plunge_acc``, ``pitch_acc`` per unit ``tau^2`` (``c omega_alpha^2``: m/s^2; ``omega_alpha^2``:
rad/s^2), ``load_factor`` (the plunge acceleration in g: ``c omega_alpha^2 / g``), ``Cl`` (``q c``: N/m),
``Cm`` about the elastic axis (``q c^2``: N m/m), and the spring loads (the section's internal loads)
``plunge_spring = k_h h`` (``m omega_h^2 c``: N/m) and ``pitch_spring = k_alpha alpha``
(``m b^2 r_alpha2 omega_alpha^2``: N m/m).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .atmosphere import G0, FlightPoint, check_point
from .errors import LoadsModelError

__all__ = ["FlexibleSection"]


@dataclass(frozen=True)
class FlexibleSection:
    """A dimensional typical section with its aerodynamic model, for loads at any flight point.

    Parameters
    ----------
    aero : aeroelastic.MotionModel or sysid.FrequencyResponse
        Motion and gust model (inputs ``gust``, ``plunge``, ``pitch``; outputs ``Cl``, ``Cm`` about the elastic
        axis), at the flight points' Mach number; data are fitted once with :func:`aeroelastic.fit_motion`.
    mass : float
        Mass per unit span ``m`` (kg/m), > 0.
    a, x_alpha, r_alpha2 : float
        Elastic axis (semichords aft of mid-chord), centre of mass aft of it (semichords), radius of gyration
        squared about it (semichords^2), as :class:`aeroelastic.TypicalSection`.
    omega_h, omega_alpha : float
        Uncoupled plunge and pitch frequencies (rad/s), > 0.
    damping : float or (float, float)
        Modal damping ratios of the in-vacuo modes (:attr:`aeroelastic.TypicalSection.damping`); default 0.02,
        typical of a wing's structure.

    Raises
    ------
    aeroelastic.SectionError
        Section parameters out of range or not finite real numbers (a string or bool is refused, not converted;
        checked by :class:`aeroelastic.TypicalSection`), ``mass``, ``omega_h`` or ``omega_alpha`` not > 0.
    LoadsModelError
        ``aero`` without a gust model.
    aeroelastic.AeroModelError
        Data whose metadata put them about another axis than the elastic axis (see
        :func:`aeroelastic.to_elastic_axis`), or not a model or data.
    """

    aero: Any
    mass: float
    a: float
    x_alpha: float
    r_alpha2: float
    omega_h: float
    omega_alpha: float
    damping: Any = 0.02

    def __post_init__(self) -> None:
        import aeroelastic as ae

        for name in ("mass", "omega_h", "omega_alpha"):
            v = getattr(self, name)
            try:
                f = math.nan if isinstance(v, (bool, np.bool_, str, bytes)) else float(v)   # "100" was parsed
            except (TypeError, ValueError):
                f = math.nan
            if not (math.isfinite(f) and f > 0):
                raise ae.SectionError(f"{name} must be a positive, finite number (SI units), got {v!r}")
            object.__setattr__(self, name, f)
        # checks a, x_alpha, r_alpha2, damping (mu and the ratio are placeholders here)
        sec = self.typical_section(mu=1.0)
        object.__setattr__(self, "damping", sec.damping)
        from aeroelastic.coupling import as_motion_model, check_axis

        check_axis(self.aero, sec)          # data about another axis than the elastic axis: AeroModelError
        model = as_motion_model(self.aero)
        if not model.has_gust:
            raise LoadsModelError("the aerodynamic model has no gust input; fit data with inputs ['gust', 'plunge', "
                                  "'pitch']")
        object.__setattr__(self, "aero", model)

    @property
    def elastic_axis(self) -> float:
        """Chords from the leading edge, ``(1 + a) / 2``."""
        return 0.5 * (1.0 + self.a)

    def typical_section(self, point: FlightPoint | None = None, *, mu: float | None = None):
        """The :class:`aeroelastic.TypicalSection` at ``point`` (``mu = m / (pi rho b^2)``), or with ``mu`` given.

        Raises
        ------
        loads.FlightPointError
            No ``mu`` and ``point`` not a :class:`FlightPoint`.
        """
        import aeroelastic as ae

        if mu is None:
            b = 0.5 * check_point(point).chord_m
            mu = self.mass / (math.pi * point.rho * b * b)
        return ae.TypicalSection(mu=mu, a=self.a, x_alpha=self.x_alpha, r_alpha2=self.r_alpha2,
                                 omega_ratio=self.omega_h / self.omega_alpha, damping=self.damping)

    def speed_index(self, point: FlightPoint) -> float:
        """``V = U / (b omega_alpha)`` at ``point``.

        Raises
        ------
        loads.FlightPointError
            ``point`` not a :class:`FlightPoint`.
        """
        return check_point(point).tas / (0.5 * point.chord_m * self.omega_alpha)

    def state_space(self, point: FlightPoint):
        """``(A, B, C, D, inputs, outputs, scales)`` in convective time at ``point`` (see the module notes).

        Raises
        ------
        loads.FlightPointError
            ``point`` not a :class:`FlightPoint`.
        """
        import aeroelastic as ae

        sec = self.typical_section(point)
        V = self.speed_index(point)
        sys = ae.coupled_model(self.aero, sec, V, gust=True)
        A, B, C, D = (np.asarray(x, dtype=float) for x in (sys.A, sys.B, sys.C, sys.D))
        names = list(sys.output_labels)
        ip, ia, iacc = names.index("plunge"), names.index("pitch"), names.index("plunge_acc")
        C = np.vstack([C, C[iacc], C[ip], C[ia]])
        D = np.vstack([D, D[iacc], D[ip], D[ia]])
        names += ["load_factor", "plunge_spring", "pitch_spring"]
        c, wa = point.chord_m, self.omega_alpha
        b = 0.5 * c
        scales = {
            "plunge": (c, "m"), "pitch": (1.0, "rad"), "plunge_rate": (c * wa, "m/s"), "pitch_rate": (wa, "rad/s"),
            "plunge_acc": (c * wa**2, "m/s^2"), "pitch_acc": (wa**2, "rad/s^2"), "load_factor": (c * wa**2 / G0, "g"),
            "Cl": (point.q * c, "N/m"), "Cm": (point.q * c * c, "N m/m"),
            "plunge_spring": (self.mass * self.omega_h**2 * c, "N/m"),
            "pitch_spring": (self.mass * b * b * self.r_alpha2 * wa**2, "N m/m"),
        }
        k = 2.0 / V          # d/ds = (2 / V) d/dtau
        return k * A, k * B, C, D, list(sys.input_labels), names, scales
