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
