"""lfdrom.cfd: a compact 2-D Euler solver (cell-centred JST) on NACA C-grids, and its linearisation.

Public entry points are listed in shared/DESIGN.md; this package knows nothing of identification.
"""

from .errors import ConvergenceError, FlowConditionError, GeometryError, MeshError
from .geometry import Aerofoil, TabulatedAerofoil, naca, naca64a010
from .mesh import Grid, GridQuality, c_grid, grid_from_nodes, grid_quality
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
