"""Arguments of the linearised solvers: checked frequency arrays, McKelvey pairs, ``x_ref`` and the pivot.

Shared by the direct path (:mod:`cfd.lfd`) and the fast sweep (:mod:`cfd.sweep`), which accept the same forms.
"""

import numpy as np

from .checks import kind_of, real_array, real_number
from .linear import LinearError

__all__ = ["frequencies", "frequency_grid", "check_position", "check_x_ref", "check_pivot",
           "check_motion_frequencies", "check_tol", "MAX_FREQUENCIES", "MAX_POSITION"]

MAX_FREQUENCIES = 100_000
"""Most frequencies one LFD call takes: each is a sparse factorisation on the direct path (about 0.1 s on the paper
grid, so 1e5 are some 3 hours) and a reduced solve plus its outputs on the fast sweep; the paper's grids have 257. A
larger array is a mistake of units or of ``sysid.mckelvey_grid``'s ``M`` (1e9 frequencies asked for 8 GB before the
first solve); split a genuine larger sweep into calls."""


def _real_frequencies(name, value):
    """``value`` as a float array if it holds real numbers, else :class:`LinearError` naming ``name``: a complex
    frequency was cast to its real part with only a ``ComplexWarning``, a string such as ``"1.0"`` parsed."""
    v = real_array(value)   # (None for text: its dtype is not numeric)
    if v is None:
        raise LinearError(f"{name} must be an array of real frequencies (U/c units); got {kind_of(value)} "
                          f"{value!r:.80}")
    return v


def frequencies(omega):
    """Accept an array of frequencies or the ``(omega_d, omega)`` pair of ``sysid.mckelvey_grid``.

    Parameters
    ----------
    omega : array_like or tuple of two 1-D arrays
        Real frequencies >= 0 (U/c units; ``inf``: the feedthrough), or the pair ``(omega_d, omega)``.

    Returns
    -------
    omega_d : ndarray or None
    omega : ndarray

    Raises
    ------
    LinearError
        If the frequencies are not real numbers (complex, strings, objects), not a non-empty 1-D array, too many,
        NaN, -inf or negative.
    """
    omega_d = None
    if isinstance(omega, tuple) and len(omega) == 2 and all(np.ndim(o) == 1 for o in omega):
        omega_d, omega = _real_frequencies("omega_d", omega[0]), omega[1]
    w = np.atleast_1d(_real_frequencies("omega", omega))
    if w.ndim != 1 or w.size == 0:
        raise LinearError(f"omega must be a non-empty 1-D array of frequencies; got shape {w.shape}")
    if w.size > MAX_FREQUENCIES:
        raise LinearError(f"omega holds {w.size} frequencies, more than cfd.frequencies.MAX_FREQUENCIES = "
                          f"{MAX_FREQUENCIES}: check the grid (the paper's has 257), or split the sweep into calls")
    if np.any(np.isnan(w)) or np.any(w == -np.inf):
        raise LinearError("omega contains NaN or -inf; give nonnegative frequencies (inf allowed: feedthrough)")
    if np.any(w < 0.0):
        raise LinearError(
            f"omega must be >= 0 (found {w[w < 0][0]!r}): only positive frequencies are solved, the response at "
            "-omega is the complex conjugate"
        )
    return omega_d, w


def frequency_grid(omega, T):
    """Frequencies (checked) and the sampling period: ``T`` as given (checked here, before any solve), else
    recovered from a McKelvey pair."""
    if T is not None:
        what = "T (sampling period of the data, convective time) must be"
        T_value = real_number(T)   # None for a bool and for text (T="1" was parsed)
        if T_value is None:
            raise LinearError(f"{what} a number; got {T!r}")
        if not (np.isfinite(T_value) and T_value > 0):
            raise LinearError(f"{what} positive and finite; got {T!r}")
        T = T_value
    omega_d, w = frequencies(omega)
    if T is None and omega_d is not None:
        inner = np.isfinite(w) & (w > 0)
        if np.any(inner):
            k = np.flatnonzero(inner)[0]
            T = 2.0 * np.tan(omega_d[k] / 2.0) / w[k]
    return w, T


MAX_POSITION = 1e4
"""Largest distance (chords) of a position (``x_ref``, ``pivot``) from the leading edge: the largest far field of a
C-grid (``cfd.mesh.generation.MAX_FARFIELD``)."""


def check_position(name, value, error=LinearError):
    """A position on the chord line (chords from the leading edge), checked real, finite and within
    :data:`MAX_POSITION` (else ``error``)."""
    try:
        if isinstance(value, (bool, np.bool_)):
            raise TypeError
        x = float(value)
    except (TypeError, ValueError):
        raise error(f"{name} must be a real number (chords from the leading edge); got {value!r}") from None
    if not np.isfinite(x):
        raise error(f"{name} must be finite (chords); got {value!r}")
    if abs(x) > MAX_POSITION:
        raise error(f"{name} = {x:g} chords is beyond cfd.frequencies.MAX_POSITION = {MAX_POSITION:g}: positions are "
                    "in chords from the leading edge (a pivot of 1e300 overflowed the pitch forcing to NaN loads)")
    return x


def check_x_ref(x_ref, error=LinearError):
    """The gust reference point (chords), checked finite (else ``error``, :class:`LinearError` by default)."""
    return check_position("x_ref", x_ref, error)


def check_pivot(pivot):
    """The pitch axis (chords from the leading edge, on the chord line), checked finite."""
    return check_position("pivot", pivot)


def check_motion_frequencies(inputs, w):
    """Refuse ``omega = inf`` for motion inputs (their loads grow with the frequency: no finite feedthrough)."""
    moving = [i for i in inputs if i != "gust"]
    if moving and np.any(np.isinf(w)):
        raise LinearError(
            f"omega = inf has no finite response for the motion input(s) {moving}: the loads of a moving section grow "
            "with the frequency (apparent mass, piston theory). Give finite frequencies (e.g. sysid.mckelvey_grid's "
            "omega[:-1] with T=T) and fit the motion columns with aeroelastic.fit_motion")


def check_tol(tol):
    """The relative error target of the fast sweep, a positive finite number (checked on every path of
    :func:`cfd.lfd_response`, also the direct one, which ignores it)."""
    t = real_number(tol)
    if t is None or not (np.isfinite(t) and t > 0.0):
        raise LinearError(f"tol must be a positive finite number (relative output error, e.g. 1e-8); got {tol!r}")
    return t
