"""Typed exceptions of the CFD layer.

Each subclasses a built-in exception so that callers may catch either the specific type or the
built-in one. Messages say what was wrong and what to do about it.
"""

__all__ = ["GeometryError", "MeshError", "FlowConditionError", "ConvergenceError", "UnsteadyError",
           "UnsteadyStepError", "NonPhysicalStateError", "LocalMachError", "MarchInterrupted"]


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


class UnsteadyError(ValueError):
    """Bad input to :func:`cfd.unsteady.unsteady_response`: a non-converged steady solution, bad ``dt``, method or gust."""


class UnsteadyStepError(ConvergenceError):
    """A time step of :func:`cfd.unsteady.unsteady_response` failed; the march stops there.

    Attributes
    ----------
    partial : cfd.unsteady.UnsteadyHistory
        The history up to the last converged step (``partial.complete`` is False).
    history : ndarray
        ``|F|`` per iteration of the failed step (the meaning of ``ConvergenceError.history``).
    step : int
        Index of the failed step (``t = step * dt``).
    time : float
        Its convective time.
    amplitude_deg : float
        The gust's peak angle.
    """

    def __init__(self, message, partial=None, history=None, step=None, time=None, amplitude_deg=None):
        super().__init__(message, history=history)
        self.partial = partial
        self.step = step
        self.time = time
        self.amplitude_deg = amplitude_deg


class NonPhysicalStateError(UnsteadyStepError):
    """The state reached non-positive density or pressure (or NaN) and a fresh Jacobian did not help."""


class LocalMachError(UnsteadyStepError):
    """The local Mach number exceeded ``max_local_mach``: a shock stronger than the study means to resolve."""


class SolveInterrupted(KeyboardInterrupt):
    """A steady solve (:func:`cfd.solve_steady`) was interrupted (Ctrl-C, or a ``KeyboardInterrupt`` raised by its
    ``progress`` callback): the interrupt propagates (``except KeyboardInterrupt`` still catches it) and carries
    the last state the solve accepted, from which ``solve_steady(..., q0=e.q)`` goes on (to the same tolerance: it
    is measured from the free stream's residual whatever the start).

    Attributes
    ----------
    q : ndarray, shape (ni-1, nj-1, 4)
        The last accepted state: the start, the state after the Runge-Kutta start, or after the last accepted
        Newton or chord step (a Runge-Kutta escape under way is not kept).
    history : ndarray
        Residual norm per accepted step up to the interrupt.
    newton_steps : int
        Newton steps taken.
    """

    def __init__(self, message, q=None, history=None, newton_steps=0):
        super().__init__(message)
        self.q = q
        self.history = history
        self.newton_steps = newton_steps


class SweepInterrupted(KeyboardInterrupt):
    """A fast frequency sweep (:func:`cfd.sweep.fast_sweep`, :func:`cfd.lfd_response` with the fast path) was
    interrupted (Ctrl-C, or a ``KeyboardInterrupt`` raised by its ``progress`` callback): the interrupt propagates
    and carries the reduced basis with every factorisation made so far, from which ``fast_sweep(..., basis=e.basis)``
    goes on (a basis grows in place; its factorisations are the sweep's cost).

    Attributes
    ----------
    basis : cfd.sweep.SweepBasis
    """

    def __init__(self, message, basis=None):
        super().__init__(message)
        self.basis = basis


class MarchInterrupted(KeyboardInterrupt):
    """A time march (:func:`cfd.unsteady_response`, :func:`cfd.ltd_response`, :func:`cfd.ltd_responses`) was
    interrupted (Ctrl-C, or a ``KeyboardInterrupt`` raised by its ``progress`` callback): the interrupt propagates
    (``except KeyboardInterrupt`` still catches it) and carries the history marched so far.

    Attributes
    ----------
    partial : cfd.ltd.LTDHistory, cfd.unsteady.UnsteadyHistory or list of LTDHistory
        The history up to the last completed step (``partial.t[-1]`` its time; an ``UnsteadyHistory`` has
        ``complete`` False; a list, one per gust, for :func:`cfd.ltd_responses`). None when the interrupt came
        before the first step was set up.
    step : int
        Index of the last completed step (``t = step * dt``).
    time : float
        Its convective time.
    """

    def __init__(self, message, partial=None, step=None, time=None):
        super().__init__(message)
        self.partial = partial
        self.step = step
        self.time = time
