"""Tests of sysid.history_metrics: envelope and RMS errors of time histories, and their input checks."""

import numpy as np
import pytest

import sysid
from sysid import envelope_errors, history_errors, peak


def test_known_values():
    t = np.arange(5.0)
    y_ref = np.array([0.0, 1.0, -2.0, 0.5, 0.0])   # largest magnitude -2 at t = 2
    y_mod = np.array([0.0, 1.5, -1.0, 0.0, 0.0])   # max 1.5 (ref 1), min -1 (ref -2)
    assert peak(t, y_ref) == (-2.0, 2.0)
    err, dt = envelope_errors(t, y_mod, y_ref)
    assert err == pytest.approx(max(0.5, 1.0) / 2.0) and dt == 0.0
    out = history_errors(t, {"Cl": y_mod}, {"Cl": y_ref})
    assert out["rms_err_Cl"] == pytest.approx(np.sqrt(np.mean((y_mod - y_ref) ** 2) / np.mean(y_ref**2)))


@pytest.mark.parametrize("call, match", [
    (lambda: peak([], []), "empty"),
    (lambda: peak([0, 1, 2], [1, np.nan, 3]), r"y contains NaN or inf at index 1"),         # (nan, 1.0) before
    (lambda: peak([0, 1], [1, 2, 3]), "y has 3 samples but t has 2 times"),              # IndexError before
    (lambda: envelope_errors([0, 1, 2], [1, 2, 3], [1, np.nan, 3]), "y_ref contains NaN"),  # (inf, 1.0) before
    (lambda: envelope_errors([0, 1, 2], [1, 2], [1, 2, 3]), "y_model has 2 samples"),     # compared silently before
    (lambda: history_errors([0, 1, 2], {"Cl": [1, 2, 3]}, {"Cl": [1, np.nan, 3]}), r"reference\['Cl'\] contains NaN"),
    (lambda: history_errors([0, 1, 2], {"Cl": [1, 2]}, {"Cl": [1, 2, 3]}), r"model\['Cl'\] has 2 samples"),
    # an output asked for but missing, or no output in common: {} before (a comparison of nothing)
    (lambda: history_errors([0, 1, 2], {"Cl": [1, 2, 3]}, {"Cl": [1, 2, 3]}, outputs=["X"]), r"outputs \['X'\] are not"),
    (lambda: history_errors([0, 1, 2], {"Cl": [1, 2, 3]}, {"Cm": [1, 2, 3]}), "have none in common"),
    (lambda: history_errors([0, 1, 2], {"Cl": [1, 2, 3]}, {"Cl": [1, 2, 3]}, outputs=[]), "outputs is empty"),
    (lambda: history_errors([0, 1, 2], [1, 2, 3], {"Cl": [1, 2, 3]}), "model must be a mapping"),  # IndexError before
    (lambda: history_errors([0, 1, 2], {"Cl": [1, 2, 3]}, np.ones(3)), "reference must be a mapping .* got ndarray"),
])
def test_bad_histories_are_refused(call, match):
    with pytest.raises(sysid.TimeDataError, match=match):
        call()


def test_an_overflowed_model_history_is_an_infinite_error():
    out = history_errors([0, 1, 2], {"Cl": [1.0, np.inf, np.nan]}, {"Cl": [1.0, 2.0, 3.0]})
    assert out == {"peak_err_Cl": np.inf, "t_peak_err_Cl": np.inf, "rms_err_Cl": np.inf}
