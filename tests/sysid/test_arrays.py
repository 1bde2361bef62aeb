"""The arrays of sysid's frozen results are read-only: a reader cannot change a result in place."""

import dataclasses

import numpy as np
import pytest
from sysid_synth import freqresp, random_system

import sysid
from sysid import FrequencyResponse, identify, mckelvey_grid
from sysid.arrays import read_only


def _data(p, m, seed=3):
    A, B, C, D, _ = random_system(4, p, m, seed, rho=0.9)
    wd, _ = mckelvey_grid(48, 1.0)
    return FrequencyResponse(freqresp(A, B, C, D, np.exp(1j * wd)), wd, 1.0)


def _array_fields(obj, seen=None):
    """``(path, array)`` of every ndarray reachable through the dataclass fields of ``obj``."""
    seen = set() if seen is None else seen
    if id(obj) in seen or not dataclasses.is_dataclass(obj):
        return []
    seen.add(id(obj))
    found = []
    for f in dataclasses.fields(obj):
        value = getattr(obj, f.name)
        if isinstance(value, np.ndarray):
            found.append((f"{type(obj).__name__}.{f.name}", value))
        else:
            found += _array_fields(value, seen)
    return found


@pytest.mark.parametrize("kwargs, p, m", [
    (dict(), 2, 2),                                                    # subspace + B/D refit
    (dict(dc_gain="match", stable=True, algorithm="subspace"), 2, 2),  # stabilisation report, refits
    (dict(dc_gain="match", stable=True), 2, 1),                        # relocation path
])
def test_identification_results_are_read_only(kwargs, p, m):
    res = identify(_data(p, m), 4, **kwargs)
    arrays = _array_fields(res)
    names = {name for name, _ in arrays}
    assert {"IdentificationResult.hankel_sv", "FitErrors.max_rel_per_output", "SubspaceResult.A"} <= names
    for name, a in arrays:
        assert not a.flags.writeable, name
    with pytest.raises(ValueError, match="read-only"):
        res.hankel_sv[0] = 0.0


def test_order_sweep_stabilise_and_diagnostics_are_read_only():
    frf = _data(2, 1)
    for result in (sysid.order_sweep(frf, 4), sysid.diagnose(frf),
                   sysid.stabilise(np.diag([1.2, 0.5]), margin=1e-3, method="reflect")):
        arrays = _array_fields(result)
        assert arrays, type(result).__name__
        assert all(not a.flags.writeable for _, a in arrays), [n for n, a in arrays if a.flags.writeable]


def test_read_only_copies_and_leaves_the_callers_array_alone():
    a = np.arange(3.0)
    b = read_only(a)
    assert not b.flags.writeable and a.flags.writeable and b is not a and read_only(None) is None
    a[0] = 7.0
    assert b[0] == 0.0
