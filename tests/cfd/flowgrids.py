"""Small C-grids for the flow-solver tests, independent of ``cfd.c_grid``.

A parabolic C-grid: the map ``z - x0 = zeta^2`` unwraps a symmetric aerofoil (leading edge near the
branch point ``x0``) into a nearly flat line; grid lines are ``xi = const`` and stretched ``eta`` from the
surface to ``eta_max``. ``thickness = 0`` gives a flat plate (a slit along ``0 <= x <= 1``), around which
a uniform stream along ``x`` is an exact slip-wall solution.
"""

import numpy as np
from scipy.optimize import brentq

from cfd import grid_from_nodes


def _yt(x, t):
    return 5 * t * (0.2969 * np.sqrt(x) - 0.1260 * x - 0.3516 * x**2 + 0.2843 * x**3 - 0.1036 * x**4)


def parabolic_c_grid(thickness=0.12, n_surface=48, n_wake=12, nj=17, eta_max=3.5, xi_max=3.5, ds0=0.02,
                     wiggle=0.0):
    """C-grid around a closed-trailing-edge NACA 00xx (or a flat plate) by the parabolic map.

    Returns
    -------
    Grid
        ``ni = 2 n_wake + n_surface + 1`` nodes around, ``nj`` nodes outward.
    """
    x0 = 0.5 * 1.1019 * thickness**2  # half the leading-edge radius: a smooth unwrapped nose
    half = n_surface // 2
    phi = np.linspace(0.0, np.pi, half + 1)
    xs = 0.5 * (1 - np.cos(phi))          # LE -> TE
    zeta = np.sqrt((xs - x0) + 1j * _yt(xs, thickness) + 0j)
    xi_u, eta_u = zeta.real, zeta.imag
    xi_te = xi_u[-1]
    # Wake: geometric growth from the last surface spacing up to xi_max.
    d = xi_u[-1] - xi_u[-2]
    k = np.arange(1, n_wake + 1)
    r = brentq(lambda r: d * np.sum(r**k) - (xi_max - xi_te), 1.0 + 1e-9, 3.0)
    xi_w = xi_te + d * np.cumsum(r ** np.arange(1, n_wake + 1))
    xi = np.concatenate([-xi_w[::-1], -xi_u[::-1], xi_u[1:], xi_w])
    eta_s = np.concatenate([np.zeros(n_wake), eta_u[::-1], eta_u[1:], np.zeros(n_wake)])
    # Outward stretching (same in every i line).
    s = np.linspace(0.0, 1.0, nj)
    b = 3.0
    f = np.sinh(b * s) / np.sinh(b)
    eta = eta_s[:, None] + (eta_max - eta_s[:, None]) * f[None, :]
    xx = np.broadcast_to(xi[:, None], eta.shape).copy()
    if wiggle:
        ii, jj = np.meshgrid(np.linspace(0, 1, len(xi)), s, indexing="ij")
        bump = wiggle * np.sin(7 * np.pi * ii) * np.sin(np.pi * jj) ** 2
        # Shifts of a fraction of the local spacing: curved, skewed, never inverted.
        xx = xx + bump * np.gradient(xx, axis=0)
        eta = eta + bump * np.sin(3 * np.pi * ii) * np.gradient(eta, axis=1)
    z = x0 + (xx + 1j * eta) ** 2
    ni = len(xi)
    assert ni == 2 * n_wake + n_surface + 1
    return grid_from_nodes(z.real, z.imag, n_wake=n_wake)
