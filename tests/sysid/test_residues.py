"""The gain bounds between the samples and the points where a model's resonances peak (sysid.residues)."""

import control
import numpy as np
import pytest

from sysid import FrequencyResponse, mckelvey_grid
from sysid.identify import unobserved_gain
from sysid.residues import GAP_FLOOR, GAP_NOISE, GAP_SLACK, bounds_at, gap_bounds, resonance_points


def test_bounds_at_takes_the_bound_of_the_interval_that_holds_the_point():
    # unequal spacing: samples at 0, 0.01 and 1 rad/sample with |G| 1, 1, 10; gap_bounds gives each interval
    # 1.25 max(neighbours) + 0.05 peak: 1.75 on [0, 0.01], 13 on [0.01, 1] and on [1, pi]
    wd = np.array([0.0, 0.01, 1.0])
    zb, ub = gap_bounds(np.exp(1j * wd), np.array([1.0, 1.0, 10.0])[None, None, :] + 0j)
    got = bounds_at(np.exp(1j * np.array([0.005, 0.05, 0.5, 2.0])), zb, ub)[0, 0]
    # 0.05 lies just above the sample at 0.01: its nearest bound point is in the interval below (1.75), which would
    # refuse a model that stays within its own interval's bound
    np.testing.assert_allclose(got, [1.75, 13.0, 13.0, 13.0])


@pytest.mark.parametrize("sigma", [0.0, 0.003, 0.01])
def test_gap_bounds_take_the_samples_noise_into_the_envelope(sigma):
    # two outputs with peaks 10 and 2 on the same grid: each one's bound grows by slack * GAP_NOISE * sigma * its
    # own peak, everywhere (sigma relative to each output's peak, as sysid.noise_level gives it)
    wd = np.array([0.0, 0.5, 1.0, 2.0])
    G = np.array([[[10.0, 4.0, 1.0, 0.5]], [[1.0, 2.0, 0.5, 0.1]]]) + 0j
    zb, ub0 = gap_bounds(np.exp(1j * wd), G)
    zb_n, ub = gap_bounds(np.exp(1j * wd), G, noise=[sigma, sigma])
    np.testing.assert_array_equal(zb_n, zb)
    peak = np.array([10.0, 2.0])[:, None, None]
    # (a difference of bounds of about 13: a few ulp of them, whatever the machine)
    np.testing.assert_allclose(ub - ub0, GAP_SLACK * GAP_NOISE * sigma * peak * np.ones_like(ub), rtol=1e-12,
                               atol=1e-13)
    # without noise: slack times the larger neighbour plus the floor (first interval of output 0: 1.25 * 10 + 0.5)
    np.testing.assert_allclose(ub0[0, 0, 0], GAP_SLACK * 10.0 + GAP_FLOOR * 10.0)


def test_gap_bounds_scale_the_noise_by_each_outputs_peak_over_its_inputs():
    # one output, two inputs, the second 100 times smaller: the same absolute noise (sigma relative to the output's
    # peak over both inputs, as sysid.noise_level gives it) widens both inputs' bounds alike
    wd = np.array([0.0, 0.5, 1.0, 2.0])
    g = np.array([10.0, 4.0, 1.0, 0.5]) + 0j
    G = np.stack([g, g / 100.0])[None]   # (1, 2, 4)
    _, ub0 = gap_bounds(np.exp(1j * wd), G)
    _, ub = gap_bounds(np.exp(1j * wd), G, noise=[1e-3])
    np.testing.assert_allclose(ub - ub0, GAP_SLACK * GAP_NOISE * 1e-3 * 10.0, rtol=1e-9)


def test_resonance_points_sit_on_each_pole_and_its_flanks():
    r, theta = 1 - 1e-3, 0.4
    pts = np.angle(resonance_points(np.array([r * np.exp(1j * theta), r * np.exp(-1j * theta), 0.2])))
    np.testing.assert_allclose(np.sort(pts), theta + 1e-3 * np.array([-2, -1, -0.5, 0, 0.5, 1, 2]), atol=1e-15)
    assert resonance_points(np.array([0.1, -0.3])).size == 0   # poles far from the circle: no narrow peak


def test_unobserved_gain_sees_a_resonance_between_its_check_points():
    # a pole pair of radius 1 - 1e-4 at 0.3 of an interval of McKelvey's M = 64 grid: its peak (about 1) lies
    # 2.5e-3 rad from the nearest of the eight check points per interval, where the gain is 0.04
    wd, _ = mckelvey_grid(64, 1.0)
    theta = np.pi * (10 + 0.3) / 64
    p = (1 - 1e-4) * np.exp(1j * theta)
    A = np.array([[2 * p.real, -abs(p) ** 2], [1.0, 0.0]])   # poles p and conj(p)
    model = control.ss(A, [[1.0], [0.0]], [[0.0, 1e-4]], [[0.0]], 1.0)
    data = FrequencyResponse(np.ones((1, 1, wd.size)) + 0j, wd, 1.0)   # unit data: gain in units of the peak
    dense = np.abs(model(np.exp(1j * np.linspace(theta - 1e-3, theta + 1e-3, 20001)))).max()
    assert dense > 0.5   # the true peak, 1e-4 / (2 sin(theta) (1 - r)) = 1.03
    assert unobserved_gain(model, data)[0] == pytest.approx(dense, rel=1e-3)
