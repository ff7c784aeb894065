import numpy as np
import pytest
from scipy.spatial.distance import cdist
from sklearn.model_selection import GridSearchCV, cross_val_score

import tentaclass.classifiers._pnn_core as pnn_module
from tentaclass.classifiers import FourierClassifier, PNNClassifier
from tentaclass.classifiers._pnn import MIN_SPREAD, auto_spread
from tentaclass.datasets import thesis_tentacle
from tentaclass.errors import InputError


def reference_scores(X_train, y_train, X, spread):
    """Direct newpnn formula with scipy distances."""
    b = np.sqrt(-np.log(0.5)) / spread
    k = np.exp(-((b * cdist(X, X_train)) ** 2))
    classes = np.unique(y_train)
    return np.stack([k[:, y_train == c].mean(axis=1) for c in classes], axis=1)


def test_pattern_at_distance_spread_scores_half():
    clf = PNNClassifier(spread=0.3).fit([[0.0, 0.0], [5.0, 5.0]], ["a", "b"])
    s = clf.class_scores([[0.3, 0.0], [0.0, 0.0]])
    np.testing.assert_allclose(s[:, 0], [0.5, 1.0])


@pytest.mark.parametrize("spread", [0.1, 1.0, 3.0])
def test_scores_match_direct_formula(spread, rng):
    X = rng.normal(size=(60, 5))
    y = rng.choice(["x", "y", "z"], size=60)
    T = rng.normal(size=(25, 5)) * 0.5
    clf = PNNClassifier(spread=spread).fit(X, y)
    np.testing.assert_allclose(clf.class_scores(T), reference_scores(X, y, T, spread), atol=1e-12)
    ref = reference_scores(X, y, T, spread)
    ok = ref.sum(axis=1) > 1e-200
    np.testing.assert_allclose(clf.predict_proba(T)[ok], (ref / ref.sum(1, keepdims=True))[ok])


def test_far_samples_give_valid_probabilities():
    clf = PNNClassifier(spread=0.01).fit([[0.0], [1.0]], [0, 1])
    p = clf.predict_proba([[100.0], [-50.0]])
    assert np.all(np.isfinite(p))
    np.testing.assert_allclose(p.sum(axis=1), 1)
    assert clf.predict([[100.0], [-50.0]]).tolist() == [1, 0]  # nearest class still wins


@pytest.mark.parametrize("dtype", ["float64", "float32"])
def test_tiled_computation_equals_single_block(rng, monkeypatch, dtype):
    X = rng.normal(size=(300, 4))
    y = rng.integers(0, 5, 300)
    T = rng.normal(size=(97, 4)) * 3
    monkeypatch.setattr(pnn_module, "_TILE_BYTES", 2**40)
    monkeypatch.setattr(pnn_module, "_TILE_COLS", 10**9)
    clf = PNNClassifier(spread=0.7, dtype=dtype).fit(X, y)
    rows, tiles = clf._tiles(1, 8)
    assert rows >= T.shape[0] and len(tiles) == 5  # one block: all rows, one tile per class
    full = clf.predict_log_proba(T)
    # 7 rows x at most 9 columns per tile, over 2 threads
    monkeypatch.setattr(pnn_module, "_TILE_COLS", 9)
    monkeypatch.setattr(pnn_module, "_TILE_BYTES", clf._pt.itemsize * 9 * 7)
    monkeypatch.setattr(pnn_module, "_MIN_PARALLEL", 1)
    monkeypatch.setattr(pnn_module, "_n_threads", lambda: 2)
    rows, tiles = clf._tiles(2, clf._pt.itemsize)
    assert rows == 7 and max(b - a for _, a, b in tiles) <= 9
    tiled = clf.predict_log_proba(T)
    np.testing.assert_allclose(tiled, full, rtol=1e-12 if dtype == "float64" else 1e-5)


@pytest.mark.parametrize("dtype", ["float64", "float32"])
@pytest.mark.parametrize("shift", [0.0, 40.0])
def test_small_batches_score_as_in_a_large_batch(rng, dtype, shift):
    # small batches take NumPy's all-classes-at-once pass, a large one the
    # compiled tiles (a shift puts every class in a framed regime): the same
    # labels, and scores within the rounding of exp and of the sums (float64:
    # a few ulp) or of the float32 product (OpenBLAS's sgemm rounds a
    # product of 40 rows differently from one of 5000)
    X = rng.normal(size=(300, 6))
    y = rng.integers(0, 4, 300)
    T = rng.normal(size=(5000, 6)) * 2 + shift
    clf = PNNClassifier(spread=0.5, dtype=dtype).fit(X, y)
    assert T.shape[0] * X.shape[0] > pnn_module._WHOLE_MAX >= 40 * X.shape[0]
    large = clf._joint_log_likelihood(T)
    rtol = 2e-15 if dtype == "float64" else 4e-6
    for lo in (0, 17, 4000):
        small = clf._joint_log_likelihood(T[lo : lo + 40])
        np.testing.assert_allclose(small, large[lo : lo + 40], rtol=rtol)
        assert np.array_equal(small.argmax(axis=1), large[lo : lo + 40].argmax(axis=1))
    np.testing.assert_allclose(clf._joint_log_likelihood(T[3:4]), large[3:4], rtol=rtol)


@pytest.mark.parametrize(("dtype", "bound"), [(np.float64, 708.0), (np.float32, np.float32(87.0))])
def test_compiled_exp_is_within_one_ulp_and_clamped_to_normal_numbers(rng, dtype, bound):
    from tentaclass.classifiers._pnn_kernel import vexp

    x = np.concatenate([rng.uniform(-bound, bound, 200_000), rng.uniform(-1, 1, 20_000)])
    x = np.concatenate([x, [0.0, -bound, bound]]).astype(dtype)
    out = np.empty_like(x)
    vexp(x, out)
    ref = np.exp(x.astype(np.float64))  # correctly rounded but for rare cases
    assert np.all(np.abs(out - ref) <= np.spacing(ref.astype(dtype)).astype(np.float64))
    # beyond the bound: the value at the bound, a normal number (no subnormals)
    beyond = np.array([-bound - 50, -1e4, bound + 50], dtype=dtype)
    vexp(beyond, out[:3])
    np.testing.assert_array_equal(out[:3], out[[-2, -2, -1]])
    assert out[0] >= np.finfo(dtype).tiny


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_compiled_row_maximum_is_numpys(rng, dtype):
    # a SIMD reduction: rows of every length modulo the vector width and its
    # unrolling, the maximum anywhere in the row, infinities and signed zeros
    from tentaclass.classifiers._pnn_kernel import _row_max

    for n in [*range(1, 40), 1000, 1003]:
        row = rng.uniform(-700, -600, n).astype(dtype)
        for where in {0, n // 2, n - 1}:
            r = row.copy()
            r[where] = -500.0
            assert _row_max(r) == np.float64(r.max()) == -500.0
    assert _row_max(np.full(9, -np.inf, dtype=dtype)) == -np.inf
    row = np.full(13, -np.inf, dtype=dtype)
    row[7] = np.inf
    assert _row_max(row) == np.inf
    assert _row_max(np.array([-0.0, -3.0, 0.0, -1.0], dtype=dtype)) == 0.0
    assert isinstance(_row_max(np.ones(3, dtype=dtype)), float)


@pytest.mark.parametrize("centre_scale", [3.0, 0.4])
@pytest.mark.parametrize("tile_cols", [4096, 100])
def test_float32_agrees_with_float64_on_clustered_data(monkeypatch, centre_scale, tile_cols):
    # eight Gaussian clusters of 32 features, as benchmarks/bench_pnn.py: far
    # apart (7 of 8 classes framed for most queries, most kernel values below
    # float32's normal range) or overlapping (probabilities far from 0 and 1);
    # tiles of a whole class or of 100 patterns
    monkeypatch.setattr(pnn_module, "_TILE_COLS", tile_cols)
    rng = np.random.default_rng(12345)
    centres = rng.normal(0, centre_scale, (8, 32))
    y, y_test = rng.integers(0, 8, 4000), rng.integers(0, 8, 400)
    X = centres[y] + rng.normal(size=(4000, 32))
    T = centres[y_test] + rng.normal(size=(400, 32))
    clf64 = PNNClassifier(spread="auto").fit(X, y)
    clf32 = PNNClassifier(spread=clf64.spread_, dtype="float32").fit(X, y)
    assert T.shape[0] * X.shape[0] > pnn_module._WHOLE_MAX  # the compiled tiles
    # float32 products round g |x - p|^2 to about 1e-6 of itself (3.5e-6 measured)
    np.testing.assert_allclose(
        clf32._joint_log_likelihood(T), clf64._joint_log_likelihood(T), rtol=1e-5
    )
    # 1.8e-6 measured on the overlapping clusters
    np.testing.assert_allclose(clf32.predict_proba(T), clf64.predict_proba(T), atol=1e-5)
    assert np.array_equal(clf32.predict(T), clf64.predict(T))


def test_memory_budget_caps_the_tile(monkeypatch):
    monkeypatch.setattr(pnn_module, "MAX_BLOCK_BYTES", 8 * 40 * 3)
    clf = PNNClassifier().fit(np.arange(80.0)[:, None], [0] * 40 + [1] * 40)
    rows, tiles = clf._tiles(3, 8)
    assert rows * max(b - a for _, a, b in tiles) * 8 * 3 <= pnn_module.MAX_BLOCK_BYTES


@pytest.mark.parametrize("n_threads", [1, 4, 64])
def test_default_budget_bounds_the_working_block_of_all_threads(n_threads):
    # a training class far wider than one tile: the block every thread holds at
    # once stays within the budget, whatever the thread count
    X = np.zeros((50_000, 1))
    clf = PNNClassifier().fit(X, [0] * 25_000 + [1] * 25_000)
    rows, tiles = clf._tiles(n_threads, 8)
    block = rows * max(b - a for _, a, b in tiles) * 8
    assert n_threads * block <= pnn_module.MAX_BLOCK_BYTES


@pytest.mark.parametrize("dtype", ["float64", "float32"])
def test_near_patterns_after_far_ones_in_a_class(rng, monkeypatch, dtype):
    # class 0's first tile lies far from the queries (its frame is a shift), a
    # later tile is near: those tile sums overflow the frame and are redone;
    # class 1 is near from its first tile on (frame 0, no shift)
    far = rng.normal(0, 1, (60, 3)) + np.array([60.0, 0, 0])
    near = rng.normal(0, 1, (60, 3))
    X = np.concatenate([far, near, rng.normal(0, 1, (60, 3)) + np.array([3.0, 0, 0])])
    y = np.array([0] * 120 + [1] * 60)
    T = rng.normal(0, 1, (40, 3))
    monkeypatch.setattr(pnn_module, "_TILE_COLS", 30)
    clf = PNNClassifier(spread=1.0, dtype=dtype).fit(X, y)
    ref = reference_scores(X, y, T, 1.0)
    # float32: the far cluster moves the training mean ~20 away from the queries,
    # and distances from a product of centred data lose ~eps32 * g|x - mean|^2
    rtol = 1e-10 if dtype == "float64" else 2e-4
    np.testing.assert_allclose(clf.class_scores(T), ref, rtol=rtol)
    # and far from everything: log scores stay finite and exact
    far_q = T + np.array([200.0, 0, 0])
    jll = clf._joint_log_likelihood(far_q)
    d2 = ((far_q[:, None, :] - X[None]) ** 2).sum(-1) * (np.log(2) / 1.0)
    ref_log = np.stack(
        [
            np.log(np.exp(-(d2[:, y == c] - d2[:, y == c].min(1, keepdims=True))).mean(1))
            - d2[:, y == c].min(1)
            for c in (0, 1)
        ],
        axis=1,
    )
    np.testing.assert_allclose(jll, ref_log, rtol=1e-9 if dtype == "float64" else 2e-4)


@pytest.mark.parametrize("dtype", ["float64", "float32"])
def test_a_large_framed_sum_rescaled_by_a_much_nearer_pattern(monkeypatch, dtype):
    # one pattern per tile: the first fixes the class's frame 5000 below 0,
    # the second lies 690 above that frame (a sum near 1e300 in it), the third
    # is near the query: re-framing scales the earlier sum by exp(-4900),
    # which is 0, not the smallest value the compiled exp returns
    monkeypatch.setattr(pnn_module, "_TILE_COLS", 1)
    g = np.log(2.0)  # spread 1
    X = np.r_[np.sqrt([5000.0 / g, 4310.0 / g]), 0.5, 3.0][:, None]
    clf = PNNClassifier(spread=1.0, dtype=dtype).fit(X, [0, 0, 0, 1])
    assert len(clf._tiles1[1]) == 4  # the compiled tiles, not the small-batch pass
    ref = np.log(np.exp(-g * X[:3, 0] ** 2).sum() / 3)
    jll = clf._joint_log_likelihood(np.zeros((1, 1)))
    # float32: the product rounds g |x - mean|^2 (about 1200 here) to ~7e-5
    np.testing.assert_allclose(jll[0, 0], ref, rtol=1e-12 if dtype == "float64" else 1e-4)


@pytest.mark.parametrize("spread", [0.3, 3.0])
def test_float32_agrees_with_float64(rng, spread):
    X = rng.normal(size=(400, 8))
    y = rng.integers(0, 3, 400)
    T = rng.normal(size=(100, 8))
    p64 = PNNClassifier(spread=spread).fit(X, y).predict_proba(T)
    clf32 = PNNClassifier(spread=spread, dtype="float32").fit(X, y)
    p32 = clf32.predict_proba(T)
    assert p32.dtype == np.float64
    np.testing.assert_allclose(p32, p64, atol=2e-5)
    np.testing.assert_allclose(p32.sum(axis=1), 1)
    assert clf32._pt.dtype == np.float32


@pytest.mark.parametrize("dtype", ["float64", "float32", np.float32, np.dtype("float64")])
def test_dtype_spellings(dtype):
    clf = PNNClassifier(dtype=dtype).fit([[0.0], [1.0]], [0, 1])
    assert clf.predict([[0.1]]).tolist() == [0]


def test_numeric_spread_is_used_as_is():
    clf = PNNClassifier(spread=0.25).fit([[0.0], [1.0]], [0, 1])
    assert clf.spread_ == clf.spread == 0.25


@pytest.mark.parametrize("scale", [0.01, 1.0, 100.0])
def test_auto_spread_on_separated_clusters(rng, scale):
    # clusters of unit width 20 apart: the spread must sit near the cluster
    # width (not the smallest grid value, not the separation), scale with
    # the data, and classify perfectly
    centres = np.array([[0.0, 0.0], [20.0, 0.0], [0.0, 20.0]])
    y = np.repeat([0, 1, 2], 60)
    X = (centres[y] + rng.normal(size=(180, 2))) * scale
    clf = PNNClassifier(spread="auto").fit(X, y)
    assert clf.spread == "auto"
    assert 0.2 * scale < clf.spread_ < 2.0 * scale
    _, grid, scores = auto_spread(clf.patterns_, np.repeat([0, 1, 2], 60), return_scores=True)
    k = int(np.argmax(scores))
    assert 0 < k < grid.size - 1  # an interior maximum, not an edge of the grid
    T = (centres[y] + rng.normal(size=(180, 2))) * scale
    assert clf.score(T, y) == 1.0


def test_auto_spread_with_one_pattern_per_class():
    X, y = thesis_tentacle(16, return_X_y=True)
    clf = FourierClassifier(spread="auto").fit(X, y)
    pnn = clf.pipeline_.named_steps["classifier"]
    assert np.isfinite(pnn.spread_) and pnn.spread_ > 0
    assert clf.predict(np.roll(X, 5, axis=1)).tolist() == y.tolist()


def test_auto_spread_ignores_duplicates_and_stays_finite():
    X = np.array([[0.0], [0.0], [0.0], [1.0], [1.0], [1.1]])
    clf = PNNClassifier(spread="auto").fit(X, [0, 0, 0, 1, 1, 1])
    assert np.isfinite(clf.spread_) and clf.spread_ > 0
    clf = PNNClassifier(spread="auto").fit(np.zeros((4, 2)), [0, 0, 1, 1])
    assert clf.spread_ > 0


@pytest.mark.parametrize("spacing", [1e-155, 1e-149])
def test_auto_spread_on_patterns_closer_than_the_smallest_spread(spacing):
    # patterns closer than MIN_SPREAD count as duplicates, so the spread never
    # falls below it: 1e-155 apart once overflowed the kernel width in fit
    X = np.array([[0.0], [1.0], [2.0], [3.0]]) * spacing
    clf = PNNClassifier(spread="auto").fit(X, [0, 0, 1, 1])
    assert MIN_SPREAD <= clf.spread_ < np.inf
    assert np.isfinite(clf.predict_proba(X)).all()
    if spacing > MIN_SPREAD:  # told apart when the spread can resolve them
        assert clf.predict(X).tolist() == [0, 0, 1, 1]


def test_rejection_gives_unknown_instead_of_forced_class():
    X, y = thesis_tentacle(16, return_X_y=True)
    clf = FourierClassifier(spread=1.0, reject_below=1e-3).fit(X, y)
    assert clf.predict(X).tolist() == y.tolist()
    star = np.tile([np.pi / 2 + 0.9, -0.9], 8)  # a wavy outline, no thesis class
    star *= 2 * np.pi / star.sum()
    assert clf.predict(star[None]).tolist() == ["unknown"]
    forced = FourierClassifier(spread=1.0).fit(X, y).predict(star[None])
    assert forced[0] in set(y)


def test_labels_of_any_type_round_trip():
    X = [[0.0], [0.1], [1.0], [1.1]]
    for labels in ([3, 3, 7, 7], [True, True, False, False], ["b", "b", "a", "a"]):
        clf = PNNClassifier().fit(X, labels)
        assert clf.predict(X).tolist() == labels


@pytest.mark.parametrize(
    "params, match",
    [
        ({"spread": 0.0}, "spread"),
        ({"spread": np.nan}, "spread"),
        ({"spread": "x"}, "spread"),
        ({"reject_below": 2.0}, "reject_below"),
        ({"spread": "big"}, "spread"),
        ({"dtype": "float16"}, "dtype"),
        ({"dtype": "complex"}, "dtype"),
        ({"spread": 1e-300}, "too small"),  # (b / spread) ** 2 overflowed
        ({"spread": 1e300}, "too large"),  # every kernel 1: chance-level answers
    ],
)
def test_bad_parameters(params, match):
    with pytest.raises(ValueError, match=match):
        PNNClassifier(**params).fit([[0.0], [1.0]], [0, 1])


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda m: m.fit([[0.0], [1.0]], [0]), "inconsistent numbers of samples"),
        (lambda m: m.fit([[0.0], [1.0]], [0.5, 1.5]), "Unknown label type: continuous"),
        (lambda m: m.fit([[0.0], [1.0]], None), "requires y to be passed"),
        (lambda m: m.fit([[0.0], [1.0]], [0, 1]).predict([[0.0, 1.0]]), "X has 2 features"),
        (lambda m: m.fit([[0.0], [1.0]], [0, 1]).predict(np.zeros((0, 1))), "0 sample"),
        (lambda m: m.fit([[0.0], [1.0]], [0, 1]).predict([[np.inf]]), "infinity"),
    ],
)
def test_bad_arrays_are_input_errors(call, match):
    # scikit-learn's checks, with their messages, as errors of tentaclass
    with pytest.raises(InputError, match=match):
        call(PNNClassifier())


def test_single_class_and_nan_are_refused():
    with pytest.raises(ValueError, match="2 classes"):
        PNNClassifier().fit([[0.0], [1.0]], [0, 0])
    with pytest.raises(ValueError, match="NaN"):
        PNNClassifier().fit([[np.nan], [1.0]], [0, 1])


@pytest.mark.parametrize("n_links", [16, 64])
def test_thesis_shapes_from_every_start_point_and_both_directions(n_links):
    X, y = thesis_tentacle(n_links, return_X_y=True)
    clf = FourierClassifier().fit(X, y)
    for k in range(n_links):
        rolled = np.roll(X, k, axis=1)
        assert clf.predict(rolled).tolist() == y.tolist()
        assert clf.predict(-rolled[:, ::-1]).tolist() == y.tolist()
    np.testing.assert_allclose(clf.predict_proba(X).sum(axis=1), 1)


def test_tentacle_classifier_in_cross_validation_and_grid_search(rng):
    X, y = thesis_tentacle(16, return_X_y=True)
    Xs = np.concatenate([np.roll(X, k, axis=1) for k in range(16)])
    ys = np.tile(y, 16)
    Xs = Xs + rng.normal(0, 0.05, Xs.shape)
    scores = cross_val_score(FourierClassifier(detrend=True), Xs, ys, cv=4)
    assert scores.min() == 1.0
    spreads = [0.05, 0.5, 5.0, 50.0]
    grid = GridSearchCV(FourierClassifier(), {"spread": spreads}, cv=3, scoring="neg_log_loss").fit(
        Xs, ys
    )
    # kernels much wider than the gaps between classes flatten the probabilities:
    # the log-loss grows with the spread past the classes' scale
    loss = -grid.cv_results_["mean_test_score"]
    assert loss[0] < 1e-6 and loss[1] < 1e-6
    assert loss[1] < loss[2] < loss[3]
    assert grid.best_params_["spread"] in (0.05, 0.5)
    assert grid.best_estimator_.spread == grid.best_params_["spread"]
    assert grid.best_estimator_.score(Xs, ys) == 1.0


def test_tentacle_classifier_with_another_classifier():
    from sklearn.neighbors import KNeighborsClassifier

    X, y = thesis_tentacle(64, return_X_y=True)
    clf = FourierClassifier(classifier=KNeighborsClassifier(1)).fit(X, y)
    assert clf.predict(np.roll(X, 7, axis=1)).tolist() == y.tolist()
    assert clf.transform(X).shape == (4, 32)


def test_row_logsumexp_is_scipys_to_the_last_bit():
    from scipy.special import logsumexp

    from tentaclass.classifiers._base import _logsumexp_rows

    rng = np.random.default_rng(0)
    for trial in range(300):
        a = rng.normal(size=(rng.integers(1, 20), rng.integers(1, 9))) * 10 ** rng.uniform(-3, 3)
        if trial % 3 == 0:
            a[rng.random(a.shape) < 0.3] = -np.inf  # whole rows too, at times
        if trial % 4 == 0:
            a[:, 0] = a[:, -1]  # equal maxima
        if trial % 5 == 0:
            a -= 800  # every exp underflows
        ref = logsumexp(a, axis=1, keepdims=True)
        assert np.array_equal(_logsumexp_rows(a), ref, equal_nan=True)


def test_probabilities_far_from_every_pattern_still_sum_to_one():
    # found by probing: scores of about -7e201 for every class rounded their
    # differences from the log-sum-exp away, and each probability came out as 1
    X, y = thesis_tentacle(16, return_X_y=True)
    model = PNNClassifier().fit(X, y)
    far = np.r_[1e100, X[0][1:]][None]
    np.testing.assert_allclose(model.predict_proba(far), [[0.25] * 4])
    near = X[:2] + 0.01
    np.testing.assert_allclose(model.predict_proba(near).sum(axis=1), 1.0)


@pytest.mark.parametrize("value", [1e160, -1e300])
def test_a_sample_whose_distances_overflow_is_refused(value):
    X, y = thesis_tentacle(16, return_X_y=True)
    model = PNNClassifier().fit(X, y)
    q = np.vstack([X[:1], np.r_[value, X[0][1:]][None]])
    with pytest.raises(InputError, match=r"X: sample 1 lies too far from the training patterns"):
        model.predict(q)


def test_a_rejection_label_that_is_a_class_is_refused_at_fit():
    rng = np.random.default_rng(0)
    X, y = rng.normal(size=(20, 8)), np.repeat(["a", "b"], 10)
    # was accepted: rejected samples of class b were answered "a"
    clf = PNNClassifier(reject_below=0.9, unknown_label="a")  # errors at fit, not here
    with pytest.raises(InputError, match=r"^unknown_label 'a' is one of the classes"):
        clf.fit(X, y)
    with pytest.raises(InputError, match=r"^unknown_label 1 is one of the classes"):
        PNNClassifier(reject_below=0.9, unknown_label=1).fit(X, np.repeat([1, 2], 10))
    with pytest.raises(InputError, match=r"^unknown_label 'unknown' is one of the classes"):
        FourierClassifier(reject_below=0.9).fit(np.tile(X, 2), np.repeat(["unknown", "b"], 10))
    # without rejection the label is never answered: any class names are fine
    assert PNNClassifier(unknown_label="a").fit(X, y).predict(X[:1])[0] in ("a", "b")
    assert PNNClassifier(reject_below=0.9, unknown_label="1").fit(X, np.repeat([1, 2], 10))
