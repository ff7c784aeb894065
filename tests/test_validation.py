"""The input checks every public entry point shares (tentaclass._validation)."""

import re

import numpy as np
import pytest
from sklearn.pipeline import make_pipeline

from tentaclass._validation import MAX_ANGLE, as_angle_array, check_angle_range
from tentaclass.classifiers import (
    FourierClassifier,
    PNNClassifier,
    RBFNetworkClassifier,
    ShiftNNClassifier,
    TentacleClassifier,
)
from tentaclass.datasets import thesis_tentacle
from tentaclass.errors import InputError, ShapeError
from tentaclass.features import AngleSpectrum, FourierFeatures, LastLap

SQUARE = np.tile([0, 0, 0, np.pi / 2], 4)


@pytest.fixture(scope="module")
def thesis():
    return thesis_tentacle(16, return_X_y=True)


RAGGED = [list(SQUARE), list(SQUARE[:15])]


@pytest.mark.parametrize(
    "make",
    [
        FourierClassifier,
        PNNClassifier,
        RBFNetworkClassifier,
        ShiftNNClassifier,
        lambda: make_pipeline(FourierFeatures(), PNNClassifier()),
        FourierFeatures,
        LastLap,
        AngleSpectrum,
    ],
)
def test_ragged_rows_are_named_by_fit_and_predict(thesis, make):
    X, y = thesis
    message = r"^X: rows have different lengths \(16 and 15, rows 0 and 1\)$"
    with pytest.raises(ShapeError, match=message):
        make().fit(RAGGED, y[:2])
    model = make().fit(X, y)
    use = model.predict if hasattr(model, "predict") else model.transform
    with pytest.raises(ShapeError, match=r"^X: rows have different lengths \(16 and 15"):
        use(RAGGED)


def test_tentacle_classifier_names_ragged_rows(thesis):
    with pytest.raises(ShapeError, match="X: rows have different lengths"):
        TentacleClassifier().fit(RAGGED, thesis[1][:2])
    model = TentacleClassifier().fit(*thesis)
    with pytest.raises(ShapeError, match=r"^X: rows have different lengths \(16 and 15"):
        model.predict(RAGGED)


@pytest.mark.parametrize(
    "x, where",
    [
        ([[1.0, 2.0], [3.0]], "2 and 1, rows 0 and 1"),
        ([[1.0, 2.0], [3.0, 4.0], 5.0], "2 and a number, rows 0 and 2"),
        ([[[1.0, 2.0], [3.0, 4.0]], [[1.0, 2.0], [3.0]]], r"2 and 1, rows \[0, 0\] and \[1, 1\]"),
    ],
)
def test_ragged_input_names_the_rows(x, where):
    with pytest.raises(ShapeError, match=rf"^q: rows have different lengths \({where}\)$"):
        as_angle_array(x, "q", min_joints=1)


def test_angles_within_the_limit_pass_and_beyond_are_refused():
    assert MAX_ANGLE == pytest.approx(2 * np.pi * 2**20)
    ok = np.tile(SQUARE, (3, 1))
    ok[1, 3] = -MAX_ANGLE
    np.testing.assert_array_equal(as_angle_array(ok, "q"), ok)
    bad = ok.copy()
    bad[2, 5] = np.nextafter(MAX_ANGLE, np.inf)
    with pytest.raises(InputError, match=r"^q: array 2 holds an angle of 6.588e\+06 rad, beyond"):
        as_angle_array(bad, "q")
    with pytest.raises(InputError, match=r"^f: array 7 holds"):
        check_angle_range(bad, "f", first=5)
    # only joint angles are bounded: velocities and torques may be large
    assert as_angle_array(bad, "qd", bounded=False) is not None


def test_an_angle_check_refuses_nan_it_is_given():
    with pytest.raises(InputError, match="holds an angle of nan"):
        check_angle_range(np.r_[np.nan, SQUARE], "q")


def _huge_count_calls():
    from tentaclass import datasets, shapes
    from tentaclass.features import outline_to_series
    from tentaclass.geometry import resample_closed
    from tentaclass.scanner import LineScanner, ScannerModel
    from tentaclass.scanner.simulate import draw_shape, make_belt, make_objects
    from tentaclass.wrapping import max_link_length

    sq = shapes.square(4.0)
    grids = [np.ones((10, 10), bool)] * 2
    return [
        (lambda: resample_closed(sq, 10**10), "n must be at most 1,000,000"),
        (lambda: resample_closed(np.stack([sq] * 20_000), 10**6), "more than the 1,000,000,000"),
        (lambda: outline_to_series(sq, 10**10), "n_points must be at most 1,000,000"),
        (lambda: shapes.circle(1.0, 10**10), "n_points must be at most 1,000,000"),
        (lambda: shapes.regular_polygon(10**10, 1.0), "n_sides must be at most 1,000,000"),
        (lambda: shapes.from_stroke(sq, 10**10), "n_points must be at most 1,000,000"),
        (lambda: datasets.synthetic_tentacle(10**12), "n_samples must be at most 100,000,000"),
        (lambda: datasets.synthetic_tentacle(2, 10**12), "n_links must be at most 100,000"),
        (lambda: datasets.synthetic_tentacle(10**6, 10**5), "more than the 1,000,000,000"),
        (lambda: datasets.drawn_shapes(10**10), "n_per_class must be at most 100,000,000"),
        (lambda: datasets.drawn_shapes(10**8), "more than the 100,000,000 allowed"),
        (lambda: datasets.reference_tentacle(16, 10**10), "n_starts must be at most 100,000,000"),
        (lambda: datasets.chain_wraps([sq], 10**10), "n_links must be at most 100,000"),
        (lambda: datasets.chain_wraps([sq], 16, n_wraps=10**10), "n_wraps must be at most"),
        (lambda: max_link_length(sq, 0.1, n_grid=10**10), "n_grid must be at most 1,000,000"),
        (lambda: make_objects(10**10), "n_objects must be at most 100,000,000"),
        (lambda: make_objects(1, shape=(10**6, 10**6)), "more than the 1,000,000,000"),
        (lambda: draw_shape("square", (10**6, 10**6), 3.0), "more than the 1,000,000,000"),
        (lambda: make_belt(10**10), "n_objects must be at most 100,000,000"),
        (lambda: make_belt(1, 10**10), "more than the 1,000,000,000"),
        (lambda: make_belt(2, 10**10, lanes=10**10 // 128), "belt image \\(rows x width\\)"),
        (lambda: ScannerModel(n_points=10**10).fit(grids, ["a", "b"]), "n_points must be at most"),
        (lambda: LineScanner(64, latency=10**12), "more than the 1,000,000,000"),
    ]


def test_an_outline_resamples_to_as_many_points_as_it_has_beyond_the_limit():
    from tentaclass.geometry import resample_closed

    n = 1_000_010
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    ring = np.column_stack([np.cos(t), np.sin(t)])
    np.testing.assert_allclose(resample_closed(ring, n), ring, atol=1e-9)


@pytest.mark.parametrize("index", range(len(_huge_count_calls())))
def test_huge_counts_are_refused_naming_the_limit(index):
    call, message = _huge_count_calls()[index]
    with pytest.raises(InputError, match=message):
        call()


@pytest.mark.parametrize(
    "x, message",
    [
        # NumPy reads each of these as numbers: True as 1 rad, "1" as 1.0, a date as its
        # seconds, and a masked value as what lies under the mask
        (SQUARE > 0, "q must hold numbers, got booleans (dtype bool)"),
        ([True] * 16, "q must hold numbers, got booleans (dtype bool)"),
        (SQUARE.astype(str), "q must hold numbers, got dtype <U"),
        (np.ones(16, "datetime64[s]"), "q must hold numbers, got dtype datetime64[s]"),
        (np.array([*SQUARE[:15], "1"], dtype=object), "q must hold numbers, got str '1'"),
        (np.array([*SQUARE[:15], True], dtype=object), "q must hold numbers, got bool True"),
        (np.ma.masked_array(SQUARE, mask=SQUARE > 1), "q holds 4 masked value(s): fill or drop"),
    ],
)
def test_angle_arrays_of_what_is_not_numbers_are_refused(x, message):
    from tentaclass import fourier_features, split_laps, turning_function

    for func in (turning_function, fourier_features, split_laps):
        with pytest.raises(InputError, match=re.escape(message)):
            func(x)


def test_arrays_of_numbers_of_any_kind_are_taken():
    from tentaclass import turning_function

    expected = turning_function(SQUARE)
    for x in (SQUARE.astype(object), np.ma.masked_array(SQUARE), SQUARE.tolist()):
        np.testing.assert_array_equal(turning_function(x), expected)
    np.testing.assert_array_equal(turning_function(np.zeros(16, np.int8)), np.zeros(16))


@pytest.mark.parametrize(
    "make", [PNNClassifier, RBFNetworkClassifier, ShiftNNClassifier, TentacleClassifier]
)
def test_labels_of_kinds_that_do_not_sort_together_are_named(thesis, make):
    # numpy's sort raised TypeError: '<' not supported between instances of 'int' and 'str'
    X, _ = thesis
    y = np.array(["a", 1] * (len(X) // 2), dtype=object)
    with pytest.raises(InputError, match=r"y mixes labels of kinds that cannot be sorted together "
                       r"\(int, str\): give labels of one kind"):  # fmt: skip
        make().fit(X[: len(y)], y)
