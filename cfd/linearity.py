"""Where the linear models hold: the nonlinear gust response (:func:`cfd.unsteady.unsteady_response`) at several
amplitudes against the LTD of the same gust (peak ratios and history errors, docs/nonlinear.md)."""

import inspect
from dataclasses import dataclass

import numpy as np

from .gust import OneMinusCosine, SharpEdged, SineGust
from .unsteady import UnsteadyError, unsteady_response

__all__ = ["LinearityResult", "linearity"]


@dataclass(frozen=True, eq=False)
class LinearityResult:
    """The nonlinear response of one case and gust shape at several amplitudes against its LTD.

    Attributes
    ----------
    amplitudes : ndarray, shape (k,)
        Gust angles (deg).
    cl_peak_ratio, cm_peak_ratio : ndarray, shape (k,)
        ``max |nonlinear| / max |linear|`` of the load perturbation at each amplitude (1 where the linear
        model holds).
    cl_error, cm_error : ndarray, shape (k,)
        ``max_t |nonlinear / A - linear / A|`` over ``max_t |linear / A|`` (``A = tan(angle)``): the history
        error of the linear model relative to its peak.
    ltd : LTDHistory
        The linear history of the gust at the amplitude given to :func:`linearity` (scale by
        ``tan(a) / gust.amplitude`` for another).
    histories : tuple of UnsteadyHistory
        One per amplitude.
    """

    amplitudes: np.ndarray
    cl_peak_ratio: np.ndarray
    cm_peak_ratio: np.ndarray
    cl_error: np.ndarray
    cm_error: np.ndarray
    ltd: object
    histories: tuple


def linearity(sol, gust, amplitudes, dt, t_end, method="svm", x_ref=0.0, lin=None, **kwargs):
    """Run one case and gust shape at several amplitudes and compare with the LTD (the linear model).

    Parameters
    ----------
    sol : SteadySolution
    gust : SineGust, OneMinusCosine or SharpEdged
        The shape; its ``angle_deg`` is replaced by each amplitude.
    amplitudes : sequence of float
        Gust angles (deg), nonzero.
    dt, t_end, method, x_ref
        As :func:`unsteady_response` (shared by the LTD).
    lin : LinearSystem, optional
        ``cfd.linearise(sol)``, built if not given.
    **kwargs
        Passed to :func:`unsteady_response` (its keyword-only settings, e.g. ``rtol``, ``max_iter``).

    Returns
    -------
    LinearityResult

    Raises
    ------
    UnsteadyError
        Empty, zero, non-numeric or 2-D amplitudes, not a gust, or a keyword :func:`unsteady_response` does not
        take (checked before the LTD is computed).
    GustError
        An amplitude that is not a gust angle (``|a| >= 90``), also before the LTD.
    """
    from dataclasses import replace

    from .linear import linearise
    from .ltd import ltd_response

    settings = [name for name, par in inspect.signature(unsteady_response).parameters.items()
                if par.kind is inspect.Parameter.KEYWORD_ONLY]
    unknown = sorted(set(kwargs) - set(settings))
    if unknown:
        raise UnsteadyError(f"unknown keyword(s) {unknown} for unsteady_response; it takes {settings}")
    try:   # (text is refused, as the solvers refuse it: "1" was parsed)
        amps = np.array([]) if np.asarray(amplitudes).dtype.kind in "USO" else np.asarray(amplitudes, dtype=float)
    except (TypeError, ValueError):
        amps = np.array([])   # refused just below, with the value as given
    if amps.ndim > 1:
        raise UnsteadyError(f"amplitudes must be a 1-D list of gust angles (deg); got shape {amps.shape}: one run per "
                            "amplitude, flatten it yourself if that is what you mean")
    amps = amps.reshape(-1)
    if amps.size == 0 or np.any(amps == 0.0) or not np.all(np.isfinite(amps)):
        raise UnsteadyError(f"amplitudes must be a non-empty list of finite, nonzero gust angles (deg); "
                            f"got {amplitudes!r}")
    if not isinstance(gust, (SineGust, OneMinusCosine, SharpEdged)):
        raise UnsteadyError(f"gust must be a cfd.SineGust, OneMinusCosine or SharpEdged; got {type(gust).__name__}")
    for a in amps:   # every amplitude a gust angle (GustError), before the LTD's work
        replace(gust, angle_deg=float(a))
    lin = linearise(sol) if lin is None else lin
    h = ltd_response(lin, gust, dt, t_end, method=method, x_ref=x_ref,
                     max_phase_error=kwargs.get("max_phase_error", 0.01))
    A0 = gust.amplitude
    rows, hists = [], []
    for a in amps:
        g = replace(gust, angle_deg=float(a))
        u = unsteady_response(sol, g, dt, t_end, method=method, x_ref=x_ref, **kwargs)
        row = []
        for y, yl in ((u.cl, h.cl), (u.cm, h.cm)):
            lin_unit = yl / A0
            peak = np.abs(lin_unit).max()
            row += [np.abs(y).max() / (abs(g.amplitude) * peak), np.abs(y / g.amplitude - lin_unit).max() / peak]
        rows.append(row)
        hists.append(u)
    r = np.array(rows)
    return LinearityResult(amplitudes=amps, cl_peak_ratio=r[:, 0], cm_peak_ratio=r[:, 2], cl_error=r[:, 1],
                           cm_error=r[:, 3], ltd=h, histories=tuple(hists))
