"""lfdrom.sysid: frequency-domain subspace identification with convex constrained refits.

Works on any frequency-response data; knows nothing of CFD.
"""

from .errors import ConstraintError, FrequencyDataError, FrequencyGridError, OrderError, SolverError
