"""Compiled inner loop of the wrap: chord walking along a support track.

Hand-written because no library walks a chain of fixed-length links along a
polyline (circle-segment intersections searched forward) with a crossing test
per link; numba compiles it (``cache=True``: compiled once per machine).

Data layout (built by ``_surface``): ``pts`` holds the vertices of every lap
curve back to back, curve ``c`` at ``pts[off[c]:off[c + 1]]``; ``theta`` the
unwrapped direction of each curve edge; ``dev`` how far an edge of curve 0
strays from the object's outline (0 where it is an outline edge). A wrap's
*track* is: the approach segment (base -> start point ``S_0``), then lap 0
on curve 0 from ``S_0`` round to ``S_0``, then lap 1 on curve
``min(1, C - 1)`` from its start point ``S_1``, and so on.
"""

from __future__ import annotations

import numba as nb
import numpy as np

from .._jit import plain_calls
from ._geom import (
    TWO_PI,
    _foot,
    _near,
    crosses,
    crosses_boxed,
    crosses_range_boxed,
    crossing_edge_boxed,
    edge_boxes,
    enters_convex,
    free_direction,
    free_direction_links,
    locate,
)

__all__ = ["crosses", "locate", "walk", "walk_many"]

STATUS_COMPLETE = 0
#: Fraction of a link within which the approach's last joint lands on the start point.
LANDING = 0.25


@nb.njit(cache=True, inline="always")
def _edge_heading(k, j, c, o, m, theta, es, th0):
    """Unwrapped direction of segment ``j`` (an edge of curve ``c``) of lap ``k``."""
    ee = es[c] + j
    return theta[o + ee % m] + TWO_PI * (ee // m) + (th0 + TWO_PI * k - theta[o + es[c]])


@nb.njit(cache=True)
def _segment(k, j, pts, off, theta, dev, es, spt, th0, base, app_th, n_laps):
    """Segment ``j`` of lap ``k`` (``k == -1``: the approach).

    Returns ``x0, y0, x1, y1, theta, deviation, n_segments_in_lap``; the
    deviation is how far the segment strays from the object's outline (inf for
    segments that are not on curve 0).
    """
    if k < 0:
        return base[0], base[1], spt[0, 0], spt[0, 1], app_th, np.inf, 1
    n_curves = off.shape[0] - 1
    c = min(k, n_curves - 1)
    o = off[c]
    m = off[c + 1] - o
    e0 = es[c]
    c_next = min(k + 1, n_curves - 1)
    nseg = m + 1
    if c_next != c and k + 1 < n_laps:
        nseg = m + 2
    shift = th0 + TWO_PI * k - theta[o + e0]
    if j == m + 1:  # transition to the next lap's curve
        x0, y0 = spt[c, 0], spt[c, 1]
        x1, y1 = spt[c_next, 0], spt[c_next, 1]
        th = _near(np.arctan2(y1 - y0, x1 - x0), theta[o + e0] + shift + TWO_PI)
        return x0, y0, x1, y1, th, np.inf, nseg
    ee = e0 + j
    i0 = o + ee % m
    th = theta[i0] + TWO_PI * (ee // m) + shift
    on = dev[i0] if c == 0 else np.inf
    if j == 0:
        i1 = o + (e0 + 1) % m
        return spt[c, 0], spt[c, 1], pts[i1, 0], pts[i1, 1], th, on, nseg
    if j == m:
        return pts[i0, 0], pts[i0, 1], spt[c, 0], spt[c, 1], th, on, nseg
    i1 = o + (ee + 1) % m
    return pts[i0, 0], pts[i0, 1], pts[i1, 0], pts[i1, 1], th, on, nseg


@nb.njit(cache=True)
def _virtual_heading(ln, pts, off, theta, es, spt, th0):
    """Heading of the chord arriving at ``S_0`` from one link length behind it on curve 0."""
    o = off[0]
    m = off[1] - o
    e0 = es[0]
    ax, ay = spt[0, 0], spt[0, 1]
    x0, y0 = ax, ay
    shift = th0 - theta[o + e0]
    for step in range(m + 1):
        ee = e0 - step
        i0 = o + ee % m
        x1, y1 = pts[i0, 0], pts[i0, 1]
        dx, dy = x1 - x0, y1 - y0
        A = dx * dx + dy * dy
        if A > 0:
            fx, fy = x0 - ax, y0 - ay
            B = 2.0 * (fx * dx + fy * dy)
            C0 = fx * fx + fy * fy - ln * ln
            disc = B * B - 4.0 * A * C0
            if disc >= 0:
                tau = (-B + np.sqrt(disc)) / (2.0 * A)
                if tau <= 1.0:
                    px, py = x0 + tau * dx, y0 + tau * dy
                    # theta of edge ee (unwrapped, may be negative index)
                    th_e = theta[i0] + TWO_PI * np.floor(ee / m) + shift
                    return _near(np.arctan2(ay - py, ax - px), 0.5 * (th_e + th0))
        x0, y0 = x1, y1
    return th0


#: Edges per block of :func:`track_blocks`.
TRACK_BLOCK = 16
#: Relative margin (on squared distances) by which a block of the track must
#: lie inside or outside a link's circle for the search to pass it unexamined.
_BLOCK_MARGIN = 1e-4


@nb.njit(cache=True)
def track_blocks(pts, off, dev):
    """Summaries of the lap curves for the forward search, per block of ``TRACK_BLOCK`` edges.

    Returns ``(boff, boxes, top_dev, seg_len)``: the blocks of curve ``c`` are
    ``boff[c] .. boff[c + 1] - 1`` (whole blocks only, local edges ``16 b ..
    16 b + 15``), each with the bounding box ``(x_min, x_max, y_min, y_max)``
    of its 17 vertices and the largest deviation of its edges of nonzero
    length (``-inf`` if none; ``inf`` off curve 0); ``seg_len`` is each edge's
    length as the search adds it up.
    """
    n_curves = off.shape[0] - 1
    boff = np.zeros(n_curves + 1, np.int64)
    for c in range(n_curves):
        boff[c + 1] = boff[c] + (off[c + 1] - off[c]) // TRACK_BLOCK
    boxes = np.empty((boff[n_curves], 4))
    top_dev = np.full(boff[n_curves], -np.inf)
    seg_len = np.zeros(pts.shape[0])
    for c in range(n_curves):
        o = off[c]
        m = off[c + 1] - o
        for e in range(m):
            i1 = o + e + 1 if e + 1 < m else o
            dx, dy = pts[i1, 0] - pts[o + e, 0], pts[i1, 1] - pts[o + e, 1]
            A = dx * dx + dy * dy
            if A > 0:
                seg_len[o + e] = np.sqrt(A)
        for b in range(boff[c + 1] - boff[c]):
            bi = boff[c] + b
            lo = b * TRACK_BLOCK
            boxes[bi, 0], boxes[bi, 1] = np.inf, -np.inf
            boxes[bi, 2], boxes[bi, 3] = np.inf, -np.inf
            for v in range(lo, lo + TRACK_BLOCK + 1):
                i = o + (v if v < m else v - m)
                x, y = pts[i, 0], pts[i, 1]
                boxes[bi, 0], boxes[bi, 1] = min(boxes[bi, 0], x), max(boxes[bi, 1], x)
                boxes[bi, 2], boxes[bi, 3] = min(boxes[bi, 2], y), max(boxes[bi, 3], y)
            for e in range(lo, lo + TRACK_BLOCK):
                if seg_len[o + e] > 0:
                    d = dev[o + e] if c == 0 else np.inf
                    top_dev[bi] = max(top_dev[bi], d)
    return boff, boxes, top_dev, seg_len


@nb.njit(cache=True, inline="always")
def _clear_of_circle(box, ax, ay, ln):
    """The box lies wholly inside or wholly outside the circle of radius ``ln`` about ``a``."""
    ddx = max(box[0] - ax, ax - box[1], 0.0)
    ddy = max(box[2] - ay, ay - box[3], 0.0)
    r2 = ln * ln
    if ddx * ddx + ddy * ddy > r2 * (1.0 + _BLOCK_MARGIN):
        return True
    fx = max(ax - box[0], box[1] - ax)
    fy = max(ay - box[2], box[3] - ay)
    return fx * fx + fy * fy < r2 * (1.0 - _BLOCK_MARGIN)


@nb.njit(cache=True, inline="always")
def _root(ax, ay, ln, px, py, dx, dy, A, skip_first):
    """First ``tau`` in [0, 1] where ``p + tau d`` lies at distance ``l`` from ``a``, or -1.

    ``tau = 0`` counts only for a start inside the circle and not after a
    rejected point (``skip_first``), which also skips roots within ``1e-9 l``.
    """
    fx, fy = px - ax, py - ay
    B = 2.0 * (fx * dx + fy * dy)
    C0 = fx * fx + fy * fy - ln * ln
    disc = B * B - 4.0 * A * C0
    if disc >= 0:
        sq = np.sqrt(disc)
        lo = 1e-9 * ln / np.sqrt(A) if skip_first else 0.0
        for tau in ((-B - sq) / (2.0 * A), (-B + sq) / (2.0 * A)):
            if lo < tau <= 1.0 or (tau == 0.0 and not skip_first and C0 <= 0):
                return tau
    return -1.0


@nb.njit(cache=True)
def _search(
    ax,
    ay,
    ln,
    k,
    j,
    px,
    py,
    skip_first,
    slack,
    limit,
    pts,
    off,
    theta,
    dev,
    es,
    spt,
    th0,
    base,
    app_th,
    n_laps,
    boff,
    tboxes,
    top_dev,
    seg_len,
):
    """Next point of the track after cursor ``(k, j, p)`` at distance ``l`` from ``a``.

    Returns ``(status, k, j, x, y, theta, deviation, bridged, walked)``; status 0
    found, 1 nothing within ``limit`` of arc, 2 out of laps. ``skip_first``
    ignores a root at the cursor itself (continuing after a rejected point).
    ``boff, tboxes, top_dev, seg_len``: :func:`track_blocks` of the lap
    curves; whole blocks of edges that lie clear of the link's circle are
    passed without solving for roots.
    """
    n_curves = off.shape[0] - 1
    bridged = False
    walked = 0.0
    first = True
    while True:
        if k >= 0 and not first:
            c = min(k, n_curves - 1)
            o = off[c]
            m = off[c + 1] - o
            if 1 <= j <= m - 1:
                # the edges of the lap curve between the lap's ends, after the
                # first segment searched (the cursor's own, often the last)
                e = (es[c] + j) % m
                while j <= m - 1:
                    if e % TRACK_BLOCK == 0 and e + TRACK_BLOCK <= m and j + TRACK_BLOCK <= m:
                        bi = boff[c] + e // TRACK_BLOCK
                        if _clear_of_circle(tboxes[bi], ax, ay, ln):
                            w = walked
                            for s in range(TRACK_BLOCK):
                                w += seg_len[o + e + s]
                                if w > limit:
                                    break
                            if w <= limit:
                                walked = w
                                if top_dev[bi] > slack:
                                    bridged = True
                                j += TRACK_BLOCK
                                e = e + TRACK_BLOCK if e + TRACK_BLOCK < m else 0
                                px, py = pts[o + e, 0], pts[o + e, 1]
                                continue
                    i1 = o + e + 1 if e + 1 < m else o
                    x1, y1 = pts[i1, 0], pts[i1, 1]
                    dx, dy = x1 - px, y1 - py
                    A = dx * dx + dy * dy
                    if A > 0:
                        dv = dev[o + e] if c == 0 else np.inf
                        if dv > slack:
                            bridged = True
                        tau = _root(ax, ay, ln, px, py, dx, dy, A, skip_first)
                        if tau >= 0.0:
                            th = _edge_heading(k, j, c, o, m, theta, es, th0)
                            return 0, k, j, px + tau * dx, py + tau * dy, th, dv, bridged, walked
                        walked += np.sqrt(A)
                    skip_first = False
                    if walked > limit:
                        th = _edge_heading(k, j, c, o, m, theta, es, th0)
                        dv = dev[o + e] if c == 0 else np.inf
                        return 1, k, j, px, py, th, dv, bridged, walked
                    j += 1
                    px, py = x1, y1
                    e = e + 1 if e + 1 < m else 0
                continue
        seg = _segment(k, j, pts, off, theta, dev, es, spt, th0, base, app_th, n_laps)
        x1, y1, th, dv, nseg = seg[2], seg[3], seg[4], seg[5], seg[6]
        dx, dy = x1 - px, y1 - py
        A = dx * dx + dy * dy
        if A > 0:
            if dv > slack:
                bridged = True
            tau = _root(ax, ay, ln, px, py, dx, dy, A, skip_first)
            if tau >= 0.0:
                return 0, k, j, px + tau * dx, py + tau * dy, th, dv, bridged, walked
            walked += np.sqrt(A)
        skip_first = False
        first = False
        if walked > limit:
            return 1, k, j, px, py, th, dv, bridged, walked
        j += 1
        px, py = x1, y1
        if j >= nseg:
            k += 1
            j = 0
            if k >= n_laps:
                return 2, k, j, px, py, th, dv, bridged, walked


@nb.njit(cache=True)
def _fold_in(i, ax, ay, ln, obj, eps, joints, phi, boxes):
    """Where link ``i`` goes when the track offers it nothing: a chain always ends somewhere.

    The link folds in towards the object from nearly a half turn left of the
    previous link and stops at the first thing it meets (the object or an
    earlier link; tip in the air); wedged, it folds back onto the previous
    link. The first link, with no link to fold back onto, turns on away from
    the object instead, to the first place it rests free. Returns the tip.
    """
    ph = phi[i - 1]
    last = max(i - 2, 0)
    ux, uy = np.cos(ph + 0.99 * np.pi), np.sin(ph + 0.99 * np.pi)
    ok, xx, xy, _ = free_direction_links(ax, ay, ux, uy, ln, obj, eps, joints, last, boxes)
    if ok:
        return xx, xy
    if i >= 2:
        return joints[i - 2, 0], joints[i - 2, 1]
    ux, uy = np.cos(ph - 0.01 * np.pi), np.sin(ph - 0.01 * np.pi)
    ok, xx, xy, _ = free_direction_links(ax, ay, ux, uy, ln, obj, eps, joints, last, boxes)
    if ok:
        return xx, xy
    return ax - ln * np.cos(ph), ay - ln * np.sin(ph)


@nb.njit(cache=True)
def _relocate(x, y, k, j, px, py, pts, off, es):
    """Move the cursor ``(k, j, p)`` forward to the point of its lap curve nearest to ``(x, y)``.

    The cursor never moves back: if the nearest point lies behind it, it stays.
    """
    bj, bx, by, _ = _nearest_on_curve(x, y, k, j, px, py, pts, off, es)
    if bj > j:
        return k, bj, bx, by
    return k, j, px, py


@nb.njit(cache=True)
def _nearest_on_curve(x, y, k, j, px, py, pts, off, es):
    """The point of lap ``k``'s curve nearest to ``(x, y)``.

    Returns its segment index (counted from the lap's start), the point and
    its squared distance; ``(j, px, py, inf)`` on the approach (``k < 0``).
    """
    if k < 0:
        return j, px, py, np.inf
    n_curves = off.shape[0] - 1
    c = min(k, n_curves - 1)
    o = off[c]
    m = off[c + 1] - o
    best = np.inf
    bj, bx, by = j, px, py
    for e in range(m):
        i0 = o + e
        i1 = o + (e + 1) % m
        _, cx, cy, d = _foot(x, y, pts[i0, 0], pts[i0, 1], pts[i1, 0], pts[i1, 1])
        if d < best:
            best = d
            bj = (e - es[c]) % m
            bx, by = cx, cy
    return bj, bx, by, best


@nb.njit(cache=True)
def walk(
    n,
    ln,
    pts,
    off,
    theta,
    dev,
    obj,
    eps,
    es,
    spt,
    th0,
    base,
    app_th,
    approach,
    check,
    n_laps,
    max_search,
    slack,
    exact,
    bridge_limit,
    vidx,
    boxes,
    track,
    joints,
    contact,
    lap,
    phi,
):
    """Place ``n`` links; fill ``joints`` (n+1, 2), ``contact``, ``lap`` and ``phi`` (n+1).

    ``check``: 0 never test crossings; 2 test links that do not join two points
    of the object's own edges (caps of the outline are allowed; anything
    bridging or in the air is tested) and let a crossing link rest on the
    corner it passes; 3 as 2, but first look further along (up to
    ``bridge_limit`` of arc) for a point the link can reach without crossing.
    ``vidx`` (taut): the outline index of each hull vertex; a link between two
    points of curve 0 across a pocket is then only tested against the outline
    between the hull vertices around it (the part of the object its hull cap
    holds but for pockets of other hull edges reaching in under it), as
    is a link from a tip beyond the hull vertex its link rests on; a link from
    another joint in the air, against the whole outline if it enters the hull;
    a chord joining two points of the object's own hull edges round a hull
    vertex, against the outline beyond the hull edges it spans (a pocket that
    reaches in under it).
    ``boxes``: :func:`edge_boxes` of ``obj``; ``track``: :func:`track_blocks` of the curves.
    Returns ``(status, n_placed, phi_virtual)``.
    """
    m0 = off[1] - off[0]
    m_obj = obj.shape[0]
    boff, tboxes, top_dev, seg_len = track
    k = -1 if approach else 0
    j = 0
    if approach:
        px, py = base[0], base[1]
    else:
        px, py = spt[0, 0], spt[0, 1]
    seg = _segment(k, j, pts, off, theta, dev, es, spt, th0, base, app_th, n_laps)
    a_th = seg[4]
    a_on = seg[5] <= exact and not approach
    a_sup = seg[5] <= slack and not approach
    # An approach joint that ends just above the start point (less than
    # LANDING of a link) counts as resting on the support: the next link
    # reaches down onto it, cutting the cap it spans, instead of floating.
    land = LANDING * ln
    if approach and np.hypot(base[0] - spt[0, 0], base[1] - spt[0, 1]) <= land:
        a_sup = True
    a_rest = False  # the joint is a tip beyond the hull vertex its link rests on
    ax, ay = px, py
    joints[0, 0], joints[0, 1] = ax, ay
    contact[0] = a_on and k == 0
    lap[0] = k
    phi_v = _virtual_heading(ln, pts, off, theta, es, spt, th0)
    phi[0] = app_th if approach else phi_v
    status = STATUS_COMPLETE
    placed = 0
    for i in range(1, n + 1):
        sk, sj, spx, spy = k, j, px, py
        r = _search(
            ax,
            ay,
            ln,
            k,
            j,
            px,
            py,
            False,
            slack,
            max_search,
            pts,
            off,
            theta,
            dev,
            es,
            spt,
            th0,
            base,
            app_th,
            n_laps,
            boff,
            tboxes,
            top_dev,
            seg_len,
        )
        if r[0] != 0:
            # nothing of the track at a link's length ahead: the link folds in
            xx, xy = _fold_in(i, ax, ay, ln, obj, eps, joints, phi, boxes)
            phi[i] = _near(np.arctan2(xy - ay, xx - ax), phi[i - 1])
            joints[i, 0], joints[i, 1] = xx, xy
            contact[i] = False
            lap[i] = -1
            k, j, px, py = _relocate(xx, xy, k, j, px, py, pts, off, es)
            ax, ay, a_th, a_sup, a_rest = xx, xy, phi[i], False, False
            placed = i
            continue
        k, j, xx, xy, x_th, x_dev = r[1], r[2], r[3], r[4], r[5], r[6]
        bridged = r[7] or not a_sup
        if sk < 0 and a_sup and k >= 0:  # from a landing approach joint onto the lap
            bridged = x_dev > slack
        overhang = False
        cross = False
        x_rest = False
        if check >= 2 and bridged:
            if vidx.shape[0] > 0 and lap[i - 1] < 0 and not a_rest:
                # from a joint in the air (other than a tip beyond the hull
                # vertex its link rests on) only a link that enters the hull
                # can meet the object, anywhere in it
                if enters_convex(ax, ay, xx, xy, pts[off[0] : off[1]], eps):
                    cross = crosses_boxed(ax, ay, xx, xy, obj, eps, boxes)
            elif (
                vidx.shape[0] > 0
                and sk >= 0
                and k >= 0
                and min(sk, k) < n_laps
                and (off.shape[0] == 2 or max(sk, k) == 0)
                and sj <= m0
                and j <= m0
            ):
                i0 = vidx[(es[0] + sj) % m0] - 1
                i1 = vidx[(es[0] + j + 1) % m0]
                # the outline edges under the hull edges spanned, one more either side
                cnt = min((i1 - i0 - 1) % m_obj + 3, m_obj)
                if (k - sk) * m0 + j - sj >= m0 - 1:
                    cnt = m_obj
                cross = crosses_range_boxed(ax, ay, xx, xy, obj, eps, i0 % m_obj, cnt, boxes)
            else:
                cross = crosses_boxed(ax, ay, xx, xy, obj, eps, boxes)
        elif (
            check >= 2
            and 0 < vidx.shape[0] < m_obj
            and sk >= 0
            and k >= 0
            and (k != sk or j != sj)
            and (off.shape[0] == 2 or max(sk, k) == 0)
            and sj <= m0
            and j <= m0
            and (k - sk) * m0 + j - sj < m0 - 1
        ):
            # A chord between two points of the object's own hull edges cuts
            # the corners it passes, which are the object's; but a pocket under
            # another hull edge may reach in under it (a link nearly as long as
            # the object): it must not cross the outline beyond its stretch.
            i0 = vidx[(es[0] + j + 1) % m0]
            i1 = vidx[(es[0] + sj) % m0]
            cnt = (i1 - i0) % m_obj
            if cnt > 0:
                cross = crosses_range_boxed(ax, ay, xx, xy, obj, eps, i0, cnt, boxes)
        if cross:
            overhang = True
            if check == 3:  # look further along for a point the link can reach
                ck, cj, cx, cy, used = k, j, xx, xy, 0.0
                for _ in range(10000):
                    if used >= bridge_limit:
                        break
                    r2 = _search(
                        ax,
                        ay,
                        ln,
                        ck,
                        cj,
                        cx,
                        cy,
                        True,
                        slack,
                        bridge_limit - used,
                        pts,
                        off,
                        theta,
                        dev,
                        es,
                        spt,
                        th0,
                        base,
                        app_th,
                        n_laps,
                        boff,
                        tboxes,
                        top_dev,
                        seg_len,
                    )
                    if r2[0] != 0:
                        break
                    used += r2[8]
                    ck, cj, cx, cy = r2[1], r2[2], r2[3], r2[4]
                    if not crosses_boxed(ax, ay, cx, cy, obj, eps, boxes):
                        k, j, xx, xy, x_th, x_dev = ck, cj, cx, cy, r2[5], r2[6]
                        overhang = False
                        break
        if overhang:
            # The chord would cut through the object: the link rests on the
            # most clockwise vertex passed (the tangent seen from the joint)
            # and its tip stays in the air.
            ux, uy = xx - ax, xy - ay
            best = np.inf
            wk, wj, wx, wy, w_th = 0, 0, 0.0, 0.0, 0.0
            ck, cj = sk, sj
            while not (ck == k and cj == j):
                s2 = _segment(ck, cj, pts, off, theta, dev, es, spt, th0, base, app_th, n_laps)
                vx, vy = s2[2] - ax, s2[3] - ay
                if vx * vx + vy * vy > 1e-24 * ln * ln:
                    ang = np.arctan2(ux * vy - uy * vx, ux * vx + uy * vy)
                    if ang < best:
                        best = ang
                        wk, wj, wx, wy, w_th = ck, cj, s2[2], s2[3], s2[4]
                cj += 1
                if cj >= s2[6]:
                    ck += 1
                    cj = 0
            if best == np.inf:  # nothing passed: rest where the cursor is
                wk, wj, wx, wy, w_th = sk, sj, spx, spy, a_th
                xx, xy = ax + ux, ay + uy
            else:
                rr = np.hypot(wx - ax, wy - ay)
                xx, xy = ax + ln * (wx - ax) / rr, ay + ln * (wy - ay) / rr
                x_rest = rr <= ln
            # On a convex support (the hull) a link that stays outside the
            # hull is free (a folded link's tip can lie inside the hull, and
            # the vertex rested on need not be the tangent one). Otherwise it
            # may still be blocked: turn it on clockwise to the first outline
            # vertex where it is free.
            convex = vidx.shape[0] > 0 and (off.shape[0] == 2 or wk == 0)
            if convex and enters_convex(ax, ay, xx, xy, pts[off[0] : off[1]], eps):
                convex = False
            x_rest = x_rest and convex
            tip_on = False
            for _ in range(0 if convex else 64):
                e = crossing_edge_boxed(ax, ay, xx, xy, obj, eps, boxes)
                if e < 0:
                    break
                # rest on the more clockwise end of the blocking edge
                ux, uy = xx - ax, xy - ay
                e2 = e + 1 if e + 1 < m_obj else 0
                v1x, v1y = obj[e, 0] - ax, obj[e, 1] - ay
                v2x, v2y = obj[e2, 0] - ax, obj[e2, 1] - ay
                a1 = np.arctan2(ux * v1y - uy * v1x, ux * v1x + uy * v1y)
                a2 = np.arctan2(ux * v2y - uy * v2x, ux * v2x + uy * v2y)
                vx, vy = (v1x, v1y) if a1 < a2 else (v2x, v2y)
                if min(a1, a2) > -1e-12:
                    break
                rv = np.hypot(vx, vy)
                xx, xy = ax + ln * vx / rv, ay + ln * vy / rv
            if not convex and crosses_boxed(ax, ay, xx, xy, obj, eps, boxes):
                ok, xx, xy, tip_on = free_direction(ax, ay, xx - ax, xy - ay, ln, obj, eps, boxes)
                if not ok:  # wedged
                    xx, xy = _fold_in(i, ax, ay, ln, obj, eps, joints, phi, boxes)
                    tip_on = False
            if best == np.inf:
                wj -= 1  # the cursor stays on its own segment
            # cursor: the segment after vertex w
            k, j, px, py = wk, wj + 1, wx, wy
            nseg_w = _segment(wk, wj, pts, off, theta, dev, es, spt, th0, base, app_th, n_laps)[6]
            if j >= nseg_w:
                k += 1
                j = 0
            x_th, x_on, x_sup = w_th, tip_on, False
            lap[i] = -1
            if convex and k >= 0:
                # a tip that comes to rest within the slack of the object's own
                # edge on the hull lies on it: the next link reaches down as a
                # chord, so that a chain on a curve is back on its joints after
                # one overhang instead of alternating tangent links for ever
                nj, _, _, gap = _nearest_on_curve(xx, xy, k, j, px, py, pts, off, es)
                c = min(k, off.shape[0] - 2)
                edge = off[c] + (nj + es[c]) % (off[c + 1] - off[c])
                if gap <= slack * slack and dev[edge] <= slack:
                    k, j, px, py = _relocate(xx, xy, k, j, px, py, pts, off, es)
                    x_sup = True
                    lap[i] = k
        else:
            px, py = xx, xy
            lap[i] = k
            x_sup = x_dev <= slack
            if k < 0 and np.hypot(xx - spt[0, 0], xy - spt[0, 1]) <= land:
                x_sup = True
            x_on = x_dev <= exact and k == 0
        phi[i] = _near(np.arctan2(xy - ay, xx - ax), 0.5 * (a_th + x_th))
        joints[i, 0], joints[i, 1] = xx, xy
        contact[i] = x_on
        ax, ay, a_th, a_sup, a_rest = xx, xy, x_th, x_sup, x_rest
        placed = i
    return status, placed, phi_v


@nb.njit(cache=True)
def walk_many(
    n,
    ls,
    pts,
    off,
    theta,
    dev,
    obj,
    eps,
    es,
    spt,
    th0,
    bases,
    app_th,
    approach,
    check,
    n_laps,
    max_search,
    slack,
    exact,
    bridge_limit,
    vidx,
):
    """``walk`` over a batch; per-wrap arrays have a leading batch axis."""
    b = ls.shape[0]
    joints = np.full((b, n + 1, 2), np.nan)
    contact = np.zeros((b, n + 1), np.bool_)
    lap = np.full((b, n + 1), -2, np.int64)
    phi = np.full((b, n + 1), np.nan)
    status = np.empty(b, np.int64)
    placed = np.empty(b, np.int64)
    phi_v = np.empty(b)
    boxes = edge_boxes(obj)
    track = track_blocks(pts, off, dev)
    for q in range(b):
        s, p, v = walk(
            n,
            ls[q],
            pts,
            off,
            theta,
            dev,
            obj,
            eps,
            es[q],
            spt[q],
            th0[q],
            bases[q],
            app_th[q],
            approach[q],
            check,
            n_laps,
            max_search[q],
            slack * ls[q],
            exact,
            bridge_limit,
            vidx,
            boxes,
            track,
            joints[q],
            contact[q],
            lap[q],
            phi[q],
        )
        status[q], placed[q], phi_v[q] = s, p, v
    return joints, contact, lap, phi, status, placed, phi_v


plain_calls(globals())
