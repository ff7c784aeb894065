import numpy as np
import pytest

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402

from tentaclass.datasets import thesis_scanner  # noqa: E402
from tentaclass.plot.scanner import (  # noqa: E402
    DEFECT_COLORS,
    plot_belt,
    plot_inspection,
    save_belt_figure,
)
from tentaclass.scanner import LineScanner, inspect  # noqa: E402
from tentaclass.scanner.simulate import draw_shape, make_belt  # noqa: E402


@pytest.fixture(autouse=True)
def _close():
    yield
    plt.close("all")


def test_plot_inspection_marks_holes_and_bites():
    grid = draw_shape("square", (40, 40), 24.0, angle=0.3)
    grid[18:21, 18:21] = False  # hole
    grid[8:13, 16:22] = False  # bite from the top edge
    result = inspect(grid)
    _, ax = plt.subplots()
    art = plot_inspection(grid, result, ax=ax)
    assert art["image"].axes is ax
    assert art["expected"] is not None
    kinds = [d.kind for d in result.defects]
    assert "hole" in kinds
    colors = [p.get_edgecolor() for p in art["defects"]]
    assert len(colors) == len(result.defects)
    assert matplotlib.colors.same_color(colors[0], DEFECT_COLORS["hole"])
    assert ax.get_title().endswith("REJECT")


def test_plot_inspection_new_axes():
    art = plot_inspection(thesis_scanner().grids[0])
    assert art["defects"] == [] and "ACCEPT" in art["image"].axes.get_title()


def test_plot_belt_and_save(tmp_path):
    belt = make_belt(5, width=96, lanes=2, random_state=2)
    objs = list(LineScanner(96).scan([belt.image]))
    _, ax = plt.subplots()
    art = plot_belt(belt.image, objs, ax=ax)
    assert len(art["boxes"]) == len(art["labels"]) == len(objs)
    for box, obj in zip(art["boxes"], objs, strict=True):
        want = "tab:green" if obj.accept else "tab:red"
        assert matplotlib.colors.same_color(box.get_edgecolor(), want)
    assert art["labels"][0].get_text().startswith("0 ")
    save_belt_figure(belt.image, objs, tmp_path / "belt.png")
    assert (tmp_path / "belt.png").read_bytes()[:4] == b"\x89PNG"


def test_plot_belt_draws_grey_levels_as_they_are():
    belt = make_belt(3, width=64, random_state=1).image
    grey = np.where(belt, 30, 200).astype(np.uint8)
    objs = list(LineScanner(64).scan([grey]))
    assert len(objs) == 3
    _, ax = plt.subplots()
    art = plot_belt(grey, objs, ax=ax)
    assert np.array_equal(art["image"].get_array(), grey.astype(float))
    assert art["image"].get_clim() == (30.0, 200.0) and art["image"].get_cmap().name == "gray"
    binary = plot_belt(belt, objs, ax=ax)["image"]  # 0/1: objects black on white
    assert binary.get_cmap().name == "Greys" and binary.get_array().dtype == bool


def test_bad_images():
    with pytest.raises(ValueError, match="2-D"):
        plot_belt(np.zeros((2, 2, 2)), [])


@pytest.mark.parametrize(
    ("objects", "match"),
    [
        (3, r"^objects must be a sequence of ScannedObject, got int"),  # was a TypeError
        ("id", r"^objects must be a sequence of ScannedObject, got str"),
        ([None], r"^objects\[0\] must be a ScannedObject, got NoneType"),  # an AttributeError
    ],
)
def test_objects_that_are_not_scanner_records_are_named(tmp_path, objects, match):
    from tentaclass.errors import InputError

    belt = make_belt(2, width=64, random_state=0)
    with pytest.raises(InputError, match=match):
        plot_belt(belt.image, objects)
    with pytest.raises(InputError, match=match):
        save_belt_figure(belt.image, objects, tmp_path / "belt.png")
    assert not (tmp_path / "belt.png").exists()


@pytest.mark.parametrize(
    ("dpi", "match"),
    [
        (0, r"^dpi must be at least 1, got 0"),  # was a ZeroDivisionError
        (10**6, r"^dpi 1,000,000 would make a figure 4,000,000 pixels across, more than"),
        (72.5, r"^dpi must be an integer"),
    ],
)
def test_save_belt_figure_refuses_a_dpi_it_cannot_draw(tmp_path, dpi, match):
    from tentaclass.errors import InputError

    belt = make_belt(2, width=64, random_state=0)
    with pytest.raises(InputError, match=match):  # 1e6 was a MemoryError (std::bad_alloc)
        save_belt_figure(belt.image, [], tmp_path / "belt.png", dpi=dpi)
    with pytest.raises(
        InputError, match=r"^image must be a non-empty 2-D array \(rows, width\), got \(64,\)"
    ):
        save_belt_figure(belt.image[0], [], tmp_path / "belt.png")
    assert not (tmp_path / "belt.png").exists()
