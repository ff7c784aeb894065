"""Model files: fitted estimators saved as arrays plus JSON, never as pickles.

A ``.tcm`` file is a zip archive holding

- ``metadata.json``: format name ``"tentaclass-model"``, format version, the
  library version that wrote it, the estimator tree (below), free-form
  ``info`` (for example the chain a model was trained for) and, for every
  array, its shape, dtype and SHA-256;
- one ``a<k>.npy`` member per array, written and read with ``allow_pickle=False``.

The estimator tree records, for every estimator, its class name (looked up in
a fixed allow-list, never imported from a path in the file), its constructor
parameters (``get_params(deep=False)``; nested estimators recursively) and
its fitted state (every instance attribute that is not a parameter). Values
are JSON scalars, strings, lists, tuples, dicts with string keys, numpy
scalars and dtypes, arrays (numbers, booleans or text: never objects) and
nested allowed estimators. Caches an estimator rebuilds from its state are
not stored (the PNN's prepared kernel matrix); helper objects that only
matter for further training are dropped (an MLP's optimiser and random
generator, a ``RandomState`` given as ``random_state``, which is stored as
``None``).

Version-1 files (a TentacleClassifier, a Pipeline of FourierFeatures and a
PNN or RBF network, or a bare PNN or RBF network) are still read.
"""

from __future__ import annotations

import hashlib
import importlib
import io
import json
import keyword
import math
import os
import zipfile
import zlib
from collections.abc import Callable
from functools import cache
from pathlib import Path
from typing import Any

import numpy as np

from .. import classifiers
from .._validation import as_path
from ..errors import InputError, ModelFileError, ModelFileNotFoundError

__all__ = ["FORMAT_NAME", "FORMAT_VERSION", "load_model", "model_info", "save_model"]

#: Value of the ``format`` field of every model file.
FORMAT_NAME = "tentaclass-model"

#: Version of the file layout written by :func:`save_model`; :func:`load_model`
#: reads this version and version 1.
FORMAT_VERSION = 2

_METADATA = "metadata.json"
_MAX_METADATA_BYTES = 16 * 2**20
_MAX_DEPTH = 48
#: Array kinds a file may hold: booleans, integers, floats, complex, text.
_ARRAY_KINDS = "biufcUS"
_TAGS = ("__array__", "__dict__", "__dtype__", "__estimator__", "__float__", "__scalar__",
         "__strings__", "__tuple__")  # fmt: skip

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


# ------------------------------------------------------------------ registry


#: Every class a model file may name (the project's estimators and a few of
#: scikit-learn's), and the module it is imported from: only the classes a file
#: names are imported when it is read.
_ALLOWED: dict[str, str] = {
    **dict.fromkeys(["AngleSpectrum", "FourierFeatures", "LastLap"], "tentaclass.features"),
    # every estimator of the classifiers package (the package loads a class on first use)
    **dict.fromkeys(
        [name for name in classifiers.__all__ if name.endswith("Classifier")],
        "tentaclass.classifiers",
    ),
    "ScannerModel": "tentaclass.scanner",
    "FeatureUnion": "sklearn.pipeline",
    "Pipeline": "sklearn.pipeline",
    "KNeighborsClassifier": "sklearn.neighbors",
    "LabelBinarizer": "sklearn.preprocessing",
    "LogisticRegression": "sklearn.linear_model",
    "MLPClassifier": "sklearn.neural_network",
    "StandardScaler": "sklearn.preprocessing",
}


@cache
def _allowed_class(name: str) -> type:
    """The class a model file names as ``name`` (which must be in ``_ALLOWED``)."""
    return getattr(importlib.import_module(_ALLOWED[name]), name)


def _rebuild_knn(est: Any) -> None:
    est.fit(est._fit_X, est.classes_[est._y])


#: Attributes not stored for a class (caches rebuilt from the state, or helpers
#: that only matter for further training), and what rebuilds them on loading.
_DERIVED: dict[str, tuple[tuple[str, ...], Callable[[Any], None] | None]] = {
    "PNNClassifier": (
        ("_center", "_gamma", "_pt", "_bounds", "_tiles1"),
        lambda est: est._prepare(),
    ),
    "MLPClassifier": (("_optimizer", "_random_state"), None),
    "FixedEpochsMLPClassifier": (("_optimizer", "_random_state"), None),
    "KNeighborsClassifier": (("_tree",), _rebuild_knn),
}


#: Parameters and fitted attributes renamed since files were first written: old -> new.
_RENAMED: dict[str, dict[str, str]] = {
    "FourierFeatures": {"n_coeffs": "n_harmonics", "n_coeffs_": "n_harmonics_"},
    "AngleSpectrum": {"n_coeffs": "n_harmonics", "n_coeffs_": "n_harmonics_"},
    "FourierClassifier": {"n_coeffs": "n_harmonics"},
    "ScannerModel": {"n_coeffs": "n_harmonics"},
}


def _renamed_keys(name: str, d: dict) -> dict:
    """``d`` with the old names of ``name``'s parameters or attributes replaced by the new."""
    out = dict(d)
    for old, new in _RENAMED.get(name, {}).items():
        if old in out and new not in out:
            out[new] = out.pop(old)
    return out


def _class_name(est: object) -> str:
    name = type(est).__name__
    if name not in _ALLOWED or _allowed_class(name) is not type(est):
        raise InputError(
            f"save_model cannot save a {name}: model files hold only "
            f"{', '.join(sorted(_ALLOWED))} (and pipelines of them)"
        )
    return name


# --------------------------------------------------------------------- saving


class _Writer:
    """Encodes values into JSON-able trees, collecting arrays on the side."""

    def __init__(self) -> None:
        self.arrays: dict[str, np.ndarray] = {}

    def value(self, v: Any, where: str) -> Any:
        from sklearn.base import BaseEstimator

        if v is None or isinstance(v, bool | str):
            return v
        if isinstance(v, int):
            return int(v)
        if isinstance(v, float):
            return v if math.isfinite(v) else {"__float__": repr(v)}
        if isinstance(v, np.ndarray):
            return self.array(v, where)
        if isinstance(v, np.generic):
            if v.dtype.kind not in _ARRAY_KINDS:
                raise InputError(f"cannot save {where}: numpy scalar of dtype {v.dtype}")
            item = v.item()
            if isinstance(item, float) and not math.isfinite(item):
                item = {"__float__": repr(item)}
            elif isinstance(item, complex | bytes):
                return self.array(np.asarray(v), where)
            return {"__scalar__": item, "dtype": v.dtype.str}
        if isinstance(v, np.dtype) or (isinstance(v, type) and issubclass(v, np.generic)):
            return {"__dtype__": _savable_dtype(np.dtype(v), where).str}
        if isinstance(v, tuple):
            return {"__tuple__": [self.value(x, f"{where}[{i}]") for i, x in enumerate(v)]}
        if isinstance(v, list):
            return [self.value(x, f"{where}[{i}]") for i, x in enumerate(v)]
        if isinstance(v, dict):
            if not all(isinstance(k, str) for k in v):
                raise InputError(f"cannot save {where}: a dict whose keys are not all strings")
            return {"__dict__": {k: self.value(x, f"{where}[{k!r}]") for k, x in v.items()}}
        if isinstance(v, BaseEstimator):
            return self.estimator(v, where)
        raise InputError(f"cannot save {where} of type {type(v).__name__}: {v!r:.80}")

    def array(self, arr: np.ndarray, where: str) -> dict:
        if arr.dtype.kind == "O":
            flat = arr.ravel().tolist()
            if not all(isinstance(x, str) for x in flat):
                raise InputError(f"cannot save {where}: an object array that is not all strings")
            return {"__strings__": flat, "shape": list(arr.shape)}
        _savable_dtype(arr.dtype, where)
        name = f"a{len(self.arrays)}"
        # Fortran-ordered arrays stay so (the .npy header records it): a model
        # reloaded with another memory order takes other BLAS paths and can
        # differ from the saved one in the last bits.
        if not arr.flags.f_contiguous:
            arr = np.ascontiguousarray(arr)
        self.arrays[name] = arr
        return {"__array__": name}

    def estimator(self, est: Any, where: str) -> dict:
        import numbers

        name = _class_name(est)
        params = est.get_params(deep=False)
        skipped = _DERIVED.get(name, ((), None))[0]
        enc_params = {}
        for key, val in params.items():
            if key == "random_state" and not isinstance(val, numbers.Integral | type(None)):
                val = None  # a generator only matters for refitting
            enc_params[key] = self.value(val, f"{name} parameter {key!r}")
        state = {}
        for key, val in vars(est).items():
            if key in params or key in skipped or key.startswith("__"):
                continue
            state[key] = self.value(val, f"{name} attribute {key!r}")
        return {"__estimator__": name, "params": enc_params, "state": state}


def _savable_dtype(dtype: np.dtype, where: str) -> np.dtype:
    if dtype.kind not in _ARRAY_KINDS or dtype.fields is not None or dtype.subdtype is not None:
        raise InputError(f"cannot save {where}: arrays of dtype {dtype} are not stored")
    return dtype


def _npy_bytes(arr: np.ndarray) -> bytes:
    buf = io.BytesIO()
    np.lib.format.write_array(buf, arr, allow_pickle=False)
    return buf.getvalue()


def _check_json(value: Any, where: str) -> None:
    """``value`` must be plain JSON (str keys, finite numbers)."""
    if value is None or isinstance(value, bool | str | int):
        return
    if isinstance(value, float):
        if not math.isfinite(value):
            raise InputError(f"{where} must be finite, got {value!r}")
        return
    if isinstance(value, list | tuple):
        for i, v in enumerate(value):
            _check_json(v, f"{where}[{i}]")
        return
    if isinstance(value, dict):
        for k, v in value.items():
            if not isinstance(k, str):
                raise InputError(f"{where} keys must be strings, got {k!r}")
            _check_json(v, f"{where}[{k!r}]")
        return
    raise InputError(f"{where} must hold only JSON values, got {type(value).__name__}")


def save_model(estimator: object, path: str | os.PathLike, *, info: dict | None = None) -> Path:
    """Write a fitted estimator to a ``.tcm`` model file.

    Parameters
    ----------
    estimator : estimator
        Fitted. Any of the project's classifiers and transformers
        (:mod:`tentaclass.classifiers`, :mod:`tentaclass.features`), the
        scanner's :class:`~tentaclass.scanner.ScannerModel`, and scikit-learn's
        ``Pipeline``, ``FeatureUnion``, ``StandardScaler``, ``MLPClassifier``,
        ``LogisticRegression`` and ``KNeighborsClassifier``, nested in any way.
    path : str or path-like
        Destination, overwritten if it exists (conventionally ``*.tcm``).
    info : dict, optional
        JSON-able facts to keep with the model, such as the chain it was
        trained for (``{"chain": {"n_links": 16, "link_length": 1.0}}``);
        read back by :func:`model_info`.

    Returns
    -------
    path : pathlib.Path

    Raises
    ------
    tentaclass.errors.InputError
        An estimator outside the allow-list, or a value that cannot be stored
        without pickle (e.g. an ``unknown_label`` that is an arbitrary object).
    sklearn.exceptions.NotFittedError
        The estimator is not fitted.

    Examples
    --------
    >>> import numpy as np, tempfile, os
    >>> from tentaclass.classifiers import TentacleClassifier
    >>> from tentaclass.datasets import thesis_tentacle
    >>> X, y = thesis_tentacle(16, return_X_y=True)
    >>> clf = TentacleClassifier().fit(X, y)
    >>> path = os.path.join(tempfile.mkdtemp(), "shapes.tcm")
    >>> _ = save_model(clf, path, info={"chain": {"n_links": 16}})
    >>> loaded = load_model(path)
    >>> bool(np.array_equal(loaded.predict_proba(X), clf.predict_proba(X)))
    True
    >>> model_info(path)["chain"]
    {'n_links': 16}
    """
    from sklearn.utils.validation import check_is_fitted

    from .. import __version__

    _class_name(estimator)
    check_is_fitted(estimator)
    path = as_path(path)
    info = {} if info is None else info
    if not isinstance(info, dict):
        raise InputError(f"info must be a dict, got {type(info).__name__}")
    _check_json(info, "info")
    writer = _Writer()
    tree = writer.estimator(estimator, "estimator")
    blobs = {name: _npy_bytes(arr) for name, arr in writer.arrays.items()}
    meta: dict[str, Any] = {
        "format": FORMAT_NAME,
        "format_version": FORMAT_VERSION,
        "library_version": __version__,
        "estimator": tree,
        "info": info,
        "arrays": {
            name: {
                "shape": list(arr.shape),
                "dtype": arr.dtype.str,
                "sha256": hashlib.sha256(blobs[name]).hexdigest(),
            }
            for name, arr in writer.arrays.items()
        },
    }
    with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_DEFLATED) as zf:
        zf.writestr(_METADATA, json.dumps(meta, indent=None, sort_keys=True))
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


def _dtype_from(text: object, where: str) -> np.dtype:
    """A dtype from a string in the metadata: never a dict, list or object dtype."""
    if not isinstance(text, str):
        raise ModelFileError(f"metadata: {where} must be a dtype string, got {type(text).__name__}")
    try:
        dt = np.dtype(text)
    except (TypeError, ValueError, SyntaxError):
        raise ModelFileError(f"metadata: {where} {text!r} is not a dtype") from None
    if dt.kind not in _ARRAY_KINDS or dt.fields is not None or dt.subdtype is not None:
        raise ModelFileError(f"metadata: {where} {text!r} is not allowed (only {_ARRAY_KINDS})")
    return dt


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
        dtype = _dtype_from(_field(spec, "dtype", (str, dict, list), where), f"{where}dtype")
        digest = _field(spec, "sha256", str, where)
        blob = _read_member(zf, f"{name}.npy", path)
        if hashlib.sha256(blob).hexdigest() != digest:
            raise ModelFileError(f"{path}: checksum mismatch for array {name!r} (damaged file)")
        try:
            arr = np.lib.format.read_array(io.BytesIO(blob), allow_pickle=False)
        except (ValueError, OSError, EOFError) as exc:
            raise ModelFileError(f"{path}: array {name!r} is not a valid .npy ({exc})") from None
        if list(arr.shape) != shape or arr.dtype != dtype or arr.dtype.str != dtype.str:
            raise ModelFileError(
                f"{path}: array {name!r} is {arr.dtype.str} {list(arr.shape)}, "
                f"metadata says {dtype.str} {shape}"
            )
        arrays[name] = arr
    return arrays


class _Reader:
    """Decodes the estimator tree, checking every node."""

    def __init__(self, arrays: dict[str, np.ndarray]) -> None:
        self.arrays = arrays
        self.used: set[str] = set()

    def value(self, v: Any, where: str, depth: int = 0) -> Any:
        if depth > _MAX_DEPTH:
            raise ModelFileError(f"metadata: {where} is nested too deeply")
        if v is None or isinstance(v, bool | str | int):
            return v
        if isinstance(v, float):
            if not math.isfinite(v):
                raise ModelFileError(f"metadata: {where} is not a finite number")
            return v
        if isinstance(v, list):
            return [self.value(x, f"{where}[{i}]", depth + 1) for i, x in enumerate(v)]
        if not isinstance(v, dict):
            raise ModelFileError(f"metadata: {where} has an unknown type")
        tags = [t for t in _TAGS if t in v]
        if len(tags) != 1:
            raise ModelFileError(f"metadata: {where} is an object without one known tag")
        tag = tags[0]
        body = v[tag]
        if tag == "__estimator__":
            return self.estimator(v, where, depth)
        if set(v) - {tag, "dtype", "shape"}:
            raise ModelFileError(f"metadata: {where} has unknown fields {sorted(set(v) - {tag})}")
        if tag == "__tuple__":
            items = _field(v, tag, list, f"{where}.")
            return tuple(self.value(x, f"{where}[{i}]", depth + 1) for i, x in enumerate(items))
        if tag == "__dict__":
            items = _field(v, tag, dict, f"{where}.")
            return {k: self.value(x, f"{where}[{k!r}]", depth + 1) for k, x in items.items()}
        if tag == "__float__":
            if body not in ("nan", "inf", "-inf"):
                raise ModelFileError(f"metadata: {where} is not nan, inf or -inf: {body!r}")
            return float(body)
        if tag == "__dtype__":
            return _dtype_from(body, f"{where} dtype")
        if tag == "__scalar__":
            dt = _dtype_from(v.get("dtype"), f"{where} dtype")
            if isinstance(body, dict) and set(body) == {"__float__"}:
                body = self.value(body, where, depth + 1)
            if body is None or (isinstance(body, list | dict | str) and dt.kind not in "US"):
                raise ModelFileError(f"metadata: {where} is not a {dt} scalar")
            try:
                return np.array(body, dtype=dt)[()]
            except (TypeError, ValueError, OverflowError):
                raise ModelFileError(f"metadata: {where} {body!r} is not a {dt} scalar") from None
        if tag == "__strings__":
            items = _field(v, tag, list, f"{where}.")
            shape = _field(v, "shape", list, f"{where}.")
            if not all(isinstance(s, str) for s in items) or not _is_shape(shape):
                raise ModelFileError(f"metadata: {where} must be strings with a valid shape")
            if math.prod(shape) != len(items):
                raise ModelFileError(f"metadata: {where} holds {len(items)} strings, not {shape}")
            out = np.empty(len(items), dtype=object)
            out[:] = items
            return out.reshape(shape)
        # "__array__"
        if not isinstance(body, str) or body not in self.arrays:
            raise ModelFileError(f"metadata: {where} names no array of the file ({body!r})")
        if body in self.used:
            raise ModelFileError(f"metadata: array {body!r} is used twice")
        self.used.add(body)
        return self.arrays[body]

    def estimator(self, v: dict, where: str, depth: int) -> Any:
        if set(v) != {"__estimator__", "params", "state"}:
            raise ModelFileError(f"metadata: {where} must hold __estimator__, params and state")
        name = v["__estimator__"]
        if not isinstance(name, str) or name not in _ALLOWED:
            raise ModelFileError(
                f"metadata: {where} is a {name!r}, which is not an estimator model files may "
                f"hold ({', '.join(sorted(_ALLOWED))})"
            )
        cls = _allowed_class(name)
        params = _renamed_keys(name, _field(v, "params", dict, f"{where}."))
        state = _renamed_keys(name, _field(v, "state", dict, f"{where}."))
        kwargs = {k: self.value(x, f"{name} parameter {k!r}", depth + 1) for k, x in params.items()}
        try:
            est = cls(**kwargs)
            # an old file lacks the deprecated aliases its own names became
            kwargs.update({k: x for k, x in est.get_params(deep=False).items() if k not in kwargs
                           and k in _RENAMED.get(name, {})})  # fmt: skip
        except (TypeError, ValueError) as exc:
            raise ModelFileError(f"metadata: bad {name} parameters: {exc}") from None
        if set(kwargs) != set(est.get_params(deep=False)):
            raise ModelFileError(
                f"metadata: {name} parameters {sorted(kwargs)} are not "
                f"{sorted(est.get_params(deep=False))}"
            )
        skipped = _DERIVED.get(name, ((), None))[0]
        for key, x in state.items():
            if (
                not key.isidentifier()
                or keyword.iskeyword(key)
                or key.startswith("__")
                or key in kwargs
                or key in skipped
                or hasattr(cls, key)
            ):
                raise ModelFileError(f"metadata: {name} cannot have the attribute {key!r}")
            setattr(est, key, self.value(x, f"{name} attribute {key!r}", depth + 1))
        _check_estimator(est, name)
        return est


def _is_shape(shape: object) -> bool:
    return isinstance(shape, list) and all(
        isinstance(s, int) and not isinstance(s, bool) and s >= 0 for s in shape
    )


def _check_pnn(est: Any) -> None:
    P, counts = est.patterns_, est.class_count_
    n_classes = len(est.classes_)
    if (
        not isinstance(P, np.ndarray)
        or P.dtype.kind != "f"
        or P.ndim != 2
        or P.shape[1] != est.n_features_in_
        or not isinstance(counts, np.ndarray)
        or counts.dtype.kind not in "iu"
        or counts.shape != (n_classes,)
        or np.any(counts < 1)
        or int(counts.sum()) != P.shape[0]
    ):
        raise ModelFileError("PNN arrays are inconsistent with each other or the classes")
    if not np.all(np.isfinite(P)):
        raise ModelFileError("PNN patterns hold NaN or infinite values")
    spread = est.spread_
    if not (isinstance(spread, float | int) and math.isfinite(spread) and spread > 0):
        raise ModelFileError(f"PNN spread_ must be a finite number > 0, got {est.spread_!r}")


def _check_rbf(est: Any) -> None:
    C, W, b = est.centers_, est.coef_, est.intercept_
    n_classes = len(est.classes_)
    if not all(isinstance(a, np.ndarray) and a.dtype.kind == "f" for a in (C, W, b)) or (
        C.ndim != 2
        or C.shape[1] != est.n_features_in_
        or W.shape != (C.shape[0], n_classes)
        or b.shape != (n_classes,)
    ):
        raise ModelFileError("RBF arrays are inconsistent with each other or the classes")


def _check_names(steps: object, where: str) -> None:
    """A Pipeline's steps or a FeatureUnion's transformers: (name, estimator) pairs.

    The names follow scikit-learn's rules: distinct strings without ``__``.
    """
    items = steps if isinstance(steps, list) else [None]
    names = [s[0] if isinstance(s, tuple) and len(s) == 2 else None for s in items]
    if (
        not isinstance(steps, list)
        or not all(isinstance(n, str) and n and "__" not in n for n in names)
        or len(set(names)) != len(names)
    ):
        raise ModelFileError(f"{where} must be (name, estimator) pairs with distinct names")


#: How many features a fitted transformer gives, from its state.
_OUTPUT_WIDTH: dict[str, str] = {
    "AngleSpectrum": "n_harmonics_",
    "FourierFeatures": "n_harmonics_",
    "LastLap": "n_out_",
    "StandardScaler": "n_features_in_",
}


def _check_pipeline(est: Any) -> None:
    """Step names, and each fitted step taking as many features as the one before gives."""
    _check_names(est.steps, "Pipeline steps")
    for (name_a, a), (name_b, b) in zip(est.steps, est.steps[1:], strict=False):
        attr = _OUTPUT_WIDTH.get(type(a).__name__)
        width = getattr(a, attr, None) if attr else None
        takes = getattr(b, "n_features_in_", None)
        if width is not None and takes is not None and takes != width:
            raise ModelFileError(
                f"step {name_b!r} has n_features_in_ {takes}, but step {name_a!r} gives "
                f"{width} features ({attr} {width})"
            )


def _check_feature_union(est: Any) -> None:
    """FeatureUnion's parameters, which scikit-learn checks only when it transforms."""
    _check_names(est.transformer_list, "FeatureUnion transformer_list")
    n_jobs, weights = est.n_jobs, est.transformer_weights
    if n_jobs is not None and (
        isinstance(n_jobs, bool) or not isinstance(n_jobs, int) or n_jobs == 0
        or abs(n_jobs) > 2**31 - 1
    ):  # fmt: skip
        raise ModelFileError(f"FeatureUnion n_jobs must be None or a non-zero int, got {n_jobs!r}")
    if weights is not None and not (
        isinstance(weights, dict)
        and all(
            isinstance(w, int | float) and not isinstance(w, bool) and math.isfinite(w)
            for w in weights.values()
        )
    ):
        raise ModelFileError(
            f"FeatureUnion transformer_weights must be None or a dict of numbers, got {weights!r}"
        )


def _check_tentacle(est: Any) -> None:
    """The matchers of a TentacleClassifier compare laps of ``n_points`` angles."""
    for key in ("matcher_", "exact_"):
        takes = getattr(getattr(est, key, None), "n_features_in_", None)
        if takes is not None and takes != est.n_points:
            raise ModelFileError(
                f"{key} has n_features_in_ {takes}, but laps have n_points {est.n_points} angles"
            )


_CHECKS: dict[str, Callable[[Any], None]] = {
    "PNNClassifier": _check_pnn,
    "RBFNetworkClassifier": _check_rbf,
    "TentacleClassifier": _check_tentacle,
}

#: Checks of estimators whether fitted or not (a FeatureUnion has no fitted state).
_PARAM_CHECKS: dict[str, Callable[[Any], None]] = {
    "FeatureUnion": _check_feature_union,
    "Pipeline": _check_pipeline,
}

#: Fitted counts that must be integers >= 1 wherever an estimator has them.
_COUNTS = ("n_features_in_", "n_harmonics_", "n_out_")

_MLP_COUNTS: tuple[tuple[str, Callable[[Any], int]], ...] = (
    ("n_features_in_", lambda e: e.coefs_[0].shape[0]),
    ("n_layers_", lambda e: len(e.coefs_) + 1),
    ("n_outputs_", lambda e: e.coefs_[-1].shape[1]),
)

#: Fitted counts that the stored arrays fix: count -> its value read from the arrays.
_SHAPE_COUNTS: dict[str, tuple[tuple[str, Callable[[Any], int]], ...]] = {
    "FixedEpochsMLPClassifier": _MLP_COUNTS,
    "KNeighborsClassifier": (
        ("n_features_in_", lambda e: e._fit_X.shape[1]),
        ("n_samples_fit_", lambda e: e._fit_X.shape[0]),
    ),
    "LogisticRegression": (("n_features_in_", lambda e: e.coef_.shape[1]),),
    "MLPClassifier": _MLP_COUNTS,
    "RBFNetworkClassifier": (("n_centers_", lambda e: e.centers_.shape[0]),),
    "StandardScaler": (
        ("n_features_in_", lambda e: (e.scale_ if e.mean_ is None else e.mean_).shape[0]),
    ),
}

#: Transformers of ``n_features_in_`` angles keep at most ``n_features_in_ // 2 + extra``
#: harmonics (the rfft's length less the Nyquist term, or all of it).
_HARMONICS_EXTRA = {"FourierFeatures": 0, "AngleSpectrum": 1}


def _check_counts(est: Any) -> None:
    state = vars(est)
    for key in _COUNTS:
        value = state.get(key, 1)
        if isinstance(value, bool) or not isinstance(value, int) or not 1 <= value <= 2**31 - 1:
            raise ModelFileError(f"{key} must be an integer from 1 to 2**31 - 1, got {value!r}")


def _check_shape_counts(est: Any, name: str) -> None:
    """Counts of a fitted estimator against the arrays it stores and its input length."""
    state = vars(est)
    for key, from_arrays in _SHAPE_COUNTS.get(name, ()):
        if key in state and state[key] != from_arrays(est):
            raise ModelFileError(
                f"{key} is {state[key]}, but the stored arrays are for {from_arrays(est)}"
            )
    if name in _HARMONICS_EXTRA and "n_harmonics_" in state and "n_features_in_" in state:
        top = state["n_features_in_"] // 2 + _HARMONICS_EXTRA[name]
        if state["n_harmonics_"] > top:
            raise ModelFileError(
                f"n_harmonics_ is {state['n_harmonics_']}, more than the {top} that "
                f"n_features_in_ {state['n_features_in_']} angles have"
            )


def _check_estimator(est: Any, name: str) -> None:
    """Validate parameters and state, then rebuild derived caches."""
    from sklearn.base import BaseEstimator

    own_check = getattr(type(est), "_validate_params", None) is not BaseEstimator._validate_params
    try:
        if hasattr(est, "_parameter_constraints") or own_check:
            est._validate_params()
        _check_counts(est)
        _check_shape_counts(est, name)
        if name in _PARAM_CHECKS:
            _PARAM_CHECKS[name](est)
        if name in _CHECKS and hasattr(est, "classes_"):
            _CHECKS[name](est)
        rebuild = _DERIVED.get(name, ((), None))[1]
        if rebuild is not None and hasattr(est, "n_features_in_"):
            rebuild(est)
    except ModelFileError as exc:
        raise ModelFileError(f"metadata: {name}: {exc}") from None
    except (TypeError, ValueError, KeyError, AttributeError, IndexError) as exc:
        raise ModelFileError(f"metadata: bad {name} parameters or state: {exc}") from None


def model_path(path: str | os.PathLike) -> Path:
    """``path`` as a Path, refused unless it names a file.

    Raises
    ------
    tentaclass.errors.ModelFileNotFoundError
        Nothing at ``path`` (a ``ModelFileError`` and a ``FileNotFoundError``).
    tentaclass.errors.ModelFileError
        A directory, or anything else that is not a file, at ``path``.

    Examples
    --------
    >>> import tempfile
    >>> model_path(tempfile.mkdtemp())
    Traceback (most recent call last):
    ...
    tentaclass.errors.ModelFileError: ...: is a directory, not a model file
    """
    path = as_path(path)
    if path.is_file():
        return path
    if path.is_dir():
        raise ModelFileError(f"{path}: is a directory, not a model file")
    if path.exists():
        raise ModelFileError(f"{path}: not a regular file, so not a model file")
    raise ModelFileNotFoundError(f"{path}: no such model file")


def _open(path: str | os.PathLike) -> tuple[dict, dict[str, np.ndarray], Path]:
    """Metadata and checked arrays of a model file."""
    path = model_path(path)
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
        except (UnicodeDecodeError, json.JSONDecodeError, RecursionError) as exc:
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
        if version not in (1, FORMAT_VERSION):
            raise ModelFileError(f"{path}: unknown format version {version!r}")
        try:
            arrays = _read_arrays(zf, meta, path)
        except ModelFileError as exc:
            msg = str(exc)
            raise ModelFileError(msg if msg.startswith(str(path)) else f"{path}: {msg}") from None
    return meta, arrays, path


def model_info(path: str | os.PathLike) -> dict:
    """The ``info`` stored with a model, plus what the file says about itself.

    Parameters
    ----------
    path : str or path-like

    Returns
    -------
    info : dict
        The ``info`` given to :func:`save_model` (empty for version-1 files),
        with ``"estimator"`` (class name), ``"format_version"`` and
        ``"library_version"`` added.

    Raises
    ------
    tentaclass.errors.ModelFileError
        As :func:`load_model`.

    Examples
    --------
    >>> from importlib.resources import files
    >>> info = model_info(files("tentaclass.data") / "default-16.tcm")
    >>> info["chain"]["n_links"], info["estimator"]
    (16, 'Pipeline')
    """
    meta, _, path = _open(path)
    return info_from_metadata(meta, path)


def info_from_metadata(meta: dict, path: Path) -> dict:
    """What :func:`model_info` returns, from the metadata of the file at ``path``."""
    info = meta.get("info", {})
    if not isinstance(info, dict):
        raise ModelFileError(f"{path}: metadata: info must be an object")
    tree = meta.get("estimator")
    name = tree.get("__estimator__") if isinstance(tree, dict) else tree
    return {
        **info,
        "estimator": name if isinstance(name, str) else None,
        "format_version": meta["format_version"],
        "library_version": meta.get("library_version"),
    }


def load_model(path: str | os.PathLike) -> Any:
    """Read a model written by :func:`save_model`.

    Parameters
    ----------
    path : str or path-like

    Returns
    -------
    estimator : estimator
        Fitted, predicting exactly as the saved one did.

    Raises
    ------
    tentaclass.errors.ModelFileError
        ``path`` is a directory, or the file is not a tentaclass model (text,
        random zip, plain ``.npz``),
        is truncated or damaged (bad zip, checksum mismatch), has an unknown
        or newer format version, names a class outside the allow-list, holds
        an object or structured dtype, a dtype that is not a string, or
        parameters and arrays that do not fit together.
    tentaclass.errors.ModelFileNotFoundError
        No file at ``path``: a ``ModelFileError`` and a ``FileNotFoundError``.

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
    meta, arrays, path = _open(path)
    try:
        if meta["format_version"] == 1:
            from ._v1 import build_v1

            return build_v1(meta, arrays)
        _field(meta, "library_version", str, "")
        info = meta.get("info", {})
        if not isinstance(info, dict):
            raise ModelFileError("metadata: info must be an object")
        reader = _Reader(arrays)
        tree = _field(meta, "estimator", dict, "")
        if "__estimator__" not in tree:
            raise ModelFileError("metadata: estimator is not an estimator record")
        est = reader.value(tree, "estimator")
        if reader.used != set(arrays):
            raise ModelFileError(f"metadata: arrays {sorted(set(arrays) - reader.used)} unused")
        return est
    except ModelFileError as exc:
        raise ModelFileError(f"{path}: {exc}") from None
