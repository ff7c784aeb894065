"""Probabilistic neural network (Specht 1990) with MATLAB newpnn's kernel.

Prediction is a brute-force pass over every (sample, pattern) pair, organised
for speed and bounded memory:

- the squared distance comes out of one matrix product: samples and patterns
  are centred on the training mean and augmented with two columns each, so
  that ``[2g x, 1, -g |x|^2] @ [p, -g |p|^2, 1]^T = -g |x - p|^2`` - the log
  kernel itself, with no further pass;
- the product is taken tile by tile (a few hundred rows times a few thousand
  columns, each tile inside one class's contiguous run of patterns, sized to
  stay in cache), and each class's sum of kernels is accumulated over its
  tiles, so no full kernel row is ever held and every value is computed once;
- the sums are log-scaled per (row, class) by a "frame" fixed on the class's
  first tile: no shift at all when the kernel there is not tiny, else that
  tile's maximum. The frame is folded into the product (it is one more term
  of the augmented row), so later tiles need neither a max pass nor a shift:
  product, ``exp`` in place, and a matrix-vector product with ones for the
  sum. The rare tile whose sum overflows its frame (a near pattern after far
  ones) is redone for those rows with an exact shift;
- row blocks are spread over threads (numpy and BLAS release the GIL), with
  BLAS itself limited to one thread inside the workers; as many threads as
  CPUs, but no more than BLAS may use (``threadpoolctl.threadpool_limits``
  on BLAS limits the PNN too);
- ``dtype="float32"`` halves the memory traffic and doubles the SIMD width.

``benchmarks/bench_pnn.py`` measures this against scikit-learn's brute-force
1-nearest-neighbour search and the bare matrix product.
"""

from __future__ import annotations

import itertools
import os
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import numpy as np
from threadpoolctl import threadpool_info, threadpool_limits

from .._typing import ArrayLike, FloatArray
from .._validation import check_fraction, check_spread, check_X_y
from ..errors import InputError
from ._base import BaseProbabilisticClassifier, class_indices

__all__ = ["MAX_BLOCK_BYTES", "NEWPNN_BIAS", "PNNClassifier"]

#: ``b * spread`` for MATLAB's newpnn: a pattern at distance ``spread`` scores 0.5.
NEWPNN_BIAS = float(np.sqrt(-np.log(0.5)))

#: Smallest spread accepted: below it the kernel width ``(b / spread) ** 2`` overflows.
MIN_SPREAD = 1e-150

#: Upper bound, in bytes, on the kernel values held in memory at once, summed
#: over all worker threads (256 MiB). Tiles are normally far smaller (see
#: ``_TILE_BYTES``); this cap only binds on machines with very many threads.
MAX_BLOCK_BYTES = 256 * 2**20

#: Target size of one kernel tile, in bytes: small enough to stay in cache
#: between the product, the ``exp`` pass and the sum.
_TILE_BYTES = 4 * 2**20

#: Most pattern columns in one tile (a tile never spans two classes).
_TILE_COLS = 4096

#: Per dtype: a class whose first tile reaches a log-kernel value above this is
#: summed with no shift (``exp`` of values 40 below it is still a normal number
#: in that dtype), and tile sums above ``_SUM_BIG`` are redone with a shift.
_FRAME_LOW = {np.float64: -600.0, np.float32: -40.0}
_SUM_BIG = {np.float64: 1e300, np.float32: 1e36}

#: Below this many kernel values a prediction runs in the calling thread.
_MIN_PARALLEL = 2**22

#: Spread grid of ``spread="auto"``, relative to the median nearest-neighbour
#: distance, and the most training patterns used as leave-one-out queries.
_AUTO_GRID = np.geomspace(1 / 8, 8, 25)
_AUTO_MAX_QUERIES = 1000

_DTYPES = {"float64": np.float64, "float32": np.float32}


def _n_threads() -> int:
    """Threads for a large prediction.

    The CPUs this process may use, at most as many as BLAS may use (so a
    ``threadpoolctl`` limit applies to the PNN too).
    """
    try:
        cpus = max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        cpus = max(1, os.cpu_count() or 1)
    blas = [i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas"]
    return max(1, min([cpus, *blas]))


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


class PNNClassifier(BaseProbabilisticClassifier):
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

    def _compute_dtype(self) -> type:
        try:
            name = np.dtype(self.dtype).name
        except TypeError:
            name = None
        if name not in _DTYPES:
            raise InputError(f"dtype must be 'float64' or 'float32', got {self.dtype!r}")
        return _DTYPES[name]

    def fit(self, X: ArrayLike, y: ArrayLike) -> PNNClassifier:
        """Store the training patterns (and choose the spread if ``"auto"``).

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
        X, y = check_X_y(self, X, y, dtype=np.float64)
        classes, y_idx = class_indices(y)
        order = np.argsort(y_idx, kind="stable")
        self.classes_ = classes
        self.patterns_ = X[order]
        self.class_count_ = np.bincount(y_idx, minlength=classes.size)
        if isinstance(self.spread, str):
            self.spread_ = auto_spread(self.patterns_, y_idx[order])
        else:
            self.spread_ = float(self.spread)
        self._prepare()
        return self

    def _prepare(self) -> None:
        """Derived arrays for prediction, from ``patterns_`` and ``spread_``."""
        dt = self._compute_dtype()
        P = self.patterns_
        self._center = P.mean(axis=0)
        Pc = P - self._center
        g = self._gamma = (NEWPNN_BIAS / self.spread_) ** 2
        # [p, -g |p|^2, 1]^T, row-major (n_features + 2, n_patterns)
        pt = np.empty((P.shape[1] + 2, P.shape[0]), dtype=dt)
        pt[:-2] = Pc.T
        pt[-2] = -g * np.einsum("ij,ij->i", Pc, Pc)
        pt[-1] = 1.0
        self._pt = pt
        bounds = np.concatenate([[0], np.cumsum(self.class_count_)])
        self._bounds = bounds
        self._tiles1 = self._tiles(1, np.dtype(dt).itemsize)  # single-threaded predictions

    def _tiles(self, n_threads: int, itemsize: int) -> tuple[int, list[tuple[int, int, int]]]:
        """Rows per tile and the column tiles ``(class, start, stop)``."""
        cols = max(1, min(_TILE_COLS, int(self.class_count_.max())))
        tiles = []
        for c in range(self.classes_.size):
            lo, hi = int(self._bounds[c]), int(self._bounds[c + 1])
            n_split = -(-(hi - lo) // cols)
            edges = np.linspace(lo, hi, n_split + 1).round().astype(int)
            tiles += [(c, int(a), int(b)) for a, b in itertools.pairwise(edges)]
        widest = max(b - a for _, a, b in tiles)
        budget = min(_TILE_BYTES, MAX_BLOCK_BYTES // n_threads)
        rows = max(1, budget // (itemsize * widest))
        return rows, tiles

    def _log_sums(self, xa: np.ndarray, rows: int, tiles: list) -> FloatArray:
        """``log sum_j exp(-g d^2)`` per class for the augmented samples ``xa``.

        Sums are kept relative to a per-(row, class) log "frame": 0 where the
        class's first tile already shows a kernel value above ``_FRAME_LOW``
        (then ``exp`` needs no shift at all), else that first tile's maximum.
        Later tiles thus need neither a max pass nor, mostly, a shift; a row
        whose tile sum overflows the frame (a near pattern after far ones) is
        recomputed for that tile and re-framed on its true maximum.
        """
        n, n_classes = xa.shape[0], self.classes_.size
        dt = xa.dtype
        low, big = _FRAME_LOW[dt.type], _SUM_BIG[dt.type]
        frame = np.zeros((n, n_classes))
        s = np.zeros((n, n_classes))
        width = max(b - a for _, a, b in tiles)
        buf = np.empty(min(rows, n) * width, dtype=dt)
        for lo in range(0, n, rows):
            xb = xa[lo : lo + rows]
            fb, sb = frame[lo : lo + rows], s[lo : lo + rows]
            self._frame_block(xb, fb, sb, tiles, buf, low, big)
        return frame + np.log(s)

    def _frame_block(
        self,
        xb: np.ndarray,
        fb: FloatArray,
        sb: FloatArray,
        tiles: list,
        buf: np.ndarray,
        low: float,
        big: float,
    ) -> None:
        """Accumulate one row block's framed class sums into ``fb``, ``sb``.

        The frame is folded into the product: the samples' last augmented
        column (``-g |x|^2``, multiplied by the patterns' row of ones) becomes
        ``-g |x|^2 - frame``, so later tiles come out of the product already
        shifted. Tile sums are matrix-vector products with a vector of ones.
        """
        dt, pt = xb.dtype, self._pt
        ones = np.ones(max(b - a for _, a, b in tiles), dtype=dt)
        xs = xb.copy()  # xb with the current class's frame folded in
        current = -1
        with np.errstate(over="ignore"):  # overflowing tile sums are redone below
            for c, a, b in tiles:
                t = buf[: xb.shape[0] * (b - a)].reshape(xb.shape[0], b - a)
                if c != current:  # first tile of class c: fix the frame
                    current = c
                    np.matmul(xb, pt[:, a:b], out=t)
                    m0 = t.max(axis=1).astype(np.float64)
                    f = np.where(m0 > low, 0.0, m0)
                    fb[:, c] = f
                    xs[:, -1] = xb[:, -1] - f.astype(dt)
                    if f.any():
                        t -= f.astype(dt)[:, None]
                else:
                    np.matmul(xs, pt[:, a:b], out=t)
                np.exp(t, out=t)
                tsum = (t @ ones[: b - a]).astype(np.float64)
                bad = ~(tsum <= big)
                if bad.any():
                    idx = np.flatnonzero(bad)
                    tt = xb[idx] @ pt[:, a:b]
                    new = np.maximum(f[idx], tt.max(axis=1).astype(np.float64))
                    tt -= new.astype(dt)[:, None]
                    np.exp(tt, out=tt)
                    sb[idx, c] = sb[idx, c] * np.exp(f[idx] - new) + tt.sum(axis=1)
                    f[idx] = fb[idx, c] = new
                    xs[idx, -1] = xb[idx, -1] - new.astype(dt)
                    tsum[idx] = 0.0
                sb[:, c] += tsum

    def _joint_log_likelihood(self, X: FloatArray) -> FloatArray:
        dt = self._pt.dtype
        g = self._gamma
        Xc = X - self._center
        xa = np.empty((X.shape[0], X.shape[1] + 2), dtype=dt)
        xa[:, :-2] = 2 * g * Xc
        xa[:, -2] = 1.0
        xa[:, -1] = -g * np.einsum("ij,ij->i", Xc, Xc)
        work = X.shape[0] * self.patterns_.shape[0]
        n_threads = 1 if work < 2 * _MIN_PARALLEL else min(_n_threads(), work // _MIN_PARALLEL)
        rows, tiles = self._tiles1 if n_threads == 1 else self._tiles(n_threads, dt.itemsize)
        if n_threads == 1:
            lse = self._log_sums(xa, rows, tiles)
        else:
            step = -(-X.shape[0] // (4 * n_threads))
            step = -(-step // rows) * rows
            parts = [xa[lo : lo + step] for lo in range(0, X.shape[0], step)]
            with threadpool_limits(1, user_api="blas"), ThreadPoolExecutor(n_threads) as pool:
                lse = np.concatenate(
                    list(pool.map(lambda p: self._log_sums(p, rows, tiles), parts))
                )
        # a log mean kernel is <= 0; rounding in the product may leave tiny excesses
        return np.minimum(lse - np.log(self.class_count_), 0.0)

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
