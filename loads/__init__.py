"""lfdrom.loads: certification gust loads (CS-25.341 / 14 CFR 25.341) from gust ROMs.

Tuned discrete 1-cosine gusts (:func:`tuned_gust`) and continuous turbulence (:func:`continuous_turbulence`)
at a :class:`FlightPoint` (the ICAO standard atmosphere), for a rigid section (a :mod:`sysid` ROM or any
state-space gust model) or a flexible one (:class:`FlexibleSection`, the :mod:`aeroelastic` coupled section
with structural damping); dimensional loads per unit span; correlated-load, load-versus-H and PSD plots.
Uses sysid, aeroelastic and python-control; knows nothing of CFD or studies.
"""

from .errors import FlightPointError, GustError, LoadsModelError, SpectrumError
from .atmosphere import FlightPoint, alleviation_factor
from .flexible import FlexibleSection
from .system import GustSystem, gust_system
from .tuned_gust import TunedGustResult, tuned_gust
from .turbulence import TurbulenceResult, continuous_turbulence, von_karman
from .plots import correlated_loads_plot, gust_history_plot, load_vs_H_plot, psd_plot, turbulence_ellipse

__all__ = [
    "FlightPointError", "GustError", "LoadsModelError", "SpectrumError",
    "FlightPoint", "alleviation_factor", "FlexibleSection", "GustSystem", "gust_system",
    "TunedGustResult", "tuned_gust", "TurbulenceResult", "continuous_turbulence", "von_karman",
    "correlated_loads_plot", "gust_history_plot", "load_vs_H_plot", "psd_plot", "turbulence_ellipse",
]
