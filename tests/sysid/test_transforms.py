"""Tests of sysid.transforms: bilinear (Eqs. 26, 31) and zero-order-hold (Eq. 32) conversions."""

import control
import warnings

import numpy as np
import pytest
from sysid_synth import random_system

from sysid import FrequencyGridError, ModelError, c2d_bilinear, c2d_zoh, d2c_bilinear


def stable_continuous(n, p, m, seed):
    """Random stable continuous system: poles with negative real parts in a random basis."""
    rng = np.random.default_rng(seed)
    re = -rng.uniform(0.1, 3.0, n)
    A0 = np.diag(re)
    for i in range(0, n - 1, 2):  # oscillatory pairs
        w = rng.uniform(0.2, 4.0)
        A0[i, i + 1], A0[i + 1, i] = w, -w
        A0[i + 1, i + 1] = A0[i, i]
    S = rng.standard_normal((n, n)) + 2 * np.eye(n)
    A = S @ A0 @ np.linalg.inv(S)
    return control.ss(A, rng.standard_normal((n, m)), rng.standard_normal((p, n)), rng.standard_normal((p, m)))


def tf_discrete(sys, z):
    """G(z) = C (zI - A)^-1 B + D evaluated directly (independent of control's evaluation)."""
    A, B, C, D = (np.asarray(x) for x in (sys.A, sys.B, sys.C, sys.D))
    return np.stack([C @ np.linalg.solve(zk * np.eye(A.shape[0]) - A, B) + D for zk in z], axis=-1)


# ------------------------------------------------------------------------------- known values
def test_d2c_scalar_known_values():
    # Ahat = 0.5, Bhat = 1, Chat = 1, Dhat = 0, T = 2: Eq. 26 gives A = (2/2)(0.5-1)/(1.5) = -1/3,
    # B = C = (2/sqrt 2)/1.5, D = -1/1.5.
    sysd = control.ss([[0.5]], [[1.0]], [[1.0]], [[0.0]], 2.0)
    sysc = d2c_bilinear(sysd)
    assert sysc.isctime(strict=True)
    np.testing.assert_allclose(sysc.A, [[-1.0 / 3.0]], rtol=1e-15)
    np.testing.assert_allclose(sysc.B, [[np.sqrt(2) / 1.5]], rtol=1e-15)
    np.testing.assert_allclose(sysc.C, [[np.sqrt(2) / 1.5]], rtol=1e-15)
    np.testing.assert_allclose(sysc.D, [[-1.0 / 1.5]], rtol=1e-15)


def test_zoh_integrators_known_values():
    T = 0.4
    # single integrator: Ahat = 1, Bhat = T
    d = c2d_zoh(control.ss([[0.0]], [[1.0]], [[1.0]], [[0.0]]), T)
    np.testing.assert_allclose(d.A, [[1.0]])
    np.testing.assert_allclose(d.B, [[T]], rtol=1e-15)
    # double integrator: Ahat = [[1, T], [0, 1]], Bhat = [T^2/2, T]
    d2 = c2d_zoh(control.ss([[0.0, 1.0], [0.0, 0.0]], [[0.0], [1.0]], [[1.0, 0.0]], [[0.0]]), T)
    np.testing.assert_allclose(d2.A, [[1.0, T], [0.0, 1.0]], atol=1e-15)
    np.testing.assert_allclose(d2.B, [[T ** 2 / 2], [T]], rtol=1e-14)
    assert d2.dt == T


def test_zoh_first_order_known_values():
    a, T = -2.0, 0.3
    d = c2d_zoh(control.ss([[a]], [[1.0]], [[1.0]], [[0.5]]), T)
    np.testing.assert_allclose(d.A, [[np.exp(a * T)]], rtol=1e-14)
    np.testing.assert_allclose(d.B, [[(np.exp(a * T) - 1) / a]], rtol=1e-14)
    np.testing.assert_allclose(d.D, [[0.5]])


# ------------------------------------------------------------------ equality with python-control
@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("T", [0.05, 0.7, 70 / (2 * np.pi)])
def test_c2d_bilinear_matches_control_tustin(seed, T):
    sysc = stable_continuous(4, 2, 3, seed)
    ours = c2d_bilinear(sysc, T)
    ref = control.c2d(sysc, T, "tustin")
    assert ours.dt == T
    z = np.exp(1j * np.linspace(0.0, np.pi * 0.999, 40))
    G1, G2 = tf_discrete(ours, z), tf_discrete(ref, z)
    np.testing.assert_allclose(G1, G2, rtol=1e-9, atol=1e-9 * np.abs(G2).max())


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("T", [0.05, 0.7, 3.0])
def test_c2d_zoh_matches_control_zoh(seed, T):
    sysc = stable_continuous(4, 2, 3, seed)
    ours = c2d_zoh(sysc, T)
    ref = control.c2d(sysc, T, "zoh")
    np.testing.assert_allclose(ours.A, ref.A, rtol=1e-12, atol=1e-13)
    np.testing.assert_allclose(ours.B, ref.B, rtol=1e-12, atol=1e-13)
    np.testing.assert_allclose(ours.C, ref.C)
    np.testing.assert_allclose(ours.D, ref.D)


@pytest.mark.parametrize("seed", [3, 4])
def test_d2c_bilinear_transfer_function_on_mapped_frequencies(seed):
    # G_c(j omega) = G_d(exp(j omega_d)) with omega = (2/T) tan(omega_d / 2) (paper Eq. 28)
    A, B, C, D, _ = random_system(5, 2, 2, seed)
    T = 1.3
    sysd = control.ss(A, B, C, D, T)
    sysc = d2c_bilinear(sysd)
    wd = np.linspace(0.0, 3.0, 30)
    w = 2.0 / T * np.tan(wd / 2)
    Gc = np.stack([np.asarray(sysc.C) @ np.linalg.solve(1j * x * np.eye(5) - np.asarray(sysc.A), sysc.B)
                   + sysc.D for x in w], axis=-1)
    Gd = tf_discrete(sysd, np.exp(1j * wd))
    # Both sides are backward-stable solves of shifted systems, and d2c inverts (I + A): their difference is
    # bounded by a modest multiple of eps times the sum of the condition numbers involved, times |G|. Seed 4
    # has cond(e^{j w_d} I - A) ~ 4e4 and cond(j w I - A_c) ~ 6e5, so a fixed rtol of 1e-11 sits at its
    # round-off (it failed with other BLAS builds); measured errors stay below 0.1 x this bound.
    eye = np.eye(5)
    kappa = (max(np.linalg.cond(np.exp(1j * x) * eye - A) for x in wd) + np.linalg.cond(eye + A)
             + max(np.linalg.cond(1j * x * eye - np.asarray(sysc.A)) for x in w))
    tol = 10 * np.finfo(float).eps * kappa * np.abs(Gd).max()
    np.testing.assert_allclose(Gc, Gd, rtol=0, atol=tol)
    # the Nyquist value is the continuous feedthrough
    np.testing.assert_allclose(sysc.D, tf_discrete(sysd, [-1.0])[:, :, 0].real, rtol=0, atol=tol)


# ------------------------------------------------------------------------------- round trips
@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("T", [0.1, 70 / (2 * np.pi)])
def test_round_trip_continuous_discrete_continuous(seed, T):
    sysc = stable_continuous(5, 2, 2, seed)
    back = d2c_bilinear(c2d_bilinear(sysc, T))
    for X, Y in [(back.A, sysc.A), (back.B, sysc.B), (back.C, sysc.C), (back.D, sysc.D)]:
        np.testing.assert_allclose(X, Y, rtol=1e-10, atol=1e-11 * max(1.0, np.abs(Y).max()))


@pytest.mark.parametrize("seed", [0, 1])
def test_round_trip_discrete_continuous_discrete(seed):
    A, B, C, D, _ = random_system(6, 2, 1, seed)
    sysd = control.ss(A, B, C, D, 0.25, inputs=["gust"], outputs=["Cl", "Cm"])
    back = c2d_bilinear(d2c_bilinear(sysd), 0.25)
    for X, Y in [(back.A, A), (back.B, B), (back.C, C), (back.D, D)]:
        np.testing.assert_allclose(X, Y, rtol=1e-10, atol=1e-12)
    assert back.dt == 0.25
    assert list(back.input_labels) == ["gust"] and list(back.output_labels) == ["Cl", "Cm"]


@pytest.mark.parametrize("conv", ["bilinear", "zoh"])
def test_dc_gain_preserved(conv):
    sysc = stable_continuous(4, 2, 2, 9)
    dc = np.asarray(sysc.D) - np.asarray(sysc.C) @ np.linalg.solve(sysc.A, sysc.B)  # G_c(0)
    sysd = c2d_bilinear(sysc, 0.5) if conv == "bilinear" else c2d_zoh(sysc, 0.5)
    np.testing.assert_allclose(tf_discrete(sysd, [1.0])[:, :, 0].real, dc, rtol=1e-11, atol=1e-12)


# ------------------------------------------------------------------------------------ errors
def test_d2c_rejects_continuous_model():
    with pytest.raises(ModelError, match="discrete-time"):
        d2c_bilinear(control.ss([[-1.0]], [[1.0]], [[1.0]], [[0.0]]))


@pytest.mark.parametrize("func", [c2d_bilinear, c2d_zoh])
def test_c2d_rejects_discrete_model(func):
    with pytest.raises(ModelError, match="continuous-time"):
        func(control.ss([[0.5]], [[1.0]], [[1.0]], [[0.0]], 0.1), 0.1)


@pytest.mark.parametrize("func", [c2d_bilinear, c2d_zoh])
@pytest.mark.parametrize("T", [0.0, -1.0, np.nan, np.inf])
def test_c2d_rejects_bad_T(func, T):
    with pytest.raises(FrequencyGridError, match="T"):
        func(control.ss([[-1.0]], [[1.0]], [[1.0]], [[0.0]]), T)


def test_d2c_pole_at_minus_one():
    sysd = control.ss([[-1.0, 0.0], [0.0, 0.5]], [[1.0], [1.0]], [[1.0, 1.0]], [[0.0]], 0.5)
    with pytest.raises(ModelError, match="z = -1"):
        d2c_bilinear(sysd)


def test_d2c_pole_near_minus_one_warns():
    sysd = control.ss([[-1.0 + 1e-10, 0.0], [0.0, 0.5]], [[1.0], [1.0]], [[1.0, 1.0]], [[0.0]], 0.5)
    with pytest.warns(RuntimeWarning, match="z = -1"):
        d2c_bilinear(sysd)


def test_c2d_bilinear_pole_at_two_over_T():
    T = 0.5
    sysc = control.ss([[2.0 / T]], [[1.0]], [[1.0]], [[0.0]])
    with pytest.raises(ModelError, match="s = 2/T"):
        c2d_bilinear(sysc, T)


def test_d2c_needs_sampling_period():
    with pytest.raises(FrequencyGridError, match="dt=True"):
        d2c_bilinear(control.ss([[0.5]], [[1.0]], [[1.0]], [[0.0]], True))


# ---------------------------------------------------------------------- input checks (issue 34 findings)
@pytest.mark.parametrize("T, side", [(1e-300, "small"), (1e-17, "small"), (1e300, "large")])
@pytest.mark.parametrize("convert", [c2d_bilinear, c2d_zoh])
def test_a_period_that_puts_a_stable_pole_on_the_unit_circle_is_refused(T, side, convert):
    # c2d_bilinear(model, 1e-300) returned A = [[1.0]] for the pole s = -1 silently
    if convert is c2d_zoh and side == "large":
        pytest.skip("zero-order hold sends slow poles to z = exp(sT) -> 0: inside the circle at any large T")
    sys = control.ss([[-1.0]], [[1.0]], [[1.0]], [[0.0]])
    with pytest.raises(ModelError, match=rf"stable pole s = -1 .* unit circle .* T is too {side}"):
        convert(sys, T)


def test_a_period_that_keeps_few_digits_of_a_pole_warns():
    # 1 - |z| = 2e-11 for s = -1e-3 at T = 1e-8: the decay is held in about five digits
    sys = control.ss([[-1e-3]], [[1.0]], [[1.0]], [[0.0]])
    with pytest.warns(RuntimeWarning, match="keeps about 5 digits"):
        c2d_bilinear(sys, 1e-8)


def test_marginal_poles_are_not_refused():
    # an integrator (s = 0) maps to z = 1 at any T: not a stable pole made marginal
    integrator = control.ss([[0.0]], [[1.0]], [[1.0]], [[0.0]])
    assert np.allclose(c2d_bilinear(integrator, 1e-6).A, 1.0)


@pytest.mark.parametrize("convert, dt", [(c2d_bilinear, 0), (c2d_zoh, 0), (lambda s, T: d2c_bilinear(s), 1.0)])
def test_a_model_with_nan_is_refused(convert, dt):
    # c2d_bilinear called it singular ("a pole at s = 2/T"); c2d_zoh returned NaN matrices
    A = np.array([[np.nan]])
    with pytest.raises(ModelError, match="A contains NaN or inf"):
        convert(control.ss(A, [[1.0]], [[1.0]], [[0.0]], dt), 0.5)


def test_zoh_of_a_growth_that_overflows_is_refused():
    # exp(1000): numpy's overflow warning and inf matrices before
    unstable = control.ss([[1.0]], [[1.0]], [[1.0]], [[0.0]])
    with pytest.raises(ModelError, match=r"exp\(A T\) overflows at T = 1000"):
        c2d_zoh(unstable, 1e3)


def test_an_unstable_models_own_pole_outside_the_circle_is_not_a_lost_stable_pole():
    # the paper's plain ROMs are unstable: re-discretised at the simulation step their unstable pole stays outside
    # the circle (|z| = (1 + 0.005) / (1 - 0.005)), and the stable one inside; this was refused as "a stable pole
    # lands on the unit circle" (1 - |z|^2 = 7.3e-4 for the stable pole, far above round-off), which failed 108
    # ROM-simulation pieces of the paper study
    import control

    m = control.ss(np.diag([0.5, -0.0182481]), np.ones((2, 1)), np.ones((1, 2)), np.zeros((1, 1)))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        d = c2d_bilinear(m, 0.02)
    mags = np.sort(np.abs(np.linalg.eigvals(np.asarray(d.A))))
    np.testing.assert_allclose(mags, [(1 - 0.0182481 * 0.01) / (1 + 0.0182481 * 0.01), 1.005 / 0.995], rtol=1e-9)
