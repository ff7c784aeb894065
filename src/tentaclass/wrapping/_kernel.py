"""Compiled inner loop of the wrap: chord walking along a support track.

Hand-written because no library walks a chain of fixed-length links along a
polyline (circle-segment intersections searched forward) with a crossing test
per link; numba compiles it (``cache=True``: compiled once per machine).

Data layout (built by ``_surface``): ``pts`` holds the vertices of the first
lap's support curve, ``pts[off[0]:off[1]]``; ``theta`` the unwrapped direction
of each of its edges; ``dev`` how far an edge strays from the object's
outline (0 where it is an outline edge). A wrap's *track* is: the approach
segment (base -> start point ``S_0``, lap index -1), then lap 0 on the support
curve from ``S_0`` round to ``S_0`` (lap index 0), then the chain itself (lap
index 1), as a real chain lies on itself: the chain's *envelope* (each link,
with the vertices of the track it spanned that lie outside it: where the
object or an earlier lap bulges beyond a link, the next lap rests on that),
offset outward by the chain's thickness. The envelope grows as links are
placed; a link never walks on the two links before it.

The walk's state travels in one tuple, the *track* ``trk``:
``(pts, off, theta, dev, es, spt, th0, base, app_th, tp, tth, tlev, tdev, nv,
thick, ln)``: ``tp[:nv[0]]`` holds the envelope's vertices usable so far, ``tth``
the unwrapped direction of the track arriving at each, ``tlev`` the lap each
lies on, ``tdev`` how far the track arriving there strays from the object,
``thick`` the thickness.
"""

from __future__ import annotations

import numba as nb
import numpy as np

from ._geom import (
    TWO_PI,
    _near,
    crosses,
    crossing_edge,
    crossing_edge_range,
    crossing_link,
    edge_grid,
    free_direction,
    free_direction_links,
    inside,
    locate,
    meets_outside_stretch,
)

__all__ = ["crosses", "locate", "walk", "walk_many"]

STATUS_COMPLETE = 0
#: Fraction of a link within which the approach's last joint lands on the start point.
LANDING = 0.25
#: Segments in the chain part of the track: it has no fixed end.
_OPEN = 1 << 62


@nb.njit(cache=True)
def _unit(tp, s):
    dx = tp[s + 1, 0] - tp[s, 0]
    dy = tp[s + 1, 1] - tp[s, 1]
    r = np.hypot(dx, dy)
    return dx / r, dy / r, r


@nb.njit(cache=True)
def _offset_vertex(tp, v, thick):
    """Vertex ``v`` of the envelope ``tp`` moved outward by ``thick``.

    It moves along the bisector of the normals of its two segments (the
    right of the walk is outward), so that the offset keeps the envelope's
    vertices in order at convex and reflex vertices alike.
    """
    x, y = tp[v, 0], tp[v, 1]
    if thick == 0.0:
        return x, y
    bx, by, _ = _unit(tp, v)
    nx, ny = by, -bx
    if v > 0:
        ax, ay, _ = _unit(tp, v - 1)
        sx, sy = nx + ay, ny - ax
        r = np.hypot(sx, sy)
        if r > 1e-6:
            nx, ny = sx / r, sy / r
    return x + thick * nx, y + thick * ny


@nb.njit(cache=True)
def _chain_segment(j, trk):
    """Segment ``j`` of the chain part of the track (see the module docstring).

    The chain's envelope ``tp`` (its links, and whatever they cut off of the
    track they lay on) offset outward by the thickness: segment 0 climbs from
    ``S_0`` onto the offset of envelope vertex 0, segment ``j`` joins the
    offsets of vertices ``j - 1`` and ``j``. Returns as :func:`_segment`;
    ``n_segments`` 0 where the track does not reach yet.
    """
    spt, th0, tp, tth, tlev, tdev, nv, thick = (trk[5], trk[6], trk[9], trk[10], trk[11],
                                                trk[12], trk[13][0], trk[14])  # fmt: skip
    # a vertex's offset needs the segment after it when the chain is thick
    if j < 0 or j + (1 if thick > 0.0 else 0) >= nv:
        return 0.0, 0.0, 0.0, 0.0, 0.0, np.inf, 0, 0
    if j == 0:
        x0, y0 = spt[0, 0], spt[0, 1]
        th, lap, dv = th0 + TWO_PI, 1, tdev[0] if thick == 0.0 else np.inf
    else:
        x0, y0 = _offset_vertex(tp, j - 1, thick)
        th, lap = tth[j] + TWO_PI, tlev[j] + 1
        # on the object where the envelope follows it (a thin chain only)
        dv = tdev[j] if thick == 0.0 else np.inf
    x1, y1 = _offset_vertex(tp, j, thick)
    if x1 != x0 or y1 != y0:
        th = _near(np.arctan2(y1 - y0, x1 - x0), th)
    return x0, y0, x1, y1, th, dv, _OPEN, lap


@nb.njit(cache=True)
def _curve_segment(k, j, pts, off, theta, dev, es, spt, th0, base, app_th):
    """Segment ``j`` of the approach (``k == -1``) or of the first lap (``k == 0``).

    Returns as :func:`_segment`. Takes the arrays themselves rather than the
    track tuple: unpacking the tuple on every segment walked costs reference
    counting on each of its arrays.
    """
    if k < 0:
        return base[0], base[1], spt[0, 0], spt[0, 1], app_th, np.inf, 1, -1
    o = off[0]
    m = off[1] - o
    e0 = es[0]
    shift = th0 - theta[o + e0]
    ee = e0 + j
    i0 = o + ee % m
    th = theta[i0] + TWO_PI * (ee // m) + shift
    on = dev[i0]
    if j == 0:
        i1 = o + (e0 + 1) % m
        return spt[0, 0], spt[0, 1], pts[i1, 0], pts[i1, 1], th, on, m + 1, 0
    if j == m:
        return pts[i0, 0], pts[i0, 1], spt[0, 0], spt[0, 1], th, on, m + 1, 0
    i1 = o + (ee + 1) % m
    return pts[i0, 0], pts[i0, 1], pts[i1, 0], pts[i1, 1], th, on, m + 1, 0


@nb.njit(cache=True)
def _segment(k, j, trk):
    """Segment ``j`` of lap ``k`` (``k == -1``: the approach; ``k == 1``: the chain).

    Returns ``x0, y0, x1, y1, theta, deviation, n_segments_in_lap, lap``; the
    deviation is how far the segment strays from the object's outline (inf
    for segments that are not on the support curve), ``lap`` the lap a joint
    placed on it belongs to.
    """
    if k > 0:
        return _chain_segment(j, trk)
    return _curve_segment(k, j, trk[0], trk[1], trk[2], trk[3], trk[4], trk[5], trk[6],
                          trk[7], trk[8])  # fmt: skip


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


@nb.njit(cache=True)
def _search(ax, ay, ln, k, j, px, py, skip_first, slack, limit, trk):
    """Next point of the track after cursor ``(k, j, p)`` at distance ``l`` from ``a``.

    Returns ``(status, k, j, x, y, theta, deviation, bridged, walked, lap)``;
    status 0 found, 1 nothing within ``limit`` of arc, 2 the end of the track.
    ``skip_first`` ignores a root at the cursor itself (continuing after a
    rejected point).
    """
    bridged = False
    walked = 0.0
    pts, off, theta, dev, es = trk[0], trk[1], trk[2], trk[3], trk[4]
    spt, th0, base, app_th = trk[5], trk[6], trk[7], trk[8]
    while True:
        if k > 0:
            seg = _chain_segment(j, trk)
        else:
            seg = _curve_segment(k, j, pts, off, theta, dev, es, spt, th0, base, app_th)
        x1, y1, th, dv, nseg = seg[2], seg[3], seg[4], seg[5], seg[6]
        if nseg == 0:
            return 2, k, j, px, py, th, dv, bridged, walked, seg[7]
        dx, dy = x1 - px, y1 - py
        A = dx * dx + dy * dy
        if A > 0:
            fx, fy = px - ax, py - ay
            B = 2.0 * (fx * dx + fy * dy)
            C0 = fx * fx + fy * fy - ln * ln
            disc = B * B - 4.0 * A * C0
            if dv > slack:
                bridged = True
            if not skip_first and abs(C0) <= 2e-9 * ln * ln:
                # the cursor itself lies a link from a (up to rounding): a
                # lap closing on a vertex
                return 0, k, j, px, py, th, dv, bridged, walked, seg[7]
            if disc >= 0:
                sq = np.sqrt(disc)
                # after a rejected point, skip roots within 1e-9 l of it
                lo = 1e-9 * ln / np.sqrt(A) if skip_first else 0.0
                for tau in ((-B - sq) / (2.0 * A), (-B + sq) / (2.0 * A)):
                    if lo < tau <= 1.0 or (tau == 0.0 and not skip_first and C0 <= 0):
                        x, y = px + tau * dx, py + tau * dy
                        return 0, k, j, x, y, th, dv, bridged, walked, seg[7]
            walked += np.sqrt(A)
        skip_first = False
        if walked > limit:
            return 1, k, j, px, py, th, dv, bridged, walked, seg[7]
        j += 1
        px, py = x1, y1
        if j >= nseg:
            k += 1
            j = 0


@nb.njit(cache=True)
def _fold_in(i, ax, ay, ln, obj, eps, joints, phi):
    """Where link ``i`` goes when the track offers it nothing: a chain always ends somewhere.

    The link folds in towards the object from nearly a half turn left of the
    previous link and stops at the first thing it meets (the object or an
    earlier link; tip in the air); wedged, it folds back onto the previous
    link. Returns the tip.
    """
    ph = phi[i - 1]
    last = max(i - 2, 0)
    ok, xx, xy, _ = free_direction_links(
        ax, ay, np.cos(ph + 0.99 * np.pi), np.sin(ph + 0.99 * np.pi), ln, obj, eps, joints, last
    )
    if ok:
        return xx, xy
    if i >= 2:
        return joints[i - 2, 0], joints[i - 2, 1]
    return ax - ln * np.cos(ph), ay - ln * np.sin(ph)


@nb.njit(cache=True, inline="always")
def _nearest_on(x, y, x0, y0, x1, y1):
    """Squared distance from ``(x, y)`` to segment 0-1, and the nearest point."""
    dx, dy = x1 - x0, y1 - y0
    A = dx * dx + dy * dy
    t = ((x - x0) * dx + (y - y0) * dy) / A if A > 0 else 0.0
    t = min(max(t, 0.0), 1.0)
    cx, cy = x0 + t * dx, y0 + t * dy
    return (cx - x) ** 2 + (cy - y) ** 2, cx, cy


@nb.njit(cache=True)
def _relocate(x, y, k, j, px, py, trk):
    """Move the cursor ``(k, j, p)`` forward to the point of its lap's track nearest to ``(x, y)``.

    The cursor never moves back: if the nearest point lies behind it, it stays.
    """
    if k < 0:
        return k, j, px, py
    best = np.inf
    bj, bx, by = j, px, py
    if k > 0:  # the chain: a few links on from the cursor (further, it would overtake itself)
        best = (px - x) ** 2 + (py - y) ** 2
        jj = j
        walked = 0.0
        while walked < 3.0 * trk[15]:
            s = _segment(k, jj, trk)
            if s[6] == 0:
                break
            walked += np.hypot(s[2] - s[0], s[3] - s[1])
            x0, y0 = (px, py) if jj == j else (s[0], s[1])
            d, cx, cy = _nearest_on(x, y, x0, y0, s[2], s[3])
            if d < best:
                best = d
                bj, bx, by = jj, cx, cy
            jj += 1
        return k, bj, bx, by
    pts, off, es = trk[0], trk[1], trk[4]
    o = off[0]
    m = off[1] - o
    for e in range(m):
        i0 = o + e
        i1 = o + (e + 1) % m
        d, cx, cy = _nearest_on(x, y, pts[i0, 0], pts[i0, 1], pts[i1, 0], pts[i1, 1])
        if d < best:
            best = d
            bj = (e - es[0]) % m
            bx, by = cx, cy
    if bj > j:
        return k, bj, bx, by
    return k, j, px, py


@nb.njit(cache=True)
def _crosses_chain(ax, ay, bx, by, joints, first, last, obj, eps):
    """True if segment a-b crosses one of the links ``first <= t < last`` outside the object.

    Two chords that cross inside the object (each cutting the cap it spans)
    are allowed.
    """
    t0 = first
    while t0 < last:
        t = crossing_link(ax, ay, bx, by, joints, last, eps, t0)
        if t < 0:
            return False
        px, py = joints[t, 0], joints[t, 1]
        qx, qy = joints[t + 1, 0], joints[t + 1, 1]
        o1 = (bx - ax) * (py - ay) - (by - ay) * (px - ax)
        o2 = (bx - ax) * (qy - ay) - (by - ay) * (qx - ax)
        f = o1 / (o1 - o2)
        if not inside(px + f * (qx - px), py + f * (qy - py), obj, 0.0):
            return True
        t0 = t + 1
    return False


@nb.njit(cache=True)
def _blocked(ax, ay, bx, by, k, obj, eps, joints, a0, i):
    """True if link ``i`` (a-b) crosses the object or, on the chain (``k >= 1``), an earlier link.

    The approach links (before joint ``a0``) do not count: a chain that stands
    off and wraps more than once passes over its own approach.
    """
    if crosses(ax, ay, bx, by, obj, eps):
        return True
    # two links cross where each passes clearly (5e-7 of the object's size, in
    # signed area: times a link) from one side of the other to its other side
    tol = 5e-7 * np.sqrt(eps / 1e-12) * np.hypot(bx - ax, by - ay)
    return k >= 1 and a0 >= 0 and _crosses_chain(ax, ay, bx, by, joints, a0, i - 1, obj, tol)


@nb.njit(cache=True)
def _grown(tp, tth, tlev, tdev, nv):
    """The envelope's arrays with twice the room (the first ``nv`` entries copied)."""
    tp2 = np.empty((2 * nv, 2))
    tp2[:nv] = tp[:nv]
    tth2 = np.empty(2 * nv)
    tth2[:nv] = tth[:nv]
    tlev2 = np.empty(2 * nv, np.int64)
    tlev2[:nv] = tlev[:nv]
    tdev2 = np.empty(2 * nv)
    tdev2[:nv] = tdev[:nv]
    return tp2, tth2, tlev2, tdev2


@nb.njit(cache=True)
def _put(tp, tth, tlev, tdev, nv, x, y, th, lev, dv, tol):
    """Append vertex ``(x, y)`` to the envelope (room for it given); the new count.

    ``th`` is the unwrapped direction of the track arriving there, ``lev`` the
    lap it lies on, ``dv`` how far the track arriving there strays from the
    object (inf: off it). A vertex on the last one is not repeated. Returns
    the count only: handing the arrays back would count references on each
    of them on every vertex.
    """
    if nv > 0 and abs(tp[nv - 1, 0] - x) <= tol and abs(tp[nv - 1, 1] - y) <= tol:
        return nv
    tp[nv, 0], tp[nv, 1] = x, y
    tth[nv], tlev[nv], tdev[nv] = th, max(lev, 0), dv
    return nv + 1


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
    thick,
    max_search,
    slack,
    exact,
    bridge_limit,
    vidx,
    grid,
    joints,
    contact,
    lap,
    phi,
):
    """Place ``n`` links; fill ``joints`` (n+1, 2), ``contact``, ``lap`` and ``phi`` (n+1).

    ``check``: 0 never test crossings; 2 test links that do not join two points
    of the object's own edges (caps of the outline are allowed; anything
    bridging, in the air or on the chain is tested) and let a crossing link
    rest on the corner it passes; 3 as 2, but first look further along (up to
    ``bridge_limit`` of arc) for a point the link can reach without crossing.
    A link on the chain (a later lap) is tested against the object and the
    earlier links, and always looks further along first: it moves on over the
    track rather than folding back over it. ``vidx`` (taut): the outline
    index of each hull vertex; a link between two points of the first lap's
    hull is then only tested against the outline between the hull vertices
    around it (the only part of the object its hull cap can hold). With
    ``check`` 3 a chord between two points resting on the support is tested
    too: it may meet the outline only within the stretch between its joints
    (``grid``: the outline's edges binned, see :func:`_geom.edge_grid`).
    ``thick``: the chain's thickness, by which each lap lies outside the
    links of the one before. Returns ``(status, n_placed, phi_virtual)``.
    """
    m0 = off[1] - off[0]
    m_obj = obj.shape[0]
    tl = np.full(n + 1, -1, np.int64)
    tn = np.zeros(n + 1, np.int64)  # envelope vertices once each joint is placed
    tp = np.empty((2 * n + 2 * m0 + 16, 2))
    tth = np.empty(2 * n + 2 * m0 + 16)
    tlev = np.empty(2 * n + 2 * m0 + 16, np.int64)
    tdev = np.empty(2 * n + 2 * m0 + 16)
    nv = 0
    k = -1 if approach else 0
    j = 0
    if approach:
        px, py = base[0], base[1]
    else:
        px, py = spt[0, 0], spt[0, 1]
    # the usable count travels in an array, so that the track is only rebuilt
    # when the envelope's arrays grow (building it counts references on each)
    nvb = np.zeros(1, np.int64)
    trk = (pts, off, theta, dev, es, spt, th0, base, app_th, tp, tth, tlev, tdev, nvb, thick, ln)
    stale = False
    seg = _segment(k, j, trk)
    a_th = seg[4]
    a_on = seg[5] <= exact and not approach
    a_sup = seg[5] <= slack and not approach
    # An approach joint that ends just above the start point (less than
    # LANDING of a link) counts as resting on the support: the next link
    # reaches down onto it, cutting the cap it spans, instead of floating.
    land = LANDING * ln
    if approach and np.hypot(base[0] - spt[0, 0], base[1] - spt[0, 1]) <= land:
        a_sup = True
    a0 = 0 if (not approach or a_sup) else -1
    ax, ay = px, py
    joints[0, 0], joints[0, 1] = ax, ay
    contact[0] = a_on and k == 0
    lap[0] = k
    tl[0] = k
    if a0 == 0:
        if nv == tp.shape[0]:
            tp, tth, tlev, tdev = _grown(tp, tth, tlev, tdev, nv)
            stale = True
        nv = _put(tp, tth, tlev, tdev, nv, ax, ay, th0, 0, 0.0 if a_sup else np.inf, exact)
        tn[0] = nv
    phi_v = _virtual_heading(ln, pts, off, theta, es, spt, th0)
    phi[0] = app_th if approach else phi_v
    status = STATUS_COMPLETE
    placed = 0
    # the last link rested in the air with the cursor left where it was: the
    # next one must not reach back to the cursor (the joint before) itself
    stay = False
    for i in range(1, n + 1):
        nvb[0] = tn[i - 2] if i >= 2 else 0
        if stale:
            trk = (pts, off, theta, dev, es, spt, th0, base, app_th, tp, tth, tlev, tdev, nvb,
                   thick, ln)  # fmt: skip
            stale = False
        sk, sj, spx, spy = k, j, px, py
        # on the chain the next joint is near: further on, it would overtake itself
        limit = max_search if k < 1 else 3.0 * ln
        r = _search(ax, ay, ln, k, j, px, py, stay, slack, limit, trk)
        stay = False
        if r[0] != 0:
            # nothing of the track at a link's length ahead: the link folds in
            xx, xy = _fold_in(i, ax, ay, ln, obj, eps, joints, phi)
            phi[i] = _near(np.arctan2(xy - ay, xx - ax), phi[i - 1])
            joints[i, 0], joints[i, 1] = xx, xy
            contact[i] = False
            lap[i] = -1
            k, j, px, py = _relocate(xx, xy, k, j, px, py, trk)
            s = _segment(k, j, trk)
            tl[i] = max(tl[i - 1], s[7] if s[6] > 0 else tl[i - 1])
            if a0 < 0 and k >= 0:
                a0 = i
            if a0 >= 0:
                if nv == tp.shape[0]:
                    tp, tth, tlev, tdev = _grown(tp, tth, tlev, tdev, nv)
                    stale = True
                nv = _put(tp, tth, tlev, tdev, nv, xx, xy, phi[i], tl[i], np.inf, exact)
            tn[i] = nv
            ax, ay, a_th, a_sup = xx, xy, phi[i], False
            placed = i
            continue
        k, j, xx, xy, x_th, x_dev, x_lap = r[1], r[2], r[3], r[4], r[5], r[6], r[9]
        bridged = r[7] or not a_sup
        if sk < 0 and a_sup and k >= 0:  # from a landing approach joint onto the lap
            bridged = x_dev > slack
        overhang = False
        cross = False
        if check >= 2 and bridged:
            if vidx.shape[0] > 0 and sk == 0 and k == 0 and sj <= m0 and j <= m0:
                i0 = vidx[(es[0] + sj) % m0] - 1
                i1 = vidx[(es[0] + j + 1) % m0]
                cnt = (i1 - i0) % m_obj + 2
                if j - sj >= m0 - 1:
                    cnt = m_obj
                cross = crossing_edge_range(ax, ay, xx, xy, obj, eps, i0 % m_obj, cnt) >= 0
            else:
                cross = _blocked(ax, ay, xx, xy, k, obj, eps, joints, a0, i)
        elif check == 3 and k <= 0:
            # a chord between two points resting on the support may cut the
            # object's cap between them, and nothing else of it
            cross = meets_outside_stretch(ax, ay, xx, xy, obj, np.sqrt(eps), 2.0 * slack, grid)
        if cross:
            overhang = True
            if check == 3 or k >= 1:  # look further along for a point the link can reach
                ck, cj, cx, cy, used = k, j, xx, xy, 0.0
                # on the chain only a few links on: further, it would overtake itself
                reach = bridge_limit if k < 1 else 2.0 * ln
                for _ in range(10000):
                    if used >= reach:
                        break
                    r2 = _search(ax, ay, ln, ck, cj, cx, cy, True, slack, reach - used, trk)
                    if r2[0] != 0:
                        break
                    used += r2[8]
                    ck, cj, cx, cy = r2[1], r2[2], r2[3], r2[4]
                    if not _blocked(ax, ay, cx, cy, ck, obj, eps, joints, a0, i):
                        k, j, xx, xy, x_th, x_dev, x_lap = ck, cj, cx, cy, r2[5], r2[6], r2[9]
                        overhang = False
                        break
        pivot = False
        if overhang and k >= 1:
            # On the chain: the link rests on the furthest vertex of the track
            # it passed that it can reach without crossing anything (its tip
            # just beyond it), so that the walk moves on along the track.
            vk, vj, vx, vy, found = 0, 0, 0.0, 0.0, False
            ck, cj = sk, sj
            while not (ck == k and cj == j):
                if ck > 0:
                    s2 = _chain_segment(cj, trk)
                else:  # the arrays at hand: no reference counting per segment
                    s2 = _curve_segment(ck, cj, pts, off, theta, dev, es, spt, th0, base, app_th)
                rr = np.hypot(s2[2] - ax, s2[3] - ay)
                if 1e-12 * ln < rr:
                    tx, ty = ax + ln * (s2[2] - ax) / rr, ay + ln * (s2[3] - ay) / rr
                    if not _blocked(ax, ay, tx, ty, 1, obj, eps, joints, a0, i):
                        vk, vj, vx, vy, found = ck, cj, tx, ty, True
                cj += 1
                if cj >= s2[6]:
                    ck += 1
                    cj = 0
            if found:
                overhang, pivot = False, True
                xx, xy = vx, vy
                k, j = vk, vj + 1
                if k <= 0 and j >= _segment(vk, vj, trk)[6]:
                    k, j = k + 1, 0
                s = _segment(k, j, trk)
                px, py = s[0], s[1]
                x_th = s[4] if s[6] > 0 else a_th
                x_lap = max(tl[i - 1], s[7] if s[6] > 0 else tl[i - 1])
                x_on, x_sup = False, False
                lap[i] = -1
        if overhang and k >= 1:
            # else it turns clockwise until it rests on whatever blocks it
            ok, tx, ty, t_on = free_direction_links(
                ax, ay, xx - ax, xy - ay, ln, obj, eps, joints, i - 1
            )
            if ok:
                overhang, pivot = False, True
                xx, xy = tx, ty
                if sk < k:
                    k, j, px, py = _relocate(xx, xy, k, 0, spt[0, 0], spt[0, 1], trk)
                else:
                    k, j, px, py = _relocate(xx, xy, sk, sj, spx, spy, trk)
                s = _segment(k, j, trk)
                x_th = s[4] if s[6] > 0 else a_th
                x_lap = max(tl[i - 1], s[7] if s[6] > 0 else tl[i - 1])
                x_on, x_sup = t_on, False
                lap[i] = -1
        if overhang:
            # The chord would cut through the object: the link rests on the
            # most clockwise vertex passed (the tangent seen from the joint)
            # and its tip stays in the air.
            ux, uy = xx - ax, xy - ay
            best = np.inf
            wk, wj, wx, wy, w_th = 0, 0, 0.0, 0.0, 0.0
            ck, cj = sk, sj
            while not (ck == k and cj == j):
                if ck > 0:
                    s2 = _chain_segment(cj, trk)
                else:  # the arrays at hand: no reference counting per segment
                    s2 = _curve_segment(ck, cj, pts, off, theta, dev, es, spt, th0, base, app_th)
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
                stay = True
                wk, wj, wx, wy, w_th = sk, sj, spx, spy, a_th
                xx, xy = ax + ux, ay + uy
            else:
                rr = np.hypot(wx - ax, wy - ay)
                xx, xy = ax + ln * (wx - ax) / rr, ay + ln * (wy - ay) / rr
            # On a convex support (the hull) the link along the hull edge is
            # free. Otherwise it may still be blocked: turn it on clockwise to
            # the first outline vertex where it is free.
            convex = vidx.shape[0] > 0 and wk == 0
            tip_on = False
            for _ in range(0 if convex else 64):
                e = crossing_edge(ax, ay, xx, xy, obj, eps)
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
            if not convex and crosses(ax, ay, xx, xy, obj, eps):
                ok, xx, xy, tip_on = free_direction(ax, ay, xx - ax, xy - ay, ln, obj, eps)
                if not ok:  # wedged
                    xx, xy = _fold_in(i, ax, ay, ln, obj, eps, joints, phi)
                    tip_on = False
            # on the chain (and in the air over the first lap when hugging, where
            # the links before may fold): turn on until the link rests on the
            # object or a link
            on_chain = max(wk, k) >= 1 or check == 3
            if on_chain and _blocked(ax, ay, xx, xy, 1, obj, eps, joints, a0, i):
                ok, xx, xy, tip_on = free_direction_links(
                    ax, ay, xx - ax, xy - ay, ln, obj, eps, joints, i - 1
                )
                if not ok:
                    xx, xy = _fold_in(i, ax, ay, ln, obj, eps, joints, phi)
                    tip_on = False
            if (
                check == 3
                and max(wk, k) < 1
                and meets_outside_stretch(ax, ay, xx, xy, obj, np.sqrt(eps), 2.0 * slack, grid)
            ):
                # resting on the outline behind its joints: turn on to where it rests fairly
                ok, tx, ty, t_on = free_direction_links(
                    ax, ay, xx - ax, xy - ay, ln, obj, eps, joints, i - 1, grid, 2.0 * slack
                )
                if ok:
                    xx, xy, tip_on = tx, ty, t_on
            if best == np.inf:
                wj -= 1  # the cursor stays on its own segment
            # cursor: the segment after vertex w
            k, j, px, py = wk, wj + 1, wx, wy
            if wk <= 0 and j >= _segment(wk, max(wj, 0), trk)[6]:
                k += 1
                j = 0
            x_th, x_on, x_sup = w_th, tip_on, False
            s = _segment(k, j, trk)
            x_lap = max(tl[i - 1], s[7] if s[6] > 0 else tl[i - 1])
            lap[i] = -1
        elif not pivot:
            px, py = xx, xy
            lap[i] = x_lap
            x_sup = x_dev <= slack
            if k < 0 and np.hypot(xx - spt[0, 0], xy - spt[0, 1]) <= land:
                x_sup = True
            x_on = x_dev <= exact and k == 0
        tl[i] = x_lap
        phi[i] = _near(np.arctan2(xy - ay, xx - ax), 0.5 * (a_th + x_th))
        joints[i, 0], joints[i, 1] = xx, xy
        if a0 >= 0:
            # the envelope: the vertices passed that lie outside the link, then its tip
            # (each with whether the envelope reaching it follows the object)
            ux, uy = xx - ax, xy - ay
            ck, cj = sk, sj
            # a link from a landing joint reaches down onto the object as if from it
            landing = i - 1 == a0 and sk < 0 and a_sup
            on = contact[i - 1] or landing
            while not (ck == k and cj == j):
                if ck > 0:
                    s2 = _chain_segment(cj, trk)
                else:  # the arrays at hand: no reference counting per segment
                    s2 = _curve_segment(ck, cj, pts, off, theta, dev, es, spt, th0, base, app_th)
                kept = ux * (s2[3] - ay) - uy * (s2[2] - ax) < -exact * ln
                on = on and (kept or landing) and (s2[5] <= exact or ck < 0)
                if kept:
                    if nv == tp.shape[0]:
                        tp, tth, tlev, tdev = _grown(tp, tth, tlev, tdev, nv)
                        stale = True
                    nv = _put(
                        tp, tth, tlev, tdev, nv, s2[2], s2[3], s2[4], s2[7],
                        0.0 if on else np.inf, exact,
                    )  # fmt: skip
                cj += 1
                if cj >= s2[6]:
                    ck += 1
                    cj = 0
            on = on and not (sk == k and sj == j)  # a bare link is not on the object
            x_dv = 0.0 if on and x_dev <= exact and not (overhang or pivot) else np.inf
            if nv == tp.shape[0]:
                tp, tth, tlev, tdev = _grown(tp, tth, tlev, tdev, nv)
                stale = True
            nv = _put(tp, tth, tlev, tdev, nv, xx, xy, phi[i], x_lap, x_dv, exact)
        elif k >= 0 or x_sup:
            a0 = i
            # The chain's track begins at S_0: where the approach passed over
            # support that bulges beyond the line from S_0 to this joint, the
            # envelope keeps that support (a later lap lies on it, not
            # through it).
            ux, uy = xx - spt[0, 0], xy - spt[0, 1]
            ck, cj = sk, sj
            while k >= 0 and not (ck == k and cj == j):
                s2 = _curve_segment(ck, cj, pts, off, theta, dev, es, spt, th0, base, app_th)
                if ck >= 0 and ux * (s2[3] - spt[0, 1]) - uy * (s2[2] - spt[0, 0]) < -exact * ln:
                    if nv == tp.shape[0]:
                        tp, tth, tlev, tdev = _grown(tp, tth, tlev, tdev, nv)
                        stale = True
                    nv = _put(tp, tth, tlev, tdev, nv, s2[2], s2[3], s2[4], s2[7],
                              0.0 if s2[5] <= exact else np.inf, exact)  # fmt: skip
                cj += 1
                if cj >= s2[6]:
                    ck += 1
                    cj = 0
            if nv == tp.shape[0]:
                tp, tth, tlev, tdev = _grown(tp, tth, tlev, tdev, nv)
                stale = True
            nv = _put(tp, tth, tlev, tdev, nv, xx, xy, th0, x_lap, 0.0 if x_sup else np.inf, exact)
        tn[i] = nv
        contact[i] = x_on
        ax, ay, a_th, a_sup = xx, xy, x_th, x_sup
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
    thick,
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
    # the outline's edges in cells of a link or more (hug tests each chord locally)
    grid = edge_grid(obj, max(ls.max() if b > 0 else 0.0, 1e-9 * (obj.max() - obj.min())))
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
            thick,
            max_search[q],
            slack * ls[q],
            exact,
            bridge_limit,
            vidx,
            grid,
            joints[q],
            contact[q],
            lap[q],
            phi[q],
        )
        status[q], placed[q], phi_v[q] = s, p, v
    return joints, contact, lap, phi, status, placed, phi_v
