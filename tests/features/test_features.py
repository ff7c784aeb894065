import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from strategies import closed_laps, examples
from tentaclass import angles_to_points, points_to_angles
from tentaclass._validation import MAX_ANGLE
from tentaclass.errors import InputError
from tentaclass.features import (
    AngleSpectrum,
    FourierFeatures,
    canonical_direction,
    dft_layer,
    fourier_features,
    periodic_signal,
    turning_function,
)


@settings(deadline=None, max_examples=examples(80))
@given(closed_laps(), st.integers(0, 1000))
def test_features_invariant_to_start_point(q, shift):
    np.testing.assert_allclose(
        fourier_features(np.roll(q, shift)), fourier_features(q), atol=1e-9, rtol=1e-9
    )


@settings(deadline=None, max_examples=examples(80))
@given(closed_laps(), st.integers(0, 1000))
def test_features_invariant_to_direction(q, shift):
    other_way = -np.roll(q, shift)[::-1]
    np.testing.assert_allclose(fourier_features(other_way), fourier_features(q), atol=1e-9)


@settings(deadline=None, max_examples=examples(60))
@given(closed_laps(max_n=40), st.floats(1e-3, 1e3), st.floats(-np.pi, np.pi))
def test_features_independent_of_link_length_and_rotation(q, length, rotation):
    # the chain drawn with other link lengths and rotated measures the same angles
    p = angles_to_points(q, link_lengths=length, heading=rotation)
    q_measured = points_to_angles(p, closed=False, heading=rotation)
    np.testing.assert_allclose(fourier_features(q_measured), fourier_features(q), atol=1e-7)


@settings(deadline=None, max_examples=examples(60))
@given(closed_laps(max_n=40), st.floats(-np.pi, np.pi))
def test_turning_function_shifts_by_a_constant_under_rotation(q, rotation):
    p = angles_to_points(q)
    c, s = np.cos(rotation), np.sin(rotation)
    rotated = p @ np.array([[c, s], [-s, c]])
    q_rot = points_to_angles(rotated, closed=False)  # measured from the x axis
    diff = turning_function(q_rot) - turning_function(q)
    diff = np.mod(diff - diff[0] + np.pi, 2 * np.pi) - np.pi
    np.testing.assert_allclose(diff, 0, atol=1e-9)


@pytest.mark.parametrize("n", [1, 2, 3, 8, 15, 16, 64, 101])
def test_dft_layer_equals_numpy_fft(n, rng):
    w_cos, w_sin = dft_layer(n)
    x = rng.normal(size=(5, n))
    np.testing.assert_allclose(x @ w_cos.T + 1j * (x @ w_sin.T), np.fft.fft(x), atol=1e-12)


@pytest.mark.parametrize("n", [3, 4, 16, 63, 64, 200])
@pytest.mark.parametrize("detrend", [False, True])
def test_features_equal_definition_for_both_methods(n, detrend, rng):
    q = rng.normal(0, 0.2, size=(40, n)) + 2 * np.pi / n
    q[::3] *= -1  # some clockwise rows
    canon = canonical_direction(q)
    expected = np.abs(np.fft.fft(periodic_signal(canon, detrend=detrend), axis=-1))[
        :, 1 : n // 2 + 1
    ]
    for method in ("matmul", "fft", "auto"):
        got = fourier_features(q, detrend=detrend, method=method)
        np.testing.assert_allclose(got, expected, atol=1e-10)


def test_thesis_square_features_known_values():
    square = np.tile([0, 0, 0, np.pi / 2], 4)
    f = fourier_features(square)
    # only every 4th harmonic is non-zero; k = 8 (Nyquist) is sum(E_j (-1)^j) = pi
    np.testing.assert_allclose(f[[0, 1, 2, 4, 5, 6]], 0, atol=1e-12)
    np.testing.assert_allclose(f[7], np.pi, atol=1e-12)
    np.testing.assert_allclose(fourier_features(np.full(16, np.pi / 8)), 0, atol=1e-12)


def test_n_harmonics_and_normalize(rng):
    q = rng.normal(size=(4, 32))
    full = fourier_features(q)
    assert full.shape == (4, 16)
    np.testing.assert_allclose(fourier_features(q, 5), full[:, :5])
    np.testing.assert_allclose(fourier_features(q, normalize=True), full / 32)


def test_detrend_removes_total_turn_drift():
    q = np.full(16, np.pi / 8) + 0.01  # a circle whose encoders all read 0.01 too much
    assert fourier_features(q).max() > 0.1
    np.testing.assert_allclose(fourier_features(q, detrend=True), 0, atol=1e-12)


@pytest.mark.parametrize("shape", [(16,), (3, 16), (2, 3, 16), (1, 1, 16)])
def test_feature_shape_table_and_batch_equals_loop(shape, rng):
    q = rng.normal(size=shape)
    f = fourier_features(q)
    assert f.shape == (*shape[:-1], 8)
    flat = q.reshape(-1, 16)
    np.testing.assert_allclose(f.reshape(-1, 8), [fourier_features(r) for r in flat])


def test_periodic_signal_ramp_and_degrees():
    q = np.full(8, 45.0)
    np.testing.assert_allclose(periodic_signal(q, period=360), 0, atol=1e-12)
    np.testing.assert_allclose(periodic_signal(np.zeros(4)), -2 * np.pi * np.arange(1, 5) / 4)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"q": [1.0]}, "at least 2"),
        ({"q": [0, np.inf, 0]}, "NaN or infinite"),
        ({"q": [[]]}, "empty"),
        ({"q": np.zeros(8), "n_harmonics": 5}, "at most"),
        ({"q": np.zeros(8), "n_harmonics": 0}, "at least 1"),
        ({"q": np.zeros(8), "method": "dct"}, "method"),
        ({"q": "abc"}, "must hold numbers, got dtype <U3"),
        # a string would read as true
        ({"q": np.zeros(8), "detrend": "no"}, "detrend must be True or False, got 'no'"),
        ({"q": np.zeros(8), "normalize": 2}, "normalize must be True or False"),
        ({"q": np.zeros(8), "canonicalize": None}, "canonicalize must be True or False"),
    ],
)
def test_bad_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        fourier_features(**kwargs)


def test_transformer_matches_function(rng):
    X = rng.normal(size=(6, 20))
    t = FourierFeatures(n_harmonics=7, detrend=True).fit(X)
    np.testing.assert_allclose(t.transform(X), fourier_features(X, 7, detrend=True))
    assert t.get_feature_names_out().tolist()[:2] == ["fourier1", "fourier2"]
    with pytest.raises(ValueError, match="features"):
        t.transform(X[:, :10])
    with pytest.raises(ValueError, match="n_harmonics"):
        FourierFeatures(n_harmonics=11).fit(X)


def test_transformer_weight_power(rng):
    X = rng.normal(size=(5, 16))
    plain = FourierFeatures().fit_transform(X)
    weighted = FourierFeatures(weight_power=0.5).fit_transform(X)
    np.testing.assert_allclose(weighted, plain * np.sqrt(np.arange(1, 9)))
    with pytest.raises(ValueError, match="weight_power"):
        FourierFeatures(weight_power=np.nan).fit(X)


def test_transformer_fractional_n_harmonics(rng):
    X = rng.normal(size=(3, 64))
    t = FourierFeatures(n_harmonics=0.5).fit(X)
    assert t.n_harmonics_ == 16 and t.n_harmonics == 0.5
    np.testing.assert_allclose(t.transform(X), fourier_features(X, 16))
    assert FourierFeatures(n_harmonics=0.01).fit(X).n_harmonics_ == 1
    with pytest.raises(ValueError, match="fractional"):
        FourierFeatures(n_harmonics=1.5).fit(X)


def test_angle_spectrum_known_values():
    square = np.tile([0.0, 0.0, 0.0, np.pi / 2], 4)[None]
    f = AngleSpectrum().fit_transform(square)
    assert f.shape == (1, 9)
    # the mean turn (2 pi / 16) and the harmonics of period 4 survive
    expected = np.zeros(9)
    expected[[0, 4, 8]] = np.pi / 8
    np.testing.assert_allclose(f[0], expected, atol=1e-12)
    twice = np.tile([0.0, np.pi / 2], 8)[None]  # a smaller square, two laps in 16 joints
    assert AngleSpectrum(n_harmonics=1).fit_transform(twice)[0, 0] == pytest.approx(np.pi / 4)


@settings(max_examples=examples(40), deadline=None)
@given(st.integers(0, 30), st.integers(4, 40))
def test_angle_spectrum_ignores_where_the_chain_starts(shift, n):
    q = np.random.default_rng(n).normal(size=(2, n))
    t = AngleSpectrum().fit(q)
    np.testing.assert_allclose(t.transform(np.roll(q, shift, axis=1)), t.transform(q), atol=1e-12)
    np.testing.assert_allclose(t.transform(q[:, ::-1]), t.transform(q), atol=1e-12)


@pytest.mark.parametrize("n_harmonics", [0, 10, 2.5, True])
def test_angle_spectrum_bad_n_harmonics(n_harmonics):
    with pytest.raises(ValueError, match="n_harmonics"):
        AngleSpectrum(n_harmonics=n_harmonics).fit(np.zeros((2, 16)))


def test_angle_spectrum_feature_names():
    X = np.ones((2, 8))
    assert AngleSpectrum(3).fit(X).get_feature_names_out().tolist() == [
        "spectrum0", "spectrum1", "spectrum2"
    ]  # fmt: skip


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"n_harmonics": "half"}, "n_harmonics must be a number"),
        ({"weight_power": "x"}, "weight_power must be a finite number"),
        # 8 ** 1e300 overflowed to infinite features with a RuntimeWarning
        ({"weight_power": 1e300}, "weight_power 1e[+]300 is out of range: 8 [*][*] 1e[+]300"),
        ({"weight_power": -400.0}, "weight_power -400 is out of range"),
        ({"detrend": "yes"}, "detrend must be True or False"),
        ({"normalize": 1}, "normalize must be True or False"),
        ({"n_harmonics": 8.0}, None),  # an integral float counts frequencies
    ],
)
def test_transformer_option_types(kwargs, match, rng):
    X = rng.normal(size=(2, 16))
    if match is None:
        assert FourierFeatures(**kwargs).fit(X).n_harmonics_ == 8
        return
    with pytest.raises(ValueError, match=match):
        FourierFeatures(**kwargs).fit(X)


@pytest.mark.parametrize(
    "q, where",
    [
        (np.r_[1e300, np.zeros(17)], "q holds an angle of 1e+300 rad"),
        (np.full(2, 8.98846567e307), "q holds an angle of 8.988e+307 rad"),
        (np.stack([np.full(19, 0.3), np.full(19, -3.11463753e306)]), "q: array 1 holds"),
        (np.r_[np.nextafter(MAX_ANGLE, np.inf), np.zeros(17)], "q holds an angle of 6.588e+06"),
    ],
)
def test_angles_beyond_the_bound_are_refused(q, where):
    # features of such angles are huge or overflow: not joint angles in radians
    with pytest.raises(ValueError, match=rf"^{re.escape(where)}.*beyond 2\*\*20 turns"):
        fourier_features(q)


def test_angles_up_to_the_bound_give_features_linear_in_them():
    # with detrend the signal is linear in q: features at the bound scale with it
    one = np.r_[1.0, np.zeros(17)]
    for method in ("matmul", "fft"):
        f = fourier_features(np.stack([MAX_ANGLE * one, -MAX_ANGLE * one]), detrend=True,
                             method=method)  # fmt: skip
        ref = fourier_features(one, detrend=True, method=method)
        np.testing.assert_allclose(f, [MAX_ANGLE * ref, MAX_ANGLE * ref], rtol=1e-12)


def test_huge_coordinates_give_the_angles_of_the_shape():
    # points_to_angles scales the outline first: products of 1e300 coordinates stay finite
    square = np.array([(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)])
    for scale in (1e300, 1.7e308, 1e-300):
        np.testing.assert_allclose(points_to_angles(square * scale), np.full(4, np.pi / 2))


@pytest.mark.parametrize(
    "n, kwargs", [(16, {}), (64, {}), (64, {"detrend": True, "n_harmonics": 7}), (128, {})]
)
def test_matmul_tiles_on_two_threads_give_the_same_bits_as_on_one(n, kwargs, rng, monkeypatch):
    from threadpoolctl import threadpool_info, threadpool_limits

    from tentaclass.features import fourier

    # any batch of several tiles goes to two threads (but short chains: one)
    monkeypatch.setattr(fourier, "_THREADED_MIN_WORK", 0)
    threads_used = []

    def spy(threads, work, starts):
        threads_used.append(threads)
        run_threads(threads, work, starts)

    run_threads = fourier._run_threads
    monkeypatch.setattr(fourier, "_run_threads", spy)
    # several tiles and a short last one, a third of them clockwise
    q = rng.normal(0, 0.3, size=(5 * fourier._TILE_ROWS + 37, n)) + 2 * np.pi / n
    q[::3] = -q[::3, ::-1]
    with threadpool_limits(1, user_api="blas"):
        one = fourier_features(q, method="matmul", **kwargs)
    with threadpool_limits(2, user_api="blas"):
        two = fourier_features(q, method="matmul", **kwargs)
        # the BLAS setting is back as the caller made it
        assert {i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas"} == {2}
    assert threads_used == [1, 1 if n <= fourier._ONE_THREAD_MAX_JOINTS else 2]
    assert np.array_equal(one, two)
    # row by row, without tiles or threads, the same numbers up to rounding
    np.testing.assert_allclose(
        one[::97], [fourier_features(r, method="fft", **kwargs) for r in q[::97]], atol=1e-10
    )


def test_matmul_tiles_called_from_several_threads_at_once(rng):
    from concurrent.futures import ThreadPoolExecutor

    from threadpoolctl import threadpool_info, threadpool_limits

    qs = [rng.normal(0, 0.3, size=(9000 + 100 * i, 64)) + np.pi / 32 for i in range(4)]
    expected = [fourier_features(q) for q in qs]
    with threadpool_limits(2, user_api="blas"), ThreadPoolExecutor(4) as pool:
        got = list(pool.map(fourier_features, qs * 3))
        # each call's hold on BLAS ends with the last of them, not before nor never
        assert {i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas"} == {2}
    # OpenBLAS may round a few rows of a product differently when it is called
    # from a thread other than the main one (seen on AMD EPYC: 1 ulp in the rows
    # at its block edges), so the same numbers up to that rounding
    for g, e in zip(got, expected * 3, strict=True):
        np.testing.assert_allclose(g, e, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize(
    "bad, match",
    [
        (np.nan, r"^q contains 1 NaN or infinite value\(s\)"),
        (-np.inf, r"^q contains 1 NaN or infinite value\(s\)"),
        (1e300, r"^q: array 4321 holds an angle of 1e\+300 rad, beyond 2\*\*20 turns"),
    ],
)
@pytest.mark.parametrize("threads", [1, 2])
def test_bad_angle_deep_in_a_large_batch_is_refused(bad, match, threads, rng, monkeypatch):
    from threadpoolctl import threadpool_limits

    from tentaclass.features import fourier

    # the matrix-product path checks the values tile by tile, on every thread
    monkeypatch.setattr(fourier, "_THREADED_MIN_WORK", 0)
    q = rng.normal(0, 0.3, size=(6000, 64)) + np.pi / 32
    q[4321, 17] = bad
    with threadpool_limits(threads, user_api="blas"), pytest.raises(ValueError, match=match):
        fourier_features(q, method="matmul")


def test_dft_layer_too_large_to_hold_is_refused():
    # n = 1e6 asked numpy for 7.28 TiB (MemoryError)
    with pytest.raises(InputError, match=r"^the DFT layer of n = 1,000,000 .* would hold 2,000"):
        dft_layer(10**6)
    with pytest.raises(InputError, match=r"n = 22,361 .* 1,000,028,642 values, more than"):
        dft_layer(22_361)


def test_one_blas_thread_holds_blas_on_one_thread_and_restores_it():
    from threadpoolctl import threadpool_info, threadpool_limits

    from tentaclass.features.fourier import _blas_controller, _blas_libraries, _one_blas_thread

    # the controllers are found once per process: find them again, so that they
    # include any BLAS library that earlier tests loaded since
    _blas_controller.cache_clear()
    _blas_libraries.cache_clear()

    def blas_threads():
        return {i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas"}

    with threadpool_limits(2, user_api="blas"):
        with _one_blas_thread() as threads:
            assert threads == 2 and blas_threads() <= {1}
            with _one_blas_thread() as inner:  # nested: the user's setting, still held
                assert inner == 2 and blas_threads() <= {1}
            assert blas_threads() <= {1}
        assert blas_threads() <= {2}
        with pytest.raises(KeyError), _one_blas_thread():
            raise KeyError("inside")
        assert blas_threads() <= {2}  # restored after an error too
    with threadpool_limits(1, user_api="blas"), _one_blas_thread() as threads:
        assert threads == 1 and blas_threads() <= {1}
