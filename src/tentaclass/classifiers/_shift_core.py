"""Shift-invariant distances of a fitted shift 1-NN, free of scikit-learn.

:class:`~tentaclass.classifiers.ShiftNNClassifier` inherits them; a model
file is evaluated with them without importing scikit-learn
(:mod:`tentaclass.io._light`).
"""

from __future__ import annotations

import numpy as np

from .._typing import FloatArray
from ..features import canonical_direction, periodic_signal
from ..geometry import angles_to_points, resample_closed

#: Upper bound on the correlation block held in memory at once, in bytes.
_BLOCK_BYTES = 64 * 2**20


class ShiftCore:
    """Distances to the training signals (``spectra_``, ``norms_``, ``weights_``)."""

    signal: str
    mirror: bool
    center: bool
    closure: str
    weights_: np.ndarray
    spectra_: np.ndarray
    norms_: np.ndarray

    def _signals(self, X: FloatArray) -> np.ndarray:
        if self.signal == "turning":
            s = periodic_signal(canonical_direction(X), detrend=True)
        elif self.signal == "shape":
            return _closed_polygon(X, self.closure)
        else:
            s = X
        if self.center:
            s = s - s.mean(axis=1, keepdims=True)
        return s

    def _spectrum(self, s: np.ndarray) -> tuple[np.ndarray, FloatArray]:
        """Weighted spectra of the signals and the squared norms of what they describe."""
        n = s.shape[1]
        spec = np.fft.fft(s, axis=1) if np.iscomplexobj(s) else np.fft.rfft(s, axis=1)
        spec = spec * self.weights_
        power = np.abs(spec) ** 2
        if not np.iscomplexobj(s):  # rfft holds each frequency but 0 and n/2 once
            power[:, 1 : (n + 1) // 2] *= 2
        return spec, power.sum(axis=1) / n

    def _shift_distances(self, X: FloatArray) -> FloatArray:
        """Squared shift-invariant distances of checked queries (n_queries, n_train)."""
        s = self._signals(X)
        spec, sq = self._spectrum(s)
        return self._dense_distances(spec, sq, s.shape[1])

    def _best_correlation(self, spec_q: np.ndarray, n: int, conj_train: bool) -> FloatArray:
        """Max over shifts of the circular cross-correlation, (n_query, n_train)."""
        train = np.conj(self.spectra_) if conj_train else self.spectra_
        rows = max(1, _BLOCK_BYTES // (16 * max(1, train.size)))
        out = np.empty((spec_q.shape[0], train.shape[0]))
        complex_signal = self.signal == "shape"
        for lo in range(0, spec_q.shape[0], rows):
            prod = spec_q[lo : lo + rows, None, :] * train[None, :, :]
            if complex_signal:  # |correlation|: the best rotation for each shift
                corr = np.abs(np.fft.ifft(prod, axis=-1))
            else:
                corr = np.fft.irfft(prod, n=n, axis=-1)
            out[lo : lo + rows] = corr.max(axis=-1)
        return out

    def _dense_distances(self, spec: np.ndarray, sq: FloatArray, n: int) -> FloatArray:
        """:meth:`shift_distances` from the queries' weighted spectra and squared norms."""
        # corr_b(shift) = sum_j a_j b_{j-shift}: spectrum A * conj(B);
        # the time-reversed b has spectrum conj(B) (up to a shift), so A * B.
        best = self._best_correlation(spec, n, conj_train=True)
        if self.mirror:
            np.maximum(best, self._best_correlation(spec, n, conj_train=False), out=best)
        return np.maximum(sq[:, None] + self.norms_[None, :] - 2 * best, 0.0)

    def _pair_distances(
        self, spec: np.ndarray, sq: FloatArray, qi: np.ndarray, ti: np.ndarray, n: int
    ) -> FloatArray:
        """Squared shift distances of the pairs (query ``qi``, training signal ``ti``)."""
        out = np.empty(qi.size)
        rows = max(1, _BLOCK_BYTES // (16 * spec.shape[1]))
        complex_signal = self.signal == "shape"
        for lo in range(0, qi.size, rows):
            q, t = spec[qi[lo : lo + rows]], self.spectra_[ti[lo : lo + rows]]
            best = None
            for train in (np.conj(t), t) if self.mirror else (np.conj(t),):
                prod = q * train
                if complex_signal:
                    corr = np.abs(np.fft.ifft(prod, axis=-1)).max(axis=-1)
                else:
                    corr = np.fft.irfft(prod, n=n, axis=-1).max(axis=-1)
                best = corr if best is None else np.maximum(best, corr)
            sl = slice(lo, lo + rows)
            assert best is not None  # at least one view was scored
            out[sl] = np.maximum(sq[qi[sl]] + self.norms_[ti[sl]] - 2 * best, 0.0)
        return out

    def _nearest(self, X: FloatArray) -> np.ndarray:
        """Index of the nearest training signal of each query (first of equals)."""
        s = self._signals(X)
        n = s.shape[1]
        spec, sq = self._spectrum(s)
        c = np.ones(spec.shape[1])
        if not np.iscomplexobj(s):
            c[1 : (n + 1) // 2] = 2.0  # as in _spectrum: rfft holds these frequencies once
        # sum_k c_k (|A_k| - |B_k|)^2 / n <= the distance under any shift (and
        # mirror, rotation); a margin covers the rounding of both sides
        lower = sq[:, None] + self.norms_[None, :]
        margin = 1e-9 * lower + 1e-300
        lower -= (2.0 / n) * ((np.abs(spec) * c) @ np.abs(self.spectra_).T)
        lower -= margin
        n_q, n_t = lower.shape
        best = np.full(n_q, np.inf)
        arg = np.zeros(n_q, dtype=np.int64)
        done = np.zeros((n_q, n_t), dtype=bool)
        # the most promising first (by the bound: 4, then 28 more), then whatever
        # the best so far cannot rule out
        ranks = [(0, 4), (4, 32)] if n_t > 32 else []
        if ranks:
            order = np.argpartition(lower, 31, axis=1)[:, :32]
            order = np.take_along_axis(
                order, np.argsort(np.take_along_axis(lower, order, axis=1), axis=1), axis=1
            )
        while True:
            if ranks:
                a, b = ranks.pop(0)
                cand = order[:, a:b]
                keep = lower[np.arange(n_q)[:, None], cand] <= best[:, None]
                qi, ti = np.nonzero(keep)
                ti = cand[qi, ti]
                if qi.size == 0:
                    continue
            else:
                pending = ~done & (lower <= best[:, None])
                # a query the bound helps little with: all its distances at once
                dense = np.flatnonzero(pending.sum(axis=1) > n_t // 4)
                if dense.size:
                    d2 = self._dense_distances(spec[dense], sq[dense], n)
                    arg[dense], best[dense] = np.argmin(d2, axis=1), -np.inf  # settled
                    pending[dense] = False
                qi, ti = np.nonzero(pending)
                if qi.size == 0:
                    return arg
            done[qi, ti] = True
            d2 = self._pair_distances(spec, sq, qi, ti, n)
            # per query: the smallest distance, the first index among equals
            by = np.lexsort((ti, d2, qi))
            qi, ti, d2 = qi[by], ti[by], d2[by]
            head = np.r_[True, qi[1:] != qi[:-1]]
            q, t, d = qi[head], ti[head], d2[head]
            better = (d < best[q]) | ((d == best[q]) & (t < arg[q]))
            best[q[better]], arg[q[better]] = d[better], t[better]


def _closed_polygon(q: FloatArray, closure: str = "spread") -> np.ndarray:
    """Joint polygon of one-lap wraps as complex points, closed, centred, unit norm.

    ``"spread"``: joint noise makes the rebuilt chain miss its start in heading
    and in position; both misses are spread evenly over the links (the turn is
    set to exactly one lap, then the end-point gap is removed linearly), so
    noise does not pile up at the end of the chain. ``"chord"``: the polygon is
    closed by the straight gap back to the first joint and resampled to equal
    arc lengths.
    """
    q = canonical_direction(q)
    n = q.shape[1]
    if closure == "chord":
        p = resample_closed(angles_to_points(q), n)
    else:
        q = q + (2 * np.pi - q.sum(axis=1, keepdims=True)) / n
        p = angles_to_points(q)
        p = p - (np.arange(n + 1) / n)[None, :, None] * (p[:, -1:] - p[:, :1])
        p = p[:, :-1]
    z = p[..., 0] + 1j * p[..., 1]
    z = z - z.mean(axis=1, keepdims=True)
    norm = np.linalg.norm(z, axis=1, keepdims=True)
    return z / np.where(norm > 0, norm, 1.0)
