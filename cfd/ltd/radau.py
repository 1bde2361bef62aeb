"""Three-stage Radau IIA (order 5, L-stable) for the linear time-domain equations ``V dq/dt + J q + b(t) = 0``.

One step of ``h`` (solver time) from ``q_n`` has stage values ``Q_i`` at ``t_n + c_i h``,
``c = ((4 - sqrt 6) / 10, (4 + sqrt 6) / 10, 1)``, that satisfy

    (A^-1 (x) V + h I (x) J) Q = (A^-1 1) (x) V q_n - h b,      b_i = b(t_n + c_i h),

and ``q_{n+1} = Q_3`` (stiffly accurate). ``A^-1 = P diag(lambda) P^-1`` has one real eigenvalue and a complex
pair, so with ``W = (P^-1 (x) I) Q`` the 3 x 4N system splits into

    (lambda_k / h V + J) w_k = (lambda_k / h) (P^-1 1)_k V q_n - (P^-1 b)_k,      Q = (P (x) I) W:

one real and one complex sparse solve per step (the third stage is the conjugate of the second): two
factorisations, made once for the whole march. The equations are linear, so the stages are exact solutions of
the collocation equations (no Newton iteration). Between the step points the collocation polynomial (degree 3
through ``q_n`` and the three stages) gives the dense output, accurate to ``O(h^4)``.

Per radian of a harmonic ``exp(i omega t)`` the method damps by about ``(omega h)^5 / 7200`` and its phase rate
errs by about ``(omega h)^6 / 42 000``, against BDF2's ``(omega h)^3 / 4`` and ``(omega h)^2 / 3``
(``bench/ltd_schemes.py`` tabulates both at the paper's gust frequencies).
"""

import numpy as np

__all__ = ["RADAU_C", "RADAU_A", "radau_transform", "dense_weights", "stability_function"]

_S6 = np.sqrt(6.0)
RADAU_C = np.array([(4.0 - _S6) / 10.0, (4.0 + _S6) / 10.0, 1.0])
"""Stage times of the three-stage Radau IIA method, fractions of the step."""
RADAU_A = np.array([[(88.0 - 7.0 * _S6) / 360.0, (296.0 - 169.0 * _S6) / 1800.0, (-2.0 + 3.0 * _S6) / 225.0],
                    [(296.0 + 169.0 * _S6) / 1800.0, (88.0 + 7.0 * _S6) / 360.0, (-2.0 - 3.0 * _S6) / 225.0],
                    [(16.0 - _S6) / 36.0, (16.0 + _S6) / 36.0, 1.0 / 9.0]])
"""Butcher matrix of the three-stage Radau IIA method."""


def stability_function(z, A=RADAU_A):
    """``R(z) = 1 + z b^T (I - z A)^-1 1`` of a stiffly accurate Runge-Kutta method (``b`` the last row of
    ``A``): one step multiplies ``y' = lambda y`` by ``R(lambda h)``.

    Parameters
    ----------
    z : complex
        ``lambda h``.
    A : ndarray, shape (s, s)
        Butcher matrix (default: the three-stage Radau IIA's).

    Returns
    -------
    complex
    """
    s = A.shape[0]
    return complex(1.0 + z * A[-1] @ np.linalg.solve(np.eye(s) - z * A, np.ones(s)))


def radau_transform():
    """The eigen-decomposition ``A^-1 = P diag(lam) P^-1`` of the Radau IIA matrix, arranged for real arithmetic.

    Returns
    -------
    lam : ndarray, shape (2,), complex
        The real eigenvalue (as a complex number with zero imaginary part) and the one of the complex pair with
        positive imaginary part.
    P : ndarray, shape (3, 3), complex
        Columns: the real eigenvector (real), the complex one, its conjugate.
    Pinv : ndarray, shape (3, 3), complex
        ``P^-1``; its first row is real, its third the conjugate of its second.
    """
    vals, vecs = np.linalg.eig(np.linalg.inv(RADAU_A))
    i_real = int(np.argmin(np.abs(vals.imag)))
    i_cplx = int(np.argmax(vals.imag))
    v_r = vecs[:, i_real].real / np.linalg.norm(vecs[:, i_real].real)
    v_c = vecs[:, i_cplx]
    P = np.stack([v_r.astype(complex), v_c, v_c.conj()], axis=1)
    lam = np.array([complex(vals[i_real].real, 0.0), vals[i_cplx]])
    return lam, P, np.linalg.inv(P)


def dense_weights(tau):
    """Lagrange weights of the collocation polynomial at fractions ``tau`` of a step.

    Parameters
    ----------
    tau : ndarray, shape (k,)
        Points in ``[0, 1]`` (0: the step's start, 1: its end).

    Returns
    -------
    ndarray, shape (k, 4)
        Weights of ``(q_n, Q_1, Q_2, Q_3)``: ``q(t_n + tau h) ~= weights @ [q_n, Q_1, Q_2, Q_3]``.
    """
    tau = np.asarray(tau, dtype=float).reshape(-1)
    nodes = np.concatenate([[0.0], RADAU_C])
    W = np.ones((tau.size, 4))
    for j in range(4):
        for m in range(4):
            if m != j:
                W[:, j] *= (tau - nodes[m]) / (nodes[j] - nodes[m])
    return W
