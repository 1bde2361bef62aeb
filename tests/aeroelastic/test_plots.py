"""Plot functions draw on given axes and return them (smoke tests, Agg backend)."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import aeroelastic as ae  # noqa: E402
from aeroelastic import theodorsen as th  # noqa: E402


def test_plots_return_axes():
    sec = ae.TypicalSection(20, -0.2, 0.1, 0.24, 0.4)
    W = np.concatenate([[0.0], np.geomspace(0.01, 4.0, 60)])
    model = ae.fit_motion(th.jones_frf(W, sec.a), 2, gust_order=3)
    r = ae.flutter(model, sec, np.linspace(0.05, 3.0, 30))
    ax = ae.root_locus_plot(r)
    assert len(ax.lines) >= 7
    ax_g, ax_f = ae.vg_plot(r)
    assert ax_g.get_xlabel() == "" and "speed index" in ax_f.get_xlabel()
    fig = ae.flutter_plot(r)
    assert len(fig.axes) == 3
    t = np.linspace(0, 20, 201)
    g = ae.gust_response(model, sec, 1.0, (t, np.where(t > 1, 0.01, 0.0)))
    assert len(ae.gust_response_plot(g)) == 5
    axs = ae.gust_response_plot(g, reference=g)
    assert len(axs) == 6   # the difference row, zero here
    assert all(np.all(np.asarray(line.get_ydata()) == 0.0) for line in axs[5].lines)
    plt.close("all")


def test_gust_plot_difference_row_is_per_cent_of_the_reference_peak():
    # the row that shows the few per cent docs/aeroelastic.md quotes: (response - reference) / peak |reference|
    import types

    t = np.linspace(0.0, 10.0, 101)
    ref = types.SimpleNamespace(t=t, plunge=np.sin(t), pitch=2 * np.sin(t), Cl=np.cos(t), Cm=-np.cos(t))
    resp = types.SimpleNamespace(t=t, u=0 * t, speed=1.0, plunge=1.02 * np.sin(t), pitch=2 * np.sin(t),
                                 Cl=np.cos(t) + 0.03, Cm=-np.cos(t))
    axs = ae.gust_response_plot(resp, reference=ref)
    lines = {line.get_label(): line.get_ydata() for line in axs[5].lines if not line.get_label().startswith("_")}
    peak = np.max(np.abs(np.sin(t)))
    np.testing.assert_allclose(lines["plunge"], 2 * np.sin(t) / peak, atol=1e-12)
    np.testing.assert_allclose(lines["Cl"], 3.0, atol=1e-12)
    np.testing.assert_allclose(lines["pitch"], 0.0, atol=1e-12)
    plt.close("all")


@pytest.mark.parametrize("plot, what", [(ae.root_locus_plot, "aeroelastic.flutter"),
                                        (ae.vg_plot, "aeroelastic.flutter"), (ae.flutter_plot, "aeroelastic.flutter"),
                                        (ae.gust_response_plot, "aeroelastic.gust_response")])
@pytest.mark.parametrize("bad", [None, 3, "result"])
def test_plots_name_what_they_expected(plot, what, bad):
    with pytest.raises(ae.AeroModelError, match=rf"expected the result of {what}, got {type(bad).__name__}"):
        plot(bad)


def test_root_locus_flag_is_a_bool():
    sec = ae.TypicalSection(20, -0.2, 0.1, 0.24, 0.4)
    W = np.concatenate([[0.0], np.geomspace(0.01, 4.0, 40)])
    r = ae.flutter(ae.fit_motion(th.jones_frf(W, sec.a), 2, gust_order=3), sec, np.linspace(0.05, 3.0, 20))
    with pytest.raises(ae.AeroModelError, match=r"show_lags must be True or False, got 'no'"):
        ae.root_locus_plot(r, show_lags="no")
    plt.close("all")
