"""Grey-level rows: thresholds, polarity, uneven light, any chunking, bad input."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tentaclass.errors import InputError
from tentaclass.scanner import LineScanner
from tentaclass.scanner.simulate import make_belt
from tentaclass.scanner.threshold import choose_threshold


def _belt(seed=5, n=10, width=128):
    belt = make_belt(
        n, width=width, lanes=2, gap=(4, 12), random_state=seed, radius_range=(5.0, 14.0)
    )
    pad = np.zeros((16, width), dtype=bool)  # quiet belt first: the calibration rows
    return np.concatenate([pad, belt.image])


def _grey(mask, polarity, dtype, slope, seed=0):
    """A camera's view of ``mask``: belt level rising across the line, noise, objects."""
    rng = np.random.default_rng(seed)
    width = mask.shape[1]
    top = 1000.0 if dtype == np.uint16 else 1.0 if dtype == np.float32 else 60.0
    belt = top * (1.0 + slope * np.linspace(0.0, 1.0, width))[None, :] * np.ones(mask.shape)
    noise = rng.normal(0.0, 0.01 * top, mask.shape)
    obj = belt * 0.25 if polarity == "dark" else belt * 2.0
    img = np.where(mask, obj, belt) + noise
    return np.clip(img, 0, None).astype(dtype)


def _feed(image, chunks, **kwargs):
    scanner = LineScanner(image.shape[1], **kwargs)
    out, i = [], 0
    for step in chunks:
        out += scanner.feed(image[i : i + step])
        i += step
    out += scanner.feed(image[i:]) if i < len(image) else []
    return [o.to_dict() for o in out + scanner.close()], scanner


def _summary(objs):
    return [(o["bbox"], o["area"]) for o in objs]


@pytest.mark.parametrize("polarity", ["dark", "light"])
@pytest.mark.parametrize("dtype", [np.uint8, np.uint16, np.float32])
@pytest.mark.parametrize("slope", [0.0, 0.8])
def test_grey_rows_give_the_binary_objects_for_any_chunking(polarity, dtype, slope):
    mask = _belt()
    ref, _ = _feed(mask, [len(mask)])
    img = _grey(mask, polarity, dtype, slope)
    whole, scanner = _feed(img, [len(img)])
    t = scanner.threshold_
    assert t.polarity == polarity  # chosen from the data
    assert t.mode == ("adaptive" if slope else "fixed")
    assert _summary(whole) == _summary(ref)
    assert [o["label"] for o in whole] == [o["label"] for o in ref]
    one, _ = _feed(img, [1] * len(img))
    rng = np.random.default_rng(int(slope * 10) + len(polarity))
    random, _ = _feed(img, rng.integers(1, 40, size=len(img)).tolist())
    assert one == whole and random == whole


@settings(max_examples=10, deadline=None)
@given(
    seed=st.integers(0, 1000),
    cuts=st.lists(st.integers(1, 30), min_size=1, max_size=6),
    polarity=st.sampled_from(["dark", "light"]),
)
def test_chunking_invariance_property_grey_uneven_light(seed, cuts, polarity):
    mask = _belt(seed, n=4, width=64)
    img = _grey(mask, polarity, np.uint8, 1.0, seed)
    whole, _ = _feed(img, [len(img)])
    steps = (cuts * len(img))[: len(img)]
    assert _feed(img, steps)[0] == whole
    assert _summary(whole) == _summary(_feed(mask, [len(mask)])[0])


def test_polarity_and_threshold_can_be_given():
    mask = _belt()
    img = _grey(mask, "dark", np.uint8, 0.0)
    ref = _summary(_feed(mask, [len(mask)])[0])
    fixed, scanner = _feed(img, [1] * len(img), threshold=40, polarity="dark")
    assert _summary(fixed) == ref
    assert scanner.threshold_.describe() == "dark objects, below 40 (fixed threshold)"
    adaptive, scanner = _feed(img, [len(img)], threshold="adaptive", contrast=30)
    assert _summary(adaptive) == ref and scanner.threshold_.mode == "adaptive"
    # the wrong polarity finds the belt between the objects, not the objects
    wrong, _ = _feed(img, [len(img)], polarity="light", contrast=30)
    assert _summary(wrong) != ref


def test_binary_rows_with_dark_polarity_take_zeros_as_object():
    mask = _belt()
    ref = _summary(_feed(mask, [len(mask)])[0])
    inverted = ~mask
    got, scanner = _feed(inverted, [7] * (len(mask) // 7), polarity="dark")
    assert _summary(got) == ref and scanner.threshold_.mode == "binary"


@pytest.mark.parametrize("binary", [np.zeros((3, 16), bool), bytes(16)])
def test_binary_rows_after_grey_rows_held_for_the_threshold_are_refused(binary):
    # they were scanned before the held grey rows: every object in the wrong rows
    grey = np.full((60, 16), 200, dtype=np.uint8)
    grey[10:20, 4:10] = 20
    scanner = LineScanner(16)
    assert scanner.feed(grey) == [] and scanner.threshold_ is None
    with pytest.raises(InputError, match="row 60: binary rows after 60 grey rows held"):
        scanner.feed(binary)
    found = scanner.feed(np.full((5, 16), 200, dtype=np.uint8)) + scanner.close()
    assert [(o.first_row, o.last_row) for o in found] == [(10, 19)]


def test_all_white_belt_finds_nothing_and_says_how():
    img = np.full((50, 40), 255, dtype=np.uint8)
    objs, scanner = _feed(img, [len(img)])
    assert objs == []
    assert scanner.threshold_.polarity == "dark"
    assert "below" in scanner.threshold_.describe()


def test_threshold_choice_reports_background_and_contrast():
    rows = np.full((20, 30), 200.0) + np.linspace(0, 100, 30)
    rows[5:9, 10:14] = 20.0
    t = choose_threshold(rows)
    assert (t.mode, t.polarity) == ("adaptive", "dark")
    assert t.background == pytest.approx((200.0, 300.0))
    assert choose_threshold(rows, threshold="fixed").mode == "fixed"
    assert choose_threshold(rows.astype(int) // 300).mode == "binary"


@pytest.mark.parametrize(
    ("bad", "match"),
    [
        (np.full((2, 6), np.nan), r"row 4, column 0: value nan is not finite"),
        (np.zeros((2, 5)), "row 4 has 5 pixels, expected 6"),
        (np.zeros((1, 2, 6)), "shape"),
        (np.array([[None] * 6]), "numbers or bool"),
        (np.array(["a"] * 6), "numbers or bool"),
        (np.zeros(6, dtype=complex), "numbers or bool, got dtype complex128"),
        ([[1, 2, 3, 4, 5, 6], [1, 2]], "row 5 has 2 pixels"),
    ],
)
def test_bad_grey_rows_are_refused_and_the_scanner_goes_on(bad, match):
    img = np.full((8, 6), 200, dtype=np.uint8)
    img[1:3, 1:4] = 10
    scanner = LineScanner(6, threshold=100, polarity="dark")
    first = scanner.feed(img[:3])
    assert first == [] and scanner.feed(img[3]) != []  # emitted when row 3 arrives
    with pytest.raises(InputError, match=match):
        scanner.feed(bad)
    assert scanner.rows_seen == 4
    assert scanner.feed(img[4:]) == [] and scanner.close() == []


def test_none_row_is_a_clear_error():
    with pytest.raises(InputError, match="numbers or bool"):
        LineScanner(4).feed(np.array([[None] * 4]))
    with pytest.raises(InputError, match="numbers or bool"):
        LineScanner(4).feed([[None] * 4])


def test_bad_options():
    with pytest.raises(InputError, match="polarity"):
        LineScanner(4, polarity="up")
    with pytest.raises(InputError, match="threshold"):
        LineScanner(4, threshold="otsu")
    with pytest.raises(InputError, match="contrast"):
        LineScanner(4, contrast=-1)
