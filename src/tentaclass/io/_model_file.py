"""Model files: fitted classifiers saved as arrays plus JSON, never as pickles.

A ``.tcm`` file is a zip archive holding

- ``metadata.json``: format name ``"tentaclass-model"``, format version, the
  library version that wrote it, the estimator kind, the classes (JSON values
  and their numpy dtype), the feature settings, the classifier's parameters
  and fitted scalars, and for every array its shape, dtype and SHA-256;
- one ``<name>.npy`` member per array, written and read with
  ``allow_pickle=False``.

Supported estimators, fitted: :class:`~tentaclass.classifiers.TentacleClassifier`
whose classifier is a PNN or an RBF network, a scikit-learn ``Pipeline`` of
:class:`~tentaclass.features.FourierFeatures` and one of those, and a bare
:class:`~tentaclass.classifiers.PNNClassifier` or
:class:`~tentaclass.classifiers.RBFNetworkClassifier`.

:func:`load_model` checks everything before building the estimator and
refuses, with :class:`~tentaclass.errors.ModelFileError` naming the problem,
foreign files (text, a random zip, a plain ``.npz``), truncated or damaged
files, checksum mismatches, unknown or newer format versions and
inconsistent contents. No code from the file is ever executed.
"""

from __future__ import annotations

import hashlib
import io
import json
import numbers
import os
import zipfile
import zlib
from pathlib import Path
from typing import Any

import numpy as np
from sklearn.pipeline import Pipeline
from sklearn.utils.validation import check_is_fitted

from ..classifiers import PNNClassifier, RBFNetworkClassifier, TentacleClassifier
from ..errors import InputError, ModelFileError
from ..features import FourierFeatures

__all__ = ["FORMAT_NAME", "FORMAT_VERSION", "load_model", "save_model"]

#: Value of the ``format`` field of every model file.
FORMAT_NAME = "tentaclass-model"

#: Version of the file layout written by :func:`save_model`; :func:`load_model`
#: reads this version and refuses any other.
FORMAT_VERSION = 1

_METADATA = "metadata.json"
_MAX_METADATA_BYTES = 16 * 2**20
_KINDS = ("TentacleClassifier", "Pipeline", "PNNClassifier", "RBFNetworkClassifier")
_CLASSIFIER_ARRAYS = {
    "pnn": {"patterns": "f8", "class_count": "i8"},
    "rbf": {"centers": "f8", "coef": "f8", "intercept": "f8"},
}
_JSON_SCALARS = (str, int, float, bool, type(None))

#: What the zip reader raises on truncated or damaged archives: bad headers or
#: CRC, corrupt deflate streams, compression methods or flags (encryption)
#: turned on by flipped bits, names that are not text.
_ZIP_ERRORS = (
    zipfile.BadZipFile,
    zlib.error,
    EOFError,
    OSError,
    ValueError,
    NotImplementedError,
    RuntimeError,
    UnicodeDecodeError,
)


# --------------------------------------------------------------------- saving


def _json_scalar(value: object, what: str) -> object:
    """A JSON-able scalar (numpy scalars converted), or an InputError."""
    if isinstance(value, np.generic):
        value = value.item()
    if not isinstance(value, _JSON_SCALARS):
        raise InputError(f"cannot save {what} of type {type(value).__name__}: {value!r}")
    if isinstance(value, float) and not np.isfinite(value):
        raise InputError(f"cannot save non-finite {what}: {value!r}")
    return value


def _classes_to_json(classes: np.ndarray) -> dict:
    kind = classes.dtype.kind
    if kind == "O":
        if not all(isinstance(c, str) for c in classes):
            raise InputError("cannot save object-dtype class labels that are not all strings")
        return {"dtype": "object", "values": [str(c) for c in classes]}
    if kind not in "Ubiuf":
        raise InputError(f"cannot save class labels of dtype {classes.dtype}")
    values = [_json_scalar(c, "class label") for c in classes]
    return {"dtype": classes.dtype.str, "values": values}


def _classifier_record(clf: object) -> tuple[dict, dict[str, np.ndarray]]:
    """Metadata and arrays of a fitted PNN or RBF network."""
    if isinstance(clf, PNNClassifier):
        check_is_fitted(clf)
        params = {
            "spread": _json_scalar(clf.spread, "spread"),
            "reject_below": _json_scalar(clf.reject_below, "reject_below"),
            "unknown_label": _json_scalar(clf.unknown_label, "unknown_label"),
            "dtype": np.dtype(clf.dtype).name,
        }
        fitted = {"spread_": float(clf.spread_)}
        arrays = {"patterns": clf.patterns_, "class_count": clf.class_count_}
        kind = "pnn"
    elif isinstance(clf, RBFNetworkClassifier):
        check_is_fitted(clf)
        rs = clf.random_state
        params = {
            "centers": clf.centers,
            "n_centers": _json_scalar(clf.n_centers, "n_centers"),
            "spread": _json_scalar(clf.spread, "spread"),
            "alpha": float(clf.alpha),
            "goal": float(clf.goal),
            # a RandomState object only matters for refitting: stored as None
            "random_state": rs if isinstance(rs, numbers.Integral) else None,
        }
        fitted = {"spread_": float(clf.spread_)}
        arrays = {"centers": clf.centers_, "coef": clf.coef_, "intercept": clf.intercept_}
        kind = "rbf"
    else:
        raise InputError(
            "save_model supports a PNNClassifier or RBFNetworkClassifier as classifier, "
            f"got {type(clf).__name__}"
        )
    record = {
        "kind": kind,
        "params": params,
        "fitted": fitted,
        "n_features_in": int(clf.n_features_in_),
        "classes": _classes_to_json(clf.classes_),
    }
    return record, arrays


def _features_record(ff: FourierFeatures) -> dict:
    check_is_fitted(ff)
    return {
        "n_coeffs": _json_scalar(ff.n_coeffs, "n_coeffs"),
        "detrend": bool(ff.detrend),
        "normalize": bool(ff.normalize),
        "n_coeffs_": int(ff.n_coeffs_),
        "n_features_in": int(ff.n_features_in_),
    }


def _npy_bytes(arr: np.ndarray) -> bytes:
    buf = io.BytesIO()
    np.lib.format.write_array(buf, np.ascontiguousarray(arr), allow_pickle=False)
    return buf.getvalue()


def save_model(estimator: object, path: str | os.PathLike) -> Path:
    """Write a fitted estimator to a ``.tcm`` model file.

    Parameters
    ----------
    estimator : TentacleClassifier, Pipeline, PNNClassifier or RBFNetworkClassifier
        Fitted. A ``TentacleClassifier`` must use a PNN or an RBF network; a
        ``Pipeline`` must be ``FourierFeatures`` followed by one of those.
    path : str or path-like
        Destination, overwritten if it exists (conventionally ``*.tcm``).

    Returns
    -------
    path : pathlib.Path

    Raises
    ------
    tentaclass.errors.InputError
        Unsupported or unfitted estimator, or a value that JSON cannot hold
        (e.g. an ``unknown_label`` that is not a string or number).

    Examples
    --------
    >>> import numpy as np, tempfile, os
    >>> from tentaclass.classifiers import TentacleClassifier
    >>> from tentaclass.datasets import thesis_tentacle
    >>> X, y = thesis_tentacle(16, return_X_y=True)
    >>> clf = TentacleClassifier(spread=0.5).fit(X, y)
    >>> path = os.path.join(tempfile.mkdtemp(), "shapes.tcm")
    >>> loaded = load_model(save_model(clf, path))
    >>> bool(np.array_equal(loaded.predict_proba(X), clf.predict_proba(X)))
    True
    >>> loaded.predict(X).tolist()
    ['square', 'circle', 'triangle', 'rectangle']
    """
    from .. import __version__

    meta: dict[str, Any] = {
        "format": FORMAT_NAME,
        "format_version": FORMAT_VERSION,
        "library_version": __version__,
    }
    if isinstance(estimator, TentacleClassifier):
        check_is_fitted(estimator)
        features = estimator.pipeline_.named_steps["features"]
        clf = estimator.pipeline_.named_steps["classifier"]
        meta["estimator"] = "TentacleClassifier"
        meta["tentacle_params"] = {
            "n_coeffs": _json_scalar(estimator.n_coeffs, "n_coeffs"),
            "detrend": bool(estimator.detrend),
            "normalize": bool(estimator.normalize),
            "spread": _json_scalar(estimator.spread, "spread"),
            "reject_below": _json_scalar(estimator.reject_below, "reject_below"),
            "custom_classifier": estimator.classifier is not None,
        }
    elif isinstance(estimator, Pipeline):
        steps = estimator.steps
        if len(steps) != 2 or not isinstance(steps[0][1], FourierFeatures):
            raise InputError(
                "save_model supports a Pipeline of exactly FourierFeatures and a classifier, "
                f"got steps {[name for name, _ in steps]}"
            )
        features, clf = steps[0][1], steps[1][1]
        meta["estimator"] = "Pipeline"
        meta["step_names"] = [str(steps[0][0]), str(steps[1][0])]
    elif isinstance(estimator, (PNNClassifier, RBFNetworkClassifier)):
        features, clf = None, estimator
        meta["estimator"] = type(estimator).__name__
    else:
        raise InputError(
            "save_model supports TentacleClassifier, Pipeline(FourierFeatures, classifier), "
            f"PNNClassifier and RBFNetworkClassifier, got {type(estimator).__name__}"
        )
    meta["features"] = None if features is None else _features_record(features)
    record, arrays = _classifier_record(clf)
    meta["classifier"] = record
    meta["classes"] = record.pop("classes")
    blobs = {name: _npy_bytes(arr) for name, arr in arrays.items()}
    meta["arrays"] = {
        name: {
            "shape": list(arr.shape),
            "dtype": np.ascontiguousarray(arr).dtype.str,
            "sha256": hashlib.sha256(blobs[name]).hexdigest(),
        }
        for name, arr in arrays.items()
    }
    path = Path(path)
    with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_DEFLATED) as zf:
        zf.writestr(_METADATA, json.dumps(meta, indent=1, sort_keys=True))
        for name, blob in blobs.items():
            zf.writestr(f"{name}.npy", blob)
    return path


# -------------------------------------------------------------------- loading


def _field(d: object, key: str, types: type | tuple, where: str) -> Any:
    if not isinstance(d, dict) or key not in d:
        raise ModelFileError(f"metadata: missing field {where}{key!r}")
    v = d[key]
    if isinstance(v, bool) and bool not in (types if isinstance(types, tuple) else (types,)):
        raise ModelFileError(f"metadata: field {where}{key!r} has the wrong type (bool)")
    if not isinstance(v, types):
        raise ModelFileError(
            f"metadata: field {where}{key!r} has the wrong type ({type(v).__name__})"
        )
    return v


def _read_member(zf: zipfile.ZipFile, name: str, path: Path) -> bytes:
    try:
        return zf.read(name)
    except _ZIP_ERRORS as exc:
        raise ModelFileError(f"{path}: damaged model file ({name}: {exc})") from None


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


def _read_arrays(zf: zipfile.ZipFile, meta: dict, path: Path) -> dict[str, np.ndarray]:
    specs = _field(meta, "arrays", dict, "")
    members = set(zf.namelist()) - {_METADATA}
    expected = {f"{name}.npy" for name in specs}
    if members != expected:
        extra, missing = sorted(members - expected), sorted(expected - members)
        raise ModelFileError(
            f"{path}: archive members do not match the metadata "
            f"(unexpected {extra}, missing {missing})"
        )
    arrays = {}
    for name, spec in specs.items():
        where = f"arrays.{name}."
        shape = _field(spec, "shape", list, where)
        dtype = _field(spec, "dtype", str, where)
        digest = _field(spec, "sha256", str, where)
        blob = _read_member(zf, f"{name}.npy", path)
        if hashlib.sha256(blob).hexdigest() != digest:
            raise ModelFileError(f"{path}: checksum mismatch for array {name!r} (damaged file)")
        try:
            arr = np.lib.format.read_array(io.BytesIO(blob), allow_pickle=False)
        except (ValueError, OSError, EOFError) as exc:
            raise ModelFileError(f"{path}: array {name!r} is not a valid .npy ({exc})") from None
        if list(arr.shape) != shape or arr.dtype.str != dtype:
            raise ModelFileError(
                f"{path}: array {name!r} is {arr.dtype.str} {list(arr.shape)}, "
                f"metadata says {dtype} {shape}"
            )
        arrays[name] = arr
    return arrays


def _build_classifier(rec: object, classes: np.ndarray, arrays: dict) -> object:
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
    except (TypeError, InputError) as exc:
        raise ModelFileError(f"metadata: bad {kind} parameters: {exc}") from None
    clf.classes_ = classes
    clf.n_features_in_ = n_features
    clf.spread_ = float(spread_)
    if kind == "pnn":
        clf._prepare()
    return clf


def _build_features(rec: object, n_out: int) -> FourierFeatures:
    where = "features."
    n_coeffs = _field(rec, "n_coeffs", (int, type(None)), where)
    ff = FourierFeatures(
        n_coeffs=n_coeffs,
        detrend=_field(rec, "detrend", bool, where),
        normalize=_field(rec, "normalize", bool, where),
    )
    ff.n_coeffs_ = _field(rec, "n_coeffs_", int, where)
    ff.n_features_in_ = _field(rec, "n_features_in", int, where)
    n = ff.n_features_in_
    if not (n >= 3 and 1 <= ff.n_coeffs_ <= n // 2 and ff.n_coeffs_ == n_out):
        raise ModelFileError(
            f"metadata: features ({n} joints -> {ff.n_coeffs_} coefficients) do not fit "
            f"a classifier of {n_out} features"
        )
    return ff


def load_model(path: str | os.PathLike) -> object:
    """Read a model written by :func:`save_model`.

    Parameters
    ----------
    path : str or path-like

    Returns
    -------
    estimator : TentacleClassifier, Pipeline, PNNClassifier or RBFNetworkClassifier
        Fitted, predicting exactly as the saved one did.

    Raises
    ------
    tentaclass.errors.ModelFileError
        The file is not a tentaclass model (text, random zip, plain ``.npz``),
        is truncated or damaged (bad zip, checksum mismatch), has an unknown
        or newer format version, or its contents are inconsistent.
    FileNotFoundError
        No file at ``path``.

    Examples
    --------
    >>> import tempfile, os
    >>> bad = os.path.join(tempfile.mkdtemp(), "notes.tcm")
    >>> with open(bad, "w") as f:
    ...     _ = f.write("hello")
    >>> load_model(bad)
    Traceback (most recent call last):
    ...
    tentaclass.errors.ModelFileError: ...notes.tcm: not a tentaclass model file (not a zip archive)
    """
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no such model file")
    try:
        zf = zipfile.ZipFile(path)
    except _ZIP_ERRORS:
        raise ModelFileError(f"{path}: not a tentaclass model file (not a zip archive)") from None
    with zf:
        names = zf.namelist()
        if _METADATA not in names:
            plain = names and all(n.endswith(".npy") for n in names)
            hint = " (a plain .npz?)" if plain else ""
            raise ModelFileError(f"{path}: not a tentaclass model file (no {_METADATA}){hint}")
        if zf.getinfo(_METADATA).file_size > _MAX_METADATA_BYTES:
            raise ModelFileError(f"{path}: {_METADATA} is implausibly large")
        raw = _read_member(zf, _METADATA, path)
        try:
            meta = json.loads(raw.decode("utf-8"))
        except (UnicodeDecodeError, json.JSONDecodeError) as exc:
            raise ModelFileError(f"{path}: {_METADATA} is not valid JSON ({exc})") from None
        if not isinstance(meta, dict) or meta.get("format") != FORMAT_NAME:
            raise ModelFileError(
                f"{path}: not a tentaclass model file (format is not {FORMAT_NAME!r})"
            )
        version = meta.get("format_version")
        if isinstance(version, bool) or not isinstance(version, int):
            raise ModelFileError(f"{path}: unknown format version {version!r}")
        if version > FORMAT_VERSION:
            raise ModelFileError(
                f"{path}: format version {version} is newer than this tentaclass reads "
                f"({FORMAT_VERSION}); upgrade tentaclass (file written by version "
                f"{meta.get('library_version')!r})"
            )
        if version != FORMAT_VERSION:
            raise ModelFileError(f"{path}: unknown format version {version!r}")
        arrays = _read_arrays(zf, meta, path)
    try:
        return _build(meta, arrays)
    except ModelFileError as exc:
        raise ModelFileError(f"{path}: {exc}") from None


def _build(meta: dict, arrays: dict[str, np.ndarray]) -> object:
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
        "n_coeffs": _field(tp, "n_coeffs", (int, type(None)), where),
        "detrend": _field(tp, "detrend", bool, where),
        "normalize": _field(tp, "normalize", bool, where),
        "spread": _field(tp, "spread", (int, float, str), where),
        "reject_below": _field(tp, "reject_below", (int, float, type(None)), where),
    }
    if not custom and not isinstance(clf, PNNClassifier):
        raise ModelFileError("metadata: a TentacleClassifier without custom classifier uses a PNN")
    model = TentacleClassifier(**params, classifier=_unfitted_copy(clf) if custom else None)
    model.pipeline_ = Pipeline([("features", features), ("classifier", clf)])
    model.classes_ = clf.classes_
    model.n_features_in_ = features.n_features_in_
    return model


def _unfitted_copy(clf: object) -> object:
    from sklearn.base import clone

    return clone(clf)
