"""Canonical JSON and its hash: the form in which configurations key the results store.

Sorted keys, no spaces, floats normalised to 12 significant digits (:func:`studies.config.numbers.normalise_float`),
ASCII; dataclasses by their fields, paths as strings.
"""

from __future__ import annotations

import hashlib
import json
import math
import numbers
from pathlib import Path
from typing import Mapping

from .numbers import normalise_float

__all__ = ["canonical_json", "config_hash", "dataclass_dict"]


def dataclass_dict(obj) -> dict:
    """The fields of a dataclass instance, by name (not recursive)."""
    return {k: getattr(obj, k) for k in obj.__dataclass_fields__}


def _canon(obj):
    if isinstance(obj, bool) or obj is None or isinstance(obj, str):
        return obj
    if isinstance(obj, numbers.Integral):
        return int(obj)
    if isinstance(obj, numbers.Real):
        v = float(obj)
        if not math.isfinite(v):
            raise ValueError(f"canonical_json: non-finite number {v!r}")
        return normalise_float(v)
    if isinstance(obj, Mapping):
        out = {}
        for k, v in obj.items():
            if not isinstance(k, str):
                raise TypeError(f"canonical_json: keys must be strings, got {k!r}")
            out[k] = _canon(v)
        return out
    if isinstance(obj, (list, tuple)):
        return [_canon(v) for v in obj]
    if isinstance(obj, Path):
        return str(obj)
    if hasattr(obj, "__dataclass_fields__"):
        return _canon(dataclass_dict(obj))
    raise TypeError(f"canonical_json: cannot encode {type(obj).__name__} {obj!r}")


def canonical_json(obj) -> str:
    """Canonical JSON: sorted keys, no spaces, floats normalised to 12 significant digits, ASCII.

    Accepts dicts, lists, tuples, strings, numbers, booleans, None, paths and dataclasses.
    """
    return json.dumps(_canon(obj), sort_keys=True, separators=(",", ":"), ensure_ascii=True, allow_nan=False)


def config_hash(obj) -> str:
    """sha256 (hex) of :func:`canonical_json`."""
    return hashlib.sha256(canonical_json(obj).encode()).hexdigest()
