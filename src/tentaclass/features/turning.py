"""Turning function and its periodic signal (thesis chapter 4, eq 4.5)."""

from __future__ import annotations

import numpy as np

from .._dask import blockwise
from .._typing import ArrayLike, FloatArray
from .._validation import as_angle_array, check_positive_float

__all__ = ["canonical_direction", "periodic_signal", "turning_function"]


@blockwise
def turning_function(q: ArrayLike) -> FloatArray:
    """Heading of each link of a planar chain, from its relative joint angles.

    Parameters
    ----------
    q : array_like of shape (..., n_joints)
        Relative joint angles. Leading axes are a batch.

    Returns
    -------
    heading : ndarray of shape (..., n_joints)
        ``t_k = q_1 + ... + q_k``, the tangent direction of link ``k``
        (Arkin et al. 1991). A rotation of the object adds a constant.

    References
    ----------
    E. M. Arkin et al., "An efficiently computable metric for comparing
    polygonal shapes", IEEE PAMI 13(3), 1991.

    Examples
    --------
    >>> turning_function([[0.0, 0.5, 1.0], [0.1, 0.2, 0.3]])
    array([[0. , 0.5, 1.5],
           [0.1, 0.3, 0.6]])
    """
    return np.cumsum(as_angle_array(q, "q", min_joints=1), axis=-1)


@blockwise
def periodic_signal(
    q: ArrayLike, *, detrend: bool = False, period: float = 2 * np.pi
) -> FloatArray:
    """Turning function with its ramp removed, periodic for a closed outline.

    Parameters
    ----------
    q : array_like of shape (..., n_joints)
        Relative joint angles.
    detrend : bool, default=False
        If False subtract the thesis's ramp ``period * k / n`` (eq 4.5). If True
        subtract ``t_n * k / n``, the ramp through the measured total turn: the
        signal then ends at exactly zero even when joint noise has made the
        total drift away from one lap, which keeps noise from leaking into every
        Fourier coefficient.
    period : float, default=2*pi
        One full turn in the units of ``q``; use 360 for degrees.

    Returns
    -------
    signal : ndarray of shape (..., n_joints)
        ``E_k = t_k - period * k / n`` for ``k = 1..n``.

    Examples
    --------
    >>> import numpy as np
    >>> E = periodic_signal([np.pi / 8] * 16)
    >>> bool(np.allclose(E, 0))
    True
    """
    q = as_angle_array(q, "q", min_joints=1)
    period = check_positive_float(period, "period")
    n = q.shape[-1]
    t = np.cumsum(q, axis=-1)
    k = np.arange(1, n + 1) / n
    total = t[..., -1:] if detrend else period
    return t - total * k


@blockwise
def canonical_direction(q: ArrayLike) -> FloatArray:
    """Turn clockwise wraps into counter-clockwise ones.

    A chain wrapped the other way round measures the same object with its
    angles negated and in reverse order. Rows whose total turn is negative are
    mapped back with ``q -> -q[::-1]``; the others are returned unchanged.

    Parameters
    ----------
    q : array_like of shape (..., n_joints)

    Returns
    -------
    q_ccw : ndarray of shape (..., n_joints)
        A new array; the total turn of every row is >= 0.

    Examples
    --------
    >>> canonical_direction([[0.1, 0.2, 0.3], [-0.1, -0.2, -0.4]])
    array([[0.1, 0.2, 0.3],
           [0.4, 0.2, 0.1]])
    """
    q = as_angle_array(q, "q", min_joints=1)
    cw = q.sum(axis=-1) < 0
    return np.where(cw[..., None], -q[..., ::-1], q)
