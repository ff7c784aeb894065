import numpy as np
import pytest
import shapely

from tentaclass.datasets import DRAWN_CLASSES, drawn_shapes
from tentaclass.errors import InputError
from tentaclass.shapes import from_stroke


def test_drawn_shapes_layout_and_seed():
    d = drawn_shapes(3, random_state=4)
    assert d.target.tolist() == [c for c in DRAWN_CLASSES for _ in range(3)]
    assert all(s.ndim == 2 and s.shape[1] == 2 and 40 <= len(s) < 200 for s in d.strokes)
    again = drawn_shapes(3, random_state=4)
    assert all(np.array_equal(a, b) for a, b in zip(d.strokes, again.strokes, strict=True))
    other = drawn_shapes(3, random_state=5)
    assert not np.array_equal(d.strokes[0], other.strokes[0])


def test_drawn_strokes_are_uneven_and_not_closed():
    d = drawn_shapes(10, random_state=1)
    gaps, spread = [], []
    for s in d.strokes:
        step = np.hypot(*np.diff(s, axis=0).T)
        spread.append(step.max() / np.median(step))
        gaps.append(np.hypot(*(s[-1] - s[0])) / np.ptp(s, axis=0).max())
    assert np.median(spread) > 2  # uneven spacing
    assert min(gaps) > 0  # never exactly closed
    sizes = [np.ptp(s, axis=0).max() for s in d.strokes]
    assert min(sizes) < 200 < max(sizes)


def test_drawn_shapes_bad_arguments():
    with pytest.raises(InputError, match="classes"):
        drawn_shapes(2, classes=("hexagon",))
    with pytest.raises(InputError, match="random_state"):
        drawn_shapes(2, random_state=-1)
    with pytest.raises(ValueError, match="n_per_class"):
        drawn_shapes(0)


def test_every_drawn_stroke_cleans_to_a_simple_outline():
    d = drawn_shapes(8, random_state=3)
    for s in d.strokes:
        out = from_stroke(s, 128)
        assert out.shape == (128, 2)
        assert shapely.LinearRing(out).is_simple
