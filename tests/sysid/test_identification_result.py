"""sysid.identification_result: the result's evaluation at frequencies a user gives."""

import warnings

import numpy as np
import pytest

import sysid
from sysid import FrequencyGridError


@pytest.fixture(scope="module")
def result():
    # G(z) = 1 / (z - 0.5), identified exactly at order 1
    wd, _ = sysid.mckelvey_grid(32, 1.0)
    frf = sysid.FrequencyResponse((1.0 / (np.exp(1j * wd) - 0.5)).reshape(1, 1, -1), wd, 1.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return sysid.identify(frf, 1)


def test_evaluation_at_given_frequencies(result):
    wd = np.array([0.0, 0.3, np.pi])
    np.testing.assert_allclose(result.evaluate(wd)[0, 0], 1.0 / (np.exp(1j * wd) - 0.5), rtol=1e-10)
    np.testing.assert_allclose(result.frequency_response(wd).H, result.evaluate(wd), rtol=0)
    # omega = inf is omega_d = pi; a negative omega gives the conjugate (a real system)
    np.testing.assert_allclose(result.evaluate_continuous([np.inf, -2.0, 2.0])[0, 0],
                               [-1.0 / 1.5, np.conj(result.evaluate_continuous([2.0])[0, 0, 0]),
                                result.evaluate_continuous([2.0])[0, 0, 0]], rtol=1e-12)


@pytest.mark.parametrize("method", ["evaluate", "evaluate_continuous", "frequency_response"])
@pytest.mark.parametrize("freq, match", [
    ("x", "must be real frequencies"),       # a bare ValueError from NumPy before
    (1 + 1j, "must be real frequencies"),    # a bare TypeError before
    (np.array([0.1, 0.2 + 1j]), "must be real frequencies"),   # imaginary part dropped with a ComplexWarning
    (np.nan, r"omega(_d)?\[0\] = nan"),     # a NaN response before
    ([0.1, np.nan], r"omega(_d)?\[1\] = nan"),
])
def test_frequencies_that_are_not_real_numbers_are_refused(result, method, freq, match):
    with pytest.raises(FrequencyGridError, match=match):
        getattr(result, method)(freq)


@pytest.mark.parametrize("method", ["evaluate", "frequency_response"])
def test_an_infinite_discrete_frequency_is_refused(result, method):
    with pytest.raises(FrequencyGridError, match=r"omega_d\[1\] is infinite"):
        getattr(result, method)([0.1, np.inf])
