import numpy as np
import pytest

from tentaclass.features import split_laps

# A 64-link chain hugging MPEG-7 dog-17 (fixed-chain protocol, no noise): the
# generator wrapped 1.448 laps along the chain's support after the approach.
DOG = np.array([
    -0.4505, 0.2675, -1.3036, -1.3159, -0.0489, -0.6935, 0.2951, 0.8936, 2.3660, -2.8295, 0.1053,
    2.2776, 0.1101, -0.3544, 0.0150, -1.4625, 0.0709, 0.1139, 1.5753, 0.2750, 0.1454, 1.1571,
    0.0605, -0.1719, -0.0537, -0.6363, 0.0685, 0.3217, 0.0085, -0.6507, -0.0295, 1.9201, 0.5408,
    0.9660, -1.2317, 0.3632, -0.3451, 0.1554, -0.1471, 0.7942, 2.2593, 0.2006, -1.6296, -1.2715,
    0.9180, 1.9180, 0.6364, -1.6992, -0.6668, -0.7719, -0.4306, 0.1373, 1.6129, -0.6144, 1.6021,
    0.5563, -0.4005, 0.0190, -1.5489, 0.3594, -0.0588, 1.8551, 0.0188, 0.1825,
])  # fmt: skip


def _end_gap(q, period):
    """Distance from the chain's last joint to the point ``period`` links before it."""
    p = np.r_[0, np.cumsum(np.exp(1j * np.cumsum(q)))]  # joints, unit links
    x = len(q) - period
    i = int(np.floor(x))
    return float(abs(p[-1] - (p[i] + (x - i) * (p[i + 1] - p[i]))))


def test_hugging_wrap_lap_is_not_the_whole_chain():
    s = split_laps(DOG)
    assert s.closed
    np.testing.assert_allclose(s.laps, 1.448, atol=0.05)
    # independent: the rebuilt chain's end comes back onto its own path 43.1 links
    # earlier, and near it one lap from where split_laps says
    assert _end_gap(DOG * s.direction, 43.1) < 0.1
    np.testing.assert_allclose(s.period, 43.1, atol=1.5)
    assert _end_gap(DOG * s.direction, float(s.period)) < 1.5
    # the whole chain as one lap would leave the end far from where it started
    assert _end_gap(DOG * s.direction, len(DOG) - float(s.offset) - 1) > 3.0


@pytest.mark.parametrize("extra", [1, 2, 3, 5])
def test_lap_barely_longer_than_one_turn_is_found_when_it_closes(extra):
    # a square of 15-link sides (60 links a lap) wrapped once and a few links more:
    # the overlap is short, but the chain's end lands exactly one lap on
    side = np.r_[np.zeros(14), np.pi / 2]
    lap = np.tile(side, 4)
    q = np.r_[lap, lap[:extra]]
    s = split_laps(q)
    assert s.closed
    np.testing.assert_allclose(s.period, 60.0, atol=0.15)
    np.testing.assert_allclose(s.laps, (60 + extra) / 60, atol=0.01)


def test_square_with_approach():
    square = np.tile([0, 0, 0, np.pi / 2], 4)
    approach = np.r_[0.0, 0.0, -np.pi / 2]
    s = split_laps(np.r_[approach, square, square[:8]], n_out=16)
    assert np.isclose(s.period, 16.0) and int(s.offset) == 2 and bool(s.closed)
    np.testing.assert_allclose(s.lap.sum(), 2 * np.pi)


def test_lap_search_in_blocks_of_candidates_gives_the_same_laps(monkeypatch):
    # a long chain's search was one (candidates x arcs) block per row: 4.5 GB at 2000 links
    from tentaclass import shapes, wrap
    from tentaclass.features import laps

    rng = np.random.default_rng(3)
    q = np.array([
        wrap(shapes.rectangle(3.0, 1.0), 120, 0.09, start=0.2).angles,
        wrap(shapes.circle(1.0), 120, 0.1).angles + rng.normal(0, 0.02, 120),
    ])  # fmt: skip
    whole = split_laps(q, n_out=32)
    monkeypatch.setattr(laps, "_WORK_VALUES", 5_000)  # blocks of 20 candidates
    blocks = split_laps(q, n_out=32)
    for name in ("period", "laps", "lap", "offset", "closed"):
        np.testing.assert_array_equal(getattr(blocks, name), getattr(whole, name), err_msg=name)
    assert np.all(whole.closed)
