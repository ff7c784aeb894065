"""Deployed tentacle models: the chain a model was trained for, rejection, bundled models.

A model trained for a robot's chain stores that chain in its file's ``info``
(``{"chain": {"n_links": ..., "link_length": ..., ...}}``) and, when it can
reject objects of unknown classes, a threshold ``reject_below`` on its best
class score. The package ships such models for the thesis's four classes
(``tentaclass/data/default-<n_links>.tcm``, built by
``benchmarks/build_default_models.py``).
"""

from __future__ import annotations

import inspect
import re
from functools import lru_cache
from importlib.resources import as_file, files
from typing import Any

import numpy as np

from .._typing import ArrayLike, FloatArray
from .._validation import (
    MAX_LINKS,
    as_angle_array,
    check_fitted_X,
    check_fraction,
    check_positive_int,
)
from ..errors import InputError, ModelFileError
from ._model_file import load_model, model_info

__all__ = [
    "best_class_score",
    "bundled_links",
    "bundled_model",
    "check_chain_length",
    "rejection_threshold",
]

_BUNDLED = re.compile(r"^default-(\d+)\.tcm$")


def bundled_links() -> tuple[int, ...]:
    """Chain lengths (numbers of links) the package ships a default model for.

    Examples
    --------
    >>> 16 in bundled_links()
    True
    """
    names = [p.name for p in files("tentaclass.data").iterdir()]
    return tuple(sorted(int(m[1]) for n in names if (m := _BUNDLED.match(n))))


@lru_cache(maxsize=8)
def _load_bundled(n_links: int) -> tuple[Any, dict]:
    with as_file(files("tentaclass.data") / f"default-{n_links}.tcm") as path:
        return load_model(path), model_info(path)


@lru_cache(maxsize=8)
def bundled_predictor(n_links: int) -> tuple[Any, dict]:
    """:func:`bundled_model` for prediction only, read without scikit-learn when it can be.

    The model :func:`~tentaclass.io._light.load_light` reads (predicting
    exactly as the bundled model), else the bundled model itself.
    """
    from ._light import load_light

    if n_links not in bundled_links():
        return bundled_model(n_links)  # the error naming the bundled chains
    with as_file(files("tentaclass.data") / f"default-{n_links}.tcm") as path:
        light, info = load_light(path)
    return (light, info) if light is not None else bundled_model(n_links)


def bundled_model(n_links: int) -> tuple[Any, dict]:
    """The shipped model of the four thesis classes for a chain of ``n_links`` links.

    Trained on generated wraps of squares, circles, equilateral triangles and
    rectangles (aspect 2-4) by one chain: 0.45-3.2 laps, a stand-off of 0-3.5
    links, joint noise up to 0.025 rad, both directions, taut and hug
    (``benchmarks/build_default_models.py``).

    Parameters
    ----------
    n_links : int

    Returns
    -------
    model : estimator
        Fitted; shared between calls (do not refit it).
    info : dict
        What :func:`model_info` reads: ``info["chain"]``, ``info["reject_below"]``.

    Raises
    ------
    tentaclass.errors.InputError
        No model is shipped for that chain length; the message lists those that are.

    Examples
    --------
    >>> import numpy as np
    >>> model, info = bundled_model(16)
    >>> model.predict(np.tile([0, 0, 0, np.pi / 2], 4)[None]).tolist()
    ['square']
    >>> info["chain"]["n_links"]
    16
    """
    links = bundled_links()
    if n_links not in links:
        raise InputError(
            f"no bundled model for a chain of {n_links} links: bundled models cover "
            f"{', '.join(map(str, links))} links (train one for {n_links} links with "
            f"'tentaclass train --outlines ... --links {n_links}')"
        )
    return _load_bundled(int(n_links))


def check_chain_length(
    X: ArrayLike, info: dict, n_features_in: int | None, name: str = "model"
) -> None:
    """Refuse arrays whose length is not the chain ``info`` (or the model) was trained for.

    Parameters
    ----------
    X : array_like of shape (n_samples, n_joints)
    info : dict
        From :func:`model_info`; its ``"chain"`` entry is used when present.
    n_features_in : int or None
        The model's ``n_features_in_``, used when ``info`` names no chain;
        None for a model that takes arrays of any length.
    name : str
        How to call the model in the message (e.g. its file name).

    Raises
    ------
    tentaclass.errors.InputError
        Naming both lengths.
    tentaclass.errors.ModelFileError
        ``info`` names a chain length that is not a count of links, or not
        the length the model takes (a file edited by hand).

    Examples
    --------
    >>> check_chain_length(np.zeros((1, 20)), {"chain": {"n_links": 16}}, 16, "m")
    Traceback (most recent call last):
    ...
    tentaclass.errors.InputError: m was trained for a chain of 16 links; these arrays have 20...
    >>> check_chain_length(np.zeros((1, 16)), {"chain": {"n_links": 24}}, 16, "m")
    Traceback (most recent call last):
    ...
    tentaclass.errors.ModelFileError: m: info says a chain of 24 links, but the model takes \
arrays of 16 angles: the file was edited or damaged
    """
    X = as_angle_array(X, "angle arrays")
    chain = info.get("chain") if isinstance(info, dict) else None
    n = chain.get("n_links") if isinstance(chain, dict) else None
    if n is not None:
        try:
            n = check_positive_int(n, "n_links", maximum=MAX_LINKS)
        except InputError as exc:
            raise ModelFileError(f"{name}: info chain {exc}") from None
        if n_features_in is not None and n != n_features_in:
            raise ModelFileError(
                f"{name}: info says a chain of {n} links, but the model takes arrays of "
                f"{n_features_in} angles: the file was edited or damaged"
            )
    n = n_features_in if n is None else n
    if n is not None and X.shape[-1] != n:
        raise InputError(
            f"{name} was trained for a chain of {n} links; these arrays have "
            f"{X.shape[-1]} joint angles (classify arrays of {n} angles, or train a model "
            f"for {X.shape[-1]} links with 'tentaclass train --links {X.shape[-1]}')"
        )


def _final_scorer(model: Any) -> tuple[list, Any]:
    """The transform steps before the final classifier, and that classifier."""
    inner = getattr(model, "pipeline_", model)
    steps = getattr(inner, "steps", None)  # a Pipeline, or the light reader's
    if isinstance(steps, list) and steps:
        return [step for _, step in steps[:-1]], steps[-1][1]
    return [], inner


def predict_with_proba(model: Any, X: ArrayLike) -> tuple[np.ndarray, FloatArray]:
    """``model.predict(X)`` and ``model.predict_proba(X)``, the class scores computed once.

    The labels are those ``predict`` gives, rejection included (``unknown``
    where the model rejects), and the probabilities those of
    ``predict_proba``, to the last bit: the arrays pass through a pipeline's
    transforms once, and the classifier's scores are evaluated once for both
    when it is a :class:`~tentaclass.classifiers.TentacleClassifier` or a
    classifier of per-class log scores (a PNN, an RBF network); any other
    final classifier is asked for both in turn.

    Parameters
    ----------
    model : fitted classifier
        An estimator, a ``Pipeline`` or a :class:`~tentaclass.classifiers.FourierClassifier`,
        or what :func:`~tentaclass.io._light.load_light` reads.
    X : array_like of shape (n_samples, n_joints)
        In memory (not a dask array).

    Returns
    -------
    labels : ndarray of shape (n_samples,)
    proba : ndarray of shape (n_samples, n_classes)
        Columns in the order of ``model.classes_``.

    Examples
    --------
    >>> from tentaclass.classifiers import FourierClassifier
    >>> from tentaclass.datasets import thesis_tentacle
    >>> X, y = thesis_tentacle(16, return_X_y=True)
    >>> model = FourierClassifier(spread=0.5).fit(X, y)
    >>> labels, proba = predict_with_proba(model, X)
    >>> labels.tolist() == model.predict(X).tolist(), bool((proba == model.predict_proba(X)).all())
    (True, True)
    """
    labels, proba, _ = _predict_once(model, X)
    return labels, proba


def _predict_once(model: Any, X: ArrayLike) -> tuple[np.ndarray, FloatArray, FloatArray | None]:
    """:func:`predict_with_proba`, and :func:`best_class_score` where it comes for free.

    The third value is ``best_class_score(model, X)`` when the final
    classifier is a PNN (its class scores are the exponentials of the log
    scores just computed), else ``None``.
    """
    from ..classifiers import PNNCore, TentacleCore
    from ..classifiers._prob_core import ProbabilisticCore

    steps, final = _final_scorer(model)
    if steps and hasattr(model, "pipeline_"):  # a FourierClassifier checks X first
        X = check_fitted_X(model, X)
    for step in steps:
        if step is not None and not (isinstance(step, str) and step == "passthrough"):
            X = step.transform(X)
    if isinstance(final, TentacleCore) and hasattr(final, "_scores"):
        s, closed, _, novelty = final._scores(X)
        return final._labels_of(s, novelty), final._proba_of(s, closed), None
    if isinstance(final, ProbabilisticCore) and all(
        inspect.unwrap(getattr(type(final), name)) is getattr(ProbabilisticCore, name)
        for name in ("predict", "predict_proba", "predict_log_proba")
    ):
        labels, proba, jll = final._predict_with_proba(X)
        own = isinstance(final, PNNCore) and type(final).class_scores is PNNCore.class_scores
        if own and not hasattr(model, "novelty_scores"):  # what best_class_score asks for
            return labels, proba, np.max(np.exp(jll), axis=1)
        return labels, proba, None
    return final.predict(X), final.predict_proba(X), None


def best_class_score(model: Any, X: ArrayLike) -> FloatArray:
    """How well each array fits its best class: the model's largest class score.

    For a PNN (alone, at the end of a pipeline or inside a
    :class:`~tentaclass.classifiers.TentacleClassifier`) this is the mean
    kernel value of the closest class, in [0, 1]: near 0 for an object unlike
    every training class. A model with its own ``novelty_scores`` method is
    asked directly.

    Parameters
    ----------
    model : fitted estimator
    X : array_like of shape (n_samples, n_joints)

    Returns
    -------
    scores : ndarray of shape (n_samples,)

    Raises
    ------
    tentaclass.errors.InputError
        The model has no class scores (its classifier is not a PNN).

    Examples
    --------
    >>> from sklearn.pipeline import make_pipeline
    >>> from tentaclass.classifiers import PNNClassifier
    >>> from tentaclass.datasets import thesis_tentacle
    >>> from tentaclass.features import FourierFeatures
    >>> X, y = thesis_tentacle(16, return_X_y=True)
    >>> model = make_pipeline(FourierFeatures(), PNNClassifier(spread=0.5)).fit(X, y)
    >>> best_class_score(model, X).round(3).tolist()  # each array is a training pattern
    [1.0, 1.0, 1.0, 1.0]
    """
    if hasattr(model, "novelty_scores"):
        return np.asarray(model.novelty_scores(X), dtype=float)
    steps, final = _final_scorer(model)
    if not hasattr(final, "class_scores"):
        raise InputError(
            f"the model's classifier ({type(final).__name__}) gives no class scores to reject "
            "unknown objects with; rejection needs a PNN classifier"
        )
    Xt = as_angle_array(X, "angle arrays")
    for step in steps:
        Xt = step.transform(Xt)
    return np.max(final.class_scores(Xt), axis=1)


def info_reject_below(info: dict, name: str = "model") -> float | None:
    """The rejection threshold ``info["reject_below"]`` of a model file, or None without one.

    Raises
    ------
    tentaclass.errors.ModelFileError
        A threshold that is not a number in [0, 1] (a file edited by hand:
        ``true`` rejected every array, ``-5`` none).

    Examples
    --------
    >>> info_reject_below({"reject_below": 0.02}), info_reject_below({})
    (0.02, None)
    """
    value = info.get("reject_below") if isinstance(info, dict) else None
    if value is None:
        return None
    try:
        return check_fraction(value, "reject_below")
    except InputError as exc:
        raise ModelFileError(f"{name}: info {exc}") from None


def rejection_threshold(model: Any, X_known: ArrayLike, false_rejections: float = 0.01) -> float:
    """A ``reject_below`` that rejects about ``false_rejections`` of known-class arrays.

    ``X_known`` should be arrays the model was not trained on (a held-out set
    of the known classes).
    """
    if not 0 <= false_rejections < 1:
        raise InputError(f"false_rejections must be in [0, 1), got {false_rejections!r}")
    scores = best_class_score(model, X_known)
    return float(np.quantile(scores, false_rejections))
