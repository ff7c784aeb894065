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
from ..features import LapSplit, fourier_features, last_lap, split_laps
from ..geometry import resample_closed

#: Floor of member probabilities before their logarithm is taken.
_P_FLOOR = 1e-4
#: Points of the rebuilt lap outline the elastic member describes.
_ELASTIC_POINTS = 64
#: Scales of a partial arc's length (laps from its turning) tried against the training laps.
_ARC_SCALES = (0.6, 0.7, 0.8, 0.9, 1.0, 1.1, 1.25, 1.4, 1.6, 1.8, 2.0)
#: Full wraps of fewer laps than this are also matched as arcs (they may be partial).
_AMBIGUOUS_LAPS = 1.15
#: A lap counts as closed where the chain runs on past its start for this many
#: links and its end lies within this share of a lap of the point one lap before,
#: or where its end lies within this many links of that point (a chain that
#: closes exactly, with no overlap): a chain short of a lap ends a chord of the
#: missing arc from its start.
_MIN_OVERLAP = 1.5
_CLOSE_GAP = 0.12
_EXACT_GAP = 1.5
#: Training wraps matched elastically per query: the nearest by the lap matcher
#: and by the exact matcher (the elastic matcher re-ranks them).
_ELASTIC_CANDIDATES = (30, 15)
#: Members whose scores the rejection rule reads, in order (indices into
#: ``_closed_members``: the elastic matchers of the averaged and of the last
#: lap); a rule over ``m`` members reads the first ``m``.
REJECT_MEMBERS = (3, 4)


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
    last_scale_: float
    last_heights_: np.ndarray
    last_complexity_: np.ndarray
    owner_: np.ndarray
    headings_: np.ndarray
    arc_labels_: np.ndarray
    scale_: float
    temperature_: float
    partial_scale_: float
    partial_temperature_: float
    partial_reject_distance_: float
    partial_reject_margin_: float
    reject_distance_: float
    reject_margin_: float
    class_spread_: np.ndarray
    reject_coef_: np.ndarray
    reject_threshold_: float

    def _checked_scores(
        self, Xv: FloatArray
    ) -> tuple[FloatArray, np.ndarray, FloatArray, FloatArray]:
        """Scores of checked wraps: class distances, closed flags, laps, unknown-ness.

        Returns the scaled distances to every class (n, n_classes), whether a
        full lap was seen (n,), the laps (n,) and how far each wrap lies past
        the rejection limit (n,): positive for a wrap to answer "unknown".
        """
        Xv = _three_or_more(Xv)
        split = split_laps(Xv, self.n_points)
        k = len(self.classes_)
        out = np.empty((len(Xv), k))
        novelty = np.full(len(Xv), -np.inf)
        closed = split.closed & _closes(Xv, split)
        laps = split.laps.copy()
        if closed.any():
            members = self._closed_members(Xv[closed], split.lap[closed])
            out[closed] = _blend(members, self._weights()) / self.scale_
            novelty[closed] = self._closed_novelty(out[closed], members)
        # barely more than a lap: maybe a partial wrap whose ends happen to meet
        near_one = np.flatnonzero(closed & (laps < _AMBIGUOUS_LAPS))
        if near_one.size:
            heads, turning = _arc_after_approach(
                Xv[near_one], split.offset[near_one], split.direction[near_one], self.n_points
            )
            d = _partial_distances(heads, turning, self.headings_)
            out[near_one] += _class_minima(d, self.arc_labels_, k) / self.partial_scale_
        rows = np.flatnonzero(~closed)
        if rows.size:
            heads = np.cumsum(split.lap[rows], axis=1)
            # a lap split_laps found but the chain does not close: the arc after the approach
            unsure = np.flatnonzero(split.closed[rows])
            if unsure.size:
                r = rows[unsure]
                heads[unsure], laps[r] = _arc_after_approach(
                    Xv[r], split.offset[r], split.direction[r], self.n_points
                )
            d = _partial_distances(heads, laps[rows], self.headings_)
            s = _class_minima(d, self.arc_labels_, k) / self.partial_scale_
            out[rows] = s
            ordered = np.sort(s, axis=1)
            margin = ordered[:, 1] - ordered[:, 0] if k > 1 else np.full(len(s), np.inf)
            novelty[rows] = np.maximum(
                ordered[:, 0] - self.partial_reject_distance_,
                self.partial_reject_margin_ - margin,
            )
        return out, closed, laps, novelty

    def _weights(self) -> FloatArray:
        """The five member weights (models saved before the elastic members weigh them 0)."""
        w = self.weights_
        return np.append(w, np.zeros(5 - len(w)))

    def _rejects(self) -> bool:
        """Whether full wraps are ever answered "unknown" (the rule needs the elastic member)."""
        if hasattr(self, "reject_coef_"):
            return bool(np.isfinite(self.reject_threshold_))
        return bool(np.isfinite(self.reject_distance_) or np.isfinite(self.reject_margin_))

    def _reject_members(self) -> int:
        """How many members (of ``REJECT_MEMBERS``) the fitted rejection rule reads.

        0 without the rule; 1 (the averaged lap's elastic matcher) in models
        saved before the last lap's elastic matcher joined the rule.
        """
        if not (hasattr(self, "reject_coef_") and self._rejects()):
            return 0
        return (len(self.reject_coef_) - 2) // 2

    def _closed_novelty(self, s: FloatArray, members: list[FloatArray | None]) -> FloatArray:
        """How far full wraps lie past the rejection limit (positive: "unknown")."""
        if not self._rejects():
            return np.full(len(s), -np.inf)
        if not hasattr(self, "reject_coef_"):  # models saved before the elastic rule
            ordered = np.sort(s, axis=1)
            margin = ordered[:, 1] - ordered[:, 0] if s.shape[1] > 1 else np.full(len(s), np.inf)
            return np.maximum(ordered[:, 0] - self.reject_distance_, self.reject_margin_ - margin)
        m = self._reject_members()
        used = [members[j] for j in REJECT_MEMBERS[:m]]
        spreads = list(self.class_spread_.reshape(m, -1))
        f = _novelty_features(s, used, spreads)  # type: ignore[arg-type]
        return f @ self.reject_coef_[:-1] + self.reject_coef_[-1] - self.reject_threshold_

    def _closed_members(self, X: FloatArray, laps: FloatArray) -> list[FloatArray | None]:
        """Scaled class scores of each member for wraps with a full lap.

        A member of weight 0 is left out (``None``), except the elastic one
        of the averaged lap where the rejection rule needs it.
        """
        k = len(self.classes_)
        d_lap = np.sqrt(self.matcher_.shift_distances(laps))
        s_lap = _class_minima(d_lap, self.matcher_.labels_, k) / self.lap_scale_
        s_exact = s_spec = s_el = s_last = None
        w = self._weights()
        rule = self._reject_members()
        elastic = w[3] > 0 or rule >= 1
        last_lap_outline = w[4] > 0 or rule >= 2
        if w[1] > 0 or elastic or last_lap_outline:
            last = last_lap(X, self.n_points)[0]
            d_exact = np.sqrt(self.exact_.shift_distances(last))
            s_exact = _class_minima(d_exact, self.exact_.labels_, k) / self.exact_scale_
        if w[2] > 0:
            s_spec = _spectrum_scores(self.spectrum_, _spectrum_features(X), k)
        if elastic or last_lap_outline:
            s_el, s_last = self._elastic_minima(
                laps if elastic else None, last if last_lap_outline else None, d_lap, d_exact
            )
            s_el = None if s_el is None else s_el / self.elastic_scale_
            s_last = None if s_last is None else s_last / self.last_scale_
        return [s_lap, s_exact, s_spec, s_el, s_last]

    def _elastic_minima(
        self,
        laps: FloatArray | None,
        last: FloatArray | None,
        d_lap: FloatArray,
        d_exact: FloatArray,
    ) -> tuple[FloatArray | None, FloatArray | None]:
        """Elastic distances of lap outlines to each class, over candidate training wraps.

        The averaged laps (``laps``) are matched against the training wraps'
        averaged laps, the last laps rebuilt from the joint positions
        (``last``) against theirs (either may be ``None``: not matched). The
        candidates are the training wraps nearest by the lap matcher
        (``d_lap``, over its rows) and by the exact matcher (``d_exact``);
        a class without a candidate scores the query's largest candidate
        distance (it was far by the other matchers).
        """
        ia = _candidates(d_lap, self.owner_, d_exact)
        ib = np.repeat(np.arange(len(d_lap)), [len(c) for c in ia])
        ia_all = np.concatenate(ia) if ia else np.empty(0, np.int64)
        s_el = s_last = None
        if laps is not None:
            s_el = self._elastic_class_minima(
                laps, self.elastic_heights_, self.elastic_complexity_, ia_all, ib
            )
        if last is not None:
            s_last = self._elastic_class_minima(
                last, self.last_heights_, self.last_complexity_, ia_all, ib
            )
        return s_el, s_last

    def _elastic_class_minima(
        self,
        rows: FloatArray,
        heights: np.ndarray,
        complexity: np.ndarray,
        ia: np.ndarray,
        ib: np.ndarray,
    ) -> FloatArray:
        """Per query row, the smallest elastic distance to each class over pairs ``(ia, ib)``."""
        from . import _elastic  # numba: imported only where an elastic member is used

        labels, k = self.exact_.labels_, len(self.classes_)
        F, Fm, c = _elastic.query_descriptors(_lap_outlines(rows))
        d = _elastic.pair_distances(heights, complexity, F, Fm, c, ia, ib)
        out = np.full((len(rows), k), np.inf)
        np.minimum.at(out, (ib, labels[ia]), d)
        finite = np.isfinite(out)
        fill = np.where(finite, out, -np.inf).max(axis=1, initial=-np.inf)
        fill = np.where(np.isfinite(fill), fill, 1.0)
        return np.where(finite, out, fill[:, None])

    def _proba_of(self, s: FloatArray, closed: np.ndarray) -> FloatArray:
        """Calibrated class probabilities from the scores of :meth:`_checked_scores`."""
        t = np.where(closed, self.temperature_, self.partial_temperature_)[:, None]
        return softmax_rows(-s / t)

    def _labels_of(self, s: FloatArray, novelty: FloatArray) -> np.ndarray:
        """Class of each wrap, or ``unknown_label``, from the scores of :meth:`_checked_scores`."""
        pred = self.classes_[np.argmin(s, axis=1)]
        unknown = novelty > 0
        if unknown.any():
            pred = pred.astype(object)
            pred[unknown] = self.unknown_label
        return pred


def _novelty_features(
    s: FloatArray, members: list[FloatArray], spreads: list[FloatArray]
) -> FloatArray:
    """What tells a wrap of an unseen class, per wrap: ratios, each ``log(1 + r)``.

    - the blended score of the nearest class over that of the second nearest
      (near 1: as close to two classes as to one);
    - for each of ``members``: the same for that member alone,
    - then for each member: its distance to the blend's nearest class over
      that class's spread (the typical distance of its training wraps to
      their own class): far from a compact class weighs more than from a
      loose one.

    ``s`` and each member are (n, n_classes) scores, each of ``spreads``
    (n_classes,) or (n, n_classes). Returns (n, 1 + 2 * len(members)).

    Examples
    --------
    >>> import numpy as np
    >>> s = np.array([[1.0, 2.0, 4.0]])
    >>> f = _novelty_features(s, [s], [np.array([0.5, 1.0, 1.0])])
    >>> np.round(np.expm1(f), 3)
    array([[0.5, 0.5, 2. ]])
    """
    rows = np.arange(len(s))
    best = np.argmin(s, axis=1)

    def ratio(a: FloatArray) -> FloatArray:
        if a.shape[1] < 2:
            return np.zeros(len(a))
        o = np.sort(a, axis=1)
        return o[:, 0] / o[:, 1]

    with np.errstate(divide="ignore", invalid="ignore"):
        ratios = [ratio(s)] + [ratio(m) for m in members]
        ratios += [
            m[rows, best] / np.broadcast_to(sp, s.shape)[rows, best]
            for m, sp in zip(members, spreads, strict=True)
        ]
    f = np.stack(ratios, axis=1)
    return np.log1p(np.clip(np.nan_to_num(f, nan=0.0, posinf=1e6), 0.0, 1e6))


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
    matcher's, the spectrum network's, the elastic matcher's of the averaged
    lap and of the last lap (each may be ``None`` where its weight is 0).
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


def _closes(X: FloatArray, split: LapSplit) -> np.ndarray:
    """Whether each wrap's lap (as :func:`~tentaclass.features.split_laps` found it) closes.

    Rebuilds the joints from the angles and compares the chain's end with the
    point one lap (``split.period`` links) before it: see ``_MIN_OVERLAP``,
    ``_CLOSE_GAP`` and ``_EXACT_GAP``. False where no lap was found.
    """
    n = X.shape[1]
    heading = np.cumsum(X * split.direction[:, None], axis=1)
    z = np.concatenate([np.zeros((len(X), 1)), np.cumsum(np.exp(1j * heading), axis=1)], axis=1)
    period = np.where(split.closed, split.period, n)
    x = np.clip(n - period, 0.0, n)
    i = np.minimum(np.floor(x).astype(np.int64), n - 1)[:, None]
    lo, hi = np.take_along_axis(z, i, axis=1)[:, 0], np.take_along_axis(z, i + 1, axis=1)[:, 0]
    gap = np.abs(z[:, -1] - (lo + (x - i[:, 0]) * (hi - lo)))
    overlap = n - split.offset - period
    runs_on = (overlap >= _MIN_OVERLAP) & (gap < _CLOSE_GAP * period)
    return split.closed & (runs_on | (gap < _EXACT_GAP))


def _arc_after_approach(
    X: FloatArray, offset: np.ndarray, direction: np.ndarray, n_points: int
) -> tuple[FloatArray, FloatArray]:
    """Heading functions of the chain after its approach, in ``n_points`` equal steps.

    What :func:`~tentaclass.features.split_laps` gives a partial wrap, for any
    wrap: returns the headings (n, n_points), relative to the first link after
    the approach, and the laps the chain turns through after its approach.
    """
    n = X.shape[1]
    heading = np.cumsum(X * direction[:, None], axis=1)
    a = offset.astype(float)
    x = a[:, None] + (np.arange(n_points + 1) / n_points) * (n - 1 - a)[:, None]
    # linear interpolation of each row at its own points (np.interp, all rows at once)
    i0 = np.clip(np.floor(x).astype(np.int64), 0, n - 2)
    lo = np.take_along_axis(heading, i0, axis=1)
    hi = np.take_along_axis(heading, i0 + 1, axis=1)
    h = lo + (x - i0) * (hi - lo)
    return np.cumsum(np.diff(h, axis=1), axis=1), (h[:, -1] - h[:, 0]) / (2 * np.pi)


def _partial_distances(heads: FloatArray, laps: FloatArray, headings: FloatArray) -> FloatArray:
    """Distances of partial wraps to every training lap: the best stretch, over arc lengths.

    ``heads`` (g, n) are heading functions of partial wraps resampled to
    ``n`` links, ``laps`` (g,) the laps each covers by its turning. The
    turning tells an arc's share of the outline only roughly (a hugging
    chain bridges concavities), so the arc is matched as covering each of
    ``laps * _ARC_SCALES`` of a training lap and the best is kept.
    """
    n = headings.shape[1]
    d = np.full((len(heads), len(headings)), np.inf)
    # (scale, wrap) -> points: an arc's distances depend on its points only, so each
    # wrap is matched once per distinct length, whichever scales round to it
    ms = np.array([[_arc_points(t * f, n) for t in laps] for f in _ARC_SCALES], dtype=np.int64)
    for m in np.unique(ms):
        sel = np.flatnonzero((ms == m).any(axis=0))
        d[sel] = np.minimum(d[sel], _arc_distances(_resample_rows(heads[sel], m), headings))
    return d


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
