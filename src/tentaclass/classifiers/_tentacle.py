"""The default recogniser: any wrap of a fixed chain -> object class, or "unknown"."""

from __future__ import annotations

import itertools
import numbers
import warnings
from typing import Any

import numpy as np
from scipy.optimize import minimize_scalar
from sklearn.base import BaseEstimator, ClassifierMixin
from sklearn.exceptions import ConvergenceWarning
from sklearn.model_selection import GroupKFold
from sklearn.neural_network import MLPClassifier
from sklearn.pipeline import Pipeline, make_pipeline
from sklearn.preprocessing import StandardScaler
from threadpoolctl import threadpool_limits

from .._dask import DaskMixin
from .._typing import ArrayLike, FloatArray
from .._validation import (
    check_fitted_X,
    check_positive_int,
    check_unknown_label,
    check_X_y,
    class_indices,
)
from ..errors import InputError
from ..features import LapSplit, last_lap, split_laps
from . import _elastic
from ._shift_nn import ShiftNNClassifier
from ._tentacle_core import (
    REJECT_MEMBERS,
    TentacleCore,
    _arc_points,
    _blend,
    _class_minima,
    _lap_outlines,
    _novelty_features,
    _partial_distances,
    _resample_rows,
    _spectrum_features,
    _spectrum_scores,
    _three_or_more,
)

__all__ = ["TentacleClassifier"]

#: Training wraps used as held-out queries to weigh the members and calibrate.
_CALIBRATION_QUERIES = 300
#: Calibration queries when rejecting (the rejection limit is a tail quantile).
_REJECT_QUERIES = 1000
#: Pseudo-count pulling a class's spread towards the median over classes.
_SPREAD_PRIOR = 3.0
#: Windows of one lap cut from each training wrap of more than one lap (extra views).
_VIEWS = 2
#: Weights tried for the exact-lap and the spectrum member (the lap matcher weighs 1).
_WEIGHTS = (0.0, 0.25, 0.5, 1.0, 2.0)
#: Weights tried for the elastic outline member.
_ELASTIC_WEIGHTS = (0.0, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0)
#: Folds (over objects) giving the spectrum member's held-out probabilities.
_INNER_FOLDS = 3
#: The spectrum member needs this many training wraps per class (else it is left out).
_SPECTRUM_MIN_PER_CLASS = 4
#: Partial arcs cut from training laps to calibrate the partial-wrap matcher.
_PARTIAL_QUERIES = 100


class TentacleClassifier(TentacleCore, DaskMixin, ClassifierMixin, BaseEstimator):
    """Object class from the joint angles of any wrap of a chain of equal links.

    The chain may stand off the object (approach links), wrap it partly, once
    or several times, clockwise or counter-clockwise, from any start point,
    with noisy encoders. From the angles alone the classifier finds the
    approach and the length of one lap (:func:`tentaclass.features.split_laps`)
    and averages every lap it sees into one (joint noise falls with the number
    of laps). Five members score every class:

    - the averaged lap against every training lap by the Procrustes distance
      of the rebuilt outlines, minimised over start point, rotation and mirror
      image, on the lowest half of the frequencies weighted by frequency
      (:class:`ShiftNNClassifier` with ``signal="shape"``): what held best from
      clean to 0.05 rad of joint noise. Training wraps of more than one lap
      add windows of exactly one lap cut at other points of the chain (other
      joint positions on the same outline);
    - the last lap rebuilt from the joint positions
      (:func:`tentaclass.features.last_lap`), matched on every frequency: the
      sharpest with clean encoders;
    - ``|DFT|`` of the last lap and of the whole array, classified by a small
      neural network (the whole array resolves corners that a lap of few links
      cuts);
    - the averaged lap rebuilt by forward kinematics as a closed outline and
      matched *elastically* (height functions aligned by dynamic programming,
      as :func:`tentaclass.shape_distances` matches outlines) against the
      outlines of the training wraps nearest by the two matchers above (30 by
      the lap matcher, 15 by the exact one): legs, necks and bridged slots
      that bend from one object of a class to the next still line up. The
      strongest member on MPEG-7 wraps;
    - the last lap rebuilt from the joint positions, matched elastically
      against the training wraps' last laps over the same candidates. The
      averaged lap is resampled from the headings of every lap, which rounds
      corners; the last lap keeps the joints where the chain laid them.

    The scores (distances to each class's nearest training wrap, scaled, and
    the network's negative log probabilities) are summed with weights chosen
    on held-out training wraps (leave-one-object-out for the matchers, 3-fold
    cross-validation over objects for the network): fewest errors, then least
    log loss. A wrap of less than one lap is matched as an arc against every
    stretch of every training lap, as covering 0.6-2 times the share of a
    lap its turning tells (a hugging chain bridges concavities, so turning
    and length disagree), the best kept. A wrap of barely more than one lap
    (under 1.15 by its turning) may be a partial one whose ends happen to
    meet: the arc matcher's scores are added to the blend's.

    Probabilities are a softmax of the blended scores, with a temperature
    fitted on the same held-out wraps (and on partial arcs cut from them, for
    partial wraps).

    Parameters
    ----------
    n_points : int, default=64
        Links of the averaged lap every wrap is resampled to.
    reject : bool or float, default=False
        Open set: the fraction of objects of known classes that may be
        answered ``unknown_label`` (``True``: 0.05; ``False``: never reject).
        A wrap is rejected when it looks more like an object of a class
        never trained on than all but that fraction of held-out training
        wraps do: as close to its second class as to its first (blended and
        by each elastic matcher), or far from its class for how compact the
        class is (see ``reject_coef_``). The rule is learnt from held-out training wraps
        (up to 1000), each scored as it is and with its own class taken out
        (then it is an object of an unseen class), and its limit is the
        quantile of the known ones at the requested fraction. Partial wraps
        are rejected by the arc distance to the nearest class or the margin to
        the second (each half of the fraction).
    unknown_label : str, default="unknown"
        The answer for rejected wraps.

    Attributes
    ----------
    classes_ : ndarray of shape (n_classes,)
    n_features_in_ : int
        Joint angles per array seen in ``fit``.
    matcher_ : ShiftNNClassifier
        The shape matcher, fitted on the averaged training laps and the extra
        one-lap windows.
    exact_ : ShiftNNClassifier
        The matcher of last laps rebuilt from joint positions.
    spectrum_ : Pipeline or None
        The spectrum network (``None`` with fewer than four training wraps in
        some class).
    weights_ : ndarray of shape (5,)
        Weights of the five members in the blend: lap matcher (1), exact
        matcher, spectrum network, elastic matcher of the averaged lap and
        of the last lap.
    lap_scale_, exact_scale_, elastic_scale_, last_scale_ : float
        Median held-out nearest distance of each matcher: its distances are
        divided by it before blending.
    elastic_heights_ : ndarray of shape (n_samples, 64, 20), float32
        Height descriptors of the training wraps' lap outlines (no rows when
        the elastic member's weight is 0).
    elastic_complexity_ : ndarray of shape (n_samples,)
        Their complexities (the elastic distance is divided by the sum of the
        two outlines' complexities).
    last_heights_, last_complexity_ : ndarray
        The same for the training wraps' last laps (no rows when the last-lap
        elastic member's weight is 0).
    owner_ : ndarray of shape (n_rows,)
        Training wrap of each row of the lap matcher.
    headings_ : ndarray of shape (n_arcs, n_points)
        Heading functions of the closed training laps (and their mirror
        images), for partial wraps.
    arc_labels_ : ndarray of shape (n_arcs,)
        Class index of each row of ``headings_``.
    scale_ : float
        Median held-out score of the nearest class: blended scores are
        divided by it.
    temperature_ : float
        Softmax temperature of full wraps (on scaled distances).
    partial_scale_, partial_temperature_ : float
        The same for partial wraps.
    class_spread_ : ndarray of shape (2 * n_classes,)
        Typical held-out distance of each class's wraps to their own class,
        by the elastic matcher of the averaged lap, then by that of the last
        lap (empty without ``reject``; models saved before the last lap's
        matcher joined the rule hold the first half only).
    reject_coef_ : ndarray of shape (6,)
        Weights of the five rejection features
        (``tentaclass.classifiers._tentacle_core._novelty_features``: the
        ratio of the nearest to the second nearest class of the blend and of
        each elastic matcher, each elastic matcher's distance to the nearest
        class over that class's spread, each ``log(1 + r)``) and the
        intercept (shape (4,), three features, in models saved before).
    reject_threshold_ : float
        Full wraps scoring above it are "unknown" (``inf`` without ``reject``).
    partial_reject_distance_ : float
        Scaled arc distance to the nearest class beyond which a partial wrap
        is "unknown" (``inf`` without ``reject``).
    partial_reject_margin_ : float
        Scaled margin between the nearest and the second nearest class below
        which a partial wrap is "unknown" (``-inf`` without ``reject``).

    Examples
    --------
    >>> from tentaclass.datasets import synthetic_tentacle
    >>> X, y = synthetic_tentacle(150, 32, noise=0.02, random_state=0, return_X_y=True)
    >>> clf = TentacleClassifier().fit(X, y)
    >>> Xt, yt = synthetic_tentacle(50, 32, noise=0.02, random_state=1, return_X_y=True)
    >>> bool(clf.score(Xt, yt) > 0.9)
    True
    >>> bool(np.allclose(clf.predict_proba(Xt).sum(axis=1), 1.0))
    True
    """

    def __init__(
        self, n_points: int = 64, reject: bool | float = False, unknown_label: str = "unknown"
    ):
        self.n_points = n_points
        self.reject = reject
        self.unknown_label = unknown_label

    # ------------------------------------------------------------------ fit
    def _check_params(self) -> float | None:
        check_positive_int(self.n_points, "n_points", minimum=8)
        r = self.reject
        if r is False or r is None:
            return None
        if r is True:
            return 0.05
        if isinstance(r, numbers.Real) and 0 < float(r) < 1:
            return float(r)
        raise InputError(f"reject must be True, False or a fraction in (0, 1), got {r!r}")

    def fit(
        self, X: ArrayLike, y: ArrayLike, groups: ArrayLike | None = None
    ) -> TentacleClassifier:
        """Learn the training laps and calibrate probabilities and rejection.

        Parameters
        ----------
        X : array_like of shape (n_samples, n_joints)
            Joint angles of wraps, one per row.
        y : array_like of shape (n_samples,)
            Class labels, at least two classes.
        groups : array_like of shape (n_samples,), optional
            The object each wrap was measured on. Several wraps of one object
            are near copies: with ``groups`` the calibration never matches a
            wrap with another wrap of its own object, which keeps the
            probabilities and the rejection distance honest.

        Returns
        -------
        self : TentacleClassifier
        """
        rate = self._check_params()
        Xv, yv = check_X_y(self, X, y, dtype=np.float64)
        self.classes_, y_idx = class_indices(yv)
        if rate is not None:
            check_unknown_label(self.unknown_label, self.classes_)
        groups = np.arange(len(yv)) if groups is None else np.asarray(groups)
        if groups.shape != (len(yv),):
            raise InputError(f"groups must have one entry per wrap ({len(yv)}), got {groups.shape}")
        k = len(self.classes_)
        X3 = _three_or_more(Xv)
        split = split_laps(X3, self.n_points)
        rng = np.random.default_rng(0)
        # member 1: the averaged lap, plus windows of one lap cut from longer wraps
        views, owner = _lap_views(X3, split, self.n_points, _VIEWS)
        rows = np.concatenate([split.lap, views])
        owner = np.concatenate([np.arange(len(yv)), owner])
        self.matcher_ = ShiftNNClassifier(signal="shape", n_harmonics=0.5, weight_power=1.0).fit(
            rows, y_idx[owner]
        )
        # member 2: the last lap rebuilt from the joint positions, every frequency
        last = last_lap(X3, self.n_points)[0]
        self.exact_ = ShiftNNClassifier(signal="shape").fit(last, y_idx)
        # members 4 and 5: the averaged and the last lap rebuilt as outlines, matched elastically
        self.elastic_heights_, self.elastic_complexity_ = _elastic_descriptors(split.lap)
        self.last_heights_, self.last_complexity_ = _elastic_descriptors(last)
        # member 3: spectra of the last lap and of the whole array, a small network
        counts = np.bincount(y_idx, minlength=k)
        use_spectrum = k > 1 and counts.min() >= _SPECTRUM_MIN_PER_CLASS
        features = _spectrum_features(X3) if use_spectrum else np.empty((0, 0))
        self.spectrum_ = _fit_spectrum(features, y_idx) if use_spectrum else None
        # held-out scores of every member on the calibration queries
        q = _subset(len(yv), _CALIBRATION_QUERIES if rate is None else _REJECT_QUERIES, rng)
        d_lap = np.sqrt(self.matcher_.shift_distances(split.lap[q]))
        d_lap[groups[q][:, None] == groups[owner][None, :]] = np.inf
        s_lap = _class_minima(d_lap, self.matcher_.labels_, k)
        d_exact = np.sqrt(self.exact_.shift_distances(last[q]))
        d_exact[groups[q][:, None] == groups[None, :]] = np.inf
        s_exact = _class_minima(d_exact, y_idx, k)
        self.owner_ = owner
        s_el, s_last = self._elastic_minima(split.lap[q], last[q], d_lap, d_exact)
        assert s_el is not None and s_last is not None
        s_spec = None
        if use_spectrum:
            s_spec = _held_out_spectrum(features, y_idx, groups, q, k)
        self.lap_scale_ = _median_nearest(s_lap)
        self.exact_scale_ = _median_nearest(s_exact)
        self.elastic_scale_ = _median_nearest(s_el)
        self.last_scale_ = _median_nearest(s_last)
        members = [s_lap / self.lap_scale_, s_exact / self.exact_scale_, s_spec,
                   s_el / self.elastic_scale_, s_last / self.last_scale_]  # fmt: skip
        self.weights_ = _choose_weights(members, y_idx[q])
        blended = _blend(members, self.weights_)
        # members not used: the model file need not hold their outlines
        if self.weights_[3] == 0 and rate is None:
            self.elastic_heights_ = self.elastic_heights_[:0]
            self.elastic_complexity_ = self.elastic_complexity_[:0]
        if self.weights_[4] == 0 and rate is None:
            self.last_heights_ = self.last_heights_[:0]
            self.last_complexity_ = self.last_complexity_[:0]
        self.scale_, self.temperature_, _, _ = _calibrate(blended, y_idx[q], rate)
        self.class_spread_ = np.empty(0)
        self.reject_coef_, self.reject_threshold_ = np.zeros(4), np.inf
        if rate is not None:
            used = [m for j in REJECT_MEMBERS if (m := members[j]) is not None]
            spreads = [_class_spreads(m, y_idx[q], k) for m in used]
            self.class_spread_ = np.concatenate([sp for sp, _ in spreads])
            self.reject_coef_, self.reject_threshold_ = _fit_rejection(
                blended / self.scale_, used, y_idx[q], spreads, rate
            )
        # partial wraps: arcs of 0.5-0.95 laps cut from the training laps
        closed = np.flatnonzero(split.closed)
        if closed.size == 0:  # no full lap anywhere: arcs of whatever was seen
            closed = np.arange(len(yv))
        laps = split.lap[closed]
        heads = np.cumsum(np.concatenate([laps, laps[:, ::-1]]), axis=1)
        self.headings_ = heads - heads.mean(axis=1, keepdims=True)
        self.arc_labels_ = np.concatenate([y_idx[closed], y_idx[closed]])
        arc_groups = np.concatenate([groups[closed], groups[closed]])
        q = _subset(len(closed), _PARTIAL_QUERIES, rng)
        d = _cut_arc_distances(self.headings_[q], self.headings_, rng)
        d[arc_groups[q][:, None] == arc_groups[None, :]] = np.inf
        (
            self.partial_scale_,
            self.partial_temperature_,
            self.partial_reject_distance_,
            self.partial_reject_margin_,
        ) = _calibrate(
            _class_minima(d, self.arc_labels_, len(self.classes_)), y_idx[closed][q], rate
        )
        return self

    # -------------------------------------------------------------- predict
    def _scores(self, X: ArrayLike) -> tuple[FloatArray, np.ndarray, FloatArray, FloatArray]:
        """Class distances, closed flags, laps and unknown-ness (see ``_checked_scores``)."""
        return self._checked_scores(check_fitted_X(self, X))

    def predict_proba(self, X: ArrayLike) -> FloatArray:
        """Calibrated class probabilities, shape (n_samples, n_classes); rows sum to 1."""
        return self._proba_of(*self._scores(X)[:2])

    def predict(self, X: ArrayLike) -> np.ndarray:
        """Class of each wrap; ``unknown_label`` where rejected (see ``reject``)."""
        s, _, _, novelty = self._scores(X)
        return self._labels_of(s, novelty)

    def grasp(self, X: ArrayLike) -> dict:
        """Grasp state, laps seen and the best guess with its probability, per wrap.

        Returns
        -------
        report : dict of ndarray
            ``state`` ("partial" below one full lap, else "closed"), ``laps``
            (laps after the approach, from the angles), ``label`` and
            ``probability`` of the most probable class.
        """
        s, closed, laps, _ = self._scores(X)
        p = self._proba_of(s, closed)
        return {
            "state": np.where(closed, "closed", "partial"),
            "laps": laps,
            "label": self.classes_[np.argmax(p, axis=1)],
            "probability": p.max(axis=1),
        }

    def __sklearn_tags__(self) -> Any:
        tags = super().__sklearn_tags__()
        tags.input_tags.allow_nan = False
        # the features are outlines rebuilt from joint angles: sklearn's blob
        # test data are not wraps, so its training-accuracy check does not apply
        tags.classifier_tags.poor_score = True
        return tags


# ---------------------------------------------------------------------- helpers
def _lap_views(
    X: FloatArray, split: LapSplit, n_points: int, n_views: int
) -> tuple[FloatArray, np.ndarray]:
    """Windows of exactly one lap cut from every wrap of more than one lap.

    A wrap of 1.6 laps holds a full lap ending anywhere in its last 0.6 laps;
    each such window samples the outline at other points between its joints
    (and, hugging, at another layer). ``n_views`` windows are cut at evenly
    spaced ends, resampled to ``n_points`` links like the averaged lap.
    Returns the windows (rows, n_points) and the wrap each came from.
    """
    n = X.shape[1]
    heading = np.cumsum(X * split.direction[:, None], axis=1)
    views, owner = [np.empty((0, n_points))], [np.empty(0, np.int64)]
    for i in np.flatnonzero(split.closed):
        period, first_end = split.period[i], split.offset[i] + split.period[i]
        if n - first_end < 0.5:  # one lap only: the averaged lap is that lap
            continue
        ends = np.linspace(first_end, n, n_views)
        # phases sampled as split_laps samples the averaged lap: cell centres
        arc = ends[:, None] - period + (np.arange(-1, n_points) + 0.5) / n_points * period
        views.append(np.diff(np.interp(arc - 0.5, np.arange(n), heading[i]), axis=1))
        owner.append(np.full(n_views, i))
    return np.concatenate(views), np.concatenate(owner)


def _elastic_descriptors(laps: FloatArray) -> tuple[np.ndarray, np.ndarray]:
    """Height descriptors (float32) and complexities of laps rebuilt as outlines."""
    heights = _elastic.heights(_lap_outlines(laps), _elastic.DENSE)
    return heights, _elastic.complexity(heights)


def _spectrum_model() -> Pipeline:
    return make_pipeline(StandardScaler(), MLPClassifier((64,), max_iter=400, random_state=0))


def _fit_spectrum(features: FloatArray, y: np.ndarray) -> Pipeline:
    # small matrices: threaded BLAS only adds overhead (ten times slower on two busy cores)
    with warnings.catch_warnings(), threadpool_limits(1, user_api="blas"):
        warnings.simplefilter("ignore", ConvergenceWarning)
        return _spectrum_model().fit(features, y)


def _held_out_spectrum(
    features: FloatArray, y: np.ndarray, groups: np.ndarray, q: np.ndarray, n_classes: int
) -> FloatArray:
    """Spectrum-member scores of the wraps ``q``, each from a model that never saw its object."""
    out = np.empty((len(q), n_classes))
    folds = min(_INNER_FOLDS, len(np.unique(groups)))
    for train, test in GroupKFold(folds).split(features, y, groups):
        sel = np.flatnonzero(np.isin(q, test))
        if sel.size == 0:
            continue
        model = _fit_spectrum(features[train], y[train])
        out[sel] = _spectrum_scores(model, features[q[sel]], n_classes)
    return out


def _choose_weights(members: list[FloatArray | None], y: np.ndarray) -> FloatArray:
    """Member weights with the fewest held-out errors, ties to the least log loss.

    Errors first: a member with sharp but often wrong probabilities can lower
    the log loss of a blend while costing accuracy. The lap matcher weighs 1.
    """
    grids = [(1.0,), _WEIGHTS, _WEIGHTS if members[2] is not None else (0.0,), _ELASTIC_WEIGHTS,
             _ELASTIC_WEIGHTS]  # fmt: skip
    tried = [
        (int(np.sum(np.argmin(_blend(members, np.array(w)), axis=1) != y)), w)
        for w in itertools.product(*grids)
    ]
    fewest = min(t[0] for t in tried)
    best, chosen = np.inf, tried[0][1]
    for errors, w in tried:
        if errors == fewest:
            loss = _log_loss(_blend(members, np.array(w)), y)
            if loss < best:
                best, chosen = loss, w
    return np.array(chosen, dtype=float)


def _median_nearest(s: FloatArray) -> float:
    nearest = s.min(axis=1)
    finite = nearest[np.isfinite(nearest)]
    scale = float(np.median(finite)) if finite.size else 1.0
    return scale if scale > 0 else 1.0


def _log_loss(s: FloatArray, y: np.ndarray) -> float:
    """Held-out log loss of ``softmax(-s / t)`` at the best temperature ``t``."""
    s = s / _median_nearest(s)
    rows = np.isfinite(s[np.arange(len(y)), y])
    if not rows.any():
        return np.inf
    s, y = np.where(np.isfinite(s[rows]), s[rows], 1e6), y[rows]

    def loss(log_t: float) -> float:
        return _true_class_loss(-s / np.exp(log_t), y)

    return float(minimize_scalar(loss, bounds=(-6, 4), method="bounded").fun)


def _true_class_loss(a: FloatArray, y: np.ndarray) -> float:
    """Mean ``-log(softmax(a, axis=1)[i, y[i]] + 1e-12)``.

    Only the true classes' probabilities are divided out, by the same
    operations as ``scipy.special.softmax`` (so the same numbers to the bit):
    the temperature search calls this some thirty times per candidate blend.
    """
    e = np.exp(a - np.max(a, axis=1, keepdims=True))
    p = e[np.arange(len(y)), y] / np.sum(e, axis=1)
    return float(-np.mean(np.log(p + 1e-12)))


def _subset(n: int, k: int, rng: np.random.Generator) -> np.ndarray:
    return np.sort(rng.choice(n, k, replace=False)) if n > k else np.arange(n)


def _calibrate(s: FloatArray, y: np.ndarray, rate: float | None) -> tuple[float, ...]:
    """Scale, softmax temperature and rejection limits from leave-one-out class distances.

    Rejection has two limits, each taking half of ``rate`` of the known
    wraps: the distance to the nearest class (far from everything seen) and
    the margin between the nearest and the second nearest class (as close to
    two classes as to one: typical of an object of a class not trained on).
    """
    nearest = s.min(axis=1)
    finite = np.isfinite(nearest)
    scale = float(np.median(nearest[finite])) if finite.any() else 1.0
    scale = scale if scale > 0 else 1.0
    s = np.where(np.isfinite(s), s / scale, 1e6)
    rows = finite & np.isfinite(s[np.arange(len(y)), y] if len(y) else finite)

    known = s[rows]

    def loss(log_t: float) -> float:
        return _true_class_loss(-known / np.exp(log_t), y[rows])

    t = 1.0
    if rows.any():
        t = float(np.exp(minimize_scalar(loss, bounds=(-6, 4), method="bounded").x))
    far, near = np.inf, -np.inf
    if rate and finite.any():
        far = float(np.quantile(nearest[finite] / scale, 1 - rate / 2))
        if s.shape[1] > 1:
            ordered = np.sort(s[finite], axis=1)
            near = float(np.quantile(ordered[:, 1] - ordered[:, 0], rate / 2))
    return scale, t, far, near


def _class_spreads(
    elastic: FloatArray, y: np.ndarray, n_classes: int
) -> tuple[FloatArray, FloatArray]:
    """Each class's spread, and each held-out wrap's with that wrap left out.

    The spread of a class is the geometric mean of the held-out elastic
    distances of its wraps to their own class, pulled towards the median over
    all wraps by ``_SPREAD_PRIOR`` wraps' worth (a class with few wraps gets
    the common spread). Returns ``(spread (n_classes,), loo (n, n_classes))``:
    ``loo`` is ``spread`` in every row, except at each wrap's own class,
    where the wrap itself is left out (its features are then those of a new wrap).
    """
    rows = np.arange(len(y))
    own = elastic[rows, y]
    ok = np.isfinite(own) & (own > 0)
    logs = np.log(np.where(ok, own, 1.0))
    prior = float(np.median(logs[ok])) if ok.any() else 0.0
    total = np.bincount(y[ok], weights=logs[ok], minlength=n_classes)
    count = np.bincount(y[ok], minlength=n_classes).astype(float)
    a = _SPREAD_PRIOR
    spread = np.exp((total + a * prior) / (count + a))
    loo = np.tile(spread, (len(y), 1))
    loo[rows[ok], y[ok]] = np.exp((total[y[ok]] - logs[ok] + a * prior) / (count[y[ok]] - 1 + a))
    return spread, loo


def _fit_rejection(
    s: FloatArray,
    members: list[FloatArray],
    y: np.ndarray,
    spreads: list[tuple[FloatArray, FloatArray]],
    rate: float,
) -> tuple[FloatArray, float]:
    """Coefficients and limit of the rejection rule from held-out training wraps.

    Each held-out wrap is seen twice: as it is (a known object) and with its
    own class taken out of its scores (what an object of a class never
    trained on looks like: its nearest class is another one). A logistic
    regression on :func:`_novelty_features` of ``members`` tells the two
    apart; the limit is the ``1 - rate`` quantile of the known wraps' scores
    (split-conformal: a new object of a known class is rejected with
    probability about ``rate``). ``spreads`` holds each member's
    :func:`_class_spreads`. Returns ``(coefficients and intercept, limit)``.
    """
    from sklearn.linear_model import LogisticRegression

    rows = np.arange(len(y))
    known = _novelty_features(s, members, [loo for _, loo in spreads])
    s_out = s.copy()
    s_out[rows, y] = np.inf
    out = []
    for m in members:
        m = m.copy()
        m[rows, y] = np.inf
        out.append(m)
    unseen = _novelty_features(s_out, out, [spread for spread, _ in spreads])
    features = np.vstack([known, unseen])
    target = np.r_[np.zeros(len(y)), np.ones(len(y))]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        lr = LogisticRegression(C=10.0, max_iter=1000).fit(features, target)
    coef = np.append(lr.coef_[0], lr.intercept_[0])
    scores = np.sort(known @ coef[:-1] + coef[-1])
    rank = min(len(scores) - 1, int(np.ceil((len(scores) + 1) * (1 - rate))) - 1)
    return coef, float(scores[rank])


def _cut_arc_distances(
    queries: FloatArray, heads: FloatArray, rng: np.random.Generator
) -> FloatArray:
    """Distances of arcs of 0.5-0.95 laps, cut at random from ``queries``, to ``heads``.

    Each arc is resampled to the links of a lap and its length estimated
    from its turning, as a partial wrap's is in prediction.
    """
    n = queries.shape[1]
    ms = np.array([_arc_points(rng.uniform(0.5, 0.95), n) for _ in queries])
    ks = rng.integers(n, size=len(queries))
    ext = np.concatenate([queries, queries + 2 * np.pi], axis=1)
    arcs = np.empty((len(queries), n))
    for m in np.unique(ms):
        sel = np.flatnonzero(ms == m)
        arcs[sel] = _resample_rows(np.stack([ext[i, ks[i] : ks[i] + m] for i in sel]), n)
    turning = (arcs[:, -1] - arcs[:, 0]) * n / (n - 1) / (2 * np.pi)
    return _partial_distances(arcs, turning, heads)
