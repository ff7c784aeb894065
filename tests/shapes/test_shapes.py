import shutil

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from strategies import examples
from tentaclass import shapes
from tentaclass.errors import InputError, ShapeError
from wrap_checks import MPEG7, needs_mpeg7


def _ccw_simple(p):
    assert p.ndim == 2 and p.shape[1] == 2
    assert shapes.signed_area(p) > 0
    assert shapely.LinearRing(p).is_simple
    assert not np.array_equal(p[0], p[-1])


@pytest.mark.parametrize(
    "outline, area",
    [
        (shapes.square(4), 16.0),
        (shapes.rectangle(6, 2), 12.0),
        (shapes.triangle([(0, 0), (3, 0), (0, 1)]), 1.5),
        (shapes.triangle(side=2.0), np.sqrt(3)),
        (shapes.regular_polygon(6, 1.0), 3 * np.sqrt(3) / 2),
        (shapes.circle(2.0, n_points=4096), np.pi * 4),
    ],
)
def test_primitives_are_ccw_with_the_right_area(outline, area):
    _ccw_simple(outline)
    assert shapes.signed_area(outline) == pytest.approx(area, rel=1e-5)


def test_square_and_rectangle_start_at_a_corner():
    assert shapes.square(4)[0].tolist() == [-2.0, -2.0]
    assert shapes.rectangle(6, 2)[1].tolist() == [3.0, -1.0]
    assert shapes.circle(3.0)[0].tolist() == [3.0, 0.0]


def test_polygon_orients_and_drops_closing_point():
    cw = [(0, 0), (0, 1), (1, 1), (1, 0), (0, 0)]
    p = shapes.polygon(cw)
    assert len(p) == 4
    _ccw_simple(p)
    assert shapes.polygon(p[::-1]).tolist() == p.tolist()


@pytest.mark.parametrize(
    "points, match",
    [
        ([(0, 0), (1, 0), (np.nan, 1)], "NaN"),
        ([(0, 0), (1, 0), (1, 0), (0, 0)], "fewer than 3 distinct"),
        ([(0, 0), (1, 1), (2, 2)], "zero area"),
        ([(0, 0), (4, 0), (4, 4), (2, -1), (0, 4)], "intersects itself"),
        ([(0, 0), (0, 0), (0, 0)], "fewer than 3 distinct"),
        ([(0, 0), (1, 1), (1, 0), (0, 1)], "intersects itself"),
        ([(0, 0), (1e300, 0), (1e300, 1e300)], "too large or too small"),
        ([(0, 0), (1e-300, 0), (1e-300, 1e-300)], "too large or too small"),
        ([(0, 0), (1, 0), (0, 1j)], "complex"),  # the imaginary part must not be dropped
    ],
)
def test_polygon_rejects_bad_outlines(points, match):
    with pytest.raises(InputError, match=match):
        shapes.polygon(points)


def test_bad_arguments():
    with pytest.raises(ShapeError):
        shapes.polygon([1.0, 2.0, 3.0])
    with pytest.raises(InputError):
        shapes.square(0)
    with pytest.raises(InputError):
        shapes.circle(1.0, n_points=2)
    with pytest.raises(InputError, match="3 distinct vertices"):
        shapes.triangle([(0, 0), (1, 0), (1, 1), (0, 1)])


@settings(max_examples=examples(50), deadline=None)
@given(st.integers(3, 40), st.integers(0, 2**31 - 1))
def test_polygon_of_star_shaped_points_is_valid(n, seed):
    rng = np.random.default_rng(seed)
    a = np.sort(rng.uniform(0, 2 * np.pi, n))
    a = a[np.r_[True, np.diff(a) > 1e-3]]
    if len(a) < 3 or np.max(np.diff(np.r_[a, a[0] + 2 * np.pi])) >= np.pi:
        return
    r = rng.uniform(0.5, 2.0, len(a))
    pts = np.stack([r * np.cos(a), r * np.sin(a)], axis=1)[::-1]  # clockwise in
    p = shapes.polygon(pts)
    _ccw_simple(p)
    assert len(p) == len(a)


def test_from_mask_rectangle_and_frame():
    img = np.zeros((10, 12), bool)
    img[2:5, 3:10] = True
    out = shapes.from_mask(img)
    _ccw_simple(out)
    assert out[:, 0].min() == pytest.approx(2.5) and out[:, 0].max() == pytest.approx(9.5)
    # rows 2..4 -> y = -2..-4, half-pixel boundary; the image y axis is flipped
    assert out[:, 1].max() == pytest.approx(-1.5) and out[:, 1].min() == pytest.approx(-4.5)
    assert shapes.signed_area(out) == pytest.approx(7 * 3 - 0.5, abs=0.6)


def test_from_mask_largest_component_holes_and_border():
    img = np.zeros((20, 20), np.uint8)
    img[0:12, 0:12] = 255  # touches the border
    img[4:8, 4:8] = 0  # a hole: ignored
    img[15:17, 15:17] = 255  # a speck: ignored
    out = shapes.from_mask(img)
    assert out[:, 0].max() < 12 and out[:, 1].min() > -12
    assert shapes.signed_area(out) == pytest.approx(144 - 0.5, abs=1.0)


def test_from_mask_errors():
    with pytest.raises(InputError, match="no foreground"):
        shapes.from_mask(np.zeros((5, 5)))
    with pytest.raises(ShapeError):
        shapes.from_mask(np.ones(5))


@pytest.mark.slow
@pytest.mark.mpeg7
@needs_mpeg7
def test_load_mpeg7():
    # the session's cache, which the other MPEG-7 tests share: the folder is decoded
    # once per run (the round trip through a cache is tested on a few files below)
    outlines, labels, names = shapes.load_mpeg7(MPEG7, max_vertices=1000)
    assert len(outlines) == len(labels) == len(names) == 1400
    classes, counts = np.unique(labels, return_counts=True)
    assert len(classes) == 70 and set(counts) == {20}
    assert {"Bone", "HCircle", "device9", "brick", "rat", "Glas"} <= set(classes)
    assert labels[names.index("brick-01.png")] == "brick"
    assert max(len(o) for o in outlines) <= 1000
    for o in outlines[::50]:
        _ccw_simple(o)
    # inverted files come out as objects, not as the image frame
    for name in ("rat-09.png", "Glas-12.png"):
        o = outlines[names.index(name)]
        area = shapes.signed_area(o)
        assert 0 < area < 0.9 * np.prod(np.ptp(o, axis=0) + 1)


@needs_mpeg7
def test_load_mpeg7_cache_round_trip(tmp_path):
    folder = tmp_path / "few"
    folder.mkdir()
    for name in ("rat-09.png", "Glas-12.png", "brick-01.png", "device9-3.png"):
        shutil.copy(MPEG7 / name, folder / name)
    cold = shapes.load_mpeg7(folder, max_vertices=1000, cache=tmp_path / "cache")
    assert list((tmp_path / "cache").glob("mpeg7-*.npz"))
    warm = shapes.load_mpeg7(folder, max_vertices=1000, cache=tmp_path / "cache")
    decoded = shapes.load_mpeg7(folder, max_vertices=1000, cache=False)
    for got in (warm, decoded):
        assert got[2] == cold[2] and got[1].tolist() == cold[1].tolist()
        assert all(np.array_equal(a, b) for a, b in zip(cold[0], got[0], strict=True))


def test_load_mpeg7_missing_folder(tmp_path):
    with pytest.raises(InputError, match="does not exist"):
        shapes.load_mpeg7(tmp_path / "nope")
    with pytest.raises(InputError, match=r"no \.png"):
        shapes.load_mpeg7(tmp_path, cache=False)


def test_from_mask_ragged_names_the_argument():
    with pytest.raises(ShapeError, match="image: rows have different lengths"):
        shapes.from_mask([[0, 1, 1], [1, 1]])


def test_load_mpeg7_skips_unreadable_images_with_a_warning(tmp_path):
    from PIL import Image

    from tentaclass.errors import TentaclassWarning

    img = np.zeros((20, 30), np.uint8)
    img[5:15, 5:25] = 255
    Image.fromarray(img).save(tmp_path / "bar-1.png")
    Image.fromarray(img.T.copy()).save(tmp_path / "bar-2.png")
    (tmp_path / "broken-1.png").write_bytes(b"not a png")
    Image.fromarray(np.zeros((9, 9), np.uint8)).save(tmp_path / "empty-1.png")
    with pytest.warns(TentaclassWarning, match=r"2 unreadable.*broken-1\.png.*empty-1\.png"):
        outlines, labels, names = shapes.load_mpeg7(tmp_path, cache=False)
    assert names == ["bar-1.png", "bar-2.png"] and labels.tolist() == ["bar", "bar"]
    assert len(outlines) == 2


def test_read_silhouette_refuses_unreadable_and_oversized_images(tmp_path, monkeypatch):
    from PIL import Image

    (tmp_path / "junk.png").write_bytes(b"not a png")
    with pytest.raises(InputError, match=r"junk\.png: cannot read the image \(Unidentified"):
        shapes.read_silhouette(tmp_path / "junk.png")
    # beyond Pillow's pixel limit: a DecompressionBombError traceback from tentaclass wrap --mask
    Image.new("1", (64, 64)).save(tmp_path / "big.png")
    monkeypatch.setattr(Image, "MAX_IMAGE_PIXELS", 1000)
    with pytest.raises(InputError, match=r"big\.png: cannot read the image \(DecompressionBomb"):
        shapes.read_silhouette(tmp_path / "big.png")
    with pytest.raises(FileNotFoundError):
        shapes.read_silhouette(tmp_path / "missing.png")


@pytest.mark.parametrize(
    "points",
    [
        [[-1.79769313e308, 9.97920155e291], [0, 9.97920155e291], [9.97920155e291, 9.97920155e291]],
        [[0, 0], [5.6e102, 5.6e102], [0, 5.6e102], [5.6e102, 0]],
        [[4.70041672e292, 1.0], [4.70041672e292, 3.82453991e15], [4.70041672e292, 0.0]],
    ],
)
def test_fuzz_found_outlines_out_of_range_are_refused(points):
    with pytest.raises(InputError, match="too large or too small"):
        shapes.polygon(points)


def test_signed_area_far_from_the_origin():
    # without centring, products of 1e9 cancel to a few units of error
    sq = shapes.square(2.0) + 1e9
    assert shapes.signed_area(sq) == 4.0


@pytest.mark.parametrize("scale", [1e-300, 1.0, 1e150, 2.0**500])
def test_signed_area_at_any_scale(scale):
    # found by probing: products of coordinates of 1e300 overflowed
    L = np.array([(0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (1.0, 1.0), (1.0, 2.0), (0.0, 2.0)])
    assert shapes.signed_area(L * scale) == pytest.approx(3.0 * scale**2, rel=1e-15)
    assert shapes.signed_area(L[::-1] * scale) == pytest.approx(-3.0 * scale**2, rel=1e-15)


@pytest.mark.parametrize(
    "outline, match",
    [
        (np.zeros((0, 2)), "at least 3 points"),
        ([[0, 0], [1]], r"outline: rows have different lengths \(2 and 1, rows 0 and 1\)"),
        (np.zeros((2, 4, 2)), r"shape \(n_points, 2\)"),
        ([[0, 0], [1, np.nan], [1, 1]], "NaN"),
        (shapes.square(1.0) * 1e300, "area is beyond the float range"),
    ],
)
def test_signed_area_refuses_what_is_not_an_outline(outline, match):
    with pytest.raises(InputError, match=match):
        shapes.signed_area(outline)


@pytest.mark.parametrize(
    ("make", "match"),
    [
        (
            lambda: shapes.square(1e308),
            r"^width 1e\+308 is too large to compute with \(at most 1e\+100\)",
        ),
        (
            lambda: shapes.rectangle(1.0, 1e-300),
            r"^height 1e-300 is too small .* \(at least 1e-100\)",
        ),
        (lambda: shapes.circle(1e200), r"^radius 1e\+200 is too large"),
        (lambda: shapes.regular_polygon(5, 1e-101), r"^radius 1e-101 is too small"),
        (lambda: shapes.triangle(side=1e101), r"^side 1e\+101 is too large"),
    ],
)
def test_primitive_sizes_outside_the_outline_spans_are_refused(make, match):
    # as_outline refuses such spans: the primitives refuse them too, by the size's name
    with pytest.raises(InputError, match=match):
        make()
    assert shapes.as_outline(shapes.square(1e100)).shape == (4, 2)
    assert shapes.as_outline(shapes.circle(1e-100)).shape == (256, 2)
