"""Predicting straight from a model file, without importing scikit-learn.

Importing scikit-learn takes several times as long as everything else a
one-array ``tentaclass classify`` does. :func:`load_light` reads a model
file's estimator tree into light objects that predict with the same code as
the estimators themselves: the project's estimators inherit their
prediction from scikit-learn-free cores (``TentacleCore``, ``ShiftCore``,
``PNNCore``, the transformers' cores), and a light object is such a core
with the file's parameters and fitted state set on it. Of scikit-learn's
classes, a ``Pipeline``, a ``FeatureUnion`` without weights, a
``StandardScaler`` and an ``MLPClassifier``'s forward pass are evaluated here
with the operations scikit-learn uses (the tests compare every result with
the full load's).

A tree holding anything else, a parameter value these do not cover, or an
attribute they do not know (a new member of the blend, say) is not light:
:func:`load_light` returns ``None`` and the caller loads the model in full
with :func:`~tentaclass.io.load_model`, which also gives the errors of
damaged files.
"""

from __future__ import annotations

import os
from typing import Any

import numpy as np

from .._deprecation import DEPRECATED
from .._typing import ArrayLike, FloatArray
from ..classifiers import PNNCore, ShiftCore, TentacleCore
from ..errors import InputError, ModelFileError
from ..features import AngleSpectrumCore, FourierFeaturesCore, LastLapCore
from ._model_file import (
    _RENAMED,
    _check_pnn,
    _field,
    _open,
    _Reader,
    _renamed_keys,
    info_from_metadata,
)

__all__ = ["load_light"]

#: Estimators a light model may have at its root (models of joint angles).
_ROOTS = ("TentacleClassifier", "Pipeline")


class _NotLight(Exception):
    """The tree holds something the light objects do not cover."""


def _check_rows(est: Any, X: ArrayLike) -> FloatArray:
    """Finite float64 rows of ``n_features_in_`` values, as the estimators check them."""
    X = np.asarray(X)
    if X.ndim != 2 or X.shape[0] == 0 or X.dtype.kind not in "biuf":
        raise InputError(f"expected a non-empty 2-D array of numbers, got shape {X.shape}")
    if X.shape[1] != est.n_features_in_:
        raise InputError(
            f"X has {X.shape[1]} features, but the model is expecting "
            f"{est.n_features_in_} features as input"
        )
    X = X.astype(np.float64, copy=False)
    if not np.isfinite(X).all():
        raise InputError("X holds NaN or infinite values")
    return X


class _Light:
    """A light object: ``params`` and ``state`` are the names it takes from the file.

    With ``exact``, the file must hold exactly these names; otherwise at
    least these, and parameters only from ``params | ignored`` when
    ``ignored`` is given (scikit-learn's parameters and fitted attributes
    vary across its versions).
    """

    params: frozenset[str] = frozenset()
    state: frozenset[str] = frozenset()
    exact = True
    ignored: frozenset[str] | None = None
    n_features_in_: int

    @classmethod
    def build(cls, params: dict, state: dict) -> _Light:
        for names, given in ((cls.params, params), (cls.state, state)):
            if (set(given) != names) if cls.exact else not names <= set(given):
                raise _NotLight
        if cls.ignored is not None and not set(params) <= cls.params | cls.ignored:
            raise _NotLight
        est = cls.__new__(cls)
        for key, value in {**params, **state}.items():
            setattr(est, key, value)
        est._check()
        return est

    def _check(self) -> None:
        """Refuse values the light prediction does not cover (raise ``_NotLight``)."""


def _is_array(a: object, kind: str = "f", ndim: int | None = None) -> bool:
    return isinstance(a, np.ndarray) and a.dtype.kind in kind and (ndim is None or a.ndim == ndim)


def _require(ok: bool) -> None:
    if not ok:
        raise _NotLight


# ------------------------------------------------------------------ the project's


class _Transformer(_Light):
    #: The fitted output size: its attribute and least value.
    size: tuple[str, int]

    def _check(self) -> None:
        name, least = self.size
        value = getattr(self, name)
        _require(isinstance(self.n_features_in_, int) and isinstance(value, int) and value >= least)

    def _transform(self, X: FloatArray) -> FloatArray:
        raise NotImplementedError

    def transform(self, X: ArrayLike) -> FloatArray:
        return self._transform(_check_rows(self, X))


class _FourierFeatures(FourierFeaturesCore, _Transformer):
    params = frozenset({"n_harmonics", "detrend", "normalize", "weight_power"})
    state = frozenset({"n_harmonics_", "n_features_in_"})
    size = ("n_harmonics_", 1)

    def _check(self) -> None:
        super()._check()
        _require(isinstance(self.weight_power, int | float) and np.isfinite(self.weight_power))


class _LastLap(LastLapCore, _Transformer):
    params = frozenset({"n_out"})
    state = frozenset({"n_out_", "n_features_in_"})
    size = ("n_out_", 2)


class _AngleSpectrum(AngleSpectrumCore, _Transformer):
    params = frozenset({"n_harmonics"})
    state = frozenset({"n_harmonics_", "n_features_in_"})
    size = ("n_harmonics_", 1)


class _PNN(PNNCore, _Light):
    params = frozenset({"spread", "reject_below", "unknown_label", "dtype"})
    state = frozenset({"classes_", "n_features_in_", "spread_", "patterns_", "class_count_"})

    def _check(self) -> None:
        _require(isinstance(self.n_features_in_, int) and isinstance(self.classes_, np.ndarray))
        rb = self.reject_below
        _require(rb is None or (isinstance(rb, int | float) and 0 <= rb <= 1))
        try:
            self._compute_dtype()
            _check_pnn(self)
        except (InputError, ModelFileError):
            raise _NotLight from None
        self._prepare()

    def _check_X(self, X: ArrayLike) -> FloatArray:
        return _check_rows(self, X)


class _ShiftNN(ShiftCore, _Light):
    params = frozenset({"signal", "mirror", "center", "n_harmonics", "weight_power", "closure"})
    state = frozenset({"classes_", "labels_", "n_features_in_", "weights_", "spectra_", "norms_"})

    labels_: np.ndarray

    def _check(self) -> None:
        _require(self.signal in ("turning", "shape", "raw") and self.closure in ("spread", "chord"))
        _require(isinstance(self.mirror, bool) and isinstance(self.center, bool))
        _require(isinstance(self.n_features_in_, int) and _is_array(self.labels_, "iu", 1))
        _require(_is_array(self.spectra_, "fc", 2) and _is_array(self.norms_, "f", 1))
        _require(_is_array(self.weights_, "f", 1) and self.weights_.size == self.spectra_.shape[1])
        _require(len(self.norms_) == len(self.spectra_) == len(self.labels_))

    def shift_distances(self, X: ArrayLike) -> FloatArray:
        return self._shift_distances(_check_rows(self, X))


class _Tentacle(TentacleCore, _Light):
    params = frozenset({"n_points", "reject", "unknown_label"})
    state = frozenset(
        {"classes_", "n_features_in_", "matcher_", "exact_", "spectrum_", "weights_"}
        | {"lap_scale_", "exact_scale_", "headings_", "arc_labels_", "scale_", "temperature_"}
        | {"partial_scale_", "partial_temperature_"}
        | {"partial_reject_distance_", "partial_reject_margin_"}
        | {"elastic_scale_", "elastic_heights_", "elastic_complexity_", "owner_"}
        | {"class_spread_", "reject_coef_", "reject_threshold_"}
        | {"last_scale_", "last_heights_", "last_complexity_"}
    )
    #: What models saved before the elastic member of the last lap hold (four members).
    four = state - {"last_scale_", "last_heights_", "last_complexity_"}
    #: What models saved before the elastic rejection rule hold instead of its three.
    earlier = (four - {"class_spread_", "reject_coef_", "reject_threshold_"}) | {
        "reject_distance_",
        "reject_margin_",
    }

    @classmethod
    def build(cls, params: dict, state: dict) -> _Light:
        if cls is _Tentacle and set(state) == cls.earlier:
            return _EarlierTentacle.build(params, state)
        if cls is _Tentacle and set(state) == cls.four:
            return _FourMemberTentacle.build(params, state)
        return super().build(params, state)

    def _check(self) -> None:
        _require(isinstance(self.n_points, int) and self.n_points >= 8)
        _require(isinstance(self.n_features_in_, int) and isinstance(self.classes_, np.ndarray))
        _require(isinstance(self.matcher_, _ShiftNN) and isinstance(self.exact_, _ShiftNN))
        _require(self.spectrum_ is None or isinstance(self.spectrum_, _Pipeline))
        members = 5 if hasattr(self, "last_heights_") else 4
        _require(_is_array(self.weights_, "f", 1) and self.weights_.shape == (members,))
        if members == 5:
            _require(_is_array(self.last_heights_, "f", 3) and isinstance(self.last_scale_, float))
            _require(_is_array(self.last_complexity_, "f", 1))
            _require(self.weights_[4] == 0 or len(self.last_heights_) == len(self.exact_.labels_))
        _require(self.weights_[2] == 0 or self.spectrum_ is not None)
        _require(_is_array(self.elastic_heights_, "f", 3) and _is_array(self.owner_, "iu", 1))
        _require(_is_array(self.elastic_complexity_, "f", 1))
        _require(_is_array(self.headings_, "f", 2) and _is_array(self.arc_labels_, "iu", 1))
        if hasattr(self, "reject_coef_"):
            _require(_is_array(self.reject_coef_, "f", 1))
            _require(self.reject_coef_.shape in {(4,), (6,)})
            rule = len(self.reject_coef_) // 2 - 1  # members the rejection rule reads
            _require(_is_array(self.class_spread_, "f", 1))
            _require(isinstance(self.reject_threshold_, float))
            _require(self.class_spread_.size in (0, rule * len(self.classes_)))
            _require(rule < 2 or members == 5)
            _require(rule < 2 or len(self.last_heights_) == len(self.exact_.labels_))
            _require(self.class_spread_.size > 0 or not np.isfinite(self.reject_threshold_))

    def _scores(self, X: ArrayLike) -> tuple[FloatArray, np.ndarray, FloatArray, FloatArray]:
        return self._checked_scores(_check_rows(self, X))

    def predict(self, X: ArrayLike) -> np.ndarray:
        s, _, _, novelty = self._scores(X)
        return self._labels_of(s, novelty)

    def predict_proba(self, X: ArrayLike) -> FloatArray:
        return self._proba_of(*self._scores(X)[:2])


class _FourMemberTentacle(_Tentacle):
    """A model saved before the elastic member of the last lap."""

    state = _Tentacle.four


class _EarlierTentacle(_Tentacle):
    """A model saved before the elastic rejection rule (distance and margin limits)."""

    state = _Tentacle.earlier


# ------------------------------------------------------------------ scikit-learn's


class _Pipeline(_Light):
    params = frozenset({"steps"})
    exact = False
    ignored = frozenset({"memory", "verbose", "transform_input"})  # the last is checked

    steps: list

    def _check(self) -> None:
        _require(getattr(self, "transform_input", None) is None)
        _require(isinstance(self.steps, list) and len(self.steps) > 0)
        for step in self.steps:
            _require(isinstance(step, tuple) and len(step) == 2 and isinstance(step[1], _Light))
        for _, step in self.steps[:-1]:
            _require(hasattr(step, "transform"))

    def _predicts(self) -> bool:
        final = self.steps[-1][1]
        return hasattr(final, "predict") and hasattr(final, "predict_proba")

    @property
    def n_features_in_(self) -> int:  # type: ignore[override]
        return int(self.steps[0][1].n_features_in_)

    @property
    def classes_(self) -> np.ndarray:
        return self.steps[-1][1].classes_

    def _through(self, X: ArrayLike) -> Any:
        for _, step in self.steps[:-1]:
            X = step.transform(X)
        return X

    def transform(self, X: ArrayLike) -> FloatArray:
        return self.steps[-1][1].transform(self._through(X))

    def predict(self, X: ArrayLike) -> np.ndarray:
        return self.steps[-1][1].predict(self._through(X))

    def predict_proba(self, X: ArrayLike) -> FloatArray:
        return self.steps[-1][1].predict_proba(self._through(X))


class _FeatureUnion(_Light):
    params = frozenset({"transformer_list", "transformer_weights"})
    exact = False
    ignored = frozenset({"n_jobs", "verbose", "verbose_feature_names_out"})

    transformer_list: list
    transformer_weights: Any

    def _check(self) -> None:
        _require(self.transformer_weights is None)
        _require(isinstance(self.transformer_list, list) and len(self.transformer_list) > 0)
        for item in self.transformer_list:
            _require(isinstance(item, tuple) and len(item) == 2)
            _require(isinstance(item[1], _Light) and hasattr(item[1], "transform"))

    @property
    def n_features_in_(self) -> int:  # type: ignore[override]
        return int(self.transformer_list[0][1].n_features_in_)

    def transform(self, X: ArrayLike) -> FloatArray:
        return np.concatenate([t.transform(X) for _, t in self.transformer_list], axis=1)


class _StandardScaler(_Light):
    params = frozenset({"with_mean", "with_std"})
    state = frozenset({"mean_", "scale_", "n_features_in_"})
    exact = False  # var_ and n_samples_seen_ are not used
    ignored = frozenset({"copy"})  # transform copies the caller's array either way

    with_mean: bool
    with_std: bool
    mean_: Any
    scale_: Any

    def _check(self) -> None:
        n = self.n_features_in_
        _require(isinstance(n, int))
        for flag, arr in ((self.with_mean, self.mean_), (self.with_std, self.scale_)):
            _require(isinstance(flag, bool) and (not flag or _is_array(arr, "f", 1)))
            _require(not flag or arr.shape == (n,))

    def transform(self, X: ArrayLike) -> FloatArray:
        X = _check_rows(self, X).copy()
        if self.with_mean:
            X -= self.mean_.astype(X.dtype)
        if self.with_std:
            X /= self.scale_.astype(X.dtype)
        return X


def _inplace_logistic(a: FloatArray) -> None:
    from scipy.special import expit

    expit(a, out=a)


def _inplace_softmax(a: FloatArray) -> None:
    tmp = a - a.max(axis=1)[:, np.newaxis]
    np.exp(tmp, out=a)
    a /= a.sum(axis=1)[:, np.newaxis]


#: scikit-learn's in-place activations of ``MLPClassifier``.
_ACTIVATIONS = {
    "identity": lambda a: None,
    "logistic": _inplace_logistic,
    "tanh": lambda a: np.tanh(a, out=a),
    "relu": lambda a: np.maximum(a, 0, out=a),
    "softmax": _inplace_softmax,
}


class _MLP(_Light):
    params = frozenset({"activation"})
    state = frozenset(
        {"classes_", "coefs_", "intercepts_", "n_layers_", "n_outputs_", "out_activation_"}
        | {"n_features_in_"}
    )
    exact = False  # the training settings and history do not change a prediction

    activation: str
    out_activation_: str
    classes_: np.ndarray
    n_layers_: int
    n_outputs_: int
    coefs_: list
    intercepts_: list

    def _check(self) -> None:
        _require(self.activation in _ACTIVATIONS and self.out_activation_ in _ACTIVATIONS)
        _require(isinstance(self.classes_, np.ndarray) and isinstance(self.n_features_in_, int))
        n_layers = self.n_layers_
        _require(isinstance(n_layers, int) and n_layers >= 2)
        _require(isinstance(self.coefs_, list) and isinstance(self.intercepts_, list))
        _require(len(self.coefs_) == len(self.intercepts_) == n_layers - 1)
        width = self.n_features_in_
        for W, b in zip(self.coefs_, self.intercepts_, strict=True):
            _require(_is_array(W, "f", 2) and _is_array(b, "f", 1))
            _require(W.shape[0] == width and b.shape == (W.shape[1],))
            width = W.shape[1]
        _require(width == self.n_outputs_)

    def predict_proba(self, X: ArrayLike) -> FloatArray:
        """scikit-learn's ``MLPClassifier.predict_proba``: the forward pass, step by step."""
        a = _check_rows(self, X)
        for i in range(self.n_layers_ - 1):
            a = a @ self.coefs_[i]
            a += self.intercepts_[i]
            if i != self.n_layers_ - 2:
                _ACTIVATIONS[self.activation](a)
        _ACTIVATIONS[self.out_activation_](a)
        if self.n_outputs_ == 1:
            a = a.ravel()
        return np.vstack([1 - a, a]).T if a.ndim == 1 else a


class _Bag(_Light):
    """A helper estimator prediction does not use (an MLP's label binarizer)."""

    exact = False


_LIGHT: dict[str, type[_Light]] = {
    "TentacleClassifier": _Tentacle,
    "ShiftNNClassifier": _ShiftNN,
    "PNNClassifier": _PNN,
    "FourierFeatures": _FourierFeatures,
    "LastLap": _LastLap,
    "AngleSpectrum": _AngleSpectrum,
    "Pipeline": _Pipeline,
    "FeatureUnion": _FeatureUnion,
    "StandardScaler": _StandardScaler,
    "MLPClassifier": _MLP,
    "LabelBinarizer": _Bag,
}


class _LightReader(_Reader):
    """Decodes the estimator tree into light objects."""

    def estimator(self, v: dict, where: str, depth: int) -> Any:
        if set(v) != {"__estimator__", "params", "state"} or v["__estimator__"] not in _LIGHT:
            raise _NotLight
        name = v["__estimator__"]
        params = _renamed_keys(name, _field(v, "params", dict, f"{where}."))
        state = _renamed_keys(name, _field(v, "state", dict, f"{where}."))
        for alias in set(_RENAMED.get(name, {})) & set(params):  # a deprecated alias, unset
            if params.pop(alias) != DEPRECATED:
                raise _NotLight
        dec = {k: self.value(x, f"{name} parameter {k!r}", depth + 1) for k, x in params.items()}
        fitted = {k: self.value(x, f"{name} attribute {k!r}", depth + 1) for k, x in state.items()}
        if any(not k.isidentifier() or k.startswith("__") for k in (*dec, *fitted)):
            raise _NotLight
        return _LIGHT[name].build(dec, fitted)


def load_light(path: str | os.PathLike) -> tuple[Any | None, dict]:
    """A model file's light predictor (or ``None``) and its info, reading the file once.

    Parameters
    ----------
    path : str or path-like

    Returns
    -------
    model : object or None
        With ``predict``, ``predict_proba``, ``classes_`` and
        ``n_features_in_``, predicting exactly as the model
        :func:`~tentaclass.io.load_model` reads; ``None`` when the file holds
        something else than a TentacleClassifier or a Pipeline of the
        estimators covered here.
    info : dict
        What :func:`~tentaclass.io.model_info` returns.

    Raises
    ------
    tentaclass.errors.ModelFileError
        The file is not a model file, or is damaged (as :func:`~tentaclass.io.load_model`).

    Examples
    --------
    >>> import numpy as np
    >>> from importlib.resources import files
    >>> model, info = load_light(files("tentaclass.data") / "default-16.tcm")
    >>> model.predict(np.tile([0, 0, 0, np.pi / 2], 4)[None]).tolist()
    ['square']
    """
    model, info = _read_light(path)
    tree_root = info.get("estimator")
    if tree_root not in _ROOTS:
        return None, info
    if isinstance(model, _Pipeline) and not model._predicts():
        return None, info
    return model, info


def _read_light(path: str | os.PathLike) -> tuple[Any | None, dict]:
    """The light objects of any tree the light reader covers (or ``None``), and the info."""
    meta, arrays, path = _open(path)
    info = info_from_metadata(meta, path)
    tree = meta.get("estimator")
    if meta["format_version"] != 2 or not isinstance(tree, dict) or "__estimator__" not in tree:
        return None, info
    reader = _LightReader(arrays)
    try:
        model = reader.value(tree, "estimator")
    except (_NotLight, ModelFileError, AttributeError, TypeError, ValueError, IndexError):
        return None, info  # load_model then reads it or names what is wrong
    return (model if reader.used == set(arrays) else None), info
