import warnings

import numpy as np
import pytest
from sklearn.exceptions import ConvergenceWarning
from sklearn.neural_network import MLPClassifier
from sklearn.pipeline import Pipeline
from sklearn.utils.estimator_checks import parametrize_with_checks
from threadpoolctl import threadpool_limits

from tentaclass.classifiers import (
    FixedEpochsMLPClassifier,
    TentacleClassifier,
    modern_mlp,
    thesis_mlp,
)
from tentaclass.datasets import reference_tentacle, thesis_tentacle
from tentaclass.features import fourier_features


@pytest.fixture(autouse=True)
def _one_blas_thread():
    with threadpool_limits(1, user_api="blas"):
        yield


_PIPELINE_GAPS = {
    "check_estimators_overwrite_params": "sklearn's Pipeline fits its step objects in place "
    "(a known Pipeline trait, not ours)",
    "check_dont_overwrite_parameters": "sklearn's Pipeline fits its step objects in place",
}
_EARLY_STOPPING_GAPS = {
    "check_estimators_nan_inf": "early stopping's stratified validation split fails on the "
    "check's 10-sample set before the NaN check is reached",
    "check_classifiers_one_label": "early stopping's validation split fails first on one class",
    "check_fit2d_1feature": "early stopping needs more samples than the check's tiny set",
}


def expected_failed_checks(estimator):
    if not isinstance(estimator, Pipeline):
        return {}
    gaps = dict(_PIPELINE_GAPS)
    if estimator.named_steps["mlp"].early_stopping:
        gaps.update(_EARLY_STOPPING_GAPS)
    return gaps


@parametrize_with_checks(
    [
        thesis_mlp(random_state=0),
        modern_mlp(random_state=0),
    ],
    expected_failed_checks=expected_failed_checks,
)
def test_sklearn_compatible(estimator, check):
    check(estimator)


def test_thesis_preset_settings():
    clf = thesis_mlp()
    assert isinstance(clf, MLPClassifier)
    p = clf.get_params()
    assert p["hidden_layer_sizes"] == (10,)
    assert p["activation"] == "logistic"
    assert p["solver"] == "sgd" and p["momentum"] == 0.0 and not p["nesterovs_momentum"]
    assert p["learning_rate"] == "constant" and p["learning_rate_init"] == 0.6
    assert p["max_iter"] == 50 and p["alpha"] == 0.0 and not p["early_stopping"]


def test_overrides_win():
    params = thesis_mlp(hidden_layer_sizes=(4,), random_state=3).get_params()
    assert params["hidden_layer_sizes"] == (4,) and params["random_state"] == 3
    pipe = modern_mlp(alpha=0.5, early_stopping=False)
    assert isinstance(pipe, Pipeline)
    assert pipe.named_steps["mlp"].alpha == 0.5
    assert not pipe.named_steps["mlp"].early_stopping


def test_thesis_mlp_runs_exactly_50_epochs_without_warning():
    X, y = thesis_tentacle(64, return_X_y=True)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        clf = thesis_mlp(random_state=0).fit(fourier_features(X), y)
    assert clf.n_iter_ == 50
    assert len(clf.loss_curve_) == 50


def test_plain_mlp_classifier_would_warn():
    # the reason for FixedEpochsMLPClassifier: a 50-epoch budget ends in a warning
    X, y = thesis_tentacle(16, return_X_y=True)
    with pytest.warns(ConvergenceWarning):
        MLPClassifier(**thesis_mlp(random_state=0).get_params()).fit(fourier_features(X), y)


def test_other_warnings_still_surface():
    with pytest.warns(UserWarning, match="batch_size"):
        FixedEpochsMLPClassifier(batch_size=100, max_iter=2).fit([[0.0], [1.0]], [0, 1])


def test_thesis_mlp_learns_the_thesis_shapes():
    X, y = reference_tentacle(64, n_starts=8, return_X_y=True)
    clf = TentacleClassifier(classifier=thesis_mlp(random_state=0)).fit(X, y)
    assert clf.score(X, y) == 1.0
    assert clf.predict(np.roll(X, 11, axis=1)).tolist() == y.tolist()


def test_modern_mlp_generalises_on_noisy_tentacles():
    rng = np.random.default_rng(0)
    X, y = reference_tentacle(32, n_starts=8, return_X_y=True)
    Xs = np.concatenate([np.roll(X, k, axis=1) for k in range(0, 32, 4)])
    ys = np.tile(y, 8)
    train = Xs + rng.normal(0, 0.05, Xs.shape)
    test = Xs + rng.normal(0, 0.05, Xs.shape)
    clf = TentacleClassifier(detrend=True, classifier=modern_mlp(random_state=0)).fit(train, ys)
    assert clf.score(test, ys) >= 0.95


def test_seeded_runs_are_identical():
    X, y = thesis_tentacle(16, return_X_y=True)
    F = fourier_features(X)
    a = thesis_mlp(random_state=7).fit(F, y)
    b = thesis_mlp(random_state=7).fit(F, y)
    np.testing.assert_array_equal(a.predict_proba(F), b.predict_proba(F))
