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
