"""Compiled geometric primitives of the wrap: crossing tests, nearest points, angles.

Hand-written (numba) because they run inside the compiled walk, once per
link; shapely's predicates are vectorised over geometries but cannot be
called from compiled code.
"""

from __future__ import annotations

import numba as nb
import numpy as np

TWO_PI = 2.0 * np.pi


@nb.njit(cache=True, inline="always")
def _near(phi, ref):
    """The value of ``phi`` modulo 2*pi closest to ``ref``."""
    return ref + ((phi - ref + np.pi) % TWO_PI) - np.pi


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


@nb.njit(cache=True)
def locate(points, curve):
    """Nearest point on the closed polyline ``curve`` to each of ``points``.

    Returns edge index, parameter on the edge and the point, per input point.
    """
    b = points.shape[0]
    m = curve.shape[0]
    es = np.empty(b, np.int64)
    ts = np.empty(b)
    out = np.empty((b, 2))
    for q in range(b):
        best = np.inf
        for i in range(m):
            i2 = i + 1 if i + 1 < m else 0
            x0, y0 = curve[i, 0], curve[i, 1]
            dx, dy = curve[i2, 0] - x0, curve[i2, 1] - y0
            A = dx * dx + dy * dy
            t = ((points[q, 0] - x0) * dx + (points[q, 1] - y0) * dy) / A if A > 0 else 0.0
            t = min(max(t, 0.0), 1.0)
            cx, cy = x0 + t * dx, y0 + t * dy
            d = (cx - points[q, 0]) ** 2 + (cy - points[q, 1]) ** 2
            if d < best:
                best = d
                es[q], ts[q], out[q, 0], out[q, 1] = i, t, cx, cy
    return es, ts, out


@nb.njit(cache=True)
def free_direction(ax, ay, ux, uy, ln, obj, eps):
    """Turn a blocked link (from ``a`` along ``u``) clockwise until it is free.

    The link pivots on ``a`` and stops where it first rests on the object:
    on an outline vertex within its length (tip in the air) or with its tip on
    an edge. Candidates are tried from the least rotation on. Returns
    ``(found, tip_x, tip_y, tip_on_outline)``.
    """
    m = obj.shape[0]
    angs = np.empty(3 * m)
    px = np.empty(3 * m)
    py = np.empty(3 * m)
    on = np.zeros(3 * m, np.bool_)
    c = 0
    for i in range(m):
        vx, vy = obj[i, 0] - ax, obj[i, 1] - ay
        d2 = vx * vx + vy * vy
        if 1e-24 * ln * ln < d2 <= ln * ln:
            r = np.sqrt(d2)
            angs[c] = np.arctan2(ux * vy - uy * vx, ux * vx + uy * vy)
            px[c], py[c] = ax + ln * vx / r, ay + ln * vy / r
            c += 1
        i2 = i + 1 if i + 1 < m else 0
        dx, dy = obj[i2, 0] - obj[i, 0], obj[i2, 1] - obj[i, 1]
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
                    on[c] = True
                    c += 1
    order = np.argsort(-angs[:c])
    for t in order:
        if not (-np.pi + 1e-9 < angs[t] <= 1e-12):
            continue
        if crossing_edge(ax, ay, px[t], py[t], obj, eps) < 0:
            return True, px[t], py[t], on[t]
    return False, ax, ay, False
