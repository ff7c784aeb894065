"""Shared base of the probabilistic classifiers: scikit-learn's estimator API.

The predictions themselves (``predict``, ``predict_proba`` and
``predict_log_proba`` from ``_joint_log_likelihood``) are in
:mod:`tentaclass.classifiers._prob_core`, free of scikit-learn.
"""

from __future__ import annotations

import numpy as np
from sklearn.base import BaseEstimator, ClassifierMixin
from sklearn.utils.validation import check_is_fitted

from .._dask import DaskMixin
from .._typing import ArrayLike, FloatArray
from .._validation import check_X
from ._prob_core import ProbabilisticCore, _logsumexp_rows

__all__ = ["BaseProbabilisticClassifier", "_logsumexp_rows"]


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
