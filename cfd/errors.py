"""Typed exceptions of the CFD layer.

Each subclasses a built-in exception so that callers may catch either the specific type or the
built-in one. Messages say what was wrong and what to do about it.
"""

__all__ = ["GeometryError", "MeshError", "FlowConditionError", "ConvergenceError"]


class GeometryError(ValueError):
    """An aerofoil definition is invalid (e.g. a malformed NACA code)."""


class MeshError(ValueError):
    """A grid is unusable: too small for the stencil, inverted or degenerate cells, bad sizes."""


class FlowConditionError(ValueError):
    """A flow condition is out of range (e.g. Mach <= 0 or >= 1)."""


class ConvergenceError(RuntimeError):
    """A solver diverged or stalled.

    Attributes
    ----------
    history : numpy.ndarray
        Residual norm per iteration up to the failure, so that the caller can see what happened.
    """

    def __init__(self, message, history=None):
        super().__init__(message)
        self.history = history
