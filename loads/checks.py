"""Checks of the loads package's numeric inputs, shared by its modules."""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["real_values"]


def real_values(value: Any) -> np.ndarray | None:
    """``value`` as a float array when it is a real number or an array of real numbers (ints and floats of any
    width), else None: text, None, complex and boolean values, and what NumPy cannot make an array of. The caller
    raises its own typed error, naming the argument; NaN and inf pass (the caller's range checks decide)."""
    try:
        arr = np.asarray(value)
    except (TypeError, ValueError):
        return None
    return arr.astype(float) if arr.dtype.kind in "iuf" else None
