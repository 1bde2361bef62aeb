"""Point distributions of the C-grid (cfd.mesh.spacing): what they take and what they refuse."""

import numpy as np
import pytest

from cfd import MeshError
from cfd.mesh.spacing import geometric_distribution, vinokur_distribution


def test_geometric_distribution_grows_from_first_to_length():
    points, ratio = geometric_distribution(6, np.array([0.05, 0.1]), np.array([1.0, 2.0]))
    assert points.shape == (2, 7)
    np.testing.assert_allclose(points[:, 0], 0.0, atol=0)
    np.testing.assert_allclose(points[:, -1], [1.0, 2.0], rtol=1e-12)
    np.testing.assert_allclose(points[:, 1], [0.05, 0.1], rtol=1e-9)
    np.testing.assert_allclose(np.diff(points, axis=1)[:, 1:] / np.diff(points, axis=1)[:, :-1],
                               np.broadcast_to(ratio[:, None], (2, 5)), rtol=1e-9)


def test_vinokur_distribution_has_the_end_intervals():
    s = vinokur_distribution(40, 0.005, 0.02)
    assert s[0] == 0.0 and s[-1] == 1.0 and np.all(np.diff(s) > 0)
    assert s[1] == pytest.approx(0.005, rel=0.1) and 1.0 - s[-2] == pytest.approx(0.02, rel=0.1)   # to O(1/n)


# Before: a numpy complex lost its imaginary part with only a ComplexWarning (n, first, length, ds0, ds1; a complex
# n gave an empty or complex result), None became NaN (first, length) or a bare TypeError (ds0, ds1), text a bare
# ValueError / TypeError, n = 2.5 points that miss the end, n = 0 NaN or a ZeroDivisionError, ds0 = 0 a
# ZeroDivisionError and ds0 < 0 a math domain error.
BAD_N = [(np.complex128(4), "complex128"), (4 + 0j, "complex"), (2.5, "float"), (0, "int"), ("4", "str"),
         (None, "NoneType"), (True, "bool")]


@pytest.mark.parametrize("n, kind", BAD_N)
def test_geometric_distribution_refuses_n_that_is_not_a_whole_number_of_intervals(n, kind):
    with pytest.raises(MeshError, match=f"n must be a whole number of intervals >= 1; got {kind}"):
        geometric_distribution(n, 0.1, 1.0)


@pytest.mark.parametrize("n, kind", BAD_N)
def test_vinokur_distribution_refuses_n_that_is_not_a_whole_number_of_intervals(n, kind):
    with pytest.raises(MeshError, match=f"n must be a whole number of intervals >= 1; got {kind}"):
        vinokur_distribution(n, 0.05, 0.05)


@pytest.mark.parametrize("which", ["first", "length"])
@pytest.mark.parametrize("value, kind", [(np.array([0.1, 0.2]) + 1j, "dtype complex128"),
                                         (np.complex128(0.1), "complex128"), (0.1 + 0j, "complex"),
                                         ("0.1", "str"), (None, "NoneType")])
def test_geometric_distribution_refuses_lengths_that_are_not_real(which, value, kind):
    args = {"first": 0.1, "length": 1.0, which: value}
    with pytest.raises(MeshError, match=rf"{which} must be a real number or an array of real numbers .*got {kind}"):
        geometric_distribution(5, **args)


# Before: a first interval of 0 or below (or NaN) gave the bisection's bound 5 or 0.2 as the ratio and points that
# ignore it, a length of 0 or below points that do not increase, an infinite length NaN; all without a word.
@pytest.mark.parametrize("which", ["first", "length"])
@pytest.mark.parametrize("value", [0.0, -0.1, np.nan, np.inf, np.array([0.1, 0.0])])
def test_geometric_distribution_refuses_lengths_that_are_not_positive_and_finite(which, value):
    args = {"first": 0.1, "length": 1.0, which: value}
    with pytest.raises(MeshError, match=rf"{which} must be positive and finite \(.*chords\); got \["):
        geometric_distribution(5, **args)


@pytest.mark.parametrize("which", ["ds0", "ds1"])
@pytest.mark.parametrize("value, kind", [(np.complex128(0.05 + 0.01j), "complex128"), (0.05 + 0j, "complex"),
                                         ("0.05", "str"), (None, "NoneType"), (0.0, "float"), (-0.05, "float"),
                                         (np.nan, "float"), (np.array([0.05, 0.1]), "dtype float64")])
def test_vinokur_distribution_refuses_end_intervals_that_are_not_positive_real_numbers(which, value, kind):
    args = {"ds0": 0.05, "ds1": 0.05, which: value}
    with pytest.raises(MeshError, match=rf"{which} must be a positive finite real number \(.*\); got {kind}"):
        vinokur_distribution(20, **args)


def test_real_arguments_of_any_real_type_give_the_same_points():
    ref, ratio = geometric_distribution(8, np.array([0.125, 0.25]), np.array([2.0, 4.0]))
    for n, first, length in [(8.0, [0.125, 0.25], [2, 4]), (np.int64(8), np.float32([0.125, 0.25]), np.float32([2, 4]))]:
        points, r = geometric_distribution(n, first, length)
        np.testing.assert_array_equal(points, ref)
        np.testing.assert_array_equal(r, ratio)
    ref = vinokur_distribution(16, 0.03125, 0.125)
    for n, ds0, ds1 in [(16.0, 0.03125, 0.125), (np.int32(16), np.float32(0.03125), np.float64(0.125)),
                        (16, np.array(0.03125), 0.125)]:
        np.testing.assert_array_equal(vinokur_distribution(n, ds0, ds1), ref)
