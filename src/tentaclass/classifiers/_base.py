"""Shared base of the probabilistic classifiers: scikit-learn's estimator API.

The predictions themselves (``predict``, ``predict_proba`` and
``predict_log_proba`` from ``_joint_log_likelihood``) are in
:mod:`tentaclass.classifiers._prob_core`, free of scikit-learn.
"""

from __future__ import annotations

from typing import Self

import numpy as np
from sklearn.base import BaseEstimator, ClassifierMixin

from .._dask import DaskMixin
from .._typing import ArrayLike, FloatArray
from .._validation import check_fitted_X, check_X_y, class_indices
from ._prob_core import ProbabilisticCore, _logsumexp_rows

__all__ = ["BaseProbabilisticClassifier", "_logsumexp_rows", "class_indices"]


class BaseProbabilisticClassifier(ProbabilisticCore, DaskMixin, ClassifierMixin, BaseEstimator):
    """Base class: predictions from per-class log scores.

    A subclass that keeps this ``fit`` writes ``_validate_params`` (checks the
    parameters before the data are looked at) and ``_fit`` (learns from the
    checked training set).
    """

    def _fit(self, X: FloatArray, classes: np.ndarray, y_idx: np.ndarray) -> None:
        """Learn from float64 rows ``X``, the sorted ``classes`` and each row's class index."""
        raise NotImplementedError

    def fit(self, X: ArrayLike, y: ArrayLike) -> Self:
        """Check the parameters and the training set, and learn from it.

        Parameters
        ----------
        X : array_like of shape (n_samples, n_features)
        y : array_like of shape (n_samples,)
            Class labels of any type, at least two classes.

        Returns
        -------
        self : estimator
            The fitted classifier.
        """
        self._validate_params()
        X, y = check_X_y(self, X, y, dtype=np.float64)
        classes, y_idx = class_indices(y)
        self._fit(X, classes, y_idx)
        return self

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
        return check_fitted_X(self, X)
