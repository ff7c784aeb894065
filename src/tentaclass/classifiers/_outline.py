"""Classifier of outline series: random convolution kernels made start-point invariant.

Random-kernel transforms (MiniRocket) are the strongest fast classifiers of
short series, but they learn invariances only from data. An outline series has
no natural start and no natural direction, so every training series is shown
to the transform at random cyclic shifts and mirrored, and every query is
scored at evenly spaced shifts in both directions and the scores averaged. A
shift- and mirror-invariant 1-NN (:class:`ShiftNNClassifier`) is the second
member of the ensemble; both members' probabilities are calibrated on held-out
folds and weighted by their held-out accuracy.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from scipy.optimize import minimize_scalar
from scipy.special import log_softmax
from sklearn.utils import check_random_state

from .._lazy import import_extra
from .._typing import ArrayLike, FloatArray
from .._validation import check_X_y
from ..errors import InputError
from ..features.outline import znormalize
from ._base import BaseProbabilisticClassifier, class_indices
from ._shift_nn import ShiftNNClassifier

if TYPE_CHECKING:
    from aeon.transformations.collection.convolution_based import MiniRocket
    from sklearn.linear_model import RidgeClassifier, RidgeClassifierCV

__all__ = ["OutlineClassifier"]

#: Training copies at random shifts (every other one mirrored) per series.
_N_AUGMENT = 16
#: Evenly spaced shifts at which each query is scored, in each direction.
_N_QUERY_SHIFTS = 4
#: Folds (grouped by training series) for calibration and ensemble weights.
_N_FOLDS = 3
#: The shortest series MiniRocket's kernels (length 9) run over; shorter ones are resampled.
_MIN_LENGTH = 9


def _minirocket(random_state: int) -> MiniRocket:
    aeon = import_extra(
        "aeon.transformations.collection.convolution_based",
        "outline",
        "OutlineClassifier needs aeon's MiniRocket",
        error=InputError,
    )
    return aeon.MiniRocket(random_state=random_state)


def _fit_temperature(scores: FloatArray, y: np.ndarray) -> float:
    """Scale of the scores that minimises the held-out log loss."""

    def nll(log_t: float) -> float:
        lp = log_softmax(scores * np.exp(log_t), axis=1)
        return float(-lp[np.arange(len(y)), y].mean())

    return float(np.exp(minimize_scalar(nll, bounds=(-8.0, 8.0), method="bounded").x))


class OutlineClassifier(BaseProbabilisticClassifier):
    """Class of a one-dimensional outline series, whatever its start and direction.

    Rows of ``X`` are periodic outline signatures of one length (centroid
    distance, turning function, joint angles: see
    :func:`tentaclass.features.outline_to_series`). Each series is
    z-normalised (invariant to the signature's scale and offset), so only its
    shape counts; a cyclic shift (another start point) or a reversal (the
    other direction, a mirror image) changes little.

    Two members, combined by their held-out accuracy:

    - MiniRocket random convolution features (aeon, optional extra
      ``outline``) of every training series at 16 random cyclic shifts, every
      other one reversed, with a ridge classifier; a query is scored at 4
      evenly spaced shifts in both directions and its scores averaged;
    - the shift- and mirror-invariant 1-NN (:class:`ShiftNNClassifier`).

    Each member's scores are turned into probabilities by a softmax whose
    temperature minimises the log loss on held-out folds (grouped by training
    series, so shifted copies of a series never score themselves), and its
    weight in the ensemble is its held-out accuracy.

    Parameters
    ----------
    random_state : int, RandomState instance or None, default=None
        Seeds the shifts of the training copies and MiniRocket's kernels.

    Attributes
    ----------
    classes_ : ndarray of shape (n_classes,)
    n_features_in_ : int
        Length of the series seen in ``fit``.
    member_accuracy_ : dict
        Held-out accuracy of each member (``"rocket"``, ``"shift_nn"``).
    weights_ : dict
        Weight of each member in the ensemble.

    Notes
    -----
    MiniRocket comes from aeon rather than being rewritten: its kernels and
    dilations are the published method. The augmentation, query averaging,
    calibration and weighting are this class's. There is no parameter to
    tune: the ridge penalty is chosen by leave-one-out inside
    ``RidgeClassifierCV``.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    >>> X = np.array([np.cos(k * t + p) for k in (2, 3) for p in np.linspace(0, 3, 6)])
    >>> y = np.repeat(["two lobes", "three lobes"], 6)
    >>> clf = OutlineClassifier(random_state=0).fit(X, y)
    >>> clf.predict(np.roll(X[[0, 6]], 17, axis=1)).tolist()
    ['two lobes', 'three lobes']
    """

    def __init__(self, random_state: int | np.random.RandomState | None = None):
        self.random_state = random_state

    def _augment(self, Z: FloatArray, rng: np.random.RandomState) -> FloatArray:
        n: int
        m: int
        n, m = Z.shape
        copies = [Z]
        for i in range(_N_AUGMENT):
            shift = rng.randint(m, size=n)
            idx = (np.arange(m)[None, :] - shift[:, None]) % m
            c = np.take_along_axis(Z, idx, axis=1)
            copies.append(c[:, ::-1] if i % 2 == 0 else c)
        return np.concatenate(copies)

    @staticmethod
    def _query_views(Z: FloatArray) -> list[FloatArray]:
        m = Z.shape[1]
        views = []
        for i in range(_N_QUERY_SHIFTS):
            r = np.roll(Z, (i * m) // _N_QUERY_SHIFTS, axis=1)
            views += [r, r[:, ::-1]]
        return views

    def _rocket_features(self, Z: FloatArray) -> FloatArray:
        F = self._rocket.transform(Z[:, None, :])
        return (np.asarray(F, dtype=np.float64) - self._mu) / self._sd

    def _rocket_scores(
        self, Z: FloatArray, ridge: RidgeClassifier | RidgeClassifierCV
    ) -> FloatArray:
        total = sum(ridge.decision_function(self._rocket_features(v)) for v in self._query_views(Z))
        s = np.asarray(total, dtype=np.float64) / (2 * _N_QUERY_SHIFTS)
        if s.ndim == 1:  # two classes: one score for the second class
            s = np.column_stack([-s, s]) / 2
        return s

    def _nn_scores(self, d2: FloatArray, labels: np.ndarray) -> FloatArray:
        """Minus the squared distance to the nearest series of each class."""
        out = np.full((d2.shape[0], len(self.classes_)), -np.inf)
        for k in range(len(self.classes_)):
            cols = labels == k
            if cols.any():
                out[:, k] = -d2[:, cols].min(axis=1)
        return np.maximum(out, -1e300)

    def fit(self, X: ArrayLike, y: ArrayLike) -> OutlineClassifier:
        """Learn the outline classes.

        Parameters
        ----------
        X : array_like of shape (n_samples, n_timepoints)
            Outline series (periodic). Series shorter than 9 points (the
            length of MiniRocket's kernels) are resampled periodically.
        y : array_like of shape (n_samples,)

        Returns
        -------
        self : OutlineClassifier
        """
        from sklearn.linear_model import RidgeClassifier, RidgeClassifierCV

        X, y = check_X_y(self, X, y, dtype=np.float64)
        self.classes_, yi = class_indices(y)
        Z = self._prepare(X)
        rng = check_random_state(self.random_state)
        A = self._augment(Z, rng)
        ya = np.tile(yi, _N_AUGMENT + 1)
        groups = np.tile(np.arange(len(Z)), _N_AUGMENT + 1)
        self._rocket = _minirocket(int(rng.randint(2**31 - 1)))
        F = np.asarray(self._rocket.fit_transform(A[:, None, :]), dtype=np.float64)
        self._mu = F.mean(axis=0)
        sd = F.std(axis=0)
        self._sd = np.where(sd > 0, sd, 1.0)
        F = (F - self._mu) / self._sd
        self._ridge = RidgeClassifierCV(alphas=np.logspace(-3, 3, 10)).fit(F, ya)

        # held-out folds grouped by series: calibration and ensemble weights
        fold = rng.permutation(len(Z)) % _N_FOLDS
        rocket_oof = np.zeros((len(Z), len(self.classes_)))
        nn_oof = np.zeros_like(rocket_oof)
        nn = ShiftNNClassifier(signal="raw", center=False)
        for f in range(_N_FOLDS):
            test = fold == f
            train_rows = ~test[groups]
            if len(np.unique(ya[train_rows])) < len(self.classes_):
                continue  # a class absent from this fold's training part: leave zero scores
            ridge = RidgeClassifier(alpha=self._ridge.alpha_).fit(F[train_rows], ya[train_rows])
            rocket_oof[test] = self._rocket_scores(Z[test], ridge)
            d2 = nn.fit(Z[~test], yi[~test]).shift_distances(Z[test])
            nn_oof[test] = self._nn_scores(d2, yi[~test])
        self._nn = nn.fit(Z, yi)
        self._labels = yi
        self._nn_scale = max(float(-nn_oof.min()), 1e-12)  # 1-NN scores of order one
        self._temperature = {
            "rocket": _fit_temperature(rocket_oof, yi),
            "shift_nn": _fit_temperature(nn_oof / self._nn_scale, yi),
        }
        self.member_accuracy_ = {
            "rocket": float(np.mean(rocket_oof.argmax(axis=1) == yi)),
            "shift_nn": float(np.mean(nn_oof.argmax(axis=1) == yi)),
        }
        total = sum(self.member_accuracy_.values())
        self.weights_ = {
            k: (v / total if total > 0 else 0.5) for k, v in self.member_accuracy_.items()
        }
        return self

    @staticmethod
    def _prepare(X: ArrayLike) -> FloatArray:
        """z-normalised series, resampled periodically to MiniRocket's shortest length."""
        Z = znormalize(X, "X")
        m = Z.shape[1]
        if m < _MIN_LENGTH:
            t = np.arange(_MIN_LENGTH) * m / _MIN_LENGTH
            Z = np.array([np.interp(t, np.arange(m), z, period=m) for z in Z])
            Z = znormalize(Z, "X")
        return Z

    def _joint_log_likelihood(self, X: FloatArray) -> FloatArray:
        Z = self._prepare(X)
        rocket = log_softmax(
            self._rocket_scores(Z, self._ridge) * self._temperature["rocket"], axis=1
        )
        nn_scores = self._nn_scores(self._nn.shift_distances(Z), self._labels) / self._nn_scale
        nn = log_softmax(nn_scores * self._temperature["shift_nn"], axis=1)
        w = self.weights_
        return np.logaddexp(
            np.log(w["rocket"] + 1e-300) + rocket, np.log(w["shift_nn"] + 1e-300) + nn
        )
