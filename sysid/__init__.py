"""lfdrom.sysid: frequency-domain subspace identification with convex constrained refits.

Works on any frequency-response data; knows nothing of CFD.

Main entry points: :class:`FrequencyResponse`, :func:`mckelvey_grid`, :func:`identify`,
:func:`order_sweep`, :func:`d2c_bilinear`, :func:`c2d_bilinear`, :func:`c2d_zoh`; a ROM's time response
:func:`rom_response` (:mod:`sysid.simulate`) and its errors against a reference history
(:mod:`sysid.history_metrics`); the order limits :func:`max_order`, :func:`min_order`.
"""

from .errors import (ArgumentTypeError, ConstraintError, FrequencyDataError, FrequencyFileError, FrequencyGridError,
                     FrequencyIndexError, ModelError, OptionError, OrderError, SolverError, TimeDataError)
from .frd import FrequencyResponse, continuous_to_discrete, discrete_to_continuous, mckelvey_grid
from .subspace import (
    HankelSVD,
    SubspaceResult,
    hankel_singular_values,
    hankel_svd,
    mckelvey1,
    mckelvey2,
    subspace_identify,
)
from .transforms import c2d_bilinear, c2d_zoh, d2c_bilinear
from .metrics import (
    FitErrors,
    dc_error,
    frf_errors,
    max_relative_error,
    rms_relative_error,
    rom_metrics,
    spectral_radius,
)
from .history_metrics import envelope_errors, history_errors, peak
from .simulate import markov_parameters, rediscretise, rom_response, rom_simulation, simulate_discrete
from .order import OrderSweep, order_sweep
from .order_limits import max_order, min_order
from .identify import IdentificationResult, StabilisationReport, identify
from .identification_result import ModelMatrices
from .diagnostics import DataDiagnostics, diagnose
from .noise import noise_level
from .refit import BDFit, CDFit, fit_alternating, fit_bd, fit_cd
from .stability import StabiliseResult, stabilise
from .relocation import RelocationResult, fit_relocated

__all__ = [
    "noise_level",
    # errors
    "ConstraintError",
    "FrequencyDataError",
    "FrequencyGridError",
    "OrderError",
    "SolverError",
    "ModelError",
    "TimeDataError",
    "OptionError",
    "FrequencyIndexError",
    "FrequencyFileError",
    "ArgumentTypeError",
    # data
    "FrequencyResponse",
    "mckelvey_grid",
    "discrete_to_continuous",
    "continuous_to_discrete",
    # subspace
    "HankelSVD",
    "SubspaceResult",
    "hankel_svd",
    "hankel_singular_values",
    "mckelvey1",
    "mckelvey2",
    "subspace_identify",
    # transforms
    "d2c_bilinear",
    "c2d_bilinear",
    "c2d_zoh",
    # metrics
    "FitErrors",
    "frf_errors",
    "max_relative_error",
    "rms_relative_error",
    "dc_error",
    "spectral_radius",
    "rom_metrics",
    # time histories (sysid.simulate, sysid.history_metrics)
    "markov_parameters",
    "simulate_discrete",
    "rediscretise",
    "rom_simulation",
    "rom_response",
    "peak",
    "envelope_errors",
    "history_errors",
    # order selection and limits
    "OrderSweep",
    "order_sweep",
    "max_order",
    "min_order",
    # pipeline
    "identify",
    "IdentificationResult",
    "StabilisationReport",
    "ModelMatrices",
    "diagnose",
    "DataDiagnostics",
    # convex refits and stability (sysid.refit, sysid.stability)
    "BDFit",
    "CDFit",
    "fit_bd",
    "fit_cd",
    "fit_alternating",
    "StabiliseResult",
    "stabilise",
    # pole relocation (sysid.relocation): the default stable / DC-exact path of identify
    "RelocationResult",
    "fit_relocated",
]
