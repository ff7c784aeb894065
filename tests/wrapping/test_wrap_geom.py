"""The compiled geometric tests of the walk against shapely and against each other."""

import numpy as np
import shapely
from test_wrap import star

from tentaclass.wrapping._geom import (
    crosses,
    crosses_boxed,
    crosses_range_boxed,
    crossing_edge,
    crossing_edge_boxed,
    crossing_edge_range,
    edge_boxes,
    enters_convex,
    inside,
    inside_boxed,
    locate,
    outline_distances,
)


def frozen(a):
    """``a`` read-only, as a wrap's surface holds its outline and curves (the kernels' types)."""
    a = np.ascontiguousarray(a, dtype=float)
    a.setflags(write=False)
    return a


def random_segments(rng, n, lo, hi):
    return rng.uniform(lo, hi, (n, 2, 2))


def test_blocked_crossing_test_agrees_with_the_plain_one(rng):
    # 100 vertices: the edges fall in 7 blocks, the last one short, in one group
    outline = frozen(star(50, 1.0, 2.0, 0.1))
    boxes = edge_boxes(outline)
    assert boxes.shape == (7 + 1, 4)
    lo, hi = outline.min(axis=0), outline.max(axis=0)
    np.testing.assert_array_equal(boxes[7], [lo[0], hi[0], lo[1], hi[1]])  # the group's box
    segs = random_segments(rng, 3000, -2.5, 2.5)
    eps = 1e-12 * 4.0**2
    plain = [crosses(*a, *b, outline, eps) for a, b in segs]
    boxed = [crosses_boxed(*a, *b, outline, eps, boxes) for a, b in segs]
    assert plain == boxed
    assert 0.2 < np.mean(plain) < 0.9  # both kinds of segment are drawn


def test_entering_a_convex_polygon_agrees_with_shapely(rng):
    hull = np.asarray(shapely.Polygon(star(5, 0.8, 2.0)).convex_hull.exterior.coords)[:-1]
    hull = frozen(hull if shapely.LinearRing(hull).is_ccw else hull[::-1])
    body = shapely.Polygon(hull).buffer(-1e-9)
    segs = random_segments(rng, 3000, -3.0, 3.0)
    got = np.array([enters_convex(*a, *b, hull, 1e-12) for a, b in segs])
    want = shapely.length(shapely.intersection(shapely.linestrings(segs), body)) > 0
    np.testing.assert_array_equal(got, want)
    assert 0.2 < got.mean() < 0.9
    # along an edge, ending on the outline, touching a vertex: not inside
    a, b = hull[0], hull[1]
    assert not enters_convex(*a, *b, hull, 1e-12)
    assert not enters_convex(*(2 * a - b), *a, hull, 1e-12)
    assert enters_convex(*a, *hull[2], hull, 1e-12)


def test_a_segment_cutting_a_sliver_off_a_convex_polygon_enters_it():
    # from 1.4e-6 left of the square's corner, a link 1.4 below its bottom edge
    # to its right edge cuts a sliver 7e-7 wide: inside by far more than the
    # crossing test's own side test (1e-12 in signed area) resolves
    square = frozen([[0.0, 0.0], [3.0, 0.0], [3.0, 3.0], [0.0, 3.0]])
    a, b = (2.9999986, -1.425), (3.0, 1.425)
    assert enters_convex(*a, *b, square, 1e-12)
    assert crosses(*a, *b, square, 1e-12)
    # the same link through the corner (tip beyond it, in the air) stays outside
    assert not enters_convex(*a, 3.0000014, 1.425, square, 1e-12)


def test_blocked_crossing_edge_and_inside_agree_with_the_plain_ones(rng):
    outline = frozen(star(150, 1.0, 2.0, 0.1))  # 19 blocks in 3 groups
    boxes = edge_boxes(outline)
    eps = 1e-12 * 4.0**2
    segs = random_segments(rng, 2000, -2.5, 2.5)
    plain = [crossing_edge(*a, *b, outline, eps) for a, b in segs]
    boxed = [crossing_edge_boxed(*a, *b, outline, eps, boxes) for a, b in segs]
    assert plain == boxed  # the same (first) edge, not just the same verdict
    pts = rng.uniform(-2.5, 2.5, (2000, 2))
    pts[:100] = outline[rng.integers(0, len(outline), 100)]  # on the outline: not inside
    r = np.sqrt(eps)
    got = [inside_boxed(x, y, outline, r, boxes) for x, y in pts]
    assert got == [inside(x, y, outline, r) for x, y in pts]
    want = shapely.contains_xy(shapely.Polygon(outline).buffer(-1e-5), pts[:, 0], pts[:, 1])
    assert not any(got[:100])
    np.testing.assert_array_equal(np.array(got)[100:], want[100:])


def test_outline_distances_equal_shapely_bit_for_bit(rng):
    outline = star(40, 1.0, 2.0, 0.1)
    outline[5] = outline[4]  # a zero-length edge
    outline = frozen(outline)
    pts = np.concatenate([rng.uniform(-3, 3, (1500, 2)), outline, 0.5 * (outline + outline[0])])
    got = outline_distances(pts, outline, edge_boxes(outline))
    want = shapely.distance(shapely.LinearRing(outline), shapely.points(pts))
    np.testing.assert_array_equal(got, want)
    assert np.sum(got == 0) >= len(outline)


def test_locate_finds_the_first_nearest_edge_of_a_plain_scan(rng):
    curve = frozen(star(60, 1.0, 2.0, 0.1))
    mids = 0.5 * (curve + np.roll(curve, 1, 0))
    pts = np.concatenate([rng.uniform(-3, 3, (500, 2)), curve, mids])
    e, t, p = locate(pts, curve)
    a, b = curve, np.roll(curve, -1, axis=0)
    d = b - a
    A = np.sum(d * d, axis=1)
    x, y = pts[:, None, 0], pts[:, None, 1]
    tt = np.clip(((x - a[:, 0]) * d[:, 0] + (y - a[:, 1]) * d[:, 1]) / A, 0, 1)
    cx, cy = a[:, 0] + tt * d[:, 0], a[:, 1] + tt * d[:, 1]
    want = np.argmin((cx - x) ** 2 + (cy - y) ** 2, axis=1)  # the first of equal ones
    np.testing.assert_array_equal(e, want)
    rows = np.arange(len(pts))
    np.testing.assert_array_equal(t, tt[rows, want])
    np.testing.assert_array_equal(p, np.stack([cx[rows, want], cy[rows, want]], axis=1))


def test_blocked_range_crossing_test_agrees_with_the_plain_one(rng):
    outline = frozen(star(50, 1.0, 2.0, 0.1))
    boxes = edge_boxes(outline)
    eps = 1e-12 * 4.0**2
    segs = random_segments(rng, 400, -2.5, 2.5)
    ranges = [(0, 100), (5, 40), (90, 30), (16, 16), (33, 1), (99, 100), (47, 70)]
    hits = 0
    for a, b in segs:
        for first, count in ranges:
            want = crossing_edge_range(*a, *b, outline, eps, first, count) >= 0
            assert crosses_range_boxed(*a, *b, outline, eps, first, count, boxes) == want
            hits += want
    assert 0.1 < hits / (len(segs) * len(ranges)) < 0.9


def test_search_over_track_blocks_finds_what_the_edge_by_edge_search_finds(rng):
    from tentaclass.wrapping._kernel import _search, track_blocks
    from tentaclass.wrapping._surface import _edge_theta

    pts = frozen(star(100, 1.0, 2.0, 0.1))  # 200 vertices: 12 whole blocks
    m = len(pts)
    off = np.array([0, m])
    off.setflags(write=False)
    theta = frozen(_edge_theta(pts))
    dev = frozen(np.where(rng.uniform(size=m) < 0.2, 0.3, 0.0))
    es, spt = np.array([7]), pts[7:8] + 0.5 * (pts[8] - pts[7])
    boff, boxes, top_dev, seg_len = track_blocks(pts, off, dev)
    blind = np.tile([-np.inf, np.inf, -np.inf, np.inf], (len(boxes), 1))  # never clear
    skipped = 0
    for _ in range(300):
        j = int(rng.integers(1, m))
        p = pts[(7 + j) % m]
        ln, limit, skip = rng.uniform(0.05, 1.5), rng.uniform(5.0, 300.0), bool(rng.integers(2))
        # a circle about a point further along the track (or near the cursor)
        ahead = pts[(7 + j + int(rng.integers(0, 150))) % m]
        a = ahead + ln * np.array([np.cos(phi := rng.uniform(0, 2 * np.pi)), np.sin(phi)])
        common = (a[0], a[1], ln, 0, j, p[0], p[1], skip, 0.1, limit, pts, off, theta, dev, es,
                  spt, theta[7], spt[0], 0.0, 3, boff)  # fmt: skip
        got = _search(*common, boxes, top_dev, seg_len)
        want = _search(*common, blind, top_dev, seg_len)
        assert got == want
        skipped += got[0] == 0 and (got[1] > 0 or got[2] - j > 32)
    assert skipped > 100  # searches that ran past whole blocks
