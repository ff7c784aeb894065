import numpy as np
import pytest
from sklearn.utils.estimator_checks import parametrize_with_checks

from tentaclass.classifiers._shift_nn import ShiftNNClassifier
from tentaclass.datasets import thesis_tentacle


@parametrize_with_checks([ShiftNNClassifier(signal="raw")])
def test_sklearn_compatible(estimator, check):
    check(estimator)


def brute_force(A, B, mirror):
    A = A - A.mean(1, keepdims=True)
    B = B - B.mean(1, keepdims=True)
    n = A.shape[1]
    out = np.empty((len(B), len(A)))
    for i, b in enumerate(B):
        for j, a in enumerate(A):
            cands = [((b - np.roll(a, s)) ** 2).sum() for s in range(n)]
            if mirror:
                cands += [((b - np.roll(a[::-1], s)) ** 2).sum() for s in range(n)]
            out[i, j] = min(cands)
    return out


@pytest.mark.parametrize("mirror", [True, False])
def test_distances_equal_brute_force(mirror, rng):
    A, B = rng.normal(size=(6, 13)), rng.normal(size=(4, 13))
    clf = ShiftNNClassifier(signal="raw", mirror=mirror).fit(A, np.arange(6))
    np.testing.assert_allclose(clf.shift_distances(B), brute_force(A, B, mirror), atol=1e-9)


def test_turning_signal_recognises_thesis_shapes_any_start_and_direction():
    X, y = thesis_tentacle(64, return_X_y=True)
    clf = ShiftNNClassifier().fit(X, y)
    for k in (0, 7, 33):
        rolled = np.roll(X, k, axis=1)
        assert clf.predict(rolled).tolist() == y.tolist()
        assert clf.predict(-rolled[:, ::-1]).tolist() == y.tolist()


def test_bad_signal_option():
    with pytest.raises(ValueError, match="signal"):
        ShiftNNClassifier(signal="dct").fit(np.zeros((2, 8)), [0, 1])
    for kw in ({"mirror": "no"}, {"center": None}):  # were read as truthy / falsy
        with pytest.raises(ValueError, match=next(iter(kw))):
            ShiftNNClassifier(**kw).fit(np.zeros((2, 8)), [0, 1])
