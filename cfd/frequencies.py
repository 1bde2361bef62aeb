"""Frequency arguments of the linearised solvers: checked frequency arrays, McKelvey pairs and ``x_ref``.

Shared by the direct path (:mod:`cfd.lfd`) and the fast sweep (:mod:`cfd.sweep`), which accept the same forms.
"""

import numpy as np

from .linear import LinearError

__all__ = ["frequencies", "frequency_grid", "check_x_ref"]


def frequencies(omega):
    """Accept an array of frequencies or the ``(omega_d, omega)`` pair of ``sysid.mckelvey_grid``."""
    omega_d = None
    if isinstance(omega, tuple) and len(omega) == 2 and all(np.ndim(o) == 1 for o in omega):
        omega_d, omega = (np.asarray(o, dtype=float) for o in omega)
    try:
        w = np.atleast_1d(np.asarray(omega, dtype=float))
    except (TypeError, ValueError):
        raise LinearError(f"omega must be an array of real frequencies (U/c units); got {omega!r}") from None
    if w.ndim != 1 or w.size == 0:
        raise LinearError(f"omega must be a non-empty 1-D array of frequencies; got shape {w.shape}")
    if np.any(np.isnan(w)) or np.any(w == -np.inf):
        raise LinearError("omega contains NaN or -inf; give nonnegative frequencies (inf allowed: feedthrough)")
    if np.any(w < 0.0):
        raise LinearError(
            f"omega must be >= 0 (found {w[w < 0][0]!r}): only positive frequencies are solved, the response at "
            "-omega is the complex conjugate"
        )
    return omega_d, w


def frequency_grid(omega, T):
    """Frequencies (checked) and the sampling period: ``T`` as given, else recovered from a McKelvey pair."""
    omega_d, w = frequencies(omega)
    if T is None and omega_d is not None:
        inner = np.isfinite(w) & (w > 0)
        if np.any(inner):
            k = np.flatnonzero(inner)[0]
            T = 2.0 * np.tan(omega_d[k] / 2.0) / w[k]
    return w, T


def check_x_ref(x_ref):
    """The gust reference point (chords), checked finite."""
    x_ref = float(x_ref)
    if not np.isfinite(x_ref):
        raise LinearError(f"x_ref must be finite (chords); got {x_ref!r}")
    return x_ref
