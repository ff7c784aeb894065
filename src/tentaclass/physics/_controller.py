"""The controller of a physical grasp and the simulation loop that runs it (MuJoCo)."""

from __future__ import annotations

from collections import deque
from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np
import shapely

from .._typing import FloatArray
from .._validation import check_positive_float, check_positive_int
from ..manipulator import PlanarChain
from ._model import _mujoco, build_model
from ._sweep import LEVER, SLACK, free_turn, room_about

__all__ = ["CurlController"]


#: Mass and inertia of a link not yet deployed, relative to its own.
STOWED_MASS = 1e-6
#: Time constants of the joint servos in time steps: braked joints are as stiff
#: as contacts, the driven joint softer, so a contact stops the driven joint (its
#: set point runs ahead: a stall) instead of being pushed through.
BRAKE_STEPS = 2
DRIVE_STEPS = 10
#: Impedance (MuJoCo ``solimp``) of the joint servos: a braked joint holds as
#: hard as MuJoCo allows; the driven joint yields (its constraint force, what
#: the servo's torque is, stays a fraction of a contact's for the same error),
#: so a contact stops it without being pushed in and without the braked joints
#: behind it giving way.
BRAKE_IMPEDANCE = (0.9999, 0.9999, 0.001, 0.5, 2.0)
DRIVE_IMPEDANCE = (0.5, 0.5, 0.001, 0.5, 2.0)
#: Largest turn back that lifts a link out of the object (radians).
_MAX_UNSINK = 0.6


@dataclass(frozen=True)
class CurlController:
    """Unrolls the chain link after link: each link curls until a contact stops it, then holds.

    Links not yet deployed touch nothing and weigh next to nothing. Link ``k``
    (from the base, the approach's links excepted) is deployed once joint
    ``k - 1`` has stopped: turned away from the object just enough to be free,
    then its joint is driven to curl it towards the object until a contact
    (with the object or the chain) holds it back; the joint is then braked
    where it stands (the hold), after backing off what the soft contact let
    the link sink in. The joints are position servos (MuJoCo joint equality
    constraints whose set points the controller moves): the driven joint's
    set point turns so that the link's tip moves at ``speed`` link lengths
    per second. Braked joints hold as hard as MuJoCo allows; the driven one
    yields to contacts (a low impedance bounds its torque), so it stops at a
    contact without pushing the link in or bending the braked joints behind
    it.

    Parameters
    ----------
    speed : float, default=5.0
        Tip speed of the curling link, link lengths per second.
    stall_lag : float, default=0.01
        A driven joint this far (radians) behind its set point has stopped
        when a contact pushes against it (with a lever about the joint) or
        when it turns at less than 5 % of its commanded speed (held by a
        contact next to the joint).
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
        The chain is at rest once no joint angle has ranged over more than
        ``rest_speed * rest_time`` (radians) during the last ``rest_time``:
        it turns slower than this on average (radians per second). The soft
        contacts chatter about a fixed pose at up to a few hundredths of a
        radian per second, a fraction of a milliradian; that is rest.
    rest_time : float, default=0.2
        Seconds.
    settle_time : float, default=10.0
        Seconds allowed for coming to rest during the squeeze.
    control_steps : int, default=5
        Simulation steps between two looks of the controller.

    Raises
    ------
    InputError
        A parameter that is not a finite number > 0 (``torque``, ``damping``
        and ``rest_speed`` may be 0), or ``control_steps`` below 1.

    Examples
    --------
    >>> CurlController(speed=10.0).speed
    10.0
    >>> CurlController(speed=0.0)
    Traceback (most recent call last):
    ...
    tentaclass.errors.InputError: speed must be a finite number > 0, got 0.0
    """

    speed: float = 5.0
    stall_lag: float = 0.01
    max_turn: float = 2 * np.pi
    torque: float = 0.0
    damping: float = 2.0
    rest_speed: float = 1e-3
    rest_time: float = 0.2
    settle_time: float = 10.0
    control_steps: int = 5

    def __post_init__(self) -> None:
        # every field bounds a loop of the simulation: a zero speed, a NaN or no
        # steps between looks would never reach a stop, a rest or a time limit
        for name in ("speed", "stall_lag", "max_turn", "rest_time", "settle_time"):
            check_positive_float(getattr(self, name), name)
        for name in ("torque", "damping", "rest_speed"):
            check_positive_float(getattr(self, name), name, allow_zero=True)
        check_positive_int(self.control_steps, "control_steps")


class _Sim:
    """One grasp in normalised units (mean link length 1)."""

    def __init__(self, chain: PlanarChain, outline: FloatArray, pieces: list[FloatArray],
                 base: FloatArray, heading: float, q0: FloatArray, first: int, r: float,
                 friction: float, ctrl: CurlController, rec: int, timestep: float,
                 poly: shapely.Polygon) -> None:  # fmt: skip
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
        self.m.eq_solimp[e] = DRIVE_IMPEDANCE if drive else BRAKE_IMPEDANCE
        self.d.eq_active[e] = True

    def _clear(self, k: int) -> float | None:
        """Joint ``k``'s angle after the smallest clockwise turn that leaves link ``k`` free.

        The quasi-static grasp's rule (:func:`free_turn`): where no direction
        is quite free (a joint wedged in a groove), the roomiest one if the
        link sinks in by less than half its thickness; otherwise None.
        """
        j = self.joints()
        rot = self.d.xmat[self.bodies[k]]
        phi = float(np.arctan2(rot[3], rot[0]))
        placed = np.stack([j[self.first : k - 1], j[self.first + 1 : k]], axis=1)
        f = room_about(j[k], float(self.chain.link_lengths[k]), self.poly, placed, self.r)
        a = free_turn(f, phi, self.r)
        return None if a is None else float(self.d.qpos[k]) + (a - phi)

    def _levers(self, k: int) -> Iterator[tuple[float, float]]:
        """Depth and lever about joint ``k`` of each contact that can stop it."""
        d, lg = self.d, self.link_of_geom
        anchor = d.xanchor[k, :2]
        for i in range(d.ncon):
            c = d.contact[i]
            if c.dist >= 0 or max(lg[c.geom1], lg[c.geom2]) < k:
                continue
            rel, normal = c.pos[:2] - anchor, c.frame[:2]
            arm = abs(float(rel[0] * normal[1] - rel[1] * normal[0]))  # lever of the normal
            if arm > LEVER:  # contacts on the joint's own cap do not stop its turn
                yield -c.dist, arm

    def _blocked(self, k: int) -> bool:
        return any(True for _ in self._levers(k))

    def _sunk(self, k: int, turn: float = 0.0) -> float:
        """How far link ``k`` (turned back by ``turn``) sinks into the object past its joint's cap.

        MuJoCo gives one contact point per capsule and convex piece, at the
        deepest point: a joint resting next to a corner of the object hides
        a contact further along its link, which then turns through the
        object. The geometry tells: the link's axis beyond ``LEVER`` of its
        length must keep its clearance (``SLACK`` of the radius, or the
        joint's own if that is less) from the object.
        """
        j = self.joints()
        p, tip = j[k], j[k + 1]
        need = min(SLACK * self.r, float(shapely.distance(shapely.Point(p), self.poly)))
        a = float(np.arctan2(*(tip - p)[::-1])) - turn
        u = np.array([np.cos(a), np.sin(a)])
        ln = float(self.chain.link_lengths[k])
        seg = shapely.LineString([p + LEVER * ln * u, p + ln * u])
        return float(need - shapely.distance(seg, self.poly))

    def _unsink(self, k: int) -> float:
        """The smallest turn back that lifts link ``k`` out of the object.

        At most ``_MAX_UNSINK``: more than the driven joint turns between two
        looks of the controller.
        """
        for turn in np.arange(0.0, _MAX_UNSINK, 0.002):
            if self._sunk(k, float(turn)) <= 0:
                return float(turn)
        return _MAX_UNSINK

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

    def _look(self, steps: int) -> int:
        """Simulate until the controller's next look; the step count then.

        Records the joints when a frame is due.
        """
        nstep = self.ctrl.control_steps
        self.mj.mj_step(self.m, self.d, nstep=nstep)
        steps += nstep
        if self.rec and steps % (self.rec * nstep) == 0:
            self.frames.append(self.joints())
        return steps

    def run(self, time_limit: float) -> tuple[str, int]:
        c, dt = self.ctrl, self.m.opt.timestep
        period = c.control_steps * dt
        # looks in rest_time; a chain can be seen at rest only within settle_time
        need = max(1, int(np.ceil(min(c.rest_time, c.settle_time + period) / period)))
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
            q_last = q_start
            target = q_start
            t_max = 2 * c.max_turn / self.omega[k] + 1.0
            while True:
                target += self.omega[k] * period
                self._lock(k, target, drive=True)
                steps = self._look(steps)
                t_k += period
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
                # held back by something near the joint: it hardly turns any more
                turned, q_last = float(self.d.qpos[k]) - q_last, float(self.d.qpos[k])
                slow = turned < 0.05 * self.omega[k] * period
                if lag > c.stall_lag and t_k > 3 * period and slow:
                    break
                if self._sunk(k) > 0.5 * self.r:  # a contact MuJoCo did not report
                    break
            back = self._back_off(k)
            if self._sunk(k) > 0.5 * self.r:  # stopped, but deep in the object: lift it out
                back = max(back, self._unsink(k))
            self._lock(k, float(self.d.qpos[k]) - back)
        # The squeeze: brakes off, every link pressed towards the object by the
        # same moment (joint k turns the n - k links beyond it), damped, until
        # the chain rests where the contacts hold it.
        for k in range(self.first, self.n) if c.torque > 0 else ():  # pragma: no cover
            self.d.eq_active[self.cm.lock_ids[k]] = False
            self.m.dof_damping[k] = c.damping
            self.d.ctrl[k] = c.torque * (self.n - k)
        t_settle = 0.0
        window: deque[FloatArray] = deque(maxlen=need + 1)  # the angles over the last rest_time
        while True:
            steps = self._look(steps)
            t_settle += period
            if not np.all(np.isfinite(self.d.qpos)):
                return "the simulation diverged while settling", steps
            window.append(self.d.qpos.copy())
            moved = float(np.ptp(np.array(window), axis=0).max())
            if len(window) == window.maxlen and moved <= c.rest_speed * c.rest_time:
                break
            if t_settle > c.settle_time or self.d.time > time_limit:
                return (
                    f"the chain did not come to rest within {c.settle_time:g} s (a joint "
                    f"still turned {moved:.3g} rad in {c.rest_time:g} s)"
                ), steps
        return reason, steps

    def contact_points(self) -> FloatArray:
        nc = self.d.ncon
        if nc == 0:
            return np.zeros((0, 2))
        return np.array([self.d.contact[i].pos[:2] for i in range(nc)])
