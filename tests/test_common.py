"""scikit-learn's estimator checks over every public estimator and transformer.

Each estimator is checked with its defaults and with the variants its
docstring documents. A check expected to fail names the real limitation.
"""

import numpy as np
import pytest
from sklearn.pipeline import Pipeline
from sklearn.utils.estimator_checks import parametrize_with_checks
from threadpoolctl import threadpool_limits

from tentaclass.classifiers import (
    FourierClassifier,
    PNNClassifier,
    RBFNetworkClassifier,
    ShiftNNClassifier,
    TentacleClassifier,
    modern_mlp,
    thesis_mlp,
)
from tentaclass.datasets import synthetic_tentacle
from tentaclass.features import AngleSpectrum, FourierFeatures, LastLap


@pytest.fixture(autouse=True)
def _one_blas_thread():
    # small dense problems: one BLAS thread is faster, and far faster on a busy machine
    with threadpool_limits(1, user_api="blas"):
        yield


ESTIMATORS = [
    PNNClassifier(),
    PNNClassifier(spread=2.0),
    PNNClassifier(spread="auto"),
    PNNClassifier(spread="auto", dtype="float32"),
    PNNClassifier(reject_below=0.1),
    RBFNetworkClassifier(),
    RBFNetworkClassifier(spread=1.0, alpha=1e-3),
    RBFNetworkClassifier(centers="kmeans", n_centers=8, random_state=0),
    RBFNetworkClassifier(centers="forward", n_centers=10),
    ShiftNNClassifier(),
    ShiftNNClassifier(signal="shape"),
    ShiftNNClassifier(signal="shape", closure="chord"),
    ShiftNNClassifier(signal="raw"),
    ShiftNNClassifier(n_harmonics=0.5, weight_power=0.5),
    FourierFeatures(),
    FourierFeatures(n_harmonics=0.5, detrend=True, weight_power=0.5),
    LastLap(),
    LastLap(n_out=16),
    AngleSpectrum(),
    TentacleClassifier(),
    FourierClassifier(spread="auto", n_harmonics=0.5, weight_power=0.5),
    thesis_mlp(random_state=0),
    modern_mlp(random_state=0),
]


_INVARIANT_FEATURES = (
    "the check's blobs are 2-D points read as two joint angles; features invariant to the "
    "start point, rotation and mirror image of a closed chain cannot separate them"
)
_REJECTION = (
    "with reject_below, rejected samples get `unknown_label`, a label outside classes_ "
    "(here a string among numeric targets), which the check cannot compare"
)
_CHORD = (
    "closure='chord' resamples the joint polygon, which needs at least 3 links; "
    "the check's data has 2 columns"
)
_CHORD_CHECKS = [
    "check_estimators_overwrite_params",
    "check_estimators_fit_returns_self",
    "check_readonly_memmap_input",
    "check_classifier_data_not_an_array",
    "check_classifiers_classes",
    "check_classifiers_train",
    "check_fit_idempotent",
    "check_fit_check_is_fitted",
    "check_n_features_in",
]
_PIPELINE_GAPS = {
    "check_estimators_overwrite_params": "sklearn's Pipeline fits its step objects in place",
    "check_dont_overwrite_parameters": "sklearn's Pipeline fits its step objects in place",
}
_EARLY_STOPPING_GAPS = {
    "check_estimators_nan_inf": "early stopping's stratified validation split fails on the "
    "check's 10-sample set before the NaN check is reached",
    "check_classifiers_one_label": "early stopping's validation split fails first on one class",
    "check_fit2d_1feature": "early stopping needs more samples than the check's tiny set",
}


def expected_failed_checks(estimator):
    if isinstance(estimator, Pipeline):
        gaps = dict(_PIPELINE_GAPS)
        if estimator.named_steps["mlp"].early_stopping:
            gaps.update(_EARLY_STOPPING_GAPS)
        return gaps
    if isinstance(estimator, PNNClassifier) and estimator.reject_below:
        names = [
            "check_estimators_pickle",
            "check_classifiers_train",
            "check_fit_idempotent",
            "check_pipeline_consistency",
        ]
        return dict.fromkeys(names, _REJECTION)
    if isinstance(estimator, ShiftNNClassifier) and estimator.signal == "shape":
        if estimator.closure == "chord":
            return dict.fromkeys(_CHORD_CHECKS, _CHORD)
        return {"check_classifiers_train": _INVARIANT_FEATURES}
    if isinstance(estimator, FourierClassifier):
        return {"check_classifiers_train": _INVARIANT_FEATURES}
    return {}


def _left_out(estimator, check):
    """A check that repeats another one's work for this estimator (see below)."""
    return (
        isinstance(estimator, TentacleClassifier)
        and getattr(check, "func", None) is not None
        and check.func.__name__ == "check_classifiers_train"
        and bool(check.keywords)
    )


def _checks(estimators):
    """scikit-learn's parametrization of its checks, less the repeats `_left_out` names."""
    mark = parametrize_with_checks(estimators, expected_failed_checks=expected_failed_checks)
    names, cases = mark.args
    kept = [c for c in cases if not _left_out(*getattr(c, "values", c))]
    return pytest.mark.parametrize(names, kept, **mark.kwargs)


@_checks(ESTIMATORS)
def test_sklearn_compatible(estimator, check, request):
    name = getattr(check, "func", check).__name__
    if (
        isinstance(estimator, PNNClassifier)
        and estimator.dtype == "float32"
        and name == "check_methods_sample_order_invariance"
    ):
        # it passes in some processes and not in others: not strict
        reason = (
            "in float32 a sample's kernel sums round differently with the alignment of "
            "its row in the buffers (1 ulp, about 2e-8), more than the check's rtol of "
            "1e-7 allows; float64 passes"
        )
        request.applymarker(pytest.mark.xfail(reason=reason, strict=False))
    check(estimator)


def test_tentacle_classifier_reads_read_only_and_float32_input(tmp_path):
    # check_classifiers_train runs for TentacleClassifier on float64 only (four fits of
    # 200-300 samples): its runs on read-only and on float32 input are these, smaller.
    # The classifier works on float64, so float32 input gives the model of its float64
    # values, and read-only input the model of the same values in writeable memory.
    # 24 wraps, at least 4 of each class: the fewest with which every member takes part
    X, y = synthetic_tentacle(24, 16, random_state=3, return_X_y=True)
    X32 = X.astype(np.float32)
    X64 = X32.astype(np.float64)
    reference = TentacleClassifier().fit(X64, y)
    assert reference.spectrum_ is not None  # every member takes part
    expected = reference.predict_proba(X64)
    assert (reference.classes_[expected.argmax(axis=1)] == y).mean() > 0.9
    for name, data in (("float64", X64), ("float32", X32)):
        np.save(tmp_path / f"{name}.npy", data)
        read_only = np.load(tmp_path / f"{name}.npy", mmap_mode="r")
        assert not read_only.flags.writeable
        model = TentacleClassifier().fit(read_only, y)
        np.testing.assert_array_equal(model.predict_proba(read_only), expected, err_msg=name)
        np.testing.assert_array_equal(model.predict(read_only), reference.predict(X64))
