"""Physical grasps in MuJoCo: result type, classification, concavities, grasp state, bad input."""

import numpy as np
import pytest
import shapely

pytest.importorskip("mujoco", reason="needs the physics extra: pip install mujoco")

from tentaclass import (
    PlanarChain,
    ShiftNNClassifier,
    Wrap,
    angles_to_points,
    grasp_state,
    wrap,
)
from tentaclass.datasets import synthetic_tentacle
from tentaclass.errors import InputError
from tentaclass.physics import (
    CurlController,
    PhysicalGrasp,
    build_model,
    grasp,
    grasp_many,
    quasi_static_grasp,
)
from tentaclass.shapes import circle, polygon, rectangle, square, triangle

#: A C whose upper arm is shorter than its lower one: the opening between the
#: lip corners (6, 1) and (4, 3) is 2.83 wide, the slot behind it 2 high.
C_SHAPE = polygon([(0, 0), (6, 0), (6, 1), (2, 1), (2, 3), (4, 3), (4, 4), (0, 4)])


@pytest.fixture(scope="module")
def recogniser():
    """Trained only on geometric wraps of the four thesis classes.

    The polygon matcher closed by its gap chord: physical chains close less of
    a lap than geometric ones (rigid links overhang corners). Objects sized
    for 1.0-1.3 laps of their perimeter take 1.0-1.47 laps of the hug
    generator (its links cut corners), so it learns 1.0-1.5 laps.
    """
    d = synthetic_tentacle(2000, 16, laps=(1.0, 1.5), offset=(0.0, 0.0), random_state=3)
    return ShiftNNClassifier(signal="shape", closure="chord").fit(d.data, d.target)


@pytest.mark.parametrize("direction", ["ccw", "cw"])
@pytest.mark.parametrize("offset", [0.0, 2.0])
def test_result_is_a_wrap_that_rebuilds_its_joints(direction, offset):
    g = grasp(square(3.0), PlanarChain([0.5] * 24), start=0.3, direction=direction, offset=offset)
    assert isinstance(g, Wrap) and isinstance(g, PhysicalGrasp)
    assert g.complete, g.reason
    assert g.angles.shape == (24,) and g.joints.shape == (25, 2)
    assert g.contact.shape == g.lap.shape == (25,)
    rebuilt = angles_to_points(g.angles, 0.5, base=g.joints[0], heading=g.heading)
    np.testing.assert_allclose(rebuilt, g.joints, atol=1e-6)
    assert np.sign(g.angles.sum()) == (1 if direction == "ccw" else -1)
    assert g.offset_links == (4 if offset else 0)
    # no joint inside the object, contact joints on its surface (links are 0.05 thick)
    body = shapely.Polygon(square(3.0))
    dist = shapely.distance(shapely.points(g.joints), body)
    assert np.all(dist > 0)
    assert g.contact.any() and np.all(dist[g.contact] < 0.05)
    if offset:
        assert np.allclose(g.angles[:3], 0.0, atol=0.05)  # the approach stays straight
        state = grasp_state(g.angles)
        assert state.offset_links.item() == 4


@pytest.mark.parametrize(
    ("outline", "label"), [(square(3.6), "square"), (circle(16 / (2 * np.pi)), "circle")]
)
def test_square_and_circle_grasped_and_classified(outline, label, recogniser):
    g = grasp(outline, PlanarChain([1.0] * 16), start=0.37)
    assert g.complete, g.reason
    assert 0.7 < g.laps < 1.3
    assert recogniser.predict(g.angles[None])[0] == label


@pytest.mark.parametrize(
    ("length", "n", "enters"),
    [(0.5, 30, True), (2.5, 9, True), (2.7, 9, False), (3.5, 6, False)],
)
def test_c_shape_opening_entered_only_when_a_link_fits(length, n, enters):
    # a link fits when it and its capsule (a tenth of a link thick) pass between the lips:
    # 2.5 + 0.25 < 2.83 enters, 2.7 + 0.27 > 2.83 bridges the opening like 3.5
    opening = shapely.Polygon([(6, 1), (2, 1), (2, 3), (4, 3)])  # the slot, behind the lip line
    g = grasp(C_SHAPE, PlanarChain([length] * n), start=0.02)
    assert g.complete, g.reason
    inside = int(np.sum(shapely.contains_xy(opening, *g.joints.T)))
    if not enters:
        assert inside == 0
    else:
        assert inside >= (5 if length < 1 else 1)  # short links follow the slot
        # resting in it: every joint in the slot touches the object or the chain
        in_slot = shapely.contains_xy(opening, *g.joints.T)
        assert np.all(g.lap[in_slot] >= 0)


def _true_state(g):
    """State from the simulation's own lap count (it knows the offset and direction)."""
    return "partial" if g.laps < 0.9 else ("once" if g.laps <= 1.1 else "multiple")


def _random_grasps(n, seed):
    rng = np.random.default_rng(seed)
    makers = [lambda s: square(s), lambda s: circle(s / 2), lambda s: rectangle(1.5 * s, s),
              lambda s: triangle(side=1.5 * s)]  # fmt: skip
    out = []
    for i in range(n):
        o = makers[i % 4](1.0)
        target = [0.6, 1.0, 1.7][i % 3]
        off = float(rng.choice([0.0, 0.0, 2.0]))
        o = o * ((16 - off) / target / shapely.Polygon(o).length)
        out.append((o, float(rng.uniform(0, 1)), off, str(rng.choice(["ccw", "cw"]))))
    return out


def _state_agreement(cases):
    """Fraction of grasps whose state and offset grasp_state reads right; the true states."""
    chain = PlanarChain([1.0] * 16)
    right, truth = 0, []
    for o, s, off, d in cases:
        g = grasp(o, chain, start=s, offset=off, direction=d)
        assert g.complete, g.reason
        st = grasp_state(g.angles)  # from the angles alone
        truth.append(_true_state(g))
        right += st.state.item() == truth[-1] and st.offset_links.item() == g.offset_links
    return right / len(cases), truth


def test_grasp_state_on_physical_grasps_quick():
    assert _state_agreement(_random_grasps(12, seed=5))[0] >= 0.9


@pytest.mark.slow
def test_grasp_state_on_200_physical_grasps():
    # 200 generated grasps of the thesis shapes (16 links, a third with a 2-link
    # approach, both directions); every grasp completes, all three states occur
    # (103 partial, 42 once, 55 multiple) and all 200 are read right
    right, truth = _state_agreement(_random_grasps(200, seed=7))
    assert right >= 0.95
    assert all(truth.count(state) >= 30 for state in ("partial", "once", "multiple"))


def _thesis_objects(n, seed):
    """Random thesis-class objects whose perimeter 16 unit links cover 1.0-1.3 times."""
    rng = np.random.default_rng(seed)
    labels, objects = [], []
    for i in range(n):
        label = ("circle", "rectangle", "square", "triangle")[i % 4]
        o = {"circle": circle(1.0), "square": square(1.0),
             "rectangle": rectangle(float(rng.uniform(1.2, 4.0)), 1.0),
             "triangle": triangle(side=1.0)}[label]  # fmt: skip
        o = o - o.mean(axis=0)
        o = o * (16 / rng.uniform(1.0, 1.3) / shapely.Polygon(o).length)
        th = rng.uniform(0, 2 * np.pi)
        rot = np.array([[np.cos(th), np.sin(th)], [-np.sin(th), np.cos(th)]])
        labels.append(label)
        objects.append(o @ rot)
    return np.array(labels), objects


def test_recogniser_trained_on_geometric_wraps_reads_physical_grasps(recogniser):
    # sim-to-real in small: trained only on generated geometric wraps, scored on hug
    # wraps and on physical grasps of the same 40 objects, same chain, start and
    # direction; an incomplete wrap or grasp counts as an error (all complete here:
    # 38 of 40 geometric and 40 of 40 physical read right)
    y, objects = _thesis_objects(40, seed=11)
    rng = np.random.default_rng(12)
    starts = rng.uniform(0, 1, len(y))
    dirs = [str(d) for d in rng.choice(["ccw", "cw"], len(y))]
    geo = [wrap(o, 16, 1.0, start=s, direction=d, mode="hug")
           for o, s, d in zip(objects, starts, dirs, strict=True)]  # fmt: skip
    phys = grasp_many(objects, PlanarChain([1.0] * 16), starts, direction=dirs)

    def accuracy(ws):
        ok = np.array([w.complete for w in ws])
        pred = recogniser.predict(np.array([w.angles for w in ws]))
        return float(np.mean(ok & (pred == y)))

    acc_geo, acc_phys = accuracy(geo), accuracy(phys)
    assert acc_geo >= 0.9
    assert acc_phys >= 0.95 * acc_geo, (acc_geo, acc_phys)


def test_grasp_many_matches_single_grasps():
    chain = PlanarChain([0.5] * 12)
    outs = [square(2.0), triangle(side=3.0)]
    many = grasp_many(outs, chain, [0.1, 0.6], direction=["ccw", "cw"], n_jobs=2)
    for o, s, d, g in zip(outs, [0.1, 0.6], ["ccw", "cw"], many, strict=True):
        one = grasp(o, chain, start=s, direction=d)
        np.testing.assert_allclose(g.angles, one.angles)


def test_frames_record_the_closing():
    g = grasp(square(2.0), PlanarChain([0.5] * 12), frames=5)
    assert g.frames.ndim == 3 and g.frames.shape[1:] == (13, 2) and len(g.frames) > 3
    np.testing.assert_allclose(g.frames[-1], g.joints)


def test_unreachable_and_time_limit_are_flagged_incomplete():
    far = grasp(square(2.0), PlanarChain([1.0] * 8), offset=10.0)
    assert not far.complete and "cannot reach" in far.reason
    short = grasp(square(2.0), PlanarChain([0.5] * 12), time_limit=0.05)
    assert not short.complete and "time limit" in short.reason
    # rest needs a still second; only half a second is allowed to settle
    restless = CurlController(rest_time=1.0, settle_time=0.5)
    g = grasp(square(2.0), PlanarChain([0.5] * 12), controller=restless)
    assert not g.complete and "did not come to rest within 0.5 s" in g.reason


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"speed": 0.0}, "speed"),  # the set point would never move: no stop, no time limit
        ({"speed": float("nan")}, "speed"),
        ({"rest_time": 0.0}, "rest_time"),
        ({"settle_time": -1.0}, "settle_time"),
        ({"torque": -1.0}, "torque"),
        ({"control_steps": 0}, "control_steps"),  # simulated time would never advance
    ],
)
def test_controller_that_could_never_finish_is_refused(kwargs, match):
    with pytest.raises(InputError, match=match):
        CurlController(**kwargs)


def test_step_budget_counts_the_time_limit_and_the_longest_chain():
    # a short time limit bounds the steps of a small timestep: the grasp runs and stops
    g = grasp(square(2.0), PlanarChain([0.5] * 8), timestep=1e-6, time_limit=0.002)
    assert not g.complete and "time limit" in g.reason and g.steps <= 2005
    # a rest_time longer than every settle: never at rest, flagged (was an OverflowError)
    never = CurlController(rest_time=1e300, settle_time=0.5)
    g = grasp(square(2.0), PlanarChain([0.5] * 12), controller=never)
    assert not g.complete and "did not come to rest within 0.5 s" in g.reason


def test_batch_and_model_refuse_what_is_not_a_chain():
    with pytest.raises(InputError, match="must be a PlanarChain or a sequence of them, got str"):
        grasp_many(square(2.0), "chain")
    with pytest.raises(InputError, match="chain must hold PlanarChain objects, got float"):
        grasp_many(square(2.0), [1.0, 1.0], starts=[0.0, 0.5])
    with pytest.raises(InputError, match="chain must be a PlanarChain, got list"):
        build_model([1.0, 1.0])


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"outline": [(0, 0), (1, 1), (1, 0), (0, 1)]}, "intersects itself"),
        ({"outline": [(0, 0), (1, 1), (2, 2)]}, "zero area"),
        ({"start": 1.0}, "start"),
        ({"offset": -1.0}, "offset"),
        ({"direction": "up"}, "direction"),
        ({"chain": [1.0] * 4}, "PlanarChain"),
        ({"controller": "curl"}, "CurlController"),
        ({"outline": C_SHAPE, "start": 0.45, "offset": 5.0}, "passes through"),
        # links far longer than the object: refused before MuJoCo is asked to mesh it
        ({"outline": square(2e-9)}, r"link_length 0.5 is longer than the object's diameter 2.8"),
        ({"chain": PlanarChain([0.5] * 7 + [2.9])}, r"link_length 2.9 .* \(use link_length <= 2.8"),
        ({"thickness": 1e300}, r"thickness 1e\+300 is larger than the object \(diameter 2.8"),
        ({"chain": PlanarChain([1e-300] * 8)}, "link_length 1e-300 is too short for an object"),
        ({"chain": PlanarChain([0.001] * 497)}, "MuJoCo builds chains of at most 496 links"),
        ({"chain": PlanarChain([0.001] * 10**6)}, "at most 496 links .*, got 1,000,000"),
        ({"thickness": 1e-300}, r"thickness 1e-300 is too thin .* \(use thickness >= 2.8"),
        ({"start": None}, "start must be a finite number, got None"),
        ({"start": [0.1]}, r"start must be a finite number, got \[0.1\]"),
        ({"frames": "2"}, "frames must be an integer, got '2'"),
        ({"frames": -1}, "frames must be at least 0, got -1"),
        # simulations no call could finish: refused before a step is taken
        ({"timestep": 1e-9}, r"up to 3.11e\+10 simulation steps \(31.11 s in steps of 1e-09 s"),
        ({"controller": CurlController(control_steps=10**9)}, r"up to 1e\+09 simulation steps"),
        ({"controller": CurlController(speed=1e-300)}, r"up to 2.51e\+304 simulation steps"),
        # masses the controller cannot move: a chain of 1e21 kg links used to read as at rest
        ({"chain": PlanarChain([0.5] * 8, masses=1e300)}, r"masses: link 0 weighs 1e\+300"),
        ({"chain": PlanarChain([0.5] * 8, masses=[1.0] * 7 + [1e-300])}, r"link 7 weighs 1e-300"),
        ({"chain": PlanarChain([0.5] * 8, inertia=1e300)}, r"inertia: link 0 has inertia 4e\+300"),
    ],
)
def test_bad_input(kwargs, match):
    args = {"outline": square(2.0), "chain": PlanarChain([0.5] * 8)} | kwargs
    outline, chain = args.pop("outline"), args.pop("chain")
    with pytest.raises(InputError, match=match):
        grasp(outline, chain, **args)


@pytest.mark.parametrize("method", [grasp, quasi_static_grasp])
def test_links_longer_than_the_object_are_refused_as_wrap_refuses_them(method):
    for length in (2.0, 2.8):  # up to the diagonal 2.83, links fit
        method(square(2.0), PlanarChain([length] * 3))
    with pytest.raises(InputError) as physical:
        method(square(2.0), PlanarChain([2.9] * 3))
    with pytest.raises(InputError) as geometric:
        wrap(square(2.0), 3, 2.9)
    assert str(physical.value) == str(geometric.value)
    assert "use link_length <= 2.82843" in str(physical.value)


def test_an_object_too_small_to_mesh_is_named():
    with pytest.raises(InputError, match="MuJoCo cannot build this chain or object: mesh"):
        build_model(PlanarChain([0.5] * 8), square(2e-9))


def test_controller_speed_does_not_change_a_square_much():
    a = grasp(square(3.0), PlanarChain([0.5] * 24))
    b = grasp(square(3.0), PlanarChain([0.5] * 24), controller=CurlController(speed=10.0))
    assert abs(a.laps - b.laps) < 0.05


@pytest.mark.parametrize("start", [0.0, 0.005, 0.245, 0.502])
def test_no_link_turns_through_a_corner_next_to_its_joint(start):
    # MuJoCo reports one contact per capsule and convex piece (the deepest): a joint
    # resting by a corner hides the contact further along its link
    body = shapely.Polygon(square(4.0))
    g = grasp(square(4.0), PlanarChain([1.0] * 16), start=start)
    links = shapely.linestrings(np.stack([g.joints[:-1], g.joints[1:]], axis=1))
    assert shapely.length(shapely.intersection(links, body)).max() < 0.02
