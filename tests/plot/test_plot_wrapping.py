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
