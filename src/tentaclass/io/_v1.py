"""Reading version-1 model files.

Version 1 held a ``TentacleClassifier`` (today's
:class:`~tentaclass.classifiers.FourierClassifier`) whose classifier is a
PNN or an RBF network, a ``Pipeline`` of
:class:`~tentaclass.features.FourierFeatures` and one of those, or a bare
PNN or RBF network, in a fixed layout. Files of that version are still read;
new files are written in the generic layout of ``_model_file``.
"""

from __future__ import annotations

import numpy as np
from sklearn.pipeline import Pipeline

from ..classifiers import FourierClassifier, PNNClassifier, RBFNetworkClassifier
from ..errors import ModelFileError
from ..features import FourierFeatures
from ._model_file import _field

#: "TentacleClassifier" was the name of today's FourierClassifier (features + classifier).
_KINDS = (
    "TentacleClassifier",
    "FourierClassifier",
    "Pipeline",
    "PNNClassifier",
    "RBFNetworkClassifier",
)
_CLASSIFIER_ARRAYS = {
    "pnn": {"patterns": "f8", "class_count": "i8"},
    "rbf": {"centers": "f8", "coef": "f8", "intercept": "f8"},
}
_JSON_SCALARS = (str, int, float, bool, type(None))


def _classes_from_json(rec: object) -> np.ndarray:
    dtype = _field(rec, "dtype", str, "classes.")
    values = _field(rec, "values", list, "classes.")
    if len(values) < 2 or not all(isinstance(v, _JSON_SCALARS) for v in values):
        raise ModelFileError("metadata: classes must be a list of at least 2 scalar labels")
    try:
        if dtype == "object":
            classes = np.array(values, dtype=object)
        else:
            dt = np.dtype(dtype)
            if dt.kind not in "Ubiuf":
                raise TypeError(dtype)
            classes = np.array(values, dtype=dt)
    except (TypeError, ValueError, OverflowError):
        raise ModelFileError(f"metadata: unusable classes dtype {dtype!r}") from None
    if classes.tolist() != values or len(set(values)) != len(values):
        raise ModelFileError("metadata: class labels do not survive their dtype or repeat")
    return classes


def _build_classifier(
    rec: object, classes: np.ndarray, arrays: dict
) -> PNNClassifier | RBFNetworkClassifier:
    kind = _field(rec, "kind", str, "classifier.")
    if kind not in _CLASSIFIER_ARRAYS:
        raise ModelFileError(f"metadata: unknown classifier kind {kind!r}")
    want = _CLASSIFIER_ARRAYS[kind]
    if set(arrays) != set(want):
        raise ModelFileError(f"metadata: a {kind} model needs arrays {sorted(want)}")
    for name, code in want.items():
        if arrays[name].dtype.kind != np.dtype(code).kind:
            raise ModelFileError(f"array {name!r} has dtype {arrays[name].dtype}, expected {code}")
        if arrays[name].dtype.kind == "f" and not np.all(np.isfinite(arrays[name])):
            raise ModelFileError(f"array {name!r} holds NaN or infinite values")
    params = _field(rec, "params", dict, "classifier.")
    fitted = _field(rec, "fitted", dict, "classifier.")
    n_features = _field(rec, "n_features_in", int, "classifier.")
    spread_ = _field(fitted, "spread_", (int, float), "classifier.fitted.")
    if not (np.isfinite(spread_) and spread_ > 0):
        raise ModelFileError(f"metadata: spread_ must be a finite number > 0, got {spread_!r}")
    n_classes = classes.size
    try:
        if kind == "pnn":
            clf = PNNClassifier(**params)
            clf._validate_params()
            P, counts = arrays["patterns"], arrays["class_count"]
            if (
                P.ndim != 2
                or P.shape[1] != n_features
                or counts.shape != (n_classes,)
                or np.any(counts < 1)
                or int(counts.sum()) != P.shape[0]
            ):
                raise ModelFileError("PNN arrays are inconsistent with each other or the classes")
            clf.patterns_, clf.class_count_ = P.astype(np.float64), counts.astype(np.int64)
        else:
            clf = RBFNetworkClassifier(**params)
            clf._validate_params()
            C, W, b = arrays["centers"], arrays["coef"], arrays["intercept"]
            if (
                C.ndim != 2
                or C.shape[1] != n_features
                or W.shape != (C.shape[0], n_classes)
                or b.shape != (n_classes,)
            ):
                raise ModelFileError("RBF arrays are inconsistent with each other or the classes")
            clf.centers_, clf.coef_, clf.intercept_ = C, W, b
            clf.n_centers_ = int(C.shape[0])
    except ModelFileError:
        raise
    except (TypeError, ValueError, KeyError) as exc:
        raise ModelFileError(f"metadata: bad {kind} parameters: {exc}") from None
    clf.classes_ = classes
    clf.n_features_in_ = n_features
    clf.spread_ = float(spread_)
    if kind == "pnn":
        clf._prepare()
    return clf


def _build_features(rec: object, n_out: int) -> FourierFeatures:
    where = "features."
    ff = FourierFeatures(
        n_harmonics=_field(rec, "n_coeffs", (int, type(None)), where),
        detrend=_field(rec, "detrend", bool, where),
        normalize=_field(rec, "normalize", bool, where),
    )
    ff.n_harmonics_ = _field(rec, "n_coeffs_", int, where)
    ff.n_features_in_ = _field(rec, "n_features_in", int, where)
    n = ff.n_features_in_
    if not (n >= 3 and 1 <= ff.n_harmonics_ <= n // 2 and ff.n_harmonics_ == n_out):
        raise ModelFileError(
            f"metadata: features ({n} joints -> {ff.n_harmonics_} coefficients) do not fit "
            f"a classifier of {n_out} features"
        )
    return ff


def build_v1(meta: dict, arrays: dict[str, np.ndarray]) -> object:
    """The estimator of a version-1 file from its metadata and checked arrays."""
    kind = _field(meta, "estimator", str, "")
    if kind not in _KINDS:
        raise ModelFileError(f"metadata: unknown estimator kind {kind!r}")
    _field(meta, "library_version", str, "")
    classes = _classes_from_json(meta.get("classes"))
    clf = _build_classifier(meta.get("classifier"), classes, arrays)
    features_rec = meta.get("features")
    if kind in ("PNNClassifier", "RBFNetworkClassifier"):
        expected = "pnn" if kind == "PNNClassifier" else "rbf"
        if meta["classifier"]["kind"] != expected or features_rec is not None:
            raise ModelFileError(f"metadata: a {kind} has no features and a {expected} classifier")
        return clf
    features = _build_features(features_rec, clf.n_features_in_)
    if kind == "Pipeline":
        names = _field(meta, "step_names", list, "")
        if len(names) != 2 or not all(isinstance(n, str) for n in names) or names[0] == names[1]:
            raise ModelFileError("metadata: step_names must be two distinct strings")
        return Pipeline([(names[0], features), (names[1], clf)])
    tp = _field(meta, "tentacle_params", dict, "")
    where = "tentacle_params."
    custom = _field(tp, "custom_classifier", bool, where)
    params = {
        "n_harmonics": _field(tp, "n_coeffs", (int, type(None)), where),
        "detrend": _field(tp, "detrend", bool, where),
        "normalize": _field(tp, "normalize", bool, where),
        "spread": _field(tp, "spread", (int, float, str), where),
        "reject_below": _field(tp, "reject_below", (int, float, type(None)), where),
    }
    if not custom and not isinstance(clf, PNNClassifier):
        raise ModelFileError(f"metadata: a {kind} without custom classifier uses a PNN")
    pipeline = Pipeline([("features", features), ("classifier", clf)])
    model = FourierClassifier(**params, classifier=_unfitted_copy(clf) if custom else None)
    model.pipeline_ = pipeline
    model.classes_ = clf.classes_
    model.n_features_in_ = features.n_features_in_
    return model


def _unfitted_copy(clf: object) -> object:
    from sklearn.base import clone

    return clone(clf)
