"""The prediction of a fitted probabilistic neural network, free of scikit-learn.

:class:`~tentaclass.classifiers.PNNClassifier` inherits it; a model file is
evaluated with it without importing scikit-learn (:mod:`tentaclass.io._light`).

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

import numpy as np
from threadpoolctl import threadpool_info, threadpool_limits

from .._typing import ArrayLike, FloatArray
from ..errors import InputError
from ._prob_core import ProbabilisticCore

#: ``b * spread`` for MATLAB's newpnn: a pattern at distance ``spread`` scores 0.5.
NEWPNN_BIAS = float(np.sqrt(-np.log(0.5)))

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

#: Up to this many kernel values (a small batch), all classes are framed and
#: exponentiated at once rather than tile by tile (same values, fewer steps;
#: beyond it the tiles' cache locality wins).
_WHOLE_MAX = 2**16

#: Below this many kernel values a prediction runs in the calling thread.
_MIN_PARALLEL = 2**22

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


class PNNCore(ProbabilisticCore):
    """Class scores of a fitted PNN from ``patterns_``, ``class_count_`` and ``spread_``.

    :meth:`_prepare` derives the arrays the prediction uses; the estimator
    calls it in ``fit`` and a model file's reader after setting the state.
    """

    dtype: str
    spread_: float
    patterns_: np.ndarray
    class_count_: np.ndarray
    reject_below: float | None
    unknown_label: object

    def _compute_dtype(self) -> type:
        try:
            name = np.dtype(self.dtype).name
        except TypeError:
            name = None
        if name not in _DTYPES:
            raise InputError(f"dtype must be 'float64' or 'float32', got {self.dtype!r}")
        return _DTYPES[name]

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
        if n * self._pt.shape[1] <= _WHOLE_MAX and len(tiles) == n_classes and dt == np.float64:
            whole = self._log_sums_whole(xa, low, big)
            if whole is not None:
                return whole
        frame = np.zeros((n, n_classes))
        s = np.zeros((n, n_classes))
        width = max(b - a for _, a, b in tiles)
        buf = np.empty(min(rows, n) * width, dtype=dt)
        for lo in range(0, n, rows):
            xb = xa[lo : lo + rows]
            fb, sb = frame[lo : lo + rows], s[lo : lo + rows]
            self._frame_block(xb, fb, sb, tiles, buf, low, big)
        return frame + np.log(s)

    def _log_sums_whole(self, xa: np.ndarray, low: float, big: float) -> FloatArray | None:
        """:meth:`_log_sums` of a small float64 batch when every class is one tile.

        The same values in fewer steps (one ``exp``, one maximum and one frame
        pass for all classes at once, which matters for small batches); None
        when a class's sum overflows its frame (then the tiled pass redoes it).
        """
        dt, bounds, pt = xa.dtype, self._bounds, self._pt
        t = np.empty((xa.shape[0], pt.shape[1]), dtype=dt)
        edges = list(itertools.pairwise(bounds.tolist()))
        for a, b in edges:  # per class, as the tiles are (the sums of products follow the shape)
            np.matmul(xa, pt[:, a:b], out=t[:, a:b])
        m0 = np.maximum.reduceat(t, bounds[:-1], axis=1).astype(np.float64)
        frame = np.where(m0 > low, 0.0, m0)
        if frame.any():
            t -= np.repeat(frame.astype(dt), self.class_count_, axis=1)
        with np.errstate(over="ignore"):
            np.exp(t, out=t)
            ones = np.ones(int(self.class_count_.max()), dtype=dt)
            s = np.empty(frame.shape)
            for c, (a, b) in enumerate(edges):
                # contiguous, as a tile is (BLAS's sums may follow the layout)
                s[:, c] = np.ascontiguousarray(t[:, a:b]) @ ones[: b - a]
        if not (s <= big).all():
            return None
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
        exp_low = float(np.exp(low))
        with np.errstate(over="ignore"):  # overflowing tile sums are redone below
            for c, a, b in tiles:
                t = buf[: xb.shape[0] * (b - a)].reshape(xb.shape[0], b - a)
                np.matmul(xb if c != current else xs, pt[:, a:b], out=t)
                np.exp(t, out=t)
                tsum = (t @ ones[: b - a]).astype(np.float64)
                if c != current:  # first tile of class c: fix the frame
                    current = c
                    f = np.zeros(xb.shape[0])
                    # a row whose kernel is above exp(low) somewhere in the tile
                    # has no frame (a sum of b - a kernels all below it is less)
                    if not (tsum > 2 * (b - a) * exp_low).all():
                        np.matmul(xb, pt[:, a:b], out=t)
                        m0 = t.max(axis=1).astype(np.float64)
                        f = np.where(m0 > low, 0.0, m0)
                        if f.any():
                            t -= f.astype(dt)[:, None]
                        np.exp(t, out=t)
                        tsum = (t @ ones[: b - a]).astype(np.float64)
                    fb[:, c] = f
                    xs[:, -1] = xb[:, -1] - f.astype(dt)
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
        with np.errstate(over="ignore", invalid="ignore"):
            xa[:, :-2] = 2 * g * Xc
            xa[:, -2] = 1.0
            xa[:, -1] = -g * np.einsum("ij,ij->i", Xc, Xc)
        far = ~np.isfinite(xa).all(axis=1)
        if far.any():
            i = int(np.flatnonzero(far)[0])
            raise InputError(
                f"X: sample {i} lies too far from the training patterns for its kernel "
                f"values to be computed (a feature of {X[i, np.argmax(np.abs(Xc[i]))]:.4g}, "
                f"spread {self.spread_:.4g})"
            )
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
