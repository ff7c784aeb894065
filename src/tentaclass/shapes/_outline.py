"""Outline validation and the primitive outlines (square, circle, ...).

An *outline* is a closed, simple, counter-clockwise polygon stored as an
``(n_points, 2)`` float array; the closing edge from the last point back to
the first is implied (the first point is not repeated at the end).
"""

from __future__ import annotations

import numpy as np
import shapely

from .._typing import ArrayLike, FloatArray
from .._validation import MAX_POINTS, as_points_array, check_positive_float, check_positive_int
from ..errors import InputError, ShapeError

__all__ = [
    "as_outline",
    "circle",
    "polygon",
    "rectangle",
    "regular_polygon",
    "signed_area",
    "square",
    "triangle",
]


def signed_area(outline: ArrayLike) -> float:
    """Shoelace area of a closed outline: positive for a counter-clockwise one.

    Parameters
    ----------
    outline : array_like of shape (n_points, 2)
        Vertices in order, at least 3; the closing edge is implied.

    Returns
    -------
    area : float

    Raises
    ------
    tentaclass.errors.InputError
        A ``ValueError``: not an array of at least 3 finite points, or an area
        beyond the float range.

    Examples
    --------
    >>> signed_area([(0, 0), (2, 0), (2, 1), (0, 1)])
    2.0
    >>> signed_area([(0, 0), (0, 1), (2, 1), (2, 0)])
    -2.0
    """
    p = as_points_array(outline, "outline", min_points=3)
    if p.ndim != 2:
        raise ShapeError(f"outline must have shape (n_points, 2), got shape {p.shape}")
    # scaled exactly (by a power of two) into [1, 2): the products stay in range
    peak = float(np.abs(p).max())
    scale = np.ldexp(1.0, np.frexp(peak)[1] - 1) if peak > 0 else 1.0
    q = p / scale
    # relative to the first point: far from the origin the products would lose digits
    x, y = q[:, 0] - q[0, 0], q[:, 1] - q[0, 1]
    with np.errstate(over="ignore"):
        area = 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y)) * scale * scale
    if not np.isfinite(area):
        raise InputError(f"outline's area is beyond the float range (coordinates up to {peak:g})")
    return float(area)


#: Spans of an outline that areas and intersection tests can compute with.
_MIN_SPAN, _MAX_SPAN = 1e-100, 1e100


def _size(value: object, name: str) -> float:
    """A size of a primitive shape: a number > 0 within the spans :func:`as_outline` takes.

    >>> _size(1e300, "radius")
    Traceback (most recent call last):
    ...
    tentaclass.errors.InputError: radius 1e+300 is too large to compute with (at most 1e+100): \
rescale it
    """
    v = check_positive_float(value, name)
    if not _MIN_SPAN <= v <= _MAX_SPAN:
        bound = f"at most {_MAX_SPAN:g}" if v > _MAX_SPAN else f"at least {_MIN_SPAN:g}"
        size = "large" if v > _MAX_SPAN else "small"
        raise InputError(f"{name} {v:g} is too {size} to compute with ({bound}): rescale it")
    return v


def as_outline(points: ArrayLike, name: str = "outline") -> FloatArray:
    """Validate a closed outline and return it counter-clockwise, as a new array.

    A repeated first point at the end and consecutive duplicate points are
    dropped. Raises :class:`~tentaclass.errors.InputError` (a ``ValueError``) for
    NaN, fewer than 3 distinct points, zero area or a self-intersecting outline.
    """
    p = as_points_array(points, name, min_points=3)
    if p.ndim != 2:
        raise InputError(f"{name} must have shape (n_points, 2), got shape {p.shape}")
    keep = np.any(p != np.roll(p, 1, axis=0), axis=1)
    if not np.any(keep):
        raise InputError(f"{name} has fewer than 3 distinct points: all its points coincide")
    p = p[keep]
    if len(p) < 3:
        raise InputError(f"{name} has fewer than 3 distinct points ({len(p)})")
    with np.errstate(over="ignore"):  # a span beyond float range is refused below
        scale = float(np.ptp(p, axis=0).max())
    # products of coordinates (areas, intersection tests) must stay in range
    if not _MIN_SPAN <= scale <= _MAX_SPAN or np.abs(p).max() > _MAX_SPAN:
        raise InputError(
            f"{name} spans {scale:g}: too large or too small to compute with; rescale it"
        )
    area = signed_area(p)
    ring = shapely.LinearRing(p)
    if abs(area) <= 1e-12 * scale * scale:
        sv = np.linalg.svd(p - p.mean(axis=0), compute_uv=False)
        if sv[1] > 1e-9 * sv[0] and not ring.is_simple:  # not collinear: a figure eight
            raise InputError(
                f"{name} intersects itself: an outline must be a simple closed polygon "
                "(check the point order)"
            )
        raise InputError(f"{name} has zero area: its points are collinear")
    if not ring.is_simple:
        raise InputError(
            f"{name} intersects itself: an outline must be a simple closed polygon "
            "(check the point order)"
        )
    return np.ascontiguousarray(p if area > 0 else p[::-1])


def polygon(vertices: ArrayLike) -> FloatArray:
    """A polygon outline from its vertices, validated and oriented counter-clockwise.

    Parameters
    ----------
    vertices : array_like of shape (n_vertices, 2)
        Vertices in order, either orientation; the closing edge is implied and a
        repeated first vertex at the end is dropped.

    Returns
    -------
    outline : ndarray of shape (n_vertices, 2)

    Raises
    ------
    InputError
        NaN, fewer than 3 distinct points, zero area or self-intersection.

    Examples
    --------
    >>> polygon([(0, 0), (0, 1), (1, 0)])  # clockwise in, counter-clockwise out
    array([[1., 0.],
           [0., 1.],
           [0., 0.]])
    """
    return as_outline(vertices, "vertices")


def rectangle(width: float, height: float) -> FloatArray:
    """Axis-aligned rectangle centred on the origin, starting at its lower-left corner.

    Examples
    --------
    >>> rectangle(6, 2)
    array([[-3., -1.],
           [ 3., -1.],
           [ 3.,  1.],
           [-3.,  1.]])
    """
    w = _size(width, "width") / 2
    h = _size(height, "height") / 2
    return np.array([(-w, -h), (w, -h), (w, h), (-w, h)])


def square(side: float) -> FloatArray:
    """Square centred on the origin, starting at its lower-left corner.

    Examples
    --------
    >>> square(4)[0], square(4).shape
    (array([-2., -2.]), (4, 2))
    """
    return rectangle(side, side)


def triangle(vertices: ArrayLike | None = None, *, side: float = 1.0) -> FloatArray:
    """A triangle: three vertices (any side lengths), or equilateral with ``side``.

    Examples
    --------
    >>> triangle([(0, 0), (3, 0), (0, 1)]).shape
    (3, 2)
    >>> round(float(abs(signed_area(triangle(side=2)))), 6)  # sqrt(3)
    1.732051
    """
    if vertices is None:
        s = _size(side, "side")
        return np.array([(-s / 2, 0.0), (s / 2, 0.0), (0.0, s * np.sqrt(3) / 2)])
    p = as_outline(vertices, "vertices")
    if len(p) != 3:
        raise InputError(f"a triangle needs 3 distinct vertices, got {len(p)}")
    return p


def regular_polygon(n_sides: int, radius: float) -> FloatArray:
    """Regular polygon with circumradius ``radius``, a flat bottom side, starting at a vertex.

    Examples
    --------
    >>> p = regular_polygon(4, np.sqrt(2))
    >>> np.round(p, 12) + 0.0
    array([[ 1., -1.],
           [ 1.,  1.],
           [-1.,  1.],
           [-1., -1.]])
    """
    n = check_positive_int(n_sides, "n_sides", minimum=3, maximum=MAX_POINTS)
    r = _size(radius, "radius")
    a = -np.pi / 2 + np.pi / n + 2 * np.pi * np.arange(n) / n
    return r * np.stack([np.cos(a), np.sin(a)], axis=1)


def circle(radius: float, n_points: int = 256) -> FloatArray:
    """Circle centred on the origin as a regular ``n_points``-gon, starting at ``(radius, 0)``.

    Examples
    --------
    >>> circle(1.0, n_points=4).round(12) + 0.0
    array([[ 1.,  0.],
           [ 0.,  1.],
           [-1.,  0.],
           [ 0., -1.]])
    """
    r = _size(radius, "radius")
    n = check_positive_int(n_points, "n_points", minimum=3, maximum=MAX_POINTS)
    a = 2 * np.pi * np.arange(n) / n
    return r * np.stack([np.cos(a), np.sin(a)], axis=1)
