"""Analytic gust references against the tabulated values of docs/references.md section 3."""

import numpy as np
import pytest

from cfd.analytic import (
    AnalyticError,
    kussner,
    sears,
    sears_compressible,
    sears_hankel,
    step_response,
    theodorsen,
    wagner,
)

K_TAB = np.array([0.05, 0.1, 0.5, 1.0, 2.0])
PHASE_TAB = np.array([-8.1, -11.3, -4.8, 18.9, 73.1])  # deg, mid-chord reference
MAG_TAB = np.array([0.914, 0.837, 0.526, 0.390, 0.280])


@pytest.mark.parametrize("func", [sears, sears_hankel])
def test_sears_table(func):
    S = func(2.0 * K_TAB)  # omega = 2 k in U/c units
    # table digits: 0.1 deg and 0.001 -> half a unit of the last digit
    np.testing.assert_allclose(np.degrees(np.angle(S)), PHASE_TAB, atol=0.05 + 1e-9)
    np.testing.assert_allclose(np.abs(S), MAG_TAB, atol=0.0005 + 1e-9)


def test_sears_two_forms_agree_and_theodorsen_form():
    w = np.linspace(0.0, 40.0, 801)
    np.testing.assert_allclose(sears(w), sears_hankel(w), rtol=1e-12, atol=1e-14)
    # S = [J0 - i J1] C + i J1 (classical decomposition with Theodorsen's function)
    from scipy.special import j0, j1

    k = w / 2
    np.testing.assert_allclose(sears(w), (j0(k) - 1j * j1(k)) * theodorsen(w) + 1j * j1(k), rtol=1e-10, atol=1e-12)


def test_sears_limits_and_leading_edge_reference():
    assert sears(0.0) == 1.0
    w = np.array([0.3, 3.0])
    np.testing.assert_allclose(sears(w, "leading_edge"), sears(w) * np.exp(-0.5j * w), rtol=1e-14)
    # leading-edge referenced phase tends to -45 deg at high frequency
    assert abs(np.degrees(np.angle(sears(2000.0, "leading_edge"))) + 45.0) < 0.1
    # the magnitude decays as 1 / sqrt(2 pi k)
    k = 500.0
    assert abs(abs(sears(2 * k)) * np.sqrt(2 * np.pi * k) - 1.0) < 1e-3


def test_compressible_sears_limits():
    w = np.array([0.0, 0.1, 1.0, 4.0])
    np.testing.assert_allclose(sears_compressible(w, 0.0), sears(w), rtol=1e-14)
    np.testing.assert_allclose(sears_compressible(w, 1e-6), sears(w), atol=1e-9)
    assert sears_compressible(0.0, 0.5) == pytest.approx(1.0)
    # continuous in Mach near the incompressible limit
    d = np.abs(sears_compressible(w, 0.05) - sears(w))
    assert d.max() < 0.02
    # compressibility adds phase lag at low frequency (both correction factors lag)
    k = np.array([0.05, 0.1, 0.2])
    lag = np.angle(sears_compressible(2 * k, 0.5) / sears(2 * k / 0.75))
    assert np.all(lag < 0)


def test_kussner_table():
    s = np.array([1.0, 2.0, 5.0, 10.0, 20.0])  # semichords
    lo = np.array([0.38, 0.54, 0.74, 0.85, 0.93]) - 0.005
    hi = np.array([0.42, 0.55, 0.74, 0.86, 0.96]) + 0.005
    for approx in ("jones", "sears-sparks"):
        psi = kussner(s, approx, unit="semichord")
        # Sears-Sparks is the cruder fit: allow it 0.01 more than the table's digits
        slack = 0.0 if approx == "jones" else 0.01
        assert np.all(psi >= lo - slack) and np.all(psi <= hi + slack), (approx, psi)
    np.testing.assert_allclose(kussner(s / 2), kussner(s, unit="semichord"))
    assert kussner(-1.0) == 0.0


def test_step_response_quadrature_on_first_order_lag():
    tau = 1.7
    s = np.array([0.5, 2.0, 10.0])
    y = step_response(lambda w: 1.0 / (1.0 + 1j * w * tau), s)
    # the truncated tail is below (2 / pi) int_W^inf dw / (tau^2 w^3) = 1 / (pi tau^2 W^2) = 7e-9 at W = 4000; the
    # trapezoidal rule on the oscillating integrand (phase step s dw <= 0.2 at W for s = 10) adds a few 1e-8
    np.testing.assert_allclose(y, 1.0 - np.exp(-s / tau), rtol=0, atol=1e-7)


def test_kussner_is_step_response_of_sears():
    """Fourier inversion of the leading-edge Sears function against the Kussner approximations."""
    s_b = np.array([1.0, 2.0, 5.0, 10.0, 20.0])
    exact = step_response(lambda w: sears(w, "leading_edge"), s_b / 2)
    # R.T. Jones's fit is quoted to about 1 % of the final value; Sears-Sparks to about 4 %.
    np.testing.assert_allclose(kussner(s_b, "jones", unit="semichord"), exact, atol=0.015)
    np.testing.assert_allclose(kussner(s_b, "sears-sparks", unit="semichord"), exact, atol=0.045)


def test_wagner_is_step_response_of_theodorsen():
    s_b = np.array([1.0, 2.0, 5.0, 10.0, 20.0])
    exact = step_response(theodorsen, s_b / 2, high_value=0.5)
    np.testing.assert_allclose(wagner(s_b, unit="semichord"), exact, atol=0.01)
    assert wagner(0.0) == pytest.approx(0.5)


def test_bad_input():
    with pytest.raises(AnalyticError, match="omega must be finite and >= 0"):
        sears(-1.0)
    with pytest.raises(AnalyticError, match="omega must be finite and >= 0"):
        sears([np.nan])
    with pytest.raises(AnalyticError, match="reference"):
        sears(1.0, reference="trailing_edge")
    with pytest.raises(AnalyticError, match="mach"):
        sears_compressible(1.0, 1.2)
    with pytest.raises(AnalyticError, match="approximation"):
        kussner(1.0, "foo")
    with pytest.raises(AnalyticError, match="unit"):
        wagner(1.0, unit="metre")


@pytest.mark.parametrize("call, match", [
    (lambda: sears_compressible(1.0, mach="a"), r"mach = 'a' must be in \[0, 1\)"),
    (lambda: sears_compressible(1.0, mach=None), r"mach = None"),
    (lambda: sears_compressible(1.0, mach=True), r"mach = True"),
    (lambda: sears("one"), r"omega must be a real number or an array of real numbers.*'one'"),
    (lambda: sears_compressible([1.0, "x"], 0.5), r"omega must be a real number"),
    (lambda: kussner("late"), r"s must be a real number or an array of real times"),
    (lambda: wagner(["a"]), r"s must be a real number or an array of real times"),
    # a complex omega was cast to its real part (ComplexWarning); "1" was parsed as a frequency
    (lambda: sears(1.0 + 1.0j), r"omega must be a real number .*got complex"),
    (lambda: sears("1"), r"omega must be a real number .*got str"),
    # None became NaN: "time contains NaN"
    (lambda: kussner(None), r"s must be a real number or an array of real times .*got NoneType"),
    (lambda: wagner("1"), r"s must be a real number or an array of real times .*got str"),
    (lambda: kussner([0.0, np.nan]), r"s \(time\) contains NaN"),
])
def test_non_numeric_input_is_an_analytic_error(call, match):
    with pytest.raises(AnalyticError, match=match):
        call()


# Large frequencies: the scaled Bessel functions and, from K_ASYMPTOTIC on, Hankel's expansion (sears(1e10) was
# NaN: SciPy's K_nu(i k) gives NaN above k ~ 1e9, H_nu^(2)(k) above k ~ 1e16).
K_LARGE = [1.0, 30.0, 9.9e3, 1.0e4, 1.0e5, 1.0e8, 1.0e9, 5.0e9, 1.0e10, 1.0e12, 1.0e100, 8.0e307]


@pytest.mark.filterwarnings("error")
@pytest.mark.parametrize("k", K_LARGE)
def test_sears_and_theodorsen_are_finite_and_agree_at_any_frequency(k):
    w = 2.0 * k
    S, Sh, C = sears(w), sears_hankel(w), theodorsen(w)
    assert np.isfinite(S) and np.isfinite(Sh) and np.isfinite(C)
    assert abs(S / Sh - 1.0) < 1e-13   # the two forms, evaluated independently below K_ASYMPTOTIC
    # S = [J0 - i J1] C + i J1 (the classical decomposition), where Cephes' J0, J1 are accurate (their argument
    # reduction loses ~ k * 1e-16 of phase)
    if k <= 1e4:
        from scipy.special import j0, j1

        assert abs(S - ((j0(k) - 1j * j1(k)) * C + 1j * j1(k))) < 1e-12 * abs(S)


@pytest.mark.filterwarnings("error")
@pytest.mark.parametrize("k", [1.0e3, 1.0e4, 1.0e6, 1.0e9, 1.0e10, 1.0e12, 1.0e100])
def test_large_frequency_asymptotics(k):
    # From the definitions, with H_nu^(2)(k) ~ sqrt(2 / (pi k)) e^{-i (k - nu pi / 2 - pi / 4)} (1 - i a_1(nu) / k),
    # a_1(0) = -1/8, a_1(1) = 3/8 (DLMF 10.17.6): S_le = e^{-i pi / 4} / sqrt(2 pi k) (1 + i / (8 k) + O(k^-2)),
    # S_mid = S_le e^{i k}, C = 1/2 - i / (8 k) + O(k^-2).
    w = 2.0 * k
    lead = np.exp(-0.25j * np.pi) / np.sqrt(2.0 * np.pi * k)
    assert abs(sears(w, "leading_edge") / lead - (1.0 + 1j / (8.0 * k))) < 1.0 / k**2 + 1e-15
    assert abs(abs(sears(w)) * np.sqrt(2.0 * np.pi * k) - 1.0) < 1.0 / k**2 + 1e-15
    assert abs(theodorsen(w) - (0.5 - 1j / (8.0 * k))) < 1.0 / k**2 + 1e-15


def test_scaled_bessel_functions_match_scipy_across_the_switch():
    from scipy import special

    from cfd.analytic import K_ASYMPTOTIC, _hankel2_scaled, _kv_imaginary_scaled

    k = np.array([0.5, 50.0, 0.999 * K_ASYMPTOTIC, K_ASYMPTOTIC, 1.001 * K_ASYMPTOTIC, 1e6, 1e8])
    for nu in (0, 1):
        np.testing.assert_allclose(_hankel2_scaled(nu, k), special.hankel2e(nu, k), rtol=1e-14)
        np.testing.assert_allclose(_kv_imaginary_scaled(nu, k), special.kve(nu, 1j * k), rtol=1e-14)


def test_moderate_frequencies_keep_the_unscaled_values():
    from scipy import special

    w = np.concatenate([[0.0], np.logspace(-6, 6, 301)])
    k = np.where(w > 0, w / 2, 1.0)
    old_sears = np.where(w > 0, 1.0 / (1j * k * (special.kv(0, 1j * k) + special.kv(1, 1j * k))), 1.0)
    old_hankel = np.where(w > 0, 2.0 / (np.pi * k * (special.hankel2(0, k) - 1j * special.hankel2(1, k))), 1.0)
    h1, h0 = special.hankel2(1, k), special.hankel2(0, k)
    old_c = np.where(w > 0, h1 / (h1 + 1j * h0), 1.0)
    np.testing.assert_allclose(sears(w), old_sears, rtol=2e-15)
    np.testing.assert_allclose(sears_hankel(w), old_hankel, rtol=2e-15)
    np.testing.assert_allclose(theodorsen(w), old_c, rtol=2e-15)


@pytest.mark.filterwarnings("error")
def test_compressible_sears_at_large_frequency():
    w = np.array([1e10, 1e12])
    assert np.all(np.isfinite(sears_compressible(w, 0.5)))
    np.testing.assert_allclose(sears_compressible(w, 0.0), sears(w), rtol=1e-15)
    with pytest.raises(AnalyticError, match=r"omega / \(2 beta\^2\) overflows at mach = 0.9"):
        sears_compressible(1.7e308, 0.9)


@pytest.mark.filterwarnings("error")
@pytest.mark.parametrize("s", [-1e10, -1e300, -np.inf])
def test_indicial_functions_are_zero_long_before_the_step_without_overflow(s):
    assert kussner(s) == 0.0 and kussner(s, "sears-sparks") == 0.0 and wagner(s) == 0.0


def test_step_response_refuses_complex_times():
    with pytest.raises(AnalyticError, match=r"s must be a real number .*got list \[\(1\+1j\)\]"):
        step_response(sears, [1.0 + 1.0j])
