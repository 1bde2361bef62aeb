"""Argument checks of sysid.order_limits (the limits themselves are tested against identify in
tests/studies/config/test_config.py)."""

import numpy as np
import pytest

import sysid
from sysid.order_limits import max_order, min_order, order_supported


@pytest.mark.parametrize("call, error, match", [
    (lambda: max_order(10.5), sysid.FrequencyGridError, r"M \(number of grid intervals\) must be a positive integer"),
    (lambda: max_order(-3), sysid.FrequencyGridError, "got -3"),
    (lambda: max_order(True), sysid.FrequencyGridError, "got True"),
    (lambda: max_order(32, "nonsense"), ValueError, "algorithm must be one of"),
    (lambda: max_order(32, p=0), ValueError, r"p \(outputs\) must be a positive integer"),
    (lambda: max_order(32, order=2.5), sysid.OrderError, "order must be a positive integer"),
    (lambda: order_supported(0, 32, "auto", 2), sysid.OrderError, "order must be a positive integer"),
    (lambda: min_order(0), ValueError, r"p \(outputs\) must be a positive integer"),
    (lambda: min_order(2, 1.5), ValueError, r"m \(inputs\) must be a positive integer"),
    (lambda: min_order(2, dc_gain="yes"), ValueError, "dc_gain must be 'none' or 'match'"),
    (lambda: min_order(2, algorithm="auto"), ValueError, "algorithm must be 'subspace' or 'relocation'"),
])
def test_bad_arguments(call, error, match):
    with pytest.raises(error, match=match):
        call()


@pytest.mark.parametrize("algorithm", ["auto", "subspace", "relocation", "mckelvey1"])
def test_algorithms_of_a_study_file_use_algorithm_1_bounds(algorithm):
    assert max_order(np.int64(32), algorithm, p=np.int64(2)) == max_order(32, "mckelvey1", 2) == 31
    assert min_order(2, 1, "match", "subspace") == 2 and min_order(2, 1, "none", "relocation") == 1
