"""studies.report.plots: figures from plain arrays (Agg backend; the data drawn is read back from the artists)."""

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from PIL import Image  # noqa: E402

import sysid  # noqa: E402
from studies.report import plots  # noqa: E402
from studies.report.plots import PlotDataError  # noqa: E402


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def delayed_lag(omega, delay=0.5, pole=0.4, gain=6.0):
    """H(omega) = gain e^{-i omega delay} / (1 + i omega / pole): the phase leaves (-180, 180] (unwrapping matters)."""
    with np.errstate(invalid="ignore"):
        H = gain * np.exp(-1j * omega * delay) / (1.0 + 1j * omega / pole)
    return np.where(np.isfinite(omega), H, 0.0)


@pytest.fixture
def grid():
    omega_d, omega = sysid.mckelvey_grid(64, 70 / (2 * np.pi))
    return omega, np.stack([delayed_lag(omega), 0.1 * delayed_lag(omega, delay=1.0)])[:, None, :]


def test_frf_plot_draws_k_magnitude_and_unwrapped_phase(grid):
    omega, H = grid
    model = H * (1 + 0.01)
    fig, axes = plots.frf_plot(omega, H, [("ROM", model)], outputs=("Cl", "Cm"), title="t")
    assert axes.shape == (3, 2)
    ref_mag, rom_mag = axes[0, 0].get_lines()[:2]
    k = omega / 2
    sel = np.isfinite(k) & (k > 0)  # omega = 0 and inf are left out of the log axes
    np.testing.assert_allclose(ref_mag.get_xdata(), k[sel])
    np.testing.assert_allclose(ref_mag.get_ydata(), np.abs(H[0, 0, sel]))
    phase = axes[1, 0].get_lines()[0].get_ydata()
    expected = np.degrees(-omega[sel] * 0.5 - np.arctan(omega[sel] / 0.4))
    np.testing.assert_allclose(phase, expected, atol=1e-9)  # unwrapped, in degrees
    assert phase.min() < -250
    err = axes[2, 0].get_lines()[0].get_ydata()
    np.testing.assert_allclose(err, 0.01 * np.abs(H[0, 0, sel]) / np.abs(H[0, 0]).max(), rtol=1e-9)
    assert axes[0, 0].get_xscale() == "log" and axes[0, 0].get_yscale() == "log"
    assert "reduced frequency" in axes[2, 0].get_xlabel() and "deg" in axes[1, 1].get_ylabel()
    assert "1/rad" in axes[0, 1].get_ylabel()
    assert [t.get_text() for t in axes[0, 0].get_legend().get_texts()] == ["LFD", "ROM"]


def test_frf_plot_marks_the_identification_samples_and_aligns_model_phase(grid):
    omega, H = grid
    shifted = H * np.exp(2j * np.pi * 0.0)  # same data: the model phase must land on the data's branch
    fig, axes = plots.frf_plot(omega, H, {"ROM": shifted}, samples=np.arange(0, 65, 4), error=False)
    assert axes.shape == (2, 2)
    labels = [t.get_text() for t in axes[0, 0].get_legend().get_texts()]
    assert labels[1] == "LFD samples used (15)"  # 17 samples minus omega = 0 and inf
    ref_phase, rom_phase = (ln.get_ydata() for ln in axes[1, 0].get_lines()[:2])
    np.testing.assert_allclose(rom_phase, ref_phase)


def test_unwrapped_phase_follows_a_reference_branch():
    w = np.linspace(0.1, 20, 50)  # steps of 0.4 rad: unwrapping recovers the phase through three turns
    H = np.exp(-1j * w)
    np.testing.assert_allclose(plots.unwrapped_phase_deg(H), np.degrees(-w), atol=1e-9)
    ph = plots.unwrapped_phase_deg(H, like=plots.unwrapped_phase_deg(H) - 720.0)
    np.testing.assert_allclose(ph, np.degrees(-w) - 720.0, atol=1e-9)


@pytest.mark.parametrize("args, match", [
    ((np.array([0.0, 1.0]), np.ones(3)), "has 3 frequencies but omega has 2"),
    ((np.array([0.0, np.inf]), np.ones(2)), "no positive finite frequency"),
    ((np.array([1.0, 2.0]), np.ones((1, 1, 1, 2))), "must have shape"),
    ((np.array([1.0, 2.0]), np.ones(2), [("ROM", np.ones((2, 1, 2)))]), "model 'ROM' has shape"),
    ((np.array([1.0, 2.0]), np.ones(2), [("ROM",)]), "must be \\(label, data\\)"),
])
def test_frf_plot_rejects_bad_shapes(args, match):
    with pytest.raises(PlotDataError, match=match):
        plots.frf_plot(*args)


def test_hankel_plot_normalises_and_marks_orders():
    sv = np.array([4.0, 2.0, 1.0, 1e-3, 1e-4])
    fig, ax = plots.hankel_plot([("N_ω = 257", sv), ("N_ω = 33", sv[:3] * 2)], orders=[3, 2])
    lines = [ln for ln in ax.get_lines() if ln.get_label() in ("N_ω = 257", "N_ω = 33")]
    np.testing.assert_allclose(lines[0].get_ydata(), sv / 4.0)
    np.testing.assert_allclose(lines[0].get_xdata(), np.arange(1, 6))
    vlines = [ln for ln in ax.get_lines() if ln.get_linestyle() == ":"]
    assert sorted(ln.get_xdata()[0] for ln in vlines) == [2.5, 3.5]  # between kept and dropped values
    assert ax.get_yscale() == "log"
    fig2, ax2 = plots.hankel_plot(sv, normalise=False)
    np.testing.assert_allclose(ax2.get_lines()[0].get_ydata(), sv)


@pytest.mark.parametrize("sv, match", [(np.array([]), "non-empty 1-D"), (np.ones((2, 2)), "non-empty 1-D"),
                                       ({}, "no singular values")])
def test_hankel_plot_rejects_empty(sv, match):
    with pytest.raises(PlotDataError, match=match):
        plots.hankel_plot(sv)


def rom_rows():
    rows = []
    for M in (32, 256):
        for method in ("plain", "dc"):
            for n in (4, 9, 25):
                rows.append(dict(case="T2", T=11.14, M=M, order=n, method=method, status="ok",
                                 frf_max_err_Cl=1.0 / n / (M / 32), stable=not (n == 25 and M == 32 and method == "plain")))
    rows.append(dict(case="T2", T=11.14, M=256, order=40, method="plain", status="failed", frf_max_err_Cl=float("nan"),
                     stable=None))
    return rows


def test_error_vs_order_plot_groups_and_marks_unstable():
    fig, axes = plots.error_vs_order_plot(rom_rows(), {"frf_max_err_Cl": "FRF max error Cl"},
                                          group_by=("M", "method"))
    ax = axes[0]
    assert ax.get_yscale() == "log" and ax.get_ylabel() == "FRF max error Cl"
    curves = [ln for ln in ax.get_lines() if ln.get_marker() in ("None", "", None) and len(ln.get_xdata()) == 3]
    assert len(curves) == 4  # (M, method) groups; the failed order 40 is not drawn
    assert all(list(c.get_xdata()) == [4, 9, 25] for c in curves)
    crosses = [ln for ln in ax.get_lines() if ln.get_marker() == "x"]
    assert len(crosses) == 1 and list(crosses[0].get_xdata()) == [25]
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert legend == ["$N_\\omega$ = 33", "$N_\\omega$ = 257", "plain", "dc", "unstable ROM"]
    # one colour per N_omega, one line style per method
    colours = {(c.get_color(), c.get_linestyle()) for c in curves}
    assert len({c for c, _ in colours}) == 2 and len({s for _, s in colours}) == 2


def test_error_vs_order_plot_clips_off_scale_values():
    rows = [dict(order=n, M=256, method="plain", stable=n < 25, err=e) for n, e in [(9, 0.05), (15, 0.01), (25, 1e48)]]
    fig, axes = plots.error_vs_order_plot(rows, {"err": "worst gust peak error"}, group_by=("M", "method"), clip=10.0)
    ax = axes[0]
    (curve,) = [ln for ln in ax.get_lines() if ln.get_marker() in ("None", "", None)]
    assert list(curve.get_ydata()) == [0.05, 0.01, 10.0]  # 1e48 drawn at the clip
    (tri,) = [ln for ln in ax.get_lines() if ln.get_marker() == "^"]
    assert list(tri.get_xdata()) == [25] and not [ln for ln in ax.get_lines() if ln.get_marker() == "x"]
    assert "off scale (> 1000%)" in [t.get_text() for t in ax.get_legend().get_texts()]
    assert ax.get_ylim()[1] < 100.0


@pytest.mark.parametrize("metrics, match", [({}, "at least one metric"), (["rms_err_Cl"], "no row has a value")])
def test_error_vs_order_plot_needs_data(metrics, match):
    with pytest.raises(PlotDataError, match=match):
        plots.error_vs_order_plot(rom_rows(), metrics)


def test_history_plot_rows_and_difference():
    t = np.linspace(0, 10, 101)
    ref = {"Cl": np.sin(t), "Cm": -0.1 * np.sin(t)}
    rom = {"Cl": np.sin(t) + 0.01, "Cm": -0.1 * np.sin(t)}
    u = np.where(t > 2, 1.0, 0.0)  # G6: v_g / U = 1 is a 45-degree gust
    fig, axes = plots.history_plot(t, ref, [("ROM", rom, {"ls": "--"})], u=u, title="G6")
    assert axes.shape == (3, 2)
    np.testing.assert_allclose(axes[0, 0].get_lines()[0].get_ydata().max(), 45.0)  # gust angle atan(u), degrees
    np.testing.assert_allclose(axes[2, 0].get_lines()[0].get_ydata(), 0.01)  # ROM - LTD
    assert axes[1, 0].get_lines()[1].get_linestyle() == "--"
    assert "convective time" in axes[2, 1].get_xlabel()
    fig2, axes2 = plots.history_plot(t, None, [("T5", ref), ("T6", rom)], outputs=["Cm"], t_label="s - s0")
    assert axes2.shape == (1, 1) and axes2[0, 0].get_xlabel() == "s - s0"  # no reference: no difference row


@pytest.mark.parametrize("kwargs, match", [
    (dict(reference={"Cl": np.ones(5)}), "has 5 samples but t has 11"),
    (dict(reference={"Cm": np.ones(11)}), "has no 'Cl' history"),
    (dict(reference=None), "nothing to plot"),
    (dict(reference={"Cl": np.ones(11), "Cm": np.ones(11)}, u=np.ones(3)), "u has 3 samples"),
])
def test_history_plot_rejects_bad_data(kwargs, match):
    with pytest.raises(PlotDataError, match=match):
        plots.history_plot(np.arange(11.0), **kwargs)


def test_heatmap_annotations_and_missing_cells():
    v = np.array([[0.5, 0.012], [np.nan, 2e-6]])
    fig, ax = plots.heatmap_plot(v, ["a", "b"], ["G1", "G3"])
    texts = sorted(t.get_text() for t in ax.texts)
    assert texts == sorted(["50%", "1.2%", "-", "2e-04%"])
    assert [t.get_text() for t in ax.get_xticklabels()] == ["G1", "G3"]
    assert ax.images[0].norm.vmin == pytest.approx(2e-6) and ax.images[0].norm.vmax == pytest.approx(0.5)


def test_heatmap_clips_large_errors_and_marks_diverged_ones():
    # an unstable ROM: 1e80 (finite) or an overflowed history (inf); neither may flatten the colour scale
    v = np.array([[0.02, 1e80], [np.inf, 3.0]])
    fig, ax = plots.heatmap_plot(v, ["a", "b"], ["G1", "G3"], vmin=1e-3, vmax=10.0)
    assert sorted(t.get_text() for t in ax.texts) == sorted(["2%", ">1000%", "inf", "300%"])
    shown = ax.images[0].get_array()
    assert shown[0, 1] == shown[1, 0] == 10.0 and not np.ma.is_masked(shown[1, 0])
    assert ax.images[0].norm.vmax == 10.0


@pytest.mark.parametrize("values, match", [(np.ones((2, 3)), "there are 2 row and 2 column labels"),
                                           (-np.ones((2, 2)), "non-negative")])
def test_heatmap_rejects_bad_values(values, match):
    with pytest.raises(PlotDataError, match=match):
        plots.heatmap_plot(values, ["a", "b"], ["x", "y"])


def test_save_figure_palette_png_and_closes(tmp_path):
    fig, _ = plots.hankel_plot(np.array([1.0, 0.1, 0.01]))
    path = plots.save_figure(fig, tmp_path / "a" / "h.png", dpi=60)
    with Image.open(path) as im:
        assert im.mode == "P"  # 256-colour palette
    assert not plt.fignum_exists(fig.number)
    fig, _ = plots.hankel_plot(np.array([1.0, 0.1]))
    with Image.open(plots.save_figure(fig, tmp_path / "rgba.png", dpi=60, palette=False)) as im:
        assert im.mode == "RGBA"


def test_history_plot_stops_a_diverging_model_where_it_leaves_the_scale():
    # an unstable ROM oscillating with growing amplitude: drawn to the end it painted the clipped panel solid;
    # it is drawn up to its first sample outside the reference's range +- half its span, NaN after
    t = np.linspace(0.0, 40.0, 2001)
    ref = np.exp(-((t - 3.0) ** 2))
    bad = ref + 1e-3 * np.exp(0.5 * t) * np.sin(20 * t)
    fig, axes = plots.history_plot(t, {"Cl": ref}, [("unstable", {"Cl": bad})], outputs=("Cl",))
    line = next(ln for ln in axes[0, 0].get_lines() if ln.get_label().startswith("unstable"))
    y = np.asarray(line.get_ydata(), dtype=float)
    first_out = int(np.flatnonzero((bad < -0.5) | (bad > 1.5))[0])
    assert np.all(np.isfinite(y[:first_out + 1])) and np.all(np.isnan(y[first_out + 1:]))
    assert "diverges, off scale" in line.get_label()
    err = axes[1, 0].get_lines()[-1]
    assert np.isnan(np.asarray(err.get_ydata(), dtype=float)[first_out + 1:]).all()
    plots.pyplot().close(fig)
