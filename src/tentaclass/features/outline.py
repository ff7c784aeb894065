"""Outline signatures: a closed outline as a one-dimensional periodic series.

The UCR archive's shape sets (MPEG-7 as ShapesAll, SwedishLeaf, OSULeaf,
ArrowHead, ...) store each outline as its *centroid-distance* profile; the
tentacle's joint angles give its *turning* function. Both are periodic: the
start point of the series is arbitrary, and a mirror image reverses it.
"""

from __future__ import annotations

import numpy as np

from .._typing import ArrayLike, FloatArray
from .._validation import MAX_POINTS, as_float_array, check_choice, check_positive_int
from ..errors import InputError, ShapeError
from ..geometry import _power_of_two_scale, points_to_angles, resample_closed
from .turning import periodic_signal

__all__ = ["SIGNATURES", "outline_to_series", "znormalize"]

#: Signatures :func:`outline_to_series` computes.
SIGNATURES = ("centroid", "turning")


def outline_to_series(
    outline: ArrayLike, n_points: int = 256, *, signature: str = "centroid"
) -> FloatArray:
    """One periodic series describing a closed outline.

    The outline is resampled to ``n_points`` points equally spaced by arc
    length, so the series does not depend on how densely the outline was
    digitised.

    Parameters
    ----------
    outline : array_like of shape (n_vertices, 2)
        A closed polygon (the first point not repeated), as the functions of
        :mod:`tentaclass.shapes` return it (``shapes.from_mask(image)`` for a
        silhouette image).
    n_points : int, default=256
        Length of the series, from 8 to 1,000,000.
    signature : {"centroid", "turning"}, default="centroid"
        ``"centroid"``: distance of each point from the polygon's area centroid,
        divided by its mean (invariant to position, rotation and size).
        ``"turning"``: the periodic turning signal, the heading of each edge
        minus the ``2 pi k / n`` ramp of one counter-clockwise lap, less its
        mean (invariant to position, rotation and size).

    Returns
    -------
    series : ndarray of shape (n_points,)

    Examples
    --------
    >>> from tentaclass.shapes import circle, square
    >>> s = outline_to_series(circle(3.0), 64)
    >>> bool(abs(s - 1).max() < 1e-2)  # a circle is equally far all round
    True
    >>> outline_to_series(square(2.0), 8, signature="turning").round(2).tolist()
    [0.39, -0.39, 0.39, -0.39, 0.39, -0.39, 0.39, -0.39]
    """
    check_choice(signature, "signature", SIGNATURES)
    n = check_positive_int(n_points, "n_points", minimum=8, maximum=MAX_POINTS)
    pts = as_float_array(outline, "outline", min_ndim=2)
    if pts.ndim != 2 or pts.shape[1] != 2:
        raise ShapeError(f"outline must have shape (n_vertices, 2), got {pts.shape}")
    if len(pts) < 3:
        raise ShapeError(f"outline must have at least 3 vertices, got {len(pts)}")
    if not 1e-100 < np.abs(pts).max() < 1e100:
        # both series are invariant to size: scaled exactly (by a power of two) into
        # [1, 2), the cross products below neither overflow nor vanish
        pts = pts / _power_of_two_scale(pts)
    x, y = pts[:, 0], pts[:, 1]
    cross = x * np.roll(y, -1) - np.roll(x, -1) * y
    area = cross.sum() / 2
    if not abs(area) > 1e-12 * max(1.0, float(np.ptp(pts)) ** 2):
        raise InputError("outline encloses no area (its points are collinear or repeated)")
    if area < 0:  # counter-clockwise, so the series runs one way for every outline
        pts = pts[::-1]
    p = resample_closed(pts, n)
    if signature == "centroid":
        c = np.array(
            [
                ((x + np.roll(x, -1)) * cross).sum() / (6 * area),
                ((y + np.roll(y, -1)) * cross).sum() / (6 * area),
            ]
        )
        r = np.hypot(*(p - c).T)
        return r / r.mean()
    e = periodic_signal(points_to_angles(p))
    return e - e.mean()


def znormalize(X: ArrayLike, name: str = "X") -> FloatArray:
    """Each series minus its mean, divided by its standard deviation.

    Parameters
    ----------
    X : array_like of shape (..., n_timepoints)
    name : str
        Argument name used in error messages.

    Returns
    -------
    Z : ndarray of the same shape

    Raises
    ------
    InputError
        A series is constant (it has no shape to compare).

    Examples
    --------
    >>> znormalize([[1.0, 2.0, 3.0]]).round(3).tolist()
    [[-1.225, 0.0, 1.225]]
    """
    arr = as_float_array(X, name, min_ndim=1)
    if arr.size == 0:
        raise ShapeError(f"{name} is empty (shape {arr.shape}): there is no series to normalise")
    # each series scaled exactly (by a power of two) into [1, 2): the same result,
    # and its squares neither overflow nor vanish
    scale = np.abs(arr).max(axis=-1, keepdims=True)
    Z = arr / np.ldexp(1.0, np.frexp(np.where(scale > 0, scale, 1.0))[1] - 1)
    sd = Z.std(axis=-1, keepdims=True)
    flat = ~(sd > 1e-12 * np.abs(Z).max(axis=-1, keepdims=True))
    if flat.any():
        rows = np.flatnonzero(flat.reshape(-1))
        raise InputError(
            f"{name} holds {rows.size} constant series (first at row {rows[0]}): "
            "a constant series has no shape to compare"
        )
    return (Z - Z.mean(axis=-1, keepdims=True)) / sd
