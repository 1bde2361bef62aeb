"""Pivot and moment-axis changes: Theodorsen's loads about one axis moved to another equal those computed there."""

import numpy as np
import pytest

import aeroelastic as ae
from aeroelastic import theodorsen as th

W = np.concatenate([[0.0], np.geomspace(0.01, 4.0, 30)])


@pytest.mark.parametrize("a1, a2", [(-0.5, -0.2), (-0.2, 0.4), (0.3, -1.0), (-2.0, 0.0)])
def test_moving_theodorsen_data_between_axes(a1, a2):
    src = th.theodorsen_frf(W, a1, gust=True)
    x1, x2 = (1 + a1) / 2, (1 + a2) / 2
    moved = ae.change_axes(src, pivot=x1, moment_axis=x1, new_axis=x2)
    ref = th.theodorsen_frf(W, a2, gust=True)
    # the same closed-form loads, so only round-off separates them (entries up to ~50 at omega = 4)
    np.testing.assert_allclose(moved.H, ref.H, rtol=1e-12, atol=1e-12)
    assert moved.metadata["axis"] == x2


def test_quarter_chord_moment_with_elastic_axis_pivot():
    # moment about the quarter chord, pitch about the elastic axis: only the outputs move
    sec = ae.TypicalSection(20, -0.2, 0.1, 0.24, 0.4)
    ref = th.theodorsen_frf(W, sec.a)
    H = np.array(ref.H)
    H[1] = H[1] - (sec.elastic_axis - 0.25) * H[0]
    qc = ref.replace(H=H)
    back = ae.to_elastic_axis(qc, sec, pivot=sec.elastic_axis, moment_axis=0.25)
    np.testing.assert_allclose(back.H, ref.H, rtol=1e-12, atol=1e-12)


def test_errors():
    with pytest.raises(ae.AeroModelError, match="expects a sysid.FrequencyResponse"):
        ae.change_axes(np.zeros((2, 2, 3)), pivot=0.25, moment_axis=0.25, new_axis=0.4)
    frf = th.theodorsen_frf(W, 0.0)
    with pytest.raises(ae.AeroModelError, match="pivot must be a position"):
        ae.change_axes(frf, pivot="le", moment_axis=0.25, new_axis=0.4)


@pytest.mark.parametrize("pivot, match", [
    (1e300, r"pivot = 1e\+300 chords is beyond MAX_AXIS = 10000"),   # gave responses of 8e300
    ("0.25", r"pivot must be a position in chords"),
    (True, r"pivot must be a position in chords"),
])
def test_axes_are_positions_near_the_aerofoil(pivot, match):
    with pytest.raises(ae.AeroModelError, match=match):
        ae.change_axes(th.theodorsen_frf(np.linspace(0.0, 2.0, 11), -0.2), pivot=pivot, moment_axis=0.25, new_axis=0.4)


@pytest.mark.parametrize("pivot, moment_axis, match", [
    (0.25, 0.25, r"about the axis 0\.4 .* but pivot = 0\.25 and moment_axis = 0\.25 were given"),  # flutter 1.735 for 2.184
    (0.4, 0.25, r"but moment_axis = 0\.25 were given; pass pivot=0\.4, moment_axis=0\.4"),
    (0.25, 0.4, r"but pivot = 0\.25 were given"),
])
def test_moving_moved_data_from_another_axis_is_refused(pivot, moment_axis, match):
    ea = ae.change_axes(th.theodorsen_frf(W, -0.5), pivot=0.25, moment_axis=0.25, new_axis=0.4)
    with pytest.raises(ae.AeroModelError, match=match):
        ae.change_axes(ea, pivot=pivot, moment_axis=moment_axis, new_axis=0.4)


def test_moved_data_move_on_from_their_stated_axis():
    src = th.theodorsen_frf(W, -0.5, gust=True)
    twice = ae.change_axes(ae.change_axes(src, pivot=0.25, moment_axis=0.25, new_axis=0.4),
                           pivot=0.4, moment_axis=0.4, new_axis=0.6)
    once = ae.change_axes(src, pivot=0.25, moment_axis=0.25, new_axis=0.6)
    np.testing.assert_allclose(twice.H, once.H, rtol=1e-12, atol=1e-12)
    assert twice.metadata["axis"] == 0.6


def test_a_stated_axis_that_is_not_a_number_is_refused():
    frf = th.theodorsen_frf(W, -0.5).replace(metadata={"axis": "quarter chord"})
    with pytest.raises(ae.AeroModelError, match=r"metadata\['axis'\] = 'quarter chord' is not a position"):
        ae.change_axes(frf, pivot=0.25, moment_axis=0.25, new_axis=0.4)
