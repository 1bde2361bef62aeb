"""sysid.simulate: a discrete ROM's time response (Markov parameters, FFT convolution, python-control)."""

import control
import numpy as np
import pytest

import sysid
from sysid.simulate import markov_parameters, rom_response, rom_simulation, simulate_discrete


# ZOH is exact for a step input; Tustin treats the input as piecewise linear, so the jump at t = 0 costs
# about dt / 2 times the initial slope (1) at the first samples, and O(dt^2) afterwards
@pytest.mark.parametrize("disc, tol", [("tustin", 0.51e-2), ("zoh", 1e-10)])
def test_rom_simulation_first_order(disc, tol):
    """dx/dt = -x + u sampled at T = 0.5 (bilinear), re-discretised at dt = 0.01: step response 1 - exp(-t)."""
    cont = control.ss([[-1.0]], [[1.0]], [[1.0], [2.0]], [[0.0], [0.0]])
    rom = sysid.c2d_bilinear(cont, 0.5)
    t = np.arange(0, 801) * 0.01
    y = rom_simulation(rom.A, rom.B, rom.C, rom.D, 0.5, t, np.ones_like(t), disc)
    assert y.shape == (2, t.size)
    np.testing.assert_allclose(y[0], 1 - np.exp(-t), atol=tol)
    np.testing.assert_allclose(y[1], 2 * y[0], rtol=1e-12)


@pytest.mark.parametrize("rho, method", [(0.95, "auto"), (0.95, "convolution"), (0.95, "control"), (1.02, "auto")])
def test_simulate_discrete_matches_python_control(rho, method):
    rng = np.random.default_rng(3)
    n, N = 12, 1500
    Q, _ = np.linalg.qr(rng.normal(size=(n, n)))
    A = Q @ np.diag(rho * np.cos(np.linspace(0, 3, n))) @ Q.T  # spectral radius rho
    B, C, D = rng.normal(size=(n, 1)), rng.normal(size=(2, n)), rng.normal(size=(2, 1))
    u = np.sin(0.05 * np.arange(N)) * (np.arange(N) > 20)
    ref = np.asarray(control.forced_response(control.ss(A, B, C, D, True), U=u).outputs)
    y = simulate_discrete(A, B, C, D, u, method)
    assert y.shape == (2, N)
    np.testing.assert_allclose(y, ref, rtol=0, atol=1e-11 * np.abs(ref).max())


def test_markov_parameters():
    A = np.array([[0.5, 1.0], [0.0, 0.25]])
    B = np.array([[0.0], [1.0]])
    C = np.eye(2)
    G = markov_parameters(A, B, C, 5)
    expected = [np.linalg.matrix_power(A, k) @ B for k in range(5)]
    np.testing.assert_allclose(G[:, 0, :], np.hstack(expected), rtol=1e-15)
    with pytest.raises(sysid.OptionError, match="method must be"):
        simulate_discrete(A, B, C, np.zeros((2, 1)), np.ones(4), "rk4")


@pytest.mark.parametrize("t, disc, error, match", [
    (np.array([0.0]), "tustin", sysid.TimeDataError, "at least two time points"),
    (np.arange(3.0), "euler", sysid.OptionError, "discretisation must be"),
])
def test_rom_simulation_bad_input(t, disc, error, match):
    with pytest.raises(error, match=match):
        rom_simulation(np.eye(1) * 0.5, np.ones((1, 1)), np.ones((1, 1)), np.zeros((1, 1)), 1.0, t, t, disc)


@pytest.mark.parametrize("t, u, match", [
    (np.r_[0.0, 0.01, np.linspace(0.5, 10.0, 99)], np.ones(101), r"equispaced .*t\[2\] - t\[1\] = 0.49"),
    (np.r_[np.arange(50) * 0.1, 4.9 + 0.1 * (1 + 1e-4)], np.ones(51), r"equispaced .*t\[50\] - t\[49\]"),
    (np.arange(5.0)[::-1], np.ones(5), "times must increase"),
    (np.linspace(0.0, 10.0, 101), np.ones(50), "u has 50 samples but t has 101 times"),
    (np.linspace(0.0, 10.0, 101), np.ones((1, 102)), "u has 102 samples but t has 101 times"),
])
def test_rom_response_needs_equispaced_times_and_one_input_per_time(t, u, match):
    rom = control.ss([[0.5]], [[1.0]], [[1.0]], [[0.0]], 0.5)
    with pytest.raises(sysid.TimeDataError, match=match):
        rom_response(rom, t, u)
    # ulp-level jitter of a computed grid is still one step
    t_ok = np.cumsum(np.full(2001, 0.01)) - 0.01
    assert rom_response(rom, t_ok, np.ones(t_ok.size)).outputs.shape == (1, t_ok.size)
    # so are times rounded as given: float32, or printed with 6 significant digits
    for t_rounded in ((0.02 * np.arange(2001)).astype(np.float32), np.array([float(f"{v:.6g}") for v in
                                                                              np.arange(2001) / 30])):
        assert rom_response(rom, t_rounded, np.ones(t_rounded.size)).outputs.shape == (1, t_rounded.size)


def test_rom_response_returns_python_control_data():
    """rom_response: the same outputs as rom_simulation, as a control.TimeResponseData with the model's names."""
    rom = control.ss([[0.5]], [[1.0]], [[1.0], [2.0]], [[0.0], [0.0]], 0.5, inputs=["gust"], outputs=["Cl", "Cm"])
    t = np.arange(0, 101) * 0.05
    u = np.sin(t)
    data = rom_response(rom, t, u, discretisation="zoh")
    assert isinstance(data, control.TimeResponseData)
    assert data.outputs.shape == (2, t.size) and list(data.output_labels) == ["Cl", "Cm"]
    np.testing.assert_allclose(data.outputs, rom_simulation(rom.A, rom.B, rom.C, rom.D, 0.5, t, u, "zoh"))
    np.testing.assert_allclose(data.time, t)


# ---------------------------------------------------------------------- input checks (issue 34 findings)
A1, B1, C1, D1 = np.eye(1) * 0.5, np.ones((1, 1)), np.ones((1, 1)), np.zeros((1, 1))
T10 = np.arange(10.0)


@pytest.mark.parametrize("k", [0, 3, 9])
@pytest.mark.parametrize("bad", [np.nan, np.inf])
def test_rom_simulation_refuses_a_non_finite_input(k, bad):
    # a NaN at sample 3 returned NaN histories from sample 1 on (the FFT spreads it)
    u = np.ones(10)
    u[k] = bad
    with pytest.raises(sysid.TimeDataError, match=rf"u contains NaN or inf at sample {k} \(t = {float(k):g}\)"):
        rom_simulation(A1, B1, C1, D1, 1.0, T10, u)


def test_rom_simulation_refuses_non_finite_times():
    t = T10.copy()
    t[4] = np.nan
    with pytest.raises(sysid.TimeDataError, match=r"t contains NaN or inf at index 4"):
        rom_simulation(A1, B1, C1, D1, 1.0, t, np.ones(10))


@pytest.mark.parametrize("T", [-1.0, 0.0, np.nan, np.inf, "1", True])
def test_rom_simulation_refuses_a_bad_period(T):
    # T = -1 raised python-control's "invalid timebase, dt = -1.0"
    with pytest.raises(sysid.FrequencyGridError, match="sampling period T must be"):
        rom_simulation(A1, B1, C1, D1, T, T10, np.ones(10))


@pytest.mark.parametrize("mats, match", [
    ((np.ones((2, 3)), B1, C1, D1), r"A must be square \(n, n\), got shape \(2, 3\)"),
    ((A1, np.ones((2, 1)), C1, D1), r"B has shape \(2, 1\) but A is 1 x 1: B must be \(n, m\) = \(1, m\)"),
    ((A1, B1, np.ones((1, 2)), D1), r"C has shape \(1, 2\) but A is 1 x 1: C must be \(p, n\) = \(p, 1\)"),
    ((A1, B1, C1, np.zeros((2, 1))), r"D has shape \(2, 1\) but C and B give \(p, m\) = \(1, 1\)"),
    ((A1, B1, C1, np.zeros((1, 1, 1))), r"D must be a 2-D matrix"),
    ((np.full((1, 1), np.nan), B1, C1, D1), r"A contains NaN or inf"),
    ((A1, B1, C1, np.full((1, 1), np.inf)), r"D contains NaN or inf"),
    ((A1, B1, C1, [["a"]]), r"D must be a matrix of real numbers"),
])
def test_rom_simulation_names_the_offending_matrix(mats, match):
    # python-control's ControlDimension ("Incompatible dimensions of B matrix") before
    with pytest.raises(sysid.ModelError, match=match):
        rom_simulation(*mats, 1.0, T10, np.ones(10))


def test_rom_simulation_refuses_an_input_with_another_number_of_channels():
    with pytest.raises(sysid.TimeDataError, match=r"u has 2 input channels but the model has m = 1"):
        rom_simulation(A1, B1, C1, D1, 1.0, T10, np.ones((2, 10)))


def test_rom_simulation_refuses_a_march_that_cannot_fit_in_memory():
    from sysid.simulate import MAX_SIMULATION_VALUES

    n = 50
    N = MAX_SIMULATION_VALUES // n + 1
    t = np.arange(N, dtype=float)   # 1.6 MB of times for 2e5 steps; the Markov parameters would be n times more
    with pytest.raises(sysid.TimeDataError, match=r"n x m x N = .* above .*MAX_SIMULATION_VALUES"):
        rom_simulation(np.eye(n) * 0.5, np.ones((n, 1)), np.ones((1, n)), np.zeros((1, 1)), 1.0, t, np.ones(N))


def test_rom_response_refuses_what_is_not_a_discrete_model():
    t = T10
    with pytest.raises(TypeError, match="rom_response.. expects a control.StateSpace"):
        rom_response(np.eye(2), t, np.ones(10))
    with pytest.raises(sysid.ModelError, match="expects a discrete model"):
        rom_response(control.ss([[-1.0]], [[1.0]], [[1.0]], [[0.0]]), t, np.ones(10))


@pytest.mark.parametrize("kwargs, match", [(dict(method="fast"), "method must be"),
                                           (dict(discretisation=None), "discretisation must be")])
def test_rom_simulation_options_are_checked_before_any_work(kwargs, match):
    with pytest.raises(sysid.OptionError, match=match):   # even with a bad input, the option is named first
        rom_simulation(A1, B1, C1, D1, 1.0, T10, np.ones(10), **kwargs)


@pytest.mark.parametrize("N", [0, -1, 2.5, True, "4"])
def test_markov_parameters_refuses_a_count_that_is_not_positive(N):
    # N = -1 returned an empty array, N = 2.5 raised a bare TypeError
    with pytest.raises(sysid.OptionError, match="N must be a positive whole number"):
        markov_parameters(A1, B1, C1, N)


def test_markov_parameters_and_simulate_discrete_check_their_matrices_and_input():
    with pytest.raises(sysid.ModelError, match=r"B has shape \(2, 1\) but A is 1 x 1"):
        markov_parameters(A1, np.ones((2, 1)), C1, 4)
    with pytest.raises(sysid.ModelError, match=r"D has shape \(2, 2\)"):
        simulate_discrete(A1, B1, C1, np.ones((2, 2)), np.ones(3))
    with pytest.raises(sysid.TimeDataError, match="u contains NaN or inf at sample 1"):
        simulate_discrete(A1, B1, C1, D1, np.array([1.0, np.nan, 1.0]))
    with pytest.raises(sysid.OptionError, match="method must be"):
        simulate_discrete(A1, B1, C1, D1, np.ones(3), method=None)
    with pytest.raises(sysid.TimeDataError, match="u has no samples"):   # an IndexError before
        simulate_discrete(A1, B1, C1, D1, np.zeros((1, 0)))
    with pytest.raises(sysid.TimeDataError, match="u must be real"):   # imaginary part dropped with a warning before
        simulate_discrete(A1, B1, C1, D1, np.ones(3) + 1j)


def test_rediscretise_names_itself_for_what_is_not_a_model():
    with pytest.raises(TypeError, match=r"rediscretise\(\) expects a discrete control.StateSpace"):
        sysid.rediscretise(np.eye(2), 0.1)
