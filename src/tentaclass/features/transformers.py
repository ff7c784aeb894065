"""Descriptors as scikit-learn transformers, ready for pipelines.

This is where the library's leading-axes arrays meet scikit-learn's
``(n_samples, n_features)`` tables: a transformer sees one joint-angle array
per row.
"""

from __future__ import annotations

import numpy as np
from sklearn.base import BaseEstimator, TransformerMixin
from sklearn.utils.validation import check_is_fitted, validate_data

from .._typing import ArrayLike, FloatArray
from ..errors import InputError
from .fourier import fourier_features

__all__ = ["FourierFeatures"]


class FourierFeatures(TransformerMixin, BaseEstimator):
    """Joint angles -> ``|DFT|`` of the periodic turning signal, as a transformer.

    Parameters
    ----------
    n_coeffs : int, optional
        Frequencies ``1..n_coeffs`` to keep; default ``floor(n_joints / 2)``.
    detrend : bool, default=False
        Ramp through the measured total turn instead of ``2*pi`` (robust to
        joint noise); see :func:`tentaclass.features.periodic_signal`.
    normalize : bool, default=False
        Divide the features by ``n_joints``.

    Attributes
    ----------
    n_features_in_ : int
        Number of joint angles per row seen in ``fit``.
    n_coeffs_ : int
        Number of output features.

    Examples
    --------
    >>> import numpy as np
    >>> from tentaclass.datasets import thesis_tentacle
    >>> X, y = thesis_tentacle(16, return_X_y=True)
    >>> FourierFeatures(n_coeffs=4).fit_transform(X).shape
    (4, 4)
    """

    def __init__(self, n_coeffs: int | None = None, detrend: bool = False, normalize: bool = False):
        self.n_coeffs = n_coeffs
        self.detrend = detrend
        self.normalize = normalize

    def fit(self, X: ArrayLike, y: ArrayLike | None = None) -> FourierFeatures:
        """Check ``X`` and fix the number of joints and coefficients.

        Parameters
        ----------
        X : array_like of shape (n_samples, n_joints)
            Joint angles, one array per row.
        y : ignored

        Returns
        -------
        self : FourierFeatures
        """
        X = validate_data(self, X, dtype=np.float64)
        n = X.shape[1]
        if n < 3:
            raise InputError(f"X must hold at least 3 joint angles per row, got {n}")
        k = n // 2 if self.n_coeffs is None else self.n_coeffs
        if not 1 <= k <= n // 2:
            raise InputError(
                f"n_coeffs must be between 1 and floor(n_joints / 2) = {n // 2}, "
                f"got {self.n_coeffs}"
            )
        self.n_coeffs_ = int(k)
        return self

    def transform(self, X: ArrayLike) -> FloatArray:
        """Fourier features of each row.

        Parameters
        ----------
        X : array_like of shape (n_samples, n_joints)

        Returns
        -------
        features : ndarray of shape (n_samples, n_coeffs_)
        """
        check_is_fitted(self)
        X = validate_data(self, X, dtype=np.float64, reset=False)
        return fourier_features(X, self.n_coeffs_, detrend=self.detrend, normalize=self.normalize)

    def get_feature_names_out(self, input_features: ArrayLike | None = None) -> np.ndarray:
        """Names ``fourier1 .. fourierK`` of the output columns."""
        check_is_fitted(self)
        return np.array([f"fourier{k}" for k in range(1, self.n_coeffs_ + 1)], dtype=object)
