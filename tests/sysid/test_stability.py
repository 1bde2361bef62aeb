"""Tests of sysid.stability: the Lacy-Bernstein SDP and eigenvalue reflection."""

import numpy as np
import pytest

import sysid

from sysid.errors import FrequencyDataError
from sysid.refit import fit_bd, frequency_response
from sysid.stability import StabiliseResult, is_stable, spectral_radius, stabilise


def rot(r, th):
    return r * np.array([[np.cos(th), -np.sin(th)], [np.sin(th), np.cos(th)]])


def unstable_shift_problem(n, seed, overshoot=1.03, noise=1e-3):
    """Shift equation gamma1 A = gamma2 whose least-squares solution is unstable."""
    rng = np.random.default_rng(seed)
    A0 = rng.standard_normal((n, n))
    A0 *= overshoot / spectral_radius(A0)
    G1 = rng.standard_normal((3 * n, n))
    G2 = G1 @ A0 + noise * rng.standard_normal((3 * n, n))
    A = np.linalg.lstsq(G1, G2, rcond=None)[0]
    assert spectral_radius(A) > 1.0
    return A, G1, G2


def test_spectral_radius_and_is_stable():
    A = np.diag([0.5, -0.99])
    assert spectral_radius(A) == pytest.approx(0.99)
    assert is_stable(A) and is_stable(A, 0.005) and not is_stable(A, 0.01)
    assert spectral_radius(rot(1.2, 0.3)) == pytest.approx(1.2)


@pytest.mark.parametrize("method", ["lmi", "reflect"])
@pytest.mark.parametrize("n", [2, 5, 12, 25])
@pytest.mark.parametrize("margin", [1e-3, 1e-2, 0.1])
def test_both_methods_stabilise_with_margin(method, n, margin):
    A, G1, G2 = unstable_shift_problem(n, seed=n)
    r = stabilise(A, method=method, margin=margin, gamma1=G1, gamma2=G2)
    assert isinstance(r, StabiliseResult)
    assert r.method == method
    assert np.isrealobj(r.A) and r.A.shape == (n, n)
    assert r.spectral_radius_after == pytest.approx(spectral_radius(r.A))
    assert spectral_radius(r.A) < 1 - margin
    assert is_stable(r.A, margin)
    assert r.spectral_radius_before == pytest.approx(spectral_radius(A))
    assert r.relative_change == pytest.approx(np.linalg.norm(r.A - A) / np.linalg.norm(A))
    # without the shift-equation matrices (objective ||A P - Q||_F) as well
    r2 = stabilise(A, method=method, margin=margin)
    assert spectral_radius(r2.A) < 1 - margin


@pytest.mark.parametrize("n", [2, 4, 6])
@pytest.mark.parametrize("margin", [1e-3, 0.05])
def test_full_sdp_certificate_and_orientation(n, margin):
    """The full Lacy-Bernstein SDP: A_new = Q P^-1 has radius < 1 - margin; the LMI certificate holds."""
    import cvxpy as cp

    A, G1, G2 = unstable_shift_problem(n, seed=100 + n)
    r = stabilise(A, method="lmi", margin=margin, gamma1=G1, gamma2=G2, subspace=False)
    assert spectral_radius(r.A) < 1 - margin
    # re-solve the SDP here to check the convention: Q P^-1 is certified, P^-1 Q need not even be stable
    rho = 1 - margin
    P = cp.Variable((n, n), symmetric=True)
    Q = cp.Variable((n, n))
    lmi = cp.bmat([[rho**2 * P - 1e-6 * np.eye(n), Q], [Q.T, P]])
    cp.Problem(cp.Minimize(cp.norm(A @ P - Q, "fro")), [0.5 * (lmi + lmi.T) >> 0, cp.trace(P) == n]).solve(
        solver=cp.CLARABEL)
    Pv, Qv = P.value, Q.value
    A_new = Qv @ np.linalg.inv(Pv)
    assert spectral_radius(A_new) < rho + 1e-7
    # Lyapunov certificate rho^2 P - A_new P A_new^T > 0
    assert np.linalg.eigvalsh(rho**2 * Pv - A_new @ Pv @ A_new.T).min() > 0


def test_q_p_inverse_is_the_matrix_that_approximates_a():
    """Q P^-1 and P^-1 Q are similar (same spectrum), but only Q P^-1 approximates A (in the objective's sense)."""
    import cvxpy as cp

    n, rho = 6, 0.99
    A, _, _ = unstable_shift_problem(n, seed=5, overshoot=1.05)
    P = cp.Variable((n, n), symmetric=True)
    Q = cp.Variable((n, n))
    lmi = cp.bmat([[rho**2 * P - 1e-6 * np.eye(n), Q], [Q.T, P]])
    prob = cp.Problem(cp.Minimize(cp.norm(A @ P - Q, "fro")), [0.5 * (lmi + lmi.T) >> 0, cp.trace(P) == n])
    prob.solve(solver=cp.CLARABEL)
    Pv, Qv = P.value, Q.value
    right, left = Qv @ np.linalg.inv(Pv), np.linalg.inv(Pv) @ Qv
    assert spectral_radius(right) < rho + 1e-7 and spectral_radius(left) < rho + 1e-7
    assert np.linalg.norm((A - right) @ Pv) == pytest.approx(prob.value, rel=1e-5)
    assert np.linalg.norm(A - right) < np.linalg.norm(A - left)


def test_lmi_changes_the_fit_less_than_reflection():
    """Lightly damped modes pushed out by noise: the LMI moves them just inside the circle, reflection
    mirrors them far in; the LMI changes A less, and after refitting B, D its FRF fits the data better."""
    margin = 1e-3

    def assemble(blocks, T):
        n = sum(b.shape[0] for b in blocks)
        A0 = np.zeros((n, n))
        i = 0
        for b in blocks:
            k = b.shape[0]
            A0[i:i + k, i:i + k] = b
            i += k
        return T @ A0 @ np.linalg.inv(T)

    n = 7
    T = np.random.default_rng(3).standard_normal((n, n)) + 3 * np.eye(n)
    A = assemble([rot(1.04, 0.3), rot(0.97, 1.1), rot(1.02, 2.0), np.array([[0.6]])], T)
    # the true system: the same modes, the two lightly damped ones just inside the circle
    A_true = assemble([rot(0.995, 0.3), rot(0.97, 1.1), rot(0.995, 2.0), np.array([[0.6]])], T)
    assert spectral_radius(A) == pytest.approx(1.04)
    rl = stabilise(A, method="lmi", margin=margin)
    rr = stabilise(A, method="reflect", margin=margin)
    assert rl.spectral_radius_after < 1 - margin and rr.spectral_radius_after < 1 - margin
    assert rl.relative_change < rr.relative_change
    # the eigenvalues already inside are untouched by both
    for r in (rl, rr):
        ev = np.linalg.eigvals(r.A)
        for lam in (0.97 * np.exp(1.1j), 0.6):
            assert np.min(np.abs(ev - lam)) < 1e-8
    # data: the stable system with the same eigenvalue angles, radius just inside; refit B, D after each
    rng = np.random.default_rng(0)
    B, C = rng.standard_normal((n, 1)), rng.standard_normal((1, n))
    z = np.exp(1j * np.linspace(0, np.pi, 257))
    G = frequency_response(A_true, B, C, np.zeros((1, 1)), z)
    err = {}
    for name, r in (("lmi", rl), ("reflect", rr)):
        f = fit_bd(r.A, C, z, G)
        err[name] = f.residual
    assert err["lmi"] < err["reflect"]


def test_lmi_with_shift_equation_beats_reflection_on_its_objective():
    A, G1, G2 = unstable_shift_problem(30, seed=7, overshoot=1.02)
    rl = stabilise(A, method="lmi", gamma1=G1, gamma2=G2)
    rr = stabilise(A, method="reflect", gamma1=G1, gamma2=G2)
    assert rl.objective < rr.objective
    assert rl.objective == pytest.approx(np.linalg.norm(G1 @ rl.A - G2))


@pytest.mark.parametrize("mode", ["mirror", "circle"])
def test_reflection_places_eigenvalues_as_documented(mode):
    rho = 1 - 0.01
    lam = 1.25 * np.exp(0.7j)
    A = np.zeros((5, 5))
    A[:2, :2] = rot(1.25, 0.7)
    A[2, 2] = -1.5
    A[3:, 3:] = rot(0.5, 2.0)
    A[0, 4] = 0.3  # some coupling, so A is not normal
    S = np.random.default_rng(1).standard_normal((5, 5)) + 2 * np.eye(5)
    A = S @ A @ np.linalg.inv(S)
    r = stabilise(A, method="reflect", margin=0.01, mode=mode)
    ev = np.linalg.eigvals(r.A)
    if mode == "mirror":
        expect = [rho**2 / np.conj(lam), rho**2 / np.conj(np.conj(lam)), rho**2 / -1.5, 0.5 * np.exp(2j), 0.5 * np.exp(-2j)]
    else:
        expect = [rho * np.exp(0.7j), rho * np.exp(-0.7j), -rho, 0.5 * np.exp(2j), 0.5 * np.exp(-2j)]
    for e in expect:
        assert np.min(np.abs(ev - e)) < 1e-6
    assert np.isrealobj(r.A)


def test_already_stable_is_returned_unchanged_and_errors():
    A = np.diag([0.5, 0.2])
    r = stabilise(A)
    assert r.method == "none" and r.relative_change == 0.0 and np.array_equal(r.A, A)
    rf = stabilise(A, force=True)
    assert rf.spectral_radius_after < 1 - 1e-3
    with pytest.raises(sysid.OptionError, match="method"):
        stabilise(2 * A + np.eye(2), method="magic")
    with pytest.raises(sysid.OptionError, match="method must be 'lmi' or 'reflect'; got 'bogus'"):
        stabilise(A, method="bogus")   # a stable A returned method='none' before
    with pytest.raises(FrequencyDataError, match=r"A must be a non-empty square matrix; got shape \(2, 3\)"):
        stabilise(np.ones((2, 3)))
    with pytest.raises(sysid.OptionError, match="margin"):
        stabilise(A, margin=1.5)
    with pytest.raises(FrequencyDataError, match="gamma1"):
        stabilise(np.diag([1.5, 0.2]), gamma1=np.ones((4, 3)), gamma2=np.ones((4, 3)))


@pytest.mark.parametrize("margin", ["x", None, np.array([0.1]), True, 1.0, -0.1])
def test_margin_must_be_a_number_in_the_unit_interval(margin):
    # margin="x" raised a bare TypeError from the comparison
    import sysid

    with pytest.raises(sysid.OptionError, match="margin must lie in"):
        sysid.stabilise(np.array([[1.5]]), margin=margin)


@pytest.mark.parametrize("kwargs, match", [(dict(delta=-1.0), "delta must be a nonnegative number"),
                                           (dict(delta=np.nan), "delta must be"),
                                           (dict(subspace="no"), "subspace must be True or False"),
                                           (dict(force=1), "force must be True or False"),
                                           # checked only by the reflection before / a bare ValueError
                                           (dict(mode="bogus"), "mode must be 'mirror' or 'circle'"),
                                           (dict(solver_opts="x"), "solver_opts must be a dict")])
def test_other_options_are_checked(kwargs, match):
    # delta = -1 was accepted (a non-strict LMI); force=1 and subspace="no" were read as truthy
    import sysid

    with pytest.raises(sysid.OptionError, match=match):
        sysid.stabilise(np.array([[1.5]]), **kwargs)
