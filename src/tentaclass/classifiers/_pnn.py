"""Probabilistic neural network (Specht 1990) with MATLAB newpnn's kernel."""

from __future__ import annotations

import numbers

import numpy as np
from sklearn.utils.multiclass import check_classification_targets
from sklearn.utils.validation import validate_data

from .._typing import ArrayLike, FloatArray
from ..errors import InputError
from ._base import BaseProbabilisticClassifier

__all__ = ["PNNClassifier"]

#: ``b * spread`` for MATLAB's newpnn: a pattern at distance ``spread`` scores 0.5.
NEWPNN_BIAS = float(np.sqrt(-np.log(0.5)))

#: Upper bound on the kernel block held in memory at once, in bytes.
_BLOCK_BYTES = 64 * 2**20


class PNNClassifier(BaseProbabilisticClassifier):
    """Probabilistic neural network: one Gaussian kernel per training pattern.

    The score of class ``c`` for a sample ``x`` is the mean kernel value over the
    class's training patterns ``x_j``,
    ``s_c(x) = mean_j exp(-(b * ||x - x_j||)^2)`` with ``b = sqrt(-log 0.5) / spread``
    (MATLAB's ``newpnn``: a pattern at distance ``spread`` scores exactly 0.5).
    The decision is the largest score (Bayes rule with equal priors);
    probabilities are the scores normalised to sum 1. There is no iterative
    training: ``fit`` stores the patterns.

    Parameters
    ----------
    spread : float, default=0.1
        Kernel width, in the units of the features (newpnn's default 0.1).
    reject_below : float, optional
        If set, :meth:`predict` answers ``unknown_label`` for samples whose best
        class score (a mean kernel value in [0, 1]) is below this threshold,
        instead of forcing the nearest class.
    unknown_label : object, default="unknown"
        Label for rejected samples.

    Attributes
    ----------
    classes_ : ndarray of shape (n_classes,)
        Class labels, sorted.
    n_features_in_ : int
        Number of features seen in ``fit``.
    patterns_ : ndarray of shape (n_patterns, n_features)
        Training patterns, grouped by class.
    class_count_ : ndarray of shape (n_classes,)
        Number of patterns per class.

    Notes
    -----
    Scores are computed in log space, ``log s_c = logsumexp(-b^2 d^2) - log n_c``,
    from squared distances ``d^2 = |x|^2 + |x_j|^2 - 2 x.x_j`` taken as blocked
    matrix products, so a sample far from every pattern still gets finite log
    scores and valid probabilities, and memory stays bounded.

    References
    ----------
    D. F. Specht, "Probabilistic neural networks", Neural Networks 3(1), 1990.

    Examples
    --------
    >>> from tentaclass.classifiers import PNNClassifier
    >>> X = [[0.0], [0.1], [1.0], [1.1]]
    >>> y = ["a", "a", "b", "b"]
    >>> clf = PNNClassifier(spread=0.1).fit(X, y)
    >>> clf.predict([[0.05], [0.9]]).tolist()
    ['a', 'b']
    >>> float(clf.class_scores([[0.0]])[0, 0].round(4))  # (1 + 0.5) / 2
    0.75
    >>> PNNClassifier(spread=0.1, reject_below=0.01).fit(X, y).predict([[5.0]]).tolist()
    ['unknown']
    """

    def __init__(
        self,
        spread: float = 0.1,
        reject_below: float | None = None,
        unknown_label: object = "unknown",
    ):
        self.spread = spread
        self.reject_below = reject_below
        self.unknown_label = unknown_label

    def _validate_params(self) -> None:
        s = self.spread
        if isinstance(s, bool) or not isinstance(s, numbers.Real) or not (np.isfinite(s) and s > 0):
            raise InputError(f"spread must be a finite number > 0, got {s!r}")
        r = self.reject_below
        if r is not None and (
            isinstance(r, bool) or not isinstance(r, numbers.Real) or not 0 <= r <= 1
        ):
            raise InputError(f"reject_below must be None or a number in [0, 1], got {r!r}")

    def fit(self, X: ArrayLike, y: ArrayLike) -> PNNClassifier:
        """Store the training patterns.

        Parameters
        ----------
        X : array_like of shape (n_samples, n_features)
        y : array_like of shape (n_samples,)
            Class labels of any type.

        Returns
        -------
        self : PNNClassifier
        """
        self._validate_params()
        X, y = validate_data(self, X, y, dtype=np.float64)
        check_classification_targets(y)
        classes, y_idx = np.unique(y, return_inverse=True)
        if classes.size < 2:
            raise InputError(f"y must hold at least 2 classes, got 1 class: {classes.tolist()}")
        order = np.argsort(y_idx, kind="stable")
        self.classes_ = classes
        self.patterns_ = X[order]
        self.class_count_ = np.bincount(y_idx, minlength=classes.size)
        self._starts = np.concatenate([[0], np.cumsum(self.class_count_)[:-1]])
        self._sq_norms = np.einsum("ij,ij->i", self.patterns_, self.patterns_)
        return self

    @property
    def _bias(self) -> float:
        return NEWPNN_BIAS / float(self.spread)

    def _joint_log_likelihood(self, X: FloatArray) -> FloatArray:
        P = self.patterns_
        gamma = self._bias**2
        n_pat = P.shape[0]
        rows = max(1, _BLOCK_BYTES // (8 * max(n_pat, 1)))
        out = np.empty((X.shape[0], self.classes_.size))
        x_sq = np.einsum("ij,ij->i", X, X)
        log_counts = np.log(self.class_count_)
        for lo in range(0, X.shape[0], rows):
            xb = X[lo : lo + rows]
            # -gamma * d^2 = 2 gamma x.p - gamma |p|^2 - gamma |x|^2, clipped at 0 from above
            k = xb @ P.T
            k *= 2 * gamma
            k -= gamma * self._sq_norms
            k -= (gamma * x_sq[lo : lo + rows])[:, None]
            np.minimum(k, 0.0, out=k)
            # log-sum-exp per class over the grouped columns
            m = np.maximum.reduceat(k, self._starts, axis=1)
            k -= np.repeat(m, self.class_count_, axis=1)
            np.exp(k, out=k)
            s = np.add.reduceat(k, self._starts, axis=1)
            out[lo : lo + rows] = m + np.log(s) - log_counts
        return out

    def class_scores(self, X: ArrayLike) -> FloatArray:
        """Mean kernel value of each class: the PNN's summation layer.

        Parameters
        ----------
        X : array_like of shape (n_samples, n_features)

        Returns
        -------
        scores : ndarray of shape (n_samples, n_classes)
            Values in [0, 1]; they underflow to 0 far from every pattern (use
            :meth:`predict_log_proba` for probabilities there).
        """
        return np.exp(self._joint_log_likelihood(self._check_X(X)))

    def _decide(self, jll: FloatArray) -> np.ndarray:
        """Most probable class, or ``unknown_label`` where the best score is too low."""
        labels = super()._decide(jll)
        if not self.reject_below:
            return labels
        rejected = jll.max(axis=1) < np.log(self.reject_below)
        if not rejected.any():
            return labels
        labels = labels.astype(object)
        labels[rejected] = self.unknown_label
        return labels
