import itertools

import numpy as np
import pytest
from scipy.spatial.distance import cdist
from threadpoolctl import threadpool_limits

from tentaclass.classifiers import FourierClassifier, RBFNetworkClassifier
from tentaclass.datasets import thesis_tentacle
from tentaclass.errors import InputError, TentaclassWarning


@pytest.fixture(autouse=True)
def _one_blas_thread():
    # small dense problems: one BLAS thread is faster, and far faster on a busy machine
    with threadpool_limits(1, user_api="blas"):
        yield


def blobs(rng, n_per=40, sep=6.0, dim=2, n_classes=3):
    centres = rng.normal(0, sep, (n_classes, dim))
    y = np.repeat(np.arange(n_classes), n_per)
    return centres[y] + rng.normal(size=(y.size, dim)), y


def test_hidden_unit_at_distance_spread_gives_half():
    clf = RBFNetworkClassifier(spread=0.4).fit([[0.0, 0.0], [3.0, 0.0]], ["a", "b"])
    phi = np.exp(-((np.sqrt(-np.log(0.5)) / 0.4 * cdist([[0.4, 0.0]], clf.centers_)) ** 2))
    assert phi[0, 0] == pytest.approx(0.5)


@pytest.mark.parametrize("spread", [0.3, 1.0])
def test_all_centres_small_alpha_interpolates_training_set(rng, spread):
    X, y = blobs(rng, 15)
    clf = RBFNetworkClassifier(centers="all", spread=spread, alpha=1e-12).fit(X, y)
    np.testing.assert_allclose(clf.network_outputs(X), np.eye(3)[y], atol=1e-5)
    assert clf.n_centers_ == X.shape[0]
    assert clf.score(X, y) == 1.0


def test_outputs_match_direct_ridge_solution(rng):
    X, y = blobs(rng, 20)
    alpha, spread = 0.1, 1.5
    clf = RBFNetworkClassifier(spread=spread, alpha=alpha).fit(X, y)
    phi = np.exp(-np.log(2) * (cdist(X, X) / spread) ** 2)
    A = np.hstack([phi, np.ones((X.shape[0], 1))])
    pen = alpha * np.eye(A.shape[1])
    pen[-1, -1] = 0  # bias not penalised
    W = np.linalg.solve(A.T @ A + pen, A.T @ np.eye(3)[y])
    np.testing.assert_allclose(clf.coef_, W[:-1], atol=1e-6)
    np.testing.assert_allclose(clf.intercept_, W[-1], atol=1e-6)


def test_forward_selection_picks_one_centre_per_cluster_first(rng):
    X, y = blobs(rng, 30, sep=20.0)
    clf = RBFNetworkClassifier(centers="forward", n_centers=3, spread=3.0).fit(X, y)
    assert clf.n_centers_ == 3
    # the three centres lie in three different clusters
    nearest = np.argmin(cdist(clf.centers_, X), axis=1)
    assert sorted(y[nearest].tolist()) == [0, 1, 2]
    assert clf.score(X, y) == 1.0


def test_forward_selection_stops_at_goal(rng):
    X, y = blobs(rng, 30, sep=20.0)
    loose = RBFNetworkClassifier(centers="forward", n_centers=50, spread=3.0, goal=0.05).fit(X, y)
    tight = RBFNetworkClassifier(centers="forward", n_centers=50, spread=3.0).fit(X, y)
    assert loose.n_centers_ < tight.n_centers_ <= 50
    mse = ((loose.network_outputs(X) - np.eye(3)[y]) ** 2).mean()
    assert mse <= 0.06


def test_forward_residual_decreases_with_more_centres(rng):
    X, y = blobs(rng, 30, sep=2.0)
    errs = []
    for k in (2, 5, 10, 20):
        clf = RBFNetworkClassifier(centers="forward", n_centers=k, spread=1.0, alpha=0).fit(X, y)
        errs.append(((clf.network_outputs(X) - np.eye(3)[y]) ** 2).sum())
    assert all(a >= b - 1e-9 for a, b in itertools.pairwise(errs))


def test_kmeans_centres_are_seeded(rng):
    X, y = blobs(rng, 40)
    a = RBFNetworkClassifier(centers="kmeans", n_centers=6, random_state=3).fit(X, y)
    b = RBFNetworkClassifier(centers="kmeans", n_centers=6, random_state=3).fit(X, y)
    np.testing.assert_array_equal(a.centers_, b.centers_)
    assert a.n_centers_ == 6 and a.score(X, y) > 0.95


def test_kmeans_with_fewer_distinct_points_than_centres():
    X = [[0.0], [0.0], [1.0], [1.0]]
    clf = RBFNetworkClassifier(centers="kmeans", n_centers=10, random_state=0)
    with pytest.warns(TentaclassWarning, match="n_centers=10 is more than the 2 distinct training"):
        clf.fit(X, [0, 0, 1, 1])
    assert clf.n_centers_ == 2
    assert clf.predict(X).tolist() == [0, 0, 1, 1]


def test_more_centres_than_samples_warns_for_kmeans_only():
    X = np.arange(12.0).reshape(6, 2)
    y = [0, 0, 0, 1, 1, 1]
    with pytest.warns(TentaclassWarning, match="n_centers=50 is more than the 6 distinct"):
        km = RBFNetworkClassifier(centers="kmeans", n_centers=50, random_state=0).fit(X, y)
    assert km.n_centers_ == 6
    # forward selection takes n_centers as its upper bound, and "all" ignores it
    for centers in ("forward", "all"):
        clf = RBFNetworkClassifier(centers=centers, n_centers=50, spread=3.0).fit(X, y)
        assert clf.n_centers_ <= 6


@pytest.mark.parametrize("scale", [0.01, 1.0, 100.0])
def test_auto_spread_scales_with_data(rng, scale):
    X, y = blobs(np.random.default_rng(1), 30, sep=8.0)
    clf = RBFNetworkClassifier().fit(X * scale, y)
    ref = RBFNetworkClassifier().fit(X, y)
    assert clf.spread_ == pytest.approx(ref.spread_ * scale)
    assert clf.spread == "auto"
    assert clf.score(X * scale, y) == 1.0


def test_probabilities_valid_and_ordered_like_outputs(rng):
    X, y = blobs(rng, 30, sep=2.0)
    clf = RBFNetworkClassifier(spread=1.0, alpha=1e-2).fit(X, y)
    T = rng.normal(0, 10, (200, 2))  # many far away: outputs near the intercept
    p = clf.predict_proba(T)
    o = clf.network_outputs(T)
    assert np.all(p > 0) and np.all(np.isfinite(p))
    np.testing.assert_allclose(p.sum(axis=1), 1)
    np.testing.assert_array_equal(np.argmax(p, axis=1), np.argmax(o, axis=1))
    assert clf.predict(T).tolist() == clf.classes_[np.argmax(o, axis=1)].tolist()
    # where outputs are clearly positive, p is the clipped-normalised output
    pos = np.clip(o, 0, None)
    ok = pos.sum(axis=1) > 0.5
    np.testing.assert_allclose(p[ok], (pos / pos.sum(axis=1, keepdims=True))[ok], atol=1e-5)


def test_labels_of_any_type():
    X = [[0.0], [0.1], [1.0], [1.1]]
    for labels in ([3, 3, 7, 7], [True, True, False, False], ["b", "b", "a", "a"]):
        assert RBFNetworkClassifier().fit(X, labels).predict(X).tolist() == labels


def test_thesis_shapes_in_tentacle_classifier():
    X, y = thesis_tentacle(64, return_X_y=True)
    clf = FourierClassifier(classifier=RBFNetworkClassifier()).fit(X, y)
    assert clf.predict(np.roll(X, 9, axis=1)).tolist() == y.tolist()


@pytest.mark.parametrize(
    "params, match",
    [
        ({"centers": "some"}, "centers"),
        ({"n_centers": 0}, "n_centers"),
        ({"n_centers": 2.5}, "n_centers"),
        ({"spread": -1.0}, "spread"),
        ({"spread": "wide"}, "spread"),
        ({"alpha": -1.0}, "alpha"),
        ({"goal": np.inf}, "goal"),
        ({"spread": 1e-300}, "too small"),  # (b / spread) ** 2 overflowed
        ({"spread": 1e300}, "too large"),  # every kernel 1: chance-level answers
    ],
)
def test_bad_parameters(params, match):
    with pytest.raises(ValueError, match=match):
        RBFNetworkClassifier(**params).fit([[0.0], [1.0]], [0, 1])


@pytest.mark.parametrize(
    "params, message",
    [
        ({"n_centers": 0}, "n_centers must be at least 1, got 0"),
        ({"n_centers": 2.0}, "n_centers must be an integer"),
        ({"centers": "grid"}, "centers must be one of 'all', 'kmeans', 'forward', got 'grid'"),
    ],
)
def test_bad_parameters_are_named(params, message):
    from tentaclass.errors import InputError

    X, y = [[0.0], [1.0]], [0, 1]
    with pytest.raises(InputError, match=message):
        RBFNetworkClassifier(**params).fit(X, y)


@pytest.mark.parametrize("centers", ["all", "kmeans", "forward"])
def test_features_whose_squared_distances_overflow_are_refused(centers):
    # a LinAlgError ("Eigenvalues did not converge") from the spread's search before
    X, y = thesis_tentacle(16, return_X_y=True)
    clf = RBFNetworkClassifier(centers=centers, n_centers=4, random_state=0)
    with pytest.raises(InputError, match=r"X holds a value of 2.094e\+160: squared distances"):
        clf.fit(X * 1e160, y)
    assert clf.fit(X * 1e150, y).score(X * 1e150, y) == 1.0  # large, but within float64
