"""lfdrom.sysid: frequency-domain subspace identification with convex constrained refits.

Works on any frequency-response data; knows nothing of CFD.
"""

from .errors import ConstraintError, FrequencyDataError, FrequencyGridError, OrderError, SolverError
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

__all__ = [
    "ConstraintError",
    "FrequencyDataError",
    "FrequencyGridError",
    "OrderError",
    "SolverError",
    "FrequencyResponse",
    "mckelvey_grid",
    "discrete_to_continuous",
    "continuous_to_discrete",
    "HankelSVD",
    "SubspaceResult",
    "hankel_svd",
    "hankel_singular_values",
    "mckelvey1",
    "mckelvey2",
    "subspace_identify",
]
