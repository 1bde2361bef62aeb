"""Tests of sysid.metrics against hand-computed values."""

import numpy as np
import pytest

from sysid import FrequencyDataError, dc_error, frf_errors, max_relative_error, rms_relative_error, spectral_radius


def test_known_values_two_outputs():
    H = np.zeros((2, 1, 4), dtype=complex)
    H[0, 0] = [2.0, 1.0, 1.0j, 0.0]  # peak 2, mean square (4 + 1 + 1 + 0)/4 = 1.5
    H[1, 0] = [10.0, 10.0, 10.0, 10.0]  # peak 10, mean square 100
    Hm = H.copy()
    Hm[0, 0, 3] = 0.5  # error 0.5 at a point where the data are 0 (no division by zero)
    Hm[1, 0, 0] = 11.0  # error 1
    np.testing.assert_allclose(max_relative_error(Hm, H, per_output=True), [0.5 / 2, 1 / 10])
    assert max_relative_error(Hm, H) == pytest.approx(0.25)
    np.testing.assert_allclose(rms_relative_error(Hm, H, per_output=True),
                               [np.sqrt(0.25 / 4) / np.sqrt(1.5), np.sqrt(1 / 4) / 10])
    assert rms_relative_error(Hm, H) == pytest.approx(np.sqrt(0.25 + 1) / np.sqrt(6 + 400))
    e = frf_errors(Hm, H)
    assert e.max_rel == pytest.approx(0.25) and e.rms_rel == pytest.approx(np.sqrt(1.25 / 406))


def test_zero_data_give_infinite_or_zero_relative_errors():
    # an output whose data are zero everywhere: the relative error of a nonzero model is infinite (4.5e307 before,
    # a division by the smallest double), and 0 where the model is zero too
    H = np.zeros((2, 1, 4), dtype=complex)
    H[1] = 1.0
    Hm = H.copy()
    Hm[0, 0, 2] = 1e-3
    np.testing.assert_array_equal(max_relative_error(Hm, H, per_output=True), [np.inf, 0.0])
    np.testing.assert_array_equal(rms_relative_error(Hm, H, per_output=True), [np.inf, 0.0])
    assert frf_errors(H, H).max_rel == 0.0 and rms_relative_error(0 * H, 0 * H) == 0.0


@pytest.mark.parametrize("a, b, match", [
    (np.zeros((1, 1, 0)), np.zeros((1, 1, 0)), "K >= 1 frequencies"),        # a NumPy reduction error before
    ("a", "b", "must be arrays of numbers"),                                   # "complex() arg is malformed"
])
def test_empty_or_non_numeric_data_are_refused(a, b, match):
    with pytest.raises(FrequencyDataError, match=match):
        max_relative_error(a, b)


def test_siso_1d_and_shape_mismatch():
    assert max_relative_error(np.array([1.0, 2.0]), np.array([1.0, 1.0])) == pytest.approx(1.0)
    with pytest.raises(FrequencyDataError, match="shape"):
        rms_relative_error(np.ones((1, 1, 3)), np.ones((1, 1, 4)))


def test_dc_error_and_spectral_radius():
    assert dc_error([[1.1, 2.0]], [[1.0, 2.0]]) == pytest.approx(0.05)
    assert dc_error([[1.1]], [[1.0]], relative=False) == pytest.approx(0.1)
    assert dc_error([[0.1]], [[0.0]]) == pytest.approx(0.1)  # zero DC: absolute
    A = np.array([[0.0, -0.9], [0.9, 0.0]])  # eigenvalues +-0.9j
    assert spectral_radius(A) == pytest.approx(0.9)
    assert spectral_radius(np.zeros((0, 0))) == 0.0


# ---------------------------------------------------------------------- input checks (issue 34 findings)
@pytest.mark.parametrize("func", [frf_errors, max_relative_error, rms_relative_error])
@pytest.mark.parametrize("which", ["H_model", "H_data"])
def test_nan_is_refused_not_reported(func, which):
    # frf_errors with a NaN returned max_rel = rms_rel = nan
    good, bad = np.array([1.0, 2.0, 3.0]), np.array([1.0, np.nan, 3.0])
    args = (bad, good) if which == "H_model" else (good, bad)
    with pytest.raises(FrequencyDataError, match=rf"{which} contains NaN .*\[0, 0, 1\]"):
        func(*args)


def test_an_infinite_model_response_is_an_infinite_error_and_infinite_data_are_refused():
    H = np.array([1.0, 2.0, 3.0])
    e = frf_errors(np.array([1.0, np.inf, 3.0]), H)   # a pole on the sampled axis: honestly infinite
    assert e.max_rel == np.inf and e.rms_rel == np.inf
    with pytest.raises(FrequencyDataError, match="H_data contains inf"):
        frf_errors(H, np.array([1.0, np.inf, 3.0]))


@pytest.mark.parametrize("scale", [1e-300, 1e-200, 1e200, 1e300])
def test_errors_do_not_depend_on_the_data_scale(scale):
    # at 1e200 the squares overflowed (rms nan), at 1e-200 they underflowed (rms 0.0 of a 1e-3 error)
    H = np.zeros((2, 1, 4), dtype=complex)
    H[0, 0] = [2.0, 1.0, 1.0j, 0.0]
    H[1, 0] = [10.0, 10.0, 10.0, 10.0]
    Hm = H.copy()
    Hm[0, 0, 3] = 0.5
    Hm[1, 0, 0] = 11.0
    ref = frf_errors(Hm, H)
    got = frf_errors(Hm * scale, H * scale)
    assert np.isfinite([got.max_rel, got.rms_rel]).all()
    np.testing.assert_allclose([got.max_rel, got.rms_rel], [ref.max_rel, ref.rms_rel], rtol=1e-13)
    np.testing.assert_allclose(got.rms_rel_per_output, ref.rms_rel_per_output, rtol=1e-13)
    np.testing.assert_allclose(got.max_rel_per_output, ref.max_rel_per_output, rtol=1e-13)


def test_dc_error_refuses_nan():
    with pytest.raises(FrequencyDataError, match="dc_model contains NaN"):
        dc_error(np.array([[np.nan]]), np.array([[1.0]]))


@pytest.mark.parametrize("A, match", [(np.ones((2, 3)), r"square \(n, n\) matrix, got shape \(2, 3\)"),
                                      (np.array([[np.nan]]), "contains NaN or inf")])
def test_spectral_radius_refuses_what_has_none(A, match):
    # numpy's LinAlgError before
    import sysid

    with pytest.raises(sysid.ModelError, match=match):
        spectral_radius(A)


@pytest.mark.parametrize("kwargs, error, match", [
    (dict(fit_index=[0, 99]), "FrequencyIndexError", r"fit_index must hold whole numbers in 0 \.\. 8"),
    (dict(fit_index=[0.5]), "FrequencyIndexError", "whole numbers"),
    (dict(outputs=["Cl", "Cm"]), "FrequencyDataError", "2 output names for H of shape"),
])
def test_rom_metrics_refuses_indices_and_names_that_do_not_fit(kwargs, error, match):
    # IndexError from numpy before
    import sysid
    from sysid.metrics import rom_metrics

    H = np.ones((1, 1, 9), complex)
    args = dict(frf_rom=H, H=H, fit_index=[0, 4, 8], outputs=["Cl"], dc_model=[[1.0]], spectral_radius=0.5,
                seconds=1.0)
    args.update(kwargs)
    with pytest.raises(getattr(sysid, error), match=match):
        rom_metrics(**args)
