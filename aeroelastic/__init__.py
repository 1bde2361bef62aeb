"""lfdrom.aeroelastic: the typical section coupled with a state-space aerodynamic model.

Flutter as an eigenvalue problem and the gust response of the flexible section, from frequency-response
data of the section's motion (and gust). Uses :mod:`sysid` and python-control; knows nothing of CFD.

Main entry points: :class:`TypicalSection`, :func:`fit_motion`, :func:`change_axes`, :func:`coupled_model`,
:func:`flutter`, :func:`divergence_speed`, :func:`gust_response`, the plots :func:`root_locus_plot`,
:func:`vg_plot`, :func:`flutter_plot`, :func:`gust_response_plot`, and the analytic references in
:mod:`aeroelastic.theodorsen`.
"""

from .errors import AeroModelError, FitError, SectionError, SpeedError
from .section import TypicalSection
from .fit import MotionModel, fit_motion
from .axes import change_axes, to_elastic_axis
from .coupling import coupled_model
from .flutter import FlutterResult, divergence_speed, flutter, root_locus_response
from .gust import GustResponse, gust_response
from .plots import flutter_plot, gust_response_plot, root_locus_plot, vg_plot
from . import theodorsen

__all__ = [
    "AeroModelError", "FitError", "SectionError", "SpeedError",
    "TypicalSection", "MotionModel", "fit_motion", "change_axes", "to_elastic_axis", "coupled_model",
    "FlutterResult", "flutter", "divergence_speed", "root_locus_response",
    "GustResponse", "gust_response",
    "flutter_plot", "gust_response_plot", "root_locus_plot", "vg_plot",
    "theodorsen",
]
