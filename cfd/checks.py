"""Argument checks shared by the solvers: whole numbers given as ints, numpy integers or whole-valued floats."""

import math

__all__ = ["whole_number"]


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
    if isinstance(value, (bool, str, bytes)) or value is None:
        return None
    try:
        f = float(value)
    except (TypeError, ValueError):
        return None
    if math.isinf(f) and f > 0 and allow_inf:
        return math.inf
    if not math.isfinite(f) or f != int(f):
        return None
    return int(f)
