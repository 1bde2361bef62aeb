"""Linear frequency-domain (LFD) gust response: a sparse solve per frequency (the reference path), or the fast sweep.

For the unit harmonic gust ``v_g / U = exp(i omega (s - (x - x_ref)))`` (input ``u = exp(i omega s)`` at
``x_ref``) the face averages are ``cfd.gust.face_gust_harmonic`` and the response solves

    (i omega mach V + J) q = -b(omega),      y = C q          (omega in U/c units)

(``cfd.linear``). ``omega = 0`` is the steady gain: a uniform gust, equivalent to a change of
incidence (paper Eq. 18). ``omega = inf`` returns the feedthrough ``D = 0`` without a solve: the forcing
stays bounded while ``i omega V`` grows, so ``q -> 0``.
"""

import numpy as np

from sysid import FrequencyResponse

from .gust import face_gust_harmonic
from .frequencies import check_x_ref, frequency_grid
from .linear import LinearError, check_gust_method, check_outputs, factorise, grid_permutation

__all__ = ["lfd_response", "lfd_state", "solve_direct", "METHODS", "AUTO_FAST_ABOVE"]


def solve_direct(A, b, perm=None):
    """Solve ``A x = b`` once with :func:`cfd.linear.factorise` (checked nested-dissection LU)."""
    solve, _ = factorise(A, perm)
    return solve(b)


def _permutation(lin):
    return grid_permutation(lin.grid)


METHODS = ("auto", "direct", "fast")
AUTO_FAST_ABOVE = 8
"""``method="auto"`` takes the fast sweep for more than this many finite frequencies."""


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
    gi, gj = face_gust_harmonic(lin.grid, float(omega), x_ref)
    b = lin.forcing(gi, gj, gust)
    if omega == 0.0:  # the steady gain: a real system (the uniform gust has real face values)
        return lin.solver(np.zeros(lin.n), perm)(-b.real).astype(complex)
    return lin.solver(1j * lin.to_solver_frequency(omega) * lin.V, perm)(-b)


def lfd_response(lin, omega, gust="svm", outputs=("Cl", "Cm"), x_ref=0.0, T=None, method="auto", tol=1e-8,
                 **fast_options):
    """Gust frequency response of the linearised Euler equations.

    Parameters
    ----------
    lin : LinearSystem
        From ``cfd.linearise``.
    omega : array_like, shape (K,), or tuple (omega_d, omega)
        Angular frequencies in U/c units (``k = omega / 2``), ``>= 0``; ``np.inf`` gives the feedthrough
        (0) without a solve. The pair returned by ``sysid.mckelvey_grid(M, T)`` is accepted as is (``T``
        is then recovered from it when not given).
    gust : {"svm", "fvm"}
        Split velocity method (face velocities and sources) or field velocity method (face velocities).
    outputs : sequence of {"Cl", "Cm", "Cd"}
    x_ref : float
        Gust reference point (chords), where the input ``u = v_g(x_ref) / U`` is measured.
    T : float, optional
        Sampling period for the discrete frequencies of the result (``sysid`` Eq. 28 map).
    method : {"auto", "direct", "fast"}
        ``"direct"``: one sparse factorisation per frequency (the reference path). ``"fast"``:
        :func:`cfd.sweep.fast_sweep`, a reduced basis from a few factorisations with a per-frequency error
        estimate. ``"auto"``: fast for more than :data:`AUTO_FAST_ABOVE` finite frequencies, else direct.
    tol : float
        Relative error target of the fast sweep (ignored by the direct path).
    **fast_options
        Passed to :func:`cfd.sweep.fast_sweep` (``max_shifts``, ``n_moments``, ``basis``, ``progress``).

    Returns
    -------
    sysid.FrequencyResponse
        ``H`` of shape ``(len(outputs), 1, K)``: load coefficients per unit gust angle (per radian),
        perturbations about the steady loads, input ``"gust"``. ``metadata["method"]`` says which path
        ran; the fast path adds its error estimate (see :func:`cfd.sweep.fast_sweep`).

    Raises
    ------
    LinearError
        Negative, NaN or -inf frequencies, unknown gust method, output name or ``method``, bad ``tol``.
    """
    check_gust_method(gust)
    names, rows = check_outputs(outputs)
    if method not in METHODS:
        raise LinearError(f"method must be one of {METHODS}; got {method!r}")
    w, T = frequency_grid(omega, T)
    x_ref = check_x_ref(x_ref)
    if method == "fast" or (method == "auto" and np.isfinite(w).sum() > AUTO_FAST_ABOVE):
        from .sweep import fast_sweep

        return fast_sweep(lin, w, gust, names, tol=tol, x_ref=x_ref, T=T, **fast_options)
    if fast_options:
        raise LinearError(f"options {sorted(fast_options)} belong to the fast sweep; the direct path takes none")
    C = lin.C[rows]
    perm = _permutation(lin)
    H = np.zeros((len(rows), 1, w.size), complex)
    for k, wk in enumerate(w):  # one sparse factorisation per frequency: the reference path
        if np.isinf(wk):
            H[:, 0, k] = lin.D[rows, 0]
            continue
        H[:, 0, k] = C @ lfd_state(lin, wk, gust, x_ref, perm)
    meta = {"gust": gust, "x_ref": x_ref, "mach": lin.mach, "alpha_deg": lin.flow.alpha_deg,
            "grid": list(map(int, lin.grid.shape)), "method": "direct"}
    return FrequencyResponse.from_continuous(H, w, T, inputs=["gust"], outputs=list(names), metadata=meta)
