"""Support curves a chain wraps on: the object's hull or outline, and the laps above it."""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np
import shapely
from scipy.spatial import ConvexHull
from scipy.spatial.distance import pdist

from .._typing import FloatArray
from ..shapes import signed_area

__all__ = ["Surface", "build_surface", "outline_diameter", "point_at_fraction"]

#: A chain thickness below this fraction of the object's extent is taken as 0.
_NEGLIGIBLE = 1e-9


@dataclass(frozen=True)
class Surface:
    """Lap curves of one outline, flattened for the compiled walk."""

    outline: FloatArray  # the object, counter-clockwise (mirrored for cw wraps)
    mode: str  # "taut": curve 0 is the convex hull; "hug": the outline
    pts: FloatArray  # (N, 2) vertices of all lap curves back to back
    off: np.ndarray  # (C + 1,) curve c is pts[off[c]:off[c + 1]]
    theta: FloatArray  # (N,) unwrapped edge directions, per curve
    dev: FloatArray  # (N,) how far each edge strays from the outline (inf off curve 0)
    vidx: np.ndarray  # taut: outline index of each hull vertex; hug: empty
    n_laps: int  # laps the track provides (unbounded: the last curve repeats)
    scale: float  # largest extent of the outline
    diameter: float
    perimeter: float  # of curve 0
    max_perimeter: float

    def curve(self, c: int) -> FloatArray:
        """Vertices of lap curve ``c``."""
        return self.pts[self.off[c] : self.off[c + 1]]


def outline_diameter(outline: FloatArray) -> float:
    """Largest distance between two points of an outline (over its convex hull)."""
    return float(pdist(outline[ConvexHull(outline).vertices]).max())


def _edge_theta(p: FloatArray) -> FloatArray:
    d = np.roll(p, -1, axis=0) - p
    return np.unwrap(np.arctan2(d[:, 1], d[:, 0]))


def _hull(outline: FloatArray) -> tuple[FloatArray, FloatArray, np.ndarray]:
    """Convex hull vertices (ccw) and each hull edge's largest distance to the outline it skips."""
    idx = ConvexHull(outline).vertices  # counter-clockwise for 2-D input
    m, h = len(outline), len(idx)
    nxt = np.roll(idx, -1)
    skipped = np.maximum((nxt - idx) % m - 1, 0)  # outline vertices strictly between
    owner = np.repeat(np.arange(h), skipped)
    first = np.cumsum(skipped) - skipped
    between = (idx[owner] + 1 + np.arange(len(owner)) - first[owner]) % m
    a, b = outline[idx], outline[nxt]
    d = b - a
    u = d / np.hypot(d[:, 0], d[:, 1])[:, None]
    r = outline[between] - a[owner]
    dev = np.zeros(h)
    np.maximum.at(dev, owner, np.abs(r[:, 0] * u[owner, 1] - r[:, 1] * u[owner, 0]))
    return outline[idx], dev, idx.astype(np.int64)


def _clean_ring(p: FloatArray) -> FloatArray:
    keep = np.any(np.abs(p - np.roll(p, 1, axis=0)) > 0, axis=1)
    p = p[keep]
    return p if signed_area(p) > 0 else p[::-1]


def _closing(outline: FloatArray, radius: float) -> tuple[FloatArray, FloatArray]:
    """Boundary of the morphological closing by a disc, and each edge's distance to the outline."""
    poly = shapely.Polygon(outline)
    closed = poly.buffer(radius, quad_segs=8).buffer(-radius, quad_segs=8)
    # The polygonal buffer chamfers convex corners by a hair: put them back so
    # that the support contains the object.
    closed = shapely.union(closed, poly)
    if closed.geom_type != "Polygon":
        closed = max(closed.geoms, key=lambda g: g.area)
    c = _clean_ring(np.asarray(closed.exterior.coords)[:-1])
    probes = np.concatenate([c, 0.5 * (c + np.roll(c, -1, axis=0))])
    dist = _distance_to_outline(probes, outline)
    d, mid = dist[: len(c)], dist[len(c) :]
    return c, np.maximum(np.maximum(d, np.roll(d, -1)), mid)


def _distance_to_outline(points: FloatArray, outline: FloatArray) -> FloatArray:
    """Exact distance from each point to the closed polyline ``outline``.

    Equal to shapely's distance to the ring (each edge's distance rounded as
    GEOS rounds it), found by a compiled search over blocks of edges that
    skips the blocks further than the nearest edge so far: most of the cost of
    building a hug surface otherwise.
    """
    from ._geom import edge_boxes, outline_distances  # numba: compiled on first use

    obj = np.ascontiguousarray(outline, dtype=np.float64).view()
    obj.setflags(write=False)  # as a surface holds it: one compiled version serves both
    return outline_distances(np.ascontiguousarray(points, dtype=np.float64), obj, edge_boxes(obj))


@functools.lru_cache(maxsize=64)
def _build(
    key: bytes, m: int, mode: str, thickness: float, arc_needed: float, link_length: float
) -> Surface:
    outline = np.frombuffer(key, dtype=np.float64).reshape(m, 2)
    scale = float(np.ptp(outline, axis=0).max())
    if mode == "taut":
        c0, on0, vidx = _hull(outline)
    else:
        c0, on0 = _closing(outline, link_length / 2)
        vidx = np.zeros(0, np.int64)
    diameter = outline_diameter(outline)
    curves, flags = [c0], [on0]
    per0 = float(np.sum(np.hypot(*(np.roll(c0, -1, axis=0) - c0).T)))
    if thickness > 0:
        base = shapely.make_valid(shapely.Polygon(c0)).buffer(0)
        total, k = 0.0, 1
        while total < arc_needed + per0 and k < 200:
            grown = base.buffer(k * thickness, quad_segs=8)
            if grown.geom_type != "Polygon":  # a closing that touches itself
                grown = max(grown.geoms, key=lambda g: g.area)
            ring = grown.exterior
            ck = _clean_ring(np.asarray(ring.coords)[:-1])
            curves.append(ck)
            flags.append(np.full(len(ck), np.inf))
            total += float(ring.length)
            k += 1
    # laps beyond the last curve built lie on it again: the track never ends
    n_laps = 1 << 30
    pts = np.ascontiguousarray(np.concatenate(curves))
    off = np.cumsum([0] + [len(c) for c in curves]).astype(np.int64)
    theta = np.concatenate([_edge_theta(c) for c in curves])
    perims = [float(np.sum(np.hypot(*(np.roll(c, -1, axis=0) - c).T))) for c in curves]
    for a in (outline, pts, off, theta):
        a.setflags(write=False)
    dev = np.concatenate(flags)
    dev.setflags(write=False)
    return Surface(
        outline=outline,
        mode=mode,
        pts=pts,
        off=off,
        theta=theta,
        dev=dev,
        vidx=vidx,
        n_laps=n_laps,
        scale=scale,
        diameter=diameter,
        perimeter=per0,
        max_perimeter=max(perims),
    )


def _radius_bucket(link_length: float) -> float:
    """The link length rounded to 1/1024 of an octave (0.07 %) for the hug closing.

    Building a closing takes milliseconds, and a search over link lengths (the
    one-lap bisection) asks for many nearly equal ones: rounded, its last steps
    reuse one cached surface. A disc 0.07 % wider or narrower bridges the same
    concavities except at the knife-edge width.
    """
    return float(2.0 ** (np.round(np.log2(link_length) * 1024) / 1024))


def build_surface(
    outline: FloatArray,
    mode: str,
    thickness: float,
    arc_needed: float,
    mirror: bool,
    link_length: float,
) -> Surface:
    """Lap curves for a validated ccw outline (mirrored in x first for cw wraps).

    ``"taut"``: lap 0 is the convex hull. ``"hug"``: lap 0 is the boundary of the
    outline's closing by a disc of diameter ``link_length`` (concavities
    narrower than a link are bridged, wider ones followed), the diameter
    rounded to 0.07 % so that nearby link lengths share a surface. A
    ``thickness`` below ``1e-9`` of the object's extent counts as 0.
    """
    if mirror:
        outline = np.ascontiguousarray((outline * [-1.0, 1.0])[::-1])
    if thickness <= _NEGLIGIBLE * float(np.ptp(outline, axis=0).max()):
        thickness = 0.0  # below what a buffer resolves: the laps lie on one support
    if thickness == 0:
        arc_needed = 0.0
    else:  # bucket so that nearby chain lengths share a cached surface
        arc_needed = float(2.0 ** np.ceil(np.log2(max(arc_needed, 1e-300))))
    key_l = _radius_bucket(link_length) if mode == "hug" else 0.0
    return _build(outline.tobytes(), len(outline), mode, float(thickness), arc_needed, key_l)


def point_at_fraction(outline: FloatArray, fractions: FloatArray) -> FloatArray:
    """Points at the given fractions of the perimeter, from the first vertex, ccw."""
    closed = np.vstack([outline, outline[:1]])
    seg = np.hypot(*np.diff(closed, axis=0).T)
    s = np.concatenate([[0.0], np.cumsum(seg)])
    target = np.asarray(fractions, float) * s[-1]
    x = np.interp(target, s, closed[:, 0])
    y = np.interp(target, s, closed[:, 1])
    return np.stack([x, y], axis=-1)
