"""Compiled helpers for the per-object measurements of the scanner.

Small objects pass at thousands per second; building a shapely geometry from
a point set, or calling scipy.ndimage on a 15 x 15 mask, costs more in call
overhead than the work itself. These kernels do that work directly:

- :func:`hull_ring`: convex hull of points (Andrew's monotone chain), as the
  closed ring GEOS would return (clockwise, starting at the lowest point,
  then the leftmost; collinear points dropped), so that shapely's results
  and everything measured on the ring stay the same;
- :func:`max_distance_outside`: the largest distance of points from a convex
  polygon (0 inside), and :func:`reaches_beyond`: whether it exceeds a limit;
- :func:`fill_holes`: :func:`scipy.ndimage.binary_fill_holes` (background
  4-connected to the border stays background);
- :func:`mask_hull`: :func:`hull_ring` of a mask's pixel squares or centres;
- :func:`opening_cross`: :func:`scipy.ndimage.binary_opening` with the 3 x 3
  cross.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np

from .._geos import point_segment_distance as _point_segment_distance
from .._jit import plain_calls

_OPTS = {"cache": True, "nogil": True}


@nb.njit(**_OPTS)
def _cross(ox, oy, ax, ay, bx, by):
    return (ax - ox) * (by - oy) - (ay - oy) * (bx - ox)


@nb.njit(**_OPTS)
def _monotone_chain(a, b):
    """Andrew's monotone chain over points sorted by ``a``, then ``b``, without duplicates.

    Returns the hull's vertices ``(ha[:k], hb[:k])``, counter-clockwise in the
    ``(a, b)`` frame, collinear points dropped; ``k < 3`` if all are collinear.
    """
    m = a.shape[0]
    ha = np.empty(2 * m + 1)
    hb = np.empty(2 * m + 1)
    return ha, hb, _chain_into(a, b, m, ha, hb)


@nb.njit(**_OPTS)
def _chain_into(a, b, m, ha, hb):
    """:func:`_monotone_chain` of the first ``m`` points into ``ha``, ``hb`` (``2 m + 1`` each)."""
    k = 0
    for i in range(m):  # lower hull
        while k >= 2 and _cross(ha[k - 2], hb[k - 2], ha[k - 1], hb[k - 1], a[i], b[i]) <= 0:
            k -= 1
        ha[k] = a[i]
        hb[k] = b[i]
        k += 1
    lo = k + 1
    for i in range(m - 2, -1, -1):  # upper hull
        while k >= lo and _cross(ha[k - 2], hb[k - 2], ha[k - 1], hb[k - 1], a[i], b[i]) <= 0:
            k -= 1
        ha[k] = a[i]
        hb[k] = b[i]
        k += 1
    return k - 1  # (the last point repeats the first)


@nb.njit(**_OPTS)
def hull_ring(x, y):
    """Closed hull ring ``(m + 1, 2)`` of the points ``(x, y)`` in GEOS's order.

    Fewer than 3 hull vertices (all points collinear) give the distinct
    extreme points only (1 or 2 rows, not closed).
    """
    n = x.shape[0]
    by_y = np.argsort(y, kind="mergesort")
    order = by_y[np.argsort(x[by_y], kind="mergesort")]  # by x, then y
    xs = x[order]
    ys = y[order]
    # drop duplicates
    ux = np.empty(n)
    uy = np.empty(n)
    m = 0
    for i in range(n):
        if m == 0 or xs[i] != ux[m - 1] or ys[i] != uy[m - 1]:
            ux[m] = xs[i]
            uy[m] = ys[i]
            m += 1
    if m < 3:
        out = np.empty((m, 2))
        for i in range(m):
            out[i, 0] = ux[i]
            out[i, 1] = uy[i]
        return out
    hx, hy, k = _monotone_chain(ux[:m], uy[:m])  # hx[:k] is counter-clockwise
    if k < 3:
        out = np.empty((2, 2))
        out[0, 0], out[0, 1] = ux[0], uy[0]
        out[1, 0], out[1, 1] = ux[m - 1], uy[m - 1]
        return out
    start = 0
    for i in range(1, k):
        if hy[i] < hy[start] or (hy[i] == hy[start] and hx[i] < hx[start]):
            start = i
    out = np.empty((k + 1, 2))
    for j in range(k + 1):  # clockwise from the start: walk the ccw ring backwards
        i = (start - j) % k
        out[j, 0] = hx[i]
        out[j, 1] = hy[i]
    return out


@nb.njit(**_OPTS)
def _edge_distance(ring, i, x, y):
    """Distance of the point ``(x, y)`` from the segment ``ring[i]``-``ring[i + 1]``."""
    ax, ay = ring[i, 0], ring[i, 1]
    bx, by = ring[i + 1, 0], ring[i + 1, 1]
    dx, dy = bx - ax, by - ay
    ll = dx * dx + dy * dy
    t = 0.0 if ll == 0 else ((x - ax) * dx + (y - ay) * dy) / ll
    t = min(1.0, max(0.0, t))
    ex, ey = ax + t * dx - x, ay + t * dy - y
    return np.sqrt(ex * ex + ey * ey)


@nb.njit(**_OPTS)
def max_distance_outside(ring, px, py):
    """Largest distance of the points from the convex polygon ``ring`` (closed, clockwise)."""
    worst = 0.0
    n = ring.shape[0] - 1
    for p in range(px.shape[0]):
        x, y = px[p], py[p]
        inside = True
        best = np.inf
        for i in range(n):
            if _cross(ring[i, 0], ring[i, 1], ring[i + 1, 0], ring[i + 1, 1], x, y) > 0:
                inside = False  # left of a clockwise edge: outside
            best = min(best, _edge_distance(ring, i, x, y))
        if not inside and best > worst:
            worst = best
    return worst


@nb.njit(**_OPTS)
def reaches_beyond(ring, px, py, limit):
    """Whether :func:`max_distance_outside` of the points exceeds ``limit`` (>= 0).

    The same distances, in the same order, but a point inside the polygon
    is not measured, a point stops once some edge is within ``limit``, and
    the first point beyond it answers.
    """
    n = ring.shape[0] - 1
    for p in range(px.shape[0]):
        x, y = px[p], py[p]
        inside = True
        for i in range(n):
            if _cross(ring[i, 0], ring[i, 1], ring[i + 1, 0], ring[i + 1, 1], x, y) > 0:
                inside = False
                break
        if inside:
            continue
        best = np.inf
        for i in range(n):
            best = min(best, _edge_distance(ring, i, x, y))
            if best <= limit:
                break
        if best > limit:
            return True
    return False


@nb.njit(**_OPTS)
def _fill_holes_into(mask, out, stack):
    """:func:`fill_holes` written into ``out`` (same shape); ``stack``: ``(2, n)``, n >= pixels."""
    h, w = mask.shape
    out[:] = True  # False: background reached from the border
    top = 0
    for k in range(2 * (h + w)):  # the border: left, right, top and bottom edges
        if k < 2 * h:
            r, c = k % h, 0 if k < h else w - 1
        else:
            r, c = 0 if k < 2 * h + w else h - 1, (k - 2 * h) % w
        if not mask[r, c] and out[r, c]:
            out[r, c] = False
            stack[0, top] = r
            stack[1, top] = c
            top += 1
    while top > 0:
        top -= 1
        r, c = stack[0, top], stack[1, top]
        for dr, dc in ((-1, 0), (1, 0), (0, -1), (0, 1)):
            rr, cc = r + dr, c + dc
            if 0 <= rr < h and 0 <= cc < w and not mask[rr, cc] and out[rr, cc]:
                out[rr, cc] = False
                stack[0, top] = rr
                stack[1, top] = cc
                top += 1


@nb.njit(**_OPTS)
def fill_holes(mask):
    """``mask`` with every background region not 4-connected to the border filled."""
    out = np.empty(mask.shape, dtype=np.bool_)
    _fill_holes_into(mask, out, np.empty((2, mask.size), dtype=np.int64))
    return out


@nb.njit(**_OPTS)
def _mask_points(mask, corners):
    """The points :func:`mask_hull` takes the hull of: each row's first and last pixel."""
    h, w = mask.shape
    x = np.empty(4 * h)
    y = np.empty(4 * h)
    n = 0
    for r in range(h):
        first = -1
        last = -1
        for c in range(w):
            if mask[r, c]:
                if first < 0:
                    first = c
                last = c
        if first < 0:
            continue
        if corners:
            for dy in (-0.5, 0.5):
                x[n], y[n] = first - 0.5, r + dy
                x[n + 1], y[n + 1] = last + 0.5, r + dy
                n += 2
        else:
            x[n], y[n] = first, r
            x[n + 1], y[n + 1] = last, r
            n += 2
    return x[:n], y[:n]


@nb.njit(**_OPTS)
def mask_hull(mask, corners):
    """:func:`hull_ring` of the pixel squares' corners (or centres) of a mask.

    Only the first and last pixel of each row can be hull vertices, and of
    the points on one line ``y = const`` only the leftmost and the rightmost:
    these come sorted by ``y`` then ``x`` from a pass over the rows, so the
    monotone chain runs along ``y`` without sorting. The hull's vertices are
    the same (the extreme points, exact in half pixels), given in GEOS's
    order; collinear points (a line or a point: no polygon) go to
    :func:`hull_ring`.
    """
    scratch = _hull_scratch(mask.shape[0])
    out = np.empty((2 * mask.shape[0] + 3, 2))
    k = _mask_hull_into(mask, corners, scratch, out, 0)
    if k < 0:
        x, y = _mask_points(mask, corners)
        return hull_ring(x, y)
    return out[:k].copy()


@nb.njit(**_OPTS)
def _hull_scratch(h):
    """Scratch of :func:`_mask_hull_into` for masks of up to ``h`` rows."""
    return np.empty((6, 4 * h + 5))


@nb.njit(**_OPTS)
def _mask_hull_into(mask, corners, scratch, out, k0):
    """:func:`mask_hull` written at ``out[k0:]`` (room for ``2 h + 3`` rows); returns its end.

    ``scratch`` from :func:`_hull_scratch`. Returns -1 (nothing written) when
    the points are collinear: :func:`mask_hull` then goes to :func:`hull_ring`.
    """
    _row_ends(mask, scratch)
    return _ends_hull_into(mask.shape[0], corners, scratch, out, k0)


@nb.njit(**_OPTS)
def _row_ends(mask, scratch):
    """The first and last pixel's column of each row of ``mask`` (-1: none) in ``scratch[:2]``."""
    h, w = mask.shape
    first = scratch[0]
    last = scratch[1]
    for r in range(h):
        first[r] = -1.0
        last[r] = -1.0
        for c in range(w):
            if mask[r, c]:
                if first[r] < 0:
                    first[r] = c
                last[r] = c


@nb.njit(**_OPTS)
def _ends_hull_into(h, corners, scratch, out, k0):
    """:func:`_mask_hull_into` of a mask of ``h`` rows from its :func:`_row_ends`."""
    first = scratch[0]
    last = scratch[1]
    # the levels y = const, bottom up, each with its leftmost and rightmost point
    px = scratch[2]
    py = scratch[3]
    n = 0
    for k in range(h + 1 if corners else h):
        lo = np.inf
        hi = -np.inf
        if corners:
            for r in (k - 1, k):  # the row below ends and the row above starts at y = k - 0.5
                if 0 <= r < h and first[r] >= 0:
                    lo = min(lo, first[r] - 0.5)
                    hi = max(hi, last[r] + 0.5)
            level = k - 0.5
        else:
            if first[k] >= 0:
                lo, hi = first[k], last[k]
            level = float(k)
        if lo > hi:
            continue
        px[n], py[n] = lo, level
        n += 1
        if hi != lo:
            px[n], py[n] = hi, level
            n += 1
    # the monotone chain with y as the sort axis: counter-clockwise with x and y swapped
    hy = scratch[4]
    hx = scratch[5]
    k = _chain_into(py, px, n, hy, hx)
    if k < 3:
        return -1
    start = 0
    for i in range(1, k):
        if hy[i] < hy[start] or (hy[i] == hy[start] and hx[i] < hx[start]):
            start = i
    i = start
    for j in range(k + 1):  # clockwise with x and y as they are: walk forwards
        out[k0 + j, 0] = hx[i]
        out[k0 + j, 1] = hy[i]
        i = i + 1 if i < k - 1 else 0
    return k0 + k + 1


@nb.njit(**_OPTS)
def opening_cross(mask):
    """:func:`scipy.ndimage.binary_opening` with the 3 x 3 cross (outside = 0)."""
    h, w = mask.shape
    eroded = np.zeros((h, w), dtype=np.bool_)
    for r in range(1, h - 1):
        for c in range(1, w - 1):
            eroded[r, c] = mask[r, c] and mask[r - 1, c] and mask[r + 1, c]
            eroded[r, c] = eroded[r, c] and mask[r, c - 1] and mask[r, c + 1]
    out = np.zeros((h, w), dtype=np.bool_)
    for r in range(h):
        for c in range(w):
            if eroded[r, c]:
                out[r, c] = True
                if r > 0:
                    out[r - 1, c] = True
                if r < h - 1:
                    out[r + 1, c] = True
                if c > 0:
                    out[r, c - 1] = True
                if c < w - 1:
                    out[r, c + 1] = True
    return out


@nb.njit(**_OPTS)
def label_runs(region, eight):
    """Connected groups of ``region`` as :func:`scipy.ndimage.label` numbers them.

    Groups are numbered in the raster order of their first pixel, and each
    group's pixels listed in raster order (as :func:`scipy.ndimage.value_indices`
    gives them). Returns ``rr``, ``cc`` (all pixels, group after group) and the
    ``starts`` of the groups in them (``n_groups + 1``).
    """
    h, w = region.shape
    size = h * w
    lab = np.empty(5 * size, dtype=np.int64)
    stack = np.empty(size, dtype=np.int64)
    rows = np.empty(size, dtype=np.int64)
    cols = np.empty(size, dtype=np.int64)
    starts = np.empty(size + 1, dtype=np.int64)
    n, total = _label_runs_into(region, eight, lab, stack, rows, cols, starts)
    return rows[:total].copy(), cols[:total].copy(), starts[: n + 1].copy()


@nb.njit(**_OPTS)
def _root(parent, k):
    """The root of run ``k`` (path halving)."""
    while parent[k] != k:
        parent[k] = parent[parent[k]]
        k = parent[k]
    return k


@nb.njit(**_OPTS)
def _label_runs_into(region, eight, work, pos, rows, cols, starts):
    """:func:`label_runs` into scratch (``work``: 5 per pixel, the others 1, ``starts`` 1 more).

    The runs of each row are joined to the runs they touch in the row above
    (a union-find whose root is a group's first run, so groups come in the
    raster order of their first pixel); each group's pixels are then listed
    run after run. Returns the number of groups and of their pixels: the
    groups' pixels are ``rows[:total]``, ``cols[:total]``, their starts
    ``starts[:n + 1]``.
    """
    h, w = region.shape
    most = h * ((w + 1) // 2)  # runs at most
    first = work[:most]  # each run's first column, end column, row, root and group
    end = work[most : 2 * most]
    row_of = work[2 * most : 3 * most]
    parent = work[3 * most : 4 * most]
    group = work[4 * most : 5 * most]
    touch = 0 if eight else 1  # runs touch when one starts before the other ends (+ 1)
    nr = 0
    above = 0  # the runs of the row above: [above, here)
    for r in range(h):
        here = nr
        c = 0
        while c < w:
            if not region[r, c]:
                c += 1
                continue
            a = c
            while c < w and region[r, c]:
                c += 1
            first[nr], end[nr], row_of[nr], parent[nr] = a, c, r, nr
            nr += 1
        i, j = above, here
        while i < here and j < nr:
            if first[i] + touch <= end[j] and first[j] + touch <= end[i]:
                ri, rj = _root(parent, i), _root(parent, j)
                if ri < rj:
                    parent[rj] = ri
                elif rj < ri:
                    parent[ri] = rj
            if end[i] < end[j]:
                i += 1
            else:
                j += 1
        above = here
    n = 0
    for k in range(nr):
        root = _root(parent, k)
        if root == k:
            group[k] = n
            n += 1
        else:
            group[k] = group[root]
    starts[: n + 1] = 0
    for k in range(nr):
        starts[group[k] + 1] += end[k] - first[k]
    for g in range(n):
        starts[g + 1] += starts[g]
        pos[g] = starts[g]
    for k in range(nr):
        g = group[k]
        at = pos[g]
        for c in range(first[k], end[k]):
            rows[at] = row_of[k]
            cols[at] = c
            at += 1
        pos[g] = at
    return n, starts[n]


def row_extremes(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Rows holding pixels, and the first and last pixel's column in each."""
    rows = np.flatnonzero(mask.any(axis=1))
    sub = mask[rows]
    first = sub.argmax(axis=1)
    last = mask.shape[1] - 1 - sub[:, ::-1].argmax(axis=1)
    return rows, first, last


# -- batches: masks concatenated in one flat buffer ---------------------------------------------
# Object i's mask is ``flat[starts[i]:starts[i] + heights[i] * widths[i]]`` (C order).


@nb.njit(**_OPTS)
def _mask_of(flat, starts, heights, widths, i):
    return flat[starts[i] : starts[i] + heights[i] * widths[i]].reshape((heights[i], widths[i]))


@nb.njit(**_OPTS)
def hulls_batch(flat, starts, heights, widths, corners):
    """:func:`mask_hull` of every mask: ragged ``(coords, ring_starts)``."""
    n = heights.shape[0]
    cap = 0
    for i in range(n):
        cap += 8 * heights[i] + 2
    coords = np.empty((cap, 2))
    ring_starts = np.zeros(n + 1, dtype=np.int64)
    scratch = _hull_scratch(heights.max() if n else 0)
    k = 0
    for i in range(n):
        mask = _mask_of(flat, starts, heights, widths, i)
        end = _mask_hull_into(mask, corners, scratch, coords, k)
        if end < 0:  # collinear points
            ring = mask_hull(mask, corners)
            end = k + ring.shape[0]
            coords[k:end] = ring
        k = end
        ring_starts[i + 1] = k
    return coords[:k], ring_starts


@nb.njit(**_OPTS)
def measure_batch(flat, starts, heights, widths):
    """Filled masks (flat, as ``flat``), hull rings, areas and row/column sums.

    The hull rings of the pixel squares and of the pixel centres
    (:func:`hulls_batch` of each), from the same pass over each mask's rows
    as its area; those of the filled masks are the same. A mask whose rows
    are each one run is its own filled mask (every gap reaches the border
    along its row).
    """
    n = heights.shape[0]
    filled = np.empty(flat.shape[0], dtype=np.bool_)
    area = np.zeros(n, dtype=np.int64)
    sums = np.zeros((n, 2))
    biggest = 0
    for i in range(n):
        biggest = max(biggest, heights[i] * widths[i])
    stack = np.empty((2, biggest), dtype=np.int64)
    cap = 0
    for i in range(n):
        cap += 8 * heights[i] + 2
    coords = np.empty((cap, 2))
    centres = np.empty((cap, 2))
    ring_starts = np.zeros(n + 1, dtype=np.int64)
    centre_starts = np.zeros(n + 1, dtype=np.int64)
    scratch = _hull_scratch(heights.max() if n else 0)
    k = 0
    q = 0
    for i in range(n):
        m = _mask_of(flat, starts, heights, widths, i)
        a = 0
        sr = 0
        sc = 0
        spans = 0  # the pixels from each row's first to its last
        for r in range(m.shape[0]):
            first = -1
            last = -1
            for c in range(m.shape[1]):
                if m[r, c]:
                    a += 1
                    sr += r
                    sc += c
                    if first < 0:
                        first = c
                    last = c
            if first >= 0:
                spans += last - first + 1
            scratch[0, r] = first  # the row's ends, as _row_ends gives them
            scratch[1, r] = last
        k, q = _both_hulls_into(m, scratch, coords, k, centres, q)
        ring_starts[i + 1] = k
        centre_starts[i + 1] = q
        area[i] = a
        sums[i, 0] = sr
        sums[i, 1] = sc
        out = _mask_of(filled, starts, heights, widths, i)
        if spans == a:  # each row one run: every gap reaches the border along its row
            out[:] = m
        else:
            _fill_holes_into(m, out, stack)
    return filled, coords[:k], ring_starts, area, sums, centres[:q], centre_starts


@nb.njit(**_OPTS)
def _both_hulls_into(mask, scratch, coords, k, centres, q):
    """The hulls of a mask's pixel squares at ``coords[k:]`` and centres at ``centres[q:]``.

    ``scratch`` from :func:`_hull_scratch` holds the mask's :func:`_row_ends`.
    Returns the ends of the two rings written.
    """
    for corners in (True, False):
        at = k if corners else q
        into = coords if corners else centres
        end = _ends_hull_into(mask.shape[0], corners, scratch, into, at)
        if end < 0:  # collinear points
            ring = mask_hull(mask, corners)
            end = at + ring.shape[0]
            into[at:end] = ring
        if corners:
            k = end
        else:
            q = end
    return k, q


@nb.njit(**_OPTS)
def rectangle_sides(corners):
    """Long and short side of each rectangle ``(n, 5, 2)``, and the long side as a vector.

    Of the first two sides (from corner 0 to 1, and 1 to 2) the first is the
    long one when the lengths tie.
    """
    n = corners.shape[0]
    long = np.empty(n)
    short = np.empty(n)
    edge = np.empty((n, 2))
    for i in range(n):
        ax = corners[i, 1, 0] - corners[i, 0, 0]
        ay = corners[i, 1, 1] - corners[i, 0, 1]
        bx = corners[i, 2, 0] - corners[i, 1, 0]
        by = corners[i, 2, 1] - corners[i, 1, 1]
        l1 = np.hypot(ax, ay)
        l2 = np.hypot(bx, by)
        if l1 >= l2:
            long[i], short[i], edge[i, 0], edge[i, 1] = l1, l2, ax, ay
        else:
            long[i], short[i], edge[i, 0], edge[i, 1] = l2, l1, bx, by
    return long, short, edge


@nb.njit(**_OPTS)
def _simplify_ring(ring, tolerance, out, k0, stack, kept):
    """:func:`simplify_rings` of one closed ring of at least 4 points, written at ``out[k0:]``.

    ``stack`` ``(3, m)`` and ``kept`` ``(m,)`` are scratch for a ring of ``m``
    points. Returns the end of the ring written.
    """
    m = ring.shape[0]
    n_kept = 0  # segments kept so far: kept[s] is the start of segment s
    stack[0, 0], stack[1, 0], stack[2, 0] = 0, m - 1, 0
    top = 1
    while top:
        top -= 1
        i, j, depth = stack[0, top], stack[1, top], stack[2, top] + 1
        if i + 1 == j:
            kept[n_kept] = i
            n_kept += 1
            continue
        valid = True
        size = n_kept + 1 if n_kept else 0
        if size < 4 and depth + 1 < 4:  # the ring could end up with too few points
            valid = False
        far = -1.0
        index = i
        for k in range(i + 1, j):
            d = _point_segment_distance(
                ring[k, 0], ring[k, 1], ring[i, 0], ring[i, 1], ring[j, 0], ring[j, 1]
            )
            if d > far:
                far = d
                index = k
        if far > tolerance:
            valid = False
        if valid:
            kept[n_kept] = i
            n_kept += 1
            continue
        # both halves, the first on top
        stack[0, top], stack[1, top], stack[2, top] = index, j, depth
        stack[0, top + 1], stack[1, top + 1], stack[2, top + 1] = i, index, depth
        top += 2
    if n_kept + 1 > 4:  # the ring's endpoint goes too when its neighbours' chord is near
        a, b, e = kept[n_kept - 1], kept[1], kept[0]
        if (
            _point_segment_distance(ring[e, 0], ring[e, 1], ring[a, 0], ring[a, 1],
                                    ring[b, 0], ring[b, 1])
            <= tolerance
        ):  # fmt: skip
            kept[0] = a
            n_kept -= 1
    for s in range(n_kept):
        out[k0 + s, 0], out[k0 + s, 1] = ring[kept[s], 0], ring[kept[s], 1]
    out[k0 + n_kept, 0], out[k0 + n_kept, 1] = out[k0, 0], out[k0, 1]
    return k0 + n_kept + 1


@nb.njit(**_OPTS)
def simplify_rings(coords, starts, tolerance):
    """:func:`shapely.simplify` of convex polygons' rings, the same coordinates.

    The rings (closed, one after the other; at least 4 points each) are
    simplified as GEOS's topology-preserving simplifier does a polygon's
    shell: Douglas-Peucker, where a section is flattened only when no point
    lies farther than ``tolerance`` from its chord and the ring cannot fall
    below 4 points, then the ring's endpoint dropped when the chord of its
    neighbours passes within ``tolerance`` of it (the ring then starts at the
    last point kept). The simplifier's topology checks never fail on a
    convex ring (its chords cross no edge), so they are left out. Returns
    the simplified rings (closed, one after the other) and their starts.
    """
    n = starts.shape[0] - 1
    out = np.empty((coords.shape[0], 2))
    out_starts = np.zeros(n + 1, dtype=np.int64)
    longest = 1
    for i in range(n):
        longest = max(longest, starts[i + 1] - starts[i])
    stack = np.empty((3, longest + 1), dtype=np.int64)
    kept = np.empty(longest, dtype=np.int64)
    k = 0
    for i in range(n):
        k = _simplify_ring(coords[starts[i] : starts[i + 1]], tolerance, out, k, stack, kept)
        out_starts[i + 1] = k
    return out[:k], out_starts


@nb.njit(**_OPTS)
def hull_edges(coords, starts):
    """Outward unit normals, offsets and lengths of the edges of simplified hull rings.

    Ring ``i`` is ``coords[starts[i]:starts[i + 1]]`` as shapely gives a
    polygon's (closed; fewer than 4 points: a point or a line, kept as it
    is); a clockwise ring is taken counter-clockwise
    (:func:`shapely.orient_polygons`). Each edge longer than 1e-9 gives its
    normal ``(dy, -dx) / length`` (outward), its line's offset ``c =
    normal . start`` and its length; ``edge_starts[i]`` is where ring ``i``'s
    edges begin (numpy's arithmetic, the same bits).
    """
    n = starts.shape[0] - 1
    normal = np.empty((coords.shape[0], 2))
    c = np.empty(coords.shape[0])
    length = np.empty(coords.shape[0])
    edge_starts = np.zeros(n + 1, dtype=np.int64)
    e = 0
    for i in range(n):
        a, b = starts[i], starts[i + 1]
        flip = b - a >= 4 and not _is_ccw(coords[a:b])
        for k in range(b - a - 1):
            j0, j1 = (b - 1 - k, b - 2 - k) if flip else (a + k, a + k + 1)
            px, py = coords[j0, 0], coords[j0, 1]
            dx, dy = coords[j1, 0] - px, coords[j1, 1] - py
            if np.hypot(dx, dy) > 1e-9:
                nx, ny = dy, -dx
                size = np.hypot(nx, ny)
                nx /= size
                ny /= size
                normal[e, 0], normal[e, 1] = nx, ny
                c[e] = nx * px + ny * py
                length[e] = size
                e += 1
        edge_starts[i + 1] = e
    return normal[:e], c[:e], length[:e], edge_starts


@nb.njit(**_OPTS)
def _remainder(a, b):
    """``numpy.remainder(a, b)`` of floats (the sign of ``b``), as numpy computes it."""
    m = np.fmod(a, b)
    if m != 0:
        if (b < 0) != (m < 0):
            m += b
    else:
        m = 0.0 if b > 0 else -0.0
    return m


@nb.njit(**_OPTS)
def _unwrap_correction(dd):
    """What :func:`numpy.unwrap` adds after a step ``dd`` between two angles (its arithmetic)."""
    if abs(dd) < np.pi:
        return 0.0
    ddmod = _remainder(dd + np.pi, 2 * np.pi) - np.pi
    if ddmod == -np.pi and dd > 0:
        ddmod = np.pi
    return ddmod - dd


@nb.njit(**_OPTS)
def triangle_search(normal, c, theta, length, starts):
    """Smallest triangle on hull edge lines for each ragged group of edges.

    ``theta`` are the edge normals' angles, unwrapped here within each group
    as :func:`numpy.unwrap` does; the 12 longest edges of each group are
    searched. Returns ``found`` (False where no triple qualifies) and the
    triangles ``(n, 3, 2)``.
    """
    n = starts.shape[0] - 1
    found = np.zeros(n, dtype=np.bool_)
    tris = np.zeros((n, 3, 2))
    for i in range(n):
        a, b = starts[i], starts[i + 1]
        m = b - a
        if m < 3:
            continue
        up = np.empty(m)
        up[0] = theta[a]
        s = 0.0
        for k in range(1, m):
            s += _unwrap_correction(theta[a + k] - theta[a + k - 1])
            up[k] = theta[a + k] + s
        order = np.argsort(-length[a:b], kind="mergesort")
        top = np.sort(order[: min(12, m)])
        k, tri = _best_triangle(normal[a:b][top], c[a:b][top], up[top])
        if k >= 0:
            found[i] = True
            tris[i] = tri
    return found, tris


@nb.njit(**_OPTS)
def _meet(normal, c, i, j):
    """Where the lines ``normal[i] . p = c[i]`` and ``normal[j] . p = c[j]`` cross."""
    det = normal[i, 0] * normal[j, 1] - normal[i, 1] * normal[j, 0]
    x = (c[i] * normal[j, 1] - c[j] * normal[i, 1]) / det
    y = (normal[i, 0] * c[j] - normal[j, 0] * c[i]) / det
    return x, y


@nb.njit(**_OPTS)
def _best_triangle(normal, c, theta):
    """Smallest triangle on three of the lines whose normals span less than pi each.

    Triples are tried in lexicographic order and the first smallest kept;
    returns its index (-1 if no triple qualifies) and vertices.
    """
    m = c.shape[0]
    best = np.inf
    k = -1
    n = 0
    tri = np.zeros((3, 2))
    for i in range(m):
        for j in range(i + 1, m):
            for q in range(j + 1, m):
                if not (
                    theta[j] - theta[i] < np.pi - 1e-6
                    and theta[q] - theta[j] < np.pi - 1e-6
                    and 2 * np.pi - (theta[q] - theta[i]) < np.pi - 1e-6
                ):
                    continue
                ax, ay = _meet(normal, c, i, j)
                bx, by = _meet(normal, c, j, q)
                vx, vy = _meet(normal, c, q, i)
                area = 0.5 * np.abs((bx - ax) * (vy - ay) - (by - ay) * (vx - ax))
                if area < best:
                    best, k = area, n
                    tri[0, 0], tri[0, 1] = ax, ay
                    tri[1, 0], tri[1, 1] = bx, by
                    tri[2, 0], tri[2, 1] = vx, vy
                n += 1
    return k, tri


# codes of the groups defect_groups reports
HOLE, TRUNCATED, BROKEN_CORNER, BITE, BURR = range(5)


@nb.njit(**_OPTS)
def _circle_radius(ring, circle):
    """Radius of the circle centred at ``circle`` through the farthest point of ``ring``."""
    r = -np.inf
    for k in range(ring.shape[0]):
        r = max(r, np.hypot(ring[k, 0] - circle[0], ring[k, 1] - circle[1]))
    return r


@nb.njit(**_OPTS)
def _circle_distance(r, circle, row, col):
    """Signed distance of the point ``(row, col)`` to the circle (> 0 inside)."""
    return r - np.hypot(col - circle[0], row - circle[1])


@nb.njit(**_OPTS)
def _edge_normal(ring, k):
    """Whether edge ``k`` of a polygon's ring is longer than 1e-9, and its unit normal.

    The normal ``(dy, -dx) / length`` points out of a counter-clockwise ring.
    """
    dx = ring[k + 1, 0] - ring[k, 0]
    dy = ring[k + 1, 1] - ring[k, 1]
    length = np.hypot(dx, dy)
    if length > 1e-9:
        return True, dy / length, -dx / length
    return False, 0.0, 0.0


@nb.njit(**_OPTS)
def _signed_distance(kind, ring, circle, lo0, lo1, h, w, sd, c, nx, ny):
    """Signed distance of each canvas pixel centre to a convex outline (> 0 inside).

    ``kind`` 2: a circle centred at ``circle`` through the farthest point of
    ``ring``, to within 1e-12 (a square root for :func:`_circle_distance`'s
    :func:`numpy.hypot`); else the polygon ``ring`` (closed,
    counter-clockwise): exact inside, outside the distance to the farthest
    edge line (mitre-style), which keeps corners sharp. Written into ``sd``
    ``(h, w)``; ``c``, ``nx`` and ``ny`` are scratch of a ring's length.
    """
    if kind == 2:
        cx, cy = circle[0], circle[1]
        r = _circle_radius(ring, circle)
        for i in range(h):
            dy = float(i) + lo0 - cy
            for j in range(w):
                dx = float(j) + lo1 - cx
                sd[i, j] = r - np.sqrt(dx * dx + dy * dy)
        return sd
    m = ring.shape[0] - 1
    e = 0
    for k in range(m):
        edge, ex, ey = _edge_normal(ring, k)
        if edge:
            nx[e] = ex
            ny[e] = ey
            c[e] = ex * ring[k, 0] + ey * ring[k, 1]
            e += 1
    for i in range(h):
        row = float(i) + lo0
        line = sd[i]
        for j in range(w):
            line[j] = np.inf
        for k in range(e):
            ck, nk = c[k], nx[k]  # (locals: the row is written in between)
            t = ny[k] * row
            for j in range(w):
                v = (ck - nk * (float(j) + lo1)) - t
                if v < line[j]:
                    line[j] = v
    return sd


@nb.njit(**_OPTS)
def _edge_pixels(f, ys, xs):
    """Rows and columns of the pixels of ``f`` with a 4-neighbour outside it (or the grid).

    Written into ``ys`` and ``xs`` (room for ``f.size`` each); returns them and their number.
    """
    h, w = f.shape
    n = 0
    for y in range(h):
        for x in range(w):
            if f[y, x] and (
                y == 0
                or x == 0
                or y == h - 1
                or x == w - 1
                or not f[y - 1, x]
                or not f[y + 1, x]
                or not f[y, x - 1]
                or not f[y, x + 1]
            ):
                ys[n] = y
                xs[n] = x
                n += 1
    return ys, xs, n


@nb.njit(**_OPTS)
def _near_material(f, r, c):
    """1 if pixel ``(r, c)`` (not in ``f``) has a 4-neighbour in ``f``, 2 a diagonal one, else 3."""
    h, w = f.shape
    d2 = 3
    for dr in (-1, 0, 1):
        rr = r + dr
        if 0 <= rr < h:
            for dc in (-1, 0, 1):
                cc = c + dc
                if 0 <= cc < w and f[rr, cc]:
                    if dr == 0 or dc == 0:
                        return 1
                    d2 = 2
    return d2


@nb.njit(**_OPTS)
def defect_groups(
    flat, filled, starts, heights, widths, kind, lo, canvas, frame, rings, ring_starts, verts,
    vert_lo, vert_hi, circles, limits, extents, margin, min_hole_area, min_burr_area,
):  # fmt: skip
    """Holes, and groups of missing and extra pixels large and deep enough, of every object.

    Object ``i`` (mask and filled mask in the flat buffers) is compared with
    its expected outline: ``kind[i]`` 0 none (holes only), 1 the polygon
    ``rings[ring_starts[i]:ring_starts[i + 1]]`` (closed, counter-clockwise),
    2 a circle centred at ``circles[i]`` through the farthest of those
    points; on a canvas of ``canvas[i]`` pixels whose top-left pixel is at
    ``lo[i]`` in mask coordinates, within a frame whose top-left pixel is at
    ``frame[i]`` (the centroids and corner distances are computed from it,
    whatever part of it the canvas covers). ``limits[i]`` are the smallest area and
    depth of a group, the corner radius and a fifth of the outline's area;
    ``extents[i]`` the grid in mask coordinates; ``verts[vert_lo[i]:vert_hi[i]]``
    the outline vertices that mark broken corners.

    Returns ``ints`` (one row per group: object, code, area, row0, col0, row1,
    col1; box in mask coordinates) and ``floats`` (centroid row, column,
    depth). Groups come per object as holes, missing, extra, each in
    :func:`scipy.ndimage.label` order.
    """
    n = heights.shape[0]
    cap = 16
    ints = np.empty((cap, 7), dtype=np.int64)
    floats = np.empty((cap, 3))
    g = 0
    # scratch for the largest mask or canvas, and the longest ring
    big = 1
    longest = 1
    for i in range(n):
        big = max(big, heights[i] * widths[i], canvas[i, 0] * canvas[i, 1])
        longest = max(longest, ring_starts[i + 1] - ring_starts[i])
    holes_buf = np.empty(big, dtype=np.bool_)
    missing_buf = np.empty(big, dtype=np.bool_)
    extra_buf = np.empty(big, dtype=np.bool_)
    sd_buf = np.empty(big)
    lab_buf = np.empty(5 * big, dtype=np.int64)
    stack = np.empty(big, dtype=np.int64)
    rr = np.empty(big, dtype=np.int64)
    cc = np.empty(big, dtype=np.int64)
    gs = np.empty(big + 1, dtype=np.int64)
    edge_y = np.empty(big, dtype=np.int64)
    edge_x = np.empty(big, dtype=np.int64)
    edge_c = np.empty(longest)
    edge_nx = np.empty(longest)
    edge_ny = np.empty(longest)
    found = np.zeros(3, dtype=np.int64)
    for i in range(n):
        m = _mask_of(flat, starts, heights, widths, i)
        f = _mask_of(filled, starts, heights, widths, i)
        h, w = m.shape
        sd = sd_buf[:0].reshape((0, 0))
        # holes (in the mask), missing and extra pixels (on the canvas), and how many
        holes = holes_buf[: h * w].reshape((h, w))
        found[:] = 0
        n_holes = 0
        for r in range(h):
            for c in range(w):
                hole = f[r, c] and not m[r, c]
                holes[r, c] = hole
                n_holes += hole
        found[0] = n_holes
        missing = missing_buf[:0].reshape((0, 0))
        extra = extra_buf[:0].reshape((0, 0))
        if kind[i] != 0:
            ch, cw = canvas[i, 0], canvas[i, 1]
            a, b = ring_starts[i], ring_starts[i + 1]
            sd = sd_buf[: ch * cw].reshape((ch, cw))
            _signed_distance(
                kind[i], rings[a:b], circles[i], lo[i, 0], lo[i, 1], ch, cw, sd, edge_c,
                edge_nx, edge_ny,
            )  # fmt: skip
            outer = -(1.0 + margin)
            radius = 0.0
            if kind[i] == 2:
                # the circle's distances exact (np.hypot) wherever a comparison could
                # turn on the last bits; those of extra pixels are fixed below
                radius = _circle_radius(rings[a:b], circles[i])
                for y in range(ch):
                    for x in range(cw):
                        v = sd[y, x]
                        if abs(v - margin) < 1e-9 or abs(v - outer) < 1e-9:
                            sd[y, x] = _circle_distance(
                                radius, circles[i], float(y + lo[i, 0]), float(x + lo[i, 1])
                            )
            missing = missing_buf[: ch * cw].reshape((ch, cw))
            extra = extra_buf[: ch * cw].reshape((ch, cw))
            n_missing = 0
            n_extra = 0
            # the canvas columns that fall in the mask
            x0 = min(max(-lo[i, 1], 0), cw)
            x1 = max(min(w - lo[i, 1], cw), x0)
            for y in range(ch):
                r = y + lo[i, 0]
                # in the mask's rows, its columns: [x0, x1)
                xa, xb = (x0, x1) if 0 <= r < h else (cw, cw)
                for x in range(xa):
                    hit = sd[y, x] >= margin
                    missing[y, x] = hit
                    extra[y, x] = False
                    n_missing += hit
                for x in range(xa, xb):
                    c = x + lo[i, 1]
                    v = sd[y, x]
                    hit = v >= margin and not f[r, c]
                    missing[y, x] = hit
                    n_missing += hit
                    out = m[r, c] and v < outer
                    extra[y, x] = out
                    if out:
                        if kind[i] == 2:
                            sd[y, x] = _circle_distance(radius, circles[i], float(r), float(c))
                        n_extra += 1
                for x in range(xb, cw):
                    hit = sd[y, x] >= margin
                    missing[y, x] = hit
                    extra[y, x] = False
                    n_missing += hit
            found[1] = n_missing
            found[2] = n_extra
        n_edge = -1  # the filled mask's edge pixels, found when first needed
        for group in range(3):
            lo0, lo1 = lo[i, 0], lo[i, 1]
            f0, f1 = frame[i, 0], frame[i, 1]
            smallest = float(min_hole_area)
            if group == 0:
                region = holes
                lo0, lo1 = 0, 0
                f0, f1 = 0, 0
            elif kind[i] == 0:
                break
            elif group == 1:
                region = missing
                smallest = limits[i, 0]
            else:
                region = extra
                smallest = min_burr_area
            if found[group] == 0 or found[group] < smallest:  # no group can be large enough
                continue
            n_groups = _label_runs_into(region, group != 0, lab_buf, stack, rr, cc, gs)[0]
            for q in range(n_groups):
                a, b = gs[q], gs[q + 1]
                size = b - a
                if size < smallest:
                    continue
                depth = 0.0
                code = HOLE
                if group == 1:
                    # how far the gap reaches from the remaining material (the
                    # exact Euclidean distance transform of ~filled, at its maximum);
                    # the nearest material pixel is always one on its edge
                    # (the largest of the pixels' smallest squared distances, then its
                    # root: a pixel stops once it cannot beat the largest so far)
                    deepest = 0
                    for p in range(a, b):
                        # a pixel with a 4-neighbour in f is at 1 from its edge (that
                        # neighbour is on it), one with only a diagonal one at 2 (the
                        # neighbour's 4-neighbours next to the pixel are not in f)
                        best = _near_material(f, rr[p] + lo0, cc[p] + lo1)
                        if best <= 2:
                            deepest = max(deepest, best)
                            continue
                        if n_edge < 0:
                            n_edge = _edge_pixels(f, edge_y, edge_x)[2]
                        best = -1
                        for e in range(n_edge):
                            dy = rr[p] - (edge_y[e] - lo0)
                            dx = cc[p] - (edge_x[e] - lo1)
                            d2 = dy * dy + dx * dx
                            if best < 0 or d2 < best:
                                best = d2
                                if best <= deepest:
                                    break
                        deepest = max(deepest, best)
                    # (edges not listed: every pixel was next to the material, so it has some)
                    depth = np.sqrt(float(deepest)) if n_edge != 0 else np.inf
                elif group == 2:
                    depth = np.inf
                    for p in range(a, b):
                        depth = min(depth, sd[rr[p], cc[p]])
                    depth = -depth
                if group != 0 and depth < limits[i, 1]:
                    continue
                if group == 2:
                    code = BURR
                elif group == 1:
                    inside = True
                    for p in range(a, b):
                        r, c = rr[p] + lo0, cc[p] + lo1
                        if not (
                            r >= extents[i, 0]
                            and r < extents[i, 2]
                            and c >= extents[i, 1]
                            and c < extents[i, 3]
                        ):
                            inside = False
                    if size >= limits[i, 3] or not inside:
                        code = TRUNCATED
                    else:
                        code = BITE
                        near = np.inf
                        for v in range(vert_lo[i], vert_hi[i]):
                            vx, vy = verts[v, 0] - f1, verts[v, 1] - f0
                            for p in range(a, b):
                                # (in the frame's coordinates, as the distances always were)
                                px, py = cc[p] + lo1 - f1, rr[p] + lo0 - f0
                                near = min(near, np.hypot(vx - px, vy - py))
                        if near <= limits[i, 2]:
                            code = BROKEN_CORNER
                if g == cap:
                    cap *= 2
                    ints2 = np.empty((cap, 7), dtype=np.int64)
                    floats2 = np.empty((cap, 3))
                    ints2[:g] = ints[:g]
                    floats2[:g] = floats[:g]
                    ints, floats = ints2, floats2
                r0, c0, r1, c1 = rr[a], cc[a], rr[a], cc[a]
                sr, sc = 0, 0
                for p in range(a, b):
                    r0, r1 = min(r0, rr[p]), max(r1, rr[p])
                    c0, c1 = min(c0, cc[p]), max(c1, cc[p])
                    sr += rr[p]
                    sc += cc[p]
                ints[g, 0], ints[g, 1], ints[g, 2] = i, code, size
                ints[g, 3], ints[g, 4] = r0 + lo0, c0 + lo1
                ints[g, 5], ints[g, 6] = r1 + lo0 + 1, c1 + lo1 + 1
                # the centroid from the frame's corner, as it always was
                floats[g, 0] = (sr + size * (lo0 - f0)) / size + f0
                floats[g, 1] = (sc + size * (lo1 - f1)) / size + f1
                floats[g, 2] = depth
                g += 1
    return ints[:g], floats[:g]


@nb.njit(**_OPTS)
def _obtuse(x0, y0, x1, y1, x2, y2):
    """Whether the angle at ``(x1, y1)`` is obtuse."""
    return (x0 - x1) * (x2 - x1) + (y0 - y1) * (y2 - y1) < 0


@nb.njit(**_OPTS)
def bounding_circle(px, py):
    """Centre and radius of the smallest circle around a convex ring's vertices (not closed).

    The algorithm and arithmetic of GEOS's MinimumBoundingCircle (walk from
    the lowest point, then the point of least angle with the x axis, to the
    pair or triple of points that fixes the circle), so centre and radius are
    those :func:`shapely.minimum_bounding_circle` and
    :func:`shapely.minimum_bounding_radius` give for the same ring. Returns
    ``(cx, cy, radius)``.
    """
    return _bounding_circle_into(px, py, np.empty(px.shape[0]))


@nb.njit(**_OPTS)
def _bounding_circle_into(px, py, cosines):
    """:func:`bounding_circle` with scratch ``cosines`` (as long as the ring).

    Each step looks for the first vertex R that sees P and Q under the
    smallest angle (GEOS's ``angleBetween``: two ``atan2``), measuring that
    angle only where it may be the smallest: a vertex whose angle's cosine
    (from a dot product) is below the largest cosine by more than 1e-9 sees
    P and Q under an angle larger by more than 1e-9, far beyond the rounding
    of either computation (a few 1e-16), so it is never the one chosen.
    """
    n = px.shape[0]
    if n == 1:
        return px[0], py[0], 0.0
    if n == 2:
        cx, cy = (px[0] + px[1]) / 2.0, (py[0] + py[1]) / 2.0
        return cx, cy, np.sqrt((cx - px[0]) ** 2 + (cy - py[0]) ** 2)
    p = 0
    for i in range(n):
        if py[i] < py[p]:
            p = i
    q = -1
    best = np.finfo(np.float64).max
    for i in range(n):
        if px[i] == px[p] and py[i] == py[p]:
            continue
        dx = px[i] - px[p]
        dy = abs(py[i] - py[p])
        s = dy / np.sqrt(dx * dx + dy * dy)
        if s < best:
            best, q = s, i
    for _ in range(n):
        top = -np.inf
        finite = True
        for i in range(n):
            if (px[i] == px[p] and py[i] == py[p]) or (px[i] == px[q] and py[i] == py[q]):
                continue
            ax, ay = px[p] - px[i], py[p] - py[i]
            bx, by = px[q] - px[i], py[q] - py[i]
            c = (ax * bx + ay * by) / np.sqrt((ax * ax + ay * ay) * (bx * bx + by * by))
            cosines[i] = c
            if not np.isfinite(c):
                finite = False  # (coordinates too small or large: measure every vertex)
            elif c > top:
                top = c
        floor = top - 1e-9 if finite else -np.inf
        r = -1
        best = np.finfo(np.float64).max
        for i in range(n):
            if (px[i] == px[p] and py[i] == py[p]) or (px[i] == px[q] and py[i] == py[q]):
                continue
            if cosines[i] < floor:
                continue
            a1 = np.arctan2(py[p] - py[i], px[p] - px[i])
            a2 = np.arctan2(py[q] - py[i], px[q] - px[i])
            ang = a2 - a1 if a1 < a2 else a1 - a2
            if ang > np.pi:
                ang = 2 * np.pi - ang
            if ang < best:
                best, r = ang, i
        if _obtuse(px[p], py[p], px[r], py[r], px[q], py[q]):
            cx, cy = (px[p] + px[q]) / 2.0, (py[p] + py[q]) / 2.0
            dx, dy = cx - px[p], cy - py[p]
            return cx, cy, np.sqrt(dx * dx + dy * dy)
        if _obtuse(px[r], py[r], px[p], py[p], px[q], py[q]):
            p = r
            continue
        if _obtuse(px[r], py[r], px[q], py[q], px[p], py[p]):
            q = r
            continue
        # the circumcentre of P, Q, R
        ccx, ccy = px[r], py[r]
        ax, ay = px[p] - ccx, py[p] - ccy
        bx, by = px[q] - ccx, py[q] - ccy
        denom = 2 * (ax * by - ay * bx)
        numx = ay * (bx * bx + by * by) - (ax * ax + ay * ay) * by
        numy = ax * (bx * bx + by * by) - (ax * ax + ay * ay) * bx
        cx = ccx - numx / denom
        cy = ccy + numy / denom
        dx, dy = cx - px[p], cy - py[p]
        return cx, cy, np.sqrt(dx * dx + dy * dy)
    return np.nan, np.nan, np.nan


@nb.njit(**_OPTS)
def bounding_radius(px, py):
    """Radius of :func:`bounding_circle` (:func:`shapely.minimum_bounding_radius`)."""
    return bounding_circle(px, py)[2]


@nb.njit(**_OPTS)
def bounding_radii(coords, ring_starts):
    """:func:`bounding_radius` of each ring stored one after the other (not closed)."""
    n = ring_starts.shape[0] - 1
    out = np.empty(n)
    scratch = _ring_scratch(ring_starts)
    for i in range(n):
        a, b = ring_starts[i], ring_starts[i + 1]
        out[i] = _bounding_circle_into(coords[a:b, 0], coords[a:b, 1], scratch)[2]
    return out


@nb.njit(**_OPTS)
def _ring_scratch(ring_starts):
    """Scratch for :func:`_bounding_circle_into` of the longest ring of a batch."""
    longest = 1
    for i in range(ring_starts.shape[0] - 1):
        longest = max(longest, ring_starts[i + 1] - ring_starts[i])
    return np.empty(longest)


@nb.njit(**_OPTS)
def open_burrs(filled, starts, heights, widths, candidates, coords, ring_starts):
    """Cores of the ``candidates``: their filled masks opened where that removes burrs.

    An object's core is its opened filled mask (:func:`opening_cross`) when
    the hull of its pixel squares (``coords[ring_starts[i]:ring_starts[i + 1]]``)
    reaches more than 2 pixels beyond the opened mask's hull, i.e. the opening
    removed something that sticks out (more than the corners an opening
    rounds off). Returns the cores (flat, as ``filled``; a copy only if some
    core changed), which objects changed, and the opened hull rings of those
    (ragged: ``(rings, starts)``, one ring per changed object in order).
    """
    core = filled
    changed = np.zeros(heights.shape[0], dtype=np.bool_)
    cap = 0
    for i in candidates:
        cap += 8 * heights[i] + 2
    rings = np.empty((cap, 2))
    starts_out = [0]
    k = 0
    for i in candidates:
        f = _mask_of(filled, starts, heights, widths, i)
        opened = opening_cross(f)
        if not opened.any():
            continue
        opened_ring = mask_hull(opened, True)
        ring = coords[ring_starts[i] : ring_starts[i + 1]]
        if reaches_beyond(opened_ring, ring[:-1, 0], ring[:-1, 1], 2.0):
            if not changed.any():
                core = filled.copy()
            changed[i] = True
            core[starts[i] : starts[i] + opened.size] = opened.ravel()
            rings[k : k + opened_ring.shape[0]] = opened_ring
            k += opened_ring.shape[0]
            starts_out.append(k)
    return core, changed, rings[:k], np.array(starts_out, dtype=np.int64)


@nb.njit(**_OPTS)
def _power_of_two(peak):
    """The power of two :func:`tentaclass.geometry._power_of_two_scale` gives for ``peak``."""
    if peak > 0:
        return math.ldexp(1.0, math.frexp(peak)[1] - 1)
    return 1.0


@nb.njit(**_OPTS)
def _inverse(scale):
    """``1 / scale`` of a power of two, exact; 0 where it would overflow."""
    return 1.0 / scale if scale >= 2.0**-1022 else 0.0


@nb.njit(**_OPTS)
def _over(x, scale, inv):
    """``x / scale`` for a power of two ``scale`` and ``inv = _inverse(scale)``.

    A product by the exact inverse: the same correctly rounded number as the
    quotient, for a fraction of a division's cost.
    """
    return x * inv if inv != 0.0 else x / scale


@nb.njit(**_OPTS)
def _ring_chord_turns(ring, steps, walk, cross, dot, work):
    """Operands of the turning angles of a walk of ``n_points`` equal chords around a ring.

    The ring has no repeated first vertex (it is closed implicitly). The walk
    is :func:`tentaclass.geometry.resample_closed` of the ring and the angles
    :func:`tentaclass.geometry.points_to_angles` of the walk, ``arctan2(cross,
    dot)``; this writes ``cross`` and ``dot`` (``n_points`` each) with the
    same arithmetic, and returns False where two consecutive points of the
    walk coincide (or the ring has no perimeter), where those functions raise.
    ``steps`` holds ``k / n_points`` for each point ``k`` of the walk;
    ``walk`` is scratch of shape ``(n_points, 2)``, ``work`` of shape ``(4, m + 1)``
    or more.
    """
    n_points = steps.shape[0]
    m = ring.shape[0]
    peak = 0.0
    for j in range(m):
        peak = max(peak, abs(ring[j, 0]), abs(ring[j, 1]))
    scale = _power_of_two(peak)
    inv = _inverse(scale)
    px = work[0]
    py = work[1]
    for j in range(m):
        px[j] = _over(ring[j, 0], scale, inv)
        py[j] = _over(ring[j, 1], scale, inv)
    px[m], py[m] = px[0], py[0]
    s = work[2]
    s[0] = 0.0
    for j in range(m):
        s[j + 1] = s[j] + np.hypot(px[j + 1] - px[j], py[j + 1] - py[j])
    total = s[m]
    if not total > 0:
        return False
    u = work[3]
    for j in range(m + 1):
        u[j] = s[j] / total
    j = 0
    peak = 0.0
    for k in range(n_points):
        t = steps[k]
        while j < m and u[j + 1] <= t:  # searchsorted(u, t, "right") - 1, clipped
            j += 1
        j = min(j, m - 1)
        u0, u1 = u[j], u[j + 1]
        w = (t - u0) / (u1 - u0) if u1 > u0 else 0.0
        walk[k, 0] = (px[j] + w * (px[j + 1] - px[j])) * scale
        walk[k, 1] = (py[j] + w * (py[j + 1] - py[j])) * scale
        peak = max(peak, abs(walk[k, 0]), abs(walk[k, 1]))
    scale = _power_of_two(peak)
    inv = _inverse(scale)
    for k in range(n_points):
        walk[k, 0] = _over(walk[k, 0], scale, inv)
        walk[k, 1] = _over(walk[k, 1], scale, inv)
    ok = True
    for k in range(n_points):
        k0 = k - 1 if k > 0 else n_points - 1
        k2 = k + 1 if k < n_points - 1 else 0
        px, py = walk[k, 0] - walk[k0, 0], walk[k, 1] - walk[k0, 1]
        ex, ey = walk[k2, 0] - walk[k, 0], walk[k2, 1] - walk[k, 1]
        if ex == 0 and ey == 0:
            ok = False
        cross[k] = px * ey - py * ex
        dot[k] = px * ex + py * ey
    return ok


@nb.njit(error_model="numpy", **_OPTS)  # x / 0 is inf or NaN, as numpy gives it
def hull_descriptors(rings, ring_starts, long, short, pixels, n_points):
    """The hull group's scalars and chord-walk operands of closed hull rings, in one pass.

    ``scalars`` ``(n, 5)``: rectangularity ``area / (long * short)``, aspect
    ``short / long``, circularity ``4 pi area / perimeter**2``, circle fill
    ``area / (pi radius**2)`` (area, perimeter and bounding radius as
    :func:`hull_measures`) and pixel scale ``1 / sqrt(pixels)``, with numpy's
    arithmetic; then ``cross`` and ``dot`` ``(n, n_points)``: the operands of the
    turning angles of each ring's chord walk (:func:`_ring_chord_turns`), and
    whether some walk is degenerate.
    """
    n = ring_starts.shape[0] - 1
    scalars = np.empty((n, 5))
    cross = np.empty((n, n_points))
    dot = np.empty((n, n_points))
    walk = np.empty((n_points, 2))
    longest = 0
    for i in range(n):
        longest = max(longest, ring_starts[i + 1] - ring_starts[i])
    work = np.empty((4, longest + 1))
    steps = np.empty(n_points)
    for k in range(n_points):
        steps[k] = k / n_points
    bad = False
    areas, perimeters, radii = hull_measures(rings, ring_starts)
    for i in range(n):
        ring = rings[ring_starts[i] : ring_starts[i + 1]]
        area, perimeter, radius = areas[i], perimeters[i], radii[i]
        scalars[i, 0] = area / (long[i] * short[i])
        scalars[i, 1] = short[i] / long[i]
        scalars[i, 2] = 4 * np.pi * area / (perimeter * perimeter)
        scalars[i, 3] = area / (np.pi * (radius * radius))
        scalars[i, 4] = 1.0 / np.sqrt(float(pixels[i]))
        if not _ring_chord_turns(ring[:-1], steps, walk, cross[i], dot[i], work):
            bad = True
    return scalars, cross, dot, bad


# -- the minimum-area rectangle of GEOS (shapely.oriented_envelope), same arithmetic -------------
# Double-double numbers as GEOS's DD class computes them (Dekker's split; no fused
# multiply-add), for its exact orientation test and line intersection.
_SPLIT = 134217729.0  # 2**27 + 1
_DP_SAFE_EPSILON = 1e-15


@nb.njit(**_OPTS)
def _dd_add(hi, lo, yhi, ylo):
    s_ = hi + yhi
    t_ = lo + ylo
    e = s_ - hi
    f = t_ - lo
    s = s_ - e
    t = t_ - f
    s = (yhi - e) + (hi - s)
    t = (ylo - f) + (lo - t)
    e = s + t_
    h_ = s_ + e
    h = e + (s_ - h_)
    e = t + h
    zhi = h_ + e
    return zhi, e + (h_ - zhi)


@nb.njit(**_OPTS)
def _two_product(a, b):
    """``a * b`` and its rounding error, by Dekker's split (as GEOS's DD computes them)."""
    c = _SPLIT * a
    ah = c - (c - a)
    at = a - ah
    c = _SPLIT * b
    bh = c - (c - b)
    bt = b - bh
    p = a * b
    return p, (((ah * bh - p) + ah * bt) + at * bh) + at * bt


@nb.njit(**_OPTS)
def _dd_mul(hi, lo, yhi, ylo):
    p, err = _two_product(hi, yhi)
    c = err + (hi * ylo + lo * yhi)
    zhi = p + c
    return zhi, c + (p - zhi)


@nb.njit(error_model="numpy", **_OPTS)  # x / 0 is inf or NaN (parallel lines), as in C
def _dd_div(hi, lo, yhi, ylo):
    q = hi / yhi
    p, err = _two_product(q, yhi)
    c = ((((hi - p) - err) + lo) - q * ylo) / yhi
    u = q + c
    return u, (q - u) + c


@nb.njit(**_OPTS)
def _dd_det(ahi, alo, bhi, blo, chi, clo, dhi, dlo):
    """``a * b - c * d`` in double-double."""
    x = _dd_mul(ahi, alo, bhi, blo)
    y = _dd_mul(chi, clo, dhi, dlo)
    return _dd_add(x[0], x[1], -y[0], -y[1])


@nb.njit(**_OPTS)
def _orientation(p1x, p1y, p2x, p2y, qx, qy):
    """GEOS's Orientation::index: 1 if q is left of p1 -> p2, -1 right, 0 on the line."""
    detleft = (p1x - qx) * (p2y - qy)
    detright = (p1y - qy) * (p2x - qx)
    det = detleft - detright
    detsum = 0.0
    decided = True
    if detleft > 0.0:
        if detright > 0.0:
            decided = False
            detsum = detleft + detright
    elif detleft < 0.0:
        if detright < 0.0:
            decided = False
            detsum = -detleft - detright
    if not decided:
        errbound = _DP_SAFE_EPSILON * detsum
        decided = det >= errbound or -det >= errbound
    if decided:
        return 1 if det > 0 else (-1 if det < 0 else 0)
    dx1 = _dd_add(p2x, 0.0, -p1x, 0.0)
    dy1 = _dd_add(p2y, 0.0, -p1y, 0.0)
    dx2 = _dd_add(qx, 0.0, -p2x, 0.0)
    dy2 = _dd_add(qy, 0.0, -p2y, 0.0)
    hi, lo = _dd_det(dx1[0], dx1[1], dy2[0], dy2[1], dy1[0], dy1[1], dx2[0], dx2[1])
    if hi < 0 or (hi == 0 and lo < 0):
        return -1
    if hi > 0 or (hi == 0 and lo > 0):
        return 1
    return 0


@nb.njit(**_OPTS)
def _line_intersection(p1x, p1y, p2x, p2y, q1x, q1y, q2x, q2y):
    """GEOS's CGAlgorithmsDD::intersection of the lines p1-p2 and q1-q2 (NaN if none)."""
    px = _dd_add(p1y, 0.0, -p2y, -0.0)  # DD(a) - DD(b) adds (-b, -0.0)
    py = _dd_add(p2x, 0.0, -p1x, -0.0)
    pw = _dd_det(p1x, 0.0, p2y, 0.0, p2x, 0.0, p1y, 0.0)
    qx = _dd_add(q1y, 0.0, -q2y, -0.0)
    qy = _dd_add(q2x, 0.0, -q1x, -0.0)
    qw = _dd_det(q1x, 0.0, q2y, 0.0, q2x, 0.0, q1y, 0.0)
    x = _dd_det(py[0], py[1], qw[0], qw[1], qy[0], qy[1], pw[0], pw[1])
    y = _dd_det(qx[0], qx[1], pw[0], pw[1], px[0], px[1], qw[0], qw[1])
    w = _dd_det(px[0], px[1], qy[0], qy[1], qx[0], qx[1], py[0], py[1])
    xi = _dd_div(x[0], x[1], w[0], w[1])
    yi = _dd_div(y[0], y[1], w[0], w[1])
    xi, yi = xi[0] + xi[1], yi[0] + yi[1]
    if not (np.isfinite(xi) and np.isfinite(yi)):  # parallel lines: GEOS's null coordinate
        return np.nan, np.nan
    return xi, yi


@nb.njit(**_OPTS)
def _oriented_distance(ax, ay, bx, by, len2, length, px, py, orient):
    """GEOS's LineSegment::distancePerpendicularOriented (absolute for ``orient`` 0).

    ``len2`` is the segment's squared length ``(bx - ax)**2 + (by - ay)**2``
    and ``length`` its root, as GEOS computes them for each point.
    """
    if ax == bx and ay == by:
        dx, dy = ax - px, ay - py
        return np.sqrt(dx * dx + dy * dy)
    s = ((ay - py) * (bx - ax) - (ax - px) * (by - ay)) / len2
    dist = np.abs(s) * length
    if orient == 0:
        return dist  # abs of +-dist
    if _orientation(ax, ay, bx, by, px, py) < 0:
        return -dist
    return dist


@nb.njit(**_OPTS)
def _further_or_equal(d1, d2, orient):
    if orient == 0:
        return abs(d1) >= abs(d2)
    if orient == 1:
        return d1 >= d2
    return d1 <= d2


@nb.njit(**_OPTS)
def _furthest_vertex(ring, ax, ay, bx, by, start, orient):
    """GEOS's MinimumAreaRectangle::findFurthestVertex (``ring`` closed), and its distance.

    The distance is the oriented one of ``orient``; its absolute value is
    the vertex's distance from the line.
    """
    size = ring.shape[0]
    len2 = (bx - ax) * (bx - ax) + (by - ay) * (by - ay)
    length = np.sqrt(len2)
    max_d = _oriented_distance(ax, ay, bx, by, len2, length, ring[start, 0], ring[start, 1], orient)
    next_d = max_d
    max_i = start
    next_i = max_i
    while _further_or_equal(next_d, max_d, orient):
        max_d = next_d
        max_i = next_i
        next_i = max_i + 1
        if next_i >= size - 1:
            next_i = 0
        if next_i == start:
            break
        next_d = _oriented_distance(
            ax, ay, bx, by, len2, length, ring[next_i, 0], ring[next_i, 1], orient
        )
    return max_i, max_d


@nb.njit(**_OPTS)
def _standard_line(a, b, c):
    """Two points of the line ``a x + b y = c``, as GEOS chooses them for a rectangle."""
    if abs(b) > abs(a):
        return 0.0, c / b, 1.0, c / b - a / b
    return c / a, 0.0, c / a - b / a, 1.0


@nb.njit(**_OPTS)
def _corner(out, k, sx, sy, px, py, line1, line2):
    """Corner ``k``: the point ``p`` if the side point ``s`` is it, else where the lines meet."""
    if sx == px and sy == py:
        out[k, 0], out[k, 1] = px, py
    else:
        out[k, 0], out[k, 1] = _line_intersection(*line1, *line2)


@nb.njit(**_OPTS)
def min_area_rectangle(ring, out):
    """GEOS's MinimumAreaRectangle of a convex ring (closed, clockwise) into ``out`` (5, 2).

    Rotating calipers over the ring's edges, and the rectangle built from its
    side points (Rectangle::createFromSidePts), with GEOS's arithmetic: the
    same corners as :func:`shapely.oriented_envelope` of the polygon.
    """
    size = ring.shape[0]
    min_area = np.finfo(np.float64).max
    best_base = best_diam = best_left = best_right = -1
    diam = 1
    left = 1
    right = -1
    for i in range(size - 1):
        b0x, b0y = ring[i, 0], ring[i, 1]
        b1x, b1y = ring[i + 1, 0], ring[i + 1, 1]
        diam = _furthest_vertex(ring, b0x, b0y, b1x, b1y, diam, 0)[0]
        dpx, dpy = ring[diam, 0], ring[diam, 1]
        # LineSegment::project of the diameter point on the base
        if (dpx == b0x and dpy == b0y) or (dpx == b1x and dpy == b1y):
            bpx, bpy = dpx, dpy
        else:
            dx, dy = b1x - b0x, b1y - b0y
            r = ((dpx - b0x) * dx + (dpy - b0y) * dy) / (dx * dx + dy * dy)
            bpx = b0x + r * (b1x - b0x)
            bpy = b0y + r * (b1y - b0y)
        left, to_left = _furthest_vertex(ring, bpx, bpy, dpx, dpy, left, 1)
        if i == 0:
            right = diam
        right, to_right = _furthest_vertex(ring, bpx, bpy, dpx, dpy, right, -1)
        # the side points' distances from the line, as the search found them
        width = abs(to_left)
        width += abs(to_right)
        lx, ly = bpx - dpx, bpy - dpy
        area = np.sqrt(lx * lx + ly * ly) * width
        if area < min_area:
            min_area = area
            best_base, best_diam, best_left, best_right = i, diam, left, right
    brx, bry = ring[best_base, 0], ring[best_base, 1]
    blx, bly = ring[best_base + 1, 0], ring[best_base + 1, 1]
    opx, opy = ring[best_diam, 0], ring[best_diam, 1]
    lsx, lsy = ring[best_left, 0], ring[best_left, 1]
    rsx, rsy = ring[best_right, 0], ring[best_right, 1]
    dx = blx - brx
    dy = bly - bry
    base = _standard_line(-dy, dx, dx * bry - dy * brx)
    opp = _standard_line(-dy, dx, dx * opy - dy * opx)
    lft = _standard_line(-dx, -dy, -dy * lsy - dx * lsx)
    rgt = _standard_line(-dx, -dy, -dy * rsy - dx * rsx)
    _corner(out, 0, rsx, rsy, brx, bry, base, rgt)
    _corner(out, 1, lsx, lsy, blx, bly, base, lft)
    _corner(out, 2, lsx, lsy, opx, opy, opp, lft)
    _corner(out, 3, rsx, rsy, opx, opy, opp, rgt)
    out[4, 0], out[4, 1] = out[0, 0], out[0, 1]


@nb.njit(**_OPTS)
def min_area_rectangles(coords, ring_starts):
    """:func:`min_area_rectangle` of each closed ring stored one after the other: ``(n, 5, 2)``."""
    n = ring_starts.shape[0] - 1
    out = np.empty((n, 5, 2))
    for i in range(n):
        min_area_rectangle(coords[ring_starts[i] : ring_starts[i + 1]], out[i])
    return out


@nb.njit(**_OPTS)
def measure_cores(flat, starts, heights, widths, open_width):
    """:func:`measure_batch`, then each object's core, hull and minimum rotated rectangle.

    Objects whose rectangle's short side is at least ``open_width`` are
    opened where that removes burrs (:func:`open_burrs`); their hulls and
    rectangles are then those of the opened masks. Returns the filled masks
    and the cores (flat, as ``flat``; the cores are ``filled`` itself when no
    object changed), the hull rings of the cores' pixel squares (closed, one
    after the other) and their starts, areas, row/column sums, rectangles
    ``(n, 5, 2)``, :func:`rectangle_sides` of them, and the hull rings of the
    cores' pixel centres (closed, one after the other) and their starts.
    """
    filled, coords, ring_starts, area, sums, centres, centre_starts = measure_batch(
        flat, starts, heights, widths
    )
    corners = min_area_rectangles(coords, ring_starts)
    long, short, edge = rectangle_sides(corners)
    candidates = np.flatnonzero(short >= open_width)
    core, changed, opened, opened_starts = open_burrs(
        filled, starts, heights, widths, candidates, coords, ring_starts
    )
    if opened_starts.shape[0] == 1:  # no core changed
        return (
            filled, core, coords, ring_starts, area, sums, corners, long, short, edge, centres,
            centre_starts,
        )  # fmt: skip
    centres, centre_starts = _replaced_centres(
        core, starts, heights, widths, changed, centres, centre_starts
    )
    n = heights.shape[0]
    new_starts = np.zeros(n + 1, dtype=np.int64)
    for i in range(n):  # the ring lengths, the opened ones where changed
        new_starts[i + 1] = ring_starts[i + 1] - ring_starts[i]
    k = 0
    for i in range(n):
        if changed[i]:
            new_starts[i + 1] = opened_starts[k + 1] - opened_starts[k]
            k += 1
        new_starts[i + 1] += new_starts[i]
    new = np.empty((new_starts[n], 2))
    k = 0
    for i in range(n):
        a = new_starts[i]
        if changed[i]:
            ring = opened[opened_starts[k] : opened_starts[k + 1]]
            k += 1
            min_area_rectangle(ring, corners[i])
            sides = rectangle_sides(corners[i : i + 1])
            long[i], short[i] = sides[0][0], sides[1][0]
            edge[i, 0], edge[i, 1] = sides[2][0, 0], sides[2][0, 1]
        else:
            ring = coords[ring_starts[i] : ring_starts[i + 1]]
        new[a : a + ring.shape[0]] = ring
    return (
        filled, core, new, new_starts, area, sums, corners, long, short, edge, centres,
        centre_starts,
    )  # fmt: skip


@nb.njit(**_OPTS)
def _replaced_centres(core, starts, heights, widths, changed, centres, centre_starts):
    """The centre hull rings with those of the ``changed`` objects taken from their cores."""
    n = heights.shape[0]
    cap = centres.shape[0]
    for i in range(n):
        if changed[i]:
            cap += 2 * heights[i] + 3
    out = np.empty((cap, 2))
    out_starts = np.zeros(n + 1, dtype=np.int64)
    k = 0
    for i in range(n):
        if changed[i]:
            ring = mask_hull(_mask_of(core, starts, heights, widths, i), False)
        else:
            ring = centres[centre_starts[i] : centre_starts[i + 1]]
        out[k : k + ring.shape[0]] = ring
        k += ring.shape[0]
        out_starts[i + 1] = k
    return out[:k], out_starts


# -- areas, lengths, orientations and circles as GEOS computes them ------------------------------
_QUADRANT_SEGMENTS = 8  # GEOS's default for buffers
# shapely calls on thousands of small polygons cost more in building the geometries than
# in the arithmetic; these kernels do the arithmetic of GEOS itself on ragged rings (closed,
# ``coords[starts[i]:starts[i + 1]]``), in its order, so the results are the same bits.


@nb.njit(**_OPTS)
def _ring_area_signed(ring):
    """GEOS's Area::ofRingSigned of a closed ring (shoelace from the first vertex's x)."""
    n = ring.shape[0]
    if n < 3:
        return 0.0
    x0 = ring[0, 0]
    s = 0.0
    for i in range(1, n - 1):
        s += (ring[i, 0] - x0) * (ring[i - 1, 1] - ring[i + 1, 1])
    return s / 2.0


@nb.njit(**_OPTS)
def _ring_length(ring):
    """GEOS's Length::ofLine: the sum of the segment lengths, in order."""
    total = 0.0
    for i in range(1, ring.shape[0]):
        dx = ring[i, 0] - ring[i - 1, 0]
        dy = ring[i, 1] - ring[i - 1, 1]
        total += np.sqrt(dx * dx + dy * dy)
    return total


@nb.njit(**_OPTS)
def hull_measures(coords, starts):
    """Area, perimeter and minimum bounding radius of each closed convex ring.

    :func:`shapely.area`, :func:`shapely.length` and
    :func:`shapely.minimum_bounding_radius` of the rings' polygons.
    """
    n = starts.shape[0] - 1
    area = np.empty(n)
    length = np.empty(n)
    radius = np.empty(n)
    scratch = _ring_scratch(starts)
    for i in range(n):
        ring = coords[starts[i] : starts[i + 1]]
        area[i] = abs(_ring_area_signed(ring))
        length[i] = _ring_length(ring)
        radius[i] = _bounding_circle_into(ring[:-1, 0], ring[:-1, 1], scratch)[2]
    return area, length, radius


@nb.njit(**_OPTS)
def _same(ring, i, j):
    return ring[i, 0] == ring[j, 0] and ring[i, 1] == ring[j, 1]


@nb.njit(**_OPTS)
def _is_ccw(ring):
    """GEOS's Orientation::isCCW of a closed ring of at least 4 points."""
    n_pts = ring.shape[0] - 1
    i_up_hi = 0
    i_up_lo = -1
    hi_y = ring[0, 1]
    prev_y = hi_y
    for i in range(1, n_pts + 1):
        py = ring[i, 1]
        if py > prev_y and py >= hi_y:
            i_up_hi = i
            i_up_lo = i - 1
            hi_y = py
        prev_y = py
    if i_up_hi == 0:
        return False
    i_down_lo = i_up_hi
    while True:
        i_down_lo = (i_down_lo + 1) % n_pts
        if i_down_lo == i_up_hi or ring[i_down_lo, 1] != hi_y:
            break
    i_down_hi = i_down_lo - 1 if i_down_lo > 0 else n_pts - 1
    if _same(ring, i_up_hi, i_down_hi):
        if (
            _same(ring, i_up_lo, i_up_hi)
            or _same(ring, i_down_lo, i_up_hi)
            or _same(ring, i_up_lo, i_down_lo)
        ):
            return False
        o = _orientation(
            ring[i_up_lo, 0], ring[i_up_lo, 1], ring[i_up_hi, 0], ring[i_up_hi, 1],
            ring[i_down_lo, 0], ring[i_down_lo, 1],
        )  # fmt: skip
        return o == 1
    return ring[i_down_hi, 0] - ring[i_up_hi, 0] < 0


@nb.njit(**_OPTS)
def outline_measures(coords, starts, polygon):
    """Area, bounds and counter-clockwise rings of outlines (``polygon``: a polygon's ring).

    :func:`shapely.area` and :func:`shapely.bounds` of each outline, and the
    coordinates of :func:`shapely.orient_polygons` (a clockwise ring
    reversed); rings of points and lines are copied as they are, area 0.
    """
    n = starts.shape[0] - 1
    area = np.zeros(n)
    bounds = np.empty((n, 4))
    out = np.empty_like(coords)
    for i in range(n):
        a, b = starts[i], starts[i + 1]
        ring = coords[a:b]
        x0, y0, x1, y1 = np.inf, np.inf, -np.inf, -np.inf
        for k in range(b - a):
            x0 = min(x0, ring[k, 0])
            y0 = min(y0, ring[k, 1])
            x1 = max(x1, ring[k, 0])
            y1 = max(y1, ring[k, 1])
        bounds[i, 0], bounds[i, 1], bounds[i, 2], bounds[i, 3] = x0, y0, x1, y1
        if polygon[i]:
            area[i] = abs(_ring_area_signed(ring))
            if not _is_ccw(ring):
                for k in range(b - a):
                    out[a + k] = ring[b - a - 1 - k]
                continue
        out[a:b] = ring
    return area, bounds, out


@nb.njit(**_OPTS)
def _circle_steps():
    """Sines and cosines of the steps of :func:`_circle_ring` (values below 5e-16 snapped to 0)."""
    segs = int(abs(0.0 - 2.0 * np.pi) / (np.pi / 2.0 / _QUADRANT_SEGMENTS) + 0.5)
    inc = abs(0.0 - 2.0 * np.pi) / segs
    sc = np.empty((segs, 2))
    for j in range(segs):
        angle = 0.0 + (-j) * inc
        s = np.sin(angle)
        c = np.cos(angle)
        if abs(s) < 5e-16:
            s = 0.0
        if abs(c) < 5e-16:
            c = 0.0
        sc[j, 0], sc[j, 1] = s, c
    return sc


@nb.njit(**_OPTS)
def _circle_ring(ring, out, k, steps):
    """GEOS's minimum bounding circle of a convex ring (not closed), written at ``out[k:]``.

    The circle is GEOS's buffer of the centre (:func:`bounding_circle`): from
    ``(cx + r, cy)`` clockwise in 32 steps (sines and cosines below 5e-16
    snapped to 0, points closer than ``1e-6 r`` to the one before dropped),
    closed; a zero radius gives the centre point. ``steps``: the sines and
    cosines of :func:`_circle_steps`. Returns the end of the ring in ``out``
    and whether it is a polygon.
    """
    cx, cy, r = bounding_circle(ring[:, 0], ring[:, 1])
    a = k
    if r == 0.0:
        out[k, 0], out[k, 1] = cx, cy
        return k + 1, False
    out[k, 0], out[k, 1] = cx + r, cy
    k += 1
    near = r * 1e-6
    for j in range(steps.shape[0]):
        s, c = steps[j, 0], steps[j, 1]
        x, y = cx + r * c, cy + r * s
        dx, dy = x - out[k - 1, 0], y - out[k - 1, 1]
        if np.sqrt(dx * dx + dy * dy) < near:
            continue
        out[k, 0], out[k, 1] = x, y
        k += 1
    if out[k - 1, 0] != out[a, 0] or out[k - 1, 1] != out[a, 1]:
        out[k, 0], out[k, 1] = out[a, 0], out[a, 1]
        k += 1
    return k, True


@nb.njit(**_OPTS)
def circle_outlines(coords, starts):
    """:func:`shapely.minimum_bounding_circle` of closed convex rings, as GEOS builds them.

    See :func:`_circle_ring`. Returns the rings (ragged, with their starts),
    whether each is a polygon and the centroids of the polygons as GEOS
    computes them (triangles fanned from the first vertex).
    """
    n = starts.shape[0] - 1
    out = np.empty((n * (4 * _QUADRANT_SEGMENTS + 2), 2))
    steps = _circle_steps()
    out_starts = np.zeros(n + 1, dtype=np.int64)
    polygon = np.zeros(n, dtype=np.bool_)
    centroid = np.zeros((n, 2))
    k = 0
    for i in range(n):
        a = k
        k, polygon[i] = _circle_ring(coords[starts[i] : starts[i + 1] - 1], out, k, steps)
        if polygon[i]:
            centroid[i, 0], centroid[i, 1] = _centroid(out[a:k])
        out_starts[i + 1] = k
    return out[:k], out_starts, polygon, centroid


HULL, RECTANGLE, CIRCLE, TRIANGLE = range(4)  # expected outlines (:func:`expected_outlines`)


@nb.njit(**_OPTS)
def expected_outlines(rings, ring_starts, shape, tri_xy, tri_starts, tri_found, tris):
    """Expected outlines of convex rings (closed, one after the other), as shapely gives them.

    ``shape[i]`` says which outline ring ``i`` (a polygon's) gets: ``HULL``
    the ring itself, ``RECTANGLE`` its minimum rotated rectangle
    (:func:`min_area_rectangle`), ``CIRCLE`` its minimum bounding circle
    (:func:`_circle_ring`), ``TRIANGLE`` the next triangle of ``tris``
    (closed), or where ``tri_found`` is False the next ring of ``(tri_xy,
    tri_starts)``. Returns the outlines' rings (closed, one after the other;
    a point or a line as they are), their starts, whether each is a polygon
    and the centroids of the circles.
    """
    n = ring_starts.shape[0] - 1
    cap = 0
    t = 0
    for i in range(n):
        m = ring_starts[i + 1] - ring_starts[i]
        if shape[i] == RECTANGLE:
            cap += 5
        elif shape[i] == CIRCLE:
            cap += 4 * _QUADRANT_SEGMENTS + 2
        elif shape[i] == TRIANGLE:
            cap += 4 if tri_found[t] else tri_starts[t + 1] - tri_starts[t]
            t += 1
        else:
            cap += m
    out = np.empty((cap, 2))
    starts = np.zeros(n + 1, dtype=np.int64)
    polygon = np.zeros(n, dtype=np.bool_)
    centroid = np.zeros((n, 2))
    steps = _circle_steps()
    k = 0
    t = 0
    for i in range(n):
        ring = rings[ring_starts[i] : ring_starts[i + 1]]
        if shape[i] == RECTANGLE:
            min_area_rectangle(ring, out[k : k + 5])
            k += 5
            polygon[i] = True
        elif shape[i] == CIRCLE:
            a = k
            k, polygon[i] = _circle_ring(ring[:-1], out, k, steps)
            if polygon[i]:
                centroid[i, 0], centroid[i, 1] = _centroid(out[a:k])
        elif shape[i] == TRIANGLE and tri_found[t]:
            for j in range(4):
                out[k + j, 0], out[k + j, 1] = tris[t, j % 3, 0], tris[t, j % 3, 1]
            k += 4
            polygon[i] = True
            t += 1
        else:
            if shape[i] == TRIANGLE:
                ring = tri_xy[tri_starts[t] : tri_starts[t + 1]]
                t += 1
            out[k : k + ring.shape[0]] = ring
            k += ring.shape[0]
            polygon[i] = ring.shape[0] >= 4
        starts[i + 1] = k
    return out[:k], starts, polygon, centroid


@nb.njit(**_OPTS)
def _centroid(ring):
    """GEOS's Centroid of a polygon's shell (closed ring), area-weighted from its first vertex."""
    sign = -1.0 if _is_ccw(ring) else 1.0
    bx, by = ring[0, 0], ring[0, 1]
    gx = 0.0
    gy = 0.0
    total = 0.0
    for i in range(ring.shape[0] - 1):
        p1x, p1y = ring[i, 0], ring[i, 1]
        p2x, p2y = ring[i + 1, 0], ring[i + 1, 1]
        tx = bx + p1x + p2x
        ty = by + p1y + p2y
        a2 = (p1x - bx) * (p2y - by) - (p2x - bx) * (p1y - by)
        gx += sign * a2 * tx
        gy += sign * a2 * ty
        total += sign * a2
    return gx / 3 / total, gy / 3 / total


@nb.njit(**_OPTS)
def outline_shapes(ring_starts, code):
    """The outline each hull gets, and the hulls that get a triangle, gathered.

    ``code`` is the shape each object's class asks for; a hull of fewer than
    4 points (a point or a line) gets itself (``HULL``). Returns the shapes
    and the indices of the triangles' hulls.
    """
    n = code.shape[0]
    shape = np.empty(n, dtype=np.int64)
    picked = np.empty(n, dtype=np.int64)
    k = 0
    for i in range(n):
        shape[i] = code[i] if ring_starts[i + 1] - ring_starts[i] >= 4 else HULL
        if shape[i] == TRIANGLE:
            picked[k] = i
            k += 1
    return shape, picked[:k]


@nb.njit(**_OPTS)
def gather_rings(coords, starts, picked):
    """The rings ``picked`` (indices) of rings stored one after the other: ``(coords, starts)``."""
    out_starts = np.zeros(picked.shape[0] + 1, dtype=np.int64)
    for k in range(picked.shape[0]):
        i = picked[k]
        out_starts[k + 1] = out_starts[k] + starts[i + 1] - starts[i]
    out = np.empty((out_starts[-1], 2))
    for k in range(picked.shape[0]):
        i = picked[k]
        out[out_starts[k] : out_starts[k + 1]] = coords[starts[i] : starts[i + 1]]
    return out, out_starts


@nb.njit(**_OPTS)
def ordered_defects(ints, floats, tops, lefts):
    """The rows of :func:`defect_groups` in record order, moved by each object's offset.

    Each object's holes first, then its missing, then its extra material,
    each largest first (a stable order: equal ones as the kernel gave them);
    boxes and centroids moved by ``(tops[i], lefts[i])`` of their object
    ``i``, and the holes' depths set to 0. Returns new arrays.
    """
    n = ints.shape[0]
    order = np.arange(n)
    key = np.empty((n, 2), dtype=np.int64)  # (group, -area)
    for g in range(n):
        code = ints[g, 1]
        key[g, 0] = 0 if code == HOLE else 2 if code == BURR else 1
        key[g, 1] = -ints[g, 2]
    a = 0
    while a < n:  # each object's rows, in place by insertion (stable)
        b = a
        while b < n and ints[b, 0] == ints[a, 0]:
            b += 1
        for x in range(a + 1, b):
            v = order[x]
            y = x
            while y > a and (
                key[order[y - 1], 0] > key[v, 0]
                or (key[order[y - 1], 0] == key[v, 0] and key[order[y - 1], 1] > key[v, 1])
            ):
                order[y] = order[y - 1]
                y -= 1
            order[y] = v
        a = b
    out_ints = np.empty_like(ints)
    out_floats = np.empty_like(floats)
    for g in range(n):
        src = order[g]
        i = ints[src, 0]
        out_ints[g] = ints[src]
        out_floats[g] = floats[src]
        for c in (3, 5):
            out_ints[g, c] += tops[i]
            out_ints[g, c + 1] += lefts[i]
        out_floats[g, 0] += float(tops[i])
        out_floats[g, 1] += float(lefts[i])
        if ints[src, 1] == HOLE:
            out_floats[g, 2] = 0.0
    return out_ints, out_floats


@nb.njit(**_OPTS)
def _grown_bounds(ring, circle, centre, margin, x0, y0, x1, y1, work):
    """Bounds of where :func:`_signed_distance` can reach ``margin`` or more.

    That is the outline grown by ``-margin``: for a ``circle`` centred at
    ``centre`` through the farthest point of ``ring``, the circle of radius
    ``r - margin``; for the polygon ``ring`` (closed, counter-clockwise),
    each edge's line moved out by ``-margin`` (the mitred outline, whose
    vertices lie on the bisectors of the edges meeting there), or the
    polygon's bounds ``x0, y0, x1, y1`` when it shrinks. Unbounded (a vertex
    too sharp to move) is infinite. ``work``: scratch ``(4, m)`` or more for
    a ring of ``m`` points.
    """
    if circle:
        r = _circle_radius(ring, centre) - margin
        return centre[0] - r, centre[1] - r, centre[0] + r, centre[1] + r
    if margin >= 0:
        return x0, y0, x1, y1
    grow = -margin
    m = ring.shape[0] - 1
    # the edges longer than 1e-9, as _signed_distance takes them: start and normal
    px, py, nx, ny = work[0], work[1], work[2], work[3]
    e = 0
    for k in range(m):
        edge, nx[e], ny[e] = _edge_normal(ring, k)
        if edge:
            px[e], py[e] = ring[k, 0], ring[k, 1]
            e += 1
    if e < 3:
        return -np.inf, -np.inf, np.inf, np.inf
    gx0, gy0, gx1, gy1 = np.inf, np.inf, -np.inf, -np.inf
    for k in range(e):
        j = k - 1 if k > 0 else e - 1
        den = 1.0 + nx[j] * nx[k] + ny[j] * ny[k]
        if not den > 1e-6:
            return -np.inf, -np.inf, np.inf, np.inf
        vx = px[k] + grow * (nx[j] + nx[k]) / den
        vy = py[k] + grow * (ny[j] + ny[k]) / den
        gx0, gy0 = min(gx0, vx), min(gy0, vy)
        gx1, gy1 = max(gx1, vx), max(gy1, vy)
    if not (np.isfinite(gx0) and np.isfinite(gy0) and np.isfinite(gx1) and np.isfinite(gy1)):
        return -np.inf, -np.inf, np.inf, np.inf
    return gx0, gy0, gx1, gy1


@nb.njit(**_OPTS)
def defect_setup(
    xy, starts, polygon, circle, cornered, heights, widths, obj_area, width, length, min_area,
    min_area_fraction, min_depth, circles, margin,
):  # fmt: skip
    """What :func:`defect_groups` needs of each object, from its expected outline.

    The outline (closed rings ``xy``, one after the other) is compared with
    the object when it is a polygon of area at least 4: ``kind`` 1 (2 for a
    ``circle`` centred at ``circles[i]``); its canvas (top-left pixel ``lo``,
    size ``canvas``) covers the mask and the pixels whose centres may lie
    inside the outline grown by ``-margin`` (:func:`_grown_bounds`), at most
    2 pixels beyond mask and outline; its ring is made
    counter-clockwise; the vertices of ``cornered`` outlines mark broken
    corners (``vert_lo``, ``vert_hi``); ``limits`` are the thresholds of
    :class:`~tentaclass.scanner.DefectSettings` for the object's area, width
    and length, the corner radius and a fifth of the outline's area.
    """
    area, bounds, rings = outline_measures(xy, starts, polygon)
    n = starts.shape[0] - 1
    kind = np.zeros(n, dtype=np.int64)
    lo = np.zeros((n, 2), dtype=np.int64)
    frame = np.zeros((n, 2), dtype=np.int64)
    canvas = np.zeros((n, 2), dtype=np.int64)
    vert_lo = starts[:-1].copy()
    vert_hi = starts[:-1].copy()
    limits = np.empty((n, 4))
    longest = 1
    for i in range(n):
        longest = max(longest, starts[i + 1] - starts[i])
    work = np.empty((4, longest))
    for i in range(n):
        if polygon[i] and area[i] >= 4:
            kind[i] = 2 if circle[i] else 1
            x0, y0, x1, y1 = bounds[i, 0], bounds[i, 1], bounds[i, 2], bounds[i, 3]
            gx0, gy0, gx1, gy1 = _grown_bounds(
                rings[starts[i] : starts[i + 1]], circle[i], circles[i], margin, x0, y0, x1, y1,
                work,
            )  # fmt: skip
            frame[i, 0] = int(np.floor(min(y0, 0.0) - 2))
            frame[i, 1] = int(np.floor(min(x0, 0.0) - 2))
            lo[i, 0] = max(frame[i, 0], int(min(0.0, np.ceil(gy0 - 1e-3))))
            lo[i, 1] = max(frame[i, 1], int(min(0.0, np.ceil(gx0 - 1e-3))))
            end0 = min(
                np.ceil(max(y1, float(heights[i])) + 2), max(heights[i], np.floor(gy1 + 1e-3) + 1)
            )
            end1 = min(
                np.ceil(max(x1, float(widths[i])) + 2), max(widths[i], np.floor(gx1 + 1e-3) + 1)
            )
            canvas[i, 0] = int(end0) - lo[i, 0]
            canvas[i, 1] = int(end1) - lo[i, 1]
            if cornered[i]:
                vert_hi[i] = starts[i + 1] - 1
        pixels = float(obj_area[i])
        small = min(min_area, max(1.0, 0.1 * pixels))
        limits[i, 0] = max(small, min_area_fraction * pixels)
        limits[i, 1] = min(min_depth, max(1.0, 0.2 * width[i]))
        limits[i, 2] = min(3.0, max(1.0, 0.1 * length[i]))
        limits[i, 3] = 0.2 * area[i]
    return kind, lo, canvas, frame, rings, vert_lo, vert_hi, limits


plain_calls(globals())
