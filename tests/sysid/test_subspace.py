"""Tests of sysid.subspace: McKelvey's Algorithms 1 and 2 on synthetic systems."""

import numpy as np
import pytest
from sysid_synth import freqresp, pole_mismatch, random_system

import sysid
from sysid import FrequencyGridError, FrequencyResponse, OrderError, mckelvey_grid
from sysid.subspace import default_q, lstsq_bd, mckelvey1, mckelvey2, subspace_identify


def _fit_error(res, z, G):
    B, D = lstsq_bd(res.A, res.C, z, G)
    Gm = freqresp(res.A, B, res.C, D, z)
    return np.abs(Gm - G).max() / np.abs(G).max()


# -------------------------------------------------------------------------- exact recovery
@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("M", [16, 64, 256])
@pytest.mark.parametrize("method", ["mckelvey1", "mckelvey2"])
@pytest.mark.parametrize("p, m", [(2, 2), (2, 1), (1, 3)])
def test_exact_recovery_equispaced(seed, M, method, p, m):
    A, B, C, D, poles = random_system(6, p, m, seed)
    wd, _ = mckelvey_grid(M, 1.0)
    z = np.exp(1j * wd)
    G = freqresp(A, B, C, D, z)
    res = subspace_identify(FrequencyResponse(G, wd, 1.0), 6, method=method)
    assert res.method == method and res.order == 6
    assert res.A.shape == (6, 6) and res.C.shape == (p, 6)
    assert _fit_error(res, z, G) < 1e-8
    assert pole_mismatch(np.linalg.eigvals(res.A), poles) < 1e-8


@pytest.mark.parametrize("seed", [3, 4])
@pytest.mark.parametrize("K", [20, 60])
def test_exact_recovery_arbitrary_frequencies(seed, K):
    A, B, C, D, poles = random_system(6, 2, 2, seed)
    rng = np.random.default_rng(100 + seed)
    wd = np.sort(rng.uniform(0.0, np.pi, K))
    z = np.exp(1j * wd)
    G = freqresp(A, B, C, D, z)
    res = mckelvey2(G, wd, 6)
    assert _fit_error(res, z, G) < 1e-8
    assert pole_mismatch(np.linalg.eigvals(res.A), poles) < 1e-8
    # auto picks Algorithm 2 for a non-equispaced grid
    assert subspace_identify(G, 6, omega_d=wd).method == "mckelvey2"


def test_first_order_hankel_is_rank_one_with_known_singular_value():
    # G(z) = 1/(z - a): h_i = a^(i-1) / (1 - a^(2M)), Hankel (q x r) = outer product, rank 1 with
    # s_1 = sqrt(sum_{i<q} a^(2i)) sqrt(sum_{j<r} a^(2j)) / (1 - a^(2M)).
    a, M = 0.7, 32
    wd, _ = mckelvey_grid(M, 1.0)
    G = 1.0 / (np.exp(1j * wd) - a)
    s = sysid.hankel_singular_values(G)  # plain array: McKelvey grid assumed
    q = r = M
    s1 = np.sqrt(np.sum(a ** (2 * np.arange(q)))) * np.sqrt(np.sum(a ** (2 * np.arange(r)))) / (1 - a ** (2 * M))
    np.testing.assert_allclose(s[0], s1, rtol=1e-12)
    assert s[1] < 1e-12 * s[0]
    res = mckelvey1(G, 1)
    np.testing.assert_allclose(res.A, [[a]], rtol=1e-12)


def test_singular_values_reveal_order():
    A, B, C, D, _ = random_system(6, 2, 2, 7)
    wd, _ = mckelvey_grid(64, 1.0)
    G = freqresp(A, B, C, D, np.exp(1j * wd))
    for method in ("mckelvey1", "mckelvey2"):
        s = sysid.hankel_singular_values(G, wd, method=method)
        assert s[5] > 1e-6 * s[0] and s[6] < 1e-10 * s[0]
        np.testing.assert_array_equal(s, sysid.hankel_svd(G, wd, method=method).sv)


def test_result_carries_shift_matrices():
    A, B, C, D, _ = random_system(4, 1, 2, 8)
    wd, _ = mckelvey_grid(32, 1.0)
    G = freqresp(A, B, C, D, np.exp(1j * wd))
    res = mckelvey1(G, 4)
    p = 1
    assert res.gamma1.shape == ((res.q - 1) * p, 4) == res.gamma2.shape
    # A solves the shift equation Gamma1 A = Gamma2 (exactly for noise-free data)
    np.testing.assert_allclose(res.gamma1 @ res.A, res.gamma2, atol=1e-10)
    assert res.q == 10 and res.r == 54  # documented default q = min(M, 2n + 2), r = 2M - q
    assert res.spectral_radius < 1.0


def test_default_sizes():
    assert default_q("mckelvey1", 2, 2, 257) == (256, 256)
    assert default_q("mckelvey1", 2, 2, 257, order=6) == (14, 498)
    assert default_q("mckelvey1", 1, 1, 9, order=6) == (8, 8)
    q, r = default_q("mckelvey2", 1, 1, 257)
    assert r is None and q == 128 and q * 2 <= 2 * 257
    assert default_q("mckelvey2", 2, 2, 257, order=6) == (14, None)


# ------------------------------------------------------------------------------ errors
def test_algorithm1_rejects_non_equispaced():
    frf = FrequencyResponse(np.ones(4), [0.0, 0.3, 1.0, np.pi], 1.0)
    with pytest.raises(FrequencyGridError, match="mckelvey2"):
        mckelvey1(frf, 1)
    with pytest.raises(FrequencyGridError, match="Algorithm 2"):
        subspace_identify(frf, 1, method="mckelvey1")


def test_needs_discrete_frequencies():
    frf = FrequencyResponse.from_continuous(np.ones(4), [0.0, 1.0, 2.0, 3.0])
    with pytest.raises(FrequencyGridError, match="T"):
        subspace_identify(frf, 1)


@pytest.mark.parametrize("bad, shown", [(np.nan, "nan"), (np.inf, "inf"), (-0.5, "-0.5"), (3.5, "3.5")])
@pytest.mark.parametrize("call", [lambda G, wd: mckelvey2(G, wd, 2), lambda G, wd: sysid.hankel_svd(G, wd),
                                  lambda G, wd: subspace_identify(G, 2, omega_d=wd)])
def test_omega_d_array_checked_up_front(bad, shown, call):
    wd, _ = mckelvey_grid(32, 1.0)
    A, B, C, D, _ = random_system(2, 1, 1, 0)
    G = freqresp(A, B, C, D, np.exp(1j * wd))
    wd[3] = bad
    with pytest.raises(FrequencyGridError, match=rf"omega_d\[3\] = {shown}; .*finite and lie in \[0, pi\]"):
        call(G, wd)


def test_repeated_or_non_numeric_data_are_refused():
    # every frequency the same gave mckelvey2 a model on the unit circle (spectral radius 1.0)
    wd, _ = mckelvey_grid(32, 1.0)
    A, B, C, D, _ = random_system(2, 1, 1, 0)
    G = freqresp(A, B, C, D, np.exp(1j * wd))
    with pytest.raises(FrequencyGridError, match="are the same frequency"):
        mckelvey2(G, np.zeros(wd.size), 2)
    with pytest.raises(sysid.FrequencyDataError, match="G must be an array of numbers"):
        sysid.hankel_svd("x")


@pytest.mark.parametrize("order, q, match", [
    (8, 8, r"q = 8"),
    (20, None, r"largest possible order is 15"),
    (0, None, ">= 1"),
    (2.5, None, "integer"),
])
def test_order_limits_algorithm1(order, q, match):
    A, B, C, D, _ = random_system(4, 1, 1, 9)
    wd, _ = mckelvey_grid(16, 1.0)
    G = freqresp(A, B, C, D, np.exp(1j * wd))
    with pytest.raises(OrderError, match=match):
        mckelvey1(G, order, q=q)


def test_hankel_sizes_checked():
    wd, _ = mckelvey_grid(8, 1.0)
    with pytest.raises(OrderError, match="q \\+ r <= 2M"):
        mckelvey1(np.ones(9), 1, q=10, r=10)
    with pytest.raises(OrderError, match="q=40"):
        mckelvey2(np.ones(9), wd, 1, q=40)


def test_order_beyond_algorithm2_limit():
    wd = np.linspace(0.1, 3.0, 10)
    G = 1.0 / (np.exp(1j * wd) - 0.5)
    with pytest.raises(OrderError, match="beyond what the data support"):
        mckelvey2(G, wd, 9)


def test_round_off_order_warns():
    wd, _ = mckelvey_grid(32, 1.0)
    G = 1.0 / (np.exp(1j * wd) - 0.5)
    with pytest.warns(RuntimeWarning, match="support order 1"):
        mckelvey1(G, 3)


# ---------------------------------------------------------------------------- noisy data
def _noisy_error(M, seed, method, sigma=0.05):
    A, B, C, D, _ = random_system(6, 2, 2, 80 + seed, rho=0.9)
    wd, _ = mckelvey_grid(M, 1.0)
    z = np.exp(1j * wd)
    G = freqresp(A, B, C, D, z)
    rng = np.random.default_rng(seed)
    Gn = G + sigma * (rng.standard_normal(G.shape) + 1j * rng.standard_normal(G.shape)) / np.sqrt(2)
    res = subspace_identify(Gn, 6, omega_d=wd, method=method)
    Bh, Dh = lstsq_bd(res.A, res.C, z, Gn)
    zf = np.exp(1j * np.linspace(0, np.pi, 1001))  # dense reference grid, true system
    Gt = freqresp(A, B, C, D, zf)
    return np.linalg.norm(freqresp(res.A, Bh, res.C, Dh, zf) - Gt) / np.linalg.norm(Gt)


@pytest.mark.parametrize("method", ["mckelvey1", "mckelvey2"])
def test_noisy_error_falls_with_M(method):
    Ms = [32, 64, 128, 256]
    err = np.array([np.mean([_noisy_error(M, s, method) for s in range(8)]) for M in Ms])
    assert np.all(np.diff(err) < 0), err
    # consistent estimator: error ~ M^(-1/2) (factor 0.35 for 8x more data); ask for under one half
    assert err[-1] < 0.5 * err[0], err
