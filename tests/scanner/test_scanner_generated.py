import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from strategies import examples
from tentaclass.scanner import default_model, inspect, inspect_many
from tentaclass.scanner.simulate import draw_shape, make_belt, make_objects


@pytest.fixture(scope="module")
def generated():
    data = make_objects(400, damaged_fraction=0.5, seed=7)
    return data, inspect_many(data.grids, default_model())


def test_generated_accuracy_at_least_99_percent(generated):
    data, results = generated
    labels = np.array([r.label for r in results])
    assert (labels == data.target).mean() >= 0.99


def test_defect_recall_and_false_alarms(generated):
    data, results = generated
    rejected = np.array([not r.accept for r in results])
    assert rejected[data.damaged].mean() >= 0.95
    assert rejected[~data.damaged].mean() <= 0.02


def test_generator_is_seeded_and_balanced():
    a, b = make_objects(12, seed=3), make_objects(12, seed=3)
    assert np.array_equal(a.grids, b.grids)
    assert sorted(a.target.tolist()) == sorted(["square", "circle", "triangle", "rectangle"] * 3)
    assert all(bool(d) == dmg for d, dmg in zip(a.damages, a.damaged, strict=True))


def test_belt_boxes_hold_the_objects():
    belt = make_belt(6, width=128, lanes=2, seed=4)
    for r0, c0, r1, c1 in belt.boxes:
        assert belt.image[r0:r1, c0:c1].any()


@settings(max_examples=examples(25), deadline=None)
@given(
    label=st.sampled_from(["square", "circle", "triangle", "rectangle"]),
    angle=st.floats(0, 2 * np.pi),
    size=st.floats(16, 34),
    dr=st.integers(-8, 8),
    dc=st.integers(-8, 8),
)
def test_class_invariant_to_position_rotation_and_size(label, angle, size, dr, dc):
    aspect = 2.0
    grid = draw_shape(
        label, (64, 64), size, angle=angle, center=(31.5 + dr, 31.5 + dc), aspect=aspect
    )
    assert inspect(grid).label == label


def test_burrs_are_found_and_do_not_change_the_class():
    data = make_objects(160, damaged_fraction=1.0, damage_kinds=("burr",), seed=8)
    results = inspect_many(data.grids)
    assert np.mean([r.label == t for r, t in zip(results, data.target, strict=True)]) >= 0.98
    assert np.mean([not r.accept for r in results]) >= 0.9
    kinds = {d.kind for r in results for d in r.defects}
    assert "burr" in kinds
