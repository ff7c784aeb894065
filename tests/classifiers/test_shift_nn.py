import numpy as np
import pytest

from tentaclass.classifiers._shift_nn import ShiftNNClassifier
from tentaclass.datasets import thesis_tentacle
from tentaclass.geometry import angles_to_points


def brute_force(A, B, mirror):
    A = A - A.mean(1, keepdims=True)
    B = B - B.mean(1, keepdims=True)
    n = A.shape[1]
    out = np.empty((len(B), len(A)))
    for i, b in enumerate(B):
        for j, a in enumerate(A):
            cands = [((b - np.roll(a, s)) ** 2).sum() for s in range(n)]
            if mirror:
                cands += [((b - np.roll(a[::-1], s)) ** 2).sum() for s in range(n)]
            out[i, j] = min(cands)
    return out


@pytest.mark.parametrize("mirror", [True, False])
def test_distances_equal_brute_force(mirror, rng):
    A, B = rng.normal(size=(6, 13)), rng.normal(size=(4, 13))
    clf = ShiftNNClassifier(signal="raw", mirror=mirror).fit(A, np.arange(6))
    np.testing.assert_allclose(clf.shift_distances(B), brute_force(A, B, mirror), atol=1e-9)


def test_turning_signal_recognises_thesis_shapes_any_start_and_direction():
    X, y = thesis_tentacle(64, return_X_y=True)
    clf = ShiftNNClassifier().fit(X, y)
    for k in (0, 7, 33):
        rolled = np.roll(X, k, axis=1)
        assert clf.predict(rolled).tolist() == y.tolist()
        assert clf.predict(-rolled[:, ::-1]).tolist() == y.tolist()


def test_bad_signal_option():
    with pytest.raises(ValueError, match="signal"):
        ShiftNNClassifier(signal="dct").fit(np.zeros((2, 8)), [0, 1])
    for kw in ({"mirror": "no"}, {"center": None}):  # were read as truthy / falsy
        with pytest.raises(ValueError, match=next(iter(kw))):
            ShiftNNClassifier(**kw).fit(np.zeros((2, 8)), [0, 1])


def brute_force_procrustes(za, zb, mirror):
    """min over shifts and rotations of |zb - e^{i t} roll(za, s)|^2 by least squares."""
    cands = [za] + ([np.conj(za[::-1])] if mirror else [])
    best = np.inf
    for c in cands:
        for s in range(len(za)):
            a = np.roll(c, s)
            rot = np.vdot(a, zb) / np.vdot(a, a)  # best complex factor ...
            rot /= abs(rot)  # ... restricted to a pure rotation
            best = min(best, np.sum(np.abs(zb - rot * a) ** 2))
    return best


@pytest.mark.parametrize("mirror", [True, False])
def test_shape_distances_equal_brute_force_procrustes(mirror, rng):
    from tentaclass.classifiers._shift_core import _closed_polygon

    A, B = rng.normal(0.4, 0.2, size=(5, 12)), rng.normal(0.4, 0.2, size=(3, 12))
    clf = ShiftNNClassifier(signal="shape", mirror=mirror).fit(A, np.arange(5))
    za, zb = _closed_polygon(A), _closed_polygon(B)
    expected = [[brute_force_procrustes(a, b, mirror) for a in za] for b in zb]
    np.testing.assert_allclose(clf.shift_distances(B), expected, atol=1e-9)


def test_shape_signal_ignores_start_direction_rotation_and_link_length():
    X, y = thesis_tentacle(64, return_X_y=True)
    clf = ShiftNNClassifier(signal="shape").fit(X, y)
    cw = -X[:, ::-1]  # the same wraps, the other way round
    for q in (X, np.roll(X, 11, axis=1), cw, np.roll(cw, 5, axis=1)):
        d = clf.shift_distances(q)
        np.testing.assert_allclose(np.diag(d), 0.0, atol=1e-9)
        assert clf.predict(q).tolist() == y.tolist()


def test_shape_signal_spreads_closure_errors():
    from tentaclass.classifiers._shift_core import _closed_polygon

    X, _ = thesis_tentacle(64, return_X_y=True)
    noisy = X + np.random.default_rng(3).normal(0, 0.05, X.shape)
    z = _closed_polygon(noisy)
    np.testing.assert_allclose(z.mean(axis=1), 0.0, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(z, axis=1), 1.0)
    # the open chain drifts; the closed polygon stays nearer the noise-free one
    p = angles_to_points(noisy)[:, :-1]
    open_z = p[..., 0] + 1j * p[..., 1]
    open_z -= open_z.mean(axis=1, keepdims=True)
    open_z /= np.linalg.norm(open_z, axis=1, keepdims=True)
    clean = _closed_polygon(X)
    assert np.abs(z - clean).max() < 0.5 * np.abs(open_z - clean).max()


@pytest.mark.parametrize("n_harmonics, power", [(3, 0.0), (0.5, 1.0), (None, 0.5)])
def test_weighted_distances_equal_brute_force_on_filtered_signals(n_harmonics, power, rng):
    A, B = rng.normal(size=(5, 14)), rng.normal(size=(3, 14))
    clf = ShiftNNClassifier(signal="raw", n_harmonics=n_harmonics, weight_power=power)
    clf.fit(A, np.arange(5))
    top = {3: 3, 0.5: 4, None: 7}[n_harmonics]
    k = np.arange(8)
    w = np.where(k <= top, np.maximum(k, 1) ** power, 0.0)

    def filtered(X):
        X = X - X.mean(axis=1, keepdims=True)
        return np.fft.irfft(np.fft.rfft(X, axis=1) * w, n=14, axis=1)

    expected = brute_force(filtered(A), filtered(B), mirror=True)
    np.testing.assert_allclose(clf.shift_distances(B), expected, atol=1e-9)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"n_harmonics": 0}, "n_harmonics must be between"),
        ({"n_harmonics": 9}, "n_harmonics must be between"),
        ({"n_harmonics": 1.5}, "fractional n_harmonics"),
        ({"n_harmonics": "all"}, "n_harmonics must be a number"),
        ({"weight_power": np.nan}, "weight_power must be a finite number"),
        ({"signal": "shape", "weight_power": "x"}, "weight_power must be a finite number"),
    ],
)
def test_bad_harmonic_options(kwargs, match):
    X = np.random.default_rng(0).normal(0.4, 0.1, size=(4, 16))
    with pytest.raises(ValueError, match=match):
        ShiftNNClassifier(**kwargs).fit(X, [0, 0, 1, 1])


def test_chord_closure_matches_a_chain_that_stops_short():
    from tentaclass.classifiers._shift_core import _closed_polygon

    X, y = thesis_tentacle(64, return_X_y=True)
    short = X[:, :60]  # the last 4 links missing: a straight gap closes the lap
    z = _closed_polygon(short, "chord")
    np.testing.assert_allclose(z.mean(axis=1), 0.0, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(z, axis=1), 1.0)
    # equal arc-length steps: straight steps all alike, only corners cut shorter
    steps = np.abs(np.diff(np.concatenate([z, z[:, :1]], axis=1), axis=1))
    alike = np.isclose(steps, np.median(steps, axis=1, keepdims=True), rtol=0.02)
    assert np.all(alike.mean(axis=1) > 0.75)
    clf = ShiftNNClassifier(signal="shape", closure="chord").fit(X[:, :60], y)
    rotated = short.copy()
    rotated[:, 0] += 0.7  # the same chain, turned as a whole
    for q in (short, rotated):
        np.testing.assert_allclose(np.diag(clf.shift_distances(q)), 0.0, atol=1e-9)
    assert clf.predict(rotated).tolist() == y.tolist()


def test_bad_closure_option():
    with pytest.raises(ValueError, match="closure must be"):
        ShiftNNClassifier(signal="shape", closure="zip").fit(np.ones((2, 8)), [0, 1])


@pytest.mark.parametrize(
    "params",
    [
        {"signal": "raw"},
        {"signal": "turning"},
        {"signal": "shape"},
        {"signal": "raw", "mirror": False, "n_harmonics": 0.5, "weight_power": 1.0},
    ],
)
def test_predict_is_the_exhaustive_nearest_neighbour(params):
    # predict prunes with a lower bound; it must answer what the full distance
    # matrix answers, also the first of equal distances (duplicated rows)
    rng = np.random.default_rng(4)
    t = 2 * np.pi * np.arange(48) / 48
    base = rng.normal(size=(6, 4, 1)) * np.cos(np.arange(1, 5)[:, None] * t + rng.random((6, 4, 1)))
    y = rng.integers(0, 6, 300)
    X = np.stack([np.roll(base[k].sum(0), rng.integers(48)) for k in y])
    X += 0.4 * rng.normal(size=X.shape)
    X = np.concatenate([X, X[:40]])
    y = np.concatenate([y, (y[:40] + 1) % 6])  # the duplicates carry other labels
    clf = ShiftNNClassifier(**params).fit(X, y)
    Q = np.concatenate([X[:60] + 0.01 * rng.normal(size=(60, 48)), X[:20]])
    expected = clf.labels_[np.argmin(clf.shift_distances(Q), axis=1)]
    assert np.array_equal(clf.labels_[clf._nearest(Q)], expected)
    assert np.array_equal(clf.predict(Q), clf.classes_[expected])
