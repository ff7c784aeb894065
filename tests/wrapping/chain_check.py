"""Independent geometric check of a wrapped chain (shapely and plain numpy only).

The rules of the joint-on-outline contact model:

- no joint lies inside the object;
- a link may meet the outline only within the stretch of outline between its
  own two joints (in the walking direction; a joint off the outline counts at
  its nearest outline point): a link between two contacts may cut the cap of
  the object it spans, and nothing else of it;
- no two links cross (one passing from one side of the other to its other
  side) outside the object. Two links that both cut their caps may cross
  inside the object (a later lap's chord through the same cap as an earlier
  lap's); those crossings are counted apart, as ``"in_cap"``.

None of this uses the generator's own geometry code.
"""

from __future__ import annotations

import numpy as np
import shapely


def _ccw(outline: np.ndarray) -> np.ndarray:
    x, y = outline[:, 0], outline[:, 1]
    area = 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)
    return outline if area > 0 else outline[::-1]


def object_violations(
    outline: np.ndarray, joints: np.ndarray, direction: str = "ccw", rel_tol: float = 1e-6
) -> np.ndarray:
    """Per link: True where it meets the outline outside the stretch between its joints.

    Also True for a link whose end lies inside the object.
    """
    outline = _ccw(np.asarray(outline, float))
    scale = float(np.ptp(outline, axis=0).max())
    tol = rel_tol * scale
    ring = shapely.LinearRing(outline)
    per = ring.length
    poly = shapely.Polygon(outline)
    inner = poly.buffer(-tol)
    joints = np.asarray(joints, float)
    sj = shapely.line_locate_point(ring, shapely.points(joints))
    if direction == "cw":  # arc positions in the walking direction
        sj = per - sj
    lines = shapely.linestrings(np.stack([joints[:-1], joints[1:]], axis=1))
    bad = shapely.contains(inner, shapely.points(joints[:-1]))
    bad |= shapely.contains(inner, shapely.points(joints[1:]))
    meet = shapely.intersection(lines, ring)
    pts, which = shapely.get_coordinates(meet, return_index=True)
    if len(pts):
        s = shapely.line_locate_point(ring, shapely.points(pts))
        if direction == "cw":
            s = per - s
        lo, hi = sj[:-1][which], sj[1:][which]
        span = (hi - lo) % per
        # a link whose far joint projects behind its near one spans nothing
        span = np.where(span > 0.5 * per, 0.0, span)
        pos = (s - lo + 2 * tol) % per
        out = pos > span + 4 * tol
        np.logical_or.at(bad, which[out], True)
    return bad


def crossing_pairs(
    joints: np.ndarray,
    rel_tol: float = 1e-6,
    outline: np.ndarray | None = None,
    rest: float = 0.0,
    region=None,
) -> tuple[np.ndarray, np.ndarray]:
    """Index pairs ``(i, j)``, ``i < j``, of links that cross each other.

    Returns the pairs crossing outside the object and those crossing inside it
    (within both links' caps; all crossings are outside if ``outline`` is None).
    ``rest`` > 0 counts crossings within that distance outside the outline as
    inside (the band in which the chain is taken to rest on the object).
    ``region`` (a shapely polygon), if given, replaces the object as the
    region within which crossings are counted apart.
    """
    scale = float(np.ptp(joints, axis=0).max())
    tol = rel_tol * max(scale, 1e-300)
    lines = shapely.linestrings(np.stack([joints[:-1], joints[1:]], axis=1))
    tree = shapely.STRtree(lines)
    i, j = tree.query(lines, predicate="crosses")
    keep = i < j
    i, j = i[keep], j[keep]
    empty = np.zeros((0, 2), np.int64)
    if i.size == 0:
        return empty, empty
    # a proper crossing: each link's ends lie clearly on both sides of the other
    a0, a1, b0, b1 = joints[i], joints[i + 1], joints[j], joints[j + 1]

    def side(p, q, r):
        d = q - p
        n = np.hypot(d[:, 0], d[:, 1])
        return (d[:, 0] * (r[:, 1] - p[:, 1]) - d[:, 1] * (r[:, 0] - p[:, 0])) / n

    s1, s2 = side(a0, a1, b0), side(a0, a1, b1)
    s3, s4 = side(b0, b1, a0), side(b0, b1, a1)
    proper = (np.minimum(s1, s2) < -tol) & (np.maximum(s1, s2) > tol)
    proper &= (np.minimum(s3, s4) < -tol) & (np.maximum(s3, s4) > tol)
    i, j = i[proper], j[proper]
    s1, s2 = s1[proper], s2[proper]
    if outline is None or i.size == 0:
        return np.stack([i, j], axis=1), empty
    # the crossing point, on link j at s1 / (s1 - s2) from its start
    t = (s1 / (s1 - s2))[:, None]
    x = joints[j] + t * (joints[j + 1] - joints[j])
    if region is not None:  # on the support's boundary counts as on the support
        inner = region.buffer(max(rest, tol))
    else:
        body = shapely.Polygon(_ccw(np.asarray(outline, float)))
        inner = body.buffer(-tol) if rest <= 0 else body.buffer(rest)
    in_cap = shapely.contains(inner, shapely.points(x))
    pairs = np.stack([i, j], axis=1)
    return pairs[~in_cap], pairs[in_cap]


def support_region(outline: np.ndarray, mode: str, link_length: float):
    """The region a chain's chords may cut: the convex hull (taut) or the closing
    of the object by a disc of diameter one link (hug)."""
    poly = shapely.Polygon(_ccw(np.asarray(outline, float)))
    if mode == "taut":
        return poly.convex_hull
    r = link_length / 2
    return shapely.union(poly.buffer(r, quad_segs=8).buffer(-r, quad_segs=8), poly)


def chain_problems(outline, w, rel_tol: float = 1e-6, rest: float = 0.0, region=None) -> dict:
    """Everything wrong with one wrap ``w``: counts per kind (all 0 for a good wrap).

    ``"in_cap"`` (crossings of two links inside the object) is reported, not a
    problem; ``"self_on_laps"`` counts the crossings that do not involve an
    approach link (a chain that stands off and wraps more than once must pass
    over its own approach, which in the plane is a crossing); ``rest`` is in
    link lengths, ``region`` a shapely polygon (see :func:`crossing_pairs`).
    """
    j = w.joints
    ln = w.link_length
    lengths = np.hypot(*np.diff(j, axis=0).T)
    out, in_cap = crossing_pairs(j, rel_tol, outline, rest * ln, region)
    return {
        "incomplete": int(not w.complete),
        "bad_length": int(np.sum(~np.isclose(lengths, ln, rtol=1e-9, atol=0))),
        "object": int(object_violations(outline, j, w.direction, rel_tol).sum()),
        "self": len(out),
        "self_on_laps": int(np.sum(out.min(axis=1) >= w.offset_links)) if len(out) else 0,
        "in_cap": len(in_cap),
    }
