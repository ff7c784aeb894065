"""Defects of one object: holes, missing material and extra material.

Holes are the gaps enclosed by the object (:func:`scipy.ndimage.binary_fill_holes`).
Missing and extra material are found by comparing the object with the outline
*expected* for its class, fitted to the object:

- square, rectangle: the minimum rotated rectangle of the object's hull;
- triangle: the smallest triangle whose sides lie on edges of the hull;
- circle: the minimum bounding circle of the hull;
- any other (user) class: the convex hull itself.

The hull is that of the pixel *centres* of the object's core (the object
without burrs, see :class:`~tentaclass.scanner.descriptors.Geometry`), so
that burrs do not inflate it. A pixel is expected to be set when its centre
lies inside the expected outline grown by ``-margin``. Enclosing outlines make
bites, broken corners and cut-off parts show up as missing pixels; burrs show
up outside the outline grown by ``1 + margin``. Each 8-connected group of
missing or extra pixels is a candidate; it becomes a defect when it is large
and deep enough (see :class:`DefectSettings`).
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numba as nb
import numpy as np
import shapely
from scipy import ndimage

from ._geometry import label_runs
from .descriptors import Geometry, pixel_hull
from .records import Defect

__all__ = ["DefectSettings", "expected_outline", "find_defects"]


@dataclass(frozen=True)
class DefectSettings:
    """Decision thresholds for defects.

    Parameters
    ----------
    min_hole_area : int, default=1
        Smallest hole, in pixels, that rejects an object.
    min_area : float, default=4
        Smallest group of missing or extra pixels that counts as a defect; for
        tiny objects (under ``10 * min_area`` pixels) a tenth of the object's
        area, but at least 1 pixel.
    min_area_fraction : float, default=0.003
        ... and at least this share of the object's area.
    min_burr_area : float, default=2
        Smallest group of extra pixels (outside the outline grown by
        ``1 + margin``) that counts as a burr; it must also reach
        ``min_depth``. Smaller than ``min_area`` because most of a thin burr
        lies inside that band; clean shapes leave at most single pixels there.
    min_depth : float, default=1.5
        Depth in pixels a group must reach: for missing material the largest
        distance from a missing pixel to the remaining object, for extra
        material the largest distance out of the expected outline. For thin
        objects a fifth of their width, but at least 1 pixel. Pixel staircases
        along slanted edges reach 1 to 1.41 pixels.
    margin : float, default=-0.1
        Tolerance in pixels on the expected outline: a pixel is expected when its
        centre lies inside the outline shrunk by ``margin`` (negative: grown, so
        that pixels centred on the outline count as expected), and extra when it
        lies outside the outline grown by ``1 + margin``.
    """

    min_hole_area: int = 1
    min_area: float = 4.0
    min_area_fraction: float = 0.003
    min_burr_area: float = 2.0
    min_depth: float = 1.5
    margin: float = -0.1

    def area_threshold(self, object_area: int) -> float:
        """Smallest defect area for an object of ``object_area`` pixels.

        Examples
        --------
        >>> s = DefectSettings()
        >>> s.area_threshold(18), s.area_threshold(1000), s.area_threshold(4000)
        (1.8, 4.0, 12.0)
        """
        small = min(self.min_area, max(1.0, 0.1 * object_area))
        return max(small, self.min_area_fraction * object_area)

    def depth_threshold(self, object_width: float) -> float:
        """Smallest defect depth for an object ``object_width`` pixels wide.

        Examples
        --------
        >>> DefectSettings().depth_threshold(5.0), DefectSettings().depth_threshold(30.0)
        (1.0, 1.5)
        """
        return min(self.min_depth, max(1.0, 0.2 * object_width))


@nb.njit(cache=True, nogil=True)
def _meet(normal: np.ndarray, c: np.ndarray, i: int, j: int) -> tuple[float, float]:
    """Where the lines ``normal[i] . p = c[i]`` and ``normal[j] . p = c[j]`` cross."""
    det = normal[i, 0] * normal[j, 1] - normal[i, 1] * normal[j, 0]
    x = (c[i] * normal[j, 1] - c[j] * normal[i, 1]) / det
    y = (normal[i, 0] * c[j] - normal[j, 0] * c[i]) / det
    return x, y


@nb.njit(cache=True, nogil=True)
def _best_triangle(normal: np.ndarray, c: np.ndarray, theta: np.ndarray) -> tuple:
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


def _enclosing_triangle(hull: shapely.Polygon) -> shapely.Polygon:
    """Smallest triangle with each side on a line through an edge of ``hull``.

    Every such triangle encloses the hull (each side is a supporting line), so
    a chamfered (broken) corner is bridged by the two sides next to it. This
    is the classic result that a minimal enclosing triangle has a side flush
    with the polygon, applied to all three sides: no library offers it, and a
    vectorised search over edge triples is fast for hulls of tens of edges.
    """
    hull = shapely.simplify(hull, 0.25)
    xy = np.asarray(shapely.orient_polygons(hull).exterior.coords)
    d = np.diff(xy, axis=0)
    keep = np.hypot(d[:, 0], d[:, 1]) > 1e-9
    p, d = xy[:-1][keep], d[keep]
    if len(d) < 3:
        return hull
    normal = np.stack([d[:, 1], -d[:, 0]], axis=1)  # outward for a CCW ring
    length = np.hypot(normal[:, 0], normal[:, 1])
    normal /= length[:, None]
    c = np.einsum("ij,ij->i", normal, p)
    theta = np.unwrap(np.arctan2(normal[:, 1], normal[:, 0]))
    # The sides lie on long edges: search the 12 longest, in ring order.
    top = np.sort(np.argsort(-length, kind="stable")[:12])
    normal, c, theta = normal[top], c[top], theta[top]
    k, tri = _best_triangle(normal, c, theta)
    return shapely.Polygon(tri) if k >= 0 else hull


def _centre_hull(core: np.ndarray) -> shapely.Geometry:
    """Hull of the pixel centres of the object's core (burrs opened away)."""
    return pixel_hull(core, corners=False)


def expected_outline(g: Geometry, label: str | None) -> shapely.Geometry:
    """The outline expected for an object of class ``label``, fitted to it.

    Parameters
    ----------
    g : Geometry
        The measured object (see :func:`~tentaclass.scanner.descriptors.measure`).
    label : str or None
        Its class; classes other than the four thesis shapes use the hull.

    Returns
    -------
    outline : shapely geometry
        In ``(x, y) = (col, row)`` pixel-centre coordinates of ``g.mask``.

    Examples
    --------
    >>> import numpy as np
    >>> from tentaclass.scanner.descriptors import measure
    >>> g = measure(np.ones((3, 4), dtype=bool))
    >>> expected_outline(g, "rectangle").bounds
    (0.0, 0.0, 3.0, 2.0)
    """
    hull = _centre_hull(g.core)
    if hull.geom_type != "Polygon":
        return hull
    if label in ("square", "rectangle"):
        return shapely.oriented_envelope(hull)
    if label == "circle":
        return shapely.minimum_bounding_circle(hull)
    if label == "triangle":
        return _enclosing_triangle(hull)
    return hull


def _signed_distance(
    outline: shapely.Geometry, label: str | None, shape: tuple[int, int], lo: np.ndarray
) -> np.ndarray:
    """Signed distance of each canvas pixel centre to a convex outline (> 0 inside).

    Exact inside; outside, the distance to the farthest edge line (mitre-style),
    which keeps corners sharp. Written out because rasterising buffered
    polygons with skimage.draw costs several times more for these small canvases.
    """
    rows = np.arange(shape[0], dtype=float)[:, None] + lo[0]
    cols = np.arange(shape[1], dtype=float)[None, :] + lo[1]
    if label == "circle":
        c = outline.centroid
        r = float(np.max(np.hypot(*(np.asarray(outline.exterior.coords) - (c.x, c.y)).T)))
        return r - np.hypot(cols - c.x, rows - c.y)
    xy = np.asarray(shapely.orient_polygons(outline).exterior.coords)
    d = np.diff(xy, axis=0)
    length = np.hypot(d[:, 0], d[:, 1])
    keep = length > 1e-9
    p, d, length = xy[:-1][keep], d[keep], length[keep]
    nx, ny = d[:, 1] / length, -d[:, 0] / length  # outward normals of a CCW ring
    c = nx * p[:, 0] + ny * p[:, 1]
    return _edge_distance(c, nx, ny, rows[:, 0], cols[0])


@nb.njit(cache=True, nogil=True)
def _edge_distance(
    c: np.ndarray, nx: np.ndarray, ny: np.ndarray, rows: np.ndarray, cols: np.ndarray
) -> np.ndarray:
    """``min over edges of (c - nx * col) - ny * row`` at every canvas pixel."""
    out = np.empty((rows.shape[0], cols.shape[0]))
    for i in range(rows.shape[0]):
        for j in range(cols.shape[0]):
            best = np.inf
            for e in range(c.shape[0]):
                v = (c[e] - nx[e] * cols[j]) - ny[e] * rows[i]
                if v < best:
                    best = v
            out[i, j] = best
    return out


def _components(region: np.ndarray, eight: bool = True) -> list[tuple[np.ndarray, np.ndarray]]:
    """``(rows, cols)`` of each 8- (or 4-) connected group, numbered as ndimage.label does."""
    if not region.any():
        return []
    rr, cc, starts = label_runs(region, eight)
    return [(rr[a:b], cc[a:b]) for a, b in itertools.pairwise(starts.tolist())]


def _box(rr: np.ndarray, cc: np.ndarray) -> tuple[int, int, int, int]:
    return (int(rr.min()), int(cc.min()), int(rr.max()) + 1, int(cc.max()) + 1)


def find_defects(
    g: Geometry,
    label: str | None,
    settings: DefectSettings | None = None,
    *,
    extent: tuple[float, float, float, float] | None = None,
) -> list[Defect]:
    """Holes, missing and extra material of one object.

    Parameters
    ----------
    g : Geometry
        The measured object.
    label : str or None
        Its class (selects the expected outline, see :func:`expected_outline`).
    settings : DefectSettings, optional
        Thresholds; default :class:`DefectSettings()`.
    extent : tuple of 4 floats, optional
        ``(row0, col0, row1, col1)`` of the whole grid (or belt) in ``g.mask``
        coordinates; missing material outside it was cut off by the grid's
        edge and is reported as ``truncated``. Default: no edge.

    Returns
    -------
    defects : list of Defect
        In ``g.mask`` coordinates: holes first, then missing, then extra
        material, each largest first.

    Examples
    --------
    >>> import numpy as np
    >>> from tentaclass.scanner.descriptors import measure
    >>> grid = np.ones((5, 5), dtype=bool)
    >>> grid[1:3, 2] = False
    >>> [(d.kind, d.area, d.bbox) for d in find_defects(measure(grid), "square")]
    [('hole', 2, (1, 2, 3, 3))]
    """
    s = settings or DefectSettings()
    defects: list[Defect] = []
    holes = g.filled & ~g.mask
    if holes.any():
        # Holes are 4-connected: the background's connectivity for 8-connected objects.
        for rr, cc in sorted(_components_4(holes), key=lambda x: -len(x[0])):
            if len(rr) >= s.min_hole_area:
                defects.append(
                    Defect(
                        "hole",
                        len(rr),
                        _box(rr, cc),
                        (float(rr.mean()), float(cc.mean())),
                        0.0,
                        f"hole of {len(rr)} px",
                    )
                )
    outline = expected_outline(g, label)
    if outline.geom_type != "Polygon" or outline.area < 4:
        return defects
    # Canvas covering both the mask and the expected outline.
    x0, y0, x1, y1 = outline.bounds
    lo = np.floor([min(y0, 0) - 2, min(x0, 0) - 2]).astype(int)
    hi = np.ceil([max(y1, g.mask.shape[0]) + 2, max(x1, g.mask.shape[1]) + 2]).astype(int)
    shape = (int(hi[0] - lo[0]), int(hi[1] - lo[1]))
    filled = np.zeros(shape, dtype=bool)
    mask = np.zeros(shape, dtype=bool)
    sl = (slice(-lo[0], -lo[0] + g.mask.shape[0]), slice(-lo[1], -lo[1] + g.mask.shape[1]))
    filled[sl], mask[sl] = g.filled, g.mask
    sd = _signed_distance(outline, label, shape, lo)
    area_min = s.area_threshold(g.area)
    depth_min = s.depth_threshold(g.width)
    exp_area = outline.area
    vertices = (
        np.asarray(outline.exterior.coords)[:-1] - lo[::-1]
        if label in ("square", "rectangle", "triangle")
        else np.empty((0, 2))
    )
    corner_radius = min(3.0, max(1.0, 0.1 * g.length))

    def inside_grid(rr: np.ndarray, cc: np.ndarray) -> bool:
        """Whether all these canvas pixels lie inside the grid (or belt)."""
        if extent is None:
            return True
        r, c = rr + lo[0], cc + lo[1]
        return bool(np.all((r >= extent[0]) & (r < extent[2]) & (c >= extent[1]) & (c < extent[3])))

    missing = (sd >= s.margin) & ~filled
    extra = mask & (sd < -(1.0 + s.margin))
    gap = None
    for kind_group, region, smallest in (
        ("missing", missing, area_min),
        ("extra", extra, s.min_burr_area),
    ):
        found = []
        for rr, cc in _components(region):
            if len(rr) < smallest:
                continue
            if kind_group == "missing":
                # How far the gap reaches from the remaining material: a cut
                # corner is deep by this measure although it is near the outline.
                if gap is None:
                    gap = ndimage.distance_transform_edt(~filled)
                depth = float(gap[rr, cc].max())
            else:
                depth = float(-sd[rr, cc].min())
            if depth < depth_min:
                continue
            box = _box(rr + lo[0], cc + lo[1])
            cen = (float(rr.mean() + lo[0]), float(cc.mean() + lo[1]))
            if kind_group == "extra":
                kind, note = "burr", f"extra material, {len(rr)} px"
            elif len(rr) >= 0.2 * exp_area or not inside_grid(rr, cc):
                kind, note = "truncated", f"part missing, {len(rr)} px"
            elif (
                len(vertices)
                and np.min(
                    np.hypot(vertices[:, None, 0] - cc[None], vertices[:, None, 1] - rr[None])
                )
                <= corner_radius
            ):
                kind, note = "broken_corner", f"corner missing, {len(rr)} px"
            else:
                kind, note = "bite", f"material missing, {len(rr)} px"
            found.append(Defect(kind, len(rr), box, cen, round(depth, 3), note))
        defects += sorted(found, key=lambda d: -d.area)
    return defects


def _components_4(region: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
    return _components(region, eight=False)
