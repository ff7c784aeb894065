"""Outlines from hand-drawn strokes: resampled, closed, trimmed and smoothed."""

from __future__ import annotations

import numpy as np
import shapely

from .._typing import ArrayLike, FloatArray
from .._validation import MAX_POINTS, check_positive_float, check_positive_int
from ..errors import InputError, ShapeError
from ..geometry import resample_closed
from ._outline import as_outline

__all__ = ["from_stroke"]

#: Points the open stroke is resampled to before it is closed and smoothed.
_N_WORK = 256
#: The closing point is looked for in this fraction of the stroke at each end.
_END_FRACTION = 0.3
#: Weight of the trimmed arc length against the gap left to close.
_TRIM_WEIGHT = 0.25
#: A self-crossing stroke is kept when its largest loop holds this share of the area.
_MAIN_LOOP_SHARE = 0.8


def _arc_resample(p: FloatArray, n: int) -> FloatArray:
    """``n`` points equally spaced by arc length along an open polyline."""
    s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(p, axis=0).T))])
    t = np.linspace(0.0, s[-1], n)
    return np.stack([np.interp(t, s, p[:, 0]), np.interp(t, s, p[:, 1])], axis=1)


def _closure(q: FloatArray) -> tuple[int, int]:
    """Indices ``i < j`` where the stroke closes: gap plus a share of the trimmed ends smallest."""
    m = len(q)
    k = max(2, int(_END_FRACTION * m))
    head, tail = q[:k], q[m - k :]
    gap = np.hypot(*(head[:, None, :] - tail[None, :, :]).transpose(2, 0, 1))
    step = np.hypot(*(q[1] - q[0]))
    trimmed = (np.arange(k)[:, None] + (k - 1 - np.arange(k))[None, :]) * step
    i, j = np.unravel_index(np.argmin(gap + _TRIM_WEIGHT * trimmed), gap.shape)
    return int(i), int(m - k + j)


def _main_loop(c: FloatArray, extent: float) -> FloatArray:
    """The closed curve itself, or its dominant loop when it crosses itself only a little."""
    tiny = 1e-6 * extent * extent
    ring = shapely.LinearRing(c)
    if ring.is_simple:
        if shapely.Polygon(c).area <= tiny:
            raise InputError("stroke encloses no area: draw a closed outline, not a line")
        return c
    pieces = shapely.get_parts(shapely.get_parts(shapely.make_valid(shapely.Polygon(c))))
    parts = [g for g in pieces if isinstance(g, shapely.Polygon) and g.area > 0]
    areas = np.array([g.area for g in parts])
    if len(parts) == 0 or areas.sum() <= tiny:
        raise InputError("stroke encloses no area: draw a closed outline, not a line")
    if areas.max() < _MAIN_LOOP_SHARE * areas.sum():
        raise InputError(
            "stroke crosses itself (like a figure eight): draw one outline that does not "
            "cross itself"
        )
    return np.asarray(parts[int(np.argmax(areas))].exterior.coords)[:-1]


def from_stroke(points: ArrayLike, n_points: int = 128, *, smoothing: float = 0.01) -> FloatArray:
    """A closed outline from a hand-drawn stroke.

    Parameters
    ----------
    points : array_like of shape (n_points_in, 2)
        The stroke's points in drawing order, as a pointer trace records them:
        unevenly spaced, not quite closed or running past the start.
    n_points : int, default=128
        Points of the returned outline, equally spaced along it (at most 1,000,000).
    smoothing : float, default=0.01
        Standard deviation of the Gaussian smoothing, as a fraction of the
        perimeter, at most 1 (0 turns smoothing off).

    Returns
    -------
    outline : ndarray of shape (n_points, 2)
        Closed, simple and counter-clockwise (in the stroke's frame), as
        :func:`as_outline` returns outlines.

    Raises
    ------
    InputError
        Empty or one-point strokes, NaN, strokes with no extent, and strokes
        that cross themselves (a figure eight).

    Notes
    -----
    Cleaning steps, in order:

    1. drop repeated consecutive points; resample the stroke to 256 points
       equally spaced by arc length (removes the uneven spacing of a pointer
       moving at varying speed);
    2. close it: among pairs of points in the first and last 30 % of the
       stroke, take the pair that minimises the distance between them plus a
       quarter of the arc length cut off beyond them. An overshoot is cut off
       where the stroke passes its start; a gap is bridged by a straight line;
    3. when the closed curve crosses itself (a small loop at a sloppy
       closure), keep its largest loop if that holds at least 80 % of the
       enclosed area; otherwise (a figure eight) refuse the stroke;
    4. smooth with a periodic Gaussian filter (``smoothing`` of the perimeter)
       to remove hand jitter, then resample to ``n_points`` equally spaced
       points.

    Examples
    --------
    >>> t = np.linspace(0, 2.1 * np.pi, 50) ** 1.2  # uneven spacing, overshoot
    >>> stroke = np.stack([np.cos(t), np.sin(t)], axis=1)
    >>> out = from_stroke(stroke, 64)
    >>> out.shape, bool(np.allclose(np.hypot(*out.T), 1, atol=0.05))
    ((64, 2), True)
    """
    from scipy.ndimage import gaussian_filter1d

    try:
        p = np.asarray(points, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InputError("stroke points must be numbers") from exc
    if p.size == 0:
        raise InputError("stroke is empty: draw an outline")
    if p.ndim != 2 or p.shape[1] != 2:
        raise ShapeError(f"stroke must have shape (n_points, 2), got shape {p.shape}")
    if not np.all(np.isfinite(p)):
        raise InputError("stroke contains NaN or infinite coordinates")
    n_points = check_positive_int(n_points, "n_points", minimum=3, maximum=MAX_POINTS)
    smoothing = check_positive_float(smoothing, "smoothing", allow_zero=True)
    if smoothing > 1:
        raise InputError(
            f"smoothing must be at most 1 (a Gaussian one perimeter wide already leaves no "
            f"shape), got {smoothing:g}"
        )
    keep = np.r_[True, np.any(np.diff(p, axis=0) != 0, axis=1)]
    p = p[keep]
    if len(p) < 3:
        raise InputError(f"stroke has {len(p)} distinct point(s): draw an outline, not a dot")
    extent = float(np.ptp(p, axis=0).max())
    if not np.isfinite(extent * extent) or extent * extent == 0:
        raise InputError(f"stroke spans {extent:g}: too large or too small to compute with")
    q = _arc_resample(p, _N_WORK)
    i, j = _closure(q)
    c = q[i : j + 1]
    if len(c) < 3:
        raise InputError("stroke encloses no area: draw a closed outline, not a line")
    c = _main_loop(c, extent)
    c = resample_closed(c, _N_WORK)
    if smoothing > 0:
        c = gaussian_filter1d(c, smoothing * _N_WORK, axis=0, mode="wrap")
    c = _main_loop(c, extent)
    return as_outline(resample_closed(c, n_points), "stroke outline")
