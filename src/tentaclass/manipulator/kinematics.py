"""Kinematic kernels of a planar serial chain, vectorised over leading axes.

The kernels assume clean input (validated by :class:`~.chain.PlanarChain`):
float arrays whose last axis holds one entry per link, broadcast to a common
shape ``(..., n)``. Vectors in the plane are carried as separate x and y arrays
of shape ``(..., n)``; only the public results are stacked into ``(..., 2)``.

Notation (thesis chapter 2): ``phi_i = q_1 + ... + q_i`` is the absolute angle
of link ``i`` (eq. 2.4), ``r_i = l_i (cos phi_i, sin phi_i)`` the link vector,
``c_i = a_i l_i (cos phi_i, sin phi_i)`` the offset of its centre of mass from
joint ``i`` (``a_i`` the fraction ``com``), ``p_{i-1}`` the position of joint
``i`` (the start of link ``i``; ``p_0`` is the base at the origin) and
``perp(v) = (-v_y, v_x)`` the rotation by +90 degrees.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._typing import FloatArray
from ..geometry import angles_to_points

__all__ = ["ChainKinematics"]


@dataclass(frozen=True, slots=True)
class ChainKinematics:
    """Positions and angles of a planar chain in one or many configurations.

    Attributes
    ----------
    joints : ndarray of shape (..., n_links + 1, 2)
        Joint positions: ``joints[..., 0, :]`` is the base (the origin),
        ``joints[..., i, :]`` the end of link ``i``; the last row is the end point.
    com : ndarray of shape (..., n_links, 2)
        Position of each link's centre of mass.
    angles : ndarray of shape (..., n_links)
        Absolute link angles ``phi_i = q_1 + ... + q_i`` from the x axis.
    """

    joints: FloatArray
    com: FloatArray
    angles: FloatArray


def cumsum_excl(x: FloatArray) -> FloatArray:
    """Exclusive prefix sum along the last axis: ``out_i = x_1 + ... + x_{i-1}``."""
    out = np.zeros_like(x)
    np.cumsum(x[..., :-1], axis=-1, out=out[..., 1:])
    return out


def rcumsum(x: FloatArray) -> FloatArray:
    """Inclusive suffix sum along the last axis: ``out_i = x_i + ... + x_n``."""
    return np.cumsum(x[..., ::-1], axis=-1)[..., ::-1]


def rcumsum_excl(x: FloatArray) -> FloatArray:
    """Exclusive suffix sum along the last axis: ``out_i = x_{i+1} + ... + x_n``."""
    out = np.zeros_like(x)
    np.cumsum(x[..., :0:-1], axis=-1, out=out[..., -2::-1])
    return out


def link_vectors(
    q: FloatArray, lengths: FloatArray, com_lengths: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
    """Absolute angles ``phi``, link vectors ``(rx, ry)`` and COM offsets ``(cx, cy)``."""
    phi = np.cumsum(q, axis=-1)
    cos, sin = np.cos(phi), np.sin(phi)
    return phi, lengths * cos, lengths * sin, com_lengths * cos, com_lengths * sin


def forward_kinematics(
    q: FloatArray, lengths: FloatArray, com_lengths: FloatArray
) -> ChainKinematics:
    """Joint and centre-of-mass positions (eqs 2.4-2.7 and 2.10)."""
    phi, _, _, cx, cy = link_vectors(q, lengths, com_lengths)
    joints = angles_to_points(q, lengths)
    com = joints[..., :-1, :] + np.stack([cx, cy], axis=-1)
    return ChainKinematics(joints=joints, com=com, angles=phi)


def end_jacobian(q: FloatArray, lengths: FloatArray) -> FloatArray:
    """Jacobian of the end point, ``J[:, j] = perp(p_n - p_{j-1})`` (eq. 2.8)."""
    _, rx, ry, _, _ = link_vectors(q, lengths, lengths)
    # p_n - p_{j-1} = r_j + ... + r_n: a suffix sum over the links.
    dx, dy = rcumsum(rx), rcumsum(ry)
    return np.stack([-dy, dx], axis=-2)


def end_jacobian_dot(q: FloatArray, qd: FloatArray, lengths: FloatArray) -> FloatArray:
    """Time derivative of the end-point Jacobian (eq. 2.9).

    ``d/dt perp(p_n - p_{j-1}) = perp(sum_{k>=j} w_k perp(r_k)) = -sum_{k>=j} w_k r_k``
    with ``w_k = qd_1 + ... + qd_k`` the absolute angular velocity of link ``k``.
    """
    _, rx, ry, _, _ = link_vectors(q, lengths, lengths)
    w = np.cumsum(qd, axis=-1)
    return -np.stack([rcumsum(w * rx), rcumsum(w * ry)], axis=-2)


def com_jacobians(q: FloatArray, lengths: FloatArray, com_lengths: FloatArray) -> FloatArray:
    """Jacobians of each link's centre of mass and angle, shape ``(..., n, 3, n)`` (eq. 2.12).

    Row block ``i`` holds ``d(x_ci, y_ci, phi_i)/dq``: column ``j <= i`` is
    ``(perp(x_ci - p_{j-1}), 1)``, columns ``j > i`` are zero.
    """
    kin = forward_kinematics(q, lengths, com_lengths)
    n = q.shape[-1]
    # d[..., i, j, :] = x_ci - p_{j-1}
    d = kin.com[..., :, None, :] - kin.joints[..., None, :-1, :]
    lower = np.tril(np.ones((n, n)))  # j <= i
    out = np.empty((*kin.angles.shape[:-1], n, 3, n))
    out[..., 0, :] = -d[..., 1] * lower
    out[..., 1, :] = d[..., 0] * lower
    out[..., 2, :] = lower
    return out
