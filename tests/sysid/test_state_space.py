"""sysid.state_space: the resolvent by the Schur form against closed forms and LU solves."""

import numpy as np
import pytest

from sysid.state_space import eigen_parts, evaluate_ss, resolvent_C, shifted_solve

Z_CIRCLE = np.exp(1j * np.linspace(0.0, np.pi, 129))


def jordan(n, a, b):
    """``a I + b N`` with the nilpotent shift ``N``: not diagonalisable, so the modal form is refused."""
    return a * np.eye(n) + b * np.eye(n, k=1)


def jordan_resolvent(n, a, b, z):
    """Closed form ``(z I - A)^-1 = sum_k b^k N^k / (z - a)^(k + 1)``: shape (K, n, n)."""
    out = np.zeros((z.size, n, n), dtype=complex)
    for k in range(n):
        out += (b ** k / (z - a) ** (k + 1))[:, None, None] * np.eye(n, k=k)[None]
    return out


@pytest.mark.parametrize("n", [1, 2, 7, 30])
def test_shifted_solve_matches_closed_form_of_a_jordan_block(n):
    # |z - a| >= 0.5 on the unit circle and b / |z - a| <= 0.6: the terms of the closed form fall geometrically,
    # cond(z I - A) <= 1 / (1 - 0.6)^2 ~ 6, so a backward-stable solve is good to a few hundred eps
    A = jordan(n, 0.5, 0.3)
    B = np.arange(1.0, 2 * n + 1).reshape(n, 2)
    assert eigen_parts(A) is None or n == 1  # the modal form is not available (n > 1)
    X = shifted_solve(A, B, Z_CIRCLE)
    X_exact = jordan_resolvent(n, 0.5, 0.3, Z_CIRCLE) @ B
    assert X.shape == (Z_CIRCLE.size, n, 2)
    assert np.abs(X - X_exact).max() <= 1e-13 * np.abs(X_exact).max()


def test_shifted_solve_matches_lu_on_a_random_stable_matrix():
    rng = np.random.default_rng(3)
    n = 40
    A = 0.9 * rng.standard_normal((n, n)) / np.sqrt(n) / 1.2  # spectral radius about 0.75
    B = rng.standard_normal((n, 3))
    X = shifted_solve(A, B, Z_CIRCLE)
    X_lu = np.linalg.solve(Z_CIRCLE[:, None, None] * np.eye(n) - A, np.broadcast_to(B, (Z_CIRCLE.size, n, 3)))
    # both backward stable; cond(z I - A) <= ~1e2 here, so they agree to ~1e2 n eps of the largest entry
    assert np.abs(X - X_lu).max() <= 1e-11 * np.abs(X_lu).max()


def test_shifted_solve_empty_state():
    assert shifted_solve(np.zeros((0, 0)), np.zeros((0, 2)), Z_CIRCLE).shape == (Z_CIRCLE.size, 0, 2)


def test_evaluate_ss_and_resolvent_c_of_a_defective_matrix():
    n = 12
    A = jordan(n, -0.4, 0.5)
    B = np.ones((n, 1))
    C = np.vstack([np.linspace(1.0, 2.0, n), np.eye(n)[0]])
    D = np.array([[0.5], [0.0]])
    R = jordan_resolvent(n, -0.4, 0.5, Z_CIRCLE)
    G = evaluate_ss(A, B, C, D, Z_CIRCLE)
    G_exact = (C[None] @ R @ B + D[None]).transpose(1, 2, 0)
    # |z + 0.4| >= 0.6 and b / |z - a| <= 0.84: cond(z I - A) <= ~40, entries of R up to ~10
    assert np.abs(G - G_exact).max() <= 1e-12 * np.abs(G_exact).max()
    F = resolvent_C(A, C, Z_CIRCLE)
    assert np.abs(F - C[None] @ R).max() <= 1e-12 * np.abs(C[None] @ R).max()


def test_shifted_solve_at_an_eigenvalue_is_not_finite_and_silent():
    import warnings

    A = jordan(3, 1.0, 0.2)  # eigenvalue z = 1, the first point of Z_CIRCLE
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        X = shifted_solve(A, np.ones((3, 1)), Z_CIRCLE)
    assert not np.all(np.isfinite(X[0])) and np.all(np.isfinite(X[1:]))
