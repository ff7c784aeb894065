"""Compiled geometric primitives of the wrap: crossing tests, nearest points, angles.

Hand-written (numba) because they run inside the compiled walk, once per
link; shapely's predicates are vectorised over geometries but cannot be
called from compiled code.
"""

from __future__ import annotations

import numba as nb
import numpy as np

from .._geos import point_segment_distance as _point_segment_distance
from .._jit import plain_calls

TWO_PI = 2.0 * np.pi


@nb.njit(cache=True, inline="always")
def _near(phi, ref):
    """The value of ``phi`` modulo 2*pi closest to ``ref``."""
    return ref + ((phi - ref + np.pi) % TWO_PI) - np.pi


@nb.njit(cache=True, inline="always")
def _sides(ax, ay, bx, by, px, py, qx, qy):
    """Signed areas locating ``p`` and ``q`` left (> 0) or right of the line a-b."""
    dx, dy = bx - ax, by - ay
    return dx * (py - ay) - dy * (px - ax), dx * (qy - ay) - dy * (qx - ax)


@nb.njit(cache=True, inline="always")
def _apart(o1, o2, eps):
    """The two signed areas lie clearly on opposite sides."""
    return (o1 > eps and o2 < -eps) or (o1 < -eps and o2 > eps)


@nb.njit(cache=True)
def crosses(ax, ay, bx, by, obj, eps):
    """True if segment a-b properly crosses an edge of the closed polygon ``obj``.

    Touching, ending on the outline and running along an edge do not count.
    """
    return crossing_edge(ax, ay, bx, by, obj, eps) >= 0


@nb.njit(cache=True)
def crossing_edge(ax, ay, bx, by, obj, eps):
    """Index of the first edge of ``obj`` that segment a-b properly crosses, or -1."""
    return crossing_edge_range(ax, ay, bx, by, obj, eps, 0, obj.shape[0])


@nb.njit(cache=True)
def crossing_edge_range(ax, ay, bx, by, obj, eps, first, count):
    """As :func:`crossing_edge`, testing only edges ``first .. first + count - 1`` (cyclic)."""
    m = obj.shape[0]
    lox, hix = min(ax, bx), max(ax, bx)
    loy, hiy = min(ay, by), max(ay, by)
    dx, dy = bx - ax, by - ay
    for ii in range(first, first + count):
        i = ii % m
        px, py = obj[i, 0], obj[i, 1]
        i2 = i + 1 if i + 1 < m else 0
        qx, qy = obj[i2, 0], obj[i2, 1]
        if (px < lox and qx < lox) or (px > hix and qx > hix):
            continue
        if (py < loy and qy < loy) or (py > hiy and qy > hiy):
            continue
        o1 = dx * (py - ay) - dy * (px - ax)
        o2 = dx * (qy - ay) - dy * (qx - ax)
        if -eps <= o1 <= eps:
            # The segment passes through vertex p: it crosses there if the
            # outline, leaving p both ways along any edges that lie on the
            # segment, goes on to opposite sides of it.
            ll = dx * dx + dy * dy
            t = dx * (px - ax) + dy * (py - ay)
            if 0.0 < t < ll:
                side = 0.0
                for step in (-1, 1):
                    v = i
                    for _ in range(m):
                        v = (v + step) % m
                        ov = dx * (obj[v, 1] - ay) - dy * (obj[v, 0] - ax)
                        if ov > eps or ov < -eps:
                            break
                        tv = dx * (obj[v, 0] - ax) + dy * (obj[v, 1] - ay)
                        if not 0.0 < tv < ll:
                            ov = 0.0  # the outline leaves along the line: no crossing
                            break
                    if side == 0.0:
                        side = ov
                        if ov == 0.0:
                            break
                    elif (side > 0 and ov < 0) or (side < 0 and ov > 0):
                        return i
            continue
        if not ((o1 > eps and o2 < -eps) or (o1 < -eps and o2 > eps)):
            continue
        ex, ey = qx - px, qy - py
        o3 = ex * (ay - py) - ey * (ax - px)
        o4 = ex * (by - py) - ey * (bx - px)
        if (o3 > eps and o4 < -eps) or (o3 < -eps and o4 > eps):
            return i
    return -1


#: Edges per block of :func:`edge_boxes`.
BOX_EDGES = 16
#: Blocks per group of :func:`edge_boxes`.
BOX_GROUP = 8


@nb.njit(cache=True, inline="always")
def _n_blocks(m):
    """Blocks of ``BOX_EDGES`` edges of a closed polyline of ``m`` vertices."""
    return (m + BOX_EDGES - 1) // BOX_EDGES


@nb.njit(cache=True)
def edge_boxes(obj):
    """Bounding box ``(x_min, x_max, y_min, y_max)`` of each block of ``BOX_EDGES`` edges.

    Followed by the box of each group of ``BOX_GROUP`` blocks: rows
    ``_n_blocks(m) ..`` (a search checks a group's box before its blocks').
    """
    m = obj.shape[0]
    nb_ = _n_blocks(m)
    ng = (nb_ + BOX_GROUP - 1) // BOX_GROUP
    boxes = np.empty((nb_ + ng, 4))
    for b in range(nb_):
        lo = b * BOX_EDGES
        hi = min(lo + BOX_EDGES, m)  # the last edge of the block ends at vertex hi
        boxes[b, 0], boxes[b, 1] = np.inf, -np.inf
        boxes[b, 2], boxes[b, 3] = np.inf, -np.inf
        for v in range(lo, hi + 1):
            x, y = obj[v % m, 0], obj[v % m, 1]
            boxes[b, 0], boxes[b, 1] = min(boxes[b, 0], x), max(boxes[b, 1], x)
            boxes[b, 2], boxes[b, 3] = min(boxes[b, 2], y), max(boxes[b, 3], y)
    for g in range(ng):
        r = nb_ + g
        boxes[r, 0], boxes[r, 1] = np.inf, -np.inf
        boxes[r, 2], boxes[r, 3] = np.inf, -np.inf
        for b in range(g * BOX_GROUP, min(g * BOX_GROUP + BOX_GROUP, nb_)):
            boxes[r, 0], boxes[r, 1] = min(boxes[r, 0], boxes[b, 0]), max(boxes[r, 1], boxes[b, 1])
            boxes[r, 2], boxes[r, 3] = min(boxes[r, 2], boxes[b, 2]), max(boxes[r, 3], boxes[b, 3])
    return boxes


@nb.njit(cache=True, inline="always")
def _misses(boxes, b, lox, hix, loy, hiy):
    """Box ``b`` and the box ``[lox, hix] x [loy, hiy]`` are disjoint."""
    return boxes[b, 1] < lox or boxes[b, 0] > hix or boxes[b, 3] < loy or boxes[b, 2] > hiy


@nb.njit(cache=True)
def crossing_edge_boxed(ax, ay, bx, by, obj, eps, boxes):
    """:func:`crossing_edge`, testing only the blocks of edges whose box meets the segment's.

    The same edge as :func:`crossing_edge`: a block whose box (or whose
    group's box) misses the segment's holds no edge that the plain test would
    examine.
    """
    m = obj.shape[0]
    nb_ = _n_blocks(m)
    lox, hix = min(ax, bx), max(ax, bx)
    loy, hiy = min(ay, by), max(ay, by)
    for g in range(boxes.shape[0] - nb_):
        if _misses(boxes, nb_ + g, lox, hix, loy, hiy):
            continue
        for b in range(g * BOX_GROUP, min(g * BOX_GROUP + BOX_GROUP, nb_)):
            if _misses(boxes, b, lox, hix, loy, hiy):
                continue
            first = b * BOX_EDGES
            e = crossing_edge_range(ax, ay, bx, by, obj, eps, first, min(BOX_EDGES, m - first))
            if e >= 0:
                return e
    return -1


@nb.njit(cache=True)
def crosses_range_boxed(ax, ay, bx, by, obj, eps, first, count, boxes):
    """Whether segment a-b crosses one of edges ``first .. first + count - 1`` (cyclic).

    As :func:`crossing_edge_range` ``>= 0``, passing over the whole blocks of
    ``boxes`` (:func:`edge_boxes`) in the range whose box misses the segment's.
    """
    m = obj.shape[0]
    lox, hix = min(ax, bx), max(ax, bx)
    loy, hiy = min(ay, by), max(ay, by)
    ii, end = first, first + count
    while ii < end:
        i = ii % m
        if i % BOX_EDGES == 0 and i + BOX_EDGES <= m and ii + BOX_EDGES <= end:
            run = BOX_EDGES
            if _misses(boxes, i // BOX_EDGES, lox, hix, loy, hiy):
                ii += run
                continue
        else:  # up to the next block, the end of the outline or of the range
            run = min(BOX_EDGES - i % BOX_EDGES, m - i, end - ii)
        if crossing_edge_range(ax, ay, bx, by, obj, eps, i, run) >= 0:
            return True
        ii += run
    return False


@nb.njit(cache=True)
def crosses_boxed(ax, ay, bx, by, obj, eps, boxes):
    """:func:`crosses`, testing only the blocks of edges whose box meets the segment's."""
    return crossing_edge_boxed(ax, ay, bx, by, obj, eps, boxes) >= 0


@nb.njit(cache=True, inline="always")
def _box_gap2(boxes, b, x, y):
    """Squared distance from ``(x, y)`` to box ``b`` of ``boxes`` (0 inside it)."""
    gx = max(boxes[b, 0] - x, x - boxes[b, 1], 0.0)
    gy = max(boxes[b, 2] - y, y - boxes[b, 3], 0.0)
    return gx * gx + gy * gy


@nb.njit(cache=True, inline="always")
def _next_near_edge(boxes, m, i, x, y, far):
    """The first edge ``>= i`` whose block and group boxes lie within ``far`` of ``(x, y)``.

    ``far`` is a squared distance; returns ``m`` past the last edge. An edge
    inside a block is returned as it is: the walk let its block through on
    entering it. Walk every near edge with ``i = _next_near_edge(.., i + 1, ..)``.
    """
    if i >= m:
        return m
    if i % BOX_EDGES:
        return i
    nb_ = _n_blocks(m)
    b = i // BOX_EDGES
    while b < nb_:
        if b % BOX_GROUP == 0 and _box_gap2(boxes, nb_ + b // BOX_GROUP, x, y) > far:
            b += BOX_GROUP
        elif _box_gap2(boxes, b, x, y) > far:
            b += 1
        else:
            return b * BOX_EDGES
    return m


@nb.njit(cache=True, inline="always")
def _foot(x, y, x0, y0, x1, y1):
    """Nearest point of segment ``(x0, y0)-(x1, y1)`` to ``(x, y)``: ``(t, cx, cy, d^2)``."""
    dx, dy = x1 - x0, y1 - y0
    A = dx * dx + dy * dy
    t = ((x - x0) * dx + (y - y0) * dy) / A if A > 0 else 0.0
    t = min(max(t, 0.0), 1.0)
    cx, cy = x0 + t * dx, y0 + t * dy
    return t, cx, cy, (cx - x) ** 2 + (cy - y) ** 2


@nb.njit(cache=True)
def locate(points, curve):
    """Nearest point on the closed polyline ``curve`` to each of ``points``.

    Returns edge index, parameter on the edge and the point, per input point:
    the first edge (in order) at the least distance. The edges go by in
    blocks (:func:`edge_boxes`); a block further from the point than the
    nearest edge of the block nearest to it (beyond rounding) is passed over.
    """
    b = points.shape[0]
    m = curve.shape[0]
    boxes = edge_boxes(curve)
    nb_ = _n_blocks(m)
    ext = 0.0
    for k in range(nb_):
        ext = max(ext, abs(boxes[k, 0]), abs(boxes[k, 1]), abs(boxes[k, 2]), abs(boxes[k, 3]))
    es = np.empty(b, np.int64)
    ts = np.empty(b)
    out = np.empty((b, 2))
    for q in range(b):
        qx, qy = points[q, 0], points[q, 1]
        near, gap = 0, np.inf
        for k in range(nb_):
            g = _box_gap2(boxes, k, qx, qy)
            if g < gap:
                near, gap = k, g
        # a bound on the least distance: the nearest edge of the nearest block
        bound = np.inf
        for i in range(near * BOX_EDGES, min(near * BOX_EDGES + BOX_EDGES, m)):
            i2 = i + 1 if i + 1 < m else 0
            d = _foot(qx, qy, curve[i, 0], curve[i, 1], curve[i2, 0], curve[i2, 1])[3]
            bound = min(bound, d)
        reach = np.sqrt(bound) + 1e-9 * (np.sqrt(bound) + ext)
        best = np.inf
        for k in range(nb_):
            if _box_gap2(boxes, k, qx, qy) > reach * reach:
                continue
            for i in range(k * BOX_EDGES, min(k * BOX_EDGES + BOX_EDGES, m)):
                i2 = i + 1 if i + 1 < m else 0
                t, cx, cy, d = _foot(qx, qy, curve[i, 0], curve[i, 1], curve[i2, 0], curve[i2, 1])
                if d < best:
                    best = d
                    es[q], ts[q], out[q, 0], out[q, 1] = i, t, cx, cy
    return es, ts, out


@nb.njit(cache=True)
def _rest_candidates(ax, ay, ux, uy, ln, x0, y0, x1, y1, has_edge, tip_on, angs, px, py, on, c):
    """Add the places a link from ``a`` can rest on point ``p0`` or segment ``p0-p1``.

    A link pivoting on ``a`` rests on ``p0`` within its reach (tip in the air
    beyond it), or has its tip on the segment at distance ``ln``. Each
    candidate's rotation from ``u`` goes to ``angs``, its tip to ``px, py``;
    returns the new count.
    """
    vx, vy = x0 - ax, y0 - ay
    d2 = vx * vx + vy * vy
    if 1e-24 * ln * ln < d2 <= ln * ln:
        r = np.sqrt(d2)
        angs[c] = np.arctan2(ux * vy - uy * vx, ux * vx + uy * vy)
        px[c], py[c] = ax + ln * vx / r, ay + ln * vy / r
        c += 1
    if not has_edge:
        return c
    dx, dy = x1 - x0, y1 - y0
    A = dx * dx + dy * dy
    B = 2.0 * (vx * dx + vy * dy)
    C0 = d2 - ln * ln
    disc = B * B - 4.0 * A * C0
    if A > 0 and disc >= 0:
        sq = np.sqrt(disc)
        for t in ((-B - sq) / (2.0 * A), (-B + sq) / (2.0 * A)):
            if 0.0 <= t <= 1.0:
                wx, wy = vx + t * dx, vy + t * dy
                angs[c] = np.arctan2(ux * wy - uy * wx, ux * wx + uy * wy)
                px[c], py[c] = ax + wx, ay + wy
                on[c] = tip_on
                c += 1
    return c


#: Relative margin (on squared distances) by which a block of edges must lie
#: beyond a link's reach for the candidates of a turning link to skip it.
_REACH_MARGIN = 1e-4


@nb.njit(cache=True)
def _outline_candidates(ax, ay, ux, uy, ln, obj, boxes, angs, px, py, on, c):
    """:func:`_rest_candidates` of every outline vertex and edge, in order; returns the count.

    Blocks of edges whose box lies beyond the link's reach offer none and are
    skipped (``boxes``: :func:`edge_boxes` of ``obj``).
    """
    m = obj.shape[0]
    far = ln * ln * (1.0 + _REACH_MARGIN)
    i = _next_near_edge(boxes, m, 0, ax, ay, far)
    while i < m:
        i2 = i + 1 if i + 1 < m else 0
        c = _rest_candidates(ax, ay, ux, uy, ln, obj[i, 0], obj[i, 1], obj[i2, 0],
                             obj[i2, 1], True, True, angs, px, py, on, c)  # fmt: skip
        i = _next_near_edge(boxes, m, i + 1, ax, ay, far)
    return c


@nb.njit(cache=True)
def free_direction(ax, ay, ux, uy, ln, obj, eps, boxes):
    """Turn a blocked link (from ``a`` along ``u``) clockwise until it is free.

    The link pivots on ``a`` and stops where it first rests on the object:
    on an outline vertex within its length (tip in the air) or with its tip on
    an edge. Candidates are tried from the least rotation on. Returns
    ``(found, tip_x, tip_y, tip_on_outline)``. ``boxes``: :func:`edge_boxes` of ``obj``.
    """
    m = obj.shape[0]
    angs = np.empty(3 * m)
    px = np.empty(3 * m)
    py = np.empty(3 * m)
    on = np.zeros(3 * m, np.bool_)
    c = _outline_candidates(ax, ay, ux, uy, ln, obj, boxes, angs, px, py, on, 0)
    order = np.argsort(-angs[:c])
    for t in order:
        if not (-np.pi + 1e-9 < angs[t] <= 1e-12):
            continue
        if crossing_edge_boxed(ax, ay, px[t], py[t], obj, eps, boxes) < 0:
            return True, px[t], py[t], on[t]
    return False, ax, ay, False


@nb.njit(cache=True)
def crossing_link(ax, ay, bx, by, joints, last, eps):
    """First link ``t < last`` (``joints[t] -> joints[t + 1]``) that a-b crosses, or -1.

    A crossing passes from one side of the link to the other: touching it,
    ending on it and lying along it do not count.
    """
    lox, hix = min(ax, bx), max(ax, bx)
    loy, hiy = min(ay, by), max(ay, by)
    for t in range(last):
        px, py = joints[t, 0], joints[t, 1]
        qx, qy = joints[t + 1, 0], joints[t + 1, 1]
        if (px < lox and qx < lox) or (px > hix and qx > hix):
            continue
        if (py < loy and qy < loy) or (py > hiy and qy > hiy):
            continue
        o1, o2 = _sides(ax, ay, bx, by, px, py, qx, qy)
        if _apart(o1, o2, eps):
            o3, o4 = _sides(px, py, qx, qy, ax, ay, bx, by)
            if _apart(o3, o4, eps):
                return t
    return -1


@nb.njit(cache=True)
def inside(x, y, obj, eps):
    """True if the point lies inside the polygon ``obj`` further than ``eps`` from its outline."""
    m = obj.shape[0]
    wn = False
    dmin = np.inf
    for i in range(m):
        i2 = i + 1 if i + 1 < m else 0
        x0, y0, x1, y1 = obj[i, 0], obj[i, 1], obj[i2, 0], obj[i2, 1]
        if (y0 > y) != (y1 > y):
            if x < x0 + (y - y0) * (x1 - x0) / (y1 - y0):
                wn = not wn
        dx, dy = x1 - x0, y1 - y0
        A = dx * dx + dy * dy
        t = ((x - x0) * dx + (y - y0) * dy) / A if A > 0 else 0.0
        t = min(max(t, 0.0), 1.0)
        d = (x0 + t * dx - x) ** 2 + (y0 + t * dy - y) ** 2
        dmin = min(dmin, d)
    return wn and dmin > eps * eps


@nb.njit(cache=True)
def inside_boxed(x, y, obj, eps, boxes):
    """:func:`inside`, visiting only the blocks of edges that can decide it.

    A block wholly above or below the point flips no crossing parity, and one
    further than ``2 eps`` from it holds no edge within ``eps``.
    """
    m = obj.shape[0]
    nb_ = _n_blocks(m)
    ng = boxes.shape[0] - nb_
    wn = False
    for g in range(ng):
        if boxes[nb_ + g, 2] > y or boxes[nb_ + g, 3] <= y:
            continue
        for b in range(g * BOX_GROUP, min(g * BOX_GROUP + BOX_GROUP, nb_)):
            if boxes[b, 2] > y or boxes[b, 3] <= y:
                continue
            lo = b * BOX_EDGES
            for i in range(lo, min(lo + BOX_EDGES, m)):
                i2 = i + 1 if i + 1 < m else 0
                x0, y0, x1, y1 = obj[i, 0], obj[i, 1], obj[i2, 0], obj[i2, 1]
                if (y0 > y) != (y1 > y):
                    if x < x0 + (y - y0) * (x1 - x0) / (y1 - y0):
                        wn = not wn
    if not wn:
        return False
    far = 4.0 * eps * eps
    i = _next_near_edge(boxes, m, 0, x, y, far)
    while i < m:
        i2 = i + 1 if i + 1 < m else 0
        if not _foot(x, y, obj[i, 0], obj[i, 1], obj[i2, 0], obj[i2, 1])[3] > eps * eps:
            return False
        i = _next_near_edge(boxes, m, i + 1, x, y, far)
    return True


@nb.njit(cache=True)
def enters_convex(ax, ay, bx, by, hull, eps):
    """True if segment a-b has points inside the convex ccw polygon ``hull``.

    Inside means on the inner side of every edge by more than ``eps`` in
    signed area (edge vector cross offset): the side test with which
    :func:`crossing_edge` tells a segment's ends apart, so that a segment it
    finds crossing an object edge on the hull does enter, however shallow the
    sliver it cuts. Ending on the outline or touching it does not count. The
    segment is clipped to each edge's inner half-plane in turn (Cyrus-Beck).
    """
    m = hull.shape[0]
    t_lo, t_hi = 0.0, 1.0
    for i in range(m):
        i2 = i + 1 if i + 1 < m else 0
        ex, ey = hull[i2, 0] - hull[i, 0], hull[i2, 1] - hull[i, 1]
        if ex == 0.0 and ey == 0.0:
            continue
        fa = ex * (ay - hull[i, 1]) - ey * (ax - hull[i, 0]) - eps
        fb = ex * (by - hull[i, 1]) - ey * (bx - hull[i, 0]) - eps
        if fa <= 0.0 and fb <= 0.0:
            return False
        if fa > 0.0 and fb > 0.0:
            continue
        t = fa / (fa - fb)
        if fa <= 0.0:
            t_lo = max(t_lo, t)
        else:
            t_hi = min(t_hi, t)
        if t_hi <= t_lo:
            return False
    return True


@nb.njit(cache=True)
def blocked(ax, ay, bx, by, obj, eps, joints, last, boxes):
    """True if segment a-b enters the object or crosses one of the first ``last`` links.

    No cap allowance: a segment between two points of the outline through the
    object's inside is blocked. ``boxes``: :func:`edge_boxes` of ``obj``.
    """
    if crossing_edge_boxed(ax, ay, bx, by, obj, eps, boxes) >= 0:
        return True
    if crossing_link(ax, ay, bx, by, joints, last, eps) >= 0:
        return True
    return inside_boxed(0.5 * (ax + bx), 0.5 * (ay + by), obj, np.sqrt(eps), boxes)


@nb.njit(cache=True)
def free_direction_links(ax, ay, ux, uy, ln, obj, eps, joints, last, boxes):
    """Turn a blocked link (from ``a`` along ``u``) clockwise until it is free.

    The link pivots on ``a`` and stops where it first rests on the object or on
    one of the first ``last`` links of the chain; candidates are tried from the
    least rotation on: outline vertices and earlier joints within reach (the link
    rests on them, tip in the air), and the points of the outline and of the
    earlier links at distance ``ln`` (the tip rests there). Returns
    ``(found, tip_x, tip_y, tip_on_outline)``; ``found`` is False when every
    direction up to a half turn clockwise is blocked.
    """
    m = obj.shape[0]
    size = 3 * m + 3 * (last + 1) + 65
    angs = np.empty(size)
    px = np.empty(size)
    py = np.empty(size)
    on = np.zeros(size, np.bool_)
    c = _outline_candidates(ax, ay, ux, uy, ln, obj, boxes, angs, px, py, on, 0)
    for i in range(last + 1):
        x0, y0 = joints[i, 0], joints[i, 1]
        has_edge = i < last
        x1, y1 = (joints[i + 1, 0], joints[i + 1, 1]) if has_edge else (x0, y0)
        c = _rest_candidates(ax, ay, ux, uy, ln, x0, y0, x1, y1, has_edge, False,
                             angs, px, py, on, c)  # fmt: skip
    # directions every 1/128 turn: the link free in the air
    r = np.hypot(ux, uy)
    for s in range(1, 65):
        ang = -s * np.pi / 64 + 2e-9
        ca, sa = np.cos(ang), np.sin(ang)
        angs[c] = ang
        px[c] = ax + ln * (ca * ux - sa * uy) / r
        py[c] = ay + ln * (sa * ux + ca * uy) / r
        c += 1
    order = np.argsort(-angs[:c])
    for t in order:
        if not (-np.pi + 1e-9 < angs[t] <= 1e-12):
            continue
        if not blocked(ax, ay, px[t], py[t], obj, eps, joints, last, boxes):
            return True, px[t], py[t], on[t]
    return False, ax, ay, False


@nb.njit(cache=True)
def outline_distances(points, obj, boxes):
    """Distance from each point to the closed polyline ``obj`` (``boxes``: :func:`edge_boxes`).

    The least distance to any edge, each edge's distance rounded as GEOS
    rounds it, so that the values equal shapely's ``distance`` to the ring.
    Blocks of edges whose box lies further than the best distance so far are
    passed over; the search starts at the block nearest the previous point.
    """
    m = obj.shape[0]
    nb_ = _n_blocks(m)
    ext = 0.0
    for b in range(nb_):
        ext = max(ext, abs(boxes[b, 0]), abs(boxes[b, 1]), abs(boxes[b, 2]), abs(boxes[b, 3]))
    out = np.empty(points.shape[0])
    hint = 0
    for q in range(points.shape[0]):
        x, y = points[q, 0], points[q, 1]
        best = np.inf
        first = hint
        for step in range(nb_):
            b = first + step
            if b >= nb_:
                b -= nb_
            # a box further than the best (beyond rounding) holds no nearer edge
            if np.sqrt(_box_gap2(boxes, b, x, y)) > best + 1e-9 * (best + ext):
                continue
            lo = b * BOX_EDGES
            for i in range(lo, min(lo + BOX_EDGES, m)):
                i2 = i + 1 if i + 1 < m else 0
                d = _point_segment_distance(x, y, obj[i, 0], obj[i, 1], obj[i2, 0], obj[i2, 1])
                if d < best:
                    best = d
                    hint = b
        out[q] = best
    return out


plain_calls(globals())
