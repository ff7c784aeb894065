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
from typing import Any

import numpy as np
import shapely
from skimage.measure import regionprops

from .._deprecation import UNSET, renamed
from ..errors import InputError
from ..features import fourier_features
from ..geometry import points_to_angles, resample_closed
from ..shapes import from_mask
from ._geometry import fill_holes, mask_hull, max_distance_outside, opening_cross

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


def opening_radius(width: float) -> int:
    """Radius of the opening that removes burrs from an object ``width`` pixels wide.

    0 (no opening) below 12 pixels, where an opening would eat the shape
    itself; 1 above, which removes burrs up to 2 pixels thick.

    Examples
    --------
    >>> opening_radius(5.0), opening_radius(40.0)
    (0, 1)
    """
    return 0 if width < 12 else 1


def _sides(rect: shapely.Geometry) -> tuple[float, float]:
    xy = np.asarray(rect.exterior.coords)[:3]
    return float(np.hypot(*(xy[1] - xy[0]))), float(np.hypot(*(xy[2] - xy[1])))


def measure(mask: np.ndarray) -> Geometry:
    """Hull, minimum rotated rectangle and size of one object's mask.

    Parameters
    ----------
    mask : ndarray of bool, shape (rows, cols)
        The object's pixels (one connected object, validated by the caller).

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
    filled = fill_holes(mask)
    ring = _hull_coords(mask)
    hull = shapely.polygons(ring)
    rect = shapely.oriented_envelope(hull)
    l1, l2 = _sides(rect)
    core = filled
    radius = opening_radius(min(l1, l2))
    if radius:
        # Thin burrs would stretch the hull: if the opening removed something that
        # sticks out of the opened shape's hull by more than 2 pixels (more than
        # the corners an opening rounds off), measure the shape without it.
        opened = opening_cross(filled)  # skimage's disk(1): the 3 x 3 cross
        if opened.any():
            opened_ring = _hull_coords(opened)
            if max_distance_outside(opened_ring, ring[:-1, 0], ring[:-1, 1]) > 2.0:
                core, hull = opened, shapely.polygons(opened_ring)
                rect = shapely.oriented_envelope(hull)
                l1, l2 = _sides(rect)
    xy = np.asarray(rect.exterior.coords)[:4]
    e1, e2 = xy[1] - xy[0], xy[2] - xy[1]
    long_edge = e1 if l1 >= l2 else e2
    # rows grow downwards, so the on-screen angle uses -dy
    angle = float(np.degrees(np.arctan2(-long_edge[1], long_edge[0]))) % 180.0
    if angle > 180.0 - 1e-9:
        angle = 0.0
    return Geometry(
        mask=mask,
        filled=filled,
        core=core,
        area=int(mask.sum()),
        hull=hull,
        rect=rect,
        length=round(max(l1, l2), 9),
        width=round(min(l1, l2), 9),
        orientation=round(angle, 6),
    )


def _outlines_fourier(rings: list[np.ndarray], n_points: int, n_harmonics: int) -> np.ndarray:
    """Tentacle features of closed outlines: equal chords, turning angles, |DFT|.

    The rings are padded to one length by repeating their first vertex (a
    zero-length closing segment, which :func:`resample_closed` skips), so the
    whole batch goes through the library functions in one call each.
    """
    m = max(len(r) for r in rings)
    batch = np.stack([np.concatenate([r, np.repeat(r[:1], m - len(r), axis=0)]) for r in rings])
    q = points_to_angles(resample_closed(batch, n_points), closed=True)
    return fourier_features(q, n_harmonics, normalize=True)


def _hull_scalars(g: Geometry) -> list[float]:
    area = g.hull.area
    radius = shapely.minimum_bounding_radius(g.hull)
    return [
        area / (g.length * g.width),
        g.width / g.length,
        4 * np.pi * area / g.hull.length**2,
        area / (np.pi * radius**2),
        1.0 / np.sqrt(g.area),
    ]


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
            parts.append(np.array([_hull_scalars(g) for g in geoms]).reshape(n, -1))
            rings = [np.asarray(g.hull.exterior.coords)[:-1] for g in geoms]
            parts.append(_outlines_fourier(rings, n_points, n_harmonics))
        elif group == "outline":
            found = [(i, r) for i, g in enumerate(geoms) if (r := _outline_ring(g)) is not None]
            block = np.zeros((n, n_harmonics))
            if found:
                ok = [i for i, _ in found]
                block[ok] = _outlines_fourier([r for _, r in found], n_points, n_harmonics)
            parts.append(block)
        elif group == "region":
            parts.append(np.array([_region_features(g) for g in geoms]).reshape(n, -1))
        else:
            raise InputError(f"descriptors must be among {list(DESCRIPTOR_GROUPS)}, got {group!r}")
    return np.concatenate(parts, axis=1)
