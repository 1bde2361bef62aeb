"""lfdrom.cfd: a compact 2-D Euler solver (cell-centred JST) on NACA C-grids, and its linearisation.

Main entry points (``__all__``; the equations in docs/equations.md): geometry and grids :func:`naca`,
:func:`c_grid`, :func:`grid_quality`; the steady flow :func:`solve_steady`; gusts :class:`SineGust`,
:class:`OneMinusCosine`, :class:`SharpEdged`; the linearisation :func:`linearise` and its frequency-domain
(:func:`lfd_response`, with the fast sweep :func:`cfd.sweep.fast_sweep`, docs/lfd-sweep.md) and time-domain
(:func:`ltd_response`, :func:`ltd_responses`, :func:`coupled_ltd`) solutions; the nonlinear gust response
:func:`unsteady_response` and :func:`linearity` (docs/nonlinear.md); analytic references :func:`sears`,
:func:`sears_compressible`, :func:`kussner`, :func:`wagner`. Frequency responses are returned as
``sysid.FrequencyResponse`` (the data container); this package fits no models.
"""

from .errors import ConvergenceError, FlowConditionError, GeometryError, MeshError
from .geometry import Aerofoil, TabulatedAerofoil, naca, naca64a010
from .mesh import Grid, GridQuality, c_grid, grid_from_nodes, grid_quality
from .grid_presets import GRID_PRESETS, preset_grid
from .flow import FlowCondition, conserved, primitive
from .euler import Scheme, residual
from .jacobian import jacobian
from .loads import force_coefficients, wall_cp
from .steady import SteadySolution, solve_steady
from .analytic import AnalyticError, kussner, sears, sears_compressible, wagner
from .gust import GustError, GustPositionError, OneMinusCosine, SharpEdged, SineGust
from .linear import LinearError, LinearSystem, linearise
from .lfd import lfd_response
from .ltd import LTDHistory, ltd_response, ltd_responses
from .coupled import CoupledHistory, coupled_ltd
from .unsteady import (LocalMachError, NonPhysicalStateError, UnsteadyError, UnsteadyHistory, UnsteadyStepError,
                       unsteady_response)
from .linearity import LinearityResult, linearity

__all__ = [
    "ConvergenceError", "FlowConditionError", "GeometryError", "MeshError", "AnalyticError", "GustError",
    "GustPositionError", "LinearError", "LocalMachError", "NonPhysicalStateError", "UnsteadyError",
    "UnsteadyStepError",
    "Aerofoil", "TabulatedAerofoil", "naca", "naca64a010",
    "Grid", "GridQuality", "c_grid", "grid_from_nodes", "grid_quality", "GRID_PRESETS", "preset_grid",
    "FlowCondition", "conserved", "primitive", "Scheme", "residual", "jacobian", "force_coefficients", "wall_cp",
    "SteadySolution", "solve_steady",
    "kussner", "sears", "sears_compressible", "wagner",
    "OneMinusCosine", "SharpEdged", "SineGust",
    "LinearSystem", "linearise", "lfd_response", "LTDHistory", "ltd_response", "ltd_responses",
    "CoupledHistory", "coupled_ltd",
    "UnsteadyHistory", "unsteady_response", "LinearityResult", "linearity",
]
