"""How well a chain of links samples an outline.

A link of length ``l`` samples the outline at spatial frequency ``1 / l``:
detail finer than about ``2 l`` is lost. These functions measure that loss on
actual wraps, and find link lengths that keep it small or close a lap exactly.
"""

from __future__ import annotations

import numpy as np
import shapely

from .._typing import ArrayLike
from .._validation import MAX_POINTS, check_laps, check_positive_float, check_positive_int
from ..errors import InputError
from ..shapes import as_outline
from ._api import MAX_LINKS, wrap, wrap_many
from ._surface import outline_diameter

__all__ = ["capture_error", "closing_link_length", "link_length_for_laps", "max_link_length"]

#: Most links :func:`capture_error` puts on one lap.
MAX_LINKS_PER_LAP = 1_000_000


def capture_error(
    outline: ArrayLike,
    link_length: float,
    *,
    starts: ArrayLike = (0.0,),
    mode: str = "taut",
) -> float:
    """Hausdorff distance between one lap of the chain and the outline, per diameter.

    Parameters
    ----------
    outline : array_like of shape (n_points, 2)
    link_length : float
    starts : array_like of float, default=(0.0,)
        Start points (fractions of the perimeter); the error is averaged over them.
    mode : {"taut", "hug"}, default="taut"

    Returns
    -------
    error : float
        Mean over ``starts`` of ``hausdorff(chain polygon, outline) / diameter``,
        the chain polygon being the joints of the first lap.

    Examples
    --------
    >>> from tentaclass.shapes import square, circle
    >>> capture_error(square(4), 1.0)  # joints on the corners: exact
    0.0
    >>> round(capture_error(circle(1.0, 720), 0.5), 4)  # sagitta 1 - cos(asin(1/4)), per 2
    0.0159
    """
    p = as_outline(outline)
    ln = check_positive_float(link_length, "link_length")
    st = np.atleast_1d(np.asarray(starts, float))
    per = float(np.sum(np.hypot(*(np.roll(p, -1, axis=0) - p).T)))
    if not per / ln <= MAX_LINKS_PER_LAP:
        raise InputError(
            f"link_length {link_length!r} is too short for this outline: one lap would take "
            f"{per / ln:.3g} links (at most {MAX_LINKS_PER_LAP:,})"
        )
    n = int(np.ceil(per / ln)) + 2
    batch = wrap_many(p, n, ln, starts=st, mode=mode)
    ring = shapely.LinearRing(p)
    diameter = outline_diameter(p)
    errors = []
    for i in range(len(st)):
        w = batch[i]
        joints = w.joints[(w.lap >= -1) & (np.maximum.accumulate(w.lap) <= 0)]
        if len(joints) < 3:
            joints = w.joints
        chain = _chain_geometry(joints)
        errors.append(shapely.hausdorff_distance(chain, ring) / diameter)
    return float(np.mean(errors))


def _chain_geometry(joints: np.ndarray) -> shapely.Geometry:
    """The joints as a ring, a line or a point, whichever they can form."""
    distinct = np.unique(joints, axis=0)
    if len(distinct) >= 3:
        return shapely.LinearRing(joints)
    if len(distinct) == 2:
        return shapely.LineString(distinct)
    return shapely.Point(distinct[0])


def max_link_length(
    outline: ArrayLike,
    tolerance: float,
    *,
    starts: ArrayLike = (0.0,),
    mode: str = "taut",
    n_grid: int = 64,
) -> float:
    """Largest link length whose capture error, and every shorter one's, stays within ``tolerance``.

    Scans ``n_grid`` link lengths geometrically spaced from diameter / 1000 to the
    diameter and returns the last one before the first that exceeds the
    tolerance (the error is not monotone: a square's corners are hit exactly
    at ``a/2``, ``a/4``, ...).

    Examples
    --------
    >>> from tentaclass.shapes import circle
    >>> l = max_link_length(circle(1.0, 720), 0.02)
    >>> 0.4 < l < 0.7
    True
    """
    p = as_outline(outline)
    tol = check_positive_float(tolerance, "tolerance")
    n_grid = check_positive_int(n_grid, "n_grid", minimum=2, maximum=MAX_POINTS)
    d = outline_diameter(p)
    grid = np.geomspace(d / 1000, d, n_grid)
    best = None
    for ln in grid:
        if capture_error(p, ln, starts=starts, mode=mode) > tol:
            break
        best = float(ln)
    if best is None:
        raise InputError(f"no link length down to {grid[0]:g} keeps the capture error <= {tol}")
    return best


def closing_link_length(
    outline: ArrayLike,
    n_links: int,
    *,
    start: float = 0.0,
    direction: str = "ccw",
    mode: str = "taut",
    rtol: float = 1e-12,
) -> tuple[float, float]:
    """Link length with which ``n_links`` links wrap exactly one lap, by bisection.

    Returns ``(link_length, gap)``: ``gap`` is the distance between the last
    joint and the first (0 for a closed chain). The walk can jump when a longer
    link bridges a protrusion; the bisection then stops at the jump and the
    gap says how far from closed the chain is.

    Examples
    --------
    >>> from tentaclass.shapes import square
    >>> l, gap = closing_link_length(square(4), 16)
    >>> round(l, 9), round(gap, 9)
    (1.0, 0.0)
    """
    p = as_outline(outline)
    n = check_positive_int(n_links, "n_links", minimum=2)
    rtol = check_positive_float(rtol, "rtol", allow_zero=True)
    per = float(np.sum(np.hypot(*(np.roll(p, -1, axis=0) - p).T)))
    d = outline_diameter(p)

    def laps(ln: float) -> float:
        # 1 once the chain has reached its start point again along the support
        w = wrap(p, n, ln, start=start, direction=direction, mode=mode)
        closed = np.hypot(*(w.joints[-1] - w.start_point)) <= 1e-9 * d
        return 1.0 if closed or w.lap.max() >= 1 else 0.0

    # n links of length l advance about n * l along the support: about 1 lap at P / n.
    # Chords are shorter than the arcs they span (much so on wobbly outlines), so
    # the upper bound grows until the chain closes, up to the diameter.
    hi = min(1.001 * per / n, d)
    lo = per / (4 * n)
    while laps(hi) < 1:
        if hi >= d:
            raise InputError(f"{n} links cannot wrap this outline once (too few links)")
        lo, hi = hi, min(1.1 * hi, d)
    while laps(lo) >= 1 and lo > 1e-9 * d:
        lo /= 2
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if laps(mid) >= 1 - 1e-12:
            hi = mid
        else:
            lo = mid
        if hi - lo <= rtol * hi:
            break
    w = wrap(p, n, hi, start=start, direction=direction, mode=mode)
    return hi, float(np.hypot(*(w.joints[-1] - w.joints[0])))


def link_length_for_laps(
    outline: ArrayLike,
    n_links: int,
    laps: float,
    *,
    start: float = 0.0,
    direction: str = "ccw",
    mode: str = "taut",
    offset: float = 0.0,
) -> float:
    """Link length with which ``n_links`` links wrap about ``laps`` laps after the approach.

    ``(n_links - approach) / laps`` links close one lap (:func:`closing_link_length`);
    with a stand-off the approach takes ``ceil(offset / l)`` links, so the length
    is found twice.

    Parameters
    ----------
    outline : array_like of shape (n_points, 2)
    n_links : int
    laps : float
        Laps to wrap, > 0; at most ``n_links / 2`` (two links per lap).
    start, direction, mode, offset
        As in :func:`tentaclass.wrap`.

    Returns
    -------
    link_length : float

    Examples
    --------
    >>> from tentaclass.shapes import square
    >>> round(link_length_for_laps(square(4), 32, 2.0), 9)
    1.0
    """
    n = check_positive_int(n_links, "n_links", minimum=2)
    laps = check_positive_float(laps, "laps")
    check_laps(laps, n)
    offset = check_positive_float(offset, "offset", allow_zero=True)

    if n / laps > MAX_LINKS:
        raise InputError(
            f"laps {laps:g} is too small for {n} links: one lap would take {n / laps:.4g} links "
            f"(at most {MAX_LINKS:,}; use laps >= {n / MAX_LINKS:.4g})"
        )

    def closing(links_per_lap: float) -> float:
        n_lap = max(2, round(links_per_lap))
        return closing_link_length(outline, n_lap, start=start, direction=direction, mode=mode)[0]

    ln = closing(n / laps)
    if offset > 0:
        wrapping = n - int(np.ceil(offset / ln))
        ln = closing(wrapping / laps)
    return ln
