"""lfdrom.cfd: a compact 2-D Euler solver (cell-centred JST) on NACA C-grids, and its linearisation.

Main entry points (``__all__``; the equations in docs/equations.md): geometry and grids :func:`naca`,
:func:`c_grid`, :func:`grid_quality`; the steady flow :func:`solve_steady`; gusts :class:`SineGust`,
:class:`OneMinusCosine`, :class:`SharpEdged`; the linearisation :func:`linearise` and its frequency-domain
(:func:`lfd_response`, with the fast sweep :func:`cfd.sweep.fast_sweep`, docs/lfd-sweep.md) and time-domain
(:func:`ltd_response`, :func:`ltd_responses`, :func:`coupled_ltd`) solutions; the nonlinear gust response
:func:`unsteady_response` and :func:`linearity` (docs/nonlinear.md); analytic references :func:`sears`,
:func:`sears_compressible`, :func:`kussner`, :func:`wagner`. Frequency responses are returned as
``sysid.FrequencyResponse`` (the data container); this package fits no models.

Layout, in the order of the data (each stage imports only the stages above it; ``errors`` and ``checks``, the
error classes and the shared argument checks, serve all):

1. :mod:`cfd.mesh` (sub-package): the aerofoil (``geometry``), point distributions (``spacing``) and the
   elliptic smoother (``elliptic``) -> the C-grid (``generation``) -> its finite-volume metrics (``metrics``:
   :class:`Grid`), ``quality`` and the named grids (``presets``).
2. The flow and its physics: :mod:`cfd.flow` (conserved and primitive variables), :mod:`cfd.boundary` (wall and
   far field), :mod:`cfd.euler` (the JST residual), :mod:`cfd.loads` (force coefficients).
3. The steady state: :mod:`cfd.steady` (Runge-Kutta start, then pseudo-transient Newton with the exact Jacobian
   of :mod:`cfd.jacobian`; the sparse LU of :mod:`cfd.superlu` with the nested-dissection ordering of
   :mod:`cfd.ordering`, which the linear solutions below use too).
4. The linearisation about it: :mod:`cfd.linear` (:class:`LinearSystem`), with the gust forcing of
   :mod:`cfd.gust`, the prescribed motion of :mod:`cfd.motion` and the frequency checks of :mod:`cfd.frequencies`.
5. Its solutions: in frequency (LFD) :mod:`cfd.lfd` (one solve per frequency) and :mod:`cfd.sweep` (sub-package:
   the fast reduced-basis sweep, ``basis``, ``orthonormal``, ``workers``); in time (LTD) :mod:`cfd.ltd`
   (sub-package: the BDF2 / Radau IIA march, ``radau``, and the march with a structure, ``coupled``).
6. The nonlinear march :mod:`cfd.unsteady` and the linearity test :mod:`cfd.linearity`; the analytic references
   :mod:`cfd.analytic`; output: :mod:`cfd.export` and :mod:`cfd.plots`.

The module paths of the flat package before this layout (``cfd.mesh_metrics``, ``cfd.sweep_basis``,
``cfd.coupled``, ...) still import, with a ``DeprecationWarning`` (:mod:`cfd.legacy`).
"""

from .legacy import install as _install_legacy_paths
from .errors import (ConvergenceError, FlowConditionError, GeometryError, MarchInterrupted, MeshError,
                     SolveInterrupted, SweepInterrupted)
from .mesh.geometry import Aerofoil, TabulatedAerofoil, naca, naca64a010
from .mesh import Grid, GridQuality, c_grid, grid_from_nodes, grid_quality
from .mesh.presets import GRID_PRESETS, preset_grid
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
from .ltd.coupled import CoupledHistory, coupled_ltd
from .unsteady import (LocalMachError, NonPhysicalStateError, UnsteadyError, UnsteadyHistory, UnsteadyStepError,
                       unsteady_response)
from .linearity import LinearityResult, linearity

_install_legacy_paths()

__all__ = [
    "ConvergenceError", "FlowConditionError", "GeometryError", "MeshError", "AnalyticError", "GustError",
    "GustPositionError", "LinearError", "LocalMachError", "NonPhysicalStateError", "UnsteadyError",
    "UnsteadyStepError", "MarchInterrupted", "SolveInterrupted", "SweepInterrupted",
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
