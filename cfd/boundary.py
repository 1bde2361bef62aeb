"""Ghost cells of the cell-centred Euler scheme: wall, wake cut and characteristic far field.

The residual (``cfd.euler``) works on the state padded with two ghost layers on each side; this module
fills them. Everything is complex-safe for complex-step differentiation: ``abs`` is ``x sign(Re x)``,
and the branch choices (``cabs``, ``cmax``) are made on real parts; the far field's upwind choice is a smooth blend.

Layout: states here are component-first, ``(..., 4, n)`` or ``(..., 4, ni-1, nj-1)``.

Wall (``j = 0``, wall cells)
    Ghost layer ``-1`` mirrors cell ``(ic, 0)``, layer ``-2`` mirrors cell ``(ic, 1)``: the normal component
    of the velocity *relative to the wall* (``u - w``, ``w`` the face grid velocity) is reversed,
    density and pressure are copied (constant extrapolation). These ghosts serve the dissipation
    stencil and the pressure sensor only: the wall flux itself is pressure only, with the wall pressure
    extrapolated linearly from the first two cells (``wall_pressure``), and no dissipation crosses the
    wall.
Wake cut (``j = 0``, ``ic < n_wake`` and ``ic >= ni-1-n_wake``)
    Ghost layer ``-1`` of cell ``(ic, 0)`` is cell ``(ni-2-ic, 0)``, layer ``-2`` is cell ``(ni-2-ic, 1)``.
Far field (``j = nj-1`` and the two outflow ends ``i = 0``, ``i = ni-1``)
    Riemann invariants along the outward face normal ``n``: ``R+ = u.n + 2c/(gamma-1)`` from the interior
    cell, ``R- = u_inf.n - 2c_inf/(gamma-1)`` from the free stream; tangential velocity and entropy
    ``p / rho^gamma`` from the free stream where the relative normal velocity ``(u - w).n`` points in,
    from the interior where it points out, blended smoothly across ``|(u - w).n| < 0.05 c_inf``
    (``outflow_weight``: a hard switch stalls Newton's method where the normal velocity crosses zero). Both
    ghost layers get this boundary state. With
    ``vortex=True`` the free stream seen by the far field includes the compressible point vortex of
    Thomas & Salas (AIAA J. 24(7), 1986) at the quarter chord with circulation ``Gamma = U c Cl / 2``.
"""

import numpy as np

__all__ = ["cabs", "cmax", "wall_pressure", "farfield_state", "outflow_weight", "FARFIELD_BLEND", "wall_mirror",
           "vortex_free_stream"]


def cabs(x):
    """Complex-safe absolute value ``x sign(Re x)`` (equals ``abs`` for real input)."""
    return x * np.sign(x.real)


def cmax(a, b):
    """Complex-safe maximum: the argument with the larger real part (the active branch)."""
    return np.where(a.real >= b.real, a, b)


def wall_pressure(p0, p1):
    """Wall pressure from the first two cells off the wall, linear extrapolation in the index.

    Parameters
    ----------
    p0, p1 : ndarray, shape (...)
        Pressure in cells ``jc = 0`` and ``jc = 1``.

    Returns
    -------
    ndarray, shape (...)
        ``1.5 p0 - 0.5 p1``.
    """
    return 1.5 * p0 - 0.5 * p1


def wall_mirror(rho, u, v, p, nx, ny, wx=0.0, wy=0.0, gamma=1.4):
    """Conserved ghost state mirroring the relative normal velocity at a slip wall.

    Parameters
    ----------
    rho, u, v, p : ndarray, shape (..., n)
        Interior cell state.
    nx, ny : ndarray, shape (n,)
        Unit wall normal (either orientation).
    wx, wy : ndarray, shape (..., n) or float
        Wall (grid) velocity at the face.

    Returns
    -------
    ndarray, shape (..., 4, n)
    """
    vn = (u - wx) * nx + (v - wy) * ny
    ug = u - 2.0 * vn * nx
    vg = v - 2.0 * vn * ny
    return _conserved_first(rho, ug, vg, p, gamma)


def vortex_free_stream(xf, yf, flow, cl):
    """Free stream plus the compressible point vortex (Thomas & Salas) at ``(0.25, 0)``.

    Parameters
    ----------
    xf, yf : ndarray, shape (n,)
        Far-field face centres, chords.
    flow : FlowCondition
    cl : float
        Lift coefficient; circulation ``Gamma = 0.5 * mach * cl`` (chord 1, clockwise positive).

    Returns
    -------
    rho, u, v, p : ndarray, shape (n,)
        Isentropic, constant total enthalpy.
    """
    g, m, a = flow.gamma, flow.mach, flow.alpha
    beta = np.sqrt(1.0 - m * m)
    dx, dy = xf - 0.25, yf
    r = np.hypot(dx, dy)
    th = np.arctan2(dy, dx)
    k = 0.5 * m * cl * beta / (2.0 * np.pi * r) / (1.0 - (m * np.sin(th - a)) ** 2)
    u = m * np.cos(a) + k * np.sin(th)
    v = m * np.sin(a) - k * np.cos(th)
    h0 = 1.0 / (g - 1.0) + 0.5 * m * m          # total enthalpy of the free stream (a_inf = 1)
    c2 = (g - 1.0) * (h0 - 0.5 * (u * u + v * v))
    rho = c2 ** (1.0 / (g - 1.0))               # entropy of the free stream: p / rho^g = 1 / g
    return rho, u, v, rho * c2 / g


FARFIELD_BLEND = 0.05
"""Width of the far field's inflow/outflow blend, as a fraction of the free-stream speed of sound."""


def outflow_weight(qn, c_free):
    """Smooth upwind weight of the interior state at a far-field face: ``(1 + tanh(qn / (FARFIELD_BLEND c)))/2``.

    A hard switch on the sign of ``qn`` makes the residual non-differentiable wherever the relative normal
    velocity of a far-field face passes through zero - on the far-field lines nearly parallel to the free
    stream and at the corners where they meet the downstream boundary - and Newton's method cycles there
    instead of converging (an unsteady step stalled at ``|F| ~ 1e-6 .. 1e-5``, all of it in those cells). The
    blend is the far-field counterpart of Harten's entropy fix: the upwind choice is smoothed over a band of
    normal velocities small against the speed of sound, where the interior and the free-stream states it
    chooses between differ only by the far field's small disturbance.

    Parameters
    ----------
    qn : ndarray, shape (..., n)
        Relative normal velocity ``(u - w).n`` of the boundary state (outward normal), complex allowed.
    c_free : ndarray or float
        Free-stream speed of sound (same units).

    Returns
    -------
    ndarray, shape (..., n)
        Weight in (0, 1): 1 for outflow, 0 for inflow, 1/2 at ``qn = 0``.
    """
    return 0.5 * (1.0 + np.tanh(qn / (FARFIELD_BLEND * c_free)))


def farfield_state(rho, u, v, p, nx, ny, free, wn=0.0, gamma=1.4):
    """Characteristic (Riemann-invariant) far-field state.

    Parameters
    ----------
    rho, u, v, p : ndarray, shape (..., n)
        Interior cell next to the boundary.
    nx, ny : ndarray, shape (n,)
        Unit outward normal.
    free : tuple of 4 arrays or floats
        Free-stream ``rho, u, v, p`` (shape (n,) or scalars).
    wn : ndarray, shape (..., n) or float
        Normal grid velocity of the face (decides inflow / outflow on the relative velocity).

    Returns
    -------
    ndarray, shape (..., 4, n)
        Conserved boundary state, used for both ghost layers.
    """
    g = gamma
    rf, uf, vf, pf = free
    ci = np.sqrt(g * p / rho)
    cf = np.sqrt(g * pf / rf)
    qni = u * nx + v * ny
    qnf = uf * nx + vf * ny
    rp = qni + 2.0 * ci / (g - 1.0)
    rm = qnf - 2.0 * cf / (g - 1.0)
    qn = 0.5 * (rp + rm)
    c = 0.25 * (g - 1.0) * (rp - rm)
    # Tangential velocity and entropy from upstream of the face: weight b = 1 on the interior where the relative
    # normal velocity points out, 0 where it points in, blended smoothly across |qn - wn| < FARFIELD_BLEND c_inf.
    b = outflow_weight(qn - wn, cf)

    def upwind(interior, free_stream):
        return free_stream + b * (interior - free_stream)

    ut = upwind(u - qni * nx, uf - qnf * nx)
    vt = upwind(v - qni * ny, vf - qnf * ny)
    s = upwind(p / rho**g, pf / rf**g)
    rb = (c * c / (g * s)) ** (1.0 / (g - 1.0))
    pb = rb * c * c / g
    return _conserved_first(rb, ut + qn * nx, vt + qn * ny, pb, g)


def _conserved_first(rho, u, v, p, gamma):
    rho, u, v, p = np.broadcast_arrays(rho, u, v, p)
    return np.stack([rho, rho * u, rho * v, p / (gamma - 1.0) + 0.5 * rho * (u * u + v * v)], axis=-2)
