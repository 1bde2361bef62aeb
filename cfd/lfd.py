"""Linear frequency-domain (LFD) response to gusts and rigid motions: a sparse solve per frequency (the reference
path), or the fast sweep.

Gust: for the unit harmonic gust ``v_g / U = exp(i omega (s - (x - x_ref)))`` (input ``u = exp(i omega s)`` at
``x_ref``) the face averages are ``cfd.gust.face_gust_harmonic`` and the response solves

    (i omega mach V + J) q = -b(omega),      y = C q          (omega in U/c units)

(``cfd.linear``). ``omega = 0`` is the steady gain: a uniform gust, equivalent to a change of
incidence (paper Eq. 18). ``omega = inf`` returns the feedthrough ``D = 0`` without a solve: the forcing
stays bounded while ``i omega V`` grows, so ``q -> 0``.

Plunge and pitch (``cfd.motion``): ``h = exp(i omega s)`` or ``alpha = exp(i omega s)`` force the same operator
with ``b = b0 + i omega b1`` and the output adds the explicit ``d`` (the wind axes turning with the pitch):
``y = C q + d``. ``omega = 0`` is the steady derivative (pitch: the lift and moment slopes; plunge: 0).
``omega = inf`` has no finite value: the loads of a moving section grow with the frequency (piston theory,
apparent mass), so a grid holding ``inf`` is refused for motion inputs (:class:`~cfd.linear.LinearError`).
The discrete system follows that growth only while the grid resolves the motion's waves: far beyond it the
motion loads level off at grid-dependent constants (a coarse 81 x 16 grid: plunge Cl about -2.0e3 at both
omega = 1e3 and 1e6), which are artefacts of the grid, not the section's response.
"""

import numpy as np

from sysid import FrequencyResponse

from .gust import face_gust_harmonic
from .frequencies import check_motion_frequencies, check_pivot, check_tol, check_x_ref, frequency_grid
from .linear import LinearError, check_gust_method, check_linear_system, check_outputs, factorise, grid_permutation
from .motion import check_inputs, motion_forcing

__all__ = ["lfd_response", "lfd_state", "solve_direct", "METHODS", "AUTO_FAST_ABOVE", "FAST_OPTIONS"]


def solve_direct(A, b, perm=None):
    """Solve ``A x = b`` once with :func:`cfd.linear.factorise` (checked nested-dissection LU)."""
    solve, _ = factorise(A, perm)
    return solve(b)


def _permutation(lin):
    return grid_permutation(lin.grid)


METHODS = ("auto", "direct", "fast")
AUTO_FAST_ABOVE = 8
"""``method="auto"`` takes the fast sweep for more than this many finite frequencies."""
FAST_OPTIONS = ("max_shifts", "n_moments", "basis", "progress", "log_interval", "workers")
"""Keyword options of :func:`cfd.sweep.fast_sweep` that :func:`lfd_response` passes on (``**fast_options``)."""


def _frequency_solver(lin, omega, perm):
    """``b -> (i omega mach V + J)^-1 b`` at one finite frequency; at ``omega = 0`` a real factorisation of ``J``
    (every input's forcing is real there: the uniform gust, the incidence; the plunge's is zero)."""
    if omega == 0.0:
        solve = lin.solver(np.zeros(lin.n), perm)
        return lambda b: solve(b.real).astype(complex)
    return lin.solver(1j * lin.to_solver_frequency(omega) * lin.V, perm)


def lfd_state(lin, omega, gust="svm", x_ref=0.0, perm=None):
    """Complex state amplitude of the response to the unit harmonic gust at one finite frequency.

    Parameters
    ----------
    lin : LinearSystem
    omega : float
        U/c units, finite, ``>= 0``.
    gust : {"svm", "fvm"}
    x_ref : float
        Where the input is measured (chords).
    perm : ndarray of int, optional
        Fill-reducing ordering of the unknowns (default: nested dissection of the grid).

    Returns
    -------
    ndarray, complex, shape (4N,)
    """
    check_gust_method(gust)
    return _frequency_solver(lin, omega, perm)(-_gust_forcing(lin, omega, gust, x_ref))


def _gust_forcing(lin, omega, gust, x_ref):
    gi, gj = face_gust_harmonic(lin.grid, float(omega), x_ref)
    return lin.forcing(gi, gj, gust)


def lfd_response(lin, omega, gust="svm", outputs=("Cl", "Cm"), x_ref=0.0, T=None, method="auto", tol=1e-8, *,
                 inputs=("gust",), pivot=0.25, **fast_options):
    """Frequency response of the linearised Euler equations to a gust and to rigid plunge and pitch.

    Parameters
    ----------
    lin : LinearSystem
        From ``cfd.linearise``.
    omega : array_like, shape (K,), or tuple (omega_d, omega)
        Angular frequencies in U/c units (``k = omega / 2``), ``>= 0``; ``np.inf`` gives the gust's feedthrough
        (0) without a solve and is refused for motion inputs. The pair returned by ``sysid.mckelvey_grid(M, T)``
        is accepted as is (``T`` is then recovered from it when not given).
    gust : {"svm", "fvm"}
        Split velocity method (face velocities and sources) or field velocity method (face velocities).
    outputs : sequence of {"Cl", "Cm", "Cd"}
    x_ref : float
        Gust reference point (chords), where the input ``u = v_g(x_ref) / U`` is measured.
    T : float, optional
        Sampling period for the discrete frequencies of the result (``sysid`` Eq. 28 map).
    method : {"auto", "direct", "fast"}
        ``"direct"``: one sparse factorisation per frequency (the reference path; all inputs share it).
        ``"fast"``: :func:`cfd.sweep.fast_sweep`, a reduced dual basis from a few factorisations (one basis for
        all inputs) with a per-frequency error estimate. ``"auto"``: fast for more than :data:`AUTO_FAST_ABOVE`
        finite frequencies, else direct.
    tol : float
        Relative error target of the fast sweep (ignored by the direct path).
    inputs : sequence of {"gust", "plunge", "pitch"}
        Inputs in the order of the result's columns (docs/conventions.md): ``"gust"`` per radian of gust angle
        at ``x_ref``; ``"plunge"`` per chord of upward displacement ``h``; ``"pitch"`` per radian of nose-up
        rotation ``alpha`` about ``(pivot, 0)``. Default ``("gust",)``: the gust alone.
    pivot : float
        Pitch axis, chords from the leading edge on the chord line (used by ``"pitch"`` only).
    **fast_options
        Passed to :func:`cfd.sweep.fast_sweep`: :data:`FAST_OPTIONS` (``max_shifts``, ``n_moments``, ``basis``,
        ``progress``, ``log_interval``, ``workers``); others raise :class:`LinearError`.

    Returns
    -------
    sysid.FrequencyResponse
        ``H`` of shape ``(len(outputs), len(inputs), K)``: load coefficients (``Cl`` up, ``Cm`` nose up about the
        quarter chord, ``Cd``; lift and drag in the axes of the steady free stream) per unit input,
        perturbations about the steady loads, responses per ``exp(+i omega s)``. ``metadata["method"]`` says
        which path ran; the fast path adds its error estimate (see :func:`cfd.sweep.fast_sweep`);
        ``metadata["pivot"]`` is there when a pitch was asked for.

    Raises
    ------
    LinearError
        Negative, NaN or -inf frequencies, ``inf`` with a motion input, unknown gust method, input, output name
        or ``method``, a non-finite pivot, a ``tol`` that is not a positive finite number (on either path), more than
        ``cfd.frequencies.MAX_FREQUENCIES`` frequencies, an unknown keyword option (not in :data:`FAST_OPTIONS`), or
        fast-sweep options with the direct path; ``lin`` not a ``LinearSystem``.
    """
    check_linear_system(lin)
    check_gust_method(gust)
    names, rows = check_outputs(outputs)
    inputs = check_inputs(inputs)
    pivot = check_pivot(pivot)
    if method not in METHODS:
        raise LinearError(f"method must be one of {METHODS}; got {method!r}")
    unknown = sorted(set(fast_options) - set(FAST_OPTIONS))
    if unknown:
        raise LinearError(f"unknown option(s) {unknown}: lfd_response's fast-sweep options are {FAST_OPTIONS} "
                          "(method='fast'); check the spelling")
    tol = check_tol(tol)
    w, T = frequency_grid(omega, T)
    x_ref = check_x_ref(x_ref)
    check_motion_frequencies(inputs, w)
    if method == "fast" or (method == "auto" and np.isfinite(w).sum() > AUTO_FAST_ABOVE):
        from .sweep import fast_sweep

        return fast_sweep(lin, w, gust, names, tol=tol, x_ref=x_ref, T=T, inputs=inputs, pivot=pivot,
                          **fast_options)
    if fast_options:
        raise LinearError(f"options {sorted(fast_options)} belong to the fast sweep; the direct path takes none")
    H = _direct(lin, w, gust, rows, x_ref, inputs, pivot)
    meta = {"gust": gust, "x_ref": x_ref, "mach": lin.mach, "alpha_deg": lin.flow.alpha_deg,
            "grid": list(map(int, lin.grid.shape)), "method": "direct"}
    if "pitch" in inputs:
        meta["pivot"] = pivot
    return FrequencyResponse.from_continuous(H, w, T, inputs=list(inputs), outputs=list(names), metadata=meta)


def _direct(lin, w, gust, rows, x_ref, inputs, pivot):
    """``H`` (p, m, K) by one factorisation per finite frequency, one back-substitution per input."""
    C = lin.C[rows]
    perm = _permutation(lin)
    motions = {name: motion_forcing(lin, name, pivot) for name in inputs if name != "gust"}
    H = np.zeros((len(rows), len(inputs), w.size), complex)
    for k, wk in enumerate(w):  # one sparse factorisation per frequency: the reference path
        if np.isinf(wk):  # the gust alone reaches here (check_motion_frequencies)
            H[:, 0, k] = lin.D[rows, 0]
            continue
        solve = _frequency_solver(lin, wk, perm)
        for j, name in enumerate(inputs):
            if name == "gust":
                H[:, j, k] = C @ solve(-_gust_forcing(lin, wk, gust, x_ref))
            else:
                f = motions[name]
                H[:, j, k] = C @ solve(-f.at(wk)) + f.d[rows]
    return H
