"""Vertical gusts and their split-velocity (SVM) and field-velocity (FVM) terms.

Gust shapes (frozen; paper Eqs. 11, 29-30, 33)
----------------------------------------------
A gust is a frozen vertical velocity field convected downstream with the free stream,
``v_g(x, s) / U = A f(xi)``, ``xi = x - x0 - s`` (the paper's ``x_g0``, Eq. 30), in convective units:
lengths in chords, ``s = t U / c``, velocities in ``U``. ``A = tan(angle_deg)`` (paper Eq. 18:
``angle_deg`` is the peak effective gust angle). The front is at ``xi = 0``: at ``s = 0`` it is at
``x0`` (upstream, ``x0 < 0``) and it reaches ``x_ref`` at ``s = x_ref - x0``. The input signal of the
linear models is ``u(s) = v_g(x_ref, s) / U`` (radians of gust angle, to first order).

Solver units (``cfd.flow``: ``a_inf = 1``, ``|u_inf| = mach``), converted here once::

    t_solver = s / mach,    velocity_solver = mach * v / U,    omega_solver = mach * omega

and the gust is convected along ``x`` at ``U = mach`` (at incidence this is the free-stream speed,
not its ``x`` component: the gust source then does not vanish in the free stream, by O(alpha^2)).

Discrete gust terms
-------------------
Both methods run the residual on a grid moving with the face velocity ``w = (0, -v_g)``
(``face_velocity`` of ``cfd.euler.residual``). The gust velocity of a face is its exact average
along the face (the antiderivative of the profile, or ``sinc`` for a harmonic gust), not a
mid-point value: then ``sum over faces of v_g S_y`` vanishes exactly for every cell (``v_g`` depends
on ``x`` only, and the closed polygon integral of ``g(x) dx`` is zero), so a uniform stream stays
an exact discrete solution under any gust (discrete free-stream preservation, the geometric
conservation law of the moving-grid form).

The SVM adds the linearised sources of paper Eqs. 10 and 14 for a vertical gust,
``s_m = rho_bar (d v_g/dt + u_bar d v_g/dx)``, ``s_e = v_bar s_m``. With ``d/dt = -U d/dx`` for a
frozen gust, ``s_m = rho_bar (u_bar - U) d v_g/dx``. The steady factors ``rho_bar``, ``u_bar``,
``v_bar`` are taken as cell values (second order, like the rest of the scheme) and the gust factor
is integrated over the cell exactly by the divergence theorem,
``int_cell d v_g/dx dA = sum over faces of <v_g>_face S_x`` (outward ``S``), with the same exact face
averages: the source then equals the discrete divergence that the moving-grid flux sees, and it is
zero for a uniform gust (``omega -> 0``) and in a uniform stream (``u_bar = U``).
"""

import math
import warnings
from dataclasses import dataclass
from typing import Optional

import numpy as np

from .checks import kind_of, real_array

__all__ = [
    "GustError",
    "GustPositionError",
    "SineGust",
    "OneMinusCosine",
    "SharpEdged",
    "X0_MAX",
    "MIN_LENGTH",
    "MIN_GUST_STEPS",
    "gust_length",
    "check_gust_step",
    "warn_unseen",
    "edge_average",
    "harmonic_edge_average",
    "face_gust",
    "face_gust_harmonic",
    "cell_x_gradient",
    "gust_face_velocity",
    "svm_source",
]

X0_MAX = -0.5
"""Largest allowed gust start position (chords). The aerofoil's steady perturbation velocity is
still of the order of the thickness ratio half a chord ahead of the leading edge; a gust front placed
there at ``s = 0`` meets a non-uniform stream impulsively (a start-up transient that is not part of the
response to the gust). Upstream of ``x0 = -0.5`` the perturbation is down to a few per cent and
decays as ``1 / r``; ``x0 <= -2`` is recommended for accurate transients."""


MIN_LENGTH = 1e-3
"""Shortest gust length or sine wavelength (chords). No grid of this package resolves a shorter one: the finest
cells of ``cfd.c_grid`` are a few thousandths of a chord (wall spacing 0.004, trailing-edge spacing 0.006), and the
exact face averages of such a gust are those of a zero gust to round-off."""

MIN_GUST_STEPS = 2
"""Fewest time steps a time march takes while a 1-cosine gust (its ``length``) or one wavelength of a sine gust
passes a point (the gust is convected at ``U``: ``length / dt`` steps). Fewer, and the samples of the input may all
miss the gust (a 2-chord gust marched at ``dt = 5``: an input of zeros and loads of about 4e-4 of the true ones) or
alias the sine; the marches (:func:`cfd.ltd_response`, :func:`cfd.ltd_responses`, :func:`cfd.coupled_ltd`,
:func:`cfd.unsteady_response`) refuse it. Two steps give three samples of the bump, the least a study may take
(``studies.schema.MIN_GUST_STEPS`` is the same number, a test checks it); the BDF2 phase-rate warning of
``cfd.ltd`` asks for about 36 steps per length (1 %)."""


class GustError(ValueError):
    """A gust definition is invalid (non-positive length, non-finite angle, bad frequency...)."""


class GustPositionError(GustError):
    """A gust starts inside the aerofoil's region of influence (``x0 > X0_MAX``)."""


def _finite(name, value):
    try:
        if isinstance(value, (str, bytes)):   # length="4" was parsed
            raise TypeError
        v = float(value)
    except (TypeError, ValueError):
        raise GustError(f"{name} must be a real number; got {value!r}") from None
    if not math.isfinite(v):
        raise GustError(f"{name} must be finite; got {value!r}")
    return v


def _angle(angle_deg):
    a = _finite("angle_deg", angle_deg)
    if abs(a) >= 90.0:
        raise GustError(f"angle_deg = {a} is not a gust angle; use |angle_deg| < 90 (e.g. 1 to 5 deg)")
    return a


def _x0(x0):
    x = _finite("x0", x0)
    if x > X0_MAX:
        raise GustPositionError(
            f"x0 = {x} puts the gust front inside the aerofoil's region of influence at s = 0; "
            f"start it upstream, x0 <= {X0_MAX} chords (x0 = -2 or further is recommended)"
        )
    return x


class _Gust:
    """Common machinery: profile ``f(xi)``, its antiderivative ``F(xi)``, amplitude ``A``."""

    x0: Optional[float]
    angle_deg: float

    @property
    def amplitude(self):
        """Peak gust velocity over ``U``: ``tan(angle_deg)``."""
        return math.tan(math.radians(self.angle_deg))

    def _xi(self, x, s):
        x = np.asarray(x, dtype=float)
        s = np.asarray(s, dtype=float)
        return x - (0.0 if self.x0 is None else self.x0) - s

    def velocity(self, x, s):
        """``v_g(x, s) / U``; ``x`` and ``s`` broadcast (chords, convective time)."""
        return self.amplitude * self.profile(self._xi(x, s))

    def dvdx(self, x, s):
        """``d(v_g / U) / dx`` (per chord); zero-width fronts (sharp edge) give 0 off the front."""
        return self.amplitude * self.profile_derivative(self._xi(x, s))

    def dvds(self, x, s):
        """``d(v_g / U) / ds`` = ``-dvdx`` (frozen gust convected at ``U``)."""
        return -self.dvdx(x, s)

    def input(self, s, x_ref=0.0):
        """Input signal ``u(s) = v_g(x_ref, s) / U``, shape of ``s``.

        Raises
        ------
        GustError
            ``s`` not real numbers (a string, None, complex) or holding NaN (whose input was 0).
        """
        t = real_array(s)   # (None for text)
        if t is None or np.any(np.isnan(t)):
            raise GustError(f"s must be a real number or an array of real convective times (s = U t / c), without "
                            f"NaN; got {kind_of(s)} {s!r:.80}")
        return self.velocity(x_ref, s)

    def arrival(self, x_ref=0.0):
        """Convective time at which the front reaches ``x_ref`` (0 for an endless sine)."""
        return 0.0 if self.x0 is None else x_ref - self.x0

    def integral(self, x1, x2, s):
        """``int_{x1}^{x2} v_g(x, s) / U dx`` exactly (antiderivative), broadcast."""
        return self.amplitude * (self.antiderivative(self._xi(x2, s)) - self.antiderivative(self._xi(x1, s)))


@dataclass(frozen=True)
class SineGust(_Gust):
    """Travelling sine gust, paper Eq. 11: ``v_g / U = A sin(2 pi (x - x0 - s) / lambda)``.

    Give exactly one of ``omega`` (U/c units) and ``wavelength`` (chords), ``omega = 2 pi / wavelength``
    (reduced frequency ``k = omega / 2 = pi / wavelength``, Eq. 17).

    Parameters
    ----------
    angle_deg : float
        Peak gust angle (deg), ``A = tan(angle_deg)``.
    omega, wavelength : float
        Frequency or wavelength, positive and finite.
    x0 : float or None
        None (default): an endless wave train (Eq. 11 with phase zero at ``x = s = 0``). A number: the
        train's front, ``v_g = 0`` downstream of ``x0 + s``; the gust starts from zero velocity there
        (``x0 <= X0_MAX``).
    """

    angle_deg: float
    omega: Optional[float] = None
    wavelength: Optional[float] = None
    x0: Optional[float] = None

    def __post_init__(self):
        object.__setattr__(self, "angle_deg", _angle(self.angle_deg))
        if (self.omega is None) == (self.wavelength is None):
            raise GustError("give exactly one of omega (U/c units) and wavelength (chords) for a SineGust")
        if self.omega is not None:
            w = _finite("omega", self.omega)
            if w <= 0.0:
                raise GustError(f"omega = {w} must be positive; the omega -> 0 limit is a uniform gust")
            lam = 2.0 * math.pi / w
            if not lam >= MIN_LENGTH:
                raise GustError(f"omega = {w} (U/c units) is a wavelength of {lam:.3g} chords, below {MIN_LENGTH:g} "
                                f"(cfd.gust.MIN_LENGTH): no grid resolves it; use omega <= {2 * math.pi / MIN_LENGTH:.4g}"
                                " (k = omega / 2; the paper's reach k = 50)")
        else:
            lam = _finite("wavelength", self.wavelength)
            if not lam >= MIN_LENGTH:
                raise GustError(f"wavelength = {lam} chords must be at least {MIN_LENGTH:g} (cfd.gust.MIN_LENGTH): no "
                                "grid resolves a shorter one; give it in chords, e.g. wavelength=4.0")
            w = 2.0 * math.pi / lam
        object.__setattr__(self, "omega", w)
        object.__setattr__(self, "wavelength", lam)
        if self.x0 is not None:
            object.__setattr__(self, "x0", _x0(self.x0))

    def profile(self, xi):
        """Unit-amplitude profile ``f(xi)``, ``v_g / U = A f(xi)``, at ``xi = x - x0 - s`` (chords from the front,
        ``x0 = 0`` for an endless train; the gust fills ``xi <= 0``), any shape."""
        ph = self.omega * xi
        return np.sin(ph) if self.x0 is None else np.where(xi <= 0.0, np.sin(ph), 0.0)

    def profile_derivative(self, xi):
        """``df/dxi`` (per chord), shape of ``xi``."""
        d = self.omega * np.cos(self.omega * xi)
        return d if self.x0 is None else np.where(xi <= 0.0, d, 0.0)

    def antiderivative(self, xi):
        """``F(xi)`` with ``F' = f`` (chords), shape of ``xi``: exact cell and face integrals of the gust."""
        if self.x0 is not None:
            xi = np.minimum(xi, 0.0)
        return -np.cos(self.omega * xi) / self.omega


@dataclass(frozen=True)
class OneMinusCosine(_Gust):
    """1-cosine gust, paper Eqs. 29-30: ``v_g / U = (A / 2)(1 - cos(2 pi xi / length))`` for
    ``-length <= xi <= 0``, zero otherwise.

    Parameters
    ----------
    length : float
        Gust length (chords, ``> 0``); the peak ``A`` is at ``xi = -length / 2``.
    angle_deg : float
        Peak gust angle (deg).
    x0 : float
        Front position at ``s = 0`` (chords, ``<= X0_MAX``); the gust meets ``x_ref`` at ``s = x_ref - x0``.
    """

    length: float
    angle_deg: float
    x0: float = -2.0

    def __post_init__(self):
        L = _finite("length", self.length)
        if not L >= MIN_LENGTH:
            raise GustError(f"length = {L} chords is below {MIN_LENGTH:g} (cfd.gust.MIN_LENGTH): no grid resolves a "
                            "shorter gust; give the length in chords, e.g. length=1.0 (the paper's gusts: 1 to 20)")
        object.__setattr__(self, "length", L)
        object.__setattr__(self, "angle_deg", _angle(self.angle_deg))
        object.__setattr__(self, "x0", _x0(self.x0))

    def profile(self, xi):
        """Unit-amplitude profile ``f(xi)``, ``v_g / U = A f(xi)``, at ``xi = x - x0 - s`` (chords from the front,
        ``x0 = 0`` for an endless train; the gust fills ``xi <= 0``), any shape."""
        inside = (xi <= 0.0) & (xi >= -self.length)
        return np.where(inside, 0.5 * (1.0 - np.cos(2.0 * np.pi * xi / self.length)), 0.0)

    def profile_derivative(self, xi):
        """``df/dxi`` (per chord), shape of ``xi``."""
        inside = (xi <= 0.0) & (xi >= -self.length)
        return np.where(inside, (np.pi / self.length) * np.sin(2.0 * np.pi * xi / self.length), 0.0)

    def antiderivative(self, xi):
        """``F(xi)`` with ``F' = f`` (chords), shape of ``xi``: exact cell and face integrals of the gust."""
        L = self.length
        xc = np.clip(xi, -L, 0.0)
        return 0.5 * (xc + L) - (L / (4.0 * np.pi)) * np.sin(2.0 * np.pi * xc / L)


@dataclass(frozen=True)
class SharpEdged(_Gust):
    """Sharp-edged gust, paper Eq. 33: ``v_g / U = A`` behind the front (``xi <= 0``), 0 ahead.

    Parameters
    ----------
    angle_deg : float
        Gust angle (deg).
    x0 : float
        Front position at ``s = 0`` (chords, ``<= X0_MAX``).
    """

    angle_deg: float
    x0: float = -2.0

    def __post_init__(self):
        object.__setattr__(self, "angle_deg", _angle(self.angle_deg))
        object.__setattr__(self, "x0", _x0(self.x0))

    def profile(self, xi):
        """Unit-amplitude profile ``f(xi)``, ``v_g / U = A f(xi)``, at ``xi = x - x0 - s`` (chords from the front,
        ``x0 = 0`` for an endless train; the gust fills ``xi <= 0``), any shape."""
        return np.where(xi <= 0.0, 1.0, 0.0)

    def profile_derivative(self, xi):
        """``df/dxi`` (per chord), shape of ``xi``."""
        return np.zeros(np.shape(xi))  # a delta at the front: use the cell integrals, never point values

    def antiderivative(self, xi):
        """``F(xi)`` with ``F' = f`` (chords), shape of ``xi``: exact cell and face integrals of the gust."""
        return np.minimum(xi, 0.0)


def gust_length(gust):
    """The length a march must resolve (chords): a 1-cosine gust's ``length``, a sine gust's ``wavelength``; None for
    the sharp-edged gust (a front, no length: its steps are judged by the phase-rate warning of ``cfd.ltd``)."""
    if isinstance(gust, OneMinusCosine):
        return gust.length
    if isinstance(gust, SineGust):
        return gust.wavelength
    return None


def check_gust_step(gust, dt, error=GustError):
    """Refuse (``error``) a time step ``dt`` (convective time) in which the gust passes in fewer than
    :data:`MIN_GUST_STEPS` steps: the march's samples could all miss it.

    Parameters
    ----------
    gust : SineGust, OneMinusCosine or SharpEdged
    dt : float
        Convective time step, positive.
    error : type
        The caller's exception class (a subclass of ``ValueError``).
    """
    L = gust_length(gust)
    if L is None or L >= MIN_GUST_STEPS * dt * (1.0 - 1e-12):
        return
    what = "1-cosine gust of length" if isinstance(gust, OneMinusCosine) else "sine gust of wavelength"
    raise error(f"the {what} {L:g} chords passes a point in {L / dt:.3g} time steps of dt = {dt:g}, fewer than "
                f"{MIN_GUST_STEPS} (cfd.gust.MIN_GUST_STEPS): the march's samples can miss the gust altogether "
                f"(an input of zeros and loads of about zero). Use dt <= {L / MIN_GUST_STEPS:.3g} (the largest step "
                f"that resolves it; dt <= {L * math.sqrt(0.03) / (2.0 * math.pi):.3g} keeps the BDF2 phase-rate "
                "error under 1 %), or check that length and dt are both in chords and convective time")


def warn_unseen(gust, t_end, x_ref=0.0, stacklevel=3):
    """Warn (``RuntimeWarning``) when a march that ends at ``t_end`` stops before the gust's front reaches
    ``x_ref`` (its loads are those of the undisturbed flow, about zero, not a gust response), or before the peak of
    a 1-cosine gust reaches it (a gust of 1e300 chords: an input of zeros)."""
    arrival = gust.arrival(x_ref)
    if isinstance(gust, OneMinusCosine) and arrival < t_end < arrival + 0.5 * gust.length:
        warnings.warn(f"the march ends at t_end = {t_end:g}, before the peak of the {gust.length:g}-chord gust reaches "
                      f"x_ref = {x_ref:g} at s = {arrival + 0.5 * gust.length:g}: the loads are those of its rising "
                      f"part only. March to at least t_end = {arrival + gust.length + 5.0:g} for the whole response",
                      RuntimeWarning, stacklevel=stacklevel)
    if gust.x0 is not None and t_end <= arrival:
        warnings.warn(f"the march ends at t_end = {t_end:g}, before the gust front (x0 = {gust.x0:g}) reaches x_ref = "
                      f"{x_ref:g} at s = {arrival:g}: the loads will be about zero. March to at least "
                      f"t_end = {arrival + (gust_length(gust) or 1.0) + 5.0:g}, or start the gust nearer (x0 <= "
                      f"{X0_MAX:g})", RuntimeWarning, stacklevel=stacklevel)


# ---------------------------------------------------------------------------------------------
# Face averages and cell integrals
# ---------------------------------------------------------------------------------------------

def _abscissae(name, value):
    """Edge end-point abscissae as a float array, or :class:`GustError` naming ``name`` unless they are real
    numbers: a complex value lost its imaginary part with only a ``ComplexWarning``, None became NaN, text failed
    in NumPy."""
    v = real_array(value)
    if v is None:
        raise GustError(f"{name} must be a real number or an array of real end-point abscissae (chords); got "
                        f"{kind_of(value)} {value!r:.80}")
    return v


def edge_average(gust, x1, x2, s):
    """Exact average of ``v_g / U`` along straight edges whose end points have abscissae x1, x2.

    ``v_g`` depends on ``x`` only, so the average along the edge is
    ``(G(x2) - G(x1)) / (x2 - x1)`` with ``G`` the antiderivative; edges with ``x1 == x2`` (to
    round-off) take the point value.

    Parameters
    ----------
    gust : SineGust, OneMinusCosine or SharpEdged
    x1, x2 : ndarray, broadcastable
        End-point abscissae (chords).
    s : float
        Convective time.

    Returns
    -------
    ndarray

    Raises
    ------
    GustError
        If ``x1`` or ``x2`` is not a real number or an array of real numbers (complex, text, None).
    """
    x1 = _abscissae("x1", x1)
    x2 = _abscissae("x2", x2)
    dx = x2 - x1
    tiny = np.abs(dx) <= 1e-13 * (1.0 + np.abs(x1))
    safe = np.where(tiny, 1.0, dx)
    avg = gust.integral(x1, x2, s) / safe
    return np.where(tiny, gust.velocity(0.5 * (x1 + x2), s), avg)


def harmonic_edge_average(x1, x2, omega, x_ref=0.0):
    """Exact average of the unit harmonic gust ``exp(-i omega (x - x_ref))`` along straight edges.

    The gust ``v_g / U = exp(i omega (s - (x - x_ref)))`` has ``u(s) = exp(i omega s)`` at ``x_ref``;
    this returns its spatial amplitude averaged over each edge,
    ``exp(-i omega (x_m - x_ref)) sinc(omega dx / 2)`` (``x_m`` the mid-point), stable for any ``dx``.

    Parameters
    ----------
    x1, x2 : ndarray, broadcastable
    omega : float
        U/c units, finite.
    x_ref : float

    Returns
    -------
    ndarray, complex

    Raises
    ------
    GustError
        If ``x1`` or ``x2`` is not a real number or an array of real numbers (complex, text, None).
    """
    x1 = _abscissae("x1", x1)
    x2 = _abscissae("x2", x2)
    xm = 0.5 * (x1 + x2)
    return np.exp(-1j * omega * (xm - x_ref)) * np.sinc(omega * (x2 - x1) / (2.0 * np.pi))


def face_gust(grid, gust, s):
    """Face averages of ``v_g / U`` at convective time ``s``.

    Parameters
    ----------
    grid : Grid
    gust : gust object
    s : float

    Returns
    -------
    gi : ndarray, shape (ni, nj-1)
        On the i-faces (edge from node ``(i, jc)`` to ``(i, jc+1)``).
    gj : ndarray, shape (ni-1, nj)
        On the j-faces (edge from node ``(ic, j)`` to ``(ic+1, j)``).
    """
    x = grid.x
    return edge_average(gust, x[:, :-1], x[:, 1:], s), edge_average(gust, x[:-1, :], x[1:, :], s)


def face_gust_harmonic(grid, omega, x_ref=0.0):
    """Face averages of the unit harmonic gust amplitude (see :func:`harmonic_edge_average`).

    Returns
    -------
    gi : ndarray, complex, shape (ni, nj-1)
    gj : ndarray, complex, shape (ni-1, nj)
    """
    x = grid.x
    return (
        harmonic_edge_average(x[:, :-1], x[:, 1:], omega, x_ref),
        harmonic_edge_average(x[:-1, :], x[1:, :], omega, x_ref),
    )


def cell_x_gradient(grid, gi, gj):
    """``int_cell d g / dx dA`` from face averages ``gi``, ``gj`` by the divergence theorem.

    Exact when the face values are exact edge averages of a function of ``x`` (as from
    :func:`face_gust`).

    Parameters
    ----------
    grid : Grid
    gi : ndarray, shape (..., ni, nj-1)
    gj : ndarray, shape (..., ni-1, nj)

    Returns
    -------
    ndarray, shape (..., ni-1, nj-1)
        Units of ``g`` times chords.
    """
    fi = gi * grid.si[0]
    fj = gj * grid.sj[0]
    return fi[..., 1:, :] - fi[..., :-1, :] + fj[..., :, 1:] - fj[..., :, :-1]


def gust_face_velocity(gi, gj, mach):
    """Face grid velocities of the SVM/FVM in solver units: ``w = (0, -mach * g)``.

    Parameters
    ----------
    gi : ndarray, shape (..., ni, nj-1)
    gj : ndarray, shape (..., ni-1, nj)
        Face averages of ``v_g / U``.
    mach : float

    Returns
    -------
    (wi, wj) : ndarrays, shapes (..., 2, ni, nj-1) and (..., 2, ni-1, nj)
        As ``face_velocity`` of ``cfd.euler.residual``.
    """
    wi = np.stack([np.zeros_like(gi), -mach * gi], axis=-3)
    wj = np.stack([np.zeros_like(gj), -mach * gj], axis=-3)
    return wi, wj


def svm_source(q_bar, mach, dgdx, gamma=1.4):
    """Linearised SVM source (paper Eqs. 10, 14) integrated over the cells, as ``source`` of the residual.

    ``int s_m dA = rho_bar (u_bar - U) mach * dgdx`` (solver units, ``U = mach``), ``s_e = v_bar s_m``;
    the residual's ``source`` is minus the paper's ``S`` (``dQ/dt + div F + S = 0``).

    Parameters
    ----------
    q_bar : ndarray, shape (ni-1, nj-1, 4)
        Steady conserved state (solver units).
    mach : float
        Free-stream Mach number (the gust convection speed in solver units).
    dgdx : ndarray, shape (..., ni-1, nj-1), real or complex
        ``int_cell d(v_g / U)/dx dA`` (:func:`cell_x_gradient`).

    Returns
    -------
    ndarray, shape (..., ni-1, nj-1, 4)
    """
    rho = q_bar[..., 0]
    u = q_bar[..., 1] / rho
    v = q_bar[..., 2] / rho
    sm = rho * (u - mach) * mach * dgdx
    zero = np.zeros_like(sm)
    return -np.stack([zero, zero, sm, v * sm], axis=-1)
