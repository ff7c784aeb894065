import numpy as np
import pytest

from tentaclass.errors import ShapeError
from tentaclass.plot import features as plotting

plt = pytest.importorskip("matplotlib.pyplot")


def test_thesis_panel_has_four_axes_and_the_shape():
    q = np.tile([0, 0, 0, np.pi / 2], 4)
    fig = plotting.plot_thesis_panel(q, title="SQUARE")
    axes = fig.get_axes()
    assert [a.get_title() for a in axes] == [
        "shape",
        "turning function",
        "periodic signal",
        "feature vector",
    ]
    line = axes[0].get_lines()[0]
    np.testing.assert_allclose(line.get_xydata()[4], [3, 1], atol=1e-12)
    assert len(axes[3].patches) == 8


def test_plot_functions_return_artists_and_refuse_batches():
    fig, ax = plt.subplots()
    bars = plotting.plot_features(np.full(16, np.pi / 8), ax=ax, color="red")
    assert len(bars) == 8
    lines = plotting.plot_turning(np.full(16, np.pi / 8), ax=ax)
    assert lines[0].get_ydata()[-1] == pytest.approx(2 * np.pi)
    with pytest.raises(ShapeError, match="one joint-angle array"):  # a bare ValueError before
        plotting.plot_shape(np.zeros((2, 8)), ax=ax)
    plt.close(fig)


def test_circle_features_are_drawn_as_zero_not_as_rounding_noise():
    q = np.full(16, np.pi / 8)
    fig = plotting.plot_thesis_panel(q)
    signal_ax, features_ax = fig.get_axes()[2:]
    assert all(b.get_height() == 0 for b in features_ax.patches)
    assert features_ax.get_ylim() == (0, 1)
    np.testing.assert_array_equal(signal_ax.get_lines()[0].get_ydata(), 0)


def test_none_ax_makes_a_new_figure():
    q = np.tile([0, 0, 0, np.pi / 2], 4)
    first = plotting.plot_features(q)
    second = plotting.plot_features(q)
    assert first.patches[0].axes.figure is not second.patches[0].axes.figure
    plt.close("all")
