import numpy as np
import pytest

from tentaclass import shapes
from tentaclass.errors import InputError
from tentaclass.wrapping import (
    capture_error,
    closing_link_length,
    link_length_for_laps,
    max_link_length,
    wrap,
)
from wrap_checks import MPEG7, needs_mpeg7


@pytest.mark.parametrize("k", [1, 2, 4, 8])
def test_square_links_a_over_k_from_a_corner_are_exact(k):
    assert capture_error(shapes.square(4), 4 / k) == pytest.approx(0, abs=1e-12)


def test_square_other_lengths_or_starts_lose_the_corners():
    assert capture_error(shapes.square(4), 4 / 3 * 1.1) > 0.01
    assert capture_error(shapes.square(4), 1.0, starts=[0.1]) > 0.01


@pytest.mark.parametrize("ln", [0.2, 0.5, 0.9])
def test_circle_error_is_the_sagitta(ln):
    r = 1.0
    sagitta = r - np.sqrt(r**2 - (ln / 2) ** 2)
    err = capture_error(shapes.circle(r, 2000), ln, starts=np.linspace(0, 1, 5, endpoint=False))
    assert err * 2 * r == pytest.approx(sagitta, rel=0.05, abs=2e-4)


def test_circle_rule_l_below_r():
    """A tolerance of a few percent of the diameter allows links up to about r, not beyond."""
    circle = shapes.circle(1.0, 720)
    errs = [capture_error(circle, ln) for ln in (0.5, 1.0, 1.5)]
    assert errs[0] < errs[1] < errs[2]
    l_max = max_link_length(circle, 0.07)
    assert 0.8 < l_max <= 1.0 + 1e-9
    assert max_link_length(circle, 0.01) < max_link_length(circle, 0.05)


def test_closing_link_length_thesis_shapes():
    for outline, n in [(shapes.square(4), 16), (shapes.rectangle(6, 2), 16),
                       (shapes.circle(1, 256), 16), (shapes.circle(1, 256), 64)]:  # fmt: skip
        ln, gap = closing_link_length(outline, n, start=0.23)
        assert gap < 1e-6
        w = wrap(outline, n, ln, start=0.23)
        assert w.laps == pytest.approx(1.0, abs=1e-6)


def test_errors():
    with pytest.raises(InputError):
        capture_error(shapes.square(4), 0.0)
    with pytest.raises(InputError, match="n_links"):
        closing_link_length(shapes.square(4), 1)
    with pytest.raises(InputError, match="no link length"):
        max_link_length(shapes.square(4), 1e-12, starts=[0.1])
    # a TypeError from the bisection before
    with pytest.raises(InputError, match="rtol must be a number, got None"):
        closing_link_length(shapes.square(4), 16, rtol=None)


@pytest.mark.slow
@pytest.mark.mpeg7
@needs_mpeg7
def test_mpeg7_outline_error_grows_with_link_length():
    outlines, _, names = shapes.load_mpeg7(MPEG7, max_vertices=1000)
    o = outlines[names.index("apple-1.png")]
    d = np.ptp(o, axis=0).max()
    # taut wraps cannot see the concavities (the stem): the error stays at the
    # hull's; hugging wraps follow them and lose them as the links grow
    taut = [capture_error(o, f * d, starts=[0.0, 0.5]) for f in (0.02, 0.1)]
    assert taut[0] == pytest.approx(taut[1], rel=0.05)
    hug = [capture_error(o, f * d, starts=[0.0, 0.5], mode="hug") for f in (0.02, 0.1, 0.3)]
    assert hug[0] < hug[1] < hug[2] and hug[0] < taut[0] / 3


def test_thin_rectangle_max_link_length_is_the_diameter():
    # a 10 x 0.001 strip: one link across the whole strip stays within a tolerance
    # of one diameter (this raised a GEOSException on a one-joint chain)
    r = shapes.rectangle(10, 1e-3)
    assert max_link_length(r, 1) == pytest.approx(np.hypot(10, 1e-3), rel=1e-6)


def test_capture_error_refuses_a_link_too_short_for_memory():
    with pytest.raises(InputError, match=r"link_length .* too short"):
        capture_error(shapes.square(4), 1e-300)


@pytest.mark.parametrize("laps", [1e-4, 1e-300])
def test_link_length_for_laps_refuses_laps_too_small_for_the_chain(laps):
    # was "n_links must be at most 100,000, got 160,000" (or a number of 300 digits)
    with pytest.raises(
        InputError, match=r"laps .* is too small for 16 links: .* use laps >= 0.00016"
    ):
        link_length_for_laps(shapes.square(4), 16, laps)
    assert link_length_for_laps(shapes.square(4), 16, 2e-4) == pytest.approx(16 / 80_000, rel=0.01)
