import numpy as np
import pytest
import shapely

from tentaclass import shapes
from tentaclass.errors import InputError, ShapeError
from tentaclass.features import outline_to_series, znormalize
from tentaclass.features.outline import SIGNATURES


def _rot(p, a):
    c, s = np.cos(a), np.sin(a)
    return p @ np.array([[c, s], [-s, c]])


@pytest.mark.parametrize("signature", ["centroid", "turning"])
def test_invariant_to_position_rotation_and_size(signature):
    p = shapes.polygon([[0, 0], [4, 0], [4, 1], [1, 1], [1, 3], [0, 3]])
    a = outline_to_series(p, 120, signature=signature)
    b = outline_to_series(3.5 * _rot(p, 0.7) + [10.0, -4.0], 120, signature=signature)
    np.testing.assert_allclose(a, b, atol=1e-9)


def test_centroid_signature_against_shapely():
    p = shapes.polygon([[0, 0], [4, 0], [4, 1], [1, 1], [1, 3], [0, 3]])
    s = outline_to_series(p, 64)
    from tentaclass.geometry import resample_closed

    q = resample_closed(p, 64)
    c = np.array(shapely.Polygon(p).centroid.coords[0])
    r = np.hypot(*(q - c).T)
    np.testing.assert_allclose(s, r / r.mean(), atol=1e-12)


def test_clockwise_outline_gives_the_counter_clockwise_series():
    p = shapes.polygon([[0, 0], [4, 0], [4, 1], [1, 1], [1, 3], [0, 3]])
    np.testing.assert_allclose(outline_to_series(p[::-1], 64), outline_to_series(p, 64))


@pytest.mark.parametrize(
    ("outline", "kwargs", "match"),
    [
        ([[0, 0], [1, 1]], {}, "3 vertices"),
        ([[0, 0], [1, 1], [2, 2]], {}, "no area"),
        ([[0, 0], [1, 0], [0, np.nan]], {}, "NaN"),
        (shapes.square(1.0), {"signature": "radius"}, "signature"),
        (shapes.square(1.0), {"n_points": 4}, "n_points"),
    ],
)
def test_bad_outlines(outline, kwargs, match):
    with pytest.raises(ValueError, match=match):
        outline_to_series(outline, **kwargs)


def test_znormalize_refuses_constant_series():
    np.testing.assert_allclose(znormalize([[1.0, 3.0]]), [[-1.0, 1.0]])
    with pytest.raises(ValueError, match="constant"):
        znormalize([[1.0, 2.0], [5.0, 5.0]])


@pytest.mark.parametrize("scale", [1e-300, 1e300, 1.7e308])
def test_series_of_outlines_at_any_scale(scale):
    # found by probing: the cross products overflowed (huge) or vanished (tiny)
    outline = np.array([(0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (1.0, 1.0), (1.0, 2.0), (0.0, 2.0)])
    for signature in SIGNATURES:
        ref = outline_to_series(outline, 32, signature=signature)
        got = outline_to_series(outline * (scale / 2), 32, signature=signature)
        np.testing.assert_allclose(got, ref, atol=1e-12, err_msg=signature)


def test_outline_collapsed_by_its_scale_encloses_no_area():
    flat = np.array([(0.0, 0.0), (1e300, 0.0), (1e300, 1e-300), (0.0, 1e-300)])
    with pytest.raises(InputError, match="encloses no area"):
        outline_to_series(flat)


def test_znormalize_at_any_scale_is_the_same_series(rng):
    X = rng.normal(size=(3, 20))
    Z = znormalize(X)
    # exact: series scaled by powers of two normalise to the same bits
    np.testing.assert_array_equal(znormalize(X * 2.0**-1000), Z)
    np.testing.assert_array_equal(znormalize(X * 2.0**1000), Z)
    np.testing.assert_allclose(znormalize(X * 1e300), Z, atol=1e-12)


@pytest.mark.parametrize("X", [np.array([]), np.zeros((3, 0)), np.zeros((0, 5))])
def test_znormalize_refuses_empty_input(X):
    with pytest.raises(ShapeError, match=r"X is empty \(shape"):
        znormalize(X)
