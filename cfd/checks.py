"""Argument checks shared by the solvers: real numbers (not bools or text); whole numbers given as ints, numpy
integers or whole-valued floats; arrays of real numbers; the message for an argument that is not a grid; flags, progress callbacks and log intervals
(each raising the caller's own error class)."""

import math

import numpy as np

__all__ = ["real_number", "whole_number", "real_array", "kind_of", "not_a_grid", "flag", "callback", "log_interval"]


def real_number(value):
    """``value`` as a float if it is a real number (an int, float, numpy scalar or 0-d array of one; NaN and inf
    included: the caller checks the range), else None: a bool (``True`` is not 1.0 here), text (``"0.5"`` would be
    parsed by ``float``), None, a complex number (``float`` keeps a numpy complex's real part with only a
    ``ComplexWarning``) or anything ``float`` refuses.

    Parameters
    ----------
    value : object

    Returns
    -------
    float or None
    """
    if isinstance(value, (bool, np.bool_, str, bytes)) or value is None or np.iscomplexobj(value):
        return None
    try:
        return float(value)
    except (TypeError, ValueError):
        return None


def whole_number(value, allow_inf=False):
    """``value`` as an int if it is a whole number (``3``, ``np.int64(3)``, ``3.0``, a 0-d array of one), else
    None (``True``, ``2.5``, NaN, ``"3"``, None...); with ``allow_inf``, ``inf`` (a limit that never binds) is
    returned as ``math.inf``.

    Parameters
    ----------
    value : object
    allow_inf : bool

    Returns
    -------
    int, float (inf) or None
    """
    f = real_number(value)
    if f is None:
        return None
    if math.isinf(f) and f > 0 and allow_inf:
        return math.inf
    if not math.isfinite(f) or f != int(f):
        return None
    return int(f)


def real_array(value):
    """``value`` as a float array if it holds real numbers (bool, int or float dtype), else None.

    Parameters
    ----------
    value : array_like

    Returns
    -------
    ndarray of float or None
    """
    try:
        v = np.asarray(value)
    except (TypeError, ValueError):
        return None
    return v.astype(float) if v.dtype.kind in "biuf" else None


def kind_of(value):
    """What ``value`` is, for a message: ``"dtype complex128"`` for an array, else its type's name."""
    return f"dtype {value.dtype}" if isinstance(value, np.ndarray) else type(value).__name__


def not_a_grid(value):
    """The message for a ``grid`` argument that is not a :class:`cfd.Grid` (each caller raises its own error)."""
    return f"grid must be a cfd.Grid (from cfd.c_grid or cfd.grid_from_nodes); got {type(value).__name__}"


def flag(name, value, error):
    """``value`` if it is a bool (``True``/``False`` or a numpy bool), else ``error`` naming ``name``: a truthy
    string such as ``"no"`` would otherwise turn an option on."""
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    raise error(f"{name} must be True or False; got {value!r}")


def callback(name, value, error):
    """``value`` if it is None or callable, else ``error`` naming ``name`` (raised before any work, not at the
    first step)."""
    if value is None or callable(value):
        return value
    raise error(f"{name} must be a callable or None; got {type(value).__name__} {value!r}")


def log_interval(value, error):
    """``log_interval`` (seconds between progress lines) as a float: a number >= 0 (0 logs every step, inf never),
    else ``error``."""
    v = real_number(value)
    if v is None or not v >= 0.0:
        raise error(f"log_interval must be a number of seconds >= 0 (default 60; inf: never log); got {value!r}")
    return v
