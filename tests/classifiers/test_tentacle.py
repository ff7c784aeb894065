import copy

import numpy as np
import pytest

from tentaclass import TentacleClassifier, wrap_many
from tentaclass.datasets import synthetic_tentacle
from tentaclass.shapes import circle, rectangle, square, triangle

SHAPES = {
    "square": square(1.0),
    "circle": circle(0.5, n_points=256),
    "triangle": triangle([(0.0, 0.0), (1.0, 0.0), (0.3, 0.8)]),
    "rectangle": rectangle(2.5, 1.0),
}


@pytest.fixture(scope="module")
def model():
    X, y = synthetic_tentacle(400, 32, laps=(0.9, 3.0), noise=(0.0, 0.03), random_state=11,
                              return_X_y=True)  # fmt: skip
    return TentacleClassifier().fit(X, y)


def wraps_of(outline, laps, offset, n_links=32, starts=(0.1, 0.45, 0.8), direction="ccw"):
    """Unit-link wraps of ``outline`` scaled so the chain covers about ``laps`` laps."""
    from shapely.geometry import Polygon

    o = np.asarray(outline, float)
    o = (o - o.mean(axis=0)) * (n_links - offset) / laps / Polygon(o).length
    b = wrap_many(o, n_links, 1.0, starts=np.array(starts), offset=offset, direction=direction)
    return b.angles


@pytest.mark.parametrize("laps", [1.0, 1.5, 2.2])
@pytest.mark.parametrize("offset", [0.0, 2.0])
def test_thesis_shapes_any_laps_and_offset(model, laps, offset, rng):
    for name, outline in SHAPES.items():
        q = wraps_of(outline, laps, offset)
        for noise in (0.0, 0.02):
            pred = model.predict(q + rng.normal(0.0, noise, q.shape))
            assert pred.tolist() == [name] * len(q), (name, laps, offset, noise)


def test_direction_and_rotation_do_not_matter(model):
    q = np.vstack([wraps_of(o, 1.6, 1.0) for o in SHAPES.values()])
    p = model.predict_proba(q)
    # clockwise: the same object mirrored gives the negated angles
    np.testing.assert_allclose(model.predict_proba(-q), p, atol=1e-9)
    # a rotated object: the same joint angles (they are relative)
    theta = 0.7
    rot = np.array([[np.cos(theta), np.sin(theta)], [-np.sin(theta), np.cos(theta)]])
    q_rot = wraps_of(SHAPES["triangle"] @ rot, 1.6, 1.0)
    np.testing.assert_allclose(q_rot, wraps_of(SHAPES["triangle"], 1.6, 1.0), atol=1e-6)
    np.testing.assert_allclose(model.predict_proba(q_rot), model.predict_proba(q_rot[::-1])[::-1])


def test_start_point_does_not_matter(model):
    for name, outline in SHAPES.items():
        q = wraps_of(outline, 1.5, 0.0, starts=np.linspace(0, 1, 7, endpoint=False))
        assert set(model.predict(q)) == {name}


def test_probabilities_are_calibrated(model):
    # 150 wraps of each kind (measured: mean top probability 0.006 from the hit rate;
    # 38 errors on the noisier ones, right answers at 0.98 against 0.88 for wrong ones)
    X, y = synthetic_tentacle(150, 32, laps=(0.9, 3.0), noise=(0.0, 0.03), random_state=12,
                              return_X_y=True)  # fmt: skip
    p = model.predict_proba(X)
    np.testing.assert_allclose(p.sum(axis=1), 1.0)
    right = model.classes_[p.argmax(axis=1)] == y
    # confidence tracks accuracy: mean top probability within 0.1 of the hit rate,
    # and the right answers are given with more confidence than the wrong ones
    conf = p.max(axis=1)
    assert abs(conf.mean() - right.mean()) < 0.1
    # on encoders noisier than the training wraps (so that there are errors) the
    # right answers still come with more confidence than the wrong ones
    X, y = synthetic_tentacle(150, 32, laps=(0.9, 3.0), noise=(0.1, 0.2), random_state=14,
                              return_X_y=True)  # fmt: skip
    p = model.predict_proba(X)
    right, conf = model.classes_[p.argmax(axis=1)] == y, p.max(axis=1)
    assert (~right).sum() >= 10
    assert conf[right].mean() > conf[~right].mean()


def test_partial_wraps_are_reported_as_partial(model):
    X, y = synthetic_tentacle(80, 32, laps=(0.5, 0.8), offset=(0, 2), noise=0.0,
                              random_state=13, return_X_y=True)  # fmt: skip
    g = model.grasp(X)
    assert np.mean(g["state"] == "partial") > 0.85
    assert np.median(g["laps"][g["state"] == "partial"]) < 0.9
    p = model.predict_proba(X)
    top2 = np.argsort(p, axis=1)[:, -2:]
    assert np.mean([c in model.classes_[t] for c, t in zip(y, top2, strict=True)]) > 0.8
    # an honest confidence: lower than on full wraps
    Xf, _ = synthetic_tentacle(80, 32, laps=(1.2, 2.0), noise=0.0, random_state=13, return_X_y=True)
    assert p.max(axis=1).mean() < model.predict_proba(Xf).max(axis=1).mean()


@pytest.mark.parametrize("noise", [0.0, 0.02])
def test_wraps_just_short_of_a_lap_are_partial(model, noise):
    # 0.85-0.95 laps: the chain's end lies close to its start, but it never ran
    # past it, while 1.2-2 laps run on over their start
    short = synthetic_tentacle(80, 32, laps=(0.85, 0.95), offset=(0, 2), noise=noise,
                               random_state=13)  # fmt: skip
    g = model.grasp(short.data)
    assert np.mean(g["state"] == "partial") >= 0.95
    assert np.all(g["laps"][g["state"] == "partial"] < 1.1)  # by the turning: steps at corners
    assert np.mean(g["label"] == short.target) >= 0.9
    full = synthetic_tentacle(80, 32, laps=(1.2, 2.0), offset=(0, 2), noise=noise,
                              random_state=13)  # fmt: skip
    assert np.all(model.grasp(full.data)["state"] == "closed")


@pytest.fixture(scope="module")
def open_set():
    """``TentacleClassifier(reject=True)`` trained without triangles, its wraps, the known rows."""
    d = synthetic_tentacle(300, 32, laps=(1.1, 2.0), noise=0.0, random_state=14)
    # only wraps the generator made as asked (a few chains coil up past their laps)
    known = (d.laps < 2.4) & (d.target != "triangle")
    return TentacleClassifier(reject=True).fit(d.data[known], d.target[known]), d, known


def test_unknown_class_is_rejected(model, open_set):
    # measured: every triangle rejected, 5.1 % of the other wraps
    clf = open_set[0]
    t = synthetic_tentacle(200, 32, laps=(1.1, 2.0), noise=0.0, random_state=15)
    t_ok = t.laps < 2.4
    assert clf.reject_threshold_ < np.inf
    pred = clf.predict(t.data[t_ok])
    tri = t.target[t_ok] == "triangle"
    assert np.mean(pred[tri] == "unknown") > 0.75
    assert np.mean(pred[~tri] == "unknown") < 0.12
    assert model.reject_threshold_ == np.inf  # the default (the module's fit) rejects nothing


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"n_points": 4}, "n_points must be at least 8"),
        ({"n_points": 8.0}, "n_points must be an integer"),
        ({"n_points": True}, "n_points must be an integer"),
        ({"reject": 1.5}, "reject"),
        ({"reject": "x"}, "reject"),
    ],
)
def test_bad_parameters(kwargs, match):
    X, y = synthetic_tentacle(20, 16, random_state=0, return_X_y=True)
    with pytest.raises(ValueError, match=match):
        TentacleClassifier(**kwargs).fit(X, y)


@pytest.fixture(scope="module")
def sixteen_links():
    """Thesis classes, 16 links (8-13 per lap): where the members disagree most."""
    d = synthetic_tentacle(400, 16, noise=0.02, random_state=21)
    t = synthetic_tentacle(200, 16, noise=0.02, random_state=22)
    keep, held = np.isfinite(d.data).all(axis=1), np.isfinite(t.data).all(axis=1)
    model = TentacleClassifier().fit(d.data[keep], d.target[keep])
    return model, t.data[held], t.target[held]


def test_blend_matches_or_beats_each_member(sixteen_links):
    model, X, y = sixteen_links
    assert model.spectrum_ is not None
    assert model.weights_[0] == 1.0 and np.all(model.weights_ >= 0)
    blend = model.score(X, y)
    chosen = model.weights_.copy()
    alone = {}
    members = [("lap", [1.0, 0, 0, 0]), ("exact", [1e-9, 1, 0, 0]), ("spectrum", [1e-9, 0, 1, 0])]
    if model.weights_[3] > 0:  # the elastic members' training outlines are kept only if used
        members.append(("elastic", [1e-9, 0, 0, 1, 0]))
    if model.weights_[4] > 0:
        members.append(("elastic last lap", [1e-9, 0, 0, 0, 1]))
    for name, w in members:
        model.weights_ = np.array(w)
        alone[name] = model.score(X, y)
    model.weights_ = chosen
    # the weights come from held-out training wraps only: the blend may lose a
    # wrap or two to the best member on a test set, never more
    assert blend >= max(alone.values()) - 2.0 / len(y), (blend, alone)
    assert blend > min(alone.values())


def test_longer_wraps_give_one_lap_views():
    from tentaclass.classifiers._tentacle import _lap_views
    from tentaclass.features import split_laps

    square = np.tile([0, 0, 0, np.pi / 2], 4)  # one lap of 16 links
    for X in (np.r_[square, square[:8]], np.r_[square, square]):  # 1.5 and 2 laps
        X = np.vstack([X, X])
        views, owner = _lap_views(X, split_laps(X, 16), 16, 2)
        assert owner.tolist() == [0, 0, 1, 1]
        np.testing.assert_allclose(views.sum(axis=1), 2 * np.pi)
        # every window is the square again, from another start point
        for v in views:
            assert any(np.allclose(np.roll(v, k), square, atol=1e-9) for k in range(16))


def _fits_at_rates(monkeypatch, X, y, rates):
    """``TentacleClassifier(reject=rate).fit(X, y)`` for each rate, from one fit.

    The rate asked sets the rejection limits only: the full wraps' limit on
    the held-out novelty scores and the partial wraps' limits on their
    held-out distances, both quantiles taken after everything else is
    learnt. The fit at the first rate keeps what those quantiles are taken
    of; each other model is that fit with its limits taken at its own rate
    (``test_one_fit_gives_the_models_of_every_rate`` compares them with fits).
    """
    from tentaclass.classifiers import _tentacle

    first, others = rates[0], rates[1:]
    limits = {rate: {} for rate in others}
    fit_rejection, calibrate = _tentacle._fit_rejection, _tentacle._calibrate

    def spy_rejection(*args):
        for rate in others:
            limits[rate]["reject_threshold_"] = fit_rejection(*args[:-1], rate)[1]
        return fit_rejection(*args)

    def spy_calibrate(s, y_, rate):
        for other in others:  # the last call: the partial wraps' limits
            far, near = calibrate(s, y_, other)[2:]
            limits[other].update(partial_reject_distance_=far, partial_reject_margin_=near)
        return calibrate(s, y_, rate)

    with monkeypatch.context() as m:
        m.setattr(_tentacle, "_fit_rejection", spy_rejection)
        m.setattr(_tentacle, "_calibrate", spy_calibrate)
        model = TentacleClassifier(reject=first).fit(X, y)
    models = {first: model}
    for rate in others:
        models[rate] = copy.deepcopy(model).set_params(reject=rate)
        for name, value in limits[rate].items():
            setattr(models[rate], name, value)
    return models


def test_one_fit_gives_the_models_of_every_rate(monkeypatch):
    X, y = synthetic_tentacle(30, 16, laps=(1.1, 2.0), noise=0.02, random_state=16,
                              return_X_y=True)  # fmt: skip
    models = _fits_at_rates(monkeypatch, X, y, (0.02, 0.2))
    fitted = TentacleClassifier(reject=0.2).fit(X, y)
    assert models[0.2].get_params() == fitted.get_params()
    learnt = {k: v for k, v in vars(fitted).items() if k.endswith("_")}
    assert learnt.keys() == {k for k in vars(models[0.2]) if k.endswith("_")}
    for name, value in learnt.items():
        if isinstance(value, np.ndarray):
            np.testing.assert_array_equal(getattr(models[0.2], name), value, err_msg=name)
        elif isinstance(value, float | int | str):
            assert getattr(models[0.2], name) == value, name
    assert models[0.2].reject_threshold_ != models[0.02].reject_threshold_
    np.testing.assert_array_equal(models[0.2].predict(X), fitted.predict(X))


def test_requested_false_rejection_rate_is_kept(monkeypatch):
    """Measured on 200 training wraps: 0.5 % of 200 new wraps rejected at 2 % asked,
    19.5 % at 20 % (of 300 new wraps: 2.3 % and 15.7 %)."""
    d = synthetic_tentacle(200, 32, laps=(1.1, 2.0), noise=0.02, random_state=16)
    t = synthetic_tentacle(200, 32, laps=(1.1, 2.0), noise=0.02, random_state=17)
    ok = np.isfinite(t.data).all(axis=1) & t.complete
    models = _fits_at_rates(monkeypatch, d.data, d.target, (0.02, 0.2))
    rejected = {rate: np.mean(m.predict(t.data[ok]) == "unknown") for rate, m in models.items()}
    # split-conformal limits: new wraps of known classes are rejected at about the rate asked
    assert rejected[0.02] < 0.07
    assert 0.1 < rejected[0.2] < 0.32


def test_class_spreads_leave_each_wrap_out():
    from tentaclass.classifiers._tentacle import _SPREAD_PRIOR, _class_spreads

    # two classes; each wrap's held-out elastic distance to its own class
    d = np.array([[1.0, 5.0], [4.0, 5.0], [5.0, 2.0], [5.0, 2.0], [5.0, 2.0]])
    y = np.array([0, 0, 1, 1, 1])
    spread, loo = _class_spreads(d, y, 2)
    prior = np.log(2.0)  # median of the own-class distances 1, 4, 2, 2, 2
    a = _SPREAD_PRIOR
    np.testing.assert_allclose(spread[0], np.exp((np.log(4.0) + a * prior) / (2 + a)))
    np.testing.assert_allclose(spread[1], 2.0)
    # wrap 0 left out of its own class, the other class as it is
    np.testing.assert_allclose(loo[0], [np.exp((np.log(4.0) + a * prior) / (1 + a)), 2.0])
    np.testing.assert_allclose(loo[2], [spread[0], 2.0])


def test_partial_arc_found_whatever_its_turning_says():
    from tentaclass.classifiers._tentacle_core import (
        _arc_distances,
        _arc_points,
        _partial_distances,
        _resample_rows,
    )

    rng = np.random.default_rng(3)
    n = 64
    turns = np.abs(rng.normal(2 * np.pi / n, 0.08, size=(5, n)))
    turns *= 2 * np.pi / turns.sum(axis=1, keepdims=True)
    heads = np.cumsum(turns, axis=1)
    arc = heads[2, 10:55]  # 45 of 64 links of lap 2
    arc = np.interp((np.arange(n) + 0.5) / n * 45 - 0.5, np.arange(45), arc)[None]
    # its turning tells a share of the lap 25 % too small: the exact length is still tried
    told = 45 / 64 / 1.25
    d = _partial_distances(arc, np.array([told]), heads)
    assert np.argmin(d[0]) == 2 and d[0, 2] < 0.05
    taken_as_told = _arc_distances(_resample_rows(arc, _arc_points(told, n)), heads)
    assert d[0, 2] < 0.5 * taken_as_told[0, 2]


def test_rejection_reads_both_elastic_members_and_older_rules_still_work(model, open_set):
    from tentaclass.classifiers._tentacle_core import _blend, _three_or_more
    from tentaclass.features import split_laps

    clf, d, known = open_set  # the old rule below answers 15 of its first 60 wraps "unknown"
    k = len(clf.classes_)
    assert clf.reject_coef_.shape == (6,) and clf.class_spread_.shape == (2 * k,)
    assert len(clf.last_heights_) == known.sum()  # the rule needs the last laps' outlines
    # a rule saved before the last lap's matcher joined it: three features, one spread
    old = copy.deepcopy(clf)
    old.reject_coef_ = np.array([1.5, 2.0, 3.0, -4.0])
    old.class_spread_ = clf.class_spread_[:k]
    X = d.data[d.complete][:60]
    split = split_laps(_three_or_more(X), clf.n_points)
    _, closed, _, novelty = old._checked_scores(X)
    members = old._closed_members(X[closed], split.lap[closed])
    blend = _blend(members, old.weights_) / old.scale_
    el, best = members[3], np.argmin(blend, axis=1)
    o, e = np.sort(blend, axis=1), np.sort(el, axis=1)
    rows = np.arange(len(best))
    with np.errstate(invalid="ignore"):  # 0 / 0 where a wrap matches two classes exactly
        ratios = [o[:, 0] / o[:, 1], e[:, 0] / e[:, 1], el[rows, best] / old.class_spread_[best]]
    features = np.log1p(np.nan_to_num(np.stack(ratios, axis=1), nan=0.0))
    expected = features @ [1.5, 2.0, 3.0] - 4.0 - old.reject_threshold_
    np.testing.assert_allclose(novelty[closed], expected)
    unknown = np.flatnonzero(closed)[expected > 0]
    assert np.all(old.predict(X)[unknown] == "unknown")
    # without rejection the last laps' outlines are not kept when their weight is 0
    # (it is 0 in the module's default fit)
    assert model.weights_[4] > 0 or len(model.last_heights_) == 0


def test_one_class_is_refused():
    # it fitted, calibrating probabilities and rejection against no other class
    from tentaclass.errors import InputError

    X = wraps_of(SHAPES["square"], 1.5, 0.0)
    with pytest.raises(InputError, match="y must hold at least 2 classes, got one class"):
        TentacleClassifier().fit(X, ["square"] * len(X))


def test_a_rejection_label_that_is_a_class_is_refused_at_fit():
    from tentaclass.errors import InputError

    X, y = synthetic_tentacle(24, 32, random_state=3, return_X_y=True)
    clf = TentacleClassifier(reject=True, unknown_label=str(y[0]))
    with pytest.raises(InputError, match=rf"^unknown_label '{y[0]}' is one of the classes"):
        clf.fit(X, y)
