import numpy as np
import pytest

from cfd.boundary import FARFIELD_BLEND, farfield_state, outflow_weight

GAMMA = 1.4
# Free stream of the code's non-dimensionalisation (rho = 1, p = 1/gamma, c = 1) at M 0.8 along x.
FREE = (1.0, 0.8, 0.0, 1.0 / GAMMA)


def _state(v, rho=1.02, u=0.79, p=1.01 / GAMMA):
    # An interior cell on the far-field line y = -R (outward normal (0, -1)): its normal velocity is -v.
    return farfield_state(rho, u, v, p, np.array([0.0]), np.array([-1.0]), FREE, 0.0, GAMMA)[..., 0]


def test_outflow_weight_is_one_half_at_zero_and_the_upwind_choice_outside_the_band():
    c = 1.0
    assert outflow_weight(0.0, c) == pytest.approx(0.5, abs=1e-15)
    # Ten band widths out the blend is the hard upwind switch to within 2 exp(-20) = 4e-9.
    assert outflow_weight(10 * FARFIELD_BLEND * c, c) == pytest.approx(1.0, abs=5e-9)
    assert outflow_weight(-10 * FARFIELD_BLEND * c, c) == pytest.approx(0.0, abs=5e-9)
    q = np.linspace(-3, 3, 61) * FARFIELD_BLEND * c
    assert np.all(np.diff(outflow_weight(q, c)) > 0)  # monotone across the band


def test_farfield_state_is_differentiable_where_the_normal_velocity_crosses_zero():
    # The boundary normal velocity is the mean of the interior's and the free stream's (Riemann invariants),
    # so it crosses zero near v = 0 here. A hard inflow/outflow switch gives one-sided slopes that differ by the
    # jump between the interior and free-stream entropy and tangential velocity (~1e-2 here); the blend must
    # give one slope, equal to the complex-step derivative (exact to round-off) and to a central difference
    # (truncation h^2 |f'''| ~ 1e-10 / band^2 ~ 4e-8 relative).
    for v0 in (-1e-3, 0.0, 1e-3):
        h = 1e-30
        d_cs = _state(v0 + 1j * h).imag / h
        dv = 1e-5
        d_fd = (_state(v0 + dv) - _state(v0 - dv)) / (2 * dv)
        np.testing.assert_allclose(d_fd, d_cs, rtol=1e-6, atol=1e-8)
        left = (_state(v0) - _state(v0 - dv)) / dv
        right = (_state(v0 + dv) - _state(v0)) / dv
        np.testing.assert_allclose(left, right, rtol=1e-3, atol=1e-6)


@pytest.mark.parametrize("v, upstream", [(-0.9, "interior"), (0.9, "free")])
def test_far_outside_the_band_the_state_is_the_riemann_upwind_state(v, upstream):
    # v = -0.9: interior normal velocity +0.9 c, boundary normal velocity 0.45 c (the mean with the free
    # stream's 0): outflow, tangential velocity and entropy from the interior cell; v = +0.9: inflow, both
    # from the free stream.
    rho, u, p = 1.02, 0.79, 1.01 / GAMMA
    q = _state(v, rho, u, p)
    rb, ub, vb = q[0], q[1] / q[0], q[2] / q[0]
    pb = (GAMMA - 1) * (q[3] - 0.5 * rb * (ub**2 + vb**2))
    if upstream == "interior":
        u_t, s = u, p / rho**GAMMA
    else:
        u_t, s = FREE[1], FREE[3] / FREE[0] ** GAMMA
    # 9 band widths: the other side's weight is exp(-18) = 1.5e-8, times a jump of ~1e-2 between the two.
    assert ub == pytest.approx(u_t, abs=1e-9)
    assert pb / rb**GAMMA == pytest.approx(s, rel=1e-9)
