import numpy as np
import pytest
import shapely

from tentaclass import shapes
from tentaclass.features import outline_to_series, znormalize


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
