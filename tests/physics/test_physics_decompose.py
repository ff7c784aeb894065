"""Convex pieces of simple polygons tile them exactly."""

import numpy as np
import pytest
import shapely

from tentaclass.physics import convex_pieces
from tentaclass.shapes import circle, polygon, square


def _star(n, rng):
    ang = np.sort(rng.uniform(0, 2 * np.pi, n))
    rad = rng.uniform(0.3, 1.0, n)
    return polygon(np.c_[rad * np.cos(ang), rad * np.sin(ang)])


def _check(outline):
    pieces = convex_pieces(outline)
    body = shapely.Polygon(outline)
    polys = [shapely.Polygon(p) for p in pieces]
    for p in polys:  # convex, counter-clockwise, no area lost
        assert p.is_valid and p.exterior.is_ccw
        assert shapely.convex_hull(p).area == pytest.approx(p.area, rel=1e-9, abs=1e-12)
    assert sum(p.area for p in polys) == pytest.approx(body.area, rel=1e-9)
    assert shapely.symmetric_difference(shapely.union_all(polys), body).area < 1e-9 * body.area
    return pieces


@pytest.mark.parametrize("seed", range(5))
def test_random_star_polygons_are_tiled(seed):
    _check(_star(40, np.random.default_rng(seed)))


def test_convex_outline_is_one_piece():
    assert len(_check(circle(1.0))) == 1
    assert len(_check(square(2.0))) == 1


def test_c_shape_needs_several_pieces():
    c = polygon([(0, 0), (6, 0), (6, 1), (2, 1), (2, 3), (4, 3), (4, 4), (0, 4)])
    assert 3 <= len(_check(c)) <= 6


def test_bad_outline_raises():
    with pytest.raises(ValueError, match="intersects itself"):
        convex_pieces([(0, 0), (1, 1), (1, 0), (0, 1)])
