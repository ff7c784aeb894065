"""Physical grasps: a torque-driven chain closing on a fixed object in MuJoCo."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import shapely

from .._typing import ArrayLike, FloatArray
from .._validation import check_positive_float
from ..errors import InputError
from ..manipulator import PlanarChain
from ..shapes import as_outline
from ..wrapping import Wrap
from ._decompose import convex_pieces
from ._model import _mujoco, build_model

__all__ = ["CurlController", "PhysicalGrasp", "grasp"]


#: Mass and inertia of a link not yet deployed, relative to its own.
STOWED_MASS = 1e-6
#: Time constants of the joint servos in time steps: braked joints are as stiff
#: as contacts, the driven joint softer, so a contact stops the driven joint (its
#: set point runs ahead: a stall) instead of being pushed through.
BRAKE_STEPS = 2
DRIVE_STEPS = 10


@dataclass(frozen=True)
class CurlController:
    """Closes the chain joint after joint: curl until something stops it, then hold.

    Joint ``k`` (from the base, the approach's joints excepted) is driven once
    joint ``k - 1`` has stopped; until then it is braked at its angle, so the
    rest of the chain turns as one straight bar about the driven joint,
    towards the object, until a contact stops it. The joints are stiff
    position servos (MuJoCo joint equality constraints whose set points the
    controller moves): the driven joint's set point turns at an angular speed
    that moves the chain's tip at ``speed`` link lengths per second; when a
    contact holds the joint back by ``stall_lag`` it has stopped, and it is
    braked where it stands (the hold).

    Parameters
    ----------
    speed : float, default=20.0
        Tip speed of the turning part, link lengths per second.
    stall_lag : float, default=0.01
        A driven joint this far (radians) behind its set point, and turning at
        less than a fifth of its speed, has stopped (so has one whose lag
        exceeds this plus what following a ramp costs the servo).
    max_turn : float, default=2*pi
        A joint that turns further than this (radians) without stopping touches
        nothing: the grasp ends incomplete.
    torque : float, default=0.0
        An optional squeeze (0: none, the joints stay braked where they
        stopped): once every joint has stopped, the brakes let go and every
        link is pressed towards the object with this moment (joint ``k`` curls
        with ``torque * (n_links - k)``; N m for links of unit length and mean
        mass 1 kg, the simulation's units), so the chain settles where the
        contacts balance the torques. Without friction to hold it the squeezed
        chain tends to slide round the object and unwind, so it is off by
        default.
    damping : float, default=2.0
        Joint damping (N m s) during the squeeze.
    rest_speed : float, default=1e-3
        The chain is at rest once every joint turns slower than this (radians
        per second) for ``rest_time``.
    rest_time : float, default=0.05
        Seconds.
    settle_time : float, default=10.0
        Seconds allowed for coming to rest during the squeeze.
    control_steps : int, default=5
        Simulation steps between two looks of the controller.
    """

    speed: float = 20.0
    stall_lag: float = 0.01
    max_turn: float = 2 * np.pi
    torque: float = 0.0
    damping: float = 2.0
    rest_speed: float = 1e-3
    rest_time: float = 0.05
    settle_time: float = 10.0
    control_steps: int = 5


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


class _Sim:
    """One grasp in normalised units (mean link length 1)."""

    def __init__(self, chain, outline, pieces, base, heading, q0, first, r, friction, ctrl, rec,
                 timestep, poly):  # fmt: skip
        self.mj = _mujoco()
        n = chain.n_links
        self.cm = build_model(
            chain, outline, base=base, heading=heading, thickness=2 * r, damping=0.0,
            friction=friction, colliding=np.arange(n) >= first, pieces=pieces,
            timestep=timestep,
        )  # fmt: skip
        self.m = self.cm.model
        self.d = self.mj.MjData(self.m)
        self.d.qpos[:] = q0
        self.tip_body = self.m.body(f"link{n - 1}").id
        self.bodies = np.array([self.m.body(f"link{i}").id for i in range(n)])
        self.mass0 = self.m.body_mass.copy()
        self.inertia0 = self.m.body_inertia.copy()
        self.link_of_geom = np.full(self.m.ngeom, -1)
        self.link_of_geom[self.cm.link_geoms] = np.arange(n)
        self.n, self.first, self.ctrl, self.r = n, first, ctrl, r
        self.chain, self.poly = chain, poly
        self.omega = ctrl.speed / chain.link_lengths
        self.rec = rec
        self.frames: list[FloatArray] = []
        for i in range(first + 1, n):
            self._solid(i, False)
        for i in range(n):  # everything braked at its start angle
            self._lock(i, float(q0[i]))
        self.mj.mj_forward(self.m, self.d)

    def _solid(self, i: int, on: bool) -> None:
        """Deploy link ``i`` (it collides, with its own mass) or keep it stowed.

        Links not yet deployed touch nothing and weigh next to nothing: the
        chain unrolls link after link.
        """
        g, b = self.cm.link_geoms[i], self.bodies[i]
        self.m.geom_contype[g] = self.m.geom_conaffinity[g] = 1 if on else 0
        f = 1.0 if on else STOWED_MASS
        self.m.body_mass[b] = self.mass0[b] * f
        self.m.body_inertia[b] = self.inertia0[b] * f

    def _lock(self, i: int, target: float, drive: bool = False) -> None:
        """Hold joint ``i`` at ``target``: a braked joint, or the driven one (softer)."""
        e = self.cm.lock_ids[i]
        self.m.eq_data[e, 0] = target
        dt = self.m.opt.timestep
        self.m.eq_solref[e] = (dt * (DRIVE_STEPS if drive else BRAKE_STEPS), 1.0)
        self.d.eq_active[e] = True

    def _clear(self, k: int) -> float | None:
        """Joint ``k``'s angle after the smallest clockwise turn that leaves link ``k`` free.

        Where no direction is quite free (a joint wedged in a groove), the
        roomiest one if the link sinks in by less than half its thickness;
        otherwise None.
        """
        p = self.d.xanchor[k, :2].copy()
        rot = self.d.xmat[self.bodies[k]]
        phi = float(np.arctan2(rot[3], rot[0]))
        ln, r = float(self.chain.link_lengths[k]), self.r
        j = self.joints()
        placed = [shapely.LineString(j[i : i + 2]) for i in range(self.first, k - 1)]
        others = shapely.MultiLineString(placed) if placed else None
        q_k = float(self.d.qpos[k])
        # the joint may already sit a little deep in a contact: the link must not go deeper
        pt = shapely.Point(p)
        need_obj = min(0.98 * r, shapely.distance(pt, self.poly)) - 1e-6
        need_self = 1.96 * r if others is None else min(1.96 * r, shapely.distance(pt, others))
        best, best_turn = -np.inf, None
        for turn in np.arange(0.0, 2 * np.pi - 0.1, 0.02):
            a = phi - turn
            seg = shapely.LineString([p, p + ln * np.array([np.cos(a), np.sin(a)])])
            room = shapely.distance(seg, self.poly) - need_obj
            if others is not None:
                room = min(room, shapely.distance(seg, others) - need_self + 1e-6)
            if room >= 0:
                return q_k - turn
            if room > best:
                best, best_turn = room, turn
        # wedged in: take the roomiest direction if the link is at most a little deep
        if best_turn is not None and best > -0.5 * r:
            return q_k - best_turn
        return None

    def _levers(self, k: int):
        """Depth and lever about joint ``k`` of each contact that can stop it."""
        d, lg = self.d, self.link_of_geom
        anchor = d.xanchor[k, :2]
        for i in range(d.ncon):
            c = d.contact[i]
            if c.dist >= 0 or max(lg[c.geom1], lg[c.geom2]) < k:
                continue
            rel, normal = c.pos[:2] - anchor, c.frame[:2]
            arm = abs(float(rel[0] * normal[1] - rel[1] * normal[0]))  # lever of the normal
            if arm > 0.1:  # contacts on the joint's own cap do not stop its turn
                yield -c.dist, arm

    def _blocked(self, k: int) -> bool:
        return any(True for _ in self._levers(k))

    def _back_off(self, k: int) -> float:
        """Turn that lifts links ``k..`` out of the contacts that stopped joint ``k``.

        Soft contacts let a stopped link sink in a little; braked there, it would
        block the next link's turn at the support's tangent.
        """
        back = max((depth / arm for depth, arm in self._levers(k)), default=0.0)
        return min(back, 0.05)

    def joints(self) -> FloatArray:
        xa = self.d.xanchor[: self.n, :2]
        b = self.tip_body
        last = self.d.xpos[b, :2] + self.chain.link_lengths[-1] * self.d.xmat[b, [0, 3]]
        return np.vstack([xa, last])

    def run(self, time_limit: float) -> tuple[str, int]:
        c, dt = self.ctrl, self.m.opt.timestep
        period = c.control_steps * dt
        need = max(1, int(np.ceil(c.rest_time / period)))
        steps, reason = 0, ""
        for k in range(self.first, self.n):
            if k > self.first:  # deploy link k, turned away from the object until it is free
                self._solid(k, True)
                q_free = self._clear(k)
                if q_free is None:
                    return (
                        f"no room to deploy link {k}: the chain is jammed (in a groove it "
                        "entered and cannot leave, or between the object and itself)"
                    ), steps
                self.d.qpos[k] = q_free
                self.d.qvel[:] = 0.0
                self._lock(k, q_free)
                self.mj.mj_forward(self.m, self.d)
            q_start, t_k = float(self.d.qpos[k]), 0.0
            target = q_start
            t_max = 2 * c.max_turn / self.omega[k] + 1.0
            while True:
                target += self.omega[k] * period
                self._lock(k, target, drive=True)
                self.mj.mj_step(self.m, self.d, nstep=c.control_steps)
                steps += c.control_steps
                t_k += period
                if self.rec and steps % (self.rec * c.control_steps) == 0:
                    self.frames.append(self.joints())
                if not np.all(np.isfinite(self.d.qpos)):
                    return f"the simulation diverged at joint {k}", steps
                if self.d.time > time_limit:
                    return f"time limit {time_limit:g} s reached at joint {k}", steps
                if self.d.qpos[k] - q_start > c.max_turn or t_k > t_max:
                    return (
                        f"joint {k} turned {self.d.qpos[k] - q_start:.3g} rad without touching "
                        "anything (the chain cannot reach the object)"
                    ), steps
                lag = target - self.d.qpos[k]
                if lag > c.stall_lag and self._blocked(k):
                    break
            self._lock(k, float(self.d.qpos[k]) - self._back_off(k))
        # The squeeze: brakes off, every link pressed towards the object by the
        # same moment (joint k turns the n - k links beyond it), damped, until
        # the chain rests where the contacts hold it.
        for k in range(self.first, self.n) if c.torque > 0 else ():  # pragma: no cover
            self.d.eq_active[self.cm.lock_ids[k]] = False
            self.m.dof_damping[k] = c.damping
            self.d.ctrl[k] = c.torque * (self.n - k)
        t_settle, still = 0.0, 0
        while still < need:
            self.mj.mj_step(self.m, self.d, nstep=c.control_steps)
            steps += c.control_steps
            t_settle += period
            if self.rec and steps % (self.rec * c.control_steps) == 0:
                self.frames.append(self.joints())
            if not np.all(np.isfinite(self.d.qpos)):
                return "the simulation diverged while settling", steps
            still = still + 1 if np.max(np.abs(self.d.qvel)) < c.rest_speed else 0
            if t_settle > c.settle_time or self.d.time > time_limit:
                return (
                    f"the chain did not come to rest within {c.settle_time:g} s "
                    f"(joint speeds up to {np.max(np.abs(self.d.qvel)):.3g} rad/s)"
                ), steps
        return reason, steps

    def contact_points(self) -> FloatArray:
        nc = self.d.ncon
        if nc == 0:
            return np.zeros((0, 2))
        return np.array([self.d.contact[i].pos[:2] for i in range(nc)])


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
        Bad outline (see :func:`tentaclass.shapes.as_outline`), start outside
        [0, 1), negative offset, an approach that passes through the object.

    Notes
    -----
    The simulation runs in units of the mean link length (masses as given,
    inertias scaled to match), with the chain in the plane and no gravity.
    The base sits ``offset`` outside the object at the start point, facing it
    (without an offset, on the object with ``heading`` the chord arriving at
    the start point from one link behind, as :func:`tentaclass.wrap` does);
    the chain starts straight along the object's surface (turned away from
    it just enough to clear it) and :class:`CurlController` closes it joint
    after joint. Links are capsules of the given thickness, so their axes rest
    ``thickness / 2`` outside the object: compare with
    ``wrap(shapely.buffer(outline, thickness / 2), ...)``. A joint counts as
    in contact (``contact``, ``lap == 0``) within ``thickness / 2`` plus 10 %
    of it of the object; ``lap = k`` when it rests on lap ``k - 1`` of the chain.

    Examples
    --------
    >>> from tentaclass import PlanarChain, grasp_state
    >>> from tentaclass.shapes import square
    >>> g = grasp(square(4), PlanarChain([1.0] * 16))
    >>> g.complete, grasp_state(g.angles).state.item()
    (True, 'once')
    >>> g.angles.shape, round(g.laps, 1)
    ((16,), 1.0)
    """
    if not isinstance(chain, PlanarChain):
        raise InputError(f"chain must be a PlanarChain, got {type(chain).__name__}")
    p = as_outline(outline)
    start = float(start)
    if not 0 <= start < 1:
        raise InputError(f"start must be in [0, 1), got {start!r}")
    offset = check_positive_float(offset, "offset", allow_zero=True)
    if direction not in ("ccw", "cw"):
        raise InputError(f"direction must be one of 'ccw', 'cw', got {direction!r}")
    ctrl = CurlController() if controller is None else controller
    if not isinstance(ctrl, CurlController):
        raise InputError(f"controller must be a CurlController, got {type(ctrl).__name__}")
    friction = check_positive_float(friction, "friction", allow_zero=True)
    simplify = check_positive_float(simplify, "simplify", allow_zero=True)
    timestep = check_positive_float(timestep, "timestep")
    ln = chain.link_lengths
    s = 1.0 / float(ln.mean())
    thickness = 0.1 / s if thickness is None else check_positive_float(thickness, "thickness")
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
    pieces = convex_pieces(o)
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
    q0 = np.zeros(n)
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

    if first >= n:
        return straight(f"all {n} links are needed for the approach: the chain cannot reach "
                        "the object")  # fmt: skip
    a = _clear_turn(poly, joint, tangent, float(ln[first] * s), r)
    if a is None:
        return straight("no start pose of the first link clears the object from this start point")
    q0[first] = _wrap_angle(a - heading)
    sim = _Sim(norm_chain, o, pieces, base, heading, q0, first, r, friction, ctrl, frames, timestep,
               poly)  # fmt: skip
    if time_limit is None:
        time_limit = float(2 * np.sum(ctrl.max_turn / sim.omega[first:]) + ctrl.settle_time + 1)
    else:
        time_limit = check_positive_float(time_limit, "time_limit")
    if frames:
        sim.frames.append(sim.joints())
    reason, steps = sim.run(time_limit)
    q = np.array(sim.d.qpos, dtype=float)
    joints = sim.joints()
    fr = np.array([*sim.frames, joints]) if frames else np.zeros((0,))
    return finish(q, joints, reason, float(sim.d.time), steps, sim.contact_points(), fr)
