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
  tile's maximum. Each tile, once out of the product, is read once by a
  compiled kernel (:mod:`tentaclass.classifiers._pnn_kernel`) that
  exponentiates and sums each row in place of NumPy's ``exp`` (one value at
  a time in float64 on CPUs without AVX-512) and a matrix-vector product
  with ones. The rare row whose tile sum overflows its frame (a near pattern
  after far ones) is re-framed on that tile's maximum;
- row blocks are spread over threads (numpy and BLAS release the GIL), with
  BLAS itself limited to one thread inside the workers; as many threads as
  CPUs, but no more than BLAS may use (``threadpoolctl.threadpool_limits``
  on BLAS limits the PNN too);
- ``dtype="float32"`` halves the memory traffic and doubles the SIMD width
  of the product and of ``exp``, whose results are kept normal numbers
  (subnormal ones are slow on x86); sums are float64 in either dtype;
- small batches (up to ``_WHOLE_MAX`` kernel values) take NumPy's ``exp``
  for all classes at once, without loading numba; their scores agree with
  the tiled pass's to a few ulp.

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

#: Target size of one kernel tile, in bytes: small enough to stay in a core's
#: L2 cache between the product and the compiled ``exp`` and sum.
_TILE_BYTES = 2**20

#: Most pattern columns in one tile (a tile never spans two classes).
_TILE_COLS = 1024

#: Per dtype of the ``exp``: a class whose first tile reaches a log-kernel
#: value above this is summed with no shift, and tile sums above ``_SUM_BIG``
#: are redone with a shift. ``exp`` clamps its argument where its results
#: would leave the normal numbers (at -708 in float64, -87 in float32): values
#: there add at most ``exp(-47)`` times a class sum per kernel value.
_FRAME_LOW = {np.float64: -600.0, np.float32: -40.0}
_SUM_BIG = {np.float64: 1e300, np.float32: 1e30}

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
        Later tiles thus need no shift of their own; a row whose tile sum
        overflows the frame (a near pattern after far ones) is re-framed on
        that tile's maximum. Exponentials and sums are taken in float64
        whatever the dtype of the product.
        """
        n, n_classes = xa.shape[0], self.classes_.size
        if n * self._pt.shape[1] <= _WHOLE_MAX and len(tiles) == n_classes:
            whole = self._log_sums_whole(xa)
            if whole is not None:
                return whole
        from ._pnn_kernel import framed_exp_sums  # numba: large predictions only

        pt = self._pt
        low, big = _FRAME_LOW[xa.dtype.type], _SUM_BIG[xa.dtype.type]
        frame = np.zeros((n_classes, n))
        s = np.zeros((n_classes, n))
        width = max(b - a for _, a, b in tiles)
        buf = np.empty(min(rows, n) * width, dtype=xa.dtype)
        for lo in range(0, n, rows):
            xb = xa[lo : lo + rows]
            current = -1
            for c, a, b in tiles:
                t = buf[: xb.shape[0] * (b - a)].reshape(xb.shape[0], b - a)
                np.matmul(xb, pt[:, a:b], out=t)
                first = c != current
                current = c
                fb, sb = frame[c, lo : lo + rows], s[c, lo : lo + rows]
                framed_exp_sums(t, fb, sb, first, low, big)
        return (frame + np.log(s)).T

    def _log_sums_whole(self, xa: np.ndarray) -> FloatArray | None:
        """:meth:`_log_sums` of a small batch when every class is one tile, with NumPy.

        One ``exp``, one maximum and one frame pass for all classes at once
        (which matters for small batches); None when a class's sum overflows
        its frame (then the tiled pass redoes it). The values agree with the
        tiled pass's to a few ulp (its ``exp`` and sums are compiled ones).
        """
        bounds, pt = self._bounds, self._pt
        t = np.empty((xa.shape[0], pt.shape[1]), dtype=xa.dtype)
        edges = list(itertools.pairwise(bounds.tolist()))
        for a, b in edges:  # per class, as the tiles are (the sums of products follow the shape)
            t[:, a:b] = xa @ pt[:, a:b]
        t64 = t.astype(np.float64, copy=False)
        m0 = np.maximum.reduceat(t64, bounds[:-1], axis=1)
        frame = np.where(m0 > _FRAME_LOW[np.float64], 0.0, m0)
        if frame.any():
            t64 -= np.repeat(frame, self.class_count_, axis=1)
        with np.errstate(over="ignore"):
            np.exp(t64, out=t64)
            ones = np.ones(int(self.class_count_.max()))
            s = np.empty(frame.shape)
            for c, (a, b) in enumerate(edges):
                # contiguous, as a tile is (BLAS's sums may follow the layout)
                s[:, c] = np.ascontiguousarray(t64[:, a:b]) @ ones[: b - a]
        if not (s <= _SUM_BIG[np.float64]).all():
            return None
        return frame + np.log(s)

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
