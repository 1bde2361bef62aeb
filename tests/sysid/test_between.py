"""sysid.between: the estimate of a model's error between the samples."""

import numpy as np
import pytest
from sysid_synth import freqresp, random_system

from sysid import mckelvey_grid
from sysid.between import between_error, between_points, cubic_interpolant, polar_interpolant


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
