"""Shared base of the probabilistic classifiers: scikit-learn's estimator API.

The predictions themselves (``predict``, ``predict_proba`` and
``predict_log_proba`` from ``_joint_log_likelihood``) are in
:mod:`tentaclass.classifiers._prob_core`, free of scikit-learn.
"""

from __future__ import annotations

import numpy as np
from sklearn.base import BaseEstimator, ClassifierMixin
from sklearn.utils.multiclass import check_classification_targets
from sklearn.utils.validation import check_is_fitted

from .._dask import DaskMixin
from .._typing import ArrayLike, FloatArray
from .._validation import check_X
from ..errors import InputError
from ._prob_core import ProbabilisticCore, _logsumexp_rows

__all__ = ["BaseProbabilisticClassifier", "_logsumexp_rows", "class_indices"]


def class_indices(y: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Sorted class labels of ``y`` and the index of each sample's class.

    Raises :class:`~tentaclass.errors.InputError` unless ``y`` holds
    classification targets of at least two classes.
    """
    check_classification_targets(y)
    classes, y_idx = np.unique(y, return_inverse=True)
    if classes.size < 2:
        raise InputError(f"y must hold at least 2 classes, got one class: {classes.tolist()}")
    return classes, y_idx


class BaseProbabilisticClassifier(ProbabilisticCore, DaskMixin, ClassifierMixin, BaseEstimator):
    """Base class: predictions from per-class log scores."""

    def _check_X(self, X: ArrayLike) -> FloatArray:
        if (
            type(X) is np.ndarray
            and X.dtype == np.float64
            and X.ndim == 2
            and X.shape[0] > 0
            and X.shape[1] == getattr(self, "n_features_in_", -1)
            and not hasattr(self, "feature_names_in_")
            and np.isfinite(X).all()
        ):
            return X  # what the full check (below) returns for it, without its overhead
        check_is_fitted(self)
        return check_X(self, X, dtype=np.float64, reset=False)
