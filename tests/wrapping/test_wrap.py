import numpy as np
import pytest
import shapely
from hypothesis import example, given, settings
from hypothesis import strategies as st

from strategies import examples
from tentaclass import shapes
from tentaclass.errors import InputError
from tentaclass.geometry import angles_to_points, points_to_angles
from tentaclass.wrapping import WrapBatch, closing_link_length, wrap, wrap_many
from wrap_checks import crossing_links, link_length

PI = np.pi


def is_cyclic_shift(a, b, atol=1e-9):
    return any(np.allclose(np.roll(a, k), b, atol=atol) for k in range(len(a)))


# --- the thesis's cases --------------------------------------------------------


def test_square_thesis_array():
    w = wrap(shapes.square(4), 16, 1.0)
    assert is_cyclic_shift(w.angles, np.tile([0, 0, 0, PI / 2], 4))
    assert w.complete and w.laps == pytest.approx(1.0) and w.closure_gap < 1e-9
    assert w.contact.all()


def test_rectangle_thesis_array():
    w = wrap(shapes.rectangle(6, 2), 16, 1.0)
    assert is_cyclic_shift(w.angles, np.tile([0, 0, 0, 0, 0, PI / 2, 0, PI / 2], 2))


def test_triangle_thesis_style_array():
    tri = shapes.triangle([(0, 0), (4, 0), (0, 3)])  # sides 4, 5, 3: exact in floats
    w = wrap(tri, 12, 1.0)
    turns = points_to_angles(tri)
    expected = np.zeros(12)
    expected[[0, 4, 9]] = turns  # corners at arc 0, 4 and 9
    assert is_cyclic_shift(w.angles, expected)
    assert w.angles.sum() == pytest.approx(2 * PI)


@pytest.mark.parametrize("n", [16, 64])
def test_circle_gives_constant_angles(n):
    ln, gap = closing_link_length(shapes.circle(1.0, n_points=720), n)
    assert gap < 1e-6
    w = wrap(shapes.circle(1.0, n_points=720), n, ln, start=0.3)
    assert np.allclose(w.angles, 2 * PI / n, atol=0.02 * 2 * PI / n)


def test_circle_with_long_links_comes_out_square_like():
    """Thesis 4.5: a circle needs l < r; at l = r*sqrt(2) it is sampled as a square."""
    w = wrap(shapes.circle(1.0, n_points=720), 8, np.sqrt(2))
    assert np.allclose(w.angles, PI / 2, atol=1e-6)
    square = wrap(shapes.square(2.0), 8, 2.0)
    assert np.allclose(w.angles, square.angles, atol=1e-6)


# --- geometry properties ------------------------------------------------------


def star(n_tips, r_in, r_out, rotation=0.0):
    a = rotation + np.arange(2 * n_tips) * PI / n_tips
    r = np.where(np.arange(2 * n_tips) % 2 == 0, r_out, r_in)
    return np.stack([r * np.cos(a), r * np.sin(a)], axis=1)


OUTLINES = {
    "square": shapes.square(3.0),
    "rectangle": shapes.rectangle(5.0, 0.6),
    "triangle": shapes.triangle([(0, 0), (4, 0), (0.5, 1.5)]),
    "circle": shapes.circle(2.0, 300),
    "star": star(5, 0.8, 2.0),
    "thin star": star(3, 0.15, 2.0, 0.3),
    "L": shapes.polygon([(0, 0), (3, 0), (3, 1), (1, 1), (1, 3), (0, 3)]),
    "comb": shapes.polygon([(0, 0), (5, 0), (5, 3), (4, 3), (4, 1), (3, 1), (3, 3), (2, 3),
                            (2, 1), (1, 1), (1, 3), (0, 3)]),
}  # fmt: skip


def check_geometry(outline, w, ln):
    scale = np.ptp(outline, axis=0).max()
    ring = shapely.LinearRing(outline)
    j = w.joints
    # contacts lie on the outline
    if w.contact.any():
        d = shapely.distance(shapely.points(j[w.contact]), ring)
        assert d.max() < 1e-9 * scale
    # links are exactly l long
    assert np.allclose(np.hypot(*np.diff(j, axis=0).T), ln, rtol=1e-9, atol=0)
    # forward kinematics of the angles gives the joints back
    if len(w.angles):
        fk = angles_to_points(w.angles, ln, base=j[0], heading=w.heading)
        assert np.allclose(fk, j, atol=1e-7 * scale)
    # no link that leaves the support (approach, bridge, overhang) enters the object
    air = (w.lap[:-1] < 0) | (w.lap[1:] < 0)
    assert not (crossing_links(outline, j) & air).any()


@settings(max_examples=examples(60), deadline=None)
@given(
    name=st.sampled_from(sorted(OUTLINES)),
    n=st.integers(1, 80),
    frac=st.floats(0.02, 0.25),
    start=st.floats(0, 0.999),
    direction=st.sampled_from(["ccw", "cw"]),
    mode=st.sampled_from(["taut", "hug"]),
    offset_links=st.sampled_from([0.0, 0.5, 1.0, 2.7]),
)
# found by the fuzz profile: a stand-off longer than the whole chain is refused
@example(name="L", n=1, frac=0.25, start=0.0, direction="ccw", mode="taut", offset_links=2.7)
# found by the fuzz profile: a link from a tip in the air that cuts a sliver 7e-7 wide
# off the hull, and a chord round a corner through a slot of the comb
@example(name="L", n=1, frac=0.25, start=1.192092896e-07, direction="cw", mode="taut",
         offset_links=0.5)  # fmt: skip
@example(name="comb", n=8, frac=0.25, start=0.96875, direction="ccw", mode="taut",
         offset_links=2.7)  # fmt: skip
def test_wrap_geometry_properties(name, n, frac, start, direction, mode, offset_links):
    outline = OUTLINES[name]
    ln = link_length(outline, frac)
    offset_links = min(offset_links, n)  # the chain must reach the object
    w = wrap(outline, n, ln, start=start, direction=direction, mode=mode,
             offset=offset_links * ln)  # fmt: skip
    assert len(w.angles) == n and w.complete  # a chain always ends somewhere
    check_geometry(outline, w, ln)
    assert w.offset_links == int(np.ceil(offset_links - 1e-9))
    assert not w.contact[1 : w.offset_links].any()


def test_approach_through_the_object_turns_around_it():
    comb = OUTLINES["comb"]  # start on a tooth's wall, facing the next tooth 1 unit away
    body = shapely.Polygon(comb)
    for direction in ("ccw", "cw"):
        w = wrap(comb, 3, 0.75, start=0.4375, mode="hug", offset=2.025, direction=direction)
        assert w.complete and len(w.angles) == 3
        np.testing.assert_allclose(np.hypot(*(w.joints[0] - w.start_point)), 2.025)
        path = shapely.LineString([w.joints[0], w.start_point])
        assert shapely.intersection(path, body).length < 1e-9  # the approach stays outside
    b = wrap_many(comb, 3, 0.75, starts=0.4375, offset=[0.5, 2.025, 0.0], mode="hug")
    assert b.complete.all()
    w = wrap(comb, 4, 0.75, start=0.4375, mode="hug", offset=0.5)  # stays in the slot
    assert w.offset_links == 1 and w.complete
    np.testing.assert_allclose(w.joints[0], [3.5, 1.5])
    ok = wrap(shapes.square(4), 40, 1.0, offset=30.0)  # convex: any stand-off is fine
    assert ok.offset_links == 30


def test_taut_links_stay_on_or_outside_the_hull():
    outline = OUTLINES["star"]
    hull = shapely.Polygon(outline).convex_hull
    w = wrap(outline, 40, 0.7, start=0.31)
    pts = shapely.points(w.joints)
    assert np.all((shapely.distance(pts, hull.exterior) < 1e-9) | ~shapely.contains(hull, pts))
    assert not w.contact[w.lap == 0].all()  # joints on hull bridges do not touch


def test_hug_enters_wide_concavities_and_bridges_narrow_ones():
    comb = OUTLINES["comb"]  # slots 1 wide, 2 deep
    narrow = wrap(comb, 30, 1.5, mode="hug")  # links longer than the slots are wide
    wide = wrap(comb, 60, 0.3, mode="hug")
    slot_bottom = shapely.LineString([(1, 1), (2, 1)])
    assert shapely.distance(shapely.points(wide.joints), slot_bottom).min() < 1e-9
    assert shapely.distance(shapely.points(narrow.joints), slot_bottom).min() > 0.5


def test_full_single_wrap_sums_to_2pi():
    for name in ("square", "triangle", "circle", "star"):
        outline = OUTLINES[name]
        for start in (0.0, 0.37):
            ln, gap = closing_link_length(outline, 24, start=start)
            w = wrap(outline, 24, ln, start=start)
            if gap < 1e-6:
                assert w.angles.sum() == pytest.approx(2 * PI, abs=1e-6)
                assert w.laps == pytest.approx(1.0, abs=1e-6)
            cw = wrap(outline, 24, ln, start=start, direction="cw")
            assert cw.angles.sum() < 0


def test_laps_grow_with_n_links():
    for name in ("square", "star", "comb"):
        laps = [wrap(OUTLINES[name], n, 0.9, start=0.2).laps for n in range(1, 60, 3)]
        assert np.all(np.diff(laps) >= -1e-9)
        assert laps[-1] > 2


@pytest.mark.parametrize("mode", ["taut", "hug"])
def test_circle_laps_read_out_with_one_fixed_chain(mode):
    # one chain of 64 unit links, the circle sized for 1.2-2 laps after a stand-off
    rng = np.random.default_rng(3)
    for target in np.linspace(1.2, 2.0, 9):
        off = float(rng.uniform(0, 2))
        r = (64 - off) / target / (2 * np.pi)
        w = wrap(shapes.circle(r, 256), 64, 1.0, start=float(rng.uniform()), offset=off,
                 direction=str(rng.choice(["ccw", "cw"])), mode=mode)  # fmt: skip
        assert w.complete and w.laps == pytest.approx(target, abs=0.03)
        assert w.closure_gap < 1.0  # the second lap passes within a link of the start


def test_cw_is_the_mirror_image():
    outline = OUTLINES["L"]
    mirrored = shapes.polygon(outline * [-1, 1])
    ccw = wrap(mirrored, 20, 0.7, start=0.0)
    # the start point of the mirrored outline is the mirror of the original's start
    start_cw = shapes.polygon(outline).tolist().index((-mirrored[0] * [1, -1]).tolist())
    per = np.r_[0, np.cumsum(np.hypot(*np.diff(np.vstack([outline, outline[:1]]), axis=0).T))]
    cw = wrap(outline, 20, 0.7, start=per[start_cw] / per[-1], direction="cw")
    assert np.allclose(cw.angles, -ccw.angles, atol=1e-9)
    assert np.allclose(cw.joints, ccw.joints * [-1, 1], atol=1e-9)
    assert cw.laps == pytest.approx(ccw.laps)


def test_offset_approach():
    w = wrap(shapes.square(4), 12, 1.0, start=0.125, offset=2.5)
    assert w.offset_links == 3
    assert np.allclose(w.angles[:2], 0)
    assert w.angles[2] + w.angles[3] == pytest.approx(-PI / 2)
    assert np.hypot(*(w.joints[0] - w.start_point)) == pytest.approx(2.5)
    assert not w.contact[:3].any() and w.contact[3:].all()


@pytest.mark.parametrize("frac", [0.25, 0.3, 0.35])
@pytest.mark.parametrize("direction", ["ccw", "cw"])
def test_small_circle_after_an_overhanging_approach_link_regains_constant_angles(frac, direction):
    # the approach's last joint hangs ``frac`` above the start point: its link
    # to the circle would cut it, so it rests on the tangent with its tip a
    # hair above the circle; from there the chain lies on its joints again
    r = 6.5 / (2 * PI)
    w = wrap(shapes.circle(r, 256), 16, 1.0, start=0.4, offset=2 + frac, direction=direction)
    chord_turn = 2 * np.arcsin(1 / (2 * r))
    sign = 1 if direction == "ccw" else -1
    assert np.allclose(w.angles[5:], sign * chord_turn, atol=0.01)
    assert np.allclose(np.hypot(*w.joints[5:].T), r, atol=0.01)
    assert w.angles[3:].sum() * sign > 2 * PI


def test_multiple_laps_with_thickness():
    w = wrap(shapes.circle(1.0, 360), 60, 0.3, thickness=0.05)
    assert w.complete and w.laps > 2
    r = np.hypot(*w.joints.T)
    for k in range(int(w.lap.max()) + 1):
        on = w.lap == k
        assert np.all(r[on] <= 1 + 0.05 * k + 1e-9) and np.all(r[on] >= 1 + 0.05 * k - 0.02)
    assert np.all(np.diff(w.lap[w.lap >= 0]) >= 0)


def test_noise_is_reproducible_and_only_on_angles():
    a = wrap(shapes.square(4), 16, 1.0, noise=0.01, random_state=3)
    b = wrap(shapes.square(4), 16, 1.0, noise=0.01, random_state=3)
    c = wrap(shapes.square(4), 16, 1.0)
    assert np.array_equal(a.angles, b.angles)
    assert 0 < np.std(a.angles - c.angles) < 0.03
    assert np.array_equal(a.joints, c.joints)


def test_batch_equals_loop_and_shapes():
    starts = np.linspace(0, 1, 7, endpoint=False)
    b = wrap_many(OUTLINES["star"], 20, 0.6, starts=starts, offset=[0, 1, 0, 0.5, 0, 0, 2])
    assert isinstance(b, WrapBatch) and len(b) == 7
    assert b.angles.shape == (7, 20) and b.joints.shape == (7, 21, 2)
    assert b.contact.shape == (7, 21) and b.laps.shape == (7,)
    for i, s in enumerate(starts):
        w = wrap(OUTLINES["star"], 20, 0.6, start=s, offset=[0, 1, 0, 0.5, 0, 0, 2][i])
        assert np.array_equal(b[i].angles, w.angles)
        assert np.array_equal(b[i].joints, w.joints)
    many = wrap_many([OUTLINES["square"], OUTLINES["circle"]], 10, [0.5, 0.4], starts=[0, 0.5])
    assert many.angles.shape == (2, 10)


def test_every_link_is_placed_where_the_support_offers_none():
    # the base sits between two tips of a thin star; in hug mode a link this
    # long cannot follow the support without crossing: it folds in towards the
    # object instead, and the chain still places every link.
    results = [wrap(OUTLINES["thin star"], 50, 1.6, start=s, mode="hug")
               for s in np.linspace(0, 1, 24, endpoint=False)]  # fmt: skip
    for w in results:
        assert len(w.angles) == w.joints.shape[0] - 1 == 50 and w.complete
        np.testing.assert_allclose(np.hypot(*np.diff(w.joints, axis=0).T), 1.6, rtol=1e-9)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"outline": [(0, 0), (1, 0), (np.nan, 1)]}, "NaN"),
        ({"outline": [(0, 0), (1, 0)]}, "at least 3"),
        ({"outline": [(0, 0), (1, 1), (2, 2)]}, "zero area"),
        ({"outline": [(0, 0), (4, 0), (4, 4), (2, -1), (0, 4)]}, "intersects itself"),
        ({"link_length": 0.0}, "link_length"),
        ({"link_length": 10.0}, "diameter"),
        # joints 1e-20 apart coincide in float64: the square's corners turned by 0
        ({"link_length": 1e-20}, "link_length 1e-20 is too short for an object of diameter 5.65"),
        ({"n_links": 0}, "n_links"),
        ({"start": 1.0}, "start"),
        ({"direction": "up"}, "direction"),
        ({"mode": "loose"}, "mode"),
        ({"noise": -1.0}, "noise"),
        # the angles came back beyond 2**20 turns, refused later as "q holds an angle of"
        ({"noise": 1e300}, r"noise must be at most 2\*pi radians .*, got 1e\+300"),
        ({"offset": -1.0}, "offset"),
        ({"offset": -1.0}, "must be >= 0"),  # was "must lie in >= 0"
        ({"noise": 0.1, "random_state": "x"}, "random_state"),  # was TypeError
        # one wrap by a chain of equal links: an array of lengths was a batch cut to its first
        ({"link_length": [1.0, 2.0] * 8}, "link_length must be one number, got 16 values"),
        ({"link_length": [1.0]}, "link_length must be one number, got 1 value "),
        ({"start": [0.1, 0.2]}, "start must be one number, got 2 values"),
        ({"offset": [[0.0], [1.0, 2.0]]}, "offset must be one number, got a ragged sequence"),
    ],
)
def test_bad_input(kwargs, match):
    args = {"outline": shapes.square(4), "n_links": 16, "link_length": 1.0} | kwargs
    with pytest.raises(InputError, match=match):
        wrap(**args)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"link_length": [0.5, 0.6], "starts": [0.1, 0.2, 0.3]},
         r"link_length, starts and offset have 2, 3 and 1 values"),
        ({"starts": []}, "starts is empty"),  # was numpy's "zero-size array to reduction"
        ({"link_length": []}, "link_length is empty"),
        ({"outlines": [shapes.square(4)] * 2, "offset": [0.0, 0.1, 0.2]},
         "offset has 3 values for 2 wraps: give one value or 2"),
    ],
)  # fmt: skip
def test_wrap_many_batches_that_do_not_match(kwargs, match):
    args = {"outlines": shapes.square(4), "n_links": 16, "link_length": 1.0} | kwargs
    with pytest.raises(InputError, match=match):
        wrap_many(args.pop("outlines"), args.pop("n_links"), args.pop("link_length"), **args)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"thickness": 1e300}, "thickness .* larger than the object"),
        ({"offset": 1e20}, "offset .* longer than the chain"),
        ({"offset": 1e300}, "offset .* longer than the chain"),
    ],
)
def test_inputs_beyond_physical_sense_name_the_limit(kwargs, match):
    with pytest.raises(ValueError, match=match):
        wrap(shapes.square(4), 40, 1.0, **kwargs)


def test_link_count_has_a_documented_maximum():
    from tentaclass.wrapping import MAX_LINKS

    with pytest.raises(ValueError, match=f"at most {MAX_LINKS:,}"):
        wrap_many(shapes.square(4), MAX_LINKS + 1, 1.0, [0.0])
