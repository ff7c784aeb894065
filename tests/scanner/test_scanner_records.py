"""Records of generated belts and objects, compared with those stored in data/records.json.gz.

The file was written by the per-object implementation on shapely and scipy
(hulls, rectangles, circles, hole filling, distance transforms); the batched
compiled path must give the same JSON, byte for byte.
"""

import gzip
import json
import struct
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from strategies import examples
from tentaclass.scanner import LineScanner, inspect_many
from tentaclass.scanner.simulate import make_belt, make_objects

STORED = Path(__file__).parent / "data" / "records.json.gz"


@pytest.fixture(scope="module")
def stored():
    with gzip.open(STORED, "rt") as f:
        return json.load(f)


def _scan(image):
    scanner = LineScanner(image.shape[1], max_height=256)
    out = scanner.feed(image) + scanner.close()
    return [json.dumps(o.to_dict()) for o in out]


@pytest.mark.parametrize("seed", [0, 1])
def test_belt_records_are_unchanged(stored, seed):
    b = make_belt(60, width=256, lanes=4, gap=(1, 5), random_state=seed, radius_range=(4.0, 30.0))
    assert _scan(b.image) == stored[f"belt{seed}"]
    # grey rows, lit unevenly across the belt (adaptive threshold)
    ramp = np.arange(256, dtype=np.uint8)[None, :] // 8
    grey = np.where(b.image, 40, 200).astype(np.uint8) + ramp
    assert _scan(grey) == stored[f"grey{seed}"]


def test_inspected_objects_are_unchanged(stored):
    objs = make_objects(
        300, shape=(64, 64), radius_range=(3.0, 28.0), damaged_fraction=0.5, random_state=5
    )
    got = [json.dumps(r.to_dict()) for r in inspect_many(objs.grids)]
    assert got == stored["inspect_many"]


def test_fast_record_constructors_give_the_dataclasses():
    from tentaclass.scanner.records import (
        Defect,
        Inspection,
        ScannedObject,
        new_defect,
        new_inspection,
        new_scanned,
    )

    d = ("hole", 2, (1, 2, 3, 3), (1.5, 2.0), 0.0, "hole of 2 px")
    assert new_defect(*d) == Defect(*d)
    i = ("square", 0.9, (1, 2, 5, 6), 14, (3.0, 4.0), 0.0, 4.0, 4.0, 1, 2, (Defect(*d),), False,
         ("hole",))  # fmt: skip
    assert new_inspection(*i) == Inspection(*i)
    assert new_inspection(*i).to_dict() == Inspection(*i).to_dict()
    assert new_scanned(3, 1, 4, Inspection(*i)) == ScannedObject(3, 1, 4, Inspection(*i))
    assert hash(new_inspection(*i)) == hash(Inspection(*i))


def test_shifted_moves_every_coordinate_and_back():
    from tentaclass.scanner import inspect

    grid = np.ones((6, 6), dtype=bool)
    grid[2:4, 2:4] = False  # a hole
    r = inspect(grid)
    moved = r.shifted(10, -3)
    assert moved.bbox == (r.bbox[0] + 10, r.bbox[1] - 3, r.bbox[2] + 10, r.bbox[3] - 3)
    assert moved.centroid == (r.centroid[0] + 10, r.centroid[1] - 3)
    assert [d.bbox for d in moved.defects] == [(12, -1, 14, 1)]
    assert moved.defects[0].centroid == (12.5, -0.5)
    assert moved.shifted(-10, 3) == r


@settings(max_examples=examples(200), deadline=None)
@given(
    values=st.lists(st.floats(allow_nan=True, allow_infinity=True), min_size=1, max_size=20),
    digits=st.sampled_from([3, 6, 9]),
)
def test_rounded_is_python_round_bit_for_bit(values, digits):
    from tentaclass.scanner._rounding import rounded

    got = rounded(np.array(values), digits).tolist()
    want = [round(v, digits) for v in values]
    assert [struct.pack("<d", v) for v in got] == [struct.pack("<d", v) for v in want]


def test_rounded_near_halves_and_centroids():
    from tentaclass.scanner._rounding import rounded

    rng = np.random.default_rng(3)
    k = rng.integers(0, 10**6, 20_000)
    values = np.concatenate(
        [
            k / rng.integers(1, 500, k.size) + rng.integers(0, 5000, k.size),  # centroids
            (k + 0.5) / 1e6,  # decimal halves at 6 digits, none exact in binary
            k / 128.0,  # exact binary halves at 6 digits
            -(k + 0.5) / 1e3,
        ]
    )
    for digits in (3, 6, 9):
        want = np.array([round(v, digits) for v in values.tolist()])
        assert np.array_equal(rounded(values, digits).view(np.int64), want.view(np.int64))


def test_scanner_records_hold_plain_python_values():
    b = make_belt(30, width=256, lanes=4, gap=(1, 5), random_state=2, radius_range=(4.0, 20.0))
    found = LineScanner(256).feed(b.image)
    assert found and any(o.defects for o in found)

    def plain(v):
        if isinstance(v, tuple):
            return all(plain(x) for x in v)
        return type(v) in (int, float, str, bool, type(None)) or type(v).__name__ == "Defect"

    for o in found:
        r = o.inspection
        assert all(plain(v) for v in vars(r).values()), vars(r)
        assert all(plain(v) for d in r.defects for v in vars(d).values())
        assert type(o.id) is int and type(o.first_row) is int


def test_records_are_built_with_the_collector_paused_and_it_resumes_as_it_was():
    import gc

    from tentaclass.scanner.records import collector_paused

    seen = []

    @collector_paused
    def build(fail=False):
        seen.append(gc.isenabled())
        if fail:
            raise RuntimeError("no records")
        return [object() for _ in range(3)]

    assert gc.isenabled()
    assert len(build()) == 3 and gc.isenabled()
    with pytest.raises(RuntimeError, match="no records"):
        build(fail=True)
    assert gc.isenabled()
    gc.disable()
    try:
        build()
        assert not gc.isenabled()  # left off, as the caller had it
    finally:
        gc.enable()
    assert seen == [False, False, False]
