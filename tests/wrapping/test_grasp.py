import numpy as np
import pytest

from tentaclass import shapes
from tentaclass.errors import InputError
from tentaclass.wrapping import grasp_state, wrap
from wrap_checks import MPEG7, needs_mpeg7

THESIS = {
    "square": np.tile([0, 0, 0, np.pi / 2], 4),
    "circle": np.full(16, np.pi / 8),
    "triangle": np.array([0, 0, 0, 0, 2 * np.pi / 3] * 2 + [0, 0, 0, 0, 0, 2 * np.pi / 3]),
    "rectangle": np.tile([0, 0, 0, 0, 0, np.pi / 2, 0, np.pi / 2], 2),
}


@pytest.mark.parametrize("name", sorted(THESIS))
def test_thesis_arrays_are_once(name):
    g = grasp_state(THESIS[name])
    assert g.state.item() == "once"
    assert g.laps_rounded.item() == 1
    assert g.offset_links.item() == 0
    assert g.laps.item() == pytest.approx(1.0)


def test_batch_shape_and_direction():
    q = np.stack([THESIS["square"], -THESIS["square"][::-1]])
    g = grasp_state(np.stack([q, q, q]))
    for field in (g.state, g.laps, g.laps_rounded, g.offset_links, g.direction):
        assert field.shape == (3, 2)
    assert g.direction[0].tolist() == [1, -1]
    assert np.allclose(g.laps, 1.0)


def test_bad_input():
    with pytest.raises(InputError, match="NaN"):
        grasp_state([0.0, np.nan, 1.0])
    with pytest.raises(InputError):
        grasp_state([[]])
    with pytest.raises(InputError, match="complex"):  # the imaginary part must not be dropped
        grasp_state(np.array([1j, 1.0, 1.0, 1.0]))
    with pytest.raises(InputError, match=r"beyond 2\*\*20 turns"):  # laps_rounded overflowed
        grasp_state(np.full(8, 1e300))


def _outlines(rng, pool):
    if pool == "mpeg7":
        o, _, names = shapes.load_mpeg7(MPEG7, max_vertices=1000)
        return [(names[i], o[i]) for i in range(0, len(o), 7)]
    return [
        ("square", shapes.square(1.0)),
        ("rectangle", shapes.rectangle(1.0, rng.uniform(0.2, 0.8))),
        (
            "triangle",
            shapes.triangle(rng.uniform(-1, 1, (3, 2)) + np.array([[0, 0], [2, 0], [0, 2]])),
        ),
        ("circle", shapes.circle(1.0, n_points=256)),
    ]


def generate(n_wraps: int, seed: int = 0, pool: str = "thesis"):
    """Random taut wraps: thesis shapes and MPEG-7 outlines, size, start, direction,
    0.3-3.5 laps, offset 0-5 links (a third exactly 0), noise sigma <= 0.02 rad."""
    rng = np.random.default_rng(seed)
    pool = _outlines(rng, pool)
    rows = []
    for _ in range(n_wraps):
        name, outline = pool[rng.integers(len(pool))]
        outline = outline * rng.uniform(0.1, 10.0) / np.ptp(outline, axis=0).max()
        n = int(rng.choice([16, 32, 64]))
        off_links = 0.0 if rng.random() < 1 / 3 else rng.uniform(0, 5)
        target = rng.uniform(0.3, 3.5)
        hull = shapes.polygon(outline).tolist()
        per = float(np.sum(np.hypot(*np.diff(np.vstack([hull, hull[:1]]), axis=0).T)))
        n_wrap = max(n - int(np.ceil(off_links)), 2)
        ln = min(target * per / n_wrap, 0.9 * np.ptp(outline, axis=0).max())
        w = wrap(
            outline,
            n,
            ln,
            start=rng.uniform(0, 1),
            direction=str(rng.choice(["ccw", "cw"])),
            offset=off_links * ln,
            noise=rng.uniform(0, 0.02),
            random_state=rng.integers(1 << 31),
        )
        if 0.3 <= w.laps <= 3.5:
            rows.append((name, w))
    return rows


def _score(rows):
    """Fraction right, and fraction of unambiguous wraps with state and rounded laps right.

    "Right" = the estimated laps within 0.1 of the true laps (``Wrap.laps``,
    the noise-free turning since the start point) and the offset within one
    link of the true one. State and rounded laps then agree with the truth
    whenever the true laps is more than 0.1 from a decision boundary
    (1 +- tol, k + 0.5); those are the "unambiguous" wraps.
    """
    right = clear = clear_ok = 0
    for _, w in rows:
        g = grasp_state(w.angles)
        right += (
            abs(g.laps.item() - w.laps) <= 0.1 and abs(g.offset_links.item() - w.offset_links) <= 1
        )
        truth_state = "partial" if w.laps < 0.9 else ("once" if w.laps <= 1.1 else "multiple")
        if np.min(np.abs(w.laps - np.array([0.5, 0.9, 1.1, 1.5, 2.5, 3.5]))) > 0.1:
            clear += 1
            clear_ok += g.state.item() == truth_state and g.laps_rounded.item() == round(w.laps)
    return right / len(rows), clear_ok / clear


@pytest.mark.slow
def test_grasp_state_on_2000_generated_wraps_of_thesis_shapes():
    rows = [r for r in generate(2600, seed=1) if r[1].complete]
    assert len(rows) >= 2000, len(rows)
    right, clear = _score(rows)
    # 98.9 % with the generator that places every link (above 99 % with the
    # one that stopped early on some wraps); the goal for physical grasps is 95 %
    assert right >= 0.985 and clear >= 0.99, (right, clear)


@pytest.mark.slow
@pytest.mark.mpeg7
@needs_mpeg7
def test_grasp_state_on_2000_generated_wraps_of_mpeg7_outlines():
    rows = [r for r in generate(2600, seed=2, pool="mpeg7") if r[1].complete]
    assert len(rows) >= 2000, len(rows)
    right, clear = _score(rows)
    assert right >= 0.99 and clear >= 0.99, (right, clear)
