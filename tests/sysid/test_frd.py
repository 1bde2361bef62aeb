"""Tests of sysid.frd: FrequencyResponse, the McKelvey grid and the bilinear frequency map."""


import numpy as np
import pytest

import sysid
from sysid import FrequencyDataError, FrequencyFileError, FrequencyGridError, FrequencyResponse, mckelvey_grid


def first_order(z, a=0.5):
    """G(z) = 1 / (z - a): DC gain 1/(1 - a), Nyquist value -1/(1 + a)."""
    return 1.0 / (z - a)


# ------------------------------------------------------------------------------------------- grid
@pytest.mark.parametrize("M", [1, 4, 32, 256])
@pytest.mark.parametrize("T", [0.5, 70 / (2 * np.pi)])
def test_mckelvey_grid_points_and_map(M, T):
    wd, w = mckelvey_grid(M, T)
    assert wd.shape == w.shape == (M + 1,)
    np.testing.assert_allclose(wd, np.pi * np.arange(M + 1) / M, rtol=0, atol=1e-15)
    assert wd[0] == 0.0 and wd[-1] == np.pi
    assert w[0] == 0.0
    assert w[-1] == np.inf  # exactly inf, not tan(pi/2) ~ 1.6e16
    np.testing.assert_allclose(w[:-1], 2.0 / T * np.tan(wd[:-1] / 2.0), rtol=1e-14)


def test_mckelvey_grid_known_values():
    wd, w = mckelvey_grid(4, 1.0)
    # omega = 2 tan(omega_d / 2): tan(pi/8) = sqrt(2) - 1, tan(pi/4) = 1, tan(3 pi / 8) = sqrt(2) + 1
    np.testing.assert_allclose(w[:4], [0.0, 2 * (np.sqrt(2) - 1), 2.0, 2 * (np.sqrt(2) + 1)], rtol=1e-14)


@pytest.mark.parametrize("M, T, exc, match", [
    (0, 1.0, FrequencyGridError, "positive integer"),
    (2.5, 1.0, FrequencyGridError, "positive integer"),
    (8, 0.0, FrequencyGridError, "T"),
    (8, -1.0, FrequencyGridError, "T"),
    (8, np.nan, FrequencyGridError, "T"),
    (8, np.inf, FrequencyGridError, "T"),
])
def test_mckelvey_grid_bad_input(M, T, exc, match):
    with pytest.raises(exc, match=match):
        mckelvey_grid(M, T)


def test_bilinear_maps_are_inverse():
    w = np.array([0.0, 0.1, 1.0, 10.0, 1e3, np.inf])
    wd = sysid.continuous_to_discrete(w, 0.7)
    assert wd[-1] == np.pi
    back = sysid.discrete_to_continuous(wd, 0.7)
    np.testing.assert_allclose(back[:-1], w[:-1], rtol=1e-12)
    assert back[-1] == np.inf


@pytest.mark.parametrize("call, match", [
    # beyond pi the tangent wraps: 4.0 rad/sample used to map to omega = -4.37 without a word
    (lambda: sysid.discrete_to_continuous([0.5, 4.0], 0.7), r"omega_d\[1\] = 4.0; .*\[0, pi\]"),
    (lambda: sysid.discrete_to_continuous([np.nan], 0.7), r"omega_d\[0\] = nan"),
    (lambda: sysid.continuous_to_discrete([1.0, -1.0], 0.7), r"omega\[1\] = -1.0; .*must be >= 0"),
    (lambda: sysid.continuous_to_discrete([1.0], 0.0), r"sampling period T must be positive"),
])
def test_bilinear_maps_refuse_frequencies_outside_their_domain(call, match):
    with pytest.raises(FrequencyGridError, match=match):
        call()


# ------------------------------------------------------------------------------------ construction
def test_shapes_and_defaults():
    wd, _ = mckelvey_grid(8, 1.0)
    H = first_order(np.exp(1j * wd))
    frf = FrequencyResponse(H, wd, 1.0)  # SISO 1-D convenience
    assert frf.H.shape == (1, 1, 9) and frf.shape == (1, 1, 9)
    assert frf.inputs == ("u[0]",) and frf.outputs == ("y[0]",)
    assert frf.is_equispaced and frf.M == 8
    two = FrequencyResponse(np.vstack([H, 2 * H]), wd, 1.0, outputs=["Cl", "Cm"], inputs=["gust"])
    assert two.H.shape == (2, 1, 9)  # (p, K) is single-input
    assert two.outputs == ("Cl", "Cm") and two.inputs == ("gust",)


def test_immutable():
    wd, _ = mckelvey_grid(4, 1.0)
    frf = FrequencyResponse(np.ones(5), wd, 1.0, metadata={"a": 1})
    with pytest.raises(AttributeError, match="immutable"):
        frf.T = 2.0
    with pytest.raises(ValueError, match="read-only"):
        frf.H[0, 0, 0] = 3.0
    with pytest.raises(ValueError, match="read-only"):
        frf.omega_d[0] = 3.0
    with pytest.raises(TypeError, match="does not support item assignment"):
        frf.metadata["a"] = 2


def test_constructor_copies_input():
    wd, _ = mckelvey_grid(4, 1.0)
    H = np.ones((1, 1, 5), dtype=complex)
    frf = FrequencyResponse(H, wd, 1.0)
    H[0, 0, 0] = 7.0
    assert frf.H[0, 0, 0] == 1.0


_WD5 = np.pi * np.arange(5) / 4


@pytest.mark.parametrize("kwargs, exc, match", [
    (dict(H=np.array([1, np.nan, 1, 1, 1])), FrequencyDataError, "NaN"),
    (dict(H=np.array([1, 1, np.inf, 1, 1])), FrequencyDataError, r"H\[0, 0, 2\]"),
    (dict(H=np.ones((1, 1, 1, 5))), FrequencyDataError, r"\(p, m, K\)"),
    (dict(H=np.ones(4)), FrequencyDataError, "omega_d has 5 frequencies but H has K=4"),
    (dict(omega_d=_WD5 * 1.1), FrequencyGridError, r"\[0, pi\]"),
    (dict(omega_d=_WD5 - 0.1), FrequencyGridError, r"\[0, pi\]"),
    (dict(T=0.0), FrequencyGridError, "T"),
    (dict(T=-2.0), FrequencyGridError, "T"),
    (dict(T=np.nan), FrequencyGridError, "T"),
    (dict(T=np.inf), FrequencyGridError, "T"),
    (dict(inputs=["a", "b"]), FrequencyDataError, "inputs"),
    (dict(outputs=["Cl", "Cm"]), FrequencyDataError, "outputs"),
    (dict(omega_d=None), FrequencyGridError, "give the frequencies"),
    (dict(omega_d=_WD5 + 1j), FrequencyGridError, "must be real frequencies"),   # cast to real with a warning before
    (dict(metadata=[1]), FrequencyDataError, "metadata must be a mapping"),       # a bare TypeError before
    (dict(metadata={"f": (x for x in [])}), FrequencyDataError, "metadata must hold plain data"),   # TypeError before
])
def test_bad_input_raises(kwargs, exc, match):
    args = dict(H=np.ones(5), omega_d=_WD5, T=1.0)
    args.update(kwargs)
    with pytest.raises(exc, match=match):
        FrequencyResponse(args.pop("H"), args.pop("omega_d"), args.pop("T"), **args)


def test_typed_errors_are_value_errors():
    with pytest.raises(FrequencyGridError, match="sampling period T must be positive and finite"):
        FrequencyResponse(np.ones(5), _WD5, -1.0)


@pytest.mark.parametrize("T", [True, "eleven", None, [1.0]])
def test_a_period_that_is_not_a_number_is_refused(T):
    # True would read as T = 1 (float(True)); the study files and `lfdrom fit --T` refuse it too
    with pytest.raises(FrequencyGridError, match="sampling period T must be a positive finite number"):
        mckelvey_grid(8, T)


def test_from_continuous_maps_frequencies():
    w = np.array([0.0, 0.5, 2.0, np.inf])
    H = np.array([1.0, 0.5 - 0.2j, 0.1j, 0.0])
    frf = FrequencyResponse.from_continuous(H, w, T=2.0)
    np.testing.assert_allclose(frf.omega_d, [0.0, 2 * np.arctan(0.5), 2 * np.arctan(2.0), np.pi], rtol=1e-15)
    assert frf.omega[-1] == np.inf and frf.T == 2.0
    bare = FrequencyResponse.from_continuous(H, w)
    assert bare.omega_d is None and bare.T is None
    np.testing.assert_array_equal(bare.with_T(2.0).omega_d, frf.omega_d)


def test_from_continuous_negative_frequency():
    with pytest.raises(FrequencyGridError, match="nonnegative"):
        FrequencyResponse.from_continuous(np.ones(3), [-1.0, 0.0, 1.0], T=1.0)


def test_discrete_grid_without_T_has_no_continuous_frequencies():
    frf = FrequencyResponse(np.ones(5), _WD5, None)
    assert frf.omega is None and frf.T is None and frf.is_equispaced


# -------------------------------------------------------------------------------- special values
def test_dc_gain_and_feedthrough_of_known_system():
    wd, _ = mckelvey_grid(16, 1.0)
    frf = FrequencyResponse(first_order(np.exp(1j * wd), a=0.5), wd, 1.0)
    np.testing.assert_allclose(frf.dc_gain, [[2.0]], rtol=1e-14)  # 1 / (1 - 0.5)
    np.testing.assert_allclose(frf.feedthrough, [[-2.0 / 3.0]], rtol=1e-14)  # 1 / (-1 - 0.5)
    inner = frf.take(np.arange(1, 16))
    assert inner.dc_gain is None and inner.feedthrough is None


def test_dc_gain_from_continuous_without_T():
    frf = FrequencyResponse.from_continuous([[[3.0, 1.0j, 0.0]]], [0.0, 1.0, np.inf])
    np.testing.assert_allclose(frf.dc_gain, [[3.0]])
    np.testing.assert_allclose(frf.feedthrough, [[0.0]])


def test_complex_dc_sample_warns():
    frf = FrequencyResponse([1.0 + 0.5j, 1.0, 0.0], np.pi * np.arange(3) / 2, 1.0)
    with pytest.warns(RuntimeWarning, match="imaginary"):
        dc = frf.dc_gain
    np.testing.assert_allclose(dc, [[1.0]])


# -------------------------------------------------------------------------------------- subsample
@pytest.mark.parametrize("M_new", [128, 64, 32, 1])
def test_subsample(M_new):
    wd, _ = mckelvey_grid(256, 2.0)
    H = first_order(np.exp(1j * wd), a=-0.3)
    frf = FrequencyResponse(H, wd, 2.0, metadata={"case": "x"})
    sub = frf.subsample(M_new)
    wd_new, w_new = mckelvey_grid(M_new, 2.0)
    assert sub.M == M_new and sub.is_equispaced
    np.testing.assert_allclose(sub.omega_d, wd_new, atol=1e-15)
    np.testing.assert_allclose(sub.omega[:-1], w_new[:-1], rtol=1e-13)
    np.testing.assert_allclose(sub.H[0, 0], first_order(np.exp(1j * wd_new), a=-0.3), rtol=1e-13)
    assert sub.metadata["case"] == "x" and sub.T == 2.0


@pytest.mark.parametrize("M_new", [3, 0, 512, 100])
def test_subsample_not_a_divisor(M_new):
    wd, _ = mckelvey_grid(256, 2.0)
    frf = FrequencyResponse(np.ones(257), wd, 2.0)
    with pytest.raises(FrequencyGridError, match="divisor"):
        frf.subsample(M_new)


def test_subsample_non_equispaced():
    frf = FrequencyResponse(np.ones(4), [0.0, 0.1, 0.5, np.pi], 1.0)
    assert not frf.is_equispaced and frf.M is None
    with pytest.raises(FrequencyGridError, match="equispaced"):
        frf.subsample(1)


# ----------------------------------------------------------------------------------- persistence
def test_save_load_round_trip(tmp_path):
    rng = np.random.default_rng(0)
    wd, _ = mckelvey_grid(8, 0.3)
    H = rng.standard_normal((2, 3, 9)) + 1j * rng.standard_normal((2, 3, 9))
    meta = {"case": "NACA2410", "mach": 0.735, "grid": [181, 60], "nested": {"k": True}}
    frf = FrequencyResponse(H, wd, 0.3, inputs=["a", "b", "c"], outputs=["Cl", "Cm"], metadata=meta)
    path = frf.save(tmp_path / "resp")
    assert path.suffix == ".npz"
    back = FrequencyResponse.load(path)
    assert back == frf
    assert back.outputs == ("Cl", "Cm") and dict(back.metadata) == meta
    assert back.omega[-1] == np.inf


def test_save_load_continuous_only(tmp_path):
    frf = FrequencyResponse.from_continuous([1.0, 0.5j], [0.0, 3.0], metadata={"x": 1})
    back = FrequencyResponse.load(frf.save(tmp_path / "c.npz"))
    assert back == frf and back.omega_d is None


@pytest.mark.parametrize("entries, what", [
    (dict(header='{"inputs": ["u"], "outputs": ["y"], "T": 1.0}'), "no 'metadata' entry"),
    (dict(header="not json", metadata="{}"), "'header' or 'metadata' is not what FrequencyResponse.save writes"),
    (dict(header='{"T": 1.0}', metadata="{}"), "'header' or 'metadata' is not what FrequencyResponse.save writes"),
    (dict(header='{"inputs": ["u"], "outputs": ["y"]}', metadata="[1]"), "'header' or 'metadata' is not"),
])
def test_load_of_an_incomplete_file(tmp_path, entries, what):
    wd, _ = mckelvey_grid(8, 1.0)
    np.savez(tmp_path / "f.npz", H=np.ones((1, 1, 9), complex), omega_d=wd,
             **{k: np.array(v) for k, v in entries.items()})
    with pytest.raises(FrequencyDataError, match=f"f.npz: {what}"):
        FrequencyResponse.load(tmp_path / "f.npz")


def test_pickle_and_copy():
    import copy
    import pickle

    wd, _ = mckelvey_grid(8, 0.3)
    frf = FrequencyResponse(np.arange(9) * (1 + 1j), wd, 0.3, outputs=["Cl"], metadata={"a": [1, 2]})
    for back in (pickle.loads(pickle.dumps(frf)), copy.copy(frf), copy.deepcopy(frf)):
        assert back == frf and not back.H.flags.writeable


def test_save_rejects_non_json_metadata(tmp_path):
    frf = FrequencyResponse(np.ones(5), _WD5, 1.0, metadata={"a": object()})
    with pytest.raises(FrequencyDataError, match="JSON"):
        frf.save(tmp_path / "bad.npz")


# -------------------------------------------------------------------------------- python-control
def test_control_round_trip_drops_and_restores_infinity():
    import control

    sysc = control.ss([[-1.0, 2.0], [-2.0, -0.5]], [[1.0], [0.5]], [[1.0, 0.0], [0.3, 1.0]], [[0.0], [0.0]])
    T = 0.8
    wd, w = mckelvey_grid(16, T)
    H = np.stack([sysc(1j * x) for x in w[:-1]], axis=-1)  # (p, m, K-1)
    H = np.concatenate([H, np.zeros((2, 1, 1))], axis=2)  # feedthrough 0 at omega = inf
    frf = FrequencyResponse(H, wd, T, inputs=["gust"], outputs=["Cl", "Cm"])
    fr = frf.to_control()
    assert isinstance(fr, control.FrequencyResponseData)
    assert np.all(np.isfinite(fr.omega)) and len(fr.omega) == 16
    assert list(fr.output_labels) == ["Cl", "Cm"] and list(fr.input_labels) == ["gust"]
    # the FRD interpolates the true continuous response at its own points
    np.testing.assert_allclose(fr(1j * w[3]), sysc(1j * w[3]), rtol=1e-12)
    back = FrequencyResponse.from_control(fr, T, feedthrough=frf.feedthrough)
    np.testing.assert_allclose(back.H, frf.H, rtol=1e-14)
    np.testing.assert_allclose(back.omega_d, frf.omega_d, rtol=1e-14)
    assert back.omega[-1] == np.inf and back.outputs == frf.outputs
    no_inf = FrequencyResponse.from_control(fr, T)
    assert no_inf.nfreq == 16 and no_inf.feedthrough is None


def test_to_control_needs_continuous_frequencies():
    with pytest.raises(FrequencyGridError, match="T"):
        FrequencyResponse(np.ones(5), _WD5, None).to_control()


def test_from_model_discrete_and_continuous():
    import control

    # discrete G(z) = 1/(z - 0.5): dc 2, Nyquist -2/3
    wd, _ = mckelvey_grid(8, 0.5)
    frd = FrequencyResponse.from_model(control.ss([[0.5]], [[1.0]], [[1.0]], [[0.0]], 0.5), wd)
    assert frd.T == 0.5
    np.testing.assert_allclose(frd.H[0, 0], first_order(np.exp(1j * wd)), rtol=1e-14)
    # continuous G(s) = 1/(s + 1) + 0.25: omega = inf sample is D = 0.25
    sysc = control.ss([[-1.0]], [[1.0]], [[1.0]], [[0.25]], inputs=["gust"], outputs=["Cl"])
    frc = FrequencyResponse.from_model(sysc, wd, T=0.5)
    w = frc.omega
    np.testing.assert_allclose(frc.H[0, 0, :-1], 1.0 / (1j * w[:-1] + 1.0) + 0.25, rtol=1e-14)
    assert frc.H[0, 0, -1] == 0.25 and frc.outputs == ("Cl",)
    # equal to the samples of the Tustin discretisation (paper Eq. 28)
    frt = FrequencyResponse.from_model(sysid.c2d_bilinear(sysc, 0.5), wd)
    np.testing.assert_allclose(frt.H, frc.H, rtol=1e-12, atol=1e-14)
    with pytest.raises(FrequencyGridError, match="needs T"):
        FrequencyResponse.from_model(sysc, wd)


def test_from_model_refuses_a_period_other_than_the_discrete_models():
    import control

    # the samples at omega_d are the model's whatever T says; another T would only relabel their omega
    wd, _ = mckelvey_grid(8, 1.0)
    model = control.ss([[0.5]], [[1.0]], [[1.0]], [[0.0]], 1.0)
    assert FrequencyResponse.from_model(model, wd, 1.0).T == 1.0
    with pytest.raises(FrequencyGridError, match="contradicts the discrete model's own sampling period dt = 1.0"):
        FrequencyResponse.from_model(model, wd, 2.0)


def test_from_model_with_a_pole_on_the_sampled_axis_names_the_frequency():
    import control

    # G(z) = 1 / (z - 1): a pole at z = 1, i.e. omega_d = 0, the first sample of the grid
    wd, _ = mckelvey_grid(8, 0.5)
    with pytest.raises(FrequencyDataError, match="pole on the sampled axis at omega_d = 0 "):
        FrequencyResponse.from_model(control.ss([[1.0]], [[1.0]], [[1.0]], [[0.0]], 0.5), wd)


# ---------------------------------------------------------------------- input checks (issue 34 findings)
def test_mckelvey_grid_refuses_a_grid_too_large_to_fit():
    # 10**8 intervals allocated 1.6 GB and 10**9 did not return; the limit says why and what to do
    from sysid.grids import MAX_GRID_M

    wd, _ = mckelvey_grid(MAX_GRID_M, 1.0)
    assert wd.size == MAX_GRID_M + 1
    with pytest.raises(FrequencyGridError, match=r"M = 100000000 .* at most M = 65536"):
        mckelvey_grid(10**8, 1.0)


@pytest.mark.parametrize("indices, match", [([99], r"index 99 .* 0 \.\. 8"), ([-10], r"index -10"),
                                            ([1.5], "whole numbers"), (["a"], "whole numbers"),
                                            ([[0, 1], [2, 3]], "1-D")])
def test_take_refuses_indices_it_cannot_use(indices, match):
    wd, _ = mckelvey_grid(8, 1.0)
    frf = FrequencyResponse(first_order(np.exp(1j * wd)), wd, 1.0)
    with pytest.raises(sysid.FrequencyIndexError, match=match) as info:
        frf.take(indices)
    assert isinstance(info.value, (IndexError, ValueError))   # still caught as the built-ins


def test_take_of_a_boolean_mask_keeps_the_true_samples():
    # np.asarray([True, False, ...], dtype=int) read a mask as the indices 1 and 0
    wd, _ = mckelvey_grid(8, 1.0)
    frf = FrequencyResponse(first_order(np.exp(1j * wd)), wd, 1.0)
    mask = wd > np.pi / 2
    np.testing.assert_array_equal(frf.take(mask).omega_d, wd[mask])
    with pytest.raises(sysid.FrequencyIndexError, match="mask of 3 values but the data have 9"):
        frf.take([True, False, True])


def test_load_of_a_file_that_is_not_an_npz_says_so(tmp_path):
    # numpy's message was "This file contains pickled (object) data ... allow_pickle"
    bad = tmp_path / "notes.npz"
    bad.write_text("hello")
    with pytest.raises(sysid.FrequencyFileError, match="not an .npz file written by FrequencyResponse.save"):
        FrequencyResponse.load(bad)
    np.save(tmp_path / "array.npy", np.ones(3))
    with pytest.raises(sysid.FrequencyFileError, match="not an .npz file written by FrequencyResponse.save"):
        FrequencyResponse.load(tmp_path / "array.npy")


@pytest.mark.parametrize("name", ["folder", "folder.npz"])
def test_save_to_a_directory_is_refused(tmp_path, name):
    # "folder" wrote folder.npz beside the directory; "folder.npz" raised a bare IsADirectoryError
    wd, _ = mckelvey_grid(8, 1.0)
    frf = FrequencyResponse(first_order(np.exp(1j * wd)), wd, 1.0)
    (tmp_path / name).mkdir()
    with pytest.raises(sysid.FrequencyFileError, match="is a directory; give a file name"):
        frf.save(tmp_path / name)
    assert sorted(p.name for p in tmp_path.iterdir()) == [name]


# ------------------------------------------------------------ the period against the data's frequencies
def test_period_range_is_the_studies_rule():
    # studies accept T with the grid's centre frequency 2/T inside the aerofoil's band omega = 0.01 .. 100:
    # the same rule with factor 1 gives their range
    from studies.config.schema import T_RANGE

    from sysid.grids import period_range

    np.testing.assert_allclose(period_range([0.01, 100.0], factor=1.0), T_RANGE, rtol=1e-12)


@pytest.mark.parametrize("T, factor", [(2.0 / 3.0, 1.0), (2.0 / 100.0, 10.0), (2.0 / 1e-3, 1e3), (1e-300, 2e299)])
def test_period_factor_is_how_far_the_centre_frequency_lies_outside_the_data(T, factor):
    from sysid.grids import period_factor

    omega = np.array([0.0, 1.0, 3.0, 10.0, np.inf])   # the centre 2/T against [1, 10]
    assert period_factor(T, omega) == pytest.approx(factor, rel=1e-12)


def test_check_period_resolves_refuses_warns_and_passes():
    from sysid.grids import PERIOD_MAX_FACTOR, PERIOD_WARN_FACTOR, check_period_resolves

    omega = np.array([0.0, 1.0, 10.0, np.inf])
    with pytest.raises(FrequencyGridError, match=r"T = 1e-300 .* 2/T = 2e\+300 .* 0.002 <= T <= 200"):
        check_period_resolves(1e-300, omega)
    with pytest.raises(FrequencyGridError, match="T = 1e\\+10"):
        check_period_resolves(1e10, omega)
    with pytest.warns(RuntimeWarning, match="crowd near omega_d = 0"):
        check_period_resolves(2.0 / (10 * 2 * PERIOD_WARN_FACTOR), omega)
    assert check_period_resolves(2.0 / 10 / PERIOD_WARN_FACTOR, omega) == pytest.approx(PERIOD_WARN_FACTOR)
    assert PERIOD_WARN_FACTOR < PERIOD_MAX_FACTOR
    assert check_period_resolves(1e-300, np.array([0.0, np.inf])) == 1.0   # nothing in between to resolve


def test_from_model_and_from_control_refuse_what_they_do_not_convert():
    # AttributeError ('numpy.ndarray' object has no attribute 'A' / 'fresp') before
    wd, _ = mckelvey_grid(8, 1.0)
    with pytest.raises(TypeError, match=r"from_model\(\) expects a control.StateSpace, got ndarray"):
        FrequencyResponse.from_model(np.eye(2), wd, 1.0)
    with pytest.raises(TypeError, match=r"from_control\(\) expects a control.FrequencyResponseData, got ndarray"):
        FrequencyResponse.from_control(np.eye(2))


def test_channel_names_must_be_distinct():
    # outputs ['a', 'a'] were accepted: per-output results keyed by name overwrote each other
    with pytest.raises(FrequencyDataError, match="outputs names must be distinct .* 'a' more than once"):
        FrequencyResponse(np.ones((2, 1, 3)), [0.0, 1.0, 2.0], 1.0, outputs=["a", "a"])


def test_file_errors_are_typed(tmp_path):
    frf = FrequencyResponse(np.ones(5), _WD5, 1.0)
    with pytest.raises(FrequencyFileError, match="cannot write .*folder that exists"):
        frf.save(tmp_path / "no" / "such" / "folder" / "frf.npz")
    with pytest.raises(FrequencyFileError, match="does not exist"):
        FrequencyResponse.load(tmp_path / "missing.npz")
    with pytest.raises(FrequencyFileError, match="is a directory"):
        FrequencyResponse.load(tmp_path)
    with pytest.raises(FrequencyGridError, match="omega_d must be an array of real frequencies"):
        sysid.discrete_to_continuous("x", 1.0)
