from types import SimpleNamespace

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from cfd import c_grid, naca  # noqa: E402
from cfd.export import primitives  # noqa: E402
from cfd.plots import plot_cp, plot_grid, plot_mach  # noqa: E402


@pytest.fixture(scope="module")
def sol():
    """A synthetic 'solution' with the duck-typed interface: free stream plus a speed-up near the aerofoil."""
    g = c_grid(naca("0012"), ni=121, nj=40, n_surface=64, farfield=10.0)
    gamma, mach = 1.4, 0.7
    r2 = (g.xc - 0.3) ** 2 + g.yc**2
    speed = mach * (1.0 + 0.5 * np.exp(-r2 / 0.05) * np.sign(g.yc + 1e-3).clip(0.2, 1.0))
    p = 1.0 / gamma - 0.5 * (speed**2 - mach**2)  # Bernoulli-like, rho = 1
    q = np.stack([np.ones_like(p), speed, np.zeros_like(p), p / (gamma - 1) + 0.5 * speed**2], axis=-1)
    cp_wall = primitives(q[g.wall, 0], mach, gamma)["cp"]
    return SimpleNamespace(grid=g, q=q, mach=mach, alpha_deg=0.0, gamma=gamma, x_wall=g.xc[g.wall, 0], cp=cp_wall)


def test_plot_grid_full_and_zoom(sol, tmp_path):
    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4))
    assert plot_grid(sol.grid, ax=a) is a
    plot_grid(sol.grid, ax=b, zoom="aerofoil")
    assert b.get_xlim() == (-0.2, 1.3)
    fig.savefig(tmp_path / "grid.png")
    plt.close(fig)
    assert (tmp_path / "grid.png").stat().st_size > 10_000


def test_plot_cp_upper_and_lower(sol, tmp_path):
    ax = plot_cp(sol)
    labels = [line.get_label() for line in ax.get_lines()]
    assert "upper" in labels and "lower" in labels and "sonic" in labels
    upper = ax.get_lines()[0]
    assert np.all(np.diff(upper.get_xdata()) > 0)  # upper surface from the LE to the TE
    assert ax.get_ylabel() == "-Cp"
    ax.figure.savefig(tmp_path / "cp.png")
    plt.close(ax.figure)
    assert (tmp_path / "cp.png").stat().st_size > 10_000


def test_plot_mach_contours(sol, tmp_path):
    ax = plot_mach(sol)
    assert ax.get_xlim() == (-0.5, 1.5)
    ax.figure.savefig(tmp_path / "mach.png")
    plt.close(ax.figure)
    assert (tmp_path / "mach.png").stat().st_size > 10_000


def test_plots_never_show(sol, monkeypatch):
    monkeypatch.setattr(plt, "show", lambda *a, **k: pytest.fail("plt.show() called"))
    for f in (plot_grid, plot_cp, plot_mach):
        plt.close(f(sol.grid if f is plot_grid else sol).figure)


def test_grid_figure_has_four_panels(sol, tmp_path):
    from cfd.plots import grid_figure

    fig = grid_figure(sol.grid, title="test")
    assert len(fig.axes) == 4
    fig.savefig(tmp_path / "overview.png")
    plt.close(fig)
    assert (tmp_path / "overview.png").stat().st_size > 10_000
