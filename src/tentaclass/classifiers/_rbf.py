"""Radial-basis-function network: Gaussian hidden layer, linear output layer."""

from __future__ import annotations

import numpy as np
from sklearn.cluster import KMeans
from sklearn.utils import check_random_state

from .._typing import ArrayLike, FloatArray
from .._validation import (
    cap_count,
    check_choice,
    check_distance_scale,
    check_positive_float,
    check_positive_int,
    check_spread,
)
from ._base import BaseProbabilisticClassifier
from ._pnn import MIN_SPREAD, NEWPNN_BIAS, _evenly, _median_nn, _sq_dist

__all__ = ["RBFNetworkClassifier"]

#: Spread grid of ``spread="auto"``, relative to the median nearest-neighbour
#: distance between centres (between training patterns for ``"forward"``).
_AUTO_GRID = np.geomspace(0.5, 32, 13)

#: Most training patterns offered as candidate centres to forward selection.
_FORWARD_MAX_CANDIDATES = 2000

#: Most training patterns on which ``spread="auto"`` scores its grid.
_AUTO_MAX_SAMPLES = 500

#: Weight of the soft floor in ``predict_proba`` (see the class Notes).
_PROBA_FLOOR = 1e-6

_CENTERS = ("all", "kmeans", "forward")


def _design(X: FloatArray, centers: FloatArray, spread: float) -> FloatArray:
    """Hidden-layer outputs ``exp(-(b d)^2)``, shape (n_samples, n_centers)."""
    d = _sq_dist(X, centers, np.einsum("ij,ij->i", centers, centers))
    d *= -((NEWPNN_BIAS / spread) ** 2)
    return np.exp(d, out=d)


def _ridge(Phi: FloatArray, Y: FloatArray, alpha: float) -> tuple[FloatArray, FloatArray]:
    """Ridge least squares with an unpenalised intercept: ``coef``, ``intercept``.

    Solved through the SVD of the centred design (not the normal equations,
    whose condition number is the square of the design's), with singular
    values below ``eps * max(shape) * s_max`` treated as zero, as ``lstsq`` does.
    """
    mu_phi, mu_y = Phi.mean(axis=0), Y.mean(axis=0)
    U, s, Vt = np.linalg.svd(Phi - mu_phi, full_matrices=False)
    keep = s > np.finfo(float).eps * max(Phi.shape) * (s[0] if s.size else 0.0)
    f = np.zeros_like(s)
    f[keep] = s[keep] / (s[keep] ** 2 + alpha)
    coef = Vt.T @ (f[:, None] * (U.T @ (Y - mu_y)))
    return coef, mu_y - mu_phi @ coef


def _gcv(Phi: FloatArray, Y: FloatArray, alpha: float) -> float:
    """Generalised cross-validation score of the ridge fit (smaller is better)."""
    n = Phi.shape[0]
    Pc = Phi - Phi.mean(axis=0)
    Yc = Y - Y.mean(axis=0)
    s2, V = np.linalg.eigh(Pc.T @ Pc)
    keep = s2 > 1e-12 * max(s2.max(), 1e-300)
    s2, V = s2[keep], V[:, keep]
    z = V.T @ (Pc.T @ Yc)  # = diag(s) U^T Yc
    h = s2 / (s2 + alpha)
    uy2 = (z**2).sum(axis=1) / s2  # |U^T Yc|^2 per component
    rss = max(float((Yc**2).sum() - (uy2 * (1 - (1 - h) ** 2)).sum()), 0.0)
    dof = n - h.sum() - 1
    return n * rss / dof**2 if dof > 0.5 else np.inf


def _forward_select(Phi: FloatArray, Y: FloatArray, n_centers: int, goal: float) -> np.ndarray:
    """Orthogonal forward selection of columns of ``Phi`` (Chen et al. 1991).

    Each step adds the candidate that most reduces the residual sum of squares
    of the (intercept-centred) targets, as MATLAB's ``newrb`` adds neurons,
    until ``n_centers`` are chosen or the mean squared error reaches ``goal``.
    """
    W = Phi - Phi.mean(axis=0)
    r = Y - Y.mean(axis=0)
    norms0 = np.einsum("ij,ij->j", W, W)
    chosen: list[int] = []
    n_out = Y.size
    while len(chosen) < n_centers and (r**2).sum() / n_out > goal:
        ww = np.einsum("ij,ij->j", W, W)
        gain = ((W.T @ r) ** 2).sum(axis=1)
        usable = ww > 1e-10 * np.maximum(norms0, 1e-300)
        usable[chosen] = False
        if not usable.any():
            break
        gain = np.where(usable, gain / np.where(usable, ww, 1.0), -np.inf)
        j = int(np.argmax(gain))
        chosen.append(j)
        q = W[:, j] / np.sqrt(ww[j])
        W -= np.outer(q, q @ W)
        r -= np.outer(q, q @ r)
    return np.array(chosen, dtype=int)


class RBFNetworkClassifier(BaseProbabilisticClassifier):
    """Radial-basis-function network: Gaussian hidden layer, ridge output layer.

    Hidden unit ``j`` outputs ``exp(-(b * ||x - c_j||)^2)`` with
    ``b = sqrt(-log 0.5) / spread`` (MATLAB's ``radbas`` in ``newrb``: an input at
    distance ``spread`` from a centre gives 0.5). The linear output layer maps
    the hidden outputs to one output per class; its weights and biases are the
    ridge least-squares fit to one-hot targets.

    Parameters
    ----------
    centers : {"all", "kmeans", "forward"}, default="all"
        ``"all"``: every training pattern is a centre (``newrbe``).
        ``"kmeans"``: the ``n_centers`` k-means centroids of the training set.
        ``"forward"``: forward selection as in ``newrb``: starting from none,
        add the training pattern whose unit most reduces the residual sum of
        squares (orthogonal least squares), until ``n_centers`` units or the
        mean squared error ``goal``. Candidates are at most 2000 patterns
        (evenly spaced in the training order).
    n_centers : int, optional
        Number of centres for ``"kmeans"``, the most for ``"forward"``;
        default ``min(n_samples, 100)``. Ignored by ``"all"``. ``"kmeans"``
        cannot find more centroids than distinct training samples: it fits that
        many, with a :class:`~tentaclass.errors.TentaclassWarning` when
        ``n_centers`` asked for more. ``"forward"`` chooses among at most
        ``min(n_samples, 2000)`` candidates, so it never returns more (without a
        warning: ``n_centers`` is only its upper bound). ``n_centers_`` is the
        number fitted.
    spread : float or "auto", default="auto"
        Width of the Gaussians. ``"auto"`` picks, on a log grid from 0.5 to 32
        times the median nearest-neighbour distance between centres (training
        patterns for ``"forward"``), the spread with the smallest generalised
        cross-validation error of the ridge output layer. The grid is scored
        on at most 500 training patterns (evenly spaced; for ``"all"`` and
        ``"forward"`` they are also the centres or candidates), and the chosen
        multiple is applied to the spacing of the full centre set. The value
        used is ``spread_``.
    alpha : float, default=1e-6
        Ridge penalty on the output weights (biases are not penalised).
        ``alpha -> 0`` with ``centers="all"`` interpolates the training set.
    goal : float, default=0.0
        Mean squared error at which ``"forward"`` stops adding centres.
    random_state : int, RandomState instance or None, default=None
        Seeds k-means (``centers="kmeans"``).

    Attributes
    ----------
    classes_ : ndarray of shape (n_classes,)
    n_features_in_ : int
    centers_ : ndarray of shape (n_centers_, n_features)
        Centres of the hidden units.
    n_centers_ : int
    spread_ : float
        The spread in use.
    coef_ : ndarray of shape (n_centers_, n_classes)
        Output-layer weights.
    intercept_ : ndarray of shape (n_classes,)
        Output-layer biases.

    Notes
    -----
    Least squares on one-hot targets estimates the class posteriors, so
    :meth:`predict_proba` takes the outputs ``o`` clipped at zero and
    normalised, with a soft floor that keeps every probability positive and
    the order of the outputs: ``p_c ∝ max(o_c, 0) + 1e-6 exp(o_c - max_k o_k)``.
    :meth:`predict` takes the largest output, which is also the most probable
    class. :meth:`network_outputs` gives the raw outputs.

    References
    ----------
    S. Chen, C. F. N. Cowan, P. M. Grant, "Orthogonal least squares learning
    algorithm for radial basis function networks", IEEE Trans. Neural
    Networks 2(2), 1991.

    Examples
    --------
    >>> from tentaclass.classifiers import RBFNetworkClassifier
    >>> X = [[0.0], [0.2], [1.0], [1.2]]
    >>> y = ["a", "a", "b", "b"]
    >>> clf = RBFNetworkClassifier(spread=0.5).fit(X, y)
    >>> clf.predict([[0.1], [1.1]]).tolist()
    ['a', 'b']
    >>> clf.network_outputs([[0.0]]).round(3).tolist()  # interpolates one-hot targets
    [[1.0, 0.0]]

    Forward selection needs few units here:

    >>> clf = RBFNetworkClassifier(centers="forward", n_centers=2, spread=1.0).fit(X, y)
    >>> clf.n_centers_, clf.score(X, y)
    (2, 1.0)
    """

    def __init__(
        self,
        centers: str = "all",
        n_centers: int | None = None,
        spread: float | str = "auto",
        alpha: float = 1e-6,
        goal: float = 0.0,
        random_state: int | np.random.RandomState | None = None,
    ):
        self.centers = centers
        self.n_centers = n_centers
        self.spread = spread
        self.alpha = alpha
        self.goal = goal
        self.random_state = random_state

    def _validate_params(self) -> None:
        check_choice(self.centers, "centers", _CENTERS)
        if self.n_centers is not None:
            check_positive_int(self.n_centers, "n_centers")
        check_spread(self.spread, minimum=MIN_SPREAD)
        for name in ("alpha", "goal"):
            check_positive_float(getattr(self, name), name, allow_zero=True)

    def _fit(self, X: FloatArray, classes: np.ndarray, y_idx: np.ndarray) -> None:
        """Choose the centres and the spread, and solve the output layer."""
        check_distance_scale(X)  # (the centres' design matrix and the spread need them)
        rng = check_random_state(self.random_state)
        Y = np.eye(classes.size)[y_idx]
        n = X.shape[0]
        k = min(n, 100) if self.n_centers is None else min(int(self.n_centers), n)
        alpha = float(self.alpha)

        if self.centers == "all":
            fixed = X
        elif self.centers == "kmeans":
            distinct = np.unique(X, axis=0).shape[0]
            if self.n_centers is None:
                k = min(k, distinct)
            else:
                what = "distinct training samples"
                k = cap_count(int(self.n_centers), distinct, "n_centers", what)
            km = KMeans(n_clusters=k, n_init=3, random_state=rng).fit(X)
            fixed = km.cluster_centers_
        else:
            fixed = None
        goal = float(self.goal)

        def build(rows: np.ndarray, spread: float) -> tuple[FloatArray, FloatArray]:
            """Centres and design matrix on the training rows ``rows``."""
            Xr = X[rows]
            if fixed is not None:
                return fixed, _design(Xr, fixed, spread)
            if self.centers == "all":
                return Xr, _design(Xr, Xr, spread)
            cand = Xr[_evenly(Xr.shape[0], _FORWARD_MAX_CANDIDATES)]
            Phi = _design(Xr, cand, spread)
            chosen = _forward_select(Phi, Y[rows], k, goal)
            return cand[chosen], Phi[:, chosen]

        every = np.arange(n)
        if isinstance(self.spread, str):
            # choose the spread, relative to the centre spacing, on at most
            # _AUTO_MAX_SAMPLES training rows; then scale to the full centre set
            sub = _evenly(n, _AUTO_MAX_SAMPLES)
            ref_sub = fixed if fixed is not None else X[sub]
            ref_all = fixed if fixed is not None else X
            d_sub = _median_nn(ref_sub)
            scores = [_gcv(build(sub, d_sub * r)[1], Y[sub], alpha) for r in _AUTO_GRID]
            ratio = float(_AUTO_GRID[int(np.argmin(scores))])
            self.spread_ = ratio * (d_sub if ref_all is ref_sub else _median_nn(ref_all))
        else:
            self.spread_ = float(self.spread)
        centers, Phi = build(every, self.spread_)
        self.classes_ = classes
        self.centers_ = np.array(centers, dtype=np.float64)
        self.n_centers_ = int(self.centers_.shape[0])
        self.coef_, self.intercept_ = _ridge(Phi, Y, alpha)

    def _outputs(self, X: FloatArray) -> FloatArray:
        return _design(X, self.centers_, self.spread_) @ self.coef_ + self.intercept_

    def network_outputs(self, X: ArrayLike) -> FloatArray:
        """Raw outputs of the linear layer, one column per class.

        Parameters
        ----------
        X : array_like of shape (n_samples, n_features)

        Returns
        -------
        outputs : ndarray of shape (n_samples, n_classes)
            Near the one-hot code of the class on the training set.
        """
        return self._outputs(self._check_X(X))

    def _joint_log_likelihood(self, X: FloatArray) -> FloatArray:
        o = self._outputs(X)
        soft = np.log(_PROBA_FLOOR) + (o - o.max(axis=1, keepdims=True))
        pos = o > 0
        clipped = np.log(o, out=np.full_like(o, -np.inf), where=pos)
        return np.where(pos, np.logaddexp(clipped, soft), soft)
