"""One object's binary mask -> hull geometry and a feature vector for classification.

The class of an object should not change when it is damaged, so the default
descriptors are measured on its *convex hull*: holes and bites do not change
the hull, and a broken corner changes it only a little. Burrs would stretch
the hull, so an object with burrs is measured without them (its ``core``, see
:func:`measure`). The hull is that of the pixel squares (their corners), so
that even a one-pixel object has an area; it is exact for pixel data (no
find_contours smoothing needed).

Descriptor groups (``descriptors=`` of :class:`~tentaclass.scanner.ScannerModel`):

``"hull"`` (default)
    rectangularity (hull area over its minimum rotated rectangle), aspect
    (short over long side of that rectangle), circularity ``4 pi A / P^2``,
    fill of the minimum bounding circle, and the tentacle features of the hull
    outline: a chord walk of ``n_points`` equal steps around it
    (:func:`~tentaclass.geometry.resample_closed`), its turning angles
    (:func:`~tentaclass.geometry.points_to_angles`) and the first ``n_harmonics``
    :func:`~tentaclass.features.fourier_features`; plus the pixel scale
    ``1 / sqrt(area)``, which only matters for tiny objects (a one-pixel
    "circle" and a 2 x 2 "square" have the same hull shape).
``"outline"``
    the same Fourier features of the object's own outline
    (:func:`tentaclass.shapes.from_mask` of the hole-filled mask): sees
    concave classes, but also bites.
``"region"``
    solidity, extent and eccentricity of the mask
    (:func:`skimage.measure.regionprops`), and its number of holes (one minus
    the Euler number, divided by 4, at most 1): sees holes.

All are invariant to translation, rotation and scale up to pixel effects, and
all lie on a scale of about 0 to 1, so that they can be compared as they are.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np
import shapely
from skimage.measure import regionprops

from .._deprecation import UNSET, renamed
from .._validation import as_object_mask
from ..errors import InputError
from ..features import fourier_features
from ..features.fourier import MATMUL_MAX_JOINTS, _features_fft, _features_matmul
from ..geometry import points_to_angles, resample_closed
from ..shapes import from_mask
from ._geometry import (
    hull_descriptors,
    mask_hull,
    measure_cores,
    min_area_rectangles,
)
from ._rounding import rounded

__all__ = [
    "DESCRIPTOR_GROUPS",
    "Geometry",
    "feature_names",
    "features_matrix",
    "measure",
    "object_features",
]

DESCRIPTOR_GROUPS: tuple[str, ...] = ("hull", "outline", "region")
"""Descriptor groups :func:`object_features` can compute."""

_HULL_SCALARS = ("rectangularity", "aspect", "circularity", "circle_fill", "pixel_scale")
_REGION_SCALARS = ("solidity", "extent", "eccentricity", "holes")


@dataclass(frozen=True)
class Geometry:
    """Measurements of one object mask shared by features, defects and reports.

    Coordinates are ``(x, y) = (col, row)`` with pixel ``(r, c)`` centred at
    ``(c, r)``; ``filled`` is the mask with its holes filled; ``core`` is
    ``filled``, or, if it has burrs, ``filled`` after a morphological opening
    that removes them (see :func:`opening_radius`): the hull, rectangle and
    sizes are measured on ``core``.
    """

    mask: np.ndarray
    filled: np.ndarray
    core: np.ndarray
    area: int
    hull: shapely.Polygon
    rect: shapely.Polygon
    length: float
    width: float
    orientation: float


def _hull_coords(mask: np.ndarray, corners: bool = True) -> np.ndarray:
    """Closed ring of the hull of the pixel squares (``corners``) or centres, as GEOS orders it."""
    return mask_hull(mask, corners)


def _as_geometry(ring: np.ndarray) -> shapely.Geometry:
    """A hull ring from :func:`_hull_coords` as shapely would return the hull."""
    if len(ring) >= 4:
        return shapely.polygons(ring)
    return shapely.linestrings(ring) if len(ring) == 2 else shapely.points(ring[0])


def pixel_hull(mask: np.ndarray, *, corners: bool = True) -> shapely.Geometry:
    """Convex hull of the object's pixel squares (``corners``) or pixel centres.

    The same geometry as :func:`shapely.convex_hull` of those points, from a
    compiled monotone chain (much cheaper for small objects).

    Examples
    --------
    >>> import numpy as np
    >>> pixel_hull(np.ones((2, 3), dtype=bool)).bounds
    (-0.5, -0.5, 2.5, 1.5)
    """
    return _as_geometry(_hull_coords(mask, corners))


#: The narrowest object (short side of its rectangle) that is opened to remove burrs.
_OPEN_WIDTH = 12


def opening_radius(width: float) -> int:
    """Radius of the opening that removes burrs from an object ``width`` pixels wide.

    0 (no opening) below 12 pixels, where an opening would eat the shape
    itself; 1 above, which removes burrs up to 2 pixels thick.

    Examples
    --------
    >>> opening_radius(5.0), opening_radius(40.0)
    (0, 1)
    """
    return 0 if width < _OPEN_WIDTH else 1


class MaskBatch(NamedTuple):
    """Masks of several objects in flat bool buffers (C order), one after the other.

    Object ``i`` is ``mask[starts[i]:starts[i + 1]].reshape(heights[i],
    widths[i])``; ``filled`` and ``core`` (:class:`Geometry`) likewise, once
    measured.
    """

    mask: np.ndarray
    starts: np.ndarray
    heights: np.ndarray
    widths: np.ndarray
    filled: np.ndarray | None = None
    core: np.ndarray | None = None

    def views(self, flat: np.ndarray) -> list[np.ndarray]:
        """Each object's 2-D view of a flat buffer laid out like ``mask``."""
        return [
            flat[a:b].reshape(h, w)
            for a, b, h, w in zip(
                self.starts[:-1].tolist(),
                self.starts[1:].tolist(),
                self.heights.tolist(),
                self.widths.tolist(),
                strict=True,
            )
        ]


def flatten_masks(masks: Sequence[np.ndarray]) -> MaskBatch:
    """Masks in one flat bool buffer."""
    n = len(masks)
    shapes = np.array([m.shape for m in masks], dtype=np.int64).reshape(n, 2)
    starts = np.zeros(n + 1, dtype=np.int64)
    np.cumsum(shapes[:, 0] * shapes[:, 1], out=starts[1:])
    flat = np.concatenate([m.ravel() for m in masks]).astype(bool, copy=False)
    return MaskBatch(flat, starts, shapes[:, 0].copy(), shapes[:, 1].copy())


def polygons_from_rings(coords: np.ndarray, ring_starts: np.ndarray) -> np.ndarray:
    """Shapely polygons of closed rings stored one after the other (``ring_starts``)."""
    n = ring_starts.size - 1
    return shapely.from_ragged_array(
        shapely.GeometryType.POLYGON, coords, (ring_starts, np.arange(n + 1))
    )


def rectangles_of_rings(
    coords: np.ndarray, ring_starts: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Minimum rotated rectangles of convex rings stored one after the other.

    The rings are closed and in the order GEOS's convex hull gives (as
    :func:`~._geometry.mask_hull` makes them); returns the rectangles'
    corners ``(n, 5, 2)`` (closed) and the rectangles as shapely polygons: the
    same as :func:`shapely.oriented_envelope` of the rings' polygons, from a
    compiled copy of its algorithm and arithmetic.
    """
    corners = min_area_rectangles(coords, ring_starts)
    n = corners.shape[0]
    return corners, polygons_from_rings(corners.reshape(5 * n, 2), np.arange(0, 5 * n + 1, 5))


class Measures(NamedTuple):
    """What :func:`measure` finds, for a batch of objects in arrays.

    ``batch``: the masks, filled masks and cores in flat buffers; ``area`` the
    object pixels; ``sums`` the sums of the pixels' row and column indices;
    ``rings`` the hulls of the cores' pixel squares (closed, one after the
    other from ``ring_starts``); ``corners`` the minimum rotated rectangles
    ``(n, 5, 2)``; ``length``, ``width`` and ``orientation`` as in
    :class:`Geometry`; ``centres`` the hulls of the cores' pixel centres
    (closed, one after the other from ``centre_starts``).
    """

    batch: MaskBatch
    area: np.ndarray
    sums: np.ndarray
    rings: np.ndarray
    ring_starts: np.ndarray
    corners: np.ndarray
    length: np.ndarray
    width: np.ndarray
    orientation: np.ndarray
    centres: np.ndarray
    centre_starts: np.ndarray

    def geometries(self) -> list[Geometry]:
        """One :class:`Geometry` per object (shapely hulls and rectangles built here)."""
        b = self.batch
        assert b.filled is not None and b.core is not None
        n = self.area.shape[0]
        hulls = polygons_from_rings(self.rings, self.ring_starts)
        rects = polygons_from_rings(self.corners.reshape(5 * n, 2), np.arange(0, 5 * n + 1, 5))
        geoms = []
        new = object.__new__
        for mask, f, core, area, hull, rect, long, short, angle in zip(
            b.views(b.mask), b.views(b.filled), b.views(b.core), self.area.tolist(), hulls,
            rects, self.length.tolist(), self.width.tolist(), self.orientation.tolist(),
            strict=True,
        ):  # fmt: skip
            g = new(Geometry)  # Geometry(mask, f, ...) without its frozen __setattr__ per field
            g.__dict__.update(
                {"mask": mask, "filled": f, "core": core, "area": area, "hull": hull,
                 "rect": rect, "length": long, "width": short, "orientation": angle}
            )  # fmt: skip
            geoms.append(g)
        return geoms


def measure_batch_arrays(batch: MaskBatch) -> Measures:
    """:func:`measure` of every mask of a batch, in arrays (no per-object objects)."""
    # Thin burrs would stretch the hull: objects wide enough for an opening
    # (see opening_radius) are measured without what it removes, if that
    # sticks out of the opened shape's hull (skimage's disk(1): the 3 x 3 cross)
    (
        filled_flat, core_flat, coords, ring_starts, areas, sums, corners, long, short, edge,
        centres, centre_starts,
    ) = measure_cores(*batch[:4], float(_OPEN_WIDTH))  # fmt: skip
    # rows grow downwards, so the on-screen angle uses -dy
    angles = np.remainder(np.degrees(np.arctan2(-edge[:, 1], edge[:, 0])), 180.0)
    angles[angles > 180.0 - 1e-9] = 0.0
    return Measures(
        batch._replace(filled=filled_flat, core=core_flat),
        areas,
        sums,
        coords,
        ring_starts,
        corners,
        rounded(long, 9),
        rounded(short, 9),
        rounded(angles, 6),
        centres,
        centre_starts,
    )


def measure_many(
    masks: Sequence[np.ndarray], batch: MaskBatch | None = None
) -> tuple[list[Geometry], np.ndarray, MaskBatch]:
    """:func:`measure` of several masks in one batch.

    Returns the geometries, the ``(n, 2)`` sums of the row and column indices
    of each mask's pixels (divided by the area: the centroid) and the masks,
    filled masks and cores in flat buffers. ``batch``: the masks already
    flattened (``masks`` are then views of it).
    """
    n = len(masks)
    if batch is None:
        batch = flatten_masks(masks) if n else MaskBatch(*(np.zeros(k, int) for k in (0, 1, 0, 0)))
    if n == 0:
        return [], np.zeros((0, 2)), batch._replace(filled=batch.mask, core=batch.mask)
    m = measure_batch_arrays(batch)
    geoms = m.geometries()
    for g, mask in zip(geoms, masks, strict=True):
        g.__dict__["mask"] = mask
    return geoms, m.sums, m.batch


def measure(mask: np.ndarray) -> Geometry:
    """Hull, minimum rotated rectangle and size of one object's mask.

    Parameters
    ----------
    mask : ndarray of bool, shape (rows, cols)
        The object's pixels: one connected object (bool, or 0 and 1), at
        least one pixel.

    Returns
    -------
    geometry : Geometry
        ``length`` and ``width`` are the long and short sides of the minimum
        rotated rectangle of the pixel squares (of ``core``: burrs do not
        count); ``orientation`` the direction
        of the long side in degrees in [0, 180), counter-clockwise from the
        belt's x axis (columns) as seen on the image (rows down).

    Examples
    --------
    >>> import numpy as np
    >>> g = measure(np.ones((2, 4), dtype=bool))
    >>> g.area, g.length, g.width, g.orientation
    (8, 4.0, 2.0, 0.0)
    """
    return measure_many([as_object_mask(mask)])[0][0]


def _padded_rings(coords: np.ndarray, index: np.ndarray, n: int) -> np.ndarray:
    """Closed rings stored one after the other, padded to one length.

    ``index`` gives the ring of each vertex (closing vertices dropped); rings
    are padded by repeating their first vertex (a zero-length closing
    segment, which :func:`resample_closed` skips).
    """
    counts = np.bincount(index, minlength=n)
    first = np.zeros(n + 1, dtype=np.int64)
    np.cumsum(counts, out=first[1:])
    batch = np.repeat(coords[first[:-1]][:, None, :], counts.max(), axis=1)
    batch[index, np.arange(index.size) - first[index]] = coords
    return batch


def _outlines_fourier(batch: np.ndarray, n_points: int, n_harmonics: int) -> np.ndarray:
    """Tentacle features of padded closed outlines: equal chords, turning angles, |DFT|."""
    q = points_to_angles(resample_closed(batch, n_points), closed=True)
    return fourier_features(q, n_harmonics, normalize=True)


def _turning_fourier(q: np.ndarray, n_harmonics: int) -> np.ndarray:
    """``fourier_features(q, n_harmonics, normalize=True)`` of turning angles.

    ``q`` (n, n_points) holds angles in [-pi, pi]: with a valid
    ``n_harmonics`` the same computation without the array checks and the
    dispatch, which cost more than the product on a small batch; any other
    ``n_harmonics`` (or fewer than 2 points) goes to :func:`fourier_features`,
    which refuses it.

    Examples
    --------
    >>> q = np.tile([0.0, 0.0, 0.0, np.pi / 2], (2, 4))
    >>> bool(np.array_equal(_turning_fourier(q, 4), fourier_features(q, 4, normalize=True)))
    True
    >>> _turning_fourier(q, 9)
    Traceback (most recent call last):
    ...
    tentaclass.errors.InputError: n_harmonics must be at most floor(n_joints / 2) = 8 for 16...
    """
    n = q.shape[1]
    valid = isinstance(n_harmonics, int | np.integer) and not isinstance(n_harmonics, bool)
    if not (valid and n >= 2 and 1 <= n_harmonics <= n // 2):
        return fourier_features(q, n_harmonics, normalize=True)
    out = np.empty((q.shape[0], n_harmonics))
    kernel = _features_matmul if n <= MATMUL_MAX_JOINTS else _features_fft
    kernel(q, n_harmonics, False, 2 * np.pi, True, out)
    out /= n
    return out


def hull_features(
    rings: np.ndarray,
    ring_starts: np.ndarray,
    length: Sequence[float] | np.ndarray,
    width: Sequence[float] | np.ndarray,
    pixels: np.ndarray,
    n_points: int,
    n_harmonics: int,
) -> np.ndarray:
    """The ``"hull"`` group of every object from its hull ring (closed, one after the other)."""
    # the scalars from shapely.area, shapely.length and shapely.minimum_bounding_radius,
    # compiled (GEOS's algorithms and arithmetic: the same bits), and the operands of
    # the turning angles of each hull's chord walk, in one compiled pass
    scalars, cross, dot, bad = hull_descriptors(
        rings,
        ring_starts,
        np.asarray(length, dtype=float),
        np.asarray(width, dtype=float),
        np.asarray(pixels, dtype=float),
        n_points,
    )
    if bad:
        raise InputError("an outline has zero perimeter or two coinciding chord ends")
    turns = _turning_fourier(np.arctan2(cross, dot), n_harmonics)
    return np.concatenate([scalars, turns], axis=1)


def _hull_features(geoms: Sequence[Geometry], n_points: int, n_harmonics: int) -> np.ndarray:
    """The ``"hull"`` group of every object: scalars and hull-outline Fourier features."""
    n = len(geoms)
    hulls = np.empty(n, dtype=object)
    hulls[:] = [g.hull for g in geoms]
    coords, index = shapely.get_coordinates(hulls, return_index=True)
    return hull_features(
        coords,
        np.searchsorted(index, np.arange(n + 1)),
        [g.length for g in geoms],
        [g.width for g in geoms],
        np.array([g.area for g in geoms]),
        n_points,
        n_harmonics,
    )


def _outline_ring(g: Geometry) -> np.ndarray | None:
    """The object's outer outline (:func:`tentaclass.shapes.from_mask`), or None if degenerate."""
    try:
        return from_mask(g.filled)
    except InputError:
        return None


def _region_features(g: Geometry) -> np.ndarray:
    p = regionprops(g.mask.astype(np.uint8))[0]
    # number of holes (1 - Euler number) on the 0-1 scale of the other features
    holes = min(max(1 - p.euler_number, 0), 4) / 4
    return np.array([p.solidity, p.extent, p.eccentricity, holes])


def feature_names(
    descriptors: Sequence[str] = ("hull",), n_harmonics: int = 8, *, n_coeffs: Any = UNSET
) -> list[str]:
    """Names of the columns of :func:`object_features` (``n_coeffs``: deprecated alias).

    Examples
    --------
    >>> feature_names(("hull",), n_harmonics=2)
    ['rectangularity', 'aspect', 'circularity', 'circle_fill', 'pixel_scale', 'hull_f1', 'hull_f2']
    """
    n_harmonics = renamed("n_harmonics", n_harmonics, "n_coeffs", n_coeffs, default=8)
    names: list[str] = []
    for group in descriptors:
        if group == "hull":
            names += [*_HULL_SCALARS, *(f"hull_f{k}" for k in range(1, n_harmonics + 1))]
        elif group == "outline":
            names += [f"outline_f{k}" for k in range(1, n_harmonics + 1)]
        elif group == "region":
            names += list(_REGION_SCALARS)
        else:
            raise InputError(f"descriptors must be among {list(DESCRIPTOR_GROUPS)}, got {group!r}")
    return names


def object_features(
    g: Geometry,
    descriptors: Sequence[str] = ("hull",),
    *,
    n_points: int = 64,
    n_harmonics: int = 8,
    n_coeffs: Any = UNSET,
) -> np.ndarray:
    """Feature vector of one measured object.

    Parameters
    ----------
    g : Geometry
        From :func:`measure`.
    descriptors : sequence of {"hull", "outline", "region"}, default=("hull",)
        Groups to compute, in this order (see the module docstring).
    n_points : int, default=64
        Chords of the walk around an outline.
    n_harmonics : int, default=8
        Fourier features kept per outline.
    n_coeffs : int, optional
        Deprecated alias of ``n_harmonics``.

    Returns
    -------
    features : ndarray of shape (n_features,)

    Examples
    --------
    >>> import numpy as np
    >>> f = object_features(measure(np.ones((5, 5), dtype=bool)))
    >>> f.shape, [round(float(v), 3) for v in f[:3]]
    ((13,), [1.0, 1.0, 0.785])
    """
    n_harmonics = renamed("n_harmonics", n_harmonics, "n_coeffs", n_coeffs, default=8)
    return features_matrix([g], descriptors, n_points=n_points, n_harmonics=n_harmonics)[0]


def features_matrix(
    geoms: Sequence[Geometry],
    descriptors: Sequence[str] = ("hull",),
    *,
    n_points: int = 64,
    n_harmonics: int = 8,
    n_coeffs: Any = UNSET,
) -> np.ndarray:
    """:func:`object_features` of several objects, computed in batches.

    ``n_coeffs`` is a deprecated alias of ``n_harmonics``.

    Returns
    -------
    features : ndarray of shape (n_objects, n_features)
    """
    n_harmonics = renamed("n_harmonics", n_harmonics, "n_coeffs", n_coeffs, default=8)
    n = len(geoms)
    parts = []
    for group in descriptors:
        if group == "hull":
            parts.append(_hull_features(geoms, n_points, n_harmonics))
        elif group == "outline":
            found = [(i, r) for i, g in enumerate(geoms) if (r := _outline_ring(g)) is not None]
            block = np.zeros((n, n_harmonics))
            if found:
                ok = [i for i, _ in found]
                rings = [r for _, r in found]
                index = np.repeat(np.arange(len(rings)), [len(r) for r in rings])
                batch = _padded_rings(np.concatenate(rings), index, len(rings))
                block[ok] = _outlines_fourier(batch, n_points, n_harmonics)
            parts.append(block)
        elif group == "region":
            parts.append(np.array([_region_features(g) for g in geoms]).reshape(n, -1))
        else:
            raise InputError(f"descriptors must be among {list(DESCRIPTOR_GROUPS)}, got {group!r}")
    return np.concatenate(parts, axis=1)


def measures_features(
    m: Measures, descriptors: Sequence[str], n_points: int, n_harmonics: int
) -> np.ndarray:
    """:func:`features_matrix` of the objects of a measured batch."""
    if tuple(descriptors) == ("hull",):  # from the arrays, no per-object geometry
        return hull_features(
            m.rings, m.ring_starts, m.length, m.width, m.area, n_points, n_harmonics
        )
    return features_matrix(m.geometries(), descriptors, n_points=n_points, n_harmonics=n_harmonics)
