"""Where a link about its joint is free: the geometry both grasp methods turn links by."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import shapely

from .._typing import FloatArray

#: Contacts nearer the joint than this (link lengths) do not stop its turn.
LEVER = 0.1
#: Clearances as fractions of the ideal ones (a link's axis keeps this much of its radius).
SLACK = 0.98
#: Coarse angular step of a sweep (radians); edges are then refined by bisection.
STEP = 0.02
#: Bisection steps refining an edge (0.02 / 2**12: about 5e-6 rad).
REFINE = 12
#: Sweep steps evaluated at once.
CHUNK = 24

Room = Callable[[FloatArray], FloatArray]


def _room(pivot, angles, length, poly, others, need_obj, need_self):
    """Clearance of the link from ``pivot`` at each angle (>= 0: free), vectorised."""
    u = np.stack([np.cos(angles), np.sin(angles)], axis=1)
    segs = shapely.linestrings(np.stack([pivot + LEVER * u, pivot + length * u], axis=1))
    room = np.full(len(angles), np.inf)
    if poly is not None:
        room = shapely.distance(segs, poly) - need_obj
    if others is not None:
        room = np.minimum(room, shapely.distance(segs, others) - need_self)
    return room


def room_about(
    pivot: FloatArray, length: float, poly: shapely.Geometry, segments: FloatArray, r: float
) -> Room:
    """Clearance of a link of ``length`` about ``pivot``, as a function of its direction.

    The link (a capsule of radius ``r``) must keep ``SLACK * r`` from the
    object ``poly`` and twice that from the earlier links ``segments``
    (shape (m, 2, 2)), or, where its joint already sits closer, as much as
    the joint does; its first ``LEVER`` is not looked at (a contact there
    does not stop the joint). Only what the link can reach is looked at.
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
    need_obj = 0.0 if local is None else min(SLACK * r, float(shapely.distance(pt, local))) - 1e-6
    need_self = 0.0
    if others is not None:
        need_self = min(2 * SLACK * r, float(shapely.distance(pt, others))) - 1e-6

    def f(angles: FloatArray) -> FloatArray:
        return _room(pivot, angles, length, local, others, need_obj, need_self)

    return f


def edge(f: Room, lo: float, hi: float) -> float:
    """Bisect between a free angle ``lo`` and a blocked angle ``hi``; the last free one."""
    for _ in range(REFINE):
        mid = 0.5 * (lo + hi)
        if f(np.array([mid]))[0] >= 0:
            lo = mid
        else:
            hi = mid
    return lo


def first(
    f: Room, phi: float, sign: float, want: bool
) -> tuple[int | None, FloatArray, FloatArray]:
    """The first sweep step from ``phi`` (turning ``sign``) where ``f >= 0`` is ``want``.

    Returns its index (None when no step is), the sweep's angles and the rooms seen.
    """
    angles: FloatArray = np.asarray(phi + sign * np.arange(0.0, 2 * np.pi, STEP), dtype=float)
    rooms = []
    for lo in range(0, len(angles), CHUNK):
        room = f(angles[lo : lo + CHUNK])
        rooms.append(room)
        hit = np.flatnonzero((room >= 0) == want)
        if hit.size:
            return lo + int(hit[0]), angles, np.concatenate(rooms)
    return None, angles, np.concatenate(rooms)


def free_turn(f: Room, phi: float, r: float) -> float | None:
    """Direction after the smallest clockwise turn from ``phi`` that frees the link.

    ``phi`` itself when it is free. Where no direction is quite free (a joint
    wedged in a groove), the roomiest one if the link sinks in by less than
    half its thickness; otherwise None (jammed).

    Examples
    --------
    >>> from shapely import box
    >>> f = room_about(np.array([0.0, -0.05]), 1.0, box(-2, 0, 2, 1), np.zeros((0, 2, 2)), 0.05)
    >>> round(free_turn(f, 0.5, 0.05), 3)  # into the box: turned back along its surface
    0.001
    >>> free_turn(f, -0.5, 0.05)  # free already
    -0.5
    """
    if f(np.array([phi]))[0] >= 0:
        return phi
    k, angles, rooms = first(f, phi, -1.0, True)
    if k is None:
        best = int(np.argmax(rooms))
        if rooms[best] > -0.5 * r:  # wedged, but sinking in by less than half its thickness
            return float(angles[best])
        return None
    return edge(f, float(angles[k]), float(angles[k - 1]))
