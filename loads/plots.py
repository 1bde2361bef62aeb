"""Figures of gust loads: the ``tuned_gust`` / ``continuous_turbulence`` functions compute, ``*_plot`` draw.

Each function takes an optional matplotlib axes and returns it; none calls ``show``. Loads are drawn in SI at
the flight point (``dimensional=True``, the default) or in model units.
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np

from .atmosphere import FT
from .errors import LoadsModelError
from .tuned_gust import TunedGustResult
from .turbulence import TurbulenceResult

__all__ = ["correlated_loads_plot", "load_vs_H_plot", "psd_plot", "gust_history_plot", "turbulence_ellipse"]


def _axes(ax, size=(6.0, 4.5)):
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=size, layout="constrained")
    return ax


def _check(value, cls, what):
    if not isinstance(value, cls):
        raise LoadsModelError(f"expected the result of loads.{what}, got {type(value).__name__}")


MAX_ELLIPSE_POINTS = 100_000
"""Most points :func:`turbulence_ellipse` draws (a smooth curve needs a few hundred)."""


def turbulence_ellipse(turbulence: TurbulenceResult, x: str, y: str, *, dimensional: bool = True, n: int = 181):
    """The correlated-load ellipse of outputs ``x`` and ``y``: ``(U_sigma A_x cos t,
    U_sigma A_y (rho cos t + sqrt(1 - rho^2) sin t))``, ``t`` in ``[0, 2 pi]``; shapes (n,), (n,).

    Its extreme in ``x`` is ``(A_x U_sigma, rho A_x ... )``: the design load of ``x`` with the correlated ``y``.

    Parameters
    ----------
    turbulence : TurbulenceResult
    x, y : str
        Outputs of ``turbulence``.
    dimensional : bool
        SI at the flight point (default) or model units.
    n : int
        Points on the ellipse, 3 to :data:`MAX_ELLIPSE_POINTS` (default 181).

    Returns
    -------
    ex, ey : ndarray, shape (n,)

    Raises
    ------
    LoadsModelError
        ``turbulence`` not a :class:`TurbulenceResult`, ``x`` or ``y`` not one of its outputs, ``dimensional`` not
        a boolean, ``n`` not an integer in 3 .. :data:`MAX_ELLIPSE_POINTS`.
    """
    _check(turbulence, TurbulenceResult, "continuous_turbulence")
    for o in (x, y):
        if not isinstance(o, str) or o not in turbulence.outputs:
            raise LoadsModelError(f"no output {o!r} in the turbulence result ({list(turbulence.outputs)})")
    if not isinstance(dimensional, (bool, np.bool_)):
        raise LoadsModelError(f"dimensional must be True (SI at the flight point) or False (model units), got "
                              f"{dimensional!r}")
    if isinstance(n, (bool, np.bool_)) or not isinstance(n, (int, np.integer)) or not 3 <= n <= MAX_ELLIPSE_POINTS:
        raise LoadsModelError(f"n (points on the ellipse) must be an integer from 3 to {MAX_ELLIPSE_POINTS}, got "
                              f"{n!r}; the default 181 draws a smooth curve")
    r = turbulence.rho(x, y)
    sx, sy = turbulence.design[x], turbulence.design[y]
    if dimensional:
        sx, sy = turbulence.dimensional[x], turbulence.dimensional[y]
    t = np.linspace(0.0, 2.0 * np.pi, n)
    return sx * np.cos(t), sy * (r * np.cos(t) + np.sqrt(max(1.0 - r * r, 0.0)) * np.sin(t))


def correlated_loads_plot(tuned: TunedGustResult | None, turbulence: TurbulenceResult | None = None, *,
                          x: str = "Cl", y: str = "Cm", dimensional: bool = True, ax: Any = None):
    """The engineers' "potato" plot: ``y`` against ``x``, the tuned-gust peaks as points, the turbulence ellipse.

    For each output searched by :func:`loads.tuned_gust`, its peak and the time-correlated ``x`` and ``y`` are a
    point (and its mirror, the opposite gust); the continuous-turbulence design loads give the ellipse of
    :func:`turbulence_ellipse`. Increments about the 1 g load (the origin).

    Parameters
    ----------
    tuned : TunedGustResult or None
    turbulence : TurbulenceResult, optional
    x, y : str
        Outputs on the axes (default lift and moment).
    dimensional : bool
        SI at the flight point (default) or model units.
    ax : matplotlib.axes.Axes, optional

    Returns
    -------
    matplotlib.axes.Axes
    """
    if tuned is None and turbulence is None:
        raise LoadsModelError("give a tuned_gust result, a continuous_turbulence result or both")
    if not isinstance(dimensional, (bool, np.bool_)):   # (checked by turbulence_ellipse only, when it was drawn)
        raise LoadsModelError(f"dimensional must be True or False, got {dimensional!r}")
    ax = _axes(ax)
    unit_x = unit_y = ""
    if tuned is not None:
        _check(tuned, TunedGustResult, "tuned_gust")
        for o in (x, y):
            if o not in tuned.all_outputs:
                raise LoadsModelError(f"no output {o!r} in the tuned-gust result ({list(tuned.all_outputs)})")
        sx = tuned.system.scale[tuned.system.index(x)] if dimensional else 1.0
        sy = tuned.system.scale[tuned.system.index(y)] if dimensional else 1.0
        if dimensional:
            unit_x = f" [{tuned.system.units[tuned.system.index(x)]}]"
            unit_y = f" [{tuned.system.units[tuned.system.index(y)]}]"
        markers = "osD^vP*X"
        for k, o in enumerate(tuned.outputs):
            px, py = tuned.correlated[o][x] * sx, tuned.correlated[o][y] * sy
            ax.plot([px, -px], [py, -py], markers[k % len(markers)], ms=7, mfc="none",
                    label=f"peak {o} (H = {tuned.critical_H[o]:.3g} m)")
    if turbulence is not None:
        ex, ey = turbulence_ellipse(turbulence, x, y, dimensional=dimensional)
        ax.plot(ex, ey, "k-", lw=1.2, label=f"turbulence, U_sigma = {turbulence.u_sigma:.3g} m/s "
                f"(rho = {turbulence.rho(x, y):+.2f})")
        if dimensional and not unit_x:
            unit_x, unit_y = f" [{turbulence.units[x]}]", f" [{turbulence.units[y]}]"
    ax.axhline(0.0, color="0.8", lw=0.6, zorder=0)
    ax.axvline(0.0, color="0.8", lw=0.6, zorder=0)
    ax.set_xlabel(f"{x}{unit_x}")
    ax.set_ylabel(f"{y}{unit_y}")
    ax.set_title("correlated loads (increments about 1 g)")
    ax.legend(fontsize=7, loc="best")
    return ax


def load_vs_H_plot(tuned: TunedGustResult, outputs: Sequence[str] | None = None, *, ax: Any = None):
    """Peak ``|load|`` over time against the gust gradient ``H``, each output relative to its tuned peak.

    The first grid of :func:`loads.tuned_gust` as lines, the critical ``H`` (after refinement) as a star.
    """
    _check(tuned, TunedGustResult, "tuned_gust")
    names = list(tuned.outputs) if outputs is None else list(outputs)
    ax = _axes(ax)
    for o in names:
        if o not in tuned.outputs:
            raise LoadsModelError(f"output {o!r} was not searched ({list(tuned.outputs)})")
        j = tuned.outputs.index(o)
        line, = ax.plot(tuned.H_grid / FT, tuned.peak_vs_H[j] / max(tuned.peak[o], 1e-300), "-", marker=".", label=o)
        ax.plot([tuned.critical_H[o] / FT], [1.0], "*", color=line.get_color(), ms=12)
    ax.set_xlabel("gust gradient H [ft]")
    ax.set_ylabel("peak |load| / tuned peak")
    ax.set_title("tuned gust: load against H (both signs)")
    ax.legend(fontsize=8)
    return ax


def psd_plot(turbulence: TurbulenceResult, outputs: Sequence[str] | None = None, *, ax: Any = None):
    """Power spectral density of each output's response to unit-rms turbulence, ``|H|^2 Phi``, against frequency
    (Hz), normalised by ``A_bar^2`` (so the curves share an axis: each integrates to one over Omega)."""
    _check(turbulence, TurbulenceResult, "continuous_turbulence")
    names = list(turbulence.outputs) if outputs is None else list(outputs)
    ax = _axes(ax)
    U = turbulence.point.tas
    f = turbulence.Omega * U / (2.0 * np.pi)
    for o in names:
        if o not in turbulence.outputs:
            raise LoadsModelError(f"no output {o!r} in the turbulence result ({list(turbulence.outputs)})")
        j = turbulence.outputs.index(o)
        ax.loglog(f, turbulence.psd[j] / turbulence.a_bar[o] ** 2,
                  label=f"{o}: N0 = {turbulence.n0[o]:.3g} /s")
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("|H|^2 Phi / A_bar^2 [m/rad]")
    ax.set_title("response PSD to von Karman turbulence")
    ax.legend(fontsize=8)
    return ax


def gust_history_plot(tuned: TunedGustResult, output: str, *, others: Sequence[str] | None = None, ax: Any = None):
    """Histories at ``output``'s critical gust: the gust velocity and each output relative to its own peak."""
    _check(tuned, TunedGustResult, "tuned_gust")
    if output not in tuned.outputs:
        raise LoadsModelError(f"output {output!r} was not searched ({list(tuned.outputs)})")
    ax = _axes(ax)
    t = tuned.times[output]
    g = tuned.gust[output]
    ax.plot(t, g / np.abs(g).max(), "k--", lw=1, label="gust velocity (relative)")
    names = [output] + [o for o in (others or []) if o != output]
    for o in names:
        i = tuned.all_outputs.index(o)
        y = tuned.histories[output][i]
        ax.plot(t, y / max(np.abs(y).max(), 1e-300), label=f"{o} (max |.| {np.abs(y).max():.3g})")
    ax.axvline(tuned.peak_time[output], color="0.6", lw=0.8)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("relative to own peak")
    ax.set_title(f"critical gust of {output}: H = {tuned.critical_H[output]:.3g} m")
    ax.legend(fontsize=8)
    return ax
