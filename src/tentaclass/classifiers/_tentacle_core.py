"""The prediction of a fitted TentacleClassifier, free of scikit-learn.

:class:`~tentaclass.classifiers.TentacleClassifier` inherits it (and fits
with the helpers below); a model file is evaluated with it without importing
scikit-learn (:mod:`tentaclass.io._light`).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from threadpoolctl import threadpool_limits

from .._typing import FloatArray
from ..features import fourier_features, last_lap, split_laps
from ..geometry import resample_closed

#: Floor of member probabilities before their logarithm is taken.
_P_FLOOR = 1e-4
#: Points of the rebuilt lap outline the elastic member describes.
_ELASTIC_POINTS = 64
#: Training wraps matched elastically per query: the nearest by the lap matcher
#: and by the exact matcher (the elastic matcher re-ranks them).
_ELASTIC_CANDIDATES = (30, 15)


class TentacleCore:
    """Blended class scores, probabilities and labels from the fitted members."""

    n_points: int
    unknown_label: str
    classes_: np.ndarray
    matcher_: Any
    exact_: Any
    spectrum_: Any
    weights_: np.ndarray
    lap_scale_: float
    exact_scale_: float
    elastic_scale_: float
    elastic_heights_: np.ndarray
    elastic_complexity_: np.ndarray
    owner_: np.ndarray
    headings_: np.ndarray
    arc_labels_: np.ndarray
    scale_: float
    temperature_: float
    partial_scale_: float
    partial_temperature_: float
    reject_distance_: float
    reject_margin_: float
    partial_reject_distance_: float
    partial_reject_margin_: float

    def _checked_scores(self, Xv: FloatArray) -> tuple[FloatArray, np.ndarray, FloatArray]:
        """Scaled class distances (n, n_classes), closed flags (n,), laps (n,) of checked wraps."""
        Xv = _three_or_more(Xv)
        split = split_laps(Xv, self.n_points)
        k = len(self.classes_)
        out = np.empty((len(Xv), k))
        closed = split.closed
        if closed.any():
            out[closed] = self._closed_scores(Xv[closed], split.lap[closed]) / self.scale_
        rows = np.flatnonzero(~closed)
        if rows.size:
            heads = np.cumsum(split.lap[rows], axis=1)
            ms = np.array([_arc_points(split.laps[r], self.n_points) for r in rows])
            d = np.empty((rows.size, len(self.headings_)))
            for m in np.unique(ms):
                sel = np.flatnonzero(ms == m)
                d[sel] = _arc_distances(_resample_rows(heads[sel], m), self.headings_)
            out[rows] = _class_minima(d, self.arc_labels_, k) / self.partial_scale_
        return out, closed, split.laps

    def _closed_scores(self, X: FloatArray, laps: FloatArray) -> FloatArray:
        """Blended member scores of wraps with a full lap, before the final scale."""
        k = len(self.classes_)
        d_lap = np.sqrt(self.matcher_.shift_distances(laps))
        s_lap = _class_minima(d_lap, self.matcher_.labels_, k) / self.lap_scale_
        s_exact = s_spec = s_el = None
        w = self.weights_
        if len(w) == 3:  # saved before the elastic member: three members
            w = np.append(w, 0.0)
        if w[1] > 0 or w[3] > 0:
            d_exact = np.sqrt(self.exact_.shift_distances(last_lap(X, self.n_points)[0]))
            s_exact = _class_minima(d_exact, self.exact_.labels_, k) / self.exact_scale_
        if w[2] > 0:
            s_spec = _spectrum_scores(self.spectrum_, _spectrum_features(X), k)
        if w[3] > 0:
            s_el = self._elastic_minima(laps, d_lap, d_exact) / self.elastic_scale_
        return _blend([s_lap, s_exact, s_spec, s_el], w)

    def _elastic_minima(
        self, laps: FloatArray, d_lap: FloatArray, d_exact: FloatArray
    ) -> FloatArray:
        """Elastic distance of each lap outline to each class, over candidate training wraps.

        The candidates are the training wraps nearest by the lap matcher
        (``d_lap``, over its rows) and by the exact matcher (``d_exact``);
        a class without a candidate scores the query's largest candidate
        distance (it was far by the other matchers).
        """
        from . import _elastic  # numba: imported only where the elastic member is used

        labels, k = self.exact_.labels_, len(self.classes_)
        ia = _candidates(d_lap, self.owner_, d_exact)
        ib = np.repeat(np.arange(len(laps)), [len(c) for c in ia])
        ia_all = np.concatenate(ia) if ia else np.empty(0, np.int64)
        F, Fm, c = _elastic.query_descriptors(_lap_outlines(laps))
        d = _elastic.pair_distances(
            self.elastic_heights_, self.elastic_complexity_, F, Fm, c, ia_all, ib
        )
        out = np.full((len(laps), k), np.inf)
        np.minimum.at(out, (ib, labels[ia_all]), d)
        finite = np.isfinite(out)
        fill = np.where(finite, out, -np.inf).max(axis=1, initial=-np.inf)
        fill = np.where(np.isfinite(fill), fill, 1.0)
        return np.where(finite, out, fill[:, None])

    def _proba_of(self, s: FloatArray, closed: np.ndarray) -> FloatArray:
        """Calibrated class probabilities from the scores of :meth:`_checked_scores`."""
        t = np.where(closed, self.temperature_, self.partial_temperature_)[:, None]
        return softmax_rows(-s / t)

    def _labels_of(self, s: FloatArray, closed: np.ndarray) -> np.ndarray:
        """Class of each wrap, or ``unknown_label``, from the scores of :meth:`_checked_scores`."""
        pred = self.classes_[np.argmin(s, axis=1)]
        far = np.where(closed, self.reject_distance_, self.partial_reject_distance_)
        near = np.where(closed, self.reject_margin_, self.partial_reject_margin_)
        ordered = np.sort(s, axis=1)
        margin = ordered[:, 1] - ordered[:, 0] if s.shape[1] > 1 else np.full(len(s), np.inf)
        unknown = (ordered[:, 0] > far) | (margin < near)
        if unknown.any():
            pred = pred.astype(object)
            pred[unknown] = self.unknown_label
        return pred


def softmax_rows(a: FloatArray) -> FloatArray:
    """``scipy.special.softmax(a, axis=1)``: the same operations, without importing scipy."""
    e = np.exp(a - np.max(a, axis=1, keepdims=True))
    return e / np.sum(e, axis=1, keepdims=True)


def _three_or_more(X: FloatArray) -> FloatArray:
    """Arrays of fewer than 3 joints (no outline) get each turn split over 3 joints."""
    return np.repeat(X, 3, axis=1) / 3 if X.shape[1] < 3 else X


def _lap_outlines(laps: FloatArray) -> FloatArray:
    """Laps (n, n_points) rebuilt as polygons of equal links, resampled for the elastic matcher.

    Joint ``j`` of a lap sits at the sum of the unit links before it, each
    turned by the turns so far: the outline the chain lay on (a partial lap is
    closed by its chord).
    """
    from . import _elastic

    z = np.cumsum(np.exp(1j * np.cumsum(laps, axis=1)), axis=1)
    points = np.stack([z.real, z.imag], axis=-1)
    return resample_closed(points, _ELASTIC_POINTS * _elastic.DENSE)


def _candidates(d_rows: FloatArray, owner: np.ndarray, d_wraps: FloatArray) -> list[np.ndarray]:
    """Per query, the training wraps nearest by the lap matcher and by the exact matcher.

    ``d_rows`` (n, n_rows) are lap-matcher distances to its rows (a training
    wrap may own several: one-lap views), ``d_wraps`` (n, n_wraps) exact
    distances; infinite distances (excluded pairs) never make a candidate.
    """
    n_lap, n_exact = _ELASTIC_CANDIDATES
    out = []
    for dr, dw in zip(d_rows, d_wraps, strict=True):
        rows = np.argsort(dr)[: 4 * n_lap]
        rows = rows[np.isfinite(dr[rows])]
        owners = owner[rows]
        _, first = np.unique(owners, return_index=True)
        near = owners[np.sort(first)][:n_lap]
        wraps = np.argsort(dw)[:n_exact]
        out.append(np.union1d(near, wraps[np.isfinite(dw[wraps])]).astype(np.int64))
    return out


def _spectrum_features(X: FloatArray) -> FloatArray:
    """``|DFT|`` of the last lap (detrended) next to ``|DFT|`` of the whole array.

    The whole array sees part of the object a second time from other joint
    positions: with few links per lap its spectrum tells corners the last lap
    cuts (a square from a circle).
    """
    lap = last_lap(X)[0]
    return np.hstack([fourier_features(lap, detrend=True), np.abs(np.fft.rfft(X, axis=1))])


def _spectrum_scores(model: Any, features: FloatArray, n_classes: int) -> FloatArray:
    """Negative log probabilities of the spectrum member, (n, n_classes)."""
    p = np.full((len(features), n_classes), 0.0)
    with threadpool_limits(1, user_api="blas"):
        p[:, model.classes_] = model.predict_proba(features)
    return -np.log(np.maximum(p, _P_FLOOR))


def _blend(members: list[FloatArray | None], weights: FloatArray) -> FloatArray:
    """Weighted sum of the members' class scores (members of weight 0 left out).

    ``members``: the lap matcher's scores (always there), then the exact
    matcher's, the spectrum network's and the elastic matcher's (each may be
    ``None`` where its weight is 0).
    """
    out = weights[0] * members[0]
    for w, s in zip(weights[1:], members[1:], strict=True):
        if w > 0 and s is not None:
            out = out + w * s
    return out


def _class_minima(d: FloatArray, labels: np.ndarray, n_classes: int) -> FloatArray:
    """Per query, the smallest distance to each class (inf where a class has none)."""
    out = np.full((len(d), n_classes), np.inf)
    for c in range(n_classes):
        cols = labels == c
        if cols.any():
            out[:, c] = d[:, cols].min(axis=1)
    return out


def _arc_points(laps: float, n_points: int) -> int:
    """Points of the averaged lap a partial arc of ``laps`` laps covers."""
    return int(np.clip(np.rint(laps * n_points), 3, n_points))


def _resample_rows(h: FloatArray, m: int) -> FloatArray:
    """Rows sampled at the centres of ``n`` equal cells, resampled to ``m`` cells."""
    n = h.shape[1]
    x_old = (np.arange(n) + 0.5) / n
    x_new = (np.arange(m) + 0.5) / m
    return np.array([np.interp(x_new, x_old, row) for row in h])


def _arc_distances(arc: FloatArray, heads: FloatArray, chunk: int = 8) -> FloatArray:
    """RMS heading distance of arcs to the best stretch of each training lap.

    ``arc`` (g, m) heading functions of partial wraps, ``heads`` (t, n) of
    closed laps (one turn each). Each arc is compared with the ``m``
    consecutive samples from every start ``k`` of every lap (one turn added
    past the end), up to a constant (the object's rotation); all starts at
    once by FFT cross-correlation.
    """
    g, m = arc.shape
    t, n = heads.shape
    ext = np.concatenate([heads, heads[:, :m] + 2 * np.pi], axis=1)  # (t, n + m)
    length = n + m
    c1 = np.concatenate([np.zeros((t, 1)), np.cumsum(ext, axis=1)], axis=1)
    c2 = np.concatenate([np.zeros((t, 1)), np.cumsum(ext**2, axis=1)], axis=1)
    wsum = c1[:, m : m + n] - c1[:, :n]
    wnorm = (c2[:, m : m + n] - c2[:, :n]) - wsum**2 / m  # (t, n): centred window norms
    a = arc - arc.mean(axis=1, keepdims=True)
    anorm = np.sum(a**2, axis=1)
    spec = np.fft.rfft(ext, length, axis=1)
    out = np.empty((g, t))
    for lo in range(0, g, chunk):
        fa = np.conj(np.fft.rfft(a[lo : lo + chunk], length, axis=1))
        corr = np.fft.irfft(spec[None] * fa[:, None], length, axis=2)[:, :, :n]
        d2 = anorm[lo : lo + chunk, None, None] + wnorm[None] - 2 * corr
        out[lo : lo + chunk] = np.sqrt(np.maximum(d2.min(axis=2), 0.0) / m)
    return out
