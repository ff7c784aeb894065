import numpy as np
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from strategies import examples
from tentaclass import shapes
from tentaclass.datasets._wraps import (
    _bisect_lengths,
    _closure_gaps,
    _one_lap_lengths,
    _wrap_both_ways,
)
from tentaclass.wrapping._surface import _distance_to_outline, _radius_bucket


@st.composite
def star_outlines(draw):
    """A random star-shaped polygon (ccw) and points around it."""
    n = draw(st.integers(3, 60))
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    t = np.sort(rng.uniform(0, 2 * np.pi, n))
    t = t[np.r_[True, np.diff(t) > 1e-3]]
    if len(t) < 3:
        t = np.linspace(0, 2 * np.pi, 3, endpoint=False)
    r = rng.uniform(0.2, 2.0, len(t))
    outline = np.stack([r * np.cos(t), r * np.sin(t)], axis=1)
    points = rng.uniform(-3, 3, (50, 2))
    return outline, np.concatenate([points, outline])


@settings(max_examples=examples(60), deadline=None)
@given(star_outlines())
def test_distance_to_outline_matches_shapely(case):
    outline, points = case
    expected = shapely.distance(shapely.points(points), shapely.LinearRing(outline))
    np.testing.assert_allclose(_distance_to_outline(points, outline), expected, atol=1e-12)
    # the outline's own vertices lie on it
    np.testing.assert_allclose(_distance_to_outline(outline, outline), 0.0, atol=1e-12)


def test_radius_bucket():
    assert _radius_bucket(1.0) == 1.0
    assert _radius_bucket(8.0) == 8.0
    x = np.geomspace(0.01, 100, 2001)
    b = np.array([_radius_bucket(v) for v in x])
    assert np.all(np.abs(b / x - 1) <= 2 ** (1 / 2048) - 1 + 1e-12)  # half a step at most
    assert np.all(np.diff(b) >= 0)  # monotone
    near = [_radius_bucket(v) for v in np.linspace(1.0, 1.01, 200)]
    assert 10 < len(set(near)) < 30  # 0.07 % steps: nearby lengths share a bucket


def test_one_lap_lengths_do_not_depend_on_jobs():
    # hug mode on a notched square and two convex shapes, one wrap per chunk
    notch = np.array([[0, 0], [4, 0], [4, 4], [2.4, 4], [2.4, 2], [1.6, 2], [1.6, 4], [0, 4]],
                     float)  # fmt: skip
    outlines = [shapes.square(4.0), shapes.circle(2.0, n_points=64), notch,
                shapes.rectangle(6.0, 2.0)]  # fmt: skip
    starts = np.array([0.1, 0.3, 0.55, 0.8])
    cw = np.array([False, True, False, True])
    one = _one_lap_lengths(outlines, 16, starts, cw, "hug", n_jobs=1, chunk=1)
    two = _one_lap_lengths(outlines, 16, starts, cw, "hug", n_jobs=2, chunk=1)
    whole = _bisect_lengths(outlines, 16, starts, cw, "hug")
    np.testing.assert_array_equal(one, two)
    np.testing.assert_array_equal(one, whole)
    # convex shapes: the chain closes its lap, with chords a little shorter than arcs
    assert np.all((one[[0, 3]] > 0.85) & (one[[0, 3]] < 1.0))
    angles, *_ = _wrap_both_ways(outlines, 16, one, starts, np.zeros(4), cw, "hug")
    assert np.all(_closure_gaps(angles)[[0, 1, 3]] < 0.05)
