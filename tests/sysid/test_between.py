"""sysid.between: the estimate of a model's error between the samples."""

import numpy as np
import pytest
from sysid_synth import freqresp, random_system

from sysid import mckelvey_grid
from sysid.between import (between_error, between_points, cubic_interpolant, cubic_misfit, polar_interpolant,
                           rational_interpolant, sample_readings)


@pytest.mark.parametrize("shift", [-1, 0, 1])
def test_the_cubic_interpolant_is_exact_on_cubics(shift):
    # a cubic in omega_d (complex coefficients) is reproduced by any four-sample stencil, to round-off
    w = np.sort(np.random.default_rng(0).uniform(0.0, np.pi, 12))
    f = lambda x: (1 + 2j) - 0.5 * x + (0.3 - 1j) * x**2 + 0.1j * x**3  # noqa: E731
    at = between_points(w)
    got = cubic_interpolant(w, f(w)[None, None, :], at, shift)[0, 0]
    assert np.abs(got - f(at)).max() <= 1e-12 * np.abs(f(at)).max()


def test_the_polar_interpolant_follows_a_fast_phase():
    # a pure delay turning 60 degrees per interval: real and imaginary parts oscillate, magnitude and unwrapped phase
    # are linear, so the polar reading is exact where the cartesian one is not
    w = np.linspace(0.0, np.pi, 33)
    H = np.exp(-1j * (np.pi / 3) / (w[1] - w[0]) * w)[None, None, :]
    at = between_points(w)
    exact = np.exp(-1j * (np.pi / 3) / (w[1] - w[0]) * at)
    assert np.abs(polar_interpolant(w, H, at)[0, 0] - exact).max() < 1e-12
    assert np.abs(cubic_interpolant(w, H, at)[0, 0] - exact).max() > 1e-3


def test_an_exact_model_has_no_error_between_the_samples():
    # the system itself: its departure from the readings of its own samples is within their spread, so zero
    A, B, C, D, _ = random_system(4, 2, 1, 5, rho=0.8)
    wd, _ = mckelvey_grid(64, 1.0)
    e = between_error(A, B, C, D, wd, freqresp(A, B, C, D, np.exp(1j * wd)))
    assert e.shape == (2,) and np.all(e == 0.0)


def test_a_resonance_between_two_samples_is_seen():
    # the data of a smooth system, a model with an added narrow resonance peaking halfway between two samples:
    # invisible at the samples (0.2 % of the peak there), a quarter of the peak between them; the estimate finds it
    # (the model's resonance peak is one of the points looked at) to within the data's own departure there
    wd, _ = mckelvey_grid(64, 1.0)
    A, B, C, D, _ = random_system(2, 1, 1, 3, rho=0.5)
    H = freqresp(A, B, C, D, np.exp(1j * wd))
    th, r = 0.5 * (wd[20] + wd[21]), 1.0 - 2e-4
    Ar = r * np.array([[np.cos(th), -np.sin(th)], [np.sin(th), np.cos(th)]])
    g = 0.5 * np.abs(H).max() * (1 - r)
    A2 = np.block([[A, np.zeros((2, 2))], [np.zeros((2, 2)), Ar]])
    B2, C2 = np.vstack([B, [[g], [0.0]]]), np.hstack([C, [[1.0, 0.0]]])
    at_samples = np.abs(freqresp(A2, B2, C2, D, np.exp(1j * wd)) - H).max() / np.abs(H).max()
    fine = np.exp(1j * np.linspace(0.0, np.pi, 10001))
    true_between = np.abs(freqresp(A2, B2, C2, D, fine) - freqresp(A, B, C, D, fine)).max() / np.abs(H).max()
    e = between_error(A2, B2, C2, D, wd, H)
    assert at_samples < 0.005 and true_between > 0.2 and abs(e[0] - true_between) < 0.05 * true_between


def test_too_few_samples_give_nan():
    A, B, C, D, _ = random_system(2, 1, 1, 3)
    wd = np.array([0.0, 1.0, 2.0])
    assert np.isnan(between_error(A, B, C, D, wd, freqresp(A, B, C, D, np.exp(1j * wd))))[0]


def test_the_cubic_misfit_is_the_fourth_difference_on_an_equispaced_grid():
    # a cubic through four equispaced samples misses the next one by the fourth difference of the five (the
    # quantity whose noise sysid.noise reads); inside the grid the larger of the misses on either side
    w = np.linspace(0.0, np.pi, 21)
    H = (np.exp(1.3j * w) / (2.5 - np.cos(w)))[None, None, :]
    at = between_points(w)
    d4 = np.abs(np.diff(H[0, 0], 4))          # d4[i]: samples i .. i + 4
    k = np.arange(at.size)                     # the interval of each midpoint
    first = np.clip(k - 1, 0, w.size - 4)
    left = np.where(first >= 1, d4[np.clip(first - 1, 0, d4.size - 1)], 0.0)
    right = np.where(first + 4 < w.size, d4[np.clip(first, 0, d4.size - 1)], 0.0)
    assert np.allclose(cubic_misfit(w, H, at)[0, 0], np.maximum(left, right), rtol=1e-10, atol=1e-15)


@pytest.mark.parametrize("poles", [1, 2])
def test_the_rational_reading_is_exact_on_its_own_type(poles):
    # N / D with deg N = poles + 1, D monic of degree poles (resonances between two samples, 0.3 and 0.5 of the
    # spacing wide, on a linear background): every window around them reads it to round-off (1e-14 measured; the
    # fit's matrix has a condition number of about 1e3). Far from the poles a window sees a function of lower type,
    # its fit is rank-deficient and exact only to the pseudo-inverse's cut-off, so the points are those near them
    w = np.linspace(0.0, np.pi, 40)
    h = w[1] - w[0]
    q = [0.5 * (w[17] + w[18]) + 0.3j * h, 0.5 * (w[19] + w[20]) + 0.5j * h][:poles]
    f = lambda x: (0.7 - 0.2j + 0.3 * x) + sum((0.05 - 0.02j * j) * h / (x - qq) for j, qq in enumerate(q))  # noqa: E731
    H = f(w)[None, None, :]
    at = np.concatenate([between_points(w)[16:21], [qq.real for qq in q]])
    for shift in (-1, 0, 1):
        got, miss = rational_interpolant(w, H, at, poles, shift)
        assert np.abs(got[0, 0] - f(at)).max() <= 1e-11 * np.abs(f(at)).max()
        assert miss.max() <= 1e-11 * np.abs(H).max()


@pytest.mark.parametrize("width", [0.3, 0.5])
def test_readings_follow_a_resonance_narrower_than_the_spacing(width):
    # a lightly damped mode of a smooth system peaking between two samples (half-width 0.3 or 0.5 of the spacing):
    # the cubic readings miss the samples next to it by far more than READING_FLOOR, the local rational reading
    # explains them, and the estimate follows the truth. The system itself is charged with less than a tenth of what
    # the mode adds between the samples (0.0089 and 0.0028 of the peak; the cubic readings alone: 0.062 and 0.015),
    # a model without the mode with 0.82 and 0.88 of what it misses (the cubic readings: 0.09 and 0.32 of it)
    wd, _ = mckelvey_grid(64, 1.0)
    A, B, C, D, _ = random_system(2, 1, 1, 3, rho=0.5)
    th, r = 0.5 * (wd[20] + wd[21]), 1.0 - width * (wd[1] - wd[0])
    Ar = r * np.array([[np.cos(th), -np.sin(th)], [np.sin(th), np.cos(th)]])
    A2 = np.block([[A, np.zeros((2, 2))], [np.zeros((2, 2)), Ar]])
    B2, C2 = np.vstack([B, [[0.05], [0.0]]]), np.hstack([C, [[1.0, 0.0]]])
    H = freqresp(A2, B2, C2, D, np.exp(1j * wd))
    peak = np.abs(H).max()
    fine = np.exp(1j * np.linspace(0.0, np.pi, 20001))
    true_without = np.abs(freqresp(A, B, C, D, fine) - freqresp(A2, B2, C2, D, fine)).max() / peak
    _, _, family = sample_readings(wd, H, np.array([th]))
    assert family[0, 0, 0] >= 1
    assert between_error(A2, B2, C2, D, wd, H)[0] < 0.1 * true_without
    assert 0.7 * true_without <= between_error(A, B, C, D, wd, H)[0] <= 1.3 * true_without


def test_noise_alone_keeps_the_cubic_readings():
    # a smooth response with 1 % noise: the cubic misfits are the noise's fourth differences, below
    # CUBIC_NOISE_MULT deviations, so no rational reading replaces them
    wd, _ = mckelvey_grid(64, 1.0)
    A, B, C, D, _ = random_system(4, 1, 1, 5, rho=0.7)
    H = freqresp(A, B, C, D, np.exp(1j * wd))
    rng = np.random.default_rng(1)
    H = H + 0.01 * np.abs(H).max() * (rng.standard_normal(H.shape) + 1j * rng.standard_normal(H.shape)) / np.sqrt(2)
    _, _, family = sample_readings(wd, H, between_points(wd))
    assert np.all(family == 0)


def test_the_uncertainty_is_the_readings_spread_and_zero_for_too_few_samples():
    # between_estimate returns the estimate and the largest spread of the readings at the same points, per output;
    # a smooth system's readings agree to their interpolation error (fourth order in the spacing: 0.0020 and 0.00028
    # of the peak here, poles at radius 0.8 on 65 samples)
    from sysid.between import between_estimate, between_uncertainty

    A, B, C, D, _ = random_system(4, 2, 1, 5, rho=0.8)
    wd, _ = mckelvey_grid(64, 1.0)
    H = freqresp(A, B, C, D, np.exp(1j * wd))
    e, u = between_estimate(A, B, C, D, wd, H)
    assert np.array_equal(e, between_error(A, B, C, D, wd, H))
    assert np.array_equal(u, between_uncertainty(A, B, C, D, wd, H))
    assert u.shape == (2,) and np.all(u < 0.01)
    assert np.all(np.isnan(between_estimate(A, B, C, D, wd[:3], H[:, :, :3])))


def test_a_cache_kept_across_models_gives_the_same_estimates():
    # order_sweep estimates every order on one data set with one cache of the local rational fits: the estimates
    # are those of separate calls to the last bit, and a cache handed other data starts afresh
    from sysid_synth import noisy_resonant_system

    from sysid import FrequencyResponse, identify

    wd, w = mckelvey_grid(64, 1.0)
    frf = FrequencyResponse(noisy_resonant_system(w, w[:1], seed=11)[0], wd, 1.0)
    other = FrequencyResponse(noisy_resonant_system(w, w[:1], seed=13)[0], wd, 1.0)
    cache = {}
    for data in (frf, other, frf):
        for n in (8, 12, 16):
            m = identify(data, n).matrices
            alone = between_error(m.A, m.B, m.C, m.D, data.omega_d, data.H)
            shared = between_error(m.A, m.B, m.C, m.D, data.omega_d, data.H, cache=cache)
            assert np.array_equal(alone, shared)
    assert any(isinstance(k, int) for k in cache)   # rational fits were kept


def test_the_order_of_the_samples_does_not_matter():
    # the noise estimate that sets the readings' floor differences the samples along the sorted grid: the same
    # samples in another order give the same readings (the model without the mode was estimated 0.013 off instead
    # of 0.119 with the samples shuffled, the exact model 0.062 instead of 0.0089)
    wd, _ = mckelvey_grid(64, 1.0)
    A, B, C, D, _ = random_system(2, 1, 1, 3, rho=0.5)
    th, r = 0.5 * (wd[20] + wd[21]), 1.0 - 0.3 * (wd[1] - wd[0])
    Ar = r * np.array([[np.cos(th), -np.sin(th)], [np.sin(th), np.cos(th)]])
    A2 = np.block([[A, np.zeros((2, 2))], [np.zeros((2, 2)), Ar]])
    B2, C2 = np.vstack([B, [[0.05], [0.0]]]), np.hstack([C, [[1.0, 0.0]]])
    H = freqresp(A2, B2, C2, D, np.exp(1j * wd))
    perm = np.random.default_rng(3).permutation(wd.size)
    for model in ((A, B, C, D), (A2, B2, C2, D)):
        e = between_error(*model, wd, H)
        assert np.array_equal(e, between_error(*model, wd[perm], H[:, :, perm]))
    assert between_error(A, B, C, D, wd, H)[0] > 0.1


def test_a_jump_in_the_samples_gives_no_reading_on_its_own_pole():
    # a step between two samples: a local rational reading puts its pole at the interval's midpoint, exactly where
    # it is read (-5e14 there); such a reading is refused (at most 100 times the window's largest sample), so the
    # readings' spread stays of the order of the step (it was 3.7e14 of the peak)
    from sysid.between import between_estimate

    wd = np.linspace(0.0, np.pi, 41)[:-1]
    H = (1.0 + 0.5 * (np.arange(wd.size) >= 20)).astype(complex)[None, None, :]
    A, B, C, D = np.array([[0.5]]), np.array([[1.0]]), np.array([[0.5]]), np.array([[1.0]])
    e, u = between_estimate(A, B, C, D, wd, H)
    assert np.all(np.isfinite(e)) and 0.0 < u[0] < 1.0


def test_too_few_samples_give_nan_departures_without_numpy_warnings():
    import warnings

    from sysid.between import between_deviation

    A, B, C, D, _ = random_system(2, 1, 1, 3)
    wd = np.array([0.0, 1.0, 2.0])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        pts, dev = between_deviation(A, B, C, D, wd, freqresp(A, B, C, D, np.exp(1j * wd)))
    assert pts.shape == (2,) and dev.shape == (1, 1, 2) and np.all(np.isnan(dev))


@pytest.mark.parametrize("poles, shift, what", [(0, 0, "poles"), (1.5, 0, "poles"), (True, 0, "poles"),
                                                (1, 0.5, "shift")])
def test_the_rational_reading_refuses_a_bad_option(poles, shift, what):
    from sysid.errors import OptionError

    w = np.linspace(0.0, np.pi, 12)
    with pytest.raises(OptionError, match=f"{what} must be a whole number"):
        rational_interpolant(w, np.ones((1, 1, 12), dtype=complex), between_points(w), poles, shift)
