"""Limits on the model order that :func:`sysid.identify` accepts for a grid and a method.

:func:`max_order` mirrors the Hankel sizes of :func:`sysid.subspace.default_q` and the bounds of
``HankelSVD.max_order``, so that a caller (e.g. a study file's validation) can refuse an order before any data
exist; :func:`min_order` counts the equality constraints of the refits.
"""

from __future__ import annotations

from typing import Any, Optional

import numpy as np

from .errors import FrequencyGridError, OptionError, OrderError
from .subspace import default_q

__all__ = ["max_order", "min_order", "order_supported", "MAX_ORDER_ALGORITHMS"]

MAX_ORDER_ALGORITHMS = ("auto", "subspace", "relocation", "mckelvey1", "mckelvey2")
"""What :func:`max_order` accepts: ``"mckelvey2"`` bounds Algorithm 2, the others Algorithm 1 (the subspace step
of ``sysid.identify`` on McKelvey's grid, whichever identification algorithm follows it)."""


def _count(value: Any, name: str, error=OptionError) -> int:
    """``value`` as a positive int (NumPy integers accepted, bool refused), else ``error``."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise error(f"{name} must be a positive integer, got {value!r}")
    return int(value)


def max_order(M: int, algorithm: str = "auto", p: int = 2, m: int = 1, order: Optional[int] = None) -> int:
    """Largest model order ``sysid.identify`` accepts on McKelvey's grid with ``M + 1`` frequencies.

    Uses :func:`sysid.subspace.default_q` for the Hankel sizes that ``identify`` picks for a target ``order``
    and the bounds of ``HankelSVD.max_order``: for Algorithm 1 (``"auto"`` on the equispaced grid and
    ``"mckelvey1"``) ``q = min(M, 2 n + 2)``, ``r = 2 M - q`` and ``n <= min(q - 1, (q - 1) p, r m, #sv)``,
    which is ``M - 1`` for the large orders; for Algorithm 2 ``q = min(q_max, 2 n + 2)``,
    ``q_max = floor(2 K m / (m + p)) - 1`` and ``n <= q - 1``.

    Parameters
    ----------
    M : int
        Grid intervals (``N_omega = M + 1``).
    algorithm : {"auto", "subspace", "relocation", "mckelvey1", "mckelvey2"}
        ``"mckelvey2"``: Algorithm 2; any other: Algorithm 1 (the subspace step on McKelvey's grid).
    p, m : int
        Outputs and inputs.
    order : int, optional
        The target order (the Hankel sizes depend on it); default the largest the grid could support.

    Returns
    -------
    int
        0 when no order is possible.

    Raises
    ------
    FrequencyGridError
        ``M`` not a positive integer.
    OrderError
        ``order`` not a positive integer.
    OptionError
        Unknown ``algorithm``; ``p`` or ``m`` not a positive integer.
    """
    M = _count(M, "M (number of grid intervals)", FrequencyGridError)
    p, m = _count(p, "p (outputs)"), _count(m, "m (inputs)")
    if order is not None:
        order = _count(order, "order", OrderError)
    if algorithm not in MAX_ORDER_ALGORITHMS:
        raise OptionError(f"algorithm must be one of {MAX_ORDER_ALGORITHMS}, got {algorithm!r}")
    K = M + 1
    method = "mckelvey2" if algorithm == "mckelvey2" else "mckelvey1"
    n = order if order is not None else M  # large target: the sizes saturate
    q, r = default_q(method, p, m, K, n)
    if method == "mckelvey1":
        if q < 2 or r < 1 or q + r > 2 * M:
            return 0
        return max(0, min(q - 1, (q - 1) * p, r * m, min(q * p, r * m)))
    if q < 2 or q * (m + p) > 2 * K * m:
        return 0
    return max(0, min(q - 1, (q - 1) * p, q * p))


def order_supported(order: int, M: int, algorithm: str, p: int, m: int = 1) -> bool:
    """Whether ``order`` is at most :func:`max_order` for that target order (arguments as there)."""
    return order <= max_order(M, algorithm, p, m, order=order)


def min_order(p: int, m: int = 1, dc_gain: str = "none", algorithm: str = "subspace") -> int:
    """Smallest model order whose identification can meet the method's equality constraints.

    Subspace path: the refit of ``B`` and ``D`` (``sysid.refit.fit_bd``) has ``(n + p) m`` unknowns; on
    McKelvey's grid the ``omega = inf`` sample is always present and fixes the feedthrough (``p m``
    equations), and ``dc_gain = "match"`` adds the DC gain (``p m`` more). With both, ``n m >= p m``: at
    least ``p`` states (order 1 with two outputs and the exact DC gain has 3 unknowns for 4 equations).
    Relocation path (``sysid.relocation``): residues per pole and output, the feedthrough given, one DC
    equation per output and input: at least one state per input column (``min(p, m)``, it fits the transpose
    when ``p < m``).

    Parameters
    ----------
    p, m : int
        Outputs and inputs.
    dc_gain : {"none", "match"}
    algorithm : {"subspace", "relocation"}
        As :func:`sysid.identify.resolve_algorithm` decides it.

    Returns
    -------
    int

    Raises
    ------
    OptionError
        ``p`` or ``m`` not a positive integer, unknown ``dc_gain`` or ``algorithm``.
    """
    p, m = _count(p, "p (outputs)"), _count(m, "m (inputs)")
    if dc_gain not in ("none", "match"):
        raise OptionError(f"dc_gain must be 'none' or 'match', got {dc_gain!r}")
    if algorithm not in ("subspace", "relocation"):
        raise OptionError(f"algorithm must be 'subspace' or 'relocation' (sysid.identify.resolve_algorithm), "
                          f"got {algorithm!r}")
    if algorithm == "relocation":
        return max(1, min(p, m))
    return max(1, p) if dc_gain == "match" else 1
