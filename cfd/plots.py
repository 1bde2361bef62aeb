"""Figures: the grid, and the surface pressure and Mach field of a steady solution.

The flow plots take any object with the attributes of the steady solution (duck-typed):
``grid`` (Grid), ``q`` (ndarray (ni-1, nj-1, 4): rho, rho u, rho v, rho E with ``rho_inf = 1``,
``a_inf = 1``, ``p_inf = 1/gamma``, ``|u_inf| = mach``), ``mach``, ``alpha_deg``, ``gamma``,
``x_wall`` (n_surface,) and ``cp`` (n_surface,) of the wall cells. Functions return matplotlib
objects and never call ``plt.show()``.
"""

import numpy as np

from .export import primitives

__all__ = ["plot_grid", "grid_figure", "plot_cp", "plot_mach"]


def _axes(ax, figsize=(6, 5)):
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=figsize)
    return ax


def plot_grid(grid, ax=None, zoom=None, lw=0.3, title=None):
    """Draw the grid lines.

    Parameters
    ----------
    grid : Grid
    ax : matplotlib Axes, optional
        Created if not given.
    zoom : tuple (xmin, xmax, ymin, ymax) or "aerofoil", optional
        Axis limits in chords; ``"aerofoil"`` is ``(-0.2, 1.3, -0.5, 0.5)``. Default: the whole grid.
    lw : float
        Line width.
    title : str, optional

    Returns
    -------
    matplotlib Axes
    """
    ax = _axes(ax)
    ax.plot(grid.x, grid.y, "-", color="0.25", lw=lw)  # lines of constant j (round the C)
    ax.plot(grid.x.T, grid.y.T, "-", color="tab:blue", lw=lw)  # lines of constant i (outward)
    nw = grid.n_wake
    ax.plot(grid.x[nw : grid.shape[0] - nw, 0], grid.y[nw : grid.shape[0] - nw, 0], "k-", lw=1.2)
    if zoom == "aerofoil":
        zoom = (-0.2, 1.3, -0.5, 0.5)
    if zoom is not None:
        ax.set_xlim(zoom[0], zoom[1])
        ax.set_ylim(zoom[2], zoom[3])
    ax.set_aspect("equal")
    ax.set_xlabel("x / c")
    ax.set_ylabel("y / c")
    if title:
        ax.set_title(title)
    return ax


def grid_figure(grid, title=None):
    """A three-panel overview of a grid: whole domain, aerofoil, leading and trailing edges.

    Parameters
    ----------
    grid : Grid
    title : str, optional
        Figure title.

    Returns
    -------
    matplotlib Figure
    """
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=(15, 5.2))
    gs = fig.add_gridspec(2, 3, width_ratios=[1.0, 1.4, 0.8])
    ax_full = fig.add_subplot(gs[:, 0])
    ax_foil = fig.add_subplot(gs[:, 1])
    ax_le = fig.add_subplot(gs[0, 2])
    ax_te = fig.add_subplot(gs[1, 2])
    plot_grid(grid, ax=ax_full, lw=0.25, title="whole grid")
    plot_grid(grid, ax=ax_foil, zoom=(-0.25, 1.35, -0.45, 0.45), lw=0.35, title="aerofoil")
    plot_grid(grid, ax=ax_le, zoom=(-0.06, 0.1, -0.05, 0.05), lw=0.4, title="leading edge")
    plot_grid(grid, ax=ax_te, zoom=(0.9, 1.1, -0.05, 0.05), lw=0.4, title="trailing edge")
    for ax in (ax_le, ax_te):
        ax.set_xlabel("")
        ax.set_ylabel("")
        ax.locator_params(axis="x", nbins=5)
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    return fig


def _upper_lower(sol):
    n = len(sol.cp)
    x = np.asarray(sol.x_wall)
    cp = np.asarray(sol.cp)
    # Wall cells run lower TE -> LE -> upper TE (grid convention): first half lower, second upper.
    return (x[n // 2 :], cp[n // 2 :]), (x[: n // 2], cp[: n // 2])


def plot_cp(sol, ax=None, label=None):
    """Plot ``-Cp`` against ``x / c`` on the upper and lower surfaces.

    Parameters
    ----------
    sol : steady solution (duck-typed, see module docstring)
    ax : matplotlib Axes, optional
    label : str, optional
        Prefix of the legend entries.

    Returns
    -------
    matplotlib Axes
    """
    ax = _axes(ax)
    (xu, cpu), (xl, cpl) = _upper_lower(sol)
    pre = f"{label}: " if label else ""
    ax.plot(xu, -cpu, "-", color="tab:red", label=pre + "upper")
    ax.plot(xl, -cpl, "--", color="tab:blue", label=pre + "lower")
    if sol.mach < 1.0:
        # Sonic Cp: -Cp* marks where the flow turns supersonic.
        cps = 2.0 / (sol.gamma * sol.mach**2) * (((2 + (sol.gamma - 1) * sol.mach**2) / (sol.gamma + 1)) ** (sol.gamma / (sol.gamma - 1)) - 1)
        ax.axhline(-cps, color="0.5", lw=0.8, ls=":", label="sonic")
    ax.set_xlabel("x / c")
    ax.set_ylabel("-Cp")
    ax.set_title(f"M = {sol.mach:g}, alpha = {sol.alpha_deg:g} deg")
    ax.legend()
    ax.grid(alpha=0.3)
    return ax


def plot_mach(sol, ax=None, zoom=(-0.5, 1.5, -0.8, 0.8), levels=21):
    """Mach-number contours near the aerofoil.

    Parameters
    ----------
    sol : steady solution (duck-typed, see module docstring)
    ax : matplotlib Axes, optional
    zoom : tuple (xmin, xmax, ymin, ymax)
        Axis limits in chords.
    levels : int or array_like
        Contour levels.

    Returns
    -------
    matplotlib Axes
    """
    ax = _axes(ax, figsize=(7, 5))
    g = sol.grid
    m = primitives(sol.q, sol.mach, sol.gamma)["mach"]
    cs = ax.contourf(g.xc, g.yc, m, levels=levels, cmap="viridis")
    if np.nanmax(m) > 1.0 > np.nanmin(m):
        ax.contour(g.xc, g.yc, m, levels=[1.0], colors="w", linewidths=1.0)
    nw = g.n_wake
    ax.fill(g.x[nw : g.shape[0] - nw, 0], g.y[nw : g.shape[0] - nw, 0], color="0.7", zorder=3)
    ax.figure.colorbar(cs, ax=ax, label="Mach")
    ax.set_xlim(zoom[0], zoom[1])
    ax.set_ylim(zoom[2], zoom[3])
    ax.set_aspect("equal")
    ax.set_xlabel("x / c")
    ax.set_ylabel("y / c")
    ax.set_title(f"Mach, M = {sol.mach:g}, alpha = {sol.alpha_deg:g} deg")
    return ax
