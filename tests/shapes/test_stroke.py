import numpy as np
import pytest
import shapely

from tentaclass.datasets import drawn_shapes
from tentaclass.errors import InputError
from tentaclass.shapes import from_stroke


def test_from_stroke_trims_overshoot_and_closes_gaps():
    t = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    circle = np.stack([np.cos(t), np.sin(t)], axis=1)
    overshoot = np.concatenate([circle, circle[:60]])  # 15 % past the start
    gap = circle[:360]  # 10 % short
    for stroke in (overshoot, gap):
        out = from_stroke(stroke, 64, smoothing=0)
        poly = shapely.Polygon(out)
        assert poly.area == pytest.approx(np.pi, rel=0.03)
        assert np.allclose(np.hypot(*out.T), 1, atol=0.04) or stroke is gap


def test_from_stroke_spacing_is_even_whatever_the_input():
    rng = np.random.default_rng(0)
    t = np.sort(rng.uniform(0, 2 * np.pi, 80))
    out = from_stroke(np.stack([np.cos(t), np.sin(t)], axis=1), 100)
    step = np.hypot(*(np.roll(out, -1, axis=0) - out).T)
    assert step.max() / step.min() < 1.05


def test_from_stroke_same_outline_under_rotation_and_scale():
    s = drawn_shapes(1, classes=("arrow",), random_state=2).strokes[0]
    a = 0.7
    rot = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    moved = shapely.LinearRing(3 * from_stroke(s, 256) @ rot.T + 5)
    direct = shapely.LinearRing(from_stroke(3 * s @ rot.T + 5, 256))
    # the same curve (its points may start elsewhere along it)
    assert shapely.hausdorff_distance(moved, direct) < 2e-3 * direct.length


@pytest.mark.parametrize(
    ("stroke", "message"),
    [
        (np.empty((0, 2)), "empty"),
        ([[1.0, 1.0]], "1 distinct point"),
        ([[1.0, 1.0], [1.0, 1.0], [2.0, 2.0]], "2 distinct point"),
        ([[0, 0], [1, 0], [2, 0], [3, 0]], "no area"),
        ([[0, 0], [1, np.nan], [2, 0]], "NaN"),
        ([[0, 0, 0]], "shape"),
        ("abc", "numbers"),
    ],
)
def test_from_stroke_refuses(stroke, message):
    with pytest.raises(InputError, match=message):
        from_stroke(stroke)


@pytest.mark.parametrize("smoothing", [1.5, 1e12])
def test_from_stroke_refuses_a_smoothing_wider_than_the_outline(smoothing):
    # 1.5 read as "stroke encloses no area", 1e12 was a MemoryError (14.6 PiB)
    square = [[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]]
    with pytest.raises(InputError, match=r"smoothing must be at most 1 .*, got (1.5|1e\+12)"):
        from_stroke(square, smoothing=smoothing)
    assert from_stroke(square, smoothing=0.1).shape == (128, 2)


def test_from_stroke_refuses_a_figure_eight_but_keeps_a_small_loop():
    t = np.linspace(0, 2 * np.pi, 200)
    eight = np.stack([np.sin(t), np.sin(2 * t) / 2], axis=1)
    with pytest.raises(InputError, match="crosses itself"):
        from_stroke(eight)
    # a circle whose end curls into a small loop inside it
    circle = np.stack([np.cos(t), np.sin(t)], axis=1)
    curl = np.array([[1.0, 0.0], [0.9, 0.1], [0.85, -0.05], [0.95, -0.1]])
    out = from_stroke(np.concatenate([circle, curl]), 64)
    assert shapely.Polygon(out).area == pytest.approx(np.pi, rel=0.05)
