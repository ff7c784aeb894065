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

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import shapely

from . import _geometry as geo
from ._rounding import rounded
from .descriptors import (
    Geometry,
    MaskBatch,
    flatten_masks,
)
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


def _triangles(
    rings: np.ndarray, ring_starts: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Smallest triangle with each side on a line through an edge of each hull.

    Every such triangle encloses the hull (each side is a supporting line), so
    a chamfered (broken) corner is bridged by the two sides next to it. This
    is the classic result that a minimal enclosing triangle has a side flush
    with the polygon, applied to all three sides: no library offers it, and a
    search over edge triples is fast for hulls of tens of edges. The hulls
    (closed rings, one after the other) are simplified first (tolerance 0.25
    px, as :func:`shapely.simplify` does: :func:`~._geometry.simplify_rings`),
    and the sides lie on the 12 longest edges; a hull with no qualifying
    triple stays (simplified). Returns the
    simplified rings (closed, one after the other), their starts, whether a
    triangle was found and the triangles ``(n, 3, 2)``.
    """
    sxy, starts = geo.simplify_rings(rings, ring_starts, 0.25)
    normal, c, length, edge_starts = geo.hull_edges(sxy, starts)
    theta = np.arctan2(normal[:, 1], normal[:, 0])
    found, tris = geo.triangle_search(normal, c, theta, length, edge_starts)
    return sxy, starts, found, tris


_SHAPES = {
    "square": geo.RECTANGLE,
    "rectangle": geo.RECTANGLE,
    "circle": geo.CIRCLE,
    "triangle": geo.TRIANGLE,
}


def shape_codes(labels: Sequence | np.ndarray) -> np.ndarray:
    """The expected outline each label asks for (``geo.HULL`` for any other class)."""
    return np.array([_SHAPES.get(str(x), geo.HULL) for x in labels], dtype=np.int64)


def _expected_rings(
    rings: np.ndarray,
    ring_starts: np.ndarray,
    labels: Sequence | np.ndarray,
    code: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """:func:`expected_outline` of each centre hull ring (closed, one after the other).

    ``code``: :func:`shape_codes` of the labels, if at hand. Returns the
    outlines' rings as shapely gives their coordinates (closed, one after the
    other; a point or a line for hulls of collinear centres), their starts,
    whether each is a polygon, the circles' centroids (zero for the other
    outlines) and the shape each label asks for.
    """
    if code is None:
        code = shape_codes(labels)
    shape, triangles = geo.outline_shapes(ring_starts, code)
    if triangles.size:
        tri = _triangles(*geo.gather_rings(rings, ring_starts, triangles))
    else:
        tri = (
            np.zeros((0, 2)),
            np.zeros(1, dtype=np.int64),
            np.zeros(0, bool),
            np.zeros((0, 3, 2)),
        )
    return (*geo.expected_outlines(rings, ring_starts, shape, *tri), code)


def _centre_rings(cores: MaskBatch) -> tuple[np.ndarray, np.ndarray]:
    """Hull rings of the pixel centres of each object's core (burrs opened away)."""
    return geo.hulls_batch(*cores[:4], False)


def expected_outline(g: Geometry, label: str | None) -> shapely.Geometry:
    """The outline expected for an object of class ``label``, fitted to it.

    - square, rectangle: the minimum rotated rectangle of the hull;
    - triangle: the smallest triangle whose sides lie on edges of the hull;
    - circle: the minimum bounding circle of the hull;
    - any other (user) class: the convex hull itself.

    The hull is that of the pixel centres of the object's core.

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
    xy, starts, polygon = _expected_rings(*_centre_rings(flatten_masks([g.core])), [label])[:3]
    ring = xy[starts[0] : starts[1]]
    if polygon[0]:
        return shapely.polygons(ring)
    return shapely.linestrings(ring) if len(ring) == 2 else shapely.points(ring[0])


_KINDS = {
    geo.HOLE: ("hole", "hole of {} px"),
    geo.TRUNCATED: ("truncated", "part missing, {} px"),
    geo.BROKEN_CORNER: ("broken_corner", "corner missing, {} px"),
    geo.BITE: ("bite", "material missing, {} px"),
    geo.BURR: ("burr", "extra material, {} px"),
}


def defect_arrays(
    batch: MaskBatch,
    object_area: np.ndarray,
    width: Sequence[float] | np.ndarray,
    length: Sequence[float] | np.ndarray,
    labels: Sequence[str | None],
    settings: DefectSettings,
    extents: np.ndarray,
    centres: tuple[np.ndarray, np.ndarray] | None = None,
    shapes: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Defects of the objects of a measured batch, in arrays.

    ``extents``: ``(n, 4)`` the grid of each object in its mask's
    coordinates (infinite: no edge); ``centres``: the hull rings of the
    cores' pixel centres and their starts, if measured; ``shapes``:
    :func:`shape_codes` of the labels, if at hand. Returns what
    :func:`~._geometry.defect_groups` returns: ``ints`` (object, code, area,
    box) and ``floats`` (centroid, depth), one row per defect.
    """
    s = settings
    flat, starts, heights, widths, filled, core = batch
    assert filled is not None and core is not None  # set by measure_batch_arrays
    if centres is None:
        centres = _centre_rings(batch._replace(mask=core))
    xy, out_starts, polygon, circles, code = _expected_rings(*centres, labels, shapes)
    cornered = (code == geo.RECTANGLE) | (code == geo.TRIANGLE)
    kind, lo, canvas, frame, rings, vert_lo, vert_hi, limits = geo.defect_setup(
        xy, out_starts, polygon, code == geo.CIRCLE, cornered,
        heights, widths, np.asarray(object_area, dtype=float), np.asarray(width, dtype=float),
        np.asarray(length, dtype=float), float(s.min_area), float(s.min_area_fraction),
        float(s.min_depth), circles, float(s.margin),
    )  # fmt: skip
    return geo.defect_groups(
        flat, filled, starts, heights, widths, kind, lo, canvas, frame, rings, out_starts, xy,
        vert_lo, vert_hi, circles, limits, extents.astype(float), float(s.margin),
        int(s.min_hole_area), float(s.min_burr_area),
    )  # fmt: skip


#: The reason a defect of the kinds above gives: kind (spaced), centroid and note.
REASON = "{} at ({:.1f}, {:.1f}): {}"

_NAMES = {code: name for code, (name, _) in _KINDS.items()}
_NOTES = {code: note for code, (_, note) in _KINDS.items()}
_SPACED = {code: name.replace("_", " ") for code, name in _NAMES.items()}


def _ordered_records(
    ints: np.ndarray,
    floats: np.ndarray,
    tops: Sequence[int] | None,
    lefts: Sequence[int] | None,
) -> tuple[np.ndarray, np.ndarray, list[int], list[str], list[Defect], list[int]]:
    """The defects of :func:`defect_arrays` in record order, as records.

    Returns the ordered arrays, the defects' codes, notes and records, and
    where each object's defects begin in them (with the end last).
    """
    if tops is None or lefts is None:
        rows = cols = np.zeros(int(ints[:, 0].max()) + 1, dtype=np.int64)
    else:
        rows, cols = np.asarray(tops, dtype=np.int64), np.asarray(lefts, dtype=np.int64)
    ints, floats = geo.ordered_defects(ints, floats, rows, cols)
    codes = ints[:, 1].tolist()
    sizes = ints[:, 2].tolist()
    notes = list(map(str.format, map(_NOTES.__getitem__, codes), sizes))
    records = []
    new = object.__new__
    for name, size, box, centre, depth, note in zip(
        map(_NAMES.__getitem__, codes), sizes, map(tuple, ints[:, 3:7].tolist()),
        map(tuple, floats[:, :2].tolist()), rounded(floats[:, 2], 3).tolist(), notes, strict=True,
    ):  # fmt: skip
        d = new(Defect)  # new_defect(...), without a call per defect
        d.__dict__.update(
            {"kind": name, "area": size, "bbox": box, "centroid": centre, "depth": depth,
             "note": note}
        )  # fmt: skip
        records.append(d)
    firsts = np.flatnonzero(np.diff(ints[:, 0], prepend=-1)).tolist()
    return ints, floats, codes, notes, records, [*firsts, len(records)]


def defect_records(
    ints: np.ndarray,
    floats: np.ndarray,
    tops: Sequence[int] | None = None,
    lefts: Sequence[int] | None = None,
) -> dict[int, list[Defect]]:
    """The defects of :func:`defect_arrays` as records, by object (only objects with some).

    ``tops``, ``lefts``: rows and columns added to each object's defects'
    coordinates (as :meth:`Defect.shifted` would), default none.
    """
    if not ints.shape[0]:
        return {}
    ints, _, _, _, records, bounds = _ordered_records(ints, floats, tops, lefts)
    return {
        i: records[a:b]
        for i, a, b in zip(ints[bounds[:-1], 0].tolist(), bounds[:-1], bounds[1:], strict=True)
    }


def defect_fields(
    ints: np.ndarray,
    floats: np.ndarray,
    tops: Sequence[int] | None = None,
    lefts: Sequence[int] | None = None,
) -> dict[int, tuple[int, int, tuple[Defect, ...], tuple[str, ...]]]:
    """:func:`defect_records` as the fields of the objects' records, by object.

    Each object with defects gets its number of holes, their area, its
    defects and the reasons they give (:data:`REASON`), as an
    :class:`~tentaclass.scanner.Inspection` holds them.
    """
    if not ints.shape[0]:
        return {}
    ints, floats, codes, notes, records, bounds = _ordered_records(ints, floats, tops, lefts)
    reasons = list(
        map(
            REASON.format, map(_SPACED.__getitem__, codes), floats[:, 0].tolist(),
            floats[:, 1].tolist(), notes,
        )
    )  # fmt: skip
    starts = np.array(bounds[:-1])
    hole = ints[:, 1] == geo.HOLE
    holes = np.add.reduceat(hole.astype(np.int64), starts).tolist()
    hole_area = np.add.reduceat(np.where(hole, ints[:, 2], 0), starts).tolist()
    return {
        i: (n_holes, area, tuple(records[a:b]), tuple(reasons[a:b]))
        for i, n_holes, area, a, b in zip(
            ints[starts, 0].tolist(), holes, hole_area, bounds[:-1], bounds[1:], strict=True
        )
    }


def find_defects_many(
    geoms: Sequence[Geometry],
    labels: Sequence[str | None],
    settings: DefectSettings,
    extents: Sequence[tuple[float, float, float, float] | None],
    batch: MaskBatch | None = None,
    offsets: Sequence[tuple[int, int]] | None = None,
) -> list[list[Defect]]:
    """:func:`find_defects` of several objects in one batch.

    ``batch``: their masks, filled masks and cores flattened, if at hand
    (:func:`~tentaclass.scanner.descriptors.measure_many` returns it);
    ``offsets``: ``(row, col)`` added to every defect's coordinates (as
    :meth:`Defect.shifted` would), default none.
    """
    n = len(geoms)
    if n == 0:
        return []
    if batch is None:
        batch = flatten_masks([g.mask for g in geoms])
        batch = batch._replace(
            filled=np.concatenate([g.filled.ravel() for g in geoms]),
            core=np.concatenate([g.core.ravel() for g in geoms]),
        )
    ext = np.array([(-np.inf, -np.inf, np.inf, np.inf) if e is None else e for e in extents])
    ints, floats = defect_arrays(
        batch,
        np.array([g.area for g in geoms]),
        [g.width for g in geoms],
        [g.length for g in geoms],
        labels,
        settings,
        ext.reshape(n, 4),
    )
    if offsets is None:
        found = defect_records(ints, floats)
    else:
        found = defect_records(ints, floats, [o[0] for o in offsets], [o[1] for o in offsets])
    return [found.get(i, []) for i in range(n)]


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

    Notes
    -----
    A pixel is expected when its centre lies inside the expected outline
    (:func:`expected_outline`) grown by ``-margin``; each 8-connected group of
    missing or extra pixels is a candidate (4-connected for holes). The
    signed distance to a polygon outline is exact inside and, outside, the
    distance to the farthest edge line (mitre-style), which keeps corners
    sharp. A group of missing pixels reaches as deep as its farthest pixel
    from the remaining material (the Euclidean distance transform), so a cut
    corner is deep although it is near the outline.

    Examples
    --------
    >>> import numpy as np
    >>> from tentaclass.scanner.descriptors import measure
    >>> grid = np.ones((5, 5), dtype=bool)
    >>> grid[1:3, 2] = False
    >>> [(d.kind, d.area, d.bbox) for d in find_defects(measure(grid), "square")]
    [('hole', 2, (1, 2, 3, 3))]
    """
    return find_defects_many([g], [label], settings or DefectSettings(), [extent])[0]
