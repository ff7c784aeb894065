"""The compiled per-object geometry gives what shapely and scipy give."""

import itertools

import numpy as np
import pytest
import shapely
from scipy import ndimage

from tentaclass.scanner._geometry import (
    fill_holes,
    hull_ring,
    max_distance_outside,
    reaches_beyond,
    row_extremes,
)
from tentaclass.scanner.descriptors import pixel_hull


def _masks(n=400, seed=0):
    rng = np.random.default_rng(seed)
    for _ in range(n):
        h, w = rng.integers(1, 14, 2)
        m = rng.random((h, w)) < rng.random()
        if m.any():
            yield m


@pytest.mark.parametrize("corners", [True, False])
def test_hull_is_the_geos_hull_vertex_for_vertex(corners):
    for m in _masks():
        rows, first, last = row_extremes(m)
        if corners:
            x = np.concatenate([first - 0.5, first - 0.5, last + 0.5, last + 0.5])
            y = np.concatenate([rows - 0.5, rows + 0.5, rows - 0.5, rows + 0.5])
        else:
            x = np.concatenate([first, last]).astype(float)
            y = np.concatenate([rows, rows]).astype(float)
        ref = shapely.convex_hull(shapely.multipoints(np.stack([x, y], axis=1)))
        ours = pixel_hull(m, corners=corners)
        assert ours.geom_type == ref.geom_type
        if ref.geom_type == "Polygon":  # same ring, same start, same direction
            assert np.array_equal(np.asarray(ours.exterior.coords), np.asarray(ref.exterior.coords))
            assert np.array_equal(hull_ring(x, y.astype(float)), np.asarray(ref.exterior.coords))
        else:
            assert ours.equals(ref)


def test_batch_hulls_are_each_masks_hulls_and_the_cores_centre_hulls():
    from tentaclass.scanner._geometry import hulls_batch, mask_hull, measure_cores
    from tentaclass.scanner.descriptors import flatten_masks

    rng = np.random.default_rng(3)
    masks = list(_masks(n=300, seed=5))
    # wide blobs with a burr, whose cores are opened
    for _ in range(40):
        m = np.zeros((20, 24), dtype=bool)
        r0, c0 = rng.integers(1, 4, 2)
        m[r0 : r0 + 14, c0 : c0 + 16] = True
        m[rng.integers(4, 12), c0 + 16 : c0 + 16 + rng.integers(2, 7)] = True
        masks.append(m)
    batch = flatten_masks(masks)
    out = measure_cores(*batch[:4], 12.0)
    core, coords, starts, centres, centre_starts = out[1], out[2], out[3], out[10], out[11]
    assert not np.array_equal(core, out[0])  # some cores were opened
    ref, ref_starts = hulls_batch(core, *batch[1:4], False)
    assert np.array_equal(centres, ref) and np.array_equal(centre_starts, ref_starts)
    ref, ref_starts = hulls_batch(core, *batch[1:4], True)
    assert np.array_equal(coords, ref) and np.array_equal(starts, ref_starts)
    for corners in (True, False):
        xy, at = hulls_batch(*batch[:4], corners)
        for i, m in enumerate(masks):
            assert np.array_equal(xy[at[i] : at[i + 1]], mask_hull(m, corners))


def test_fill_holes_is_scipys():
    for m in _masks():
        assert np.array_equal(fill_holes(m), ndimage.binary_fill_holes(m))


def test_batch_fills_are_scipys_with_and_without_gaps_in_rows():
    from tentaclass.scanner._geometry import measure_batch
    from tentaclass.scanner.descriptors import flatten_masks

    rng = np.random.default_rng(4)
    masks = list(_masks(n=300, seed=6))
    for _ in range(100):  # discs: rows of one run, some with a hole or a bite
        size = int(rng.integers(3, 25))
        yy, xx = np.mgrid[:size, :size] - (size - 1) / 2
        m = yy**2 + xx**2 <= (size / 2) ** 2
        r, c = rng.integers(0, size, 2)
        m[r : r + int(rng.integers(0, 3)), c : c + int(rng.integers(0, 3))] = False
        masks.append(m)
    batch = flatten_masks(masks)
    filled = measure_batch(*batch[:4])[0]
    ref = np.concatenate([ndimage.binary_fill_holes(m).ravel() for m in masks])
    assert np.array_equal(filled, ref)
    one_run = [
        all(np.ptp(np.flatnonzero(row)) + 1 == row.sum() for row in m if row.any()) for m in masks
    ]
    assert 50 < sum(one_run) < len(masks) - 50


def test_distance_outside_a_convex_polygon_is_shapelys():
    rng = np.random.default_rng(1)
    ring = hull_ring(rng.normal(size=30), rng.normal(size=30))
    poly = shapely.polygons(ring)
    px, py = rng.normal(0, 2, 50), rng.normal(0, 2, 50)
    ref = shapely.distance(poly, shapely.points(np.stack([px, py], axis=1))).max()
    assert max_distance_outside(ring, px, py) == pytest.approx(ref, abs=1e-12)
    assert max_distance_outside(ring, px[:0], py[:0]) == 0.0


def test_reaches_beyond_is_the_largest_distance_outside_against_a_limit():
    rng = np.random.default_rng(2)
    ring = hull_ring(rng.normal(size=20), rng.normal(size=20))
    px, py = rng.normal(0, 2, 40), rng.normal(0, 2, 40)
    worst = max_distance_outside(ring, px, py)
    # each point's own distance as a limit: ties at the limit do not reach beyond
    limits = [max_distance_outside(ring, px[k : k + 1], py[k : k + 1]) for k in range(40)]
    for limit in [*limits, worst, np.nextafter(worst, 0), 0.0, 1.0, 10.0]:
        assert reaches_beyond(ring, px, py, limit) == (worst > limit)
    assert not reaches_beyond(ring, px[:0], py[:0], 0.0)


def test_opening_and_mask_hull_are_scipys_and_the_point_hulls():
    from skimage.morphology import disk

    from tentaclass.scanner._geometry import mask_hull, opening_cross

    for m in _masks(seed=3):
        assert np.array_equal(opening_cross(m), ndimage.binary_opening(m, disk(1).astype(bool)))
        rows, first, last = row_extremes(m)
        x = np.concatenate([first, last]).astype(float)
        y = np.concatenate([rows, rows]).astype(float)
        assert np.array_equal(mask_hull(m, False), hull_ring(x, y))


@pytest.mark.parametrize("eight", [True, False])
def test_groups_are_numbered_and_listed_as_ndimage_does(eight):
    from tentaclass.scanner._geometry import label_runs

    for m in _masks(seed=5):
        lab, n = ndimage.label(m, np.ones((3, 3), bool) if eight else None)
        idx = ndimage.value_indices(lab, ignore_value=0)
        rr, cc, starts = label_runs(m, eight)
        assert len(starts) == n + 1
        for k in range(1, n + 1):
            a, b = starts[k - 1], starts[k]
            assert np.array_equal(rr[a:b], idx[k][0]) and np.array_equal(cc[a:b], idx[k][1])


@pytest.mark.parametrize("corners", [True, False])
def test_bounding_radius_is_shapelys_to_the_last_bit(corners):
    from tentaclass.scanner._geometry import bounding_radii, mask_hull

    rings = [mask_hull(m, corners) for m in _masks(n=600, seed=7)]
    rings = [r for r in rings if len(r) >= 4]
    polys = [shapely.polygons(r) for r in rings]
    starts = np.r_[0, np.cumsum([len(r) - 1 for r in rings])]
    ours = bounding_radii(np.concatenate([r[:-1] for r in rings]), starts)
    assert np.array_equal(ours, shapely.minimum_bounding_radius(polys))


def _hull_rings(corners, n=600, seed=11):
    from tentaclass.scanner._geometry import mask_hull

    rings = [mask_hull(m, corners) for m in _masks(n=n, seed=seed)]
    return [r for r in rings if len(r) >= 4]


@pytest.mark.parametrize("corners", [True, False])
def test_rotated_rectangle_is_shapelys_to_the_last_bit(corners):
    from tentaclass.scanner.descriptors import rectangles_of_rings

    rings = _hull_rings(corners)
    starts = np.r_[0, np.cumsum([len(r) for r in rings])]
    xy, rects = rectangles_of_rings(np.concatenate(rings), starts)
    ref = shapely.oriented_envelope([shapely.polygons(r) for r in rings])
    ref_xy = shapely.get_coordinates(ref).reshape(-1, 5, 2)
    assert np.array_equal(xy, ref_xy)
    assert np.array_equal(np.signbit(xy), np.signbit(ref_xy))  # down to the zeros' signs
    assert shapely.equals_exact(rects, ref, tolerance=0).all()


def test_double_double_orientation_decides_what_the_fast_test_cannot():
    from tentaclass.scanner._geometry import _orientation

    # nearly collinear: the double determinant is lost in rounding, the exact sign is not
    assert _orientation(0.0, 0.0, 1.0, 1.0, 0.5, 0.5) == 0
    assert _orientation(0.0, 0.0, 1.0, 1.0, 0.5, 0.5 + 2**-52) == 1
    assert _orientation(0.0, 0.0, 1.0, 1.0, 0.5, 0.5 - 2**-53) == -1
    assert _orientation(0.1, 0.1, 0.3, 0.3, 0.7, 0.7 + 1e-17) == _orientation(
        0.1, 0.1, 0.3, 0.3, 0.7, 0.7
    )


def test_line_intersection_is_exact_and_none_for_parallel_lines():
    from tentaclass.scanner._geometry import _line_intersection

    assert _line_intersection(0.0, 0.0, 2.0, 2.0, 0.0, 2.0, 2.0, 0.0) == (1.0, 1.0)
    assert np.isnan(_line_intersection(0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 1.0)).all()


def test_chord_walk_angles_are_the_numpy_pipelines_to_the_last_bit():
    from tentaclass.geometry import points_to_angles, resample_closed
    from tentaclass.scanner._geometry import hull_descriptors

    rings = _hull_rings(True, seed=3)
    starts = np.r_[0, np.cumsum([len(r) for r in rings])]
    ones = np.ones(len(rings))
    _, cross, dot, bad = hull_descriptors(np.concatenate(rings), starts, ones, ones, ones, 64)
    assert not bad
    ours = np.arctan2(cross, dot)
    for r, q in zip(rings, ours, strict=True):
        walk = resample_closed(r[:-1][None], 64)
        assert np.array_equal(q, points_to_angles(walk, closed=True)[0])


def test_hull_scalars_are_numpys_of_shapelys_measures():
    from tentaclass.scanner._geometry import hull_descriptors

    xy, starts, polys = _ragged(_hull_rings(True, seed=4), shift_seed=3)
    rng = np.random.default_rng(0)
    long, short = rng.uniform(5, 9, len(polys)), rng.uniform(1, 5, len(polys))
    pixels = rng.integers(1, 200, len(polys)).astype(float)
    scalars = hull_descriptors(xy, starts, long, short, pixels, 16)[0]
    area, perimeter = shapely.area(polys), shapely.length(polys)
    radius = shapely.minimum_bounding_radius(polys)
    expected = np.stack(
        [
            area / (long * short),
            short / long,
            4 * np.pi * area / perimeter**2,
            area / (np.pi * radius**2),
            1.0 / np.sqrt(pixels),
        ],
        axis=1,
    )
    assert np.array_equal(scalars, expected)


def _ragged(rings, shift_seed=None):
    rng = np.random.default_rng(shift_seed)
    if shift_seed is not None:  # away from the origin, where rounding shows
        rings = [r + rng.uniform(0, 3000, 2).round(0) + 0.25 * rng.integers(0, 4) for r in rings]
    starts = np.r_[0, np.cumsum([len(r) for r in rings])]
    return np.concatenate(rings), starts, [shapely.polygons(r) for r in rings]


@pytest.mark.parametrize("corners", [True, False])
def test_hull_area_length_radius_are_shapelys_to_the_last_bit(corners):
    from tentaclass.scanner._geometry import hull_measures

    xy, starts, polys = _ragged(_hull_rings(corners, seed=5), shift_seed=1)
    area, length, radius = hull_measures(xy, starts)
    assert np.array_equal(area, shapely.area(polys))
    assert np.array_equal(length, shapely.length(polys))
    assert np.array_equal(radius, shapely.minimum_bounding_radius(polys))


def _disc_hulls(n=300, seed=0):
    """Centre and corner hulls of discs, ellipses and cut discs up to 40 px wide."""
    from tentaclass.scanner._geometry import mask_hull

    rng = np.random.default_rng(seed)
    rings = []
    for _ in range(n):
        size = int(rng.integers(4, 41))
        yy, xx = np.mgrid[:size, :size] - (size - 1) / 2
        a, b = rng.uniform(0.3, 1.0, 2) * size / 2
        t = rng.uniform(0, np.pi)
        u, v = xx * np.cos(t) + yy * np.sin(t), yy * np.cos(t) - xx * np.sin(t)
        m = (u / a) ** 2 + (v / b) ** 2 <= 1
        if rng.random() < 0.5:  # a straight cut, as a broken corner makes
            m &= xx * rng.normal() + yy * rng.normal() < rng.uniform(0, size / 3)
        if m.any():
            rings += [mask_hull(m, True), mask_hull(m, False)]
    return [r for r in rings if len(r) >= 4]


@pytest.mark.parametrize("tolerance", [0.1, 0.25, 0.5, 1.0, 3.0])
def test_simplified_rings_are_shapelys_coordinate_for_coordinate(tolerance):
    from tentaclass.scanner._geometry import hull_ring, simplify_rings

    rng = np.random.default_rng(7)
    rings = _hull_rings(False, seed=2) + _hull_rings(True, seed=3) + _disc_hulls()
    for _ in range(400):  # hulls of scattered points, on the integer grid and off it
        pts = rng.normal(size=(int(rng.integers(3, 40)), 2)) * rng.uniform(0.3, 20)
        if rng.random() < 0.5:
            pts = pts.round()
        rings.append(hull_ring(*np.ascontiguousarray(pts.T)))  # the C-order rows it is compiled for
    xy, starts, polys = _ragged([r for r in rings if len(r) >= 4], shift_seed=4)
    ours, ours_starts = simplify_rings(xy, starts, tolerance)
    ref_xy, index = shapely.get_coordinates(shapely.simplify(polys, tolerance), return_index=True)
    # some rings lose points, some their first point too (the ring then starts elsewhere)
    assert (np.diff(ours_starts) < np.diff(starts)).sum() > 40
    assert (ours[ours_starts[:-1]] != xy[starts[:-1]]).any(axis=1).sum() >= 1
    assert np.array_equal(ours_starts, np.searchsorted(index, np.arange(len(polys) + 1)))
    assert np.array_equal(ours, ref_xy)


def test_bounding_circle_outline_is_shapelys_to_the_last_bit():
    from tentaclass.scanner._geometry import circle_outlines

    xy, starts, polys = _ragged(_hull_rings(False, seed=9), shift_seed=2)
    ours, ours_starts, polygon, centroid = circle_outlines(xy, starts)
    ref = shapely.minimum_bounding_circle(polys)
    ref_xy, index = shapely.get_coordinates(ref, return_index=True)
    assert polygon.all() and np.array_equal(shapely.get_type_id(ref), np.full(len(polys), 3))
    assert np.array_equal(ours, ref_xy)  # same vertices, same start, same direction
    assert np.array_equal(ours_starts, np.searchsorted(index, np.arange(len(polys) + 1)))
    assert np.array_equal(centroid, shapely.get_coordinates(shapely.centroid(ref)))


@pytest.mark.parametrize("outline", ["hull", "rectangle", "circle", "tilted"])
def test_outline_area_bounds_and_orientation_are_shapelys(outline):
    from tentaclass.scanner._geometry import circle_outlines, min_area_rectangles, outline_measures

    xy, starts, polys = _ragged(_hull_rings(outline != "hull", seed=13), shift_seed=3)
    if outline == "rectangle":
        xy = min_area_rectangles(xy, starts).reshape(-1, 2)
        starts = np.arange(0, xy.shape[0] + 1, 5)
    elif outline == "circle":
        xy, starts = circle_outlines(xy, starts)[:2]
    elif outline == "tilted":  # clockwise and counter-clockwise rings of any direction
        rng = np.random.default_rng(4)
        rings = [xy[a:b] for a, b in itertools.pairwise(starts)]
        rings = [r[::-1] if rng.random() < 0.5 else r for r in rings]
        t = rng.uniform(0, 2 * np.pi)
        rot = np.array([[np.cos(t), -np.sin(t)], [np.sin(t), np.cos(t)]])
        xy = np.concatenate(rings) @ rot
    polys = [shapely.polygons(xy[a:b]) for a, b in itertools.pairwise(starts)]
    area, bounds, oriented = outline_measures(xy, starts, np.ones(len(polys), dtype=bool))
    assert np.array_equal(area, shapely.area(polys))
    assert np.array_equal(bounds, shapely.bounds(polys))
    assert np.array_equal(oriented, shapely.get_coordinates(shapely.orient_polygons(polys)))


@pytest.mark.parametrize("n_harmonics, n_points", [(33, 64), (0, 64), (-1, 64), (2, 3)])
def test_hull_features_refuse_harmonics_the_walk_cannot_hold(n_harmonics, n_points):
    from tentaclass.errors import InputError
    from tentaclass.scanner.descriptors import features_matrix, measure

    g = measure(np.pad(np.ones((20, 30), dtype=bool), 2))
    with pytest.raises(InputError, match="n_harmonics must be"):
        features_matrix([g], n_points=n_points, n_harmonics=n_harmonics)
    # the largest valid number of harmonics gives the walk's spectrum
    k = n_points // 2
    assert features_matrix([g], n_points=n_points, n_harmonics=k).shape == (1, 5 + k)


@pytest.mark.parametrize("margin", [-0.1, -0.6, -1.5, 0.0, 0.3])
def test_defect_canvas_holds_every_pixel_inside_the_grown_outline(margin):
    """The canvas stops where the outline grown by -margin ends, at most 2 px beyond it."""
    from tentaclass.scanner import _geometry as geo
    from tentaclass.scanner.defects import _expected_rings

    rng = np.random.default_rng(3)
    masks = list(_masks(n=300, seed=8))
    for _ in range(60):  # slivers: their triangles have sharp corners
        m = np.zeros((int(rng.integers(3, 30)), int(rng.integers(3, 30))), dtype=bool)
        rr = np.linspace(0, m.shape[0] - 1, 200)
        cc = np.linspace(0, m.shape[1] - 1, 200) * rng.uniform(0.2, 1.0)
        m[rr.round().astype(int), cc.round().astype(int)] = True
        masks.append(m)
    rings = [geo.mask_hull(m, False) for m in masks]
    starts = np.r_[0, np.cumsum([len(r) for r in rings])]
    labels = rng.choice(["square", "circle", "triangle", "other"], len(masks))
    xy, out_starts, polygon, circles, code = _expected_rings(np.concatenate(rings), starts, labels)
    n = len(masks)
    heights = np.array([m.shape[0] for m in masks])
    widths = np.array([m.shape[1] for m in masks])
    ones = np.ones(n)
    kind, lo, canvas, frame, ccw, *_ = geo.defect_setup(
        xy, out_starts, polygon, code == geo.CIRCLE, code == geo.TRIANGLE, heights, widths,
        ones * 50, ones * 5, ones * 9, 4.0, 0.003, 1.5, circles, margin,
    )  # fmt: skip
    checked = smaller = 0
    for i in np.flatnonzero(kind):
        ring = ccw[out_starts[i] : out_starts[i + 1]]
        x1, y1 = ring.max(axis=0)
        # the frame: the outline and the mask with 2 pixels to spare
        h = int(np.ceil(max(y1, heights[i]) + 2)) - frame[i, 0]
        w = int(np.ceil(max(x1, widths[i]) + 2)) - frame[i, 1]
        sd = np.empty((h, w))
        scratch = np.empty(len(ring))
        geo._signed_distance(
            kind[i], ring, circles[i], frame[i, 0], frame[i, 1], h, w, sd, scratch,
            scratch.copy(), scratch.copy(),
        )  # fmt: skip
        rows, cols = np.nonzero(sd >= margin)
        rows, cols = rows + frame[i, 0], cols + frame[i, 1]
        top, left = lo[i]
        bottom, right = lo[i] + canvas[i]
        assert top <= 0 and left <= 0 and bottom >= heights[i] and right >= widths[i]
        assert (top >= frame[i, 0]) and (left >= frame[i, 1]) and bottom <= frame[i, 0] + h
        assert ((rows >= top) & (rows < bottom) & (cols >= left) & (cols < right)).all()
        checked += 1
        smaller += canvas[i].prod() < h * w
    assert checked > 200 and smaller > checked / 2


@pytest.mark.parametrize(
    ("mask", "match"),
    [
        # an empty mask measured a rectangle of uninitialised memory (2e-321), crop failed
        # with an IndexError, and other arrays with AttributeError or AxisError
        (np.zeros((3, 3), bool), r"holds no object pixels \(shape \(3, 3\)\)"),
        (np.ones(4, bool), r"must be 2-D|at least 2 dimensions"),
        ([[0, 2], [1, 0]], "must hold only 0 and 1, found 2$"),  # was np.int64(2)
        (None, r"at least 2 dimensions, got shape \(\)"),
    ],
)
def test_measure_and_crop_refuse_what_is_not_an_object_mask(mask, match):
    from tentaclass.errors import InputError
    from tentaclass.scanner import crop, measure

    with pytest.raises(InputError, match=match):
        measure(mask)
    with pytest.raises(InputError, match=match):
        crop(mask)
    assert measure([[0, 1], [1, 1]]).area == 3 and crop([[0, 0], [0, 1]])[1:] == (1, 1)
