import numpy as np
import pytest

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from tentaclass import shapes  # noqa: E402
from tentaclass.plot.wrapping import (  # noqa: E402
    grasp_spectrum,
    plot_capture_error,
    plot_grasp_spectra,
    plot_wrap,
)
from tentaclass.wrapping import wrap  # noqa: E402


def test_plot_wrap_artists():
    sq = shapes.square(4)
    w = wrap(sq, 12, 1.0, start=0.1, offset=2.0)
    fig, ax = plt.subplots()
    art = plot_wrap(w, sq, ax=ax, color="green")
    assert np.allclose(art["links"].get_xydata(), w.joints)
    assert art["links"].get_color() == "green"
    assert len(art["contacts"].get_offsets()) == w.contact.sum()
    assert np.allclose(art["base"].get_xydata(), [w.joints[0]])
    assert np.allclose(art["object"].get_xy()[:-1], sq)
    plt.close(fig)


def test_grasp_spectrum_and_bars():
    circle = np.full(16, np.pi / 8)
    assert np.allclose(grasp_spectrum(circle), 0)
    partial = np.r_[circle[:8], np.zeros(8)]
    assert grasp_spectrum(partial).shape == (8,) and grasp_spectrum(partial)[0] > 1
    fig, ax = plt.subplots()
    bars = plot_grasp_spectra({"partial": partial, "once": circle, "multiple": 2 * circle}, ax=ax)
    assert len(bars) == 3 and all(len(b) == 8 for b in bars)
    assert np.allclose([r.get_height() for r in bars[1]], 0)
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["partial", "once", "multiple"]
    plt.close(fig)


def test_plot_capture_error_lines_and_marks():
    fig, ax = plt.subplots()
    art = plot_capture_error({"c": ([0.1, 0.2], [0.0, 0.01])}, ax=ax, marks={"l=r": [1.0]})
    assert np.allclose(art["c"].get_xydata(), [[0.1, 0.0], [0.2, 0.01]])
    assert "mark: l=r" in art
    plt.close(fig)


def test_plot_wrap_labels_its_axes_and_legend():
    sq = shapes.square(4)
    art = plot_wrap(wrap(sq, 12, 1.0), sq)
    ax = art["links"].axes
    assert ax.get_xlabel() and ax.get_ylabel()
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels == ["object", "links", "joints", "contacts", "base"]
    plt.close("all")


def test_capture_error_marks_stay_inside_the_axes():
    art = plot_capture_error({"a": ([0.1, 0.5], [0.0, 0.1])}, marks={"a/2": [0.5]})
    ax = art["a"].axes
    (label,) = ax.texts
    assert label.xy[1] < 1 and label.get_va() == "top"  # below the title, not on it
    plt.close("all")


def test_bad_arguments_are_named_before_a_figure_is_made():
    from tentaclass.errors import InputError

    before = plt.get_fignums()
    with pytest.raises(InputError, match=r"^w must be a Wrap .*, got str"):
        plot_wrap("w", shapes.square(1.0))  # was an AttributeError
    with pytest.raises(InputError, match=r"^arrays must be a mapping of label -> joint angles"):
        plot_grasp_spectra([np.ones(8)])
    with pytest.raises(
        InputError, match=r"^curves\['a'\]: link_lengths and errors .*\(3,\) and \(2,\)"
    ):
        plot_capture_error({"a": ([1.0, 2.0, 3.0], [0.1, 0.2])})  # was matplotlib's "x and y"
    with pytest.raises(InputError, match=r"^curves\['a'\] must be a pair"):
        plot_capture_error({"a": [1.0, 2.0, 3.0]})
    assert plt.get_fignums() == before
