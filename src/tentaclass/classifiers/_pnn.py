"""Probabilistic neural network (Specht 1990) with MATLAB newpnn's kernel.

See :mod:`tentaclass.classifiers._pnn_core` for how prediction is organised;
``benchmarks/bench_pnn.py`` measures it against scikit-learn's brute-force
1-nearest-neighbour search and the bare matrix product.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .._typing import FloatArray
from .._validation import check_fraction, check_spread, check_unknown_label
from ._base import BaseProbabilisticClassifier
from ._pnn_core import MAX_BLOCK_BYTES, NEWPNN_BIAS, PNNCore

__all__ = ["MAX_BLOCK_BYTES", "NEWPNN_BIAS", "PNNClassifier"]

#: Smallest spread accepted: below it the kernel width ``(b / spread) ** 2`` overflows.
MIN_SPREAD = 1e-150

#: Spread grid of ``spread="auto"``, relative to the median nearest-neighbour
#: distance, and the most training patterns used as leave-one-out queries.
_AUTO_GRID = np.geomspace(1 / 8, 8, 25)
_AUTO_MAX_QUERIES = 1000


def _sq_dist(a: FloatArray, b: FloatArray, b_sq: FloatArray) -> FloatArray:
    """Squared Euclidean distances ``(len(a), len(b))``, clipped at 0."""
    d = a @ b.T
    d *= -2
    d += b_sq
    d += np.einsum("ij,ij->i", a, a)[:, None]
    return np.maximum(d, 0.0, out=d)


def _evenly(n: int, most: int) -> np.ndarray:
    """At most ``most`` indices of ``range(n)``, evenly spaced, first and last included."""
    return np.unique(np.linspace(0, n - 1, min(n, most)).round().astype(int))


def _median_nn(A: FloatArray, a_sq: FloatArray | None = None) -> float:
    """Median distance from a row of ``A`` to its nearest distinct other row (1.0 if none).

    At most ``_AUTO_MAX_QUERIES`` rows (evenly spaced) are queried against
    all rows, in blocks of bounded size. Rows closer than the rounding of the
    distance formula (relative ``1e-12``, absolute ``1e-150``) count as
    duplicates and are ignored. ``a_sq`` holds the squared norms of the rows,
    if already at hand.
    """
    if a_sq is None:
        a_sq = np.einsum("ij,ij->i", A, A)
    queries = _evenly(A.shape[0], _AUTO_MAX_QUERIES)
    step = max(1, (32 * 2**20) // (8 * A.shape[0]))
    nn = []
    for lo in range(0, queries.size, step):
        rows = queries[lo : lo + step]
        d = _sq_dist(A[rows], A, a_sq)
        d[d <= 1e-12 * (a_sq[rows][:, None] + a_sq[None, :]) + 1e-300] = np.inf
        nn.append(np.sqrt(d.min(axis=1)))
    nn = np.concatenate(nn)
    nn = nn[np.isfinite(nn)]
    d_nn = float(np.median(nn)) if nn.size else 1.0
    return d_nn if 0 < d_nn < np.inf else 1.0


def auto_spread(X: FloatArray, y_idx: np.ndarray, *, return_scores: bool = False) -> Any:
    """The spread that maximises the leave-one-out log-likelihood of the classes.

    Each class's Parzen density - the PNN's summation unit made a normalised
    Gaussian density, ``sigma = spread / sqrt(2 log 2)`` - is evaluated at each
    of its own patterns with that pattern left out; the chosen spread maximises
    the sum of these log densities (likelihood cross-validation, Duin 1976)
    over the grid ``_AUTO_GRID`` times ``d_nn``, the median distance from a
    pattern to its nearest distinct neighbour. At most ``_AUTO_MAX_QUERIES``
    patterns (evenly spaced in the training order) serve as queries; every
    pattern of their class enters the density. When no class has two patterns,
    ``d_nn`` is returned.

    Parameters
    ----------
    X : ndarray of shape (n_samples, n_features)
    y_idx : ndarray of shape (n_samples,)
        Class index of each row.
    return_scores : bool, default=False
        Also return the grid of spreads and their log-likelihoods.

    Returns
    -------
    spread : float
    grid, scores : ndarray of shape (n_grid,)
        Only with ``return_scores``.
    """
    X = X - X.mean(axis=0)
    sq = np.einsum("ij,ij->i", X, X)
    queries = _evenly(X.shape[0], _AUTO_MAX_QUERIES)
    d_nn = _median_nn(X, sq)
    grid = d_nn * _AUTO_GRID
    counts = np.bincount(y_idx)
    scores = np.zeros(grid.size)
    usable = queries[counts[y_idx[queries]] >= 2]
    if usable.size == 0:
        return (d_nn, grid, scores) if return_scores else d_nn
    gammas = (NEWPNN_BIAS / grid) ** 2
    sigma2 = 1 / (2 * gammas)
    n_feat = X.shape[1]
    for c in np.unique(y_idx[usable]):
        members = np.flatnonzero(y_idx == c)
        qs = usable[y_idx[usable] == c]
        rows_c = max(1, (32 * 2**20) // (8 * members.size))
        for lo in range(0, qs.size, rows_c):
            q = qs[lo : lo + rows_c]
            d = _sq_dist(X[q], X[members], sq[members])
            d[np.arange(q.size), np.searchsorted(members, q)] = np.inf  # leave one out
            dmin = d.min(axis=1, keepdims=True)
            d -= dmin
            for k, g in enumerate(gammas):
                lse = np.log(np.exp(-g * d).sum(axis=1)) - g * dmin[:, 0]
                scores[k] += lse.sum()
        scores -= qs.size * (np.log(members.size - 1) + 0.5 * n_feat * np.log(2 * np.pi * sigma2))
    spread = float(grid[int(np.argmax(scores))])
    return (spread, grid, scores) if return_scores else spread


class PNNClassifier(PNNCore, BaseProbabilisticClassifier):
    """Probabilistic neural network: one Gaussian kernel per training pattern.

    The score of class ``c`` for a sample ``x`` is the mean kernel value over the
    class's training patterns ``x_j``,
    ``s_c(x) = mean_j exp(-(b * ||x - x_j||)^2)`` with ``b = sqrt(-log 0.5) / spread``
    (MATLAB's ``newpnn``: a pattern at distance ``spread`` scores exactly 0.5).
    The decision is the largest score (Bayes rule with equal priors);
    probabilities are the scores normalised to sum 1. There is no iterative
    training: ``fit`` stores the patterns (and chooses the spread if asked).

    Parameters
    ----------
    spread : float or "auto", default=0.1
        Kernel width, in the units of the features (newpnn's default 0.1).
        ``"auto"`` chooses it on the training set by leave-one-out likelihood
        (see :func:`auto_spread`); the number used is ``spread_``.
    reject_below : float, optional
        If set, :meth:`predict` answers ``unknown_label`` for samples whose best
        class score (a mean kernel value in [0, 1]) is below this threshold,
        instead of forcing the nearest class.
    unknown_label : object, default="unknown"
        Label for rejected samples.
    dtype : {"float64", "float32"}, default="float64"
        Precision of the kernel computation. ``"float32"`` is about twice as
        fast; probabilities then agree with float64 to about 1e-5 for data of
        moderate scale relative to the spread (distances come from a product of
        centred data, so precision is lost when ``|x - mean|`` is many
        thousand spreads). Log scores are returned in float64 either way.

    Attributes
    ----------
    classes_ : ndarray of shape (n_classes,)
        Class labels, sorted.
    n_features_in_ : int
        Number of features seen in ``fit``.
    spread_ : float
        The spread in use: ``spread`` itself, or the number ``"auto"`` chose.
    patterns_ : ndarray of shape (n_patterns, n_features)
        Training patterns, grouped by class.
    class_count_ : ndarray of shape (n_classes,)
        Number of patterns per class.

    Notes
    -----
    Scores are computed in log space, ``log s_c = logsumexp(-b^2 d^2) - log n_c``,
    so a sample far from every pattern still gets finite log scores and valid
    probabilities. Memory stays bounded by ``MAX_BLOCK_BYTES`` whatever the
    sizes; see the module docstring for how the computation is organised.

    References
    ----------
    D. F. Specht, "Probabilistic neural networks", Neural Networks 3(1), 1990.
    R. P. W. Duin, "On the choice of smoothing parameters for Parzen estimators
    of probability density functions", IEEE Trans. Computers C-25(11), 1976.

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

    With ``spread="auto"`` the width follows the data's scale:

    >>> import numpy as np
    >>> rng = np.random.default_rng(0)
    >>> X = np.concatenate([rng.normal(0, 1, (50, 2)), rng.normal(10, 1, (50, 2))])
    >>> clf = PNNClassifier(spread="auto").fit(X, [0] * 50 + [1] * 50)
    >>> clf.spread, 0.3 < clf.spread_ < 3
    ('auto', True)
    """

    def __init__(
        self,
        spread: float | str = 0.1,
        reject_below: float | None = None,
        unknown_label: object = "unknown",
        dtype: str = "float64",
    ):
        self.spread = spread
        self.reject_below = reject_below
        self.unknown_label = unknown_label
        self.dtype = dtype

    def _validate_params(self) -> None:
        check_spread(self.spread, minimum=MIN_SPREAD)
        if self.reject_below is not None:
            check_fraction(self.reject_below, "reject_below")
        self._compute_dtype()

    def _fit(self, X: FloatArray, classes: np.ndarray, y_idx: np.ndarray) -> None:
        """Store the training patterns (and choose the spread if ``"auto"``)."""
        if self.reject_below is not None:
            check_unknown_label(self.unknown_label, classes)
        order = np.argsort(y_idx, kind="stable")
        self.classes_ = classes
        self.patterns_ = X[order]
        self.class_count_ = np.bincount(y_idx, minlength=classes.size)
        if isinstance(self.spread, str):
            self.spread_ = auto_spread(self.patterns_, y_idx[order])
        else:
            self.spread_ = float(self.spread)
        self._prepare()
