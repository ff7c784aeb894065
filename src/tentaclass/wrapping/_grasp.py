"""Grasp state from joint angles alone: partial, once or several laps, and the offset.

The thesis (section 5.2.1) reads the grasp state from the sum ``S`` of the
joint angles: ``0 < S < 2 pi`` not fully grasped, ``S = 2 pi`` grasped once,
``S > 2 pi`` more than once. Real arrays need two additions, both made here:
a tolerance (joint noise and the last link's position make ``S`` inexact),
and the approach: links that reach from a base standing off the object have
turns close to zero and end with a turn of about ``-pi/2`` onto the surface
(for a counter-clockwise wrap), which must not count against the laps.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._typing import ArrayLike, FloatArray, IntArray
from .._validation import as_angle_array, check_positive_float

__all__ = ["GraspState", "grasp_state"]

STATES = ("partial", "once", "multiple")


@dataclass(frozen=True)
class GraspState:
    """Grasp state of a batch of joint-angle arrays; every field has the batch shape.

    Attributes
    ----------
    state : ndarray of str
        ``"partial"``, ``"once"`` or ``"multiple"``.
    laps : ndarray of float
        Turns around the object after the first contact (1.0 = one full lap).
    laps_rounded : ndarray of int
        ``laps`` rounded to the nearest integer.
    offset_links : ndarray of int
        Links from the base to the first contact (0: the base touches the object).
    direction : ndarray of int
        +1 for a counter-clockwise wrap (angles sum to a positive turn), -1 for
        clockwise.
    """

    state: np.ndarray
    laps: FloatArray
    laps_rounded: IntArray
    offset_links: IntArray
    direction: IntArray


def grasp_state(
    q: ArrayLike, *, tol: float = 0.1, zero_tol: float = 0.1, contact_tol: float = 1.2
) -> GraspState:
    """Partial, single or multiple grasp, laps and offset, from joint angles.

    Parameters
    ----------
    q : array_like of shape (..., n_joints)
        Relative joint angles (radians), as :func:`tentaclass.wrap` returns them
        (``q[0]`` against the base's heading). Leading axes are a batch.
    tol : float, default=0.1
        Laps within ``tol`` of 1 count as ``"once"``.
    zero_tol : float, default=0.1
        Turns smaller than this (radians) count as straight: an approach is a
        leading run of them ended by a turn below ``-zero_tol`` (against the
        wrapping direction).
    contact_tol : float, default=1.2
        A first turn of the approach below ``-contact_tol`` puts the contact on
        that joint; a smaller one means the turn onto the surface is split over
        two joints and the contact is the next one.

    Returns
    -------
    GraspState

    Notes
    -----
    Direction: the sign of ``sum(q)``; a clockwise array is mirrored first.
    Without an approach ``laps = sum(q) / 2pi`` (the thesis's rule). With one,
    the approach runs along the surface's inward normal and turns by ``-pi/2``
    onto it, which is not part of the wrap: ``laps = (sum(q) + pi/2) / 2pi``.
    These are the conventions of :func:`tentaclass.wrap` (``Wrap.laps``).
    States: ``laps < 1 - tol`` partial, ``|laps - 1| <= tol`` once,
    ``laps > 1 + tol`` multiple.

    Examples
    --------
    >>> import numpy as np
    >>> square = np.tile([0, 0, 0, np.pi / 2], 4)
    >>> [grasp_state(a).state.item() for a in (square, np.r_[square, square], square[:10])]
    ['once', 'multiple', 'partial']
    >>> approach = np.r_[0, 0, -np.pi / 2, square, np.zeros(13)]  # base 2 links off
    >>> g = grasp_state(np.stack([np.r_[square, square], approach]))
    >>> g.laps_rounded.tolist(), g.offset_links.tolist(), g.state.tolist()
    ([2, 1], [0, 2], ['multiple', 'once'])
    """
    q = as_angle_array(q, "q", min_joints=1)
    tol = check_positive_float(tol, "tol")
    zero_tol = check_positive_float(zero_tol, "zero_tol")
    contact_tol = check_positive_float(contact_tol, "contact_tol")
    n = q.shape[-1]
    total = q.sum(axis=-1)
    direction = np.where(total < 0, -1, 1)
    qs = q * direction[..., None]
    straight = np.abs(qs) < zero_tol
    first = np.where(straight.all(axis=-1), n, np.argmax(~straight, axis=-1))
    val = np.take_along_axis(qs, np.minimum(first, n - 1)[..., None], axis=-1)[..., 0]
    approach = (first < n) & (val < -zero_tol)
    all_straight_tail = first >= n
    offset = np.where(approach, np.where(val < -contact_tol, first, first + 1), 0)
    turning = qs.sum(axis=-1)
    laps = np.where(approach, turning + np.pi / 2, turning) / (2 * np.pi)
    laps = np.where(all_straight_tail & (np.abs(turning) < zero_tol), 0.0, laps)
    state = np.where(laps < 1 - tol, STATES[0], np.where(laps <= 1 + tol, STATES[1], STATES[2]))
    return GraspState(
        state=np.asarray(state),
        laps=np.asarray(laps, dtype=float),
        laps_rounded=np.asarray(np.rint(laps), dtype=np.int64),
        offset_links=np.asarray(offset, dtype=np.int64),
        direction=np.asarray(direction, dtype=np.int64),
    )
