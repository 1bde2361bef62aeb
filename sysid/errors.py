"""Typed exceptions of the identification layer.

Each subclasses a built-in exception so that callers may catch either the specific type or the
built-in one (``except ValueError``). Messages say what was wrong and what to do about it.
"""

__all__ = [
    "FrequencyDataError",
    "FrequencyGridError",
    "OrderError",
    "ConstraintError",
    "SolverError",
    "ModelError",
    "TimeDataError",
    "OptionError",
    "FrequencyIndexError",
    "FrequencyFileError",
    "ArgumentTypeError",
]


class FrequencyDataError(ValueError):
    """Frequency-response data are malformed: wrong shape, NaN or inf, inconsistent sizes."""


class FrequencyIndexError(FrequencyDataError, IndexError):
    """Frequency indices that do not select samples of the data (out of range, not whole numbers, a mask of
    another length); also an ``IndexError``."""


class FrequencyFileError(FrequencyDataError, OSError):
    """A path that is not a file :meth:`sysid.FrequencyResponse.save` wrote (another format, not a zip), or
    that cannot be written as one (a directory); also an ``OSError``."""


class FrequencyGridError(ValueError):
    """Frequencies are unusable: not equispaced where required, outside [0, pi], T <= 0, ..."""


class OrderError(ValueError):
    """The requested model order is not supported by the data or by the Hankel sizes."""


class TimeDataError(ValueError):
    """A time history is unusable for a simulation: times not equispaced or not increasing, an input of
    another length than the times."""


class OptionError(ValueError):
    """An option has a value the function does not take: an unknown method or solver name, a margin or
    fraction outside its range, a count that is not a whole number."""


class ConstraintError(ValueError):
    """A requested constraint cannot be imposed (e.g. a DC constraint with a pole at z = 1)."""


class SolverError(RuntimeError):
    """A convex solver failed (infeasible, unbounded or numerical failure)."""


class ModelError(ValueError):
    """A state-space model is of the wrong kind for the operation (discrete vs continuous) or is
    singular where the operation needs an inverse (e.g. a pole at z = -1 for the bilinear map)."""


class ArgumentTypeError(TypeError):
    """An argument of the wrong kind of object (``identify(None, 4)``, a NumPy array where a
    :class:`sysid.FrequencyResponse` or a ``control.StateSpace`` is expected); also a ``TypeError``."""
