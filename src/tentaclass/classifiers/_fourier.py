"""The thesis pipeline: joint angles -> Fourier features -> classifier."""

from __future__ import annotations

from typing import Any

import numpy as np
from sklearn.base import BaseEstimator, ClassifierMixin, TransformerMixin, clone
from sklearn.pipeline import Pipeline

from .._dask import DaskMixin
from .._deprecation import DEPRECATED, renamed_param
from .._typing import ArrayLike, FloatArray
from .._validation import check_fitted_X, check_X_y
from ..features import FourierFeatures
from ._pnn import PNNClassifier

__all__ = ["FourierClassifier"]


class FourierClassifier(DaskMixin, ClassifierMixin, TransformerMixin, BaseEstimator):
    """Object class from one-lap joint angles: the thesis's pipeline.

    For wraps by a real chain (any laps, an approach, noise) use
    :class:`TentacleClassifier`; this pipeline expects one closed lap. It is
    a pipeline of :class:`~tentaclass.features.FourierFeatures` (``|DFT|`` of the
    periodic turning signal: invariant to the object's position, rotation, size,
    the wrap's start point and its direction) and a classifier, by default a
    :class:`PNNClassifier`.

    Parameters
    ----------
    n_harmonics : int or float, optional
        Fourier coefficients kept; default ``floor(n_joints / 2)``; a float in
        (0, 1) keeps that fraction of them.
    detrend : bool, default=False
        Ramp through the measured total turn (robust to joint noise).
    normalize : bool, default=False
        Divide features by ``n_joints``.
    weight_power : float, default=0.0
        Weight coefficient ``k`` by ``k ** weight_power`` (0.5 helps with joint
        noise; see :class:`~tentaclass.features.FourierFeatures`).
    spread : float or "auto", default=0.1
        Kernel width of the default PNN (ignored when ``classifier`` is given);
        ``"auto"`` chooses it on the training features (see
        :class:`PNNClassifier`).
    reject_below : float, optional
        Rejection threshold of the default PNN (see :class:`PNNClassifier`).
    classifier : estimator, optional
        Any scikit-learn classifier to use instead of the PNN; it is cloned.
    n_coeffs : int or float, optional
        Deprecated alias of ``n_harmonics``.

    Attributes
    ----------
    pipeline_ : sklearn.pipeline.Pipeline
        The fitted feature + classifier pipeline.
    classes_ : ndarray of shape (n_classes,)
    n_features_in_ : int
        Joint angles per array seen in ``fit``.

    Examples
    --------
    >>> import numpy as np
    >>> from tentaclass.datasets import thesis_tentacle
    >>> X, y = thesis_tentacle(16, return_X_y=True)
    >>> clf = FourierClassifier().fit(X, y)
    >>> clf.predict(np.roll(X, 3, axis=1)).tolist()  # another start point
    ['square', 'circle', 'triangle', 'rectangle']
    """

    def __init__(
        self,
        n_harmonics: int | float | None = None,
        detrend: bool = False,
        normalize: bool = False,
        weight_power: float = 0.0,
        spread: float | str = 0.1,
        reject_below: float | None = None,
        classifier: BaseEstimator | None = None,
        n_coeffs: Any = DEPRECATED,
    ):
        self.n_harmonics = n_harmonics
        self.detrend = detrend
        self.normalize = normalize
        self.weight_power = weight_power
        self.spread = spread
        self.reject_below = reject_below
        self.classifier = classifier
        self.n_coeffs = n_coeffs

    def fit(self, X: ArrayLike, y: ArrayLike) -> FourierClassifier:
        """Fit features and classifier on joint-angle arrays.

        Parameters
        ----------
        X : array_like of shape (n_samples, n_joints)
            Joint angles, one array per row.
        y : array_like of shape (n_samples,)

        Returns
        -------
        self : FourierClassifier
        """
        X, y = check_X_y(self, X, y, dtype=np.float64)
        if self.classifier is None:
            clf = PNNClassifier(spread=self.spread, reject_below=self.reject_below)
        else:
            clf = clone(self.classifier)
        features = FourierFeatures(
            renamed_param(self, "n_harmonics", "n_coeffs"),
            detrend=self.detrend,
            normalize=self.normalize,
            weight_power=self.weight_power,
        )
        self.pipeline_ = Pipeline([("features", features), ("classifier", clf)]).fit(X, y)
        self.classes_ = self.pipeline_.classes_
        return self

    def transform(self, X: ArrayLike) -> FloatArray:
        """Feature vectors of joint-angle arrays, shape (n_samples, n_harmonics)."""
        X = check_fitted_X(self, X)
        return self.pipeline_.named_steps["features"].transform(X)

    def predict(self, X: ArrayLike) -> np.ndarray:
        """Class of each joint-angle array, shape (n_samples,)."""
        X = check_fitted_X(self, X)
        return self.pipeline_.predict(X)

    def predict_proba(self, X: ArrayLike) -> FloatArray:
        """Class probabilities, shape (n_samples, n_classes); rows sum to 1."""
        X = check_fitted_X(self, X)
        return self.pipeline_.predict_proba(X)
