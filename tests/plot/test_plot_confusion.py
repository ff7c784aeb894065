import numpy as np
import pytest

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from tentaclass.plot import plot_confusion_matrix  # noqa: E402


def test_counts_in_cells_and_integer_colour_bar():
    y = ["a"] * 7 + ["b"] * 3
    p = ["a"] * 5 + ["b"] * 2 + ["b"] * 3
    art = plot_confusion_matrix(y, p)
    texts = sorted((t.get_position(), t.get_text()) for t in art["counts"])
    # rows true, columns predicted: (x=col, y=row)
    assert texts == [((0, 0), "5"), ((1, 0), "2"), ((1, 1), "3")]
    art["image"].figure.canvas.draw()
    ticks = art["colorbar"].get_ticks()
    np.testing.assert_array_equal(ticks, np.round(ticks))
    ax = art["image"].axes
    assert [t.get_text() for t in ax.get_xticklabels()] == ["a", "b"]
    assert ax.get_xlabel() == "predicted class" and ax.get_ylabel() == "true class"
    plt.close("all")


def test_many_classes_leave_out_names_and_counts():
    y = np.arange(100).astype(str)
    art = plot_confusion_matrix(y, y, max_labels=50)
    assert art["counts"] == [] and len(art["image"].axes.get_xticks()) == 0
    plt.close("all")


def test_max_labels_must_be_a_count():
    from tentaclass.errors import InputError

    with pytest.raises(InputError, match=r"^max_labels must be an integer, got 'a'"):
        plot_confusion_matrix([1, 2], [1, 2], max_labels="a")  # was a TypeError
    with pytest.raises(InputError, match=r"^max_labels must be at least 0, got -1"):
        plot_confusion_matrix([1, 2], [1, 2], max_labels=-1)
    assert plot_confusion_matrix([1, 2], [1, 2], max_labels=0)["counts"] == []
    plt.close("all")
