"""gust_system: bad moment axes and non-finite models are refused up front, by every entry point."""

import numpy as np
import pytest

import control
import loads
import sysid

PT = loads.FlightPoint(0.5, 3000.0, 2.0)
NAN = float("nan")


def _model(**mats):
    m = dict(A=[[-1.0, 0.0], [0.0, -0.2]], B=[[1.0], [0.2]], C=[[1.0, 2.0], [0.1, -0.3]], D=[[0.0], [0.0]]) | mats
    return control.ss(m["A"], m["B"], m["C"], m["D"], inputs=["gust"], outputs=["Cl", "Cm"])


@pytest.mark.parametrize("kw, match", [
    (dict(moment_axes=[0.4], moment_reference=NAN), r"moment_reference must be a finite position.*got nan"),  # Cm@x nan
    (dict(moment_reference=NAN), r"moment_reference must be a finite"),
    (dict(moment_axes=[0.4], moment_reference="x"), r"moment_reference must be a position in chords.*got 'x'"),
    (dict(moment_axes=["a"]), r"moment_axes\[0\] must be a position in chords.*got 'a'"),        # bare ValueError
    (dict(moment_axes=[0.3, np.inf]), r"moment_axes\[1\] must be a finite position.*got inf"),
    (dict(moment_axes="0.4"), r"moment_axes must be a position in chords.*got '0.4'"),
    (dict(moment_axes=[[0.3, 0.4]]), r"moment_axes\[0\] must be a position in chords"),
    (dict(moment_axes=[True]), r"moment_axes\[0\] must be a position in chords"),
])
def test_bad_moment_axes_are_refused(kw, match):
    with pytest.raises(loads.LoadsModelError, match=match):
        loads.gust_system(_model(), PT, **kw)


@pytest.mark.parametrize("axes, names", [
    (0.4, ["Cm@0.400"]), (np.array([0.3, 0.4]), ["Cm@0.300", "Cm@0.400"]), ((), []), (np.float64(0.4), ["Cm@0.400"]),
])
def test_moment_axes_in_any_numeric_form(axes, names):
    gs = loads.gust_system(_model(), PT, moment_axes=axes, moment_reference=np.float64(0.25))
    assert list(gs.outputs) == ["Cl", "Cm"] + names


def test_data_path_checks_the_moment_axes_too():
    frf = sysid.FrequencyResponse.load("docs/data/frf-T4.npz")
    with pytest.raises(loads.LoadsModelError, match=r"moment_reference must be a position.*got 'x'"):
        loads.continuous_turbulence(frf, PT, moment_axes=[0.4], moment_reference="x")


@pytest.mark.parametrize("name, mats, dt", [
    ("C", dict(C=[[NAN, 2.0], [0.1, -0.3]]), 0),                 # tuned_gust gave {'Cl': nan}
    ("A", dict(A=[[-1.0, np.inf], [0.0, -0.2]]), 0),
    ("D", dict(D=[[0.0], [NAN]]), 0),
    ("C", dict(A=[[0.5, 0.0], [0.0, 0.2]], C=[[NAN, 2.0], [0.1, -0.3]]), 1.0),    # discrete: refused before d2c
])
def test_a_model_with_non_finite_matrices_is_refused(name, mats, dt):
    m = _model(**mats)
    if dt:
        m = control.ss(m.A, m.B, m.C, m.D, dt, inputs=["gust"], outputs=["Cl", "Cm"])
    match = rf"the model's {name} matrix has 1 non-finite entry"
    with pytest.raises(loads.LoadsModelError, match=match):
        loads.tuned_gust(m, PT)
    with pytest.raises(loads.LoadsModelError, match=match):      # blamed "a pole very near the imaginary axis"
        loads.continuous_turbulence(m, PT)


@pytest.mark.parametrize("omega, match", [
    ("a", r"omega must be real convective frequencies .*got 'a'"),                    # bare ValueError
    ([NAN], r"omega must be finite \(rad per c/U\), got 1 NaN or inf value\(s\) \(first nan\)"),   # NaN response
    ([0.3, np.inf, -np.inf], r"omega must be finite .*got 2 NaN or inf value\(s\) \(first inf\)"),
    (1 + 1j, r"omega must be real convective frequencies"),
    ([True], r"omega must be real convective frequencies"),
    (None, r"omega must be real convective frequencies"),
])
def test_frequency_response_refuses_bad_frequencies(omega, match):
    gs = loads.gust_system(_model(), PT)
    with pytest.raises(loads.LoadsModelError, match=match):
        gs.frequency_response(omega)


def test_frequency_response_of_numbers_in_any_form():
    m = _model()
    gs = loads.gust_system(m, PT)
    G = gs.frequency_response([-0.5, 0, 2])
    exact = np.array([np.asarray(m(1j * w)).ravel() for w in (-0.5, 0.0, 2.0)]).T
    assert np.allclose(G, exact, rtol=1e-12, atol=0) and np.allclose(G[:, 0], gs.frequency_response(0.5)[:, 0].conj())
    assert np.allclose(gs.frequency_response(np.int64(2)), G[:, 2:], rtol=1e-14) and gs.frequency_response([]).shape == (2, 0)


@pytest.mark.parametrize("axes", [[0.5, 0.5], [0.5, 0.5004], np.array([0.4, 0.3, 0.4])])
def test_moment_axes_sharing_a_name_are_refused(axes):
    # [0.5, 0.5] gave two outputs 'Cm@0.500'
    with pytest.raises(loads.LoadsModelError, match=r"moment_axes .* would give two outputs named 'Cm@0\.[45]00'.*give "
                                                     "each axis once"):
        loads.gust_system(_model(), PT, moment_axes=axes)
    frf = sysid.FrequencyResponse.load("docs/data/frf-T4.npz")
    with pytest.raises(loads.LoadsModelError, match=r"would give two outputs named 'Cm@0\.[45]00'"):
        loads.continuous_turbulence(frf, PT, moment_axes=axes)
