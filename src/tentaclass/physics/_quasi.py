"""The quasi-static limit of a physical grasp: each link swings until it touches (no MuJoCo)."""

from __future__ import annotations

import numpy as np
import shapely

from .._typing import ArrayLike
from ..manipulator import PlanarChain
from ._grasp import PhysicalGrasp, _prepare

__all__ = ["quasi_static_grasp"]

#: Coarse angular step of the swing search (radians); contacts are then refined by bisection.
_STEP = 0.02
#: Bisection steps refining a contact angle (0.02 / 2**12: about 5e-6 rad).
_REFINE = 12
#: Contacts nearer the joint than this (link lengths) do not stop its turn, as in the controller.
_LEVER = 0.1
#: Sweep steps evaluated at once.
_CHUNK = 24
#: Clearances as fractions of the ideal ones, as the controller's free test uses.
_SLACK = 0.98


def _room(pivot, angles, length, poly, others, need_obj, need_self):
    """Clearance of the link from ``pivot`` at each angle (>= 0: free), vectorised."""
    u = np.stack([np.cos(angles), np.sin(angles)], axis=1)
    segs = shapely.linestrings(np.stack([pivot + _LEVER * u, pivot + length * u], axis=1))
    room = np.full(len(angles), np.inf)
    if poly is not None:
        room = shapely.distance(segs, poly) - need_obj
    if others is not None:
        room = np.minimum(room, shapely.distance(segs, others) - need_self)
    return room


def _edge(f, lo, hi):
    """Bisect between a free angle ``lo`` and a blocked angle ``hi``; the last free one."""
    for _ in range(_REFINE):
        mid = 0.5 * (lo + hi)
        if f(np.array([mid]))[0] >= 0:
            lo = mid
        else:
            hi = mid
    return lo


def _first(f, phi, sign, want):
    """The first sweep step from ``phi`` (turning ``sign``) where ``f >= 0`` is ``want``.

    Returns its index (None when no step is), the sweep's angles and the rooms seen.
    """
    turns = np.arange(0.0, 2 * np.pi, _STEP)
    rooms = []
    for lo in range(0, len(turns), _CHUNK):
        room = f(phi + sign * turns[lo : lo + _CHUNK])
        rooms.append(room)
        hit = np.flatnonzero((room >= 0) == want)
        if hit.size:
            return lo + int(hit[0]), phi + sign * turns, np.concatenate(rooms)
    return None, phi + sign * turns, np.concatenate(rooms)


def _swing(pivot, phi, length, poly, segments, r):
    """Final direction of a link deployed at ``pivot`` pointing along ``phi``.

    As :class:`CurlController` deploys it: turned clockwise (away from the
    object) just enough to be free, then curled counter-clockwise until it
    touches the object ``poly`` or an earlier link (``segments``, (m, 2, 2)).
    Only what the link can reach is looked at. Returns (angle, reason);
    reason is "" on success.
    """
    reach = length + 2 * r + 1e-3
    x, y = pivot
    local = shapely.clip_by_rect(poly, x - reach, y - reach, x + reach, y + reach)
    local = None if local.is_empty else local
    others = None
    if len(segments):
        a, b = segments[:, 0], segments[:, 1]
        ab = b - a
        t = np.clip(np.sum((pivot - a) * ab, axis=1) / np.maximum(np.sum(ab * ab, axis=1), 1e-12),
                    0.0, 1.0)  # fmt: skip
        near = np.hypot(*(a + t[:, None] * ab - pivot).T) <= reach
        if near.any():
            others = shapely.multilinestrings(list(segments[near]))
    pt = shapely.Point(pivot)
    need_obj = 0.0 if local is None else min(_SLACK * r, float(shapely.distance(pt, local))) - 1e-6
    need_self = 0.0
    if others is not None:
        need_self = min(2 * _SLACK * r, float(shapely.distance(pt, others))) - 1e-6

    def f(angles):
        return _room(pivot, angles, length, local, others, need_obj, need_self)

    if f(np.array([phi]))[0] >= 0:  # free: curl counter-clockwise until the first contact
        k, angles, _ = _first(f, phi, 1.0, False)
        if k is None:
            return phi, "turned a full turn touching nothing (the chain cannot reach the object)"
        return _edge(f, angles[k - 1], angles[k]), ""
    # blocked straight on: the smallest clockwise turn that frees it, where it then touches
    k, angles, rooms = _first(f, phi, -1.0, True)
    if k is None:
        best = int(np.argmax(rooms))
        if rooms[best] > -0.5 * r:  # wedged, but sinking in by less than half its thickness
            return float(angles[best]), ""
        return phi, "no room to deploy it (the chain is jammed)"
    return _edge(f, angles[k], angles[k - 1]), ""


def quasi_static_grasp(
    outline: ArrayLike,
    chain: PlanarChain,
    *,
    start: float = 0.0,
    offset: float = 0.0,
    direction: str = "ccw",
    thickness: float | None = None,
    simplify: float = 0.05,
) -> PhysicalGrasp:
    """The grasp :func:`grasp` simulates, in its quasi-static limit: geometry only, no MuJoCo.

    The chain unrolls as :class:`CurlController` unrolls it, with every
    motion slow and every contact rigid and frictionless: link after link is
    turned away from the object just enough to be free, then swung about its
    joint towards the object until it touches the object or an earlier link
    (capsules of ``thickness``), and stays there. Unlike
    :func:`tentaclass.wrap` (which puts every joint on the outline), a link
    rests wherever its body first touches: past a corner it runs on, and the
    next joint turns by more than the corner and the one after turns back;
    on a curve only every other joint rests on the object. These are the
    patterns of physical grasps, at about a hundredth of the cost: use it to
    generate training wraps for recognisers that will read physical or real
    chains.

    Parameters
    ----------
    outline, chain, start, offset, direction, thickness, simplify
        As for :func:`grasp`.

    Returns
    -------
    PhysicalGrasp
        As :func:`grasp` returns (``sim_time`` and ``steps`` 0, no contact
        points or frames); ``complete`` False with ``reason`` when a link
        cannot be deployed (jammed) or turns a full turn touching nothing.

    Raises
    ------
    InputError
        As :func:`grasp`.

    Examples
    --------
    >>> from tentaclass import PlanarChain, grasp_state
    >>> from tentaclass.shapes import square
    >>> g = quasi_static_grasp(square(4), PlanarChain([1.0] * 16), start=0.1)
    >>> g.complete, round(g.laps, 2), grasp_state(g.angles).state.item()
    (True, 0.75, 'partial')
    >>> [round(float(a), 1) for a in g.angles[3:5]]  # a corner: past it, then back
    [2.2, -0.6]
    >>> bool(np.isclose(g.angles.sum(), 2 * np.pi * g.laps))
    True
    """
    su = _prepare(outline, chain, start, offset, direction, thickness, simplify)
    if su.early is not None:
        return su.early
    lengths = su.norm_chain.link_lengths
    n, first, r = su.n, su.first, su.r
    joints = np.empty((n + 1, 2))
    joints[0] = su.base
    for i in range(first):  # the approach: straight
        joints[i + 1] = joints[i] + lengths[i] * np.array([np.cos(su.heading), np.sin(su.heading)])
    joints[first] = su.joint
    reason = ""
    q = np.zeros(n)
    prev = su.heading
    for k in range(first, n):
        m = max(k - 1, first)  # links first .. k - 2: the earlier laps
        placed = np.stack([joints[first:m], joints[first + 1 : m + 1]], axis=1)
        phi = prev + su.q_first if k == first else prev
        a, why = _swing(joints[k], phi, float(lengths[k]), su.poly, placed, r)
        if why:
            reason = f"link {k}: {why}"
            a = prev  # the rest of the chain hangs straight on
        q[k] = a - prev
        joints[k + 1] = joints[k] + lengths[k] * np.array([np.cos(a), np.sin(a)])
        prev = a
        if why:
            for i in range(k + 1, n):
                joints[i + 1] = joints[i] + lengths[i] * np.array([np.cos(a), np.sin(a)])
            break
    return su.finish(q, joints, reason, 0.0, 0, np.zeros((0, 2)), np.zeros(0))
