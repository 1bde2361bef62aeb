"""Conserved and primitive variables (cfd.flow)."""

import numpy as np
import pytest

from cfd import MeshError
from cfd.flow import conserved, primitive


def test_primitive_inverts_conserved():
    rho, u, v, p = np.array([1.0, 0.5]), np.array([0.7, -0.2]), np.array([0.1, 0.3]), np.array([0.71, 0.4])
    for a, b in zip(primitive(conserved(rho, u, v, p)), (rho, u, v, p)):
        np.testing.assert_allclose(a, b, rtol=1e-14)


@pytest.mark.parametrize("shape", [(3, 5), (4, 3), (5,)])
def test_primitive_refuses_a_last_axis_other_than_four(shape):
    with pytest.raises(MeshError, match=rf"q has shape \({shape[0]},.*last axis of 4"):
        primitive(np.ones(shape))


# --- input checks (issue 34) ---------------------------------------------------------------------------------------

@pytest.mark.parametrize("gamma", [0.0, 1.0, 3.0, np.nan, "1.4", True])
@pytest.mark.parametrize("convert", [lambda g: primitive(np.ones(4), gamma=g),
                                     lambda g: conserved(1.0, 0.0, 0.0, 1.0, gamma=g)])
def test_gamma_out_of_range_is_refused(gamma, convert):
    # primitive(q, gamma=0) returned a pressure of -0 without a word
    from cfd import FlowConditionError

    with pytest.raises(FlowConditionError, match=r"gamma must be a real number in \(1, 3\)"):
        convert(gamma)


def test_primitive_arrays_that_do_not_broadcast_are_a_mesh_error():
    # was numpy's "shape mismatch" ValueError
    with pytest.raises(MeshError, match=r"rho, u, v and p must broadcast to one shape; got shapes \(3,\), \(4,\)"):
        conserved(np.ones(3), np.ones(4), 0.0, 1.0)


@pytest.mark.parametrize("name", ["mach", "alpha_deg", "gamma"])
@pytest.mark.parametrize("value", [True, "0.5"])     # alpha_deg=True was taken as 1 deg, mach="0.5" parsed
def test_a_flow_condition_is_not_made_of_booleans_or_strings(name, value):
    from cfd import FlowCondition, FlowConditionError

    args = dict(mach=0.5, alpha_deg=1.0, gamma=1.4)
    args[name] = value
    with pytest.raises(FlowConditionError, match=rf"{name} must be a real number; got {value!r}"):
        FlowCondition(**args)
