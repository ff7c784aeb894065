"""Descriptors as scikit-learn transformers, ready for pipelines.

This is where the library's leading-axes arrays meet scikit-learn's
``(n_samples, n_features)`` tables: a transformer sees one joint-angle array
per row.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from sklearn.base import BaseEstimator, TransformerMixin
from sklearn.utils.validation import check_is_fitted

from .._dask import DaskMixin
from .._deprecation import DEPRECATED, renamed_attribute, renamed_param
from .._typing import ArrayLike, FloatArray
from .._validation import (
    MAX_LINKS,
    check_finite_float,
    check_fitted_X,
    check_flag,
    check_frequency_count,
    check_positive_int,
    check_X,
)
from ..errors import InputError
from ._transform_core import AngleSpectrumCore, FourierFeaturesCore, LastLapCore

__all__ = ["AngleSpectrum", "FourierFeatures", "LastLap"]


def _check_joint_angles(estimator: BaseEstimator, X: ArrayLike) -> FloatArray:
    """``X`` checked for ``fit``: rows of at least 2 joint angles (a closed chain)."""
    X = check_X(estimator, X, dtype=np.float64)
    if X.shape[1] < 2:
        raise InputError(
            f"X must hold at least 2 joint angles per row, got {X.shape[1]} feature(s) "
            f"(shape {X.shape})"
        )
    return X


class _AngleTransformer(DaskMixin, TransformerMixin, BaseEstimator):
    """A transformer of joint-angle rows: ``transform`` checks them, ``_transform`` computes."""

    def _transform(self, X: FloatArray) -> FloatArray:
        raise NotImplementedError

    def transform(self, X: ArrayLike) -> FloatArray:
        """The output of each row (described in the class docstring).

        Parameters
        ----------
        X : array_like of shape (n_samples, n_joints)

        Returns
        -------
        out : ndarray of shape (n_samples, n_out)
        """
        return self._transform(check_fitted_X(self, X))


class _NumberedHarmonics:
    """``n_harmonics_`` output columns, named by a prefix and the frequency they hold."""

    #: Name of column ``k`` is ``f"{_prefix}{k + _first}"``.
    _prefix: str
    _first: int
    n_harmonics_: int

    n_coeffs_ = renamed_attribute("n_harmonics_", "n_coeffs_")

    def get_feature_names_out(self, input_features: ArrayLike | None = None) -> np.ndarray:
        """Names of the output columns: prefix and frequency (``fourier1``, ``spectrum0``)."""
        check_is_fitted(self)
        frequencies = range(self._first, self._first + self.n_harmonics_)
        return np.array([f"{self._prefix}{k}" for k in frequencies], dtype=object)


class FourierFeatures(FourierFeaturesCore, _NumberedHarmonics, _AngleTransformer):
    """Joint angles -> ``|DFT|`` of the periodic turning signal, as a transformer.

    Parameters
    ----------
    n_harmonics : int or float, optional
        Frequencies ``1..n_harmonics`` to keep; default ``floor(n_joints / 2)``. A
        float in (0, 1) keeps that fraction of them (at least one), so one
        setting serves chains of any length: on MPEG-7 wraps of 64 links, the
        lowest half (``0.5``) classified 2-3 points better than all of them,
        because chord sampling aliases fine detail into the high frequencies.
    detrend : bool, default=False
        Ramp through the measured total turn instead of ``2*pi`` (robust to
        joint noise); see :func:`tentaclass.features.periodic_signal`.
    normalize : bool, default=False
        Divide the features by ``n_joints``.
    weight_power : float, default=0.0
        Multiply coefficient ``k`` by ``k ** weight_power``. Joint-angle noise
        accumulates along the chain, so its share of coefficient ``k`` falls
        like ``1 / k``; a power of 0.5 balances distances between noise-heavy
        low and shape-carrying high frequencies (measured on MPEG-7 wraps with
        0.05 rad noise: see BENCHMARKS.md).
    n_coeffs : int or float, optional
        Deprecated alias of ``n_harmonics``.

    Attributes
    ----------
    n_features_in_ : int
        Number of joint angles per row seen in ``fit``.
    n_harmonics_ : int
        Number of output features (``n_coeffs_`` is its deprecated alias).

    Examples
    --------
    >>> import numpy as np
    >>> from tentaclass.datasets import thesis_tentacle
    >>> X, y = thesis_tentacle(16, return_X_y=True)
    >>> FourierFeatures(n_harmonics=4).fit_transform(X).shape
    (4, 4)
    """

    _prefix, _first = "fourier", 1

    def __init__(
        self,
        n_harmonics: int | float | None = None,
        detrend: bool = False,
        normalize: bool = False,
        weight_power: float = 0.0,
        n_coeffs: Any = DEPRECATED,
    ):
        self.n_harmonics = n_harmonics
        self.detrend = detrend
        self.normalize = normalize
        self.weight_power = weight_power
        self.n_coeffs = n_coeffs

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
        X = _check_joint_angles(self, X)
        n = X.shape[1]
        k = renamed_param(self, "n_harmonics", "n_coeffs")
        k = n // 2 if k is None else k
        self.n_harmonics_ = check_frequency_count(k, n // 2, "n_harmonics", "floor(n_joints / 2)")
        check_flag(self.detrend, "detrend")
        check_flag(self.normalize, "normalize")
        power = check_finite_float(self.weight_power, "weight_power")
        if abs(power) * np.log(self.n_harmonics_) > np.log(np.finfo(float).max):
            raise InputError(
                f"weight_power {power:g} is out of range: {self.n_harmonics_} ** {abs(power):g} is "
                "beyond float64 (weights of 0 to 2 are the useful range)"
            )
        return self


class LastLap(LastLapCore, _AngleTransformer):
    """Joint angles of any wrap -> its last full lap as a closed array.

    A transformer around :func:`tentaclass.features.last_lap`: removes the
    approach links of a chain standing off the object and the extra laps of a
    chain wrapped more than once, and resamples the lap to ``n_out`` equal
    links. Put it before :class:`FourierFeatures` when wraps are not exact
    single laps.

    Parameters
    ----------
    n_out : int, optional
        Links of the output lap; default the input's number of joints.

    Examples
    --------
    >>> import numpy as np
    >>> square = np.tile([0, 0, 0, np.pi / 2], 4)
    >>> twice = np.concatenate([square, square[:9]])[None]
    >>> LastLap(n_out=16).fit_transform(twice).sum().round(6)
    np.float64(6.283185)
    """

    def __init__(self, n_out: int | None = None):
        self.n_out = n_out

    def fit(self, X: ArrayLike, y: ArrayLike | None = None) -> LastLap:
        """Check ``X`` and fix the output length.

        Parameters
        ----------
        X : array_like of shape (n_samples, n_joints)
        y : ignored

        Returns
        -------
        self : LastLap
        """
        X = _check_joint_angles(self, X)
        n = X.shape[1]
        self.n_out_ = (
            n
            if self.n_out is None
            else check_positive_int(self.n_out, "n_out", minimum=2, maximum=max(n, MAX_LINKS))
        )
        return self


class AngleSpectrum(AngleSpectrumCore, _NumberedHarmonics, _AngleTransformer):
    """Joint angles -> ``|DFT|`` of the angle array itself, as a transformer.

    Where :class:`FourierFeatures` describes one closed lap, this describes the
    whole wrap as measured, approach links and extra laps included: coefficient
    0 is the mean joint angle (the total turn over the number of joints, so it
    counts the laps), the others how the turning is distributed along the
    chain. A chain that wraps 1.6 laps sees part of the object twice, from
    other joint positions; the last lap alone cannot tell a square from a
    circle when its joints cut the corners, the whole array often can. Use it
    next to :class:`LastLap` + :class:`FourierFeatures` in a feature union.

    Parameters
    ----------
    n_harmonics : int, optional
        Frequencies ``0 .. n_harmonics - 1`` to keep; default all
        ``floor(n_joints / 2) + 1`` of them.
    n_coeffs : int, optional
        Deprecated alias of ``n_harmonics``.

    Attributes
    ----------
    n_features_in_ : int
    n_harmonics_ : int
        Number of output features (``n_coeffs_`` is its deprecated alias).

    Examples
    --------
    >>> import numpy as np
    >>> square = np.tile([0, 0, 0, np.pi / 2], 4)[None]
    >>> AngleSpectrum(n_harmonics=5).fit_transform(square).round(4)
    array([[0.3927, 0.    , 0.    , 0.    , 0.3927]])
    """

    _prefix, _first = "spectrum", 0

    def __init__(self, n_harmonics: int | None = None, n_coeffs: Any = DEPRECATED):
        self.n_harmonics = n_harmonics
        self.n_coeffs = n_coeffs

    def fit(self, X: ArrayLike, y: ArrayLike | None = None) -> AngleSpectrum:
        """Check ``X`` and the number of coefficients.

        Parameters
        ----------
        X : array_like of shape (n_samples, n_joints)
        y : ignored

        Returns
        -------
        self : AngleSpectrum
        """
        X = check_X(self, X, dtype=np.float64)
        top = X.shape[1] // 2 + 1
        given = renamed_param(self, "n_harmonics", "n_coeffs")
        k = top if given is None else check_positive_int(given, "n_harmonics")
        if k > top:
            raise InputError(
                f"n_harmonics must be at most floor(n_joints / 2) + 1 = {top}, got {given}"
            )
        self.n_harmonics_ = int(k)
        return self
