"""Physical grasps: a torque-driven chain closing on a fixed object in MuJoCo."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import shapely

from .._typing import ArrayLike, FloatArray
from .._validation import (
    check_finite_float,
    check_grasp_masses,
    check_links_fit,
    check_positive_float,
    check_positive_int,
    check_thickness_builds,
    check_thickness_fits,
)
from ..errors import InputError
from ..manipulator import PlanarChain
from ..shapes import as_outline
from ..wrapping import Wrap
from ..wrapping._surface import outline_diameter
from ._controller import CurlController, _Sim
from ._decompose import convex_pieces
from ._model import check_chain_depth

__all__ = ["MAX_STEPS", "PhysicalGrasp", "grasp"]

#: Most simulation steps one grasp may take: at about 25 us a step, over
#: forty minutes. The default step (4 ms) takes about 300,000 steps for the
#: longest chain MuJoCo builds.
MAX_STEPS = 100_000_000


@dataclass(frozen=True)
class PhysicalGrasp(Wrap):
    """A simulated grasp; a :class:`tentaclass.Wrap` with what the simulation adds.

    The :class:`~tentaclass.Wrap` fields mean the same as for a geometric wrap
    (``complete`` False when the grasp did not finish: see ``reason``), so every
    classifier and :func:`tentaclass.grasp_state` take it unchanged.

    Attributes
    ----------
    reason : str
        Why the grasp is incomplete ("" when complete).
    sim_time : float
        Simulated seconds until rest (or until it stopped).
    steps : int
        Simulation steps taken.
    contact_points : ndarray of shape (n_contacts, 2)
        Where the chain touches the object or itself at the end (MuJoCo's
        contact points).
    frames : ndarray of shape (n_frames, n_links + 1, 2)
        Joint positions during the closing (for animations); empty unless asked.
    thickness : float
        Diameter of the links.
    """

    reason: str
    sim_time: float
    steps: int
    contact_points: FloatArray
    frames: FloatArray
    thickness: float


def _wrap_angle(a: float) -> float:
    return float(np.pi - np.mod(np.pi - a, 2 * np.pi))


def _ring_point(ring: shapely.LinearRing, s: float) -> FloatArray:
    return np.asarray(shapely.get_coordinates(ring.interpolate(s % ring.length))[0])


def _tangent(ring: shapely.LinearRing, s: float, ds: float) -> float:
    a, b = _ring_point(ring, s - ds), _ring_point(ring, s + ds)
    return float(np.arctan2(b[1] - a[1], b[0] - a[0]))


def _chord_behind(ring: shapely.LinearRing, s: float, ln: float) -> FloatArray:
    """First point behind arc position ``s`` at straight distance ``ln`` from it."""
    p = _ring_point(ring, s)
    steps = np.linspace(0, ring.length, 2048)[1:]
    pts = shapely.get_coordinates(shapely.line_interpolate_point(ring, (s - steps) % ring.length))
    d = np.hypot(*(pts - p).T)
    k = int(np.argmax(d >= ln)) if np.any(d >= ln) else len(d) - 1
    lo, hi = (steps[k - 1] if k else 0.0), steps[k]
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        if np.hypot(*(_ring_point(ring, s - mid) - p)) >= ln:
            hi = mid
        else:
            lo = mid
    return _ring_point(ring, s - hi)


def _clear_turn(obj, joint, theta, length, r, step=0.02):
    """Smallest clockwise turn from ``theta`` that lets a straight bar clear the object."""
    for k in range(int(np.pi / step) + 1):
        a = theta - k * step
        tip = joint + length * np.array([np.cos(a), np.sin(a)])
        seg = shapely.LineString([joint, tip])
        if shapely.distance(seg, obj) >= r * 0.98 - 1e-9:
            return a
    return None


def _laps_and_gap(q, heading, ref, joints, start):
    phi = heading + np.cumsum(q)
    laps = float((phi[-1] - ref) / (2 * np.pi)) if len(q) else 0.0
    if laps < 1:
        return laps, float("nan")
    k = int(np.argmax(phi - ref >= 2 * np.pi))  # link k+1 closes the lap
    cand = joints[[k, k + 1]]
    return laps, float(np.hypot(*(cand - start).T).min())


def _lap_flags(joints, obj, r, tol, first):
    """Contact flags and lap index of each joint from distances."""
    n1 = len(joints)
    pts = shapely.points(joints)
    d_obj = shapely.distance(pts, obj)
    lap = np.full(n1, -1, np.int64)
    lap[(d_obj <= r + tol) & (np.arange(n1) >= first)] = 0
    segs = shapely.linestrings(np.stack([joints[:-1], joints[1:]], axis=1))
    for i in range(first + 2, n1):
        if lap[i] == 0:
            continue
        prev = segs[first : max(first, i - 2)]
        if len(prev) == 0:
            continue
        dist = shapely.distance(prev, pts[i])
        j = int(np.argmin(dist))
        if dist[j] <= 2 * r + tol:
            below = max(lap[first + j], lap[first + j + 1])
            if below >= 0:
                lap[i] = below + 1
    return lap == 0, lap


def grasp(
    outline: ArrayLike,
    chain: PlanarChain,
    *,
    start: float = 0.0,
    offset: float = 0.0,
    direction: str = "ccw",
    thickness: float | None = None,
    friction: float = 0.0,
    controller: CurlController | None = None,
    time_limit: float | None = None,
    simplify: float = 0.05,
    frames: int = 0,
    timestep: float = 0.004,
) -> PhysicalGrasp:
    """Close a chain on an object in MuJoCo and read its joint angles at rest.

    Parameters
    ----------
    outline : array_like of shape (n_points, 2)
        Closed simple outline of the fixed object (see :mod:`tentaclass.shapes`).
    chain : PlanarChain
        The chain (its lengths, masses, centres of mass and inertias).
    start : float, default=0.0
        Start point as a fraction of the perimeter in [0, 1), counter-clockwise
        from the outline's first point, as in :func:`tentaclass.wrap`.
    offset : float, default=0.0
        Distance of the base from the object along the outward normal at the
        start point; the first ``floor(offset / l)`` links are the approach
        (they stay straight and touch nothing).
    direction : {"ccw", "cw"}, default="ccw"
    thickness : float, optional
        Diameter of the capsule around each link (default a tenth of the mean
        link length).
    friction : float, default=0.0
        Sliding friction coefficient.
    controller : CurlController, optional
        How the chain closes (default :class:`CurlController()`).
    time_limit : float, optional
        Simulated seconds before giving up (default: twice what the controller
        needs to turn every joint by ``max_turn``).
    simplify : float, default=0.05
        Outline detail below this fraction of a link is dropped before the
        object is built (Douglas-Peucker): pixel staircases cost many convex
        pieces and no link can feel them.
    frames : int, default=0
        Record the joint positions every ``frames`` controller looks (0: none).
    timestep : float, default=0.004
        Simulation step, seconds.

    Returns
    -------
    PhysicalGrasp
        A :class:`tentaclass.Wrap` (angles, joints, contact, lap, laps,
        offset_links, heading, complete, closure_gap, start_point,
        link_length, direction) plus ``reason``, ``sim_time``, ``steps``,
        ``contact_points``, ``frames`` and ``thickness``.

    Raises
    ------
    InputError
        Bad outline (see :func:`tentaclass.shapes.as_outline`), a link longer
        or a thickness larger than the object's diameter (as
        :func:`tentaclass.wrap` refuses them), more
        links than MuJoCo builds (:data:`tentaclass.physics.MAX_LINKS`), start
        outside [0, 1), negative offset, an approach that passes through the object,
        a thickness below ``1e-12`` of the object's diameter, link masses outside
        ``[1e-12, 1e12]`` kg or inertias above ``1e12`` (in units of the mean link
        length, where the controller cannot move the chain), or a simulation of
        more than ``MAX_STEPS`` (100,000,000) steps.

    Notes
    -----
    The simulation runs in units of the mean link length (masses as given,
    inertias scaled to match), with the chain in the plane and no gravity.
    The base sits ``offset`` outside the object at the start point, facing it
    (without an offset, on the object with ``heading`` the chord arriving at
    the start point from one link behind, as :func:`tentaclass.wrap` does);
    the first link starts along the object's surface (turned away from it
    just enough to clear it) and :class:`CurlController` unrolls the chain
    link after link. Links are capsules of the given thickness, so their axes rest
    ``thickness / 2`` outside the object: compare with
    ``wrap(shapely.buffer(outline, thickness / 2), ...)``. A joint counts as
    in contact (``contact``, ``lap == 0``) within ``thickness / 2`` plus 10 %
    of it of the object; ``lap = k`` when it rests on lap ``k - 1`` of the chain.

    Examples
    --------
    >>> from tentaclass import PlanarChain, grasp_state
    >>> from tentaclass.shapes import square
    >>> g = grasp(square(4), PlanarChain([1.0] * 16), start=0.1)
    >>> g.complete, grasp_state(g.angles).state.item()
    (True, 'partial')
    >>> g.angles.shape, round(g.laps, 2)  # rigid links lose length at every corner
    ((16,), 0.75)
    """
    ctrl = CurlController() if controller is None else controller
    if not isinstance(ctrl, CurlController):
        raise InputError(f"controller must be a CurlController, got {type(ctrl).__name__}")
    friction = check_positive_float(friction, "friction", allow_zero=True)
    timestep = check_positive_float(timestep, "timestep")
    frames = check_positive_int(frames, "frames", minimum=0)
    if isinstance(chain, PlanarChain):
        check_chain_depth(chain.n_links)  # before the setup, whose work grows with the links
    su = _prepare(outline, chain, start, offset, direction, thickness, simplify)
    check_grasp_masses(su.norm_chain.masses, su.norm_chain.inertia)
    if su.early is not None:
        return su.early
    pieces = convex_pieces(su.outline)
    q0 = np.zeros(su.n)
    q0[su.first] = su.q_first
    sim = _Sim(su.norm_chain, su.outline, pieces, su.base, su.heading, q0, su.first, su.r, friction,
               ctrl, frames, timestep, su.poly)  # fmt: skip
    # every joint stops within 2 * max_turn / omega of its start, the squeeze within settle_time
    needed = float(2 * np.sum(ctrl.max_turn / sim.omega[su.first :]) + ctrl.settle_time + 1)
    if time_limit is None:
        time_limit = needed
    else:
        time_limit = check_positive_float(time_limit, "time_limit")
    steps_needed = max(min(time_limit, needed) / timestep, ctrl.control_steps)
    if steps_needed > MAX_STEPS:
        raise InputError(
            f"the grasp would take up to {steps_needed:.3g} simulation steps "
            f"({min(time_limit, needed):.4g} s in steps of {timestep:g} s, "
            f"{ctrl.control_steps:,} steps per look of the controller), more than the "
            f"{MAX_STEPS:,} allowed: use a larger timestep, a faster controller or a "
            "shorter time_limit"
        )
    if frames:
        sim.frames.append(sim.joints())
    reason, steps = sim.run(time_limit)
    q = np.array(sim.d.qpos, dtype=float)
    joints = sim.joints()
    fr = np.array([*sim.frames, joints]) if frames else np.zeros((0,))
    return su.finish(q, joints, reason, float(sim.d.time), steps, sim.contact_points(), fr)


@dataclass
class _Setup:
    """A grasp's start in normalised units (mean link length 1), shared by both methods.

    ``early`` is the finished (incomplete) grasp when the chain cannot start.
    """

    n: int
    outline: FloatArray
    poly: shapely.Polygon
    r: float
    base: FloatArray
    heading: float
    first: int
    joint: FloatArray
    tangent: float
    q_first: float
    norm_chain: PlanarChain
    finish: Callable[..., PhysicalGrasp]
    early: PhysicalGrasp | None


def _prepare(
    outline: ArrayLike,
    chain: PlanarChain,
    start: float,
    offset: float,
    direction: str,
    thickness: float | None,
    simplify: float,
) -> _Setup:
    """Validate a grasp's arguments, place the base and the first link (see :func:`grasp`)."""
    if not isinstance(chain, PlanarChain):
        raise InputError(f"chain must be a PlanarChain, got {type(chain).__name__}")
    p = as_outline(outline)
    start = check_finite_float(start, "start")
    if not 0 <= start < 1:
        raise InputError(f"start must be in [0, 1), got {start!r}")
    offset = check_positive_float(offset, "offset", allow_zero=True)
    if direction not in ("ccw", "cw"):
        raise InputError(f"direction must be one of 'ccw', 'cw', got {direction!r}")
    simplify = check_positive_float(simplify, "simplify", allow_zero=True)
    ln = chain.link_lengths
    diameter = outline_diameter(p)
    check_links_fit(ln, diameter)  # (the object is at most 1e12 links across)
    s = 1.0 / float(ln.mean())  # the simulation runs in units of the mean link length
    thickness = 0.1 / s if thickness is None else check_positive_float(thickness, "thickness")
    check_thickness_fits(thickness, diameter)
    check_thickness_builds(thickness, diameter)
    r = 0.5 * thickness * s
    mirror = direction == "cw"

    ring0 = shapely.LinearRing(p)
    p0 = _ring_point(ring0, start * ring0.length)  # the start point, original units
    o = p * s
    p0n = p0 * s
    if mirror:
        o = o[::-1] * [-1.0, 1.0]
        p0n = p0n * [-1.0, 1.0]
    poly = shapely.Polygon(o)
    if simplify > 0:
        simple = shapely.simplify(poly, simplify)
        if simple.is_valid and not simple.is_empty and simple.geom_type == "Polygon":
            poly = shapely.Polygon(shapely.get_coordinates(simple.exterior)[:-1])
    o = as_outline(shapely.get_coordinates(poly.exterior)[:-1])
    poly = shapely.Polygon(o)
    shapely.prepare(poly)
    support = shapely.buffer(poly, r, quad_segs=16).exterior if r > 0 else poly.exterior
    support = shapely.LinearRing(shapely.get_coordinates(support)[:-1])
    if not shapely.Polygon(support).exterior.is_ccw:
        support = shapely.LinearRing(shapely.get_coordinates(support)[::-1])
    s0 = float(support.project(shapely.Point(p0n)))
    pb = _ring_point(support, s0)
    tangent = _tangent(support, s0, 1e-3)
    norm_chain = PlanarChain(ln * s, masses=chain.masses, com=chain.com,
                             inertia=chain.inertia * s * s, gravity=chain.gravity)  # fmt: skip
    n = chain.n_links
    if offset > 0:
        n_out = np.array([np.sin(tangent), -np.cos(tangent)])  # right of a ccw walk
        base = pb + offset * s * n_out
        heading = float(np.arctan2(-n_out[1], -n_out[0]))
        approach = shapely.LineString([base, pb])
        inside = shapely.intersection(approach, poly)
        if shapely.length(inside) > 1e-6:
            raise InputError(
                f"offset {offset:g}: the straight approach to the start point passes through "
                "the object; use a smaller offset or another start point"
            )
        first = int(np.floor(offset * s / 1.0 + 1e-9))
        first = min(first, n)
        reach = np.r_[0.0, np.cumsum(ln * s)]
        joint = base + reach[first] * np.array([np.cos(heading), np.sin(heading)])
        ref = heading - np.pi / 2
        offset_links = int(np.ceil(offset * s - 1e-9))
    else:
        base = pb
        behind = _chord_behind(support, s0, float(ln[-1] * s))
        heading = float(np.arctan2(*(pb - behind)[::-1]))
        first, joint, ref, offset_links = 0, base, heading, 0
    link_length = float(ln.mean())
    sign = -1.0 if mirror else 1.0

    def finish(q, joints, reason, sim_time, steps, cpts, frames_):
        contact, lap = _lap_flags(joints, poly, r, 0.1 * r + 1e-6, first)
        laps, gap = _laps_and_gap(q, heading, ref, joints, pb)
        back = np.array([sign, 1.0]) / s
        head = _wrap_angle(np.pi - heading if mirror else heading)
        return PhysicalGrasp(
            angles=sign * q, joints=joints * back, contact=contact, lap=lap, laps=laps,
            offset_links=offset_links, heading=head, complete=not reason,
            closure_gap=gap / s, start_point=p0, link_length=link_length,
            direction=direction, reason=reason, sim_time=sim_time, steps=steps,
            contact_points=cpts * back if len(cpts) else np.zeros((0, 2)),
            frames=frames_ * back if len(frames_) else np.zeros((0, n + 1, 2)),
            thickness=thickness,
        )  # fmt: skip

    def straight(reason: str) -> PhysicalGrasp:  # a grasp that never started
        along = np.r_[0.0, np.cumsum(ln * s)][:, None] * [np.cos(heading), np.sin(heading)]
        return finish(np.zeros(n), base + along, reason, 0.0, 0, np.zeros((0, 2)), np.zeros(0))

    early: PhysicalGrasp | None = None
    if first >= n:
        early = straight(f"all {n} links are needed for the approach: the chain cannot reach "
                         "the object")  # fmt: skip
        return _Setup(n, o, poly, r, base, heading, first, joint, tangent, 0.0, norm_chain,
                      finish, early)  # fmt: skip
    a = _clear_turn(poly, joint, tangent, float(ln[first] * s), r)
    if a is None:
        early = straight("no start pose of the first link clears the object from this start point")
        a = heading
    return _Setup(n, o, poly, r, base, heading, first, joint, tangent, _wrap_angle(a - heading),
                  norm_chain, finish, early)  # fmt: skip
