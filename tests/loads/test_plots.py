"""The loads figures draw what the results hold and refuse other arguments."""

import matplotlib

matplotlib.use("Agg")

import control
import matplotlib.pyplot as plt
import numpy as np
import pytest

import loads

PT = loads.FlightPoint(0.4, 2000.0, 2.0)


@pytest.fixture(scope="module")
def results():
    A = np.array([[0.0, 1.0, 0.0], [-0.16, -0.04, 0.0], [0.0, 0.0, -0.08]])
    sys = control.ss(A, [[0.0], [1.0], [0.08]], [[0.5, 2.0, 3.0], [-0.1, 0.3, 0.2]], [[0.0], [0.0]],
                     inputs=["gust"], outputs=["Cl", "Cm"])
    return loads.tuned_gust(sys, PT), loads.continuous_turbulence(sys, PT)


def test_figures_draw_the_numbers(results):
    tg, ct = results
    fig, axs = plt.subplots(2, 2)
    loads.correlated_loads_plot(tg, ct, ax=axs[0, 0])
    # two outputs' peaks (each with its mirror) and the ellipse
    xs = np.concatenate([ln.get_xdata() for ln in axs[0, 0].lines[:2]])
    assert np.allclose(np.sort(np.abs(xs)), np.sort(np.abs([tg.correlated[o]["Cl"] * PT.q * PT.chord_m
                                                            for o in ("Cl", "Cm") for _ in (0, 1)])))
    ex, ey = loads.turbulence_ellipse(ct, "Cl", "Cm")
    assert np.abs(ex).max() == pytest.approx(ct.dimensional["Cl"], rel=1e-9)
    # the ellipse's x-extreme carries rho times the y design load
    assert ey[0] == pytest.approx(ct.rho("Cl", "Cm") * ct.dimensional["Cm"], rel=1e-9)
    loads.load_vs_H_plot(tg, ax=axs[0, 1])
    assert max(ln.get_ydata().max() for ln in axs[0, 1].lines) <= 1.0 + 1e-12
    loads.psd_plot(ct, ax=axs[1, 0])
    loads.gust_history_plot(tg, "Cl", others=["Cm"], ax=axs[1, 1])
    plt.close(fig)


def test_plots_refuse_other_arguments(results):
    tg, ct = results
    with pytest.raises(loads.LoadsModelError, match="tuned_gust"):
        loads.load_vs_H_plot(ct)
    with pytest.raises(loads.LoadsModelError, match="continuous_turbulence"):
        loads.psd_plot(tg)
    with pytest.raises(loads.LoadsModelError, match="no output 'Cz'"):
        loads.correlated_loads_plot(tg, ct, y="Cz")
    with pytest.raises(loads.LoadsModelError, match="give a tuned_gust"):
        loads.correlated_loads_plot(None, None)
    with pytest.raises(loads.LoadsModelError, match="dimensional must be True or False"):   # read as truthy
        loads.correlated_loads_plot(tg, dimensional="no")
    plt.close("all")


@pytest.mark.parametrize("kw, match", [
    (dict(n=-5), r"n \(points on the ellipse\) must be an integer from 3 to 100000, got -5"),   # bare ValueError
    (dict(n=0), r"must be an integer from 3"),                                                   # empty arrays
    (dict(n=10**9), r"must be an integer from 3 to 100000"),
    (dict(n=181.0), r"must be an integer from 3"),
    (dict(dimensional="no"), r"dimensional must be True .* or False"),
    (dict(y="X"), r"no output 'X' in the turbulence result"),
])
def test_turbulence_ellipse_refuses_bad_arguments(results, kw, match):
    with pytest.raises(loads.LoadsModelError, match=match):
        loads.turbulence_ellipse(results[1], **({"x": "Cl", "y": "Cm"} | kw))
