"""Records of generated belts and objects, compared with those stored in data/records.json.gz.

The file was written by the per-object implementation on shapely and scipy
(hulls, rectangles, circles, hole filling, distance transforms); the batched
compiled path must give the same JSON, byte for byte.
"""

import gzip
import json
from pathlib import Path

import numpy as np
import pytest

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
