"""Read-only arrays for the frozen result objects: a result's arrays cannot be changed in place by its reader
(``fit.B[0, 0] = 1`` raises ``ValueError: assignment destination is read-only``)."""

from __future__ import annotations

import dataclasses

import numpy as np

__all__ = ["read_only", "freeze_array_fields"]


def read_only(a):
    """A read-only copy of the array ``a`` (None stays None).

    Parameters
    ----------
    a : ndarray or None

    Returns
    -------
    ndarray or None
        Same shape and dtype, ``flags.writeable`` False; the caller's array is not touched.
    """
    if a is None:
        return None
    a = np.array(a, copy=True)
    a.setflags(write=False)
    return a


def freeze_array_fields(obj) -> None:
    """Replace every ndarray field of the frozen dataclass instance ``obj`` by a read-only copy (for
    ``__post_init__``; other field types are left as they are)."""
    for f in dataclasses.fields(obj):
        value = getattr(obj, f.name)
        if isinstance(value, np.ndarray):
            object.__setattr__(obj, f.name, read_only(value))
