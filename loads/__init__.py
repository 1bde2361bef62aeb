"""lfdrom.loads: certification gust loads (CS-25.341 / 14 CFR 25.341) from gust ROMs (flight points first)."""

from .errors import FlightPointError, GustError, LoadsModelError, SpectrumError
from .atmosphere import FlightPoint, alleviation_factor

__all__ = ["FlightPointError", "GustError", "LoadsModelError", "SpectrumError", "FlightPoint", "alleviation_factor"]
