"""Nearest neighbour under the best cyclic shift, by FFT cross-correlation."""

from __future__ import annotations

import numpy as np
from sklearn.base import BaseEstimator, ClassifierMixin
from sklearn.utils.multiclass import check_classification_targets
from sklearn.utils.validation import check_is_fitted

from .._dask import DaskMixin
from .._typing import ArrayLike, FloatArray
from .._validation import check_finite_float, check_frequency_count, check_X, check_X_y
from ..errors import InputError
from ..features import canonical_direction, periodic_signal
from ..geometry import angles_to_points, resample_closed

__all__ = ["ShiftNNClassifier"]

#: Upper bound on the correlation block held in memory at once, in bytes.
_BLOCK_BYTES = 64 * 2**20


class ShiftNNClassifier(DaskMixin, ClassifierMixin, BaseEstimator):
    """1-NN whose distance is minimised over cyclic shifts (and mirror images).

    ``d(a, b)^2 = min_s || a - roll(b, s) ||^2`` for periodic signals ``a`` and
    ``b`` of one length: the start point does not matter, but unlike ``|DFT|``
    features the phases between harmonics still do, so shapes whose spectra
    have equal magnitudes are told apart. All shifts are scored at once by a
    circular cross-correlation through the FFT, ``O(n log n)`` per pair.

    Parameters
    ----------
    signal : {"turning", "shape", "raw"}, default="turning"
        ``"turning"``: rows are joint angles; compare their detrended periodic
        turning signals (direction canonicalised). ``"shape"``: rows are joint
        angles of closed one-lap wraps; rebuild the joint polygon (closure
        errors spread evenly over the links, centred, unit size) and compare
        polygons under the best cyclic shift *and rotation* - a Procrustes
        distance over start points. ``"raw"``: rows are already periodic
        signals (e.g. centroid-distance profiles); compare them as they are.
    mirror : bool, default=True
        Also try each training signal reversed in time (a mirror image of the
        outline), and keep the better match.
    center : bool, default=True
        Remove each signal's mean first (a rotation of the object adds a
        constant to the turning signal).
    n_harmonics : int or float, optional
        Compare only frequencies ``1 .. n_harmonics`` (and the mean, unless
        ``center``); default all. A float in (0, 1) keeps that fraction of the
        ``floor(n_points / 2)`` frequencies, so one setting serves chains of any
        length. Chord sampling aliases fine detail into the high frequencies.
    weight_power : float, default=0.0
        Scale frequency ``k`` by ``k ** weight_power`` before comparing. Joint
        noise is white in the angles, so in the turning signal (their running
        sum) it falls like ``1 / k``: a power between 0.5 and 1 with the lowest
        half of the frequencies (``n_harmonics=0.5``) is what held up best on
        taut MPEG-7 wraps with 0.05 rad noise (BENCHMARKS.md).
    closure : {"spread", "chord"}, default="spread"
        How ``signal="shape"`` closes a chain that does not end where it began.
        ``"spread"``: set the total turn to one lap and remove the end-point gap
        linearly along the chain - right when the gap is joint noise, which it
        spreads evenly. ``"chord"``: close the polygon with the straight gap
        from the last joint to the first and resample it to equal arc lengths -
        right for clean encoders on a chain that stopped short of, or ran past,
        its start (the best on clean hugging MPEG-7 wraps, far worse than
        ``"spread"`` with joint noise; BENCHMARKS.md).

    Attributes
    ----------
    classes_ : ndarray of shape (n_classes,)
    n_features_in_ : int

    Examples
    --------
    >>> import numpy as np
    >>> X = np.array([np.sin(np.linspace(0, 2 * np.pi, 16, endpoint=False) * k) for k in (1, 2)])
    >>> clf = ShiftNNClassifier(signal="raw").fit(X, ["one", "two"])
    >>> clf.predict(np.roll(X, 5, axis=1)).tolist()
    ['one', 'two']
    """

    def __init__(
        self,
        signal: str = "turning",
        mirror: bool = True,
        center: bool = True,
        n_harmonics: int | float | None = None,
        weight_power: float = 0.0,
        closure: str = "spread",
    ):
        self.closure = closure
        self.signal = signal
        self.mirror = mirror
        self.center = center
        self.n_harmonics = n_harmonics
        self.weight_power = weight_power

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

    def _frequency_weights(self, n: int, complex_signal: bool) -> FloatArray:
        k = np.abs(np.fft.fftfreq(n, 1.0 / n)) if complex_signal else np.arange(n // 2 + 1)
        w = np.maximum(k, 1.0) ** check_finite_float(self.weight_power, "weight_power")
        if self.n_harmonics is None:
            return w
        h = check_frequency_count(self.n_harmonics, n // 2, "n_harmonics", "floor(n_points / 2)")
        return np.where(k <= h, w, 0.0)

    def fit(self, X: ArrayLike, y: ArrayLike) -> ShiftNNClassifier:
        """Store the training signals' spectra.

        Parameters
        ----------
        X : array_like of shape (n_samples, n_points)
        y : array_like of shape (n_samples,)

        Returns
        -------
        self : ShiftNNClassifier
        """
        if self.signal not in ("turning", "shape", "raw"):
            raise InputError(f"signal must be 'turning', 'shape' or 'raw', got {self.signal!r}")
        if self.closure not in ("spread", "chord"):
            raise InputError(f"closure must be 'spread' or 'chord', got {self.closure!r}")
        for name in ("mirror", "center"):
            if not isinstance(getattr(self, name), bool | np.bool_):
                raise InputError(f"{name} must be True or False, got {getattr(self, name)!r}")
        X, y = check_X_y(self, X, y, dtype=np.float64)
        least = 3 if (self.signal == "shape" and self.closure == "chord") else 2
        if self.signal != "raw" and X.shape[1] < least:
            raise InputError(
                f"signal={self.signal!r} needs at least {least} joint angles, "
                f"got {X.shape[1]} feature(s)"
            )
        check_classification_targets(y)
        self.classes_, self.labels_ = np.unique(y, return_inverse=True)
        s = self._signals(X)
        self.weights_ = self._frequency_weights(X.shape[1], np.iscomplexobj(s))
        self.spectra_, self.norms_ = self._spectrum(s)
        return self

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

    def shift_distances(self, X: ArrayLike) -> FloatArray:
        """Squared shift-invariant distances to every training signal.

        Parameters
        ----------
        X : array_like of shape (n_queries, n_points)

        Returns
        -------
        d2 : ndarray of shape (n_queries, n_train)
        """
        check_is_fitted(self)
        X = check_X(self, X, dtype=np.float64, reset=False)
        s = self._signals(X)
        spec, sq = self._spectrum(s)
        return self._dense_distances(spec, sq, s.shape[1])

    def _dense_distances(self, spec: np.ndarray, sq: FloatArray, n: int) -> FloatArray:
        """:meth:`shift_distances` from the queries' weighted spectra and squared norms."""
        # corr_b(shift) = sum_j a_j b_{j-shift}: spectrum A * conj(B);
        # the time-reversed b has spectrum conj(B) (up to a shift), so A * B.
        best = self._best_correlation(spec, n, conj_train=True)
        if self.mirror:
            np.maximum(best, self._best_correlation(spec, n, conj_train=False), out=best)
        return np.maximum(sq[:, None] + self.norms_[None, :] - 2 * best, 0.0)

    def predict(self, X: ArrayLike) -> np.ndarray:
        """Class of the nearest training signal, shape (n_queries,).

        The same as the class at ``argmin(shift_distances(X), axis=1)``, but
        the exact distance (an inverse FFT per training signal) is computed
        only for the training signals a lower bound cannot rule out: the
        distance between the magnitude spectra, which no shift, mirror image
        or rotation changes, bounds the shift distance from below.
        """
        check_is_fitted(self)
        X = check_X(self, X, dtype=np.float64, reset=False)
        return self.classes_[self.labels_[self._nearest(X)]]

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
