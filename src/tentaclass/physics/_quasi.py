"""The quasi-static limit of a physical grasp: each link swings until it touches (no MuJoCo)."""

from __future__ import annotations

import numpy as np

from .._typing import ArrayLike
from ..manipulator import PlanarChain
from ._grasp import PhysicalGrasp, _prepare
from ._sweep import edge, first, free_turn, room_about

__all__ = ["quasi_static_grasp"]


def _swing(pivot, phi, length, poly, segments, r):
    """Final direction of a link deployed at ``pivot`` pointing along ``phi``.

    As :class:`CurlController` deploys it: turned clockwise (away from the
    object) just enough to be free, then curled counter-clockwise until it
    touches the object ``poly`` or an earlier link (``segments``, (m, 2, 2)).
    Returns (angle, reason); reason is "" on success.
    """
    f = room_about(pivot, length, poly, segments, r)
    if f(np.array([phi]))[0] >= 0:  # free: curl counter-clockwise until the first contact
        k, angles, _ = first(f, phi, 1.0, False)
        if k is None:
            return phi, "turned a full turn touching nothing (the chain cannot reach the object)"
        return edge(f, float(angles[k - 1]), float(angles[k])), ""
    # blocked straight on: the smallest clockwise turn that frees it, where it then touches
    a = free_turn(f, phi, r)
    if a is None:
        return phi, "no room to deploy it (the chain is jammed)"
    return a, ""


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
        As :func:`grasp`, except that any number of links is taken (no MuJoCo model).

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
