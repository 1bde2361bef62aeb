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
    axs = ae.gust_response_plot(g, reference=g)
    assert len(axs) == 5
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
