import json

import numpy as np
import pytest

from tentaclass.datasets import thesis_scanner
from tentaclass.errors import InputError
from tentaclass.scanner import DEFECT_KINDS, DefectSettings, Inspection, inspect, inspect_many
from tentaclass.scanner.simulate import draw_shape, make_objects

THESIS = thesis_scanner()


@pytest.mark.parametrize("i", range(16))
def test_every_thesis_training_grid_is_recognised_and_accepted(i):
    r = inspect(THESIS.grids[i])
    assert r.label == THESIS.target[i]
    assert r.accept, r.reasons


def test_square_with_a_hole_is_a_rejected_square():
    r = inspect(THESIS.test_grids[0])
    assert THESIS.thesis_answer[0] == "triangle"  # what the thesis got wrong
    assert r.label == "square"
    assert (r.holes, r.hole_area) == (1, 2)
    (hole,) = r.defects
    assert (hole.kind, hole.area, hole.bbox) == ("hole", 2, (1, 2, 3, 3))
    assert not r.accept and r.reasons[0].startswith("hole")


def test_three_by_three_block_is_a_smaller_square():
    grid = THESIS.test_grids[1]  # partial object: 3 x 3 block in a corner
    r = inspect(grid)
    assert (r.label, r.accept, r.length, r.width, r.area) == ("square", True, 3.0, 3.0, 9)
    sized = inspect(grid, nominal_size=5.0)
    assert not sized.accept
    assert [d.kind for d in sized.defects] == ["size"]
    assert sized.defects[0].depth == pytest.approx(-0.4)
    # per-class nominal sizes and (length, width) pairs
    assert inspect(grid, nominal_size={"square": (3, 3)}).accept
    assert inspect(grid, nominal_size={"circle": 5}).accept  # squares not checked
    assert not inspect(grid, nominal_size={"square": (3.0, 2.0)}).accept


def test_other_thesis_test_grids():
    slot = inspect(THESIS.test_grids[2])  # square with a slot -> rectangle, damaged
    assert slot.label == "rectangle" and not slot.accept
    assert slot.defects[0].kind == "bite" and slot.defects[0].area == 2
    shifted = inspect(THESIS.test_grids[4])
    assert shifted.label == "square" and shifted.accept


def test_position_and_size_fields():
    grid = np.zeros((12, 20), dtype=int)
    grid[3:7, 5:15] = 1  # 4 x 10 rectangle, long side along the columns
    r = inspect(grid)
    assert r.label == "rectangle"
    assert r.bbox == (3, 5, 7, 15)
    assert r.area == 40
    assert r.centroid == (4.5, 9.5)
    assert (r.length, r.width, r.orientation) == (10.0, 4.0, 0.0)
    assert inspect(grid.T).orientation == 90.0


def test_to_dict_is_json_ready():
    r = inspect(THESIS.test_grids[0])
    d = json.loads(json.dumps(r.to_dict()))
    assert d["label"] == "square" and d["defects"][0]["kind"] == "hole"
    assert d["bbox"] == [0, 0, 5, 5]
    assert set(d) == set(Inspection.__dataclass_fields__)
    with pytest.raises(AttributeError):
        r.label = "circle"  # frozen


def test_translation_and_quarter_turns_do_not_change_the_class():
    base = draw_shape("triangle", (40, 40), 20.0, angle=0.3)
    labels = {inspect(np.roll(base, (3, -5), axis=(0, 1))).label}
    labels |= {inspect(np.rot90(base, k)).label for k in range(4)}
    assert labels == {"triangle"}


def test_defect_kinds_on_drawn_damage():
    grid = draw_shape("square", (50, 50), 30.0, angle=0.2)
    bitten = grid.copy()
    bitten[24:28, :18] = False  # a notch from the left side
    r = inspect(bitten)
    assert r.label == "square" and not r.accept
    assert r.defects[0].kind in ("bite", "truncated")
    burr = grid.copy()
    burr[24:26, 5:12] = True  # a strip sticking out on the left
    rb = inspect(burr)
    assert rb.label == "square"
    assert [d.kind for d in rb.defects] == ["burr"]
    corner = draw_shape("square", (50, 50), 30.0)
    corner[10:16, 10:16] = False
    corner[10:19, 10:13] = False
    rc = inspect(corner)
    assert rc.label == "square" and rc.defects[0].kind == "broken_corner"
    assert all(d.kind in DEFECT_KINDS for d in r.defects + rb.defects + rc.defects)


def test_object_cut_by_the_grid_edge_is_truncated():
    grid = draw_shape("circle", (40, 40), 30.0, center=(19.5, 4.0))
    r = inspect(grid)
    assert not r.accept
    assert "truncated" in [d.kind for d in r.defects] or r.label != "circle"


def test_several_pieces_are_flagged_broken():
    grid = np.zeros((10, 10), dtype=bool)
    grid[1:4, 1:4] = True
    grid[6:9, 6:9] = True
    assert "broken" in [d.kind for d in inspect(grid).defects]


def test_settings_change_the_decision():
    grid = draw_shape("square", (50, 50), 30.0)
    grid[10:14, 24:27] = False  # 12-pixel notch at the top edge
    assert not inspect(grid).accept
    assert inspect(grid, settings=DefectSettings(min_area=20)).accept


def test_inspect_many_matches_inspect():
    grids = list(THESIS.test_grids)
    assert inspect_many(grids) == [inspect(g) for g in grids]


@pytest.mark.parametrize(
    ("grid", "match"),
    [
        ([1, 1, 1], "at least 2 dimensions"),
        ([[0, 2], [1, 1]], "only 0 and 1"),
        (np.zeros((5, 5)), "no object pixels"),
        (np.ones((2, 2, 2)), "2-D"),
        ([["a", "b"]], "0/1 or bool"),
    ],
)
def test_bad_grids(grid, match):
    with pytest.raises(InputError, match=match):
        inspect(grid)


def test_bad_options():
    with pytest.raises(InputError, match="ScannerModel"):
        inspect(np.ones((3, 3)), model="default")
    with pytest.raises(InputError, match="size_tolerance"):
        inspect(np.ones((3, 3)), size_tolerance=-1)
    with pytest.raises(InputError, match="nominal"):
        inspect(np.ones((3, 3)), nominal_size="big")
    with pytest.raises(ValueError, match="nominal"):
        inspect(np.ones((3, 3)), nominal_size=(1, 2, 3))


def test_learned_nominal_size():
    from tentaclass.scanner import ScannerModel

    big = [draw_shape(c, (40, 40), 24.0, angle=a) for c in ("square", "circle") for a in (0, 1)]
    model = ScannerModel().fit(big, ["square", "square", "circle", "circle"])
    assert model.nominal_sizes()["square"][0] == pytest.approx(24.5, abs=1.5)
    same = draw_shape("square", (40, 40), 24.0, angle=0.5)
    small = draw_shape("square", (40, 40), 16.0, angle=0.5)
    assert inspect(same, model, nominal_size="learned").accept
    r = inspect(small, model, nominal_size="learned")
    assert [d.kind for d in r.defects] == ["size"] and "smaller" in r.reasons[0]


def test_ragged_grid_names_the_argument():
    with pytest.raises(InputError, match="grid: rows have different lengths"):
        inspect([[0, 1, 1], [1, 1]])


def test_large_batches_restore_the_blas_threads_and_match_small_ones():
    from threadpoolctl import threadpool_info

    from tentaclass.scanner.model import _ONE_THREAD_MIN_ROWS

    grids = make_objects(
        _ONE_THREAD_MIN_ROWS + 6, shape=(24, 24), radius_range=(4.0, 10.0),
        damaged_fraction=0.5, random_state=8,
    ).grids  # fmt: skip
    before = [(i["filepath"], i["num_threads"]) for i in threadpool_info()]
    whole = inspect_many(grids)  # one batch, BLAS on one thread meanwhile
    assert [(i["filepath"], i["num_threads"]) for i in threadpool_info()] == before
    halves = inspect_many(grids[:35]) + inspect_many(grids[35:])  # below the limit
    assert whole == halves
