import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from strategies import examples
from tentaclass import angles_to_points, points_to_angles, resample_closed
from tentaclass.errors import InputError, ShapeError

L_SHAPE = [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)]


def test_square_closes_and_has_unit_links():
    q = np.tile([0, 0, 0, np.pi / 2], 4)
    p = angles_to_points(q)
    assert p.shape == (17, 2)
    np.testing.assert_allclose(p[-1], p[0], atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(np.diff(p, axis=0), axis=1), 1.0)
    np.testing.assert_allclose(p[3:5], [[3, 0], [3, 1]], atol=1e-12)


def test_link_lengths_base_and_heading():
    p = angles_to_points([0.0, np.pi / 2], link_lengths=[2.0, 3.0], base=(1, 1), heading=np.pi / 2)
    np.testing.assert_allclose(p, [[1, 1], [1, 3], [-2, 3]], atol=1e-12)


@pytest.mark.parametrize(
    "shape, expected",
    [((5,), (6, 2)), ((2, 5), (2, 6, 2)), ((3, 2, 5), (3, 2, 6, 2)), ((1, 1, 5), (1, 1, 6, 2))],
)
def test_angles_to_points_shape_table(shape, expected):
    assert angles_to_points(np.zeros(shape)).shape == expected


def test_l_shape_has_a_negative_turn_and_sums_to_2pi():
    q = points_to_angles(L_SHAPE)
    assert q.shape == (6,)
    assert np.sum(q < 0) == 1
    np.testing.assert_allclose(q[3], -np.pi / 2)
    np.testing.assert_allclose(q.sum(), 2 * np.pi)


def test_clockwise_outline_sums_to_minus_2pi():
    np.testing.assert_allclose(points_to_angles(L_SHAPE[::-1]).sum(), -2 * np.pi)


def test_repeated_closing_point_is_dropped():
    closed = [*L_SHAPE, L_SHAPE[0]]
    np.testing.assert_allclose(points_to_angles(closed), points_to_angles(L_SHAPE))


@settings(deadline=None, max_examples=examples(60))
@given(
    hnp.arrays(
        np.float64,
        hnp.array_shapes(min_dims=1, max_dims=3, min_side=3, max_side=12),
        elements=st.floats(-3.0, 3.0, allow_nan=False),
    )
)
def test_open_chain_round_trip(q):
    p = angles_to_points(q)
    np.testing.assert_allclose(points_to_angles(p, closed=False), q, atol=1e-9)


@settings(deadline=None, max_examples=examples(60))
@given(st.integers(3, 40), st.floats(0.01, 100.0), st.floats(-np.pi, np.pi), st.integers(0, 39))
def test_closed_round_trip_of_regular_polygon(n, length, heading, shift):
    q = np.roll(np.full(n, 2 * np.pi / n), shift % n)
    p = angles_to_points(q, link_lengths=length, heading=heading)
    np.testing.assert_allclose(points_to_angles(p[:-1]), q, atol=1e-9)


def test_closed_round_trip_of_thesis_shapes():
    from tentaclass.datasets import thesis_tentacle

    X = thesis_tentacle(64).data
    closes = [0, 1, 3]  # the thesis's triangle (5, 5, 6 links) does not close exactly
    p = angles_to_points(X[closes])
    np.testing.assert_allclose(p[:, -1], p[:, 0], atol=1e-9)
    q = points_to_angles(p[:, :-1])
    np.testing.assert_allclose(np.mod(q - X[closes] + np.pi, 2 * np.pi) - np.pi, 0, atol=1e-9)


def test_resample_square_corners():
    r = resample_closed([(0, 0), (4, 0), (4, 4), (0, 4)], 16)
    assert r.shape == (16, 2)
    np.testing.assert_allclose(r[::4], [(0, 0), (4, 0), (4, 4), (0, 4)], atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(np.roll(r, -1, axis=0) - r, axis=1), 1.0)


def test_resample_removes_uneven_spacing(rng):
    t = np.sort(rng.uniform(0, 2 * np.pi, 300))
    circle = np.stack([np.cos(t), np.sin(t)], axis=1)
    r = resample_closed(circle, 50)
    steps = np.linalg.norm(np.roll(r, -1, axis=0) - r, axis=1)
    assert steps.std() / steps.mean() < 0.02


def test_resample_batch_equals_loop(rng):
    pts = rng.normal(size=(3, 2, 9, 2))
    batch = resample_closed(pts, 11)
    assert batch.shape == (3, 2, 11, 2)
    for i in range(3):
        for j in range(2):
            np.testing.assert_allclose(batch[i, j], resample_closed(pts[i, j], 11), atol=1e-12)


@pytest.mark.parametrize(
    "func, args, match",
    [
        (angles_to_points, ([np.nan, 0, 0],), "NaN"),
        (angles_to_points, ([],), "empty"),
        (angles_to_points, ([0, 0, 0], [1, 2]), "link_lengths"),
        (angles_to_points, ([0, 0, 0], -1.0), "> 0"),
        (points_to_angles, ([(0, 0), (1, 0)],), "3 distinct"),
        (points_to_angles, ([(0, 0), (1, 0), (1, 0), (0, 1)],), "consecutive equal"),
        (points_to_angles, ([0, 1, 2],), "dimension"),
        (points_to_angles, ([(0, 0, 0), (1, 0, 0), (0, 1, 0)],), r"\(\.\.\., n_points, 2\)"),
        (resample_closed, ([(0, 0), (0, 0), (0, 0)], 5), "zero perimeter"),
        (resample_closed, ([(0, 0), (1, 0), (0, 1)], 2), "at least 3"),
        (resample_closed, ([(0, 0), (1, 0), (0, 1)], 2.5), "integer"),
    ],
)
def test_bad_input_raises_value_error(func, args, match):
    with pytest.raises(ValueError, match=match):
        func(*args)


def test_errors_are_library_errors():
    with pytest.raises(ShapeError):
        angles_to_points(1.0)
    with pytest.raises(InputError):
        points_to_angles([(0, 0), (np.inf, 0), (0, 1)])


@pytest.mark.parametrize("scale", [1e300, 1e-300, 1.0])
def test_points_to_angles_does_not_depend_on_scale(scale):
    # found by fuzzing: cross and dot products overflowed to NaN at 1e300
    p = np.array([[0, 0], [0.5, 1], [1, 2], [0, 3]])
    np.testing.assert_allclose(points_to_angles(p * scale), points_to_angles(p), atol=1e-12)
    np.testing.assert_allclose(
        points_to_angles(p * scale, closed=False), points_to_angles(p, closed=False), atol=1e-12
    )


def test_fuzz_found_points_near_the_float_limit():
    p = np.full((2, 2), 8.98846567e307)
    p[0] = 0
    np.testing.assert_allclose(points_to_angles(p, closed=False), [np.pi / 4])
    tri = np.array([[8.98846567e307, 0], [0, 0], [0, 1e307]])
    r = resample_closed(tri, 7)
    assert np.all(np.isfinite(r))
    np.testing.assert_allclose(r / 1e300, resample_closed(tri / 1e300, 7))


@pytest.mark.parametrize(
    ("lengths", "base", "match"),
    [
        (
            1e308,
            (0.0, 0.0),
            r"link_lengths up to 1e\+308 over 16 links \(from a base at 0\) reach inf",
        ),
        (1e299, (0.0, 0.0), r"reach 1.6e\+300: the joint positions would overflow float64"),
        (1.0, (1e308, 0.0), r"from a base at 1e\+308\) reach 1e\+308"),
    ],
)
def test_joint_positions_beyond_float64_are_refused(lengths, base, match):
    square = np.tile([0.0, 0.0, 0.0, np.pi / 2], 4)
    with pytest.raises(InputError, match=match):
        angles_to_points(square, lengths, base=base)
    # the same chain, rescaled into range, closes
    p = angles_to_points(square, 1e290)
    assert np.all(np.isfinite(p)) and np.allclose(p[-1], p[0], atol=1e276)
