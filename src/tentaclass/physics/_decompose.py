"""Convex pieces of a simple polygon: constrained Delaunay triangles, merged.

MuJoCo collides a mesh as its convex hull, so a non-convex object is built from
convex pieces. The polygon is triangulated without new vertices (shapely's
constrained Delaunay triangulation, GEOS), then neighbouring pieces are merged
across their shared diagonal whenever the union stays convex (Hertel and
Mehlhorn's rule). The pieces tile the polygon exactly, so the object collides
as itself; the count is at most four times the fewest convex pieces possible.
"""

from __future__ import annotations

import numpy as np
import shapely

from .._typing import ArrayLike, FloatArray
from ..shapes import as_outline

__all__ = ["convex_pieces"]


def _cross(o: FloatArray, a: FloatArray, b: FloatArray) -> float:
    return float((a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]))


def _is_convex(idx: list[int], pts: FloatArray, tol: float) -> bool:
    m = len(idx)
    return all(
        _cross(pts[idx[i - 1]], pts[idx[i]], pts[idx[(i + 1) % m]]) >= -tol for i in range(m)
    )


def _merge(a: list[int], b: list[int], u: int, v: int) -> list[int]:
    """Union of two counter-clockwise pieces across their shared edge ``u -> v`` (in ``a``)."""
    ia = a.index(v)
    a_rot = a[ia:] + a[:ia]  # v ... u
    ib = b.index(u)
    b_rot = b[ib:] + b[:ib]  # u ... v
    return a_rot + b_rot[1:-1]


def convex_pieces(outline: ArrayLike) -> list[FloatArray]:
    """Split a simple polygon into convex polygons that tile it exactly.

    Parameters
    ----------
    outline : array_like of shape (n_points, 2)
        Closed simple outline (see :func:`tentaclass.shapes.as_outline`).

    Returns
    -------
    pieces : list of ndarray of shape (n_i, 2)
        Counter-clockwise convex polygons whose union is the outline's polygon;
        one piece when the outline is convex.

    Raises
    ------
    InputError
        The outline is not a valid simple polygon.

    Examples
    --------
    >>> from tentaclass.shapes import polygon, square
    >>> len(convex_pieces(square(2)))
    1
    >>> ell = polygon([(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)])
    >>> pieces = convex_pieces(ell)  # an L: no single convex piece
    >>> len(pieces) > 1, float(sum(shapely.Polygon(p).area for p in pieces))
    (True, 3.0)
    """
    p = as_outline(outline)
    scale = float(np.ptp(p, axis=0).max())
    tol = 1e-12 * scale * scale
    if _is_convex(list(range(len(p))), p, tol):
        return [p]
    tris = shapely.get_parts(shapely.constrained_delaunay_triangles(shapely.Polygon(p)))
    pts = [tuple(v) for v in p]
    index = {v: i for i, v in enumerate(pts)}
    pieces: dict[int, list[int]] = {}
    for k, tri in enumerate(tris):
        ring = shapely.get_coordinates(tri.exterior)[:3]
        ids = []
        for vertex in map(tuple, ring):
            if vertex not in index:  # the triangulation added a vertex: keep it
                index[vertex] = len(pts)
                pts.append(vertex)
            ids.append(index[vertex])
        a = np.asarray([pts[i] for i in ids])
        if _cross(a[0], a[1], a[2]) < 0:
            ids = ids[::-1]
        if abs(_cross(a[0], a[1], a[2])) > tol:  # drop slivers of zero area
            pieces[k] = ids
    xy = np.asarray(pts, dtype=float)
    merged = True
    while merged:
        merged = False
        owner: dict[tuple[int, int], int] = {}
        for k, ids in pieces.items():
            for i in range(len(ids)):
                owner[(ids[i], ids[(i + 1) % len(ids)])] = k
        # longest diagonals first: removing them tends to leave fewer pieces
        diagonals = [(u, v, k) for (u, v), k in owner.items() if (v, u) in owner and u < v]
        diagonals.sort(key=lambda e: -np.hypot(*(xy[e[0]] - xy[e[1]])))
        done: set[int] = set()
        for u, v, k in diagonals:
            j = owner[(v, u)]
            if k in done or j in done or k == j:
                continue
            union = _merge(pieces[k], pieces[j], u, v)
            if _is_convex(union, xy, tol):
                pieces[k] = union
                del pieces[j]
                done.update((k, j))
                merged = True
    return [xy[ids] for ids in pieces.values()]
