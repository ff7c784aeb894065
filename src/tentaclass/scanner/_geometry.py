"""Compiled helpers for the per-object measurements of the scanner.

Small objects pass at thousands per second; building a shapely geometry from
a point set, or calling scipy.ndimage on a 15 x 15 mask, costs more in call
overhead than the work itself. These kernels do that work directly:

- :func:`hull_ring`: convex hull of points (Andrew's monotone chain), as the
  closed ring GEOS would return (clockwise, starting at the lowest point,
  then the leftmost; collinear points dropped), so that shapely's results
  and everything measured on the ring stay the same;
- :func:`max_distance_outside`: the largest distance of points from a convex
  polygon (0 inside);
- :func:`fill_holes`: :func:`scipy.ndimage.binary_fill_holes` (background
  4-connected to the border stays background);
- :func:`mask_hull`: :func:`hull_ring` of a mask's pixel squares or centres;
- :func:`opening_cross`: :func:`scipy.ndimage.binary_opening` with the 3 x 3
  cross.
"""

from __future__ import annotations

import numba as nb
import numpy as np

_OPTS = {"cache": True, "nogil": True}


@nb.njit(**_OPTS)
def _cross(ox, oy, ax, ay, bx, by):
    return (ax - ox) * (by - oy) - (ay - oy) * (bx - ox)


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
    hx = np.empty(2 * m)
    hy = np.empty(2 * m)
    k = 0
    for i in range(m):  # lower hull
        while k >= 2 and _cross(hx[k - 2], hy[k - 2], hx[k - 1], hy[k - 1], ux[i], uy[i]) <= 0:
            k -= 1
        hx[k] = ux[i]
        hy[k] = uy[i]
        k += 1
    lo = k + 1
    for i in range(m - 2, -1, -1):  # upper hull
        while k >= lo and _cross(hx[k - 2], hy[k - 2], hx[k - 1], hy[k - 1], ux[i], uy[i]) <= 0:
            k -= 1
        hx[k] = ux[i]
        hy[k] = uy[i]
        k += 1
    k -= 1  # the last point repeats the first; hx[:k] is counter-clockwise
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
def max_distance_outside(ring, px, py):
    """Largest distance of the points from the convex polygon ``ring`` (closed, clockwise)."""
    worst = 0.0
    n = ring.shape[0] - 1
    for p in range(px.shape[0]):
        x, y = px[p], py[p]
        inside = True
        best = np.inf
        for i in range(n):
            ax, ay = ring[i, 0], ring[i, 1]
            bx, by = ring[i + 1, 0], ring[i + 1, 1]
            if _cross(ax, ay, bx, by, x, y) > 0:  # left of a clockwise edge: outside
                inside = False
            dx, dy = bx - ax, by - ay
            ll = dx * dx + dy * dy
            t = 0.0 if ll == 0 else ((x - ax) * dx + (y - ay) * dy) / ll
            t = min(1.0, max(0.0, t))
            ex, ey = ax + t * dx - x, ay + t * dy - y
            best = min(best, np.sqrt(ex * ex + ey * ey))
        if not inside and best > worst:
            worst = best
    return worst


@nb.njit(**_OPTS)
def fill_holes(mask):
    """``mask`` with every background region not 4-connected to the border filled."""
    h, w = mask.shape
    outside = np.zeros((h, w), dtype=np.bool_)
    stack = np.empty(h * w * 4 + 4, dtype=np.int64)
    top = 0
    for k in range(2 * (h + w)):  # the border: left, right, top and bottom edges
        if k < 2 * h:
            r, c = k % h, 0 if k < h else w - 1
        else:
            r, c = 0 if k < 2 * h + w else h - 1, (k - 2 * h) % w
        if not mask[r, c] and not outside[r, c]:
            outside[r, c] = True
            stack[top] = r * w + c
            top += 1
    while top > 0:
        top -= 1
        r, c = divmod(stack[top], w)
        for dr, dc in ((-1, 0), (1, 0), (0, -1), (0, 1)):
            rr, cc = r + dr, c + dc
            if 0 <= rr < h and 0 <= cc < w and not mask[rr, cc] and not outside[rr, cc]:
                outside[rr, cc] = True
                stack[top] = rr * w + cc
                top += 1
    return ~outside


@nb.njit(**_OPTS)
def mask_hull(mask, corners):
    """:func:`hull_ring` of the pixel squares' corners (or centres) of a mask.

    Only the first and last pixel of each row can be hull vertices: at most
    ``4 * n_rows`` points.
    """
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
    return hull_ring(x[:n], y[:n])


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
    lab = np.zeros((h, w), dtype=np.int64)
    stack = np.empty(h * w, dtype=np.int64)
    n = 0
    for r0 in range(h):
        for c0 in range(w):
            if not region[r0, c0] or lab[r0, c0]:
                continue
            n += 1
            lab[r0, c0] = n
            stack[0] = r0 * w + c0
            top = 1
            while top:
                top -= 1
                r, c = divmod(stack[top], w)
                for dr in (-1, 0, 1):
                    for dc in (-1, 0, 1):
                        if (dr == 0 and dc == 0) or (not eight and dr != 0 and dc != 0):
                            continue
                        rr, cc = r + dr, c + dc
                        if 0 <= rr < h and 0 <= cc < w and region[rr, cc] and not lab[rr, cc]:
                            lab[rr, cc] = n
                            stack[top] = rr * w + cc
                            top += 1
    starts = np.zeros(n + 1, dtype=np.int64)
    for r in range(h):
        for c in range(w):
            if lab[r, c]:
                starts[lab[r, c]] += 1
    for k in range(n):
        starts[k + 1] += starts[k]
    pos = starts[:-1].copy()
    rows = np.empty(starts[n], dtype=np.int64)
    cols = np.empty(starts[n], dtype=np.int64)
    for r in range(h):
        for c in range(w):
            k = lab[r, c]
            if k:
                rows[pos[k - 1]] = r
                cols[pos[k - 1]] = c
                pos[k - 1] += 1
    return rows, cols, starts


def row_extremes(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Rows holding pixels, and the first and last pixel's column in each."""
    rows = np.flatnonzero(mask.any(axis=1))
    sub = mask[rows]
    first = sub.argmax(axis=1)
    last = mask.shape[1] - 1 - sub[:, ::-1].argmax(axis=1)
    return rows, first, last
