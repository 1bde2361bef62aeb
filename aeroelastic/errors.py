"""Typed errors of the aeroelastic package (each subclasses a built-in so callers can catch either)."""

from __future__ import annotations

__all__ = ["SectionError", "AeroModelError", "SpeedError", "FitError"]


class SectionError(ValueError):
    """A typical-section parameter is out of range (e.g. ``mu <= 0`` or ``r_alpha2 <= x_alpha**2``)."""


class AeroModelError(ValueError):
    """The aerodynamic model or data do not suit the request (missing channels, no frequencies, ...)."""


class SpeedError(ValueError):
    """A speed (index) is not positive and finite, a speed grid is unusable, or so is the instability threshold
    (``tol``) of the search along it."""


class FitError(RuntimeError):
    """The rational fit of the motion response could not be formed (e.g. too few frequencies for the order)."""
