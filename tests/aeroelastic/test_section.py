"""TypicalSection: validated inputs, matrices, in-vacuo frequencies."""

import numpy as np
import pytest

from aeroelastic import SectionError, TypicalSection

HP = dict(mu=20, a=-0.2, x_alpha=0.1, r_alpha2=0.24, omega_ratio=0.4)


@pytest.mark.parametrize(
    "change, match",
    [
        (dict(mu=0), "mu must be > 0"),
        (dict(mu=-3), "mu must be > 0"),
        (dict(mu=float("nan")), "mu must be finite"),
        (dict(a="aft"), "a must be a real number"),
        (dict(x_alpha=True), "x_alpha must be a real number"),
        (dict(omega_ratio=0.0), "omega_ratio must be > 0"),
        (dict(r_alpha2=0.01), "must exceed x_alpha"),
        (dict(r_alpha2=float("inf")), "r_alpha2 must be finite"),
        # text is refused, not parsed (as cfd.FlowCondition refuses it); a numpy bool is not a number either
        (dict(mu="20"), r"mu must be a real number, got '20'"),
        (dict(omega_ratio=b"0.4"), "omega_ratio must be a real number"),
        (dict(x_alpha=np.True_), "x_alpha must be a real number"),
    ],
)
def test_invalid_inputs_raise_typed_errors(change, match):
    with pytest.raises(SectionError, match=match):
        TypicalSection(**{**HP, **change})
    assert issubclass(SectionError, ValueError)


def test_frozen_and_derived_quantities():
    sec = TypicalSection(**HP)
    with pytest.raises(AttributeError, match="cannot assign to field 'mu'"):
        sec.mu = 3.0
    assert sec.elastic_axis == pytest.approx(0.4)
    assert isinstance(sec.mu, float)
    np.testing.assert_array_equal(sec.mass_matrix, [[2.0, -0.1], [-0.2, 0.24]])
    np.testing.assert_allclose(sec.stiffness_matrix, np.diag([0.32, 0.24]))


def test_natural_frequencies_solve_the_coupled_eigenproblem():
    sec = TypicalSection(**HP)
    w = sec.natural_frequencies()
    for wi in w:
        # det(Ks - w^2 Ms) = 0 with the inertially coupled mass matrix; entries are O(1), so 1e-12 is round-off
        assert abs(np.linalg.det(sec.stiffness_matrix - wi**2 * sec.mass_matrix)) < 1e-12
    # centre of mass on the elastic axis: uncoupled frequencies omega_ratio and 1
    np.testing.assert_allclose(TypicalSection(**{**HP, "x_alpha": 0.0}).natural_frequencies(), [0.4, 1.0], rtol=1e-12)


@pytest.mark.parametrize("a, match", [(5.0, "behind the trailing edge"), (1.2, "behind the trailing edge"),
                                      (-3.5, "more than a chord ahead")])
def test_elastic_axis_off_the_section_is_refused(a, match):
    with pytest.raises(SectionError, match=match):
        TypicalSection(**{**HP, "a": a})
    TypicalSection(**{**HP, "a": -2.0, "x_alpha": 1.8, "r_alpha2": 3.48})   # Isogai's case A stays legal


@pytest.mark.parametrize("damping, match", [(-0.01, r"\[0, 1\)"), (1.0, r"\[0, 1\)"), ((0.1, 0.2, 0.3), "two"),
                                            (float("nan"), "finite"), ("some", "real number"),
                                            ("0.02", "damping must be a real number, got '0.02'"),
                                            ((0.01, "0.02"), "damping must be a real number")])
def test_bad_damping(damping, match):
    with pytest.raises(SectionError, match=match):
        TypicalSection(**HP, damping=damping)


def test_undamped_by_default():
    sec = TypicalSection(**HP)
    assert sec.damping == (0.0, 0.0) and not sec.damping_matrix.any()


@pytest.mark.parametrize("zeta", [(0.02, 0.02), (0.05, 0.01)])
def test_free_decay_log_decrement(zeta):
    """Each in-vacuo mode, released from its shape, decays with its ratio: the logarithmic decrement of the
    successive peaks, delta = ln(x_k / x_k+1), gives zeta = delta / sqrt(4 pi^2 + delta^2) (exact for a viscously
    damped mode; peaks located by 20 000 samples per period and a parabola, hence 1e-5)."""
    from scipy.linalg import eig, expm

    sec = TypicalSection(**HP, damping=zeta)
    Ms, Ks, Ds = sec.mass_matrix, sec.stiffness_matrix, sec.damping_matrix
    Mi = np.linalg.inv(Ms)
    A = np.block([[np.zeros((2, 2)), np.eye(2)], [-Mi @ Ks, -Mi @ Ds]])
    w2, Phi = eig(Ks, Ms)
    order = np.argsort(w2.real)
    for i, z in zip(order, zeta):
        w = np.sqrt(w2[i].real)
        period = 2 * np.pi / (w * np.sqrt(1 - z * z))
        dt = period / 20000
        step = expm(A * dt)
        x = np.concatenate([Phi[:, i].real, [0.0, 0.0]])
        j = int(np.argmax(np.abs(Phi[:, i])))
        hist = []
        for _ in range(int(3.2 * 20000)):
            hist.append(x[j])
            x = step @ x
        y = np.array(hist) * np.sign(Phi[j, i].real)
        k = np.flatnonzero((y[1:-1] > y[:-2]) & (y[1:-1] >= y[2:])) + 1
        peaks = y[k] + (y[k + 1] - y[k - 1]) ** 2 / (8 * (2 * y[k] - y[k - 1] - y[k + 1]))   # parabola
        delta = np.log(peaks[0] / peaks[1])
        assert delta / np.sqrt(4 * np.pi**2 + delta**2) == pytest.approx(z, rel=1e-5)
