"""Predictions from per-class log scores, free of scikit-learn.

As in scikit-learn's ``_BaseNB``: a subclass writes one method,
``_joint_log_likelihood(X)``, returning the unnormalised log score of every
class, and inherits ``predict``, ``predict_proba`` and ``predict_log_proba``,
normalised with log-sum-exp so that scores far below the float range (all
kernel values underflowing to zero) still give valid probabilities.

The estimators inherit this through
:class:`~tentaclass.classifiers._base.BaseProbabilisticClassifier`; a model
file is evaluated with it without importing scikit-learn
(:mod:`tentaclass.io._light`).
"""

from __future__ import annotations

import numpy as np

from .._typing import ArrayLike, FloatArray


def _logsumexp_rows(a: FloatArray) -> FloatArray:
    """``scipy.special.logsumexp(a, axis=1, keepdims=True)`` of a real 2-D array.

    The same arithmetic, step by step (the maxima of a row are taken out of
    the sum and counted, the rest summed after the shift), so the results are
    the same to the last bit, without scipy's array-API dispatch, which costs
    more than the sum for the small batches of a streaming caller.
    """
    if a.dtype != np.float64 or a.ndim != 2 or a.size == 0:
        from scipy.special import logsumexp

        return np.asarray(logsumexp(a, axis=1, keepdims=True))
    if np.isfinite(a).all():
        # the same steps less those that only matter for infinite or NaN scores
        # (every row then has a maximum counted at least once, a sum >= 0)
        a_max = np.max(a, axis=1, keepdims=True)
        top = a == a_max
        m = np.sum(top.astype(np.float64), axis=1, keepdims=True, dtype=np.float64)
        with np.errstate(over="ignore"):
            s = np.sum(np.exp(np.where(top, -np.inf, a) - a_max), axis=1, keepdims=True)
            out = np.log1p(s / m) + np.log(m) + a_max
        if np.isfinite(out).all():
            return out
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        out_inf = np.log(np.sum(np.exp(a), axis=1, keepdims=True))
        a_max = np.max(a, axis=1, keepdims=True)
        top = a == a_max
        m = np.sum(top.astype(np.float64), axis=1, keepdims=True, dtype=np.float64)
        s = np.sum(np.exp(np.where(top, -np.inf, a) - a_max), axis=1, keepdims=True)
        s = np.where(s == 0, s, s / m)
        negative = np.sign(s + 1) * np.sign(m) < 0
        s = np.where(s < -1, -s - 2, s)
        out = np.log1p(s) + np.log(np.abs(m)) + a_max
    out[negative] = np.nan
    return np.where(np.isfinite(out), out, out_inf)


def _normalised(jll: FloatArray) -> FloatArray:
    """Log probabilities ``jll - logsumexp(jll)`` of each row.

    Rows of scores so large in magnitude that subtracting their log-sum-exp
    would round the differences between classes away (far below the float
    range's usual values: a sample far from every training pattern) are
    normalised after taking out their maximum, which keeps those differences.
    """
    out = jll - _logsumexp_rows(jll)
    big = np.abs(jll.max(axis=1)) > 2.0**40 if jll.size else np.zeros(0, bool)
    if big.any():
        d = jll[big] - jll[big].max(axis=1, keepdims=True)
        out[big] = d - np.log(np.exp(d).sum(axis=1, keepdims=True))
    return out


class ProbabilisticCore:
    """Predictions from ``_joint_log_likelihood``; ``_check_X`` validates the input."""

    classes_: np.ndarray

    def _joint_log_likelihood(self, X: FloatArray) -> FloatArray:
        """Unnormalised log score of each class, shape (n_samples, n_classes)."""
        raise NotImplementedError

    def _check_X(self, X: ArrayLike) -> FloatArray:
        raise NotImplementedError

    def predict_log_proba(self, X: ArrayLike) -> FloatArray:
        """Log of the class probabilities.

        Parameters
        ----------
        X : array_like of shape (n_samples, n_features)

        Returns
        -------
        log_proba : ndarray of shape (n_samples, n_classes)
            Columns in the order of ``classes_``.
        """
        return _normalised(self._joint_log_likelihood(self._check_X(X)))

    def predict_proba(self, X: ArrayLike) -> FloatArray:
        """Class probabilities; each row sums to 1.

        Parameters
        ----------
        X : array_like of shape (n_samples, n_features)

        Returns
        -------
        proba : ndarray of shape (n_samples, n_classes)
            Columns in the order of ``classes_``.
        """
        return np.exp(self.predict_log_proba(X))

    def predict(self, X: ArrayLike) -> np.ndarray:
        """Most probable class of each sample.

        Parameters
        ----------
        X : array_like of shape (n_samples, n_features)

        Returns
        -------
        labels : ndarray of shape (n_samples,)
        """
        return self._decide(self._joint_log_likelihood(self._check_X(X)))

    def _predict_with_proba(self, X: ArrayLike) -> tuple[np.ndarray, FloatArray, FloatArray]:
        """``predict(X)``, ``predict_proba(X)`` and the log scores, evaluated once."""
        jll = self._joint_log_likelihood(self._check_X(X))
        return self._decide(jll), np.exp(_normalised(jll)), jll

    def _decide(self, jll: FloatArray) -> np.ndarray:
        """Labels from log scores: the most probable class (Bayes rule)."""
        return self.classes_[np.argmax(jll, axis=1)]
