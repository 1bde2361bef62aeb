"""cfd.checks: the shared argument checks."""

import math

import numpy as np
import pytest

from cfd.checks import log_interval, real_number, whole_number
from cfd.errors import FlowConditionError


@pytest.mark.parametrize("value, expected", [
    (1, 1.0), (2.5, 2.5), (np.float32(0.5), 0.5), (np.int64(3), 3.0), (np.array(0.25), 0.25), (-math.inf, -math.inf),
])
def test_real_number_takes_real_numbers(value, expected):
    v = real_number(value)
    assert type(v) is float and v == expected


def test_real_number_keeps_nan_for_the_caller():
    assert math.isnan(real_number(np.nan))


@pytest.mark.parametrize("value", [True, np.bool_(False), "0.5", b"1", None, 1 + 0j, np.complex128(1.0), [1.0], object()])
def test_real_number_refuses_what_is_not_a_real_number(value):
    # a numpy complex was cast to its real part by float() with only a ComplexWarning; "0.5" was parsed
    assert real_number(value) is None


@pytest.mark.parametrize("value, expected", [(3, 3), (3.0, 3), (np.int64(4), 4), (2.5, None), (True, None),
                                             ("3", None), (None, None), (math.inf, None), (np.complex128(3), None)])
def test_whole_number(value, expected):
    assert whole_number(value) == expected


@pytest.mark.parametrize("value", [-1.0, "60", True, None, np.nan, 1j])
def test_log_interval_refuses(value):
    with pytest.raises(FlowConditionError, match=r"log_interval must be a number of seconds >= 0"):
        log_interval(value, FlowConditionError)


def test_log_interval_takes_seconds():
    assert log_interval(0, FlowConditionError) == 0.0 and log_interval(math.inf, FlowConditionError) == math.inf
