import numpy as np
import pytest

from tentaclass.classifiers import OutlineClassifier

pytest.importorskip("aeon", reason="OutlineClassifier needs the outline extra (aeon)")


def _lobes(n_per_class=6, n=64, seed=0):
    rng = np.random.default_rng(seed)
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    X, y = [], []
    for k in (2, 3, 5):
        for _ in range(n_per_class):
            X.append(
                np.cos(k * t + rng.uniform(0, 2 * np.pi))
                + 0.3 * np.cos(t)
                + 0.05 * rng.normal(size=n)
            )
            y.append(f"k{k}")
    return np.array(X), np.array(y)


@pytest.fixture(scope="module")
def lobes_model():
    """``OutlineClassifier(random_state=0)`` fitted on ``_lobes()``, shared (do not refit it)."""
    return OutlineClassifier(random_state=0).fit(*_lobes())


def test_recognises_shifted_and_mirrored_series(lobes_model):
    clf = lobes_model
    Xq, yq = _lobes(seed=1)
    Xq = np.array([np.roll(x, 11 * i)[:: (-1) ** i] for i, x in enumerate(Xq)])
    assert np.mean(clf.predict(Xq) == yq) >= 0.95
    p = clf.predict_proba(Xq)
    np.testing.assert_allclose(p.sum(axis=1), 1.0)
    assert set(clf.weights_) == {"rocket", "shift_nn"}
    assert abs(sum(clf.weights_.values()) - 1) < 1e-12


def test_same_seed_same_model(lobes_model):
    X, y = _lobes()
    again = OutlineClassifier(random_state=0).fit(X, y)
    np.testing.assert_array_equal(again.predict_proba(X), lobes_model.predict_proba(X))


@pytest.mark.parametrize(
    ("X", "y", "match"),
    [
        (np.full((4, 20), np.nan), [0, 0, 1, 1], "NaN"),
        (np.ones((4, 20)), [0, 0, 1, 1], "constant"),
        (np.random.default_rng(0).normal(size=(4, 20)), [0, 0, 0, 0], "one class"),
    ],
)
def test_bad_input(X, y, match):
    with pytest.raises(ValueError, match=match):
        OutlineClassifier().fit(X, y)


def test_query_of_another_length_is_refused(lobes_model):
    X, _ = _lobes()
    with pytest.raises(ValueError, match="features"):
        lobes_model.predict(X[:, :32])


# published best accuracy on the official split (MultiRocket+Hydra, HIVE-COTE 2, ...)
PUBLISHED_BEST = {"ArrowHead": 0.8973, "OSULeaf": 0.9780}


@pytest.mark.slow  # OSULeaf: about two minutes of fitting
@pytest.mark.parametrize("name", ["ArrowHead", "OSULeaf"])
def test_ahead_of_minirocket_and_near_the_published_best(name):
    from aeon.classification.convolution_based import MiniRocketClassifier
    from threadpoolctl import threadpool_limits

    from tentaclass.datasets import ucr_shapes

    d = ucr_shapes(name)
    train, test = d.split == "train", d.split == "test"
    with threadpool_limits(1):
        ours = OutlineClassifier(random_state=0).fit(d.data[train], d.target[train])
        acc = np.mean(ours.predict(d.data[test]) == d.target[test])
        peer = MiniRocketClassifier(random_state=0).fit(d.data[train][:, None], d.target[train])
        acc_peer = np.mean(peer.predict(d.data[test][:, None]) == d.target[test])
    assert acc >= acc_peer, (acc, acc_peer)
    assert acc >= PUBLISHED_BEST[name] - 0.02, acc
