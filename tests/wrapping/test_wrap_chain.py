"""Every wrap is a physical chain: complete, exact link lengths, never through the object or itself.

Checked with the independent helper in ``chain_check`` (shapely and numpy only)
over the thesis shapes, star polygons and MPEG-7 outlines, both modes, 1-3
laps, with stand-offs and thickness.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
import shapely
from chain_check import chain_problems
from hypothesis import example, given, settings
from hypothesis import strategies as st

from strategies import examples
from tentaclass import shapes
from tentaclass.wrapping import wrap, wrap_many
from wrap_checks import link_length

MPEG7 = Path(
    os.environ.get(
        "TENTACLASS_MPEG7",
        Path(__file__).resolve().parents[2].parent / "shared" / "data" / "mpeg7-part-b",
    )
)
needs_mpeg7 = pytest.mark.skipif(
    not MPEG7.is_dir(), reason=f"MPEG-7 Part B not found at {MPEG7} (shared data absent)"
)


def star(n_tips, r_in, r_out, rotation=0.0):
    a = rotation + np.arange(2 * n_tips) * np.pi / n_tips
    r = np.where(np.arange(2 * n_tips) % 2 == 0, r_out, r_in)
    return np.stack([r * np.cos(a), r * np.sin(a)], axis=1)


def random_star(seed, n=24):
    rng = np.random.default_rng(seed)
    a = np.sort(rng.uniform(0, 2 * np.pi, n))
    r = rng.uniform(0.3, 1.0, n)
    return np.stack([r * np.cos(a), r * np.sin(a)], axis=1)


THESIS = [shapes.square(4), shapes.rectangle(6, 2), shapes.circle(2, 256),
          shapes.triangle(side=5)]  # fmt: skip
STARS = [star(5, 0.8, 2.0), star(3, 0.15, 2.0, 0.3)] + [random_star(s) for s in range(6)]
CHAIN_PROBLEMS = ("incomplete", "bad_length")
CROSSINGS = ("object", "self")


def draw_case(outline, rng, mode, laps):
    """A random wrap of ``laps`` laps: link 1-10 % of the hull's perimeter, any start etc."""
    hull = shapely.Polygon(outline).convex_hull
    ln = float(np.exp(rng.uniform(np.log(0.01), np.log(0.1)))) * hull.length
    return {
        "n_links": int(np.ceil(laps * hull.length / ln)),
        "link_length": ln,
        "starts": float(rng.uniform()),
        "mode": mode,
        "direction": str(rng.choice(["ccw", "cw"])),
        "offset": float(rng.choice([0.0, rng.uniform(0, 5 * ln)])),
        "thickness": float(rng.choice([0.0, rng.uniform(0, ln)])),
    }


def problems_over(outlines, kinds, modes=("taut", "hug"), laps=(1, 2, 3), seed=0, every=True):
    """Wraps of every outline in every mode and lap count (``every=False``: the lap
    count cycles over the outlines), and which of ``kinds`` of problems they have."""
    rng = np.random.default_rng(seed)
    bad = []
    for mode in modes:
        for k in laps if every else [None]:
            for i, outline in enumerate(outlines):
                case = draw_case(outline, rng, mode, k or laps[i % len(laps)])
                w = wrap_many(outline, **case)[0]
                found = {key: v for key, v in chain_problems(outline, w).items()
                         if v and key in kinds}  # fmt: skip
                if found:
                    bad.append((i, case, found))
    return bad


def test_thesis_shapes_and_stars_place_every_link():
    assert problems_over(THESIS + STARS, CHAIN_PROBLEMS) == []


#: Silhouettes with legs, antennae, slots and springs, where links fold and bridge most.
HARD = ["beetle-1.png", "device8-1.png", "fly-1.png", "spring-1.png", "fork-1.png",
        "bat-1.png", "lizzard-1.png"]  # fmt: skip


@pytest.mark.mpeg7
@needs_mpeg7
@pytest.mark.parametrize("mode", ["taut", "hug"])
def test_spread_of_mpeg7_outlines_place_every_link(mode):
    # every 35th silhouette (all classes in turn) and the hard ones, 1-3 laps in
    # turn; benchmarks/wrap_crossings.py checks all 1400 for crossings
    outlines, _, names = shapes.load_mpeg7(MPEG7, max_vertices=1000)
    pick = sorted(set(range(0, len(outlines), 35)) | {names.index(h) for h in HARD})
    bad = problems_over([outlines[i] for i in pick], CHAIN_PROBLEMS, modes=(mode,), every=False)
    assert not bad, (len(bad), [(names[pick[i]], c, f) for i, c, f in bad[:5]])


@settings(max_examples=examples(40), deadline=None)
@given(
    which=st.integers(0, len(THESIS + STARS) - 1),
    n=st.integers(1, 150),
    frac=st.floats(0.01, 0.3),
    start=st.floats(0, 0.999),
    direction=st.sampled_from(["ccw", "cw"]),
    mode=st.sampled_from(["taut", "hug"]),
    offset_links=st.floats(0, 5),
    thickness=st.floats(0, 1),
)
@example(which=0, n=40, frac=0.0625, start=0.0, direction="ccw", mode="taut", offset_links=0,
         thickness=0)  # fmt: skip
@example(which=5, n=64, frac=0.05, start=0.3, direction="cw", mode="hug", offset_links=2.7,
         thickness=0.5)  # fmt: skip
def test_any_wrap_places_every_link(
    which, n, frac, start, direction, mode, offset_links, thickness
):
    outline = (THESIS + STARS)[which]
    ln = link_length(outline, frac)
    offset = min(offset_links * ln, n * ln)
    w = wrap(outline, n, ln, start=start, direction=direction, mode=mode, offset=offset,
             thickness=thickness * ln)  # fmt: skip
    found = chain_problems(outline, w)
    assert (found["incomplete"], found["bad_length"]) == (0, 0)
    assert len(w.angles) == n


@pytest.mark.parametrize("seed", range(3))
def test_single_taut_laps_never_cross(seed):
    assert problems_over(THESIS + STARS, CROSSINGS, modes=("taut",), laps=(1,), seed=seed) == []


@pytest.mark.xfail(
    strict=True,
    reason="a later lap retraces the first lap's support with its joints elsewhere: over "
    "concave stretches and dents its chords cross the first lap's in the air",
)
def test_later_laps_never_cross():
    assert problems_over(THESIS + STARS, CROSSINGS, laps=(2, 3)) == []
