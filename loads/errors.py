"""Typed errors of the loads package (each subclasses a built-in so callers can catch either)."""

from __future__ import annotations

__all__ = ["FlightPointError", "GustError", "LoadsModelError", "SpectrumError"]


class FlightPointError(ValueError):
    """A flight point is outside what the atmosphere or the rule covers (Mach, altitude, chord, F_g), or a ``point``
    argument is not a :class:`loads.FlightPoint`."""


class GustError(ValueError):
    """A gust setting is unusable: H range outside the rule's without saying so, tolerances, counts."""


class LoadsModelError(ValueError):
    """The model cannot give gust loads: no ``"gust"`` input, an unknown output, an unstable system, a type the
    package does not take; or it is asked for at frequencies that are not real and finite."""


class SpectrumError(ArithmeticError):
    """A continuous-turbulence integral does not converge (e.g. ``N0`` of an output with a feedthrough ``D``, whose
    ``omega^2 |H|^2 Phi`` grows like ``Omega^(1/3)``) or cannot be estimated from the data given."""
