import numpy as np
import pytest

from tentaclass.classifiers import bullseye_score, shape_distances
from tentaclass.features import znormalize


def _brute(a, b):
    a, b = znormalize(a), znormalize(b)
    n = len(a)
    best = min(np.sum((a - np.roll(c, s)) ** 2) for c in (b, b[::-1]) for s in range(n))
    return np.sqrt(best / n)


def test_shape_distances_match_a_brute_force_search():
    rng = np.random.default_rng(0)
    A = rng.normal(size=(4, 24))
    B = rng.normal(size=(3, 24))
    D = shape_distances(A, B)
    expected = np.array([[_brute(a, b) for b in B] for a in A])
    np.testing.assert_allclose(D, expected, atol=1e-9)


def test_shape_distances_ignore_start_direction_and_scale():
    rng = np.random.default_rng(1)
    a = rng.normal(size=40)
    D = shape_distances([a], [3.0 * np.roll(a, 7)[::-1] + 5.0])
    assert D[0, 0] < 1e-9


def test_square_matrix_is_symmetric_with_zero_diagonal():
    X = np.random.default_rng(2).normal(size=(5, 16))
    D = shape_distances(X)
    np.testing.assert_array_equal(D, D.T)
    np.testing.assert_array_equal(np.diag(D), 0.0)


@pytest.mark.parametrize(
    ("A", "B", "match"),
    [
        (np.zeros((2, 8)), None, "constant"),
        ([[1.0, np.nan, 2.0, 3.0]], None, "NaN"),
        (np.eye(3, 8), np.eye(3, 9), "one length"),
    ],
)
def test_bad_series(A, B, match):
    with pytest.raises(ValueError, match=match):
        shape_distances(A, B)


def test_bullseye_against_a_direct_count():
    rng = np.random.default_rng(3)
    labels = np.repeat(np.arange(5), 4)
    D = rng.random((20, 20))
    D = (D + D.T) / 2
    np.fill_diagonal(D, 0)
    top = 6
    hits = 0
    for i in range(20):
        order = sorted(range(20), key=lambda j: (j != i, D[i, j]))[:top]
        hits += sum(labels[j] == labels[i] for j in order)
    assert bullseye_score(D, labels, top=top) == pytest.approx(hits / (20 * 4))


def test_bullseye_perfect_and_bad_input():
    D = np.kron(1 - np.eye(2), np.ones((3, 3)))
    assert bullseye_score(D, [0, 0, 0, 1, 1, 1], top=3) == 1.0
    with pytest.raises(ValueError, match="square"):
        bullseye_score(np.zeros((2, 3)), [0, 1])
    with pytest.raises(ValueError, match="labels"):
        bullseye_score(np.zeros((2, 2)), [0, 1, 2])
