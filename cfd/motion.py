"""Rigid plunge and pitch of the aerofoil as inputs of the linearised equations.

Conventions (docs/conventions.md): plunge ``h`` in chords, positive up; pitch ``alpha`` in radians, positive
nose up, about the pivot ``(x_p, 0)`` (chords from the leading edge, on the chord line); convective time ``s``.

Body frame on the fixed grid
----------------------------
The whole grid moves rigidly with the aerofoil. In the inertial frame the scheme is the arbitrary Lagrangian-
Eulerian (ALE) one of ``cfd.euler``: ``d(V Q)/dt + R(Q; geometry(t), W(t), free stream) = 0`` with the face
(grid) velocities ``W`` and constant cell areas ``V`` (a rigid motion: the discrete geometric conservation law
``sum over faces of W.S = dV/dt = 0`` holds exactly, because the rigid velocity is divergence free and linear
in position, so its value at the face centre is its exact face average). Every part of the residual (central
flux, JST dissipation and its sensor, wall mirror and wall flux, characteristic far field, the optional
point vortex) is covariant under rotation: rotating the geometry, the face velocities, the momentum and the
free stream together rotates the momentum rows of ``R`` and leaves the rest unchanged. Written with the
momentum in body axes, ``Q = T q`` (``T`` rotates the momentum components from body to inertial axes), the
equations on the fixed body grid are therefore

    V dq/dt + V T^-1 (dT/dt) q + R(q; w, free stream in body axes) = 0,

with ``w = T^-1 W`` the face velocities in body axes. A nose-up pitch ``alpha`` is a clockwise rotation, so

- the free stream in body axes is at incidence ``alpha_0 + alpha`` (the far field sees it);
- the face velocities of the rotation are ``w = alpha' ((y - 0), -(x - x_p))`` (to first order), at every
  face, the wall and far-field faces included;
- ``T^-1 dT/dt q = alpha' (0, rho v, -rho u, 0)``: the frame-rotation term, first order in ``alpha'`` times
  the steady momentum;
- lift is normal to the inertial free stream, which in body axes is at ``alpha_0 + alpha``: the loads of
  ``cfd.loads`` turn with it, ``d(Cl, Cm, Cd)/d alpha = (-Cd_0, 0, Cl_0)`` at a fixed state (pressure forces;
  the moment is about the body's quarter chord, a point that moves with it).

A plunge ``h`` is a translation: face velocities ``(0, h')`` everywhere, nothing else (``T = I``). It is
exactly a spatially uniform vertical gust of velocity ``-h'`` (``cfd.gust``: a gust ``v_g`` moves the grid at
``-v_g``), so ``H_plunge(omega) = -i omega H_uniform(omega)``.

Linearised about the steady state, with ``x`` the input (``h`` or ``alpha``) and ``x' = dx/ds``::

    V dq/dt + J q + b0 x + b1 x' = 0,      y = C q + d x          (t solver time, s = mach t convective)

``b0 = dR/d alpha`` of the free stream (zero for the plunge), ``b1 = mach (dR/dw . w_unit + V T^-1 dT/dalpha q)``
(the ``mach`` converts the convective rate to solver units: face velocities are in units of ``a_inf``), and
``d`` the explicit load derivative (zero for the plunge). For ``x = exp(i omega s)``: ``b = b0 + i omega b1``.
Every derivative is a complex step through the one residual (``cfd.jacobian.residual_derivative``) or through
the loads: exact to round-off (no finite-difference step).

Pivots: the rotation's face velocities about ``x_2`` and ``x_1`` differ by the uniform ``(0, (x_2 - x_1)
alpha')``, a plunge of ``(x_2 - x_1) alpha``: ``H_alpha(x_2) = H_alpha(x_1) + (x_2 - x_1) H_h`` exactly.
"""

from dataclasses import dataclass

import numpy as np

from .flow import FlowCondition
from .frequencies import check_pivot
from .jacobian import H_STEP, residual_derivative
from .linear import LinearError, wall_loads
from .euler import residual

__all__ = ["INPUTS", "MOTION_INPUTS", "MotionForcing", "motion_forcing", "check_inputs", "rotation_face_velocity",
           "incidence_derivative", "frame_rotation_term", "load_incidence_derivative"]

INPUTS = ("gust", "plunge", "pitch")
MOTION_INPUTS = ("plunge", "pitch")


def check_inputs(inputs):
    """Input names, checked: a non-empty sequence of distinct names from :data:`INPUTS` (a string is one name).

    Returns
    -------
    tuple of str
    """
    if isinstance(inputs, str):
        inputs = (inputs,)
    try:
        inputs = tuple(inputs)
    except TypeError:
        raise LinearError(f"inputs must be a sequence of names from {INPUTS}; got {inputs!r}") from None
    bad = [i for i in inputs if i not in INPUTS]
    if bad or not inputs:
        raise LinearError(f"unknown input(s) {bad or inputs!r}; choose from {INPUTS}, e.g. inputs=('plunge', 'pitch')")
    if len(set(inputs)) != len(inputs):
        raise LinearError(f"inputs {inputs!r} name an input twice; give each once")
    return inputs


@dataclass(frozen=True)
class _ComplexIncidence(FlowCondition):
    """A :class:`FlowCondition` whose incidence carries a complex step ``dalpha`` (radians), for differentiation."""

    dalpha: complex = 0.0

    @property
    def alpha(self):
        return np.deg2rad(self.alpha_deg) + self.dalpha


def _stepped(flow, h=H_STEP):
    return _ComplexIncidence(flow.mach, flow.alpha_deg, flow.gamma, dalpha=1j * h)


def _face_centres(grid):
    """Centres of the i-faces (2, ni, nj-1) and the j-faces (2, ni-1, nj), chords."""
    x, y = grid.x, grid.y
    ci = np.stack([0.5 * (x[:, 1:] + x[:, :-1]), 0.5 * (y[:, 1:] + y[:, :-1])])
    cj = np.stack([0.5 * (x[1:, :] + x[:-1, :]), 0.5 * (y[1:, :] + y[:-1, :])])
    return ci, cj


def rotation_face_velocity(grid, pivot=0.25):
    """Face velocities of a unit nose-up pitch rate about ``(pivot, 0)``, in body axes.

    Parameters
    ----------
    grid : Grid
    pivot : float
        Chords from the leading edge.

    Returns
    -------
    wi : ndarray, shape (2, ni, nj-1)
    wj : ndarray, shape (2, ni-1, nj)
        ``(y, -(x - pivot))`` at the face centres: velocity per unit ``d alpha / ds`` in units of ``U`` (chords
        per radian). Exact face averages (the field is linear in position).
    """
    return tuple(np.stack([c[1], -(c[0] - pivot)]) for c in _face_centres(grid))


def _uniform_face_velocity(grid):
    """Face velocities ``(0, 1)`` on every face: a unit upward translation rate."""
    ni, nj = grid.shape
    wi = np.zeros((2, ni, nj - 1))
    wj = np.zeros((2, ni - 1, nj))
    wi[1] = 1.0
    wj[1] = 1.0
    return wi, wj


def incidence_derivative(lin):
    """``dR/d alpha`` of the free stream's incidence at the fixed steady state, by complex step.

    With the point-vortex far field the vortex's circulation is the lift of the state in the current wind axes,
    so it turns with the incidence too (``dCl/d alpha = -Cd_0`` at a fixed state): included.

    Parameters
    ----------
    lin : LinearSystem

    Returns
    -------
    ndarray, shape (4N,)
        Per radian, solver units (flux).
    """
    q = lin.q.astype(complex)
    R = residual(lin.grid, q, _stepped(lin.flow), scheme=lin.scheme)
    return (R.imag / H_STEP).ravel()


def load_incidence_derivative(lin):
    """``d(Cl, Cm, Cd)/d alpha`` at the fixed steady state: the wind axes turning with the body.

    Returns
    -------
    ndarray, shape (3,)
        Rows in the order of ``cfd.linear.OUTPUTS``; ``(-Cd_0, 0, Cl_0)`` to round-off (pressure loads).
    """
    return wall_loads(lin.grid, lin.q.astype(complex), _stepped(lin.flow)).imag / H_STEP


def frame_rotation_term(lin):
    """``V T^-1 dT/d alpha q``: the frame-rotation term per unit nose-up pitch rate (solver time).

    Returns
    -------
    ndarray, shape (4N,)
        ``V (0, rho v, -rho u, 0)`` per cell, steady momentum in body axes.
    """
    q = lin.q
    term = np.zeros_like(q)
    term[..., 1] = q[..., 2]
    term[..., 2] = -q[..., 1]
    return lin.V * term.ravel()


def _face_velocity_derivative(lin, direction):
    """``dR/dw . direction`` (flat, (4N,)) at the steady state."""
    d = residual_derivative(lin.grid, lin.q, lin.flow, direction, scheme=lin.scheme)
    return d.ravel()


@dataclass(frozen=True, eq=False)
class MotionForcing:
    """Forcing of one rigid-motion input: ``V dq/dt + J q + b0 x + b1 x' = 0``, ``y = C q + d x``.

    Attributes
    ----------
    name : {"plunge", "pitch"}
    pivot : float or None
        Pitch axis (chords from the leading edge); None for the plunge.
    b0 : ndarray, shape (4N,)
        Per unit input (``h`` in chords or ``alpha`` in radians), solver units.
    b1 : ndarray, shape (4N,)
        Per unit convective rate ``dx/ds``.
    d : ndarray, shape (3,)
        Explicit load derivative, rows ``(Cl, Cm, Cd)``.
    """

    name: str
    pivot: object
    b0: np.ndarray
    b1: np.ndarray
    d: np.ndarray

    def at(self, omega):
        """Forcing amplitude ``b0 + i omega b1`` of ``x = exp(i omega s)`` (omega in U/c, finite), shape (4N,)."""
        return self.b0 + 1j * float(omega) * self.b1

    @property
    def operator(self):
        """``[b0, b1]``, shape (4N, 2): ``b(omega) = operator @ [1, i omega]``."""
        return np.stack([self.b0, self.b1], axis=1)


def motion_forcing(lin, name, pivot=0.25):
    """The forcing terms of a rigid plunge or pitch (see the module docstring).

    Parameters
    ----------
    lin : LinearSystem
    name : {"plunge", "pitch"}
    pivot : float
        Pitch axis, chords from the leading edge (ignored for the plunge).

    Returns
    -------
    MotionForcing
    """
    if name == "plunge":
        b1 = lin.mach * _face_velocity_derivative(lin, _uniform_face_velocity(lin.grid))
        zero = np.zeros(lin.n)
        return MotionForcing("plunge", None, zero, b1, np.zeros(3))
    if name != "pitch":
        raise LinearError(f"motion input must be one of {MOTION_INPUTS}; got {name!r}")
    pivot = check_pivot(pivot)
    rate = _face_velocity_derivative(lin, rotation_face_velocity(lin.grid, pivot)) + frame_rotation_term(lin)
    return MotionForcing("pitch", pivot, incidence_derivative(lin), lin.mach * rate, load_incidence_derivative(lin))
