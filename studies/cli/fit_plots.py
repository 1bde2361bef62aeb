"""Figures of ``lfdrom fit`` (:mod:`studies.cli.fit`): Bode overlay, error against frequency, Hankel singular
values (with the hold-out curve of ``--order auto``) and poles in the z-plane.

Frequencies are shown in the data's unit (:func:`studies.fit_data.frequency_axis`: the reduced frequency ``k =
omega / 2`` for an aerofoil's response, Hz or rad/s with an SI prefix, or plain ``omega``) on a log axis; the
``omega = 0`` and ``omega = inf`` samples cannot sit on it and are named in the titles instead.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

__all__ = ["write_figures", "bode_figure", "error_figure", "hankel_figure", "poles_figure"]

_DATA = dict(ls="none", marker="o", ms=3.0, mfc="none", color="0.25", label="data")
_ROM = dict(color="C3", lw=1.4, label="ROM")


def _plt():
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    return plt


def _save(fig, path: Path, dpi: int = 110, text: dict | None = None) -> Path:
    """Save atomically as a palette PNG (small enough to commit) with the PNG text chunks ``text`` (the fit's
    generator marker) and close (:func:`studies.report.plots.save_figure`)."""
    from ..report.plots import save_figure

    return save_figure(fig, path, dpi=dpi, text=text)


def _tick_text(v: float) -> str:
    """A tick value: plain (0.1, 2, 30, 4500) between 1e-3 and 1e5, else m x 10^e (no "3e+11")."""
    if v == 0 or 1e-3 <= abs(v) < 1e5:
        return f"{v:g}"
    e = int(np.floor(np.log10(abs(v))))
    m = v / 10.0**e
    return rf"$10^{{{e}}}$" if abs(m - 1) < 1e-6 else rf"${m:.3g}\times10^{{{e}}}$"


def _plain_log_axis(ax, axis: str) -> None:
    """Tick labels as plain numbers (0.1, 2, 30) instead of 10^-1, 2x10^0; minor labels on short ranges: at 2, 3
    and 5 times a power of ten below 30:1, at every minor tick below 3:1, so that any axis has labels."""
    from matplotlib.ticker import FuncFormatter, NullFormatter

    fmt = FuncFormatter(lambda v, _: _tick_text(v))
    target = ax.yaxis if axis == "y" else ax.xaxis
    lo, hi = ax.get_ylim() if axis == "y" else ax.get_xlim()
    ratio = hi / max(lo, 1e-300)
    leads = (2, 3, 5) if ratio >= 3 else (2, 3, 4, 5, 6, 7, 8, 9)

    def minor(v, _):  # label chosen multiples of a power of ten only, so labels do not collide
        lead = v / 10 ** np.floor(np.log10(v)) if v > 0 else 0.0
        return _tick_text(v) if any(abs(lead - d) < 1e-6 for d in leads) else ""

    target.set_major_formatter(fmt)
    target.set_minor_formatter(FuncFormatter(minor) if ratio < 30 else NullFormatter())


def _title(fig, text: str) -> None:
    """A figure title wrapped to the figure's width (a single-output figure is narrow: it was clipped)."""
    import textwrap

    width = max(30, int(fig.get_figwidth() * 12))   # about 12 characters of 10-point text per inch
    fig.suptitle(textwrap.fill(text, width), fontsize=10)


def _finite_positive(frf):
    w = np.asarray(frf.omega, dtype=float)
    keep = np.isfinite(w) & (w > 0)
    return keep, w


def _axis(frf):
    from .fit_data import frequency_axis

    label, scale, _ = frequency_axis(frf)
    return label, scale


def _dense(frf, n: int = 500) -> np.ndarray:
    keep, w = _finite_positive(frf)
    lo, hi = w[keep].min(), w[keep].max()
    return np.logspace(np.log10(lo), np.log10(hi), n)


def _channels(frf):
    return [(i, j) for i in range(frf.noutputs) for j in range(frf.ninputs)]


def _label(frf, i, j):
    return frf.outputs[i] if frf.ninputs == 1 else f"{frf.outputs[i]} / {frf.inputs[j]}"


def _ends_note(frf, res=None) -> str:
    """What the omega = 0 and inf samples hold (they are off the log axis)."""
    w = frf.omega
    parts = []
    if (w == 0).any():
        parts.append("omega = 0 sample fitted" + (" exactly" if res is not None and res.enforced.get("dc_gain")
                                                  else ""))
    if np.isinf(w).any():
        parts.append("omega = inf sample imposed" if res is not None and res.enforced.get("feedthrough")
                     else "omega = inf sample")
    return "; ".join(parts)


def bode_figure(out):
    """Magnitude and phase of data (markers) and ROM (line) against ``k``, one column per channel."""
    plt = _plt()
    frf, res = out.data, out.result
    chans = _channels(frf)
    keep, w = _finite_positive(frf)
    wf = _dense(frf)
    Hm = res.evaluate_continuous(wf)
    H = np.asarray(frf.H)
    label, scale = _axis(frf)
    fig, axes = plt.subplots(2, len(chans), figsize=(4.2 * len(chans) + 0.6, 5.6), sharex=True, squeeze=False)
    for c, (i, j) in enumerate(chans):
        ax_m, ax_p = axes[0, c], axes[1, c]
        ax_m.loglog(w[keep] * scale, np.abs(H[i, j, keep]), **_DATA)
        ax_m.loglog(wf * scale, np.abs(Hm[i, j]), **_ROM)
        ph_d = np.degrees(np.unwrap(np.angle(H[i, j, keep])))
        ph_m = np.degrees(np.unwrap(np.angle(Hm[i, j])))
        # put both on the same branch at the first data frequency
        ph_m += 360.0 * np.round((np.interp(w[keep][0], wf, ph_m) - ph_d[0]) / -360.0)
        ax_p.semilogx(w[keep] * scale, ph_d, **_DATA)
        ax_p.semilogx(wf * scale, ph_m, **_ROM)
        ax_m.set_title(_label(frf, i, j))
        ax_m.set_ylabel("|H|" if c == 0 else "")
        ax_p.set_ylabel("phase [deg]" if c == 0 else "")
        ax_p.set_xlabel(label)
        for ax in (ax_m, ax_p):
            ax.grid(True, which="major", alpha=0.3)
        _plain_log_axis(ax_m, "y")
        _plain_log_axis(ax_p, "x")
    axes[0, 0].legend(loc="best", fontsize=8)
    note = _ends_note(frf, res)
    _title(fig, f"data and ROM (order {res.order})" + (f"; {note}" if note else ""))
    fig.tight_layout()
    return fig


def error_figure(out):
    """``|model - data| / max |data|`` per channel against frequency (log-log): at the samples (dots) and, between
    them, the estimate of :func:`sysid.between.between_deviation` (crosses: the model's departure from local readings
    of the samples beyond their spread, at every interval's midpoint and the model's resonance peaks)."""
    from sysid.between import between_deviation

    plt = _plt()
    frf, res = out.data, out.result
    keep, w = _finite_positive(frf)
    H = np.asarray(frf.H)
    Hm = res.evaluate(frf.omega_d)
    label, scale = _axis(frf)
    m = res.matrices
    pts, dev = between_deviation(m.A, m.B, m.C, m.D, frf.omega_d, H)
    inside = pts < np.pi
    w_between = 2.0 / frf.T * np.tan(pts[inside] / 2.0)
    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    floor = np.finfo(float).eps
    for c, (i, j) in enumerate(_channels(frf)):
        peak = np.abs(H[i]).max()
        e = np.abs(Hm[i, j] - H[i, j]) / peak
        ax.loglog(w[keep] * scale, np.maximum(e[keep], floor), marker="o", ms=3, lw=1.0, color=f"C{c}",
                  label=f"{_label(frf, i, j)} at the samples (max {e.max():.2g})")
        d = dev[i, j, inside] / peak
        if not np.any(np.isfinite(d)):   # fewer than four distinct frequencies: no estimate between the samples
            continue
        ax.loglog(w_between * scale, np.maximum(d, floor), ls="none", marker="x", ms=4, mew=0.9, color=f"C{c}",
                  alpha=0.8, label=f"{_label(frf, i, j)} between them, estimate (max {np.nanmax(d):.2g})")
    lo, hi = ax.get_ylim()
    lo = max(lo, hi * 1e-8)   # estimates of exactly zero (the floor) would stretch the axis over decades of nothing
    ax.set_ylim(min(lo, hi / 100), hi * 1.2)   # at least two decades, so that round-off-level errors read as such
    ax.set_xlabel(label)
    ax.set_ylabel("|ROM - data| / peak |data|")
    _plain_log_axis(ax, "x")
    ax.grid(True, which="major", alpha=0.3)
    ax.legend(fontsize=7, loc="best")
    ax.set_title(f"error of the order-{res.order} ROM at the samples and between them (sysid.between)", fontsize=10)
    fig.tight_layout()
    return fig


def hankel_figure(out):
    """Normalised Hankel singular values (chosen order marked) and, for ``--order auto``, the hold-out error."""
    plt = _plt()
    res, sel = out.result, out.selection
    sv = np.asarray(res.hankel_sv, dtype=float)
    sv = sv[: min(sv.size, max(3 * res.order, 40))]
    ncol = 2 if sel is not None else 1
    fig, axes = plt.subplots(1, ncol, figsize=(5.0 * ncol + 0.4, 3.9), squeeze=False)
    ax = axes[0, 0]
    idx = np.arange(1, sv.size + 1)
    ax.semilogy(idx, sv / sv[0], "o-", ms=3, lw=1.0, color="C0")
    ax.axvline(res.order, color="C3", ls="--", lw=1.0, label=f"order {res.order}")
    ax.set_xlabel("index i")
    ax.set_ylabel("sigma_i / sigma_1")
    from matplotlib.ticker import MaxNLocator

    ax.xaxis.set_major_locator(MaxNLocator(integer=True))
    ax.set_title("Hankel singular values of the data", fontsize=10)
    ax.grid(True, which="major", alpha=0.3)
    ax.legend(fontsize=8)
    if sel is not None:
        ax = axes[0, 1]
        fin = np.isfinite(sel.errors)
        ax.semilogy(sel.orders[fin], sel.errors[fin], "o-", ms=3, lw=1.0, color="C2")
        ax.axvline(sel.chosen, color="C3", ls="--", lw=1.0, label=f"chosen {sel.chosen}")
        ax.set_xlabel("order")
        ax.set_ylabel("hold-out error (RMS, relative)")
        ax.xaxis.set_major_locator(MaxNLocator(integer=True))
        ax.set_title("hold-out error (fit on even, test on odd frequencies)", fontsize=10)
        ax.grid(True, which="major", alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def poles_figure(out):
    """Poles of the discrete ROM: the z-plane with the unit circle, and each pole's distance to the circle
    ``1 - |z|`` (log) against its angle ``arg z`` (clusters near ``z = -1`` are hard to see in the plane)."""
    plt = _plt()
    res = out.result
    lam = np.linalg.eigvals(np.asarray(res.model.A))
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(10.0, 4.8), gridspec_kw={"width_ratios": [1.0, 1.15]})
    t = np.linspace(0, 2 * np.pi, 400)
    ax.plot(np.cos(t), np.sin(t), color="0.5", lw=1.0, label="unit circle")
    ax.plot(lam.real, lam.imag, "x", color="C3", ms=7, mew=1.5, label=f"{lam.size} poles")
    ax.axhline(0, color="0.85", lw=0.8, zorder=0)
    ax.axvline(0, color="0.85", lw=0.8, zorder=0)
    ax.set_aspect("equal")
    lim = max(1.1, 1.05 * float(np.abs(lam).max()) if lam.size else 1.1)
    ax.set_xlim(-lim, lim)
    ax.set_ylim(-lim, lim)
    ax.set_xlabel("Re z")
    ax.set_ylabel("Im z")
    ax.set_title(f"poles in the z-plane (T = {res.T:.4g})", fontsize=10)
    ax.legend(fontsize=8, loc="lower left")
    up = lam[lam.imag >= 0]
    dist = 1.0 - np.abs(up)
    inside = dist > 0
    ax2.semilogy(np.angle(up[inside]) / np.pi, dist[inside], "x", color="C3", ms=7, mew=1.5)
    if (~inside).any():
        ax2.semilogy(np.angle(up[~inside]) / np.pi, np.abs(dist[~inside]), "o", color="k", mfc="none", ms=8,
                     label="outside the circle (|z| - 1)")
        ax2.legend(fontsize=8)
    ax2.set_xlim(-0.03, 1.03)
    ax2.set_xlabel("pole angle arg z / pi  (0: DC, 1: omega = inf)")
    ax2.set_ylabel("1 - |z|  (distance to the unit circle)")
    ax2.set_title(f"stability margin: spectral radius {res.spectral_radius:.4f}", fontsize=10)
    ax2.grid(True, which="major", alpha=0.3)
    fig.tight_layout()
    return fig


def write_figures(out, out_dir, text: dict | None = None) -> dict[str, Path]:
    """Write ``bode.png``, ``error.png``, ``hankel.png`` and ``poles.png`` to ``out_dir`` (with the PNG text
    chunks ``text``: :func:`studies.fit.write_outputs` passes its generator marker)."""
    out_dir = Path(out_dir)
    figs = {"bode": bode_figure, "error": error_figure, "hankel": hankel_figure, "poles": poles_figure}
    return {name: _save(make(out), out_dir / f"{name}.png", text=text) for name, make in figs.items()}
