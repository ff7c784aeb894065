import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from strategies import examples
from tentaclass.features import fourier_features
from tentaclass.features.lap import last_lap

SQUARE = np.tile([0, 0, 0, np.pi / 2], 4)


@settings(deadline=None, max_examples=examples(40))
@given(st.integers(0, 15), st.integers(1, 15), st.booleans())
def test_last_lap_of_a_longer_wrap_is_the_shape(shift, extra, clockwise):
    q = np.roll(SQUARE, shift)
    longer = np.concatenate([q, q[:extra]])
    if clockwise:
        longer = -longer[::-1]
    lap, closed = last_lap(longer, n_out=16)
    assert closed
    np.testing.assert_allclose(lap.sum(), 2 * np.pi, atol=1e-9)
    np.testing.assert_allclose(fourier_features(lap), fourier_features(SQUARE), atol=1e-6)


def test_partial_wrap_is_flagged_and_scaled_to_one_turn():
    lap, closed = last_lap(SQUARE[:10], n_out=12)
    assert not closed
    assert lap.shape == (12,)
    np.testing.assert_allclose(lap.sum(), 2 * np.pi)


def test_batch_shapes_and_link_length_independence(rng):
    q = np.stack([np.concatenate([SQUARE, SQUARE[:5]]), np.full(21, 2 * np.pi / 16)])
    lap, closed = last_lap(q[None], n_out=16)
    assert lap.shape == (1, 2, 16) and closed.shape == (1, 2) and closed.all()
    lap2, _ = last_lap(q, n_out=16, link_lengths=3.5)
    np.testing.assert_allclose(lap2, lap[0], atol=1e-9)


def test_bad_input():
    with pytest.raises(ValueError, match="at least 2"):
        last_lap([0.1])
    with pytest.raises(ValueError, match="n_out"):
        last_lap(SQUARE, n_out=1)
    with pytest.raises(ValueError, match="complex"):  # the imaginary part must not be dropped
        last_lap(np.array([1j, 1.0, 1.0, 1.0]))


def test_outputs_longer_than_any_chain_are_refused():
    # a lap resampled to 10**9 angles ran for minutes before running out of memory
    from tentaclass.errors import InputError
    from tentaclass.features import LastLap, split_laps

    message = "n_out must be at most 100,000, got 1,000,000,000"
    with pytest.raises(InputError, match=message):
        last_lap(SQUARE, n_out=10**9)
    with pytest.raises(InputError, match=message):
        LastLap(n_out=10**9).fit(np.atleast_2d(SQUARE))
    with pytest.raises(InputError, match=message):
        split_laps(SQUARE, n_out=10**9)
    assert last_lap(SQUARE, n_out=100_000)[0].shape == (100_000,)
    # an array longer than any generated chain keeps its own length
    long = np.full(100_010, 2 * np.pi / 100_010)
    assert last_lap(long, n_out=100_010)[0].shape == (100_010,)


def test_degenerate_closure_falls_back_to_the_open_chain(monkeypatch):
    import tentaclass.features.lap as lap_module

    # a "closure" whose lap has only two distinct joints (p4 twice, then p5)
    monkeypatch.setattr(lap_module, "_closure", lambda points, t: (3, 1.0))
    q = np.array([0.0, 0.0, 0.0, 0.0, np.pi, 0.0])
    lap, closed = last_lap(q, n_out=8)
    assert not closed
    assert lap.shape == (8,) and np.all(np.isfinite(lap))


def test_straight_chain_has_no_lap_and_falls_back_without_error():
    # found by sklearn's estimator checks: the fallback went out and back along
    # the chain and met itself at the far end
    lap, closed = last_lap(np.zeros(5), n_out=16)
    assert not closed
    np.testing.assert_allclose(lap, 2 * np.pi / 16)


@pytest.mark.parametrize(
    "q", [np.full(18, 9.98718408e306), [-8.98846567e307, 9.97920155e291, 1.79769313e308, 1e291]]
)
def test_fuzz_found_huge_angles_are_refused(q):
    with pytest.raises(ValueError, match=r"beyond 2\*\*20 turns"):
        last_lap(q)


@pytest.mark.parametrize("scale", [1e-320, 1e-100, 1e100, 8e307])
def test_only_the_ratios_of_the_link_lengths_matter(scale):
    square = np.tile([0.0, 0.0, 0.0, np.pi / 2], 4)
    q = np.concatenate([[0.0, 0.0], square, square[:6]])
    lengths = np.linspace(1.0, 2.0, len(q))
    ref, ref_closed = last_lap(q, 16, lengths)
    lap, closed = last_lap(q, 16, lengths * scale)  # 1e308 overflowed, 1e-320 lost precision
    assert closed == ref_closed
    np.testing.assert_allclose(lap, ref, atol=1e-12)
    lap, _ = last_lap(q, 16, scale)
    np.testing.assert_allclose(lap, last_lap(q, 16)[0], atol=1e-12)
