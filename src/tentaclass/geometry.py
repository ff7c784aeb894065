"""Geometry of joint-angle arrays: chains of links <-> points in the plane.

A planar chain of ``n`` links with relative joint angles ``q`` (the angle
between consecutive links, counter-clockwise positive) and link lengths ``l``
has absolute link headings ``phi_i = heading + q_1 + ... + q_i`` and joint
positions ``p_0 = base``, ``p_i = p_{i-1} + l_i (cos phi_i, sin phi_i)``.
With all lengths equal and ``q`` the turning angles of an outline, the joints
trace that outline: the chain is a *shape definer*.

All functions take batches over leading axes: ``(..., n_joints)`` angles and
``(..., n_points, 2)`` points.
"""

from __future__ import annotations

import numpy as np

from ._typing import ArrayLike, FloatArray
from ._validation import (
    MAX_POINTS,
    as_angle_array,
    as_float_array,
    as_points_array,
    check_positive_int,
    check_total,
)
from .errors import InputError, ShapeError

__all__ = ["angles_to_points", "points_to_angles", "resample_closed"]


#: Farthest joint from the origin :func:`angles_to_points` places: the sums of
#: coordinates that follow (perimeters, areas) stay within float64.
_MAX_REACH = 1e300


def _link_lengths(link_lengths: ArrayLike, n: int) -> FloatArray:
    lengths = as_float_array(link_lengths, "link_lengths")
    if lengths.ndim > 0 and lengths.shape[-1] not in (1, n):
        raise ShapeError(
            f"link_lengths must be a scalar or have {n} entries along its last axis "
            f"(one per joint angle), got shape {lengths.shape}"
        )
    if np.any(lengths <= 0):
        raise InputError("link_lengths must all be > 0")
    return lengths


def _power_of_two_scale(p: FloatArray) -> FloatArray:
    """Per outline, a power of two near its largest coordinate (1 for all zeros).

    Dividing by it is exact and brings the coordinates into ``[1, 2)``.
    """
    peak = np.abs(p).max(axis=(-2, -1), keepdims=True)
    return np.ldexp(1.0, np.frexp(np.where(peak > 0, peak, 1.0))[1] - 1)


def angles_to_points(
    q: ArrayLike,
    link_lengths: ArrayLike = 1.0,
    base: ArrayLike = (0.0, 0.0),
    heading: ArrayLike = 0.0,
) -> FloatArray:
    """Joint positions of a planar chain from its relative joint angles.

    Parameters
    ----------
    q : array_like of shape (..., n_joints)
        Relative joint angles in radians; ``q[..., 0]`` is the angle of the first
        link against ``heading``. Leading axes are a batch.
    link_lengths : float or array_like of shape (..., n_joints), default=1.0
        Length of each link; broadcast against ``q``.
    base : array_like of shape (..., 2), default=(0, 0)
        Position of the chain's base, ``p_0``.
    heading : float or array_like of shape (...), default=0.0
        Direction (radians from the x axis) the first joint angle is measured from.

    Returns
    -------
    points : ndarray of shape (..., n_joints + 1, 2)
        ``points[..., 0, :]`` is the base, ``points[..., i, :]`` the end of link ``i``.

    Notes
    -----
    Forward kinematics of the planar chain:
    ``phi_i = heading + sum_{j<=i} q_j`` and
    ``p_i = p_{i-1} + l_i (cos phi_i, sin phi_i)``.

    Examples
    --------
    >>> import numpy as np
    >>> square = np.tile([0, 0, 0, np.pi / 2], 4)
    >>> p = angles_to_points(square)
    >>> p.shape
    (17, 2)
    >>> bool(np.allclose(p[-1], p[0]))
    True
    """
    q = as_angle_array(q, "q", min_joints=1)
    n = q.shape[-1]
    lengths = _link_lengths(link_lengths, n)
    base = as_float_array(base, "base", min_ndim=1)
    if base.shape[-1] != 2:
        raise ShapeError(f"base must have shape (..., 2), got shape {base.shape}")
    heading = as_float_array(heading, "heading")
    with np.errstate(over="ignore"):  # (an infinite reach is refused)
        reach = float(np.abs(base).max()) + n * float(lengths.max())
    if not reach <= _MAX_REACH:
        raise InputError(
            f"link_lengths up to {float(lengths.max()):g} over {n} links (from a base at "
            f"{float(np.abs(base).max()):g}) reach {reach:g}: the joint positions would "
            f"overflow float64 (at most {_MAX_REACH:g}); rescale the lengths"
        )
    phi = np.cumsum(q, axis=-1) + heading[..., None]
    steps = np.stack([np.cos(phi), np.sin(phi)], axis=-1) * np.asarray(lengths)[..., None]
    batch = np.broadcast_shapes(steps.shape[:-2], base.shape[:-1])
    steps = np.broadcast_to(steps, (*batch, n, 2))
    out = np.empty((*batch, n + 1, 2))
    out[..., 0, :] = base
    np.cumsum(steps, axis=-2, out=out[..., 1:, :])
    out[..., 1:, :] += out[..., :1, :]
    return out


def points_to_angles(
    points: ArrayLike, closed: bool = True, heading: ArrayLike = 0.0
) -> FloatArray:
    """Signed relative turning angles of a polyline or closed outline.

    Parameters
    ----------
    points : array_like of shape (..., n_points, 2)
        Vertices in order. For ``closed=True`` a repeated first point at the end
        is dropped.
    closed : bool, default=True
        If True the outline is closed: ``n_points`` vertices give ``n_points``
        angles, angle ``k`` being the turn at vertex ``k`` from the incoming edge
        ``p[k] - p[k-1]`` to the outgoing edge ``p[k+1] - p[k]``. A simple
        counter-clockwise outline sums to ``2*pi``. If False the polyline is an
        open chain: ``n_points`` vertices give ``n_points - 1`` angles, the first
        measured from ``heading``; this inverts :func:`angles_to_points`.
    heading : float or array_like of shape (...), default=0.0
        Reference direction of the first angle of an open chain.

    Returns
    -------
    angles : ndarray of shape (..., n_angles)
        Angles in (-pi, pi], computed as ``atan2(cross, dot)`` so that clockwise
        (concave) turns are negative.

    Raises
    ------
    InputError
        If two consecutive points coincide (the turn there is undefined).

    Examples
    --------
    >>> import numpy as np
    >>> L = [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)]
    >>> q = points_to_angles(L)
    >>> np.round(q / (np.pi / 2), 6)
    array([ 1.,  1.,  1., -1.,  1.,  1.])
    >>> float(np.round(q.sum(), 12)) == round(2 * np.pi, 12)
    True
    """
    p = as_points_array(points, "points", min_points=2)
    # Turning angles do not change with scale: products below stay in range.
    p = p / _power_of_two_scale(p)
    if closed:
        if p.shape[-2] > 3 and np.all(p[..., 0, :] == p[..., -1, :]):
            p = p[..., :-1, :]
        if p.shape[-2] < 3:
            raise ShapeError(
                f"a closed outline needs at least 3 distinct points, got {p.shape[-2]}"
            )
        edges = np.roll(p, -1, axis=-2) - p
        prev = np.roll(edges, 1, axis=-2)
    else:
        edges = np.diff(p, axis=-2)
        h = as_float_array(heading, "heading")
        ref = np.stack([np.cos(h), np.sin(h)], axis=-1)[..., None, :]
        prev = np.concatenate(
            [np.broadcast_to(ref, (*edges.shape[:-2], 1, 2)), edges[..., :-1, :]], axis=-2
        )
    length = np.hypot(edges[..., 0], edges[..., 1])
    if np.any(length == 0):
        raise InputError(
            "points contains two consecutive equal points: the turn there is undefined"
        )
    cross = prev[..., 0] * edges[..., 1] - prev[..., 1] * edges[..., 0]
    dot = prev[..., 0] * edges[..., 0] + prev[..., 1] * edges[..., 1]
    return np.arctan2(cross, dot)


def resample_closed(points: ArrayLike, n: int) -> FloatArray:
    """Points equally spaced by arc length along a closed outline.

    Parameters
    ----------
    points : array_like of shape (..., n_points, 2)
        Vertices of a closed outline (the closing edge back to the first point is
        implied; a repeated first point at the end is harmless).
    n : int
        Number of output points, at least 3 and at most 1,000,000 or the
        outline's own number of points, whichever is larger.

    Returns
    -------
    resampled : ndarray of shape (..., n, 2)
        ``resampled[..., 0, :]`` is the first input point; the others follow it
        at arc-length steps of ``perimeter / n`` along the outline.

    Notes
    -----
    Linear interpolation along the polygon: it removes uneven spacing between
    points (as in hand-drawn outlines) without smoothing corners away.

    Examples
    --------
    >>> resample_closed([(0, 0), (4, 0), (4, 4), (0, 4)], 8)[:3]
    array([[0., 0.],
           [2., 0.],
           [4., 0.]])
    """
    p = as_points_array(points, "points", min_points=3)
    # as many points as the outline has are always affordable (a lap of a long chain)
    n = check_positive_int(n, "n", minimum=3, maximum=max(MAX_POINTS, p.shape[-2]))
    check_total(int(np.prod(p.shape[:-2])) * n * 2, "the resampled outlines")
    scale = _power_of_two_scale(p)  # resampling commutes with scaling: no overflow
    p = p / scale
    batch = p.shape[:-2]
    m = p.shape[-2]
    flat = p.reshape(-1, m, 2)
    closed = np.concatenate([flat, flat[:, :1, :]], axis=1)
    seg = np.hypot(*np.moveaxis(np.diff(closed, axis=1), -1, 0))
    s = np.concatenate([np.zeros((flat.shape[0], 1)), np.cumsum(seg, axis=1)], axis=1)
    total = s[:, -1:]
    if np.any(total <= 0):
        raise InputError("points has zero perimeter: all points coincide")
    # Batched np.interp: offset each row's normalised arc length by 2*row so that
    # one searchsorted over the flattened rows finds every segment at once.
    rows = np.arange(flat.shape[0])[:, None]
    u = s / total + 2.0 * rows
    t = np.arange(n) / n + 2.0 * rows
    idx = np.searchsorted(u.ravel(), t.ravel(), side="right") - 1
    idx = np.clip(idx.reshape(t.shape) - rows * (m + 1), 0, m - 1)
    u0 = np.take_along_axis(u, idx, axis=1)
    u1 = np.take_along_axis(u, idx + 1, axis=1)
    w = np.where(u1 > u0, (t - u0) / np.where(u1 > u0, u1 - u0, 1.0), 0.0)[..., None]
    a = np.take_along_axis(closed, idx[..., None], axis=1)
    b = np.take_along_axis(closed, idx[..., None] + 1, axis=1)
    return (a + w * (b - a)).reshape(*batch, n, 2) * scale
