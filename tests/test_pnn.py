import numpy as np
import pytest
from scipy.spatial.distance import cdist
from sklearn.model_selection import GridSearchCV, cross_val_score
from sklearn.utils.estimator_checks import parametrize_with_checks

import tentaclass.classifiers._pnn as pnn_module
from tentaclass.classifiers import PNNClassifier, TentacleClassifier
from tentaclass.datasets import thesis_tentacle


@parametrize_with_checks([PNNClassifier(), PNNClassifier(spread=2.0)])
def test_sklearn_compatible(estimator, check):
    check(estimator)


def reference_scores(X_train, y_train, X, spread):
    """Direct newpnn formula with scipy distances."""
    b = np.sqrt(-np.log(0.5)) / spread
    k = np.exp(-((b * cdist(X, X_train)) ** 2))
    classes = np.unique(y_train)
    return np.stack([k[:, y_train == c].mean(axis=1) for c in classes], axis=1)


def test_pattern_at_distance_spread_scores_half():
    clf = PNNClassifier(spread=0.3).fit([[0.0, 0.0], [5.0, 5.0]], ["a", "b"])
    s = clf.class_scores([[0.3, 0.0], [0.0, 0.0]])
    np.testing.assert_allclose(s[:, 0], [0.5, 1.0])


@pytest.mark.parametrize("spread", [0.1, 1.0, 3.0])
def test_scores_match_direct_formula(spread, rng):
    X = rng.normal(size=(60, 5))
    y = rng.choice(["x", "y", "z"], size=60)
    T = rng.normal(size=(25, 5)) * 0.5
    clf = PNNClassifier(spread=spread).fit(X, y)
    np.testing.assert_allclose(clf.class_scores(T), reference_scores(X, y, T, spread), atol=1e-12)
    ref = reference_scores(X, y, T, spread)
    ok = ref.sum(axis=1) > 1e-200
    np.testing.assert_allclose(clf.predict_proba(T)[ok], (ref / ref.sum(1, keepdims=True))[ok])


def test_far_samples_give_valid_probabilities():
    clf = PNNClassifier(spread=0.01).fit([[0.0], [1.0]], [0, 1])
    p = clf.predict_proba([[100.0], [-50.0]])
    assert np.all(np.isfinite(p))
    np.testing.assert_allclose(p.sum(axis=1), 1)
    assert clf.predict([[100.0], [-50.0]]).tolist() == [1, 0]  # nearest class still wins


def test_blocked_computation_equals_single_block(rng, monkeypatch):
    X = rng.normal(size=(300, 4))
    y = rng.integers(0, 5, 300)
    T = rng.normal(size=(97, 4))
    full = PNNClassifier(spread=0.7).fit(X, y).predict_log_proba(T)
    monkeypatch.setattr(pnn_module, "_BLOCK_BYTES", 8 * 300 * 7)  # 7 rows per block
    np.testing.assert_allclose(PNNClassifier(spread=0.7).fit(X, y).predict_log_proba(T), full)


def test_rejection_gives_unknown_instead_of_forced_class():
    X, y = thesis_tentacle(16, return_X_y=True)
    clf = TentacleClassifier(spread=1.0, reject_below=1e-3).fit(X, y)
    assert clf.predict(X).tolist() == y.tolist()
    star = np.tile([np.pi / 2 + 0.9, -0.9], 8)  # a wavy outline, no thesis class
    star *= 2 * np.pi / star.sum()
    assert clf.predict(star[None]).tolist() == ["unknown"]
    forced = TentacleClassifier(spread=1.0).fit(X, y).predict(star[None])
    assert forced[0] in set(y)


def test_labels_of_any_type_round_trip():
    X = [[0.0], [0.1], [1.0], [1.1]]
    for labels in ([3, 3, 7, 7], [True, True, False, False], ["b", "b", "a", "a"]):
        clf = PNNClassifier().fit(X, labels)
        assert clf.predict(X).tolist() == labels


@pytest.mark.parametrize(
    "params, match",
    [
        ({"spread": 0.0}, "spread"),
        ({"spread": np.nan}, "spread"),
        ({"spread": "x"}, "spread"),
        ({"reject_below": 2.0}, "reject_below"),
    ],
)
def test_bad_parameters(params, match):
    with pytest.raises(ValueError, match=match):
        PNNClassifier(**params).fit([[0.0], [1.0]], [0, 1])


def test_single_class_and_nan_are_refused():
    with pytest.raises(ValueError, match="2 classes"):
        PNNClassifier().fit([[0.0], [1.0]], [0, 0])
    with pytest.raises(ValueError, match="NaN"):
        PNNClassifier().fit([[np.nan], [1.0]], [0, 1])


@pytest.mark.parametrize("n_links", [16, 64])
def test_thesis_shapes_from_every_start_point_and_both_directions(n_links):
    X, y = thesis_tentacle(n_links, return_X_y=True)
    clf = TentacleClassifier().fit(X, y)
    for k in range(n_links):
        rolled = np.roll(X, k, axis=1)
        assert clf.predict(rolled).tolist() == y.tolist()
        assert clf.predict(-rolled[:, ::-1]).tolist() == y.tolist()
    np.testing.assert_allclose(clf.predict_proba(X).sum(axis=1), 1)


def test_tentacle_classifier_in_cross_validation_and_grid_search(rng):
    X, y = thesis_tentacle(16, return_X_y=True)
    Xs = np.concatenate([np.roll(X, k, axis=1) for k in range(16)])
    ys = np.tile(y, 16)
    Xs = Xs + rng.normal(0, 0.05, Xs.shape)
    scores = cross_val_score(TentacleClassifier(detrend=True), Xs, ys, cv=4)
    assert scores.min() == 1.0
    grid = GridSearchCV(TentacleClassifier(), {"spread": [0.05, 0.5, 5.0]}, cv=3).fit(Xs, ys)
    assert grid.best_params_["spread"] in (0.05, 0.5, 5.0)
    assert grid.score(Xs, ys) >= 0.99


def test_tentacle_classifier_with_another_classifier():
    from sklearn.neighbors import KNeighborsClassifier

    X, y = thesis_tentacle(64, return_X_y=True)
    clf = TentacleClassifier(classifier=KNeighborsClassifier(1)).fit(X, y)
    assert clf.predict(np.roll(X, 7, axis=1)).tolist() == y.tolist()
    assert clf.transform(X).shape == (4, 32)
