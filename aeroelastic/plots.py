"""Figures in python-control's style: the ``*_response`` / analysis functions return data, ``*_plot`` draws.

All functions take an optional matplotlib axes (or pair of axes) and return it; they never call ``show``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .errors import AeroModelError

__all__ = ["root_locus_plot", "vg_plot", "flutter_plot", "gust_response_plot"]

_MODE_COLOURS = ("tab:blue", "tab:red")
_MODE_NAMES = ("plunge branch", "pitch branch")


def _check_result(value, needs, what):
    """Raise :class:`AeroModelError` unless ``value`` has the attributes ``needs`` (a result of ``what``)."""
    missing = [name for name in needs if not hasattr(value, name)]
    if missing:
        raise AeroModelError(f"expected the result of {what}, got {type(value).__name__} (no {', '.join(missing)})")


_FLUTTER_FIELDS = ("eigenvalues", "modes", "speeds", "g", "found", "speed_index", "frequency_ratio", "kind")


def _plt():
    import matplotlib.pyplot as plt

    return plt


def root_locus_plot(result, ax: Any = None, *, show_lags: bool = True):
    """Root locus against speed: eigenvalues in the ``(Re, Im)`` plane (``omega_alpha`` units).

    The two structural branches are drawn as coloured lines from the lowest speed (circle) to the highest
    (triangle); the other roots (the aerodynamic lag roots, real and stable, and a real root crossing to the right
    half plane at divergence) as grey points. The flutter
    point, when found, is marked with a star.

    Parameters
    ----------
    result : FlutterResult
        From :func:`aeroelastic.flutter` (uses ``eigenvalues``, ``modes``, ``speeds`` and the flutter point).
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; default a new figure of 6 x 4.5 inches.
    show_lags : bool
        Also draw the other roots (those on or above the real axis) as grey points (default True).

    Returns
    -------
    matplotlib.axes.Axes
        ``ax``, or the new axes.

    Raises
    ------
    AeroModelError
        ``result`` is not a flutter result; ``show_lags`` is not a bool.
    """
    _check_result(result, _FLUTTER_FIELDS, "aeroelastic.flutter")
    if not isinstance(show_lags, (bool, np.bool_)):
        raise AeroModelError(f"show_lags must be True or False, got {show_lags!r}")
    plt = _plt()
    if ax is None:
        _, ax = plt.subplots(figsize=(6.0, 4.5))
    E = result.eigenvalues
    if show_lags:
        others = [j for j in range(E.shape[1]) if j not in set(result.modes)]
        lag = E[:, others]
        lag = lag[lag.imag >= -1e-12]
        ax.plot(lag.real, lag.imag, ".", color="0.6", ms=2, label="other roots (lags; real, > 0 past divergence)")
    for c, name, j in zip(_MODE_COLOURS, _MODE_NAMES, result.modes):
        lam = E[:, j]
        lam = np.where(lam.imag < 0, lam.conj(), lam)
        ax.plot(lam.real, lam.imag, "-", color=c, lw=1.6, label=name)
        ax.plot(lam.real[0], lam.imag[0], "o", color=c, ms=5)
        ax.plot(lam.real[-1], lam.imag[-1], "^", color=c, ms=6)
    if result.found:
        ax.plot([0.0], [result.frequency_ratio], "*", color="k", ms=12,
                label=f"{result.kind}: V = {result.speed_index:.3f}")
    ax.axvline(0.0, color="k", lw=0.8)
    ax.set_xlabel(r"Re $\lambda$ / $\omega_\alpha$")
    ax.set_ylabel(r"Im $\lambda$ / $\omega_\alpha$")
    ax.set_title(f"Root locus, V = U/(b$\\omega_\\alpha$) from {result.speeds[0]:.2g} to {result.speeds[-1]:.3g}")
    ax.set_ylim(bottom=-0.05)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize=8)
    return ax


def vg_plot(result, axs: Any = None):
    """V-g plot: damping ``g = 2 Re(lambda) / Im(lambda)`` and frequency ``Im(lambda) / omega_alpha`` against speed.

    Parameters
    ----------
    result : FlutterResult
        From :func:`aeroelastic.flutter` (the two structural branches ``modes`` are drawn against ``speeds``).
    axs : pair of matplotlib.axes.Axes, optional
        ``(ax_g, ax_f)`` for the damping and the frequency; default a new figure with two stacked axes sharing x.

    Returns
    -------
    tuple of matplotlib.axes.Axes
        The two axes ``(ax_g, ax_f)``.
    """
    _check_result(result, _FLUTTER_FIELDS, "aeroelastic.flutter")
    plt = _plt()
    if axs is None:
        _, axs = plt.subplots(2, 1, sharex=True, figsize=(6.0, 5.5))
    ax_g, ax_f = axs
    V = result.speeds
    g = result.g
    for c, name, j in zip(_MODE_COLOURS, _MODE_NAMES, result.modes):
        ax_g.plot(V, g[:, j], color=c, lw=1.6, label=name)
        ax_f.plot(V, np.abs(result.eigenvalues[:, j].imag), color=c, lw=1.6, label=name)
    ax_g.axhline(0.0, color="k", lw=0.8)
    if result.found:
        for ax in axs:
            ax.axvline(result.speed_index, color="k", ls="--", lw=0.8)
        ax_f.plot([result.speed_index], [result.frequency_ratio], "*", color="k", ms=10,
                  label=f"{result.kind}: V = {result.speed_index:.3f}, $\\omega/\\omega_\\alpha$ = {result.frequency_ratio:.3f}")
    ax_g.set_ylabel(r"g = 2 Re$\lambda$ / Im$\lambda$")
    ax_f.set_ylabel(r"$\omega / \omega_\alpha$")
    ax_f.set_xlabel(r"speed index V = U / (b $\omega_\alpha$)")
    ax_g.set_title("V-g plot")
    gl = g[:, result.modes]
    gl = gl[np.isfinite(gl)]
    if gl.size:
        ax_g.set_ylim(max(gl.min(), -1.0) * 1.1, max(gl.max(), 0.05) * 1.1)
    for ax in axs:
        ax.grid(True, alpha=0.3)
    ax_f.legend(loc="best", fontsize=8)
    return ax_g, ax_f


def flutter_plot(result, fig: Any = None):
    """Root locus (left) and V-g plot (right) in one figure.

    Parameters
    ----------
    result : FlutterResult
        From :func:`aeroelastic.flutter`.
    fig : matplotlib.figure.Figure, optional
        Figure to draw in (three subplots are added to it); default a new figure of 12 x 5.5 inches.

    Returns
    -------
    matplotlib.figure.Figure
        ``fig``, or the new figure (after ``tight_layout``).
    """
    _check_result(result, _FLUTTER_FIELDS, "aeroelastic.flutter")
    plt = _plt()
    if fig is None:
        fig = plt.figure(figsize=(12.0, 5.5))
    gs = fig.add_gridspec(2, 2)
    ax_rl = fig.add_subplot(gs[:, 0])
    ax_g = fig.add_subplot(gs[0, 1])
    ax_f = fig.add_subplot(gs[1, 1], sharex=ax_g)
    root_locus_plot(result, ax_rl)
    vg_plot(result, (ax_g, ax_f))
    fig.tight_layout()
    return fig


def gust_response_plot(response, reference: Any = None, axs: Any = None, *, label: str = "coupled ROM",
                       reference_label: str = "reference"):
    """Gust angle, plunge, pitch, Cl and Cm against convective time; optional reference histories (dashed) and,
    with a reference, a last row of the differences ``(response - reference) / peak |reference|`` in per cent per
    channel (the few per cent between two models cannot be read off the histories themselves).

    Parameters
    ----------
    response : GustResponse
        From :func:`aeroelastic.gust_response` (uses ``t``, ``u``, ``plunge``, ``pitch``, ``Cl``, ``Cm``, ``speed``).
    reference : object with ``t``, ``plunge``, ``pitch``, ``Cl``, ``Cm``, optional
        Reference histories (e.g. another :class:`GustResponse`), drawn dashed on all rows but the gust angle.
    axs : sequence of 5 or 6 matplotlib.axes.Axes, optional
        One per row (gust angle, plunge, pitch, Cl, Cm, and the differences when a sixth is given); default a new
        figure with stacked axes sharing x: five, or six with a reference.
    label, reference_label : str
        Legend labels of ``response`` and ``reference`` (defaults ``"coupled ROM"``, ``"reference"``).

    Returns
    -------
    sequence of matplotlib.axes.Axes
        ``axs``, or the new ndarray of axes, shape (5,), or (6,) with a reference.
    """
    _check_result(response, ("t", "u", "plunge", "pitch", "Cl", "Cm"), "aeroelastic.gust_response")
    plt = _plt()
    if axs is None and reference is not None:
        _, axs = plt.subplots(6, 1, sharex=True, figsize=(7.0, 10.5), gridspec_kw=dict(height_ratios=[1] * 5 + [1.2]))
    elif axs is None:
        _, axs = plt.subplots(5, 1, sharex=True, figsize=(7.0, 9.0))
    rows = [("u", "gust angle u (rad)"), ("plunge", "h / c (up)"), ("pitch", r"$\alpha$ (rad)"),
            ("Cl", "Cl"), ("Cm", "Cm (elastic axis)")]
    for ax, (key, lab) in zip(axs, rows):
        ax.plot(response.t, getattr(response, key), color="tab:blue", lw=1.5, label=label if key != "u" else None)
        if reference is not None and key != "u":
            ax.plot(reference.t, getattr(reference, key), "--", color="tab:orange", lw=1.3, label=reference_label)
        ax.set_ylabel(lab)
        ax.grid(True, alpha=0.3)
    if reference is not None and len(axs) > 5:
        t = np.asarray(response.t, dtype=float)
        for (key, lab), colour in zip(rows[1:], ("tab:green", "tab:red", "tab:purple", "tab:brown")):
            ref = np.interp(t, np.asarray(reference.t, dtype=float), np.asarray(getattr(reference, key), dtype=float))
            peak = max(float(np.max(np.abs(ref))), np.finfo(float).tiny)
            axs[5].plot(t, 100 * (np.asarray(getattr(response, key), dtype=float) - ref) / peak, color=colour, lw=1.2,
                        label=key)
        axs[5].axhline(0.0, color="k", lw=0.6)
        axs[5].set_ylabel("difference\n(% of peak)")
        axs[5].legend(loc="best", fontsize=7, ncol=4)
        axs[5].grid(True, alpha=0.3)
    axs[1].legend(loc="best", fontsize=8)
    axs[-1].set_xlabel("convective time s = t U / c")
    axs[0].set_title(f"Flexible section in a gust, speed index V = {response.speed:.3g}")
    return axs
