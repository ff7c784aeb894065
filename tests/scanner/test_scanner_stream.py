import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from strategies import examples
from tentaclass.errors import InputError
from tentaclass.scanner import LineScanner
from tentaclass.scanner.simulate import make_belt
from tentaclass.scanner.stream import _words


def scan(image, chunk, **kwargs):
    scanner = LineScanner(image.shape[1], **kwargs)
    out = []
    for i in range(0, image.shape[0], chunk):
        out += scanner.feed(image[i : i + chunk])
    return out + scanner.close()


@pytest.fixture(scope="module")
def belt():
    return make_belt(16, width=96, lanes=2, gap=(1, 5), random_state=11, radius_range=(5.0, 16.0))


@pytest.fixture(scope="module")
def whole(belt):
    return [o.to_dict() for o in scan(belt.image, belt.image.shape[0])]


@pytest.mark.parametrize("chunk", [1, 7, 64])
def test_results_do_not_depend_on_chunk_size(belt, whole, chunk):
    assert [o.to_dict() for o in scan(belt.image, chunk)] == whole


def test_every_object_found_once_with_its_class(belt, whole):
    assert len(whole) == len(belt.target)
    assert [o["id"] for o in whole] == list(range(len(whole)))
    found = sorted((tuple(o["bbox"]), o["label"]) for o in whole)
    truth = sorted(
        (tuple(map(int, b)), str(t)) for b, t in zip(belt.boxes, belt.target, strict=True)
    )
    assert [f[0] for f in found] == [t[0] for t in truth]
    assert np.mean([f[1] == t[1] for f, t in zip(found, truth, strict=True)]) >= 0.9


def test_ids_follow_the_last_row(whole):
    keys = [(o["last_row"], o["bbox"][1]) for o in whole]
    assert keys == sorted(keys)


def test_object_spanning_chunks_is_emitted_once_when_complete():
    img = np.zeros((20, 12), dtype=bool)
    img[3:15, 2:8] = True  # 12 rows tall, across the chunk boundaries below
    scanner = LineScanner(12)
    assert scanner.feed(img[:5]) == []
    assert scanner.feed(img[5:10]) == []
    assert scanner.feed(img[10:15]) == []  # last row 14 is here; row 15 not yet
    (obj,) = scanner.feed(img[15:16])
    assert (obj.first_row, obj.last_row, obj.bbox, obj.area) == (3, 14, (3, 2, 15, 8), 72)
    assert obj.label == "rectangle"
    assert scanner.feed(img[16:]) == [] and scanner.close() == []


def test_side_by_side_touching_edges_and_diagonal_contact():
    img = np.zeros((8, 10), dtype=np.uint8)
    img[1:5, 0:3] = 1  # touches the left edge
    img[1:5, 7:10] = 1  # touches the right edge
    img[5, 3] = 1  # touches the first block only at a corner: 8-connected, same object
    objs = scan(img, 3)
    assert len(objs) == 2
    left = next(o for o in objs if o.bbox[1] == 0)
    assert left.area == 13 and left.bbox == (1, 0, 6, 4)


def test_object_open_at_the_end_is_emitted_by_close():
    img = np.zeros((5, 6), dtype=bool)
    img[2:, 1:4] = True
    scanner = LineScanner(6)
    assert scanner.feed(img) == []
    (obj,) = scanner.close()
    assert obj.last_row == 4 and obj.label == "square"
    assert scanner.close() == []
    with pytest.raises(InputError, match="closed"):
        scanner.feed(img)


def test_memory_is_bounded_by_the_tallest_object(belt):
    scanner = LineScanner(belt.image.shape[1])
    tallest = int((belt.boxes[:, 2] - belt.boxes[:, 0]).max())
    held = 0
    for row in belt.image:
        scanner.feed(row)
        held = max(held, scanner.pending_rows)
    assert held <= tallest + 1


def test_too_tall_object_is_reported_not_dropped():
    img = np.zeros((60, 10), dtype=bool)
    img[2:50, 3:6] = True  # a 48-row streak
    img[52:56, 2:6] = True  # a normal object after it
    for chunk in (1, 7, 60):
        objs = scan(img, chunk, max_height=20)
        assert len(objs) == 2
        tall, normal = objs
        assert tall.label is None and not tall.accept
        assert [d.kind for d in tall.defects] == ["too_tall"]
        assert (tall.first_row, tall.last_row) == (2, 22)
        assert normal.label == "square" and normal.first_row == 52
    assert [o.to_dict() for o in scan(img, 1, max_height=20)] == [
        o.to_dict() for o in scan(img, 60, max_height=20)
    ]


def test_bytes_in_any_split():
    img = np.zeros((9, 7), dtype=np.uint8)
    img[1:4, 1:4] = 1
    img[5:8, 2:6] = 1
    data = img.tobytes()
    ref = [o.to_dict() for o in scan(img, 9)]
    for step in (1, 5, 7, 13, len(data)):
        scanner = LineScanner(7)
        out = []
        for i in range(0, len(data), step):
            out += scanner.feed(data[i : i + step])
        out += scanner.close()
        assert [o.to_dict() for o in out] == ref


def test_read_only_and_writeable_rows_share_one_compiled_kernel(belt, whole):
    from tentaclass.scanner import _segment

    frozen = belt.image.copy()
    frozen.flags.writeable = False
    # a writeable chunk, a read-only one, bytes: the same objects
    assert [o.to_dict() for o in scan(frozen, 7)] == whole
    data = belt.image.view(np.uint8).tobytes()
    scanner = LineScanner(belt.image.shape[1])
    got = scanner.feed(data) + scanner.close()
    assert [o.to_dict() for o in got] == whole
    # every 8-bit chunk ran through one specialisation of the kernel
    uint8 = [s for s in _segment.scan_rows.signatures if str(s[0].dtype) == "uint8"]
    assert len(uint8) == 1, uint8


def test_bad_rows_are_refused_and_earlier_objects_kept():
    img = np.zeros((6, 5), dtype=int)
    img[1:3, 1:3] = 1
    scanner = LineScanner(5, threshold="binary")
    first = scanner.feed(img[:4])
    assert len(first) == 1
    with pytest.raises(InputError, match="row 4 has 4 pixels, expected 5"):
        scanner.feed(np.zeros((2, 4)))
    bad = img[4:].copy()
    bad[1, 2] = 7
    with pytest.raises(InputError, match=r"row 5, column 2: value 7"):
        scanner.feed(bad)
    with pytest.raises(InputError, match="row 4 has 3 pixels"):
        scanner.feed([[0, 0, 0, 0, 0][:3], [0, 0, 0, 0, 0]])
    with pytest.raises(InputError, match="byte value 2"):
        scanner.feed(bytes([0, 0, 2, 0, 0]))
    with pytest.raises(InputError, match="numbers or bool"):
        scanner.feed(np.array([["a"] * 5]))
    with pytest.raises(InputError, match="shape"):
        scanner.feed(np.zeros((1, 1, 5)))
    for nothing in (None, {}):  # a TypeError before
        with pytest.raises(InputError, match=r"row 4: rows must be an array of shape \(width,\)"):
            scanner.feed(nothing)
    assert scanner.rows_seen == 4  # the refused chunks changed nothing
    assert scanner.feed(img[4:]) == [] and scanner.close() == []


def test_empty_and_truncated_streams():
    with pytest.raises(InputError, match="empty stream"):
        LineScanner(4).close()
    scanner = LineScanner(4)
    scanner.feed(bytes([0, 1, 1, 0, 0, 1]))
    with pytest.raises(InputError, match="truncated stream: row 1 has only 2 of 4 bytes"):
        scanner.close()
    with pytest.raises(InputError, match="width"):
        LineScanner(0)
    # buffers of 22 numbers a pixel: 1e8 pixels a row was a MemoryError (or an OOM kill)
    with pytest.raises(
        InputError, match=r"buffers for rows of 100,000,000 pixels would hold 2,100,000,042 values"
    ):
        LineScanner(10**8)


def test_scan_iterator_helper():
    img = np.zeros((6, 5), dtype=bool)
    img[1:4, 1:4] = True
    assert [o.label for o in LineScanner(5).scan(iter(img))] == ["square"]


@settings(max_examples=examples(15), deadline=None)
@given(seed=st.integers(0, 10_000), cuts=st.lists(st.integers(1, 40), min_size=1, max_size=8))
def test_chunking_invariance_property(seed, cuts):
    belt = make_belt(4, width=64, lanes=2, gap=(1, 3), random_state=seed, radius_range=(4.0, 12.0))
    img = belt.image
    ref = [o.to_dict() for o in scan(img, img.shape[0])]
    scanner = LineScanner(img.shape[1])
    out, i, k = [], 0, 0
    while i < img.shape[0]:
        step = cuts[k % len(cuts)]
        out += scanner.feed(img[i : i + step])
        i, k = i + step, k + 1
    out += scanner.close()
    assert [o.to_dict() for o in out] == ref
    assert len(ref) == 4


@settings(max_examples=examples(100), deadline=None)
@given(
    grid=st.lists(st.lists(st.booleans(), min_size=6, max_size=6), min_size=1, max_size=24),
    max_height=st.integers(1, 6),
    chunk=st.integers(1, 9),
)
# A live object cut before it joins an already reported one below (found by hypothesis).
@example(
    grid=[
        [0, 0, 0, 0, 0, 0],
        [0, 0, 0, 0, 1, 0],
        [1, 0, 0, 1, 0, 0],
        [1, 0, 1, 0, 0, 0],
        [0, 1, 0, 0, 0, 0],
    ],
    max_height=1,
    chunk=1,
)
def test_chunking_invariance_on_noise_with_tall_cuts(grid, max_height, chunk):
    img = np.array(grid, dtype=bool)
    runs = [
        [o.to_dict() for o in LineScanner(6, max_height=max_height).scan(chunks)]
        for chunks in ([img], img, [img[i : i + chunk] for i in range(0, len(img), chunk)])
    ]
    assert runs[0] == runs[1] == runs[2]
    # every object pixel is reported once (in an object or a too-tall record) or skipped
    # only as the rest of a too-tall object
    assert sum(o["area"] for o in runs[0]) <= int(img.sum())


def test_min_area_ignores_speckle():
    img = np.zeros((10, 12), dtype=bool)
    img[1, 1] = img[3, 9] = img[9, 10] = True  # speckle
    img[4:8, 2:6] = True
    for chunk in (1, 10):
        scanner = LineScanner(12, min_area=3)
        objs = list(scanner.scan([img[i : i + chunk] for i in range(0, 10, chunk)]))
        assert [(o.id, o.label, o.area) for o in objs] == [(0, "square", 16)]
        assert scanner.n_ignored == 3
    assert len(list(LineScanner(12).scan([img]))) == 4


@pytest.mark.parametrize("latency", [1, 5, 40])
def test_latency_batches_objects_without_changing_them(belt, whole, latency):
    scanner = LineScanner(belt.image.shape[1], latency=latency)
    out, late = [], 0
    for i, row in enumerate(belt.image):
        got = scanner.feed(row)
        late = max([late] + [i - o.last_row for o in got])
        out += got
    out += scanner.close()
    assert [o.to_dict() for o in out] == whole
    assert late <= latency  # emitted at most `latency` rows after its last row


def test_latency_runs_a_stage_of_rows_at_once(belt, whole):
    # rows fed one by one go through the kernel `latency` at a time: objects
    # come out only in the calls that fill the stage, each batch holding every
    # object completed by then
    latency = 16
    scanner = LineScanner(belt.image.shape[1], latency=latency)
    calls = {}
    for i, row in enumerate(belt.image):
        got = scanner.feed(row)
        if got:
            calls[i] = got
            assert all(o.last_row < i for o in got)
    assert calls and all(i % latency == latency - 1 for i in calls)
    emitted = [o for got in calls.values() for o in got]
    last = max(calls)
    assert [o.to_dict() for o in emitted] == [o for o in whole if o["last_row"] < last]


def test_one_row_path_refuses_bad_rows_like_chunks(belt, whole):
    image = belt.image
    width = image.shape[1]
    scanner = LineScanner(width, latency=8)
    out = []
    for row in image[:20]:
        out += scanner.feed(row)
    row = image[20]
    nan, two = row.astype(float), row.astype(int)
    nan[3], two[5] = np.nan, 2
    bad = [
        (row[:-1], f"row 20 has {width - 1} pixels, expected {width}"),
        (np.append(row, False), f"row 20 has {width + 1} pixels, expected {width}"),
        (row[None, None], "shape"),
        (nan, "row 20, column 3: value nan is not finite"),
        (two, "row 20, column 5: value 2, expected 0 or 1"),
        (row.astype(str), "numbers or bool"),
    ]
    for rows, message in bad:
        with pytest.raises(InputError, match=message):
            scanner.feed(rows)
        assert scanner.rows_seen == 20
    # rows of another layout or type still go through, to the same objects
    out += scanner.feed(np.repeat(image[20], 2)[::2])  # not contiguous
    out += scanner.feed(image[21].astype(np.uint8))
    out += scanner.feed(image[22:23])  # one row as a chunk
    for row in image[23:]:
        out += scanner.feed(row)
    out += scanner.close()
    assert [o.to_dict() for o in out] == whole


@pytest.mark.parametrize("chunk", [3, 50])
def test_latency_with_chunks_and_grey_rows(belt, whole, chunk):
    assert [o.to_dict() for o in scan(belt.image, chunk, latency=10)] == whole
    grey = np.where(belt.image, 20, 200).astype(np.uint8)
    ref = [o.to_dict() for o in scan(grey, grey.shape[0])]
    assert [o.to_dict() for o in scan(grey, chunk, latency=10)] == ref
    assert [(o["bbox"], o["area"]) for o in ref] == [(o["bbox"], o["area"]) for o in whole]


@settings(max_examples=examples(15), deadline=None)
@given(seed=st.integers(0, 10_000), density=st.sampled_from([0.02, 0.3, 0.7]))
def test_binary_rows_read_by_words_or_by_pixels_give_the_same_objects(seed, density):
    from scipy import ndimage

    # runs starting and ending on and off 8-pixel words, empty and full words
    rng = np.random.default_rng(seed)
    wide = rng.random((40, 81)) < density
    wide[rng.integers(0, 40, 6)] = False
    wide[rng.integers(0, 40, 3), 8:40] = True
    aligned = np.ascontiguousarray(wide[:, 1:65])  # whole 64-bit words per row
    shifted = wide[:, 1:65]  # rows 81 bytes apart: read pixel by pixel
    as_bytes = aligned.view(np.uint8).tobytes()
    results = [
        [o.to_dict() for o in LineScanner(64, max_height=64).scan(rows)]
        for rows in ([aligned], aligned, [shifted], shifted, [as_bytes], [aligned.astype(int)])
    ]
    assert all(r == results[0] for r in results[1:])
    # every 8-connected piece is one object, every pixel in one
    n_pieces = ndimage.label(aligned, np.ones((3, 3), dtype=bool))[1]
    assert len(results[0]) == n_pieces
    assert sum(o["area"] for o in results[0]) == int(aligned.sum())
    # the two reading paths were both taken
    assert _words(aligned.view(np.uint8)).shape == (40, 8)
    assert _words(shifted.view(np.uint8)).size == 0
