"""Seeded generator of scanner objects: clean and damaged shapes, and whole belts.

Shapes are drawn as exact polygons (or discs) and rasterised by pixel centre
(:func:`skimage.draw.polygon`), so a pixel is set when its centre lies inside
the shape, as on a real line sensor that thresholds each pixel's coverage.
Damage is stamped on the clean grid: *holes* (a disc removed well inside the
object), *bites* (a disc removed at a boundary pixel, or at a corner: a broken
corner) and *burrs* (a thin strip added outside).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from scipy import ndimage
from skimage.draw import disk, polygon
from sklearn.utils import Bunch, check_random_state

from .._deprecation import UNSET, renamed
from .._thesis_data import THESIS_CLASSES
from .._validation import MAX_SAMPLES, check_positive_float, check_positive_int, check_total
from ..errors import InputError

__all__ = ["DAMAGE_KINDS", "draw_shape", "make_belt", "make_objects", "shape_polygon"]

DAMAGE_KINDS: tuple[str, ...] = ("hole", "bite", "burr")
"""Kinds of damage :func:`make_objects` can stamp on an object."""

# Circumradius of each class per unit of its nominal size (side, long side or
# diameter), used to fit a rotated object into its grid.
_ASPECT_RANGE = (1.6, 2.6)


def shape_polygon(
    label: str,
    size: float,
    *,
    angle: float = 0.0,
    center: Sequence[float] = (0.0, 0.0),
    aspect: float = 2.0,
) -> np.ndarray:
    """Vertices of one of the four thesis shapes, in ``(row, col)`` coordinates.

    Parameters
    ----------
    label : {"square", "circle", "triangle", "rectangle"}
        The shape.
    size : float
        Side of a square or equilateral triangle, long side of a rectangle,
        diameter of a circle, in pixels.
    angle : float, default=0.0
        Rotation in radians, counter-clockwise as seen on the belt image.
    center : sequence of 2 floats, default=(0, 0)
        ``(row, col)`` of the shape's centroid.
    aspect : float, default=2.0
        Long side over short side of a rectangle (ignored for other shapes).

    Returns
    -------
    vertices : ndarray of shape (n_vertices, 2)
        ``(row, col)`` vertices; a circle is a 96-gon.

    Examples
    --------
    >>> shape_polygon("square", 2.0).round(3).tolist()
    [[1.0, -1.0], [1.0, 1.0], [-1.0, 1.0], [-1.0, -1.0]]
    """
    size = check_positive_float(size, "size")
    if label == "square":
        xy = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], dtype=float) * size / 2
    elif label == "rectangle":
        aspect = check_positive_float(aspect, "aspect")
        xy = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], dtype=float)
        xy *= np.array([size / 2, size / 2 / aspect])
    elif label == "triangle":
        t = np.pi / 2 + 2 * np.pi / 3 * np.arange(3)
        xy = np.stack([np.cos(t), np.sin(t)], axis=1) * size / np.sqrt(3)
    elif label == "circle":
        t = 2 * np.pi * np.arange(96) / 96
        xy = np.stack([np.cos(t), np.sin(t)], axis=1) * size / 2
    else:
        raise InputError(f"label must be one of {list(THESIS_CLASSES)}, got {label!r}")
    c, s = np.cos(angle), np.sin(angle)
    x = c * xy[:, 0] - s * xy[:, 1]
    y = s * xy[:, 0] + c * xy[:, 1]
    # Image rows grow downwards: a counter-clockwise turn on screen is -y.
    return np.stack([center[0] - y, center[1] + x], axis=1)


def _circumradius(label: str, size: float, aspect: float) -> float:
    if label == "square":
        return size / np.sqrt(2)
    if label == "rectangle":
        return size / 2 * np.hypot(1, 1 / aspect)
    if label == "triangle":
        return size / np.sqrt(3)
    return size / 2


def draw_shape(
    label: str,
    shape: tuple[int, int],
    size: float,
    *,
    angle: float = 0.0,
    center: Sequence[float] | None = None,
    aspect: float = 2.0,
) -> np.ndarray:
    """Rasterise one clean shape into a boolean grid (pixel set if its centre is inside).

    Parameters
    ----------
    label : {"square", "circle", "triangle", "rectangle"}
        The shape.
    shape : tuple of 2 ints
        ``(rows, cols)`` of the grid.
    size, angle, aspect
        As in :func:`shape_polygon`.
    center : sequence of 2 floats, optional
        ``(row, col)`` of the centroid; default the middle of the grid.

    Returns
    -------
    grid : ndarray of bool, shape ``shape``

    Examples
    --------
    >>> draw_shape("square", (5, 5), 3.0).astype(int)
    array([[0, 0, 0, 0, 0],
           [0, 1, 1, 1, 0],
           [0, 1, 1, 1, 0],
           [0, 1, 1, 1, 0],
           [0, 0, 0, 0, 0]])
    """
    rows, cols = (check_positive_int(n, "shape") for n in shape)
    check_total(rows * cols, "the grid (shape)")
    if center is None:
        center = ((rows - 1) / 2, (cols - 1) / 2)
    grid = np.zeros((rows, cols), dtype=bool)
    if label == "circle":
        rr, cc = disk(tuple(center), size / 2 + 1e-9, shape=(rows, cols))
    else:
        v = shape_polygon(label, size, angle=angle, center=center, aspect=aspect)
        rr, cc = polygon(v[:, 0], v[:, 1], shape=(rows, cols))
    grid[rr, cc] = True
    return grid


def _random_shape(
    rng: np.random.RandomState,
    label: str,
    shape: tuple[int, int],
    radius_range: tuple[float, float],
) -> tuple[np.ndarray, dict]:
    """One clean object at a random position, rotation and size inside ``shape``."""
    aspect = float(rng.uniform(*_ASPECT_RANGE)) if label == "rectangle" else 1.0
    radius = float(rng.uniform(*radius_range))
    size = radius / _circumradius(label, 1.0, aspect)
    angle = float(rng.uniform(0, 2 * np.pi))
    margin = radius + 1.0
    center = (
        float(rng.uniform(margin, shape[0] - 1 - margin)),
        float(rng.uniform(margin, shape[1] - 1 - margin)),
    )
    grid = draw_shape(label, shape, size, angle=angle, center=center, aspect=aspect)
    info = {"label": label, "size": size, "angle": angle, "center": center, "aspect": aspect}
    return grid, info


def _stamp_damage(
    rng: np.random.RandomState, grid: np.ndarray, kind: str, info: dict
) -> dict | None:
    """Stamp one damage of ``kind`` on ``grid`` in place; ``None`` if it did not take."""
    shape = grid.shape
    if kind == "hole":
        r = float(rng.uniform(1.5, 3.5))
        depth = ndimage.distance_transform_edt(grid)
        rows, cols = np.nonzero(depth > r + 2.0)
        if rows.size == 0:
            return None
        i = rng.randint(rows.size)
        rr, cc = disk((rows[i], cols[i]), r, shape=shape)
        grid[rr, cc] = False
        return {
            "kind": "hole",
            "center": (int(rows[i]), int(cols[i])),
            "radius": r,
            "pixels": int(rr.size),
        }
    if kind == "bite":
        r = float(rng.uniform(2.5, 6.0))
        if info["label"] != "circle" and rng.uniform() < 0.3:
            v = shape_polygon(
                info["label"],
                info["size"],
                angle=info["angle"],
                center=info["center"],
                aspect=info["aspect"],
            )
            c = v[rng.randint(len(v))]
            kind_name = "broken_corner"
        else:
            edge = grid & ~ndimage.binary_erosion(grid)
            rows, cols = np.nonzero(edge)
            i = rng.randint(rows.size)
            c = (rows[i], cols[i])
            kind_name = "bite"
        rr, cc = disk(tuple(c), r, shape=shape)
        removed = int(grid[rr, cc].sum())
        grid[rr, cc] = False
        return {
            "kind": kind_name,
            "center": (float(c[0]), float(c[1])),
            "radius": r,
            "pixels": removed,
        }
    # burr: a thin strip sticking out of a boundary pixel, along the outward normal
    edge = grid & ~ndimage.binary_erosion(grid)
    rows, cols = np.nonzero(edge)
    i = rng.randint(rows.size)
    p = np.array([rows[i], cols[i]], dtype=float)
    normal = p - np.asarray(info["center"])
    normal /= max(np.hypot(*normal), 1e-9)
    length = float(rng.uniform(3.0, 6.0))
    width = float(rng.uniform(1.0, 2.0))
    side = np.array([-normal[1], normal[0]]) * width / 2
    a, b = p, p + normal * length
    quad = np.array([a - side, b - side, b + side, a + side])
    rr, cc = polygon(quad[:, 0], quad[:, 1], shape=shape)
    added = int((~grid[rr, cc]).sum())
    grid[rr, cc] = True
    return {"kind": "burr", "center": (float(b[0]), float(b[1])), "radius": length, "pixels": added}


def make_objects(
    n_objects: int,
    *,
    shape: tuple[int, int] = (64, 64),
    classes: Sequence[str] = THESIS_CLASSES,
    damaged_fraction: float = 0.5,
    damage_kinds: Sequence[str] = ("hole", "bite"),
    radius_range: tuple[float, float] = (10.0, 28.0),
    random_state: int | np.random.RandomState | None = None,
    seed: Any = UNSET,
) -> Bunch:
    """Random objects of the thesis classes, some damaged, each in its own grid.

    Parameters
    ----------
    n_objects : int
        Number of grids.
    shape : tuple of 2 ints, default=(64, 64)
        Size of each grid.
    classes : sequence of str, default=THESIS_CLASSES
        Classes drawn in turn (``i % len(classes)``), so the set is balanced.
    damaged_fraction : float, default=0.5
        Share of the objects that get one to two damages.
    damage_kinds : sequence of {"hole", "bite", "burr"}, default=("hole", "bite")
        Kinds to draw from.
    radius_range : tuple of 2 floats, default=(10, 28)
        Circumradius of the objects in pixels (sets their size).
    random_state : int, RandomState or None
        Seed for reproducible sets.
    seed : deprecated
        Old name of ``random_state``, removed in the next release.

    Returns
    -------
    data : Bunch
        ``grids`` (n_objects, rows, cols) bool; ``target`` class names;
        ``damaged`` bool; ``damages`` a list (one per object) of dicts with
        ``kind``, ``center`` (row, col), ``radius`` and ``pixels`` changed;
        ``params`` the drawing parameters (size, angle, center, aspect).

    Examples
    --------
    >>> d = make_objects(8, random_state=0)
    >>> d.grids.shape, d.target[:4].tolist()
    ((8, 64, 64), ['square', 'circle', 'triangle', 'rectangle'])
    >>> int(d.damaged.sum())
    4
    """
    n_objects = check_positive_int(n_objects, "n_objects", maximum=MAX_SAMPLES)
    rows, cols = (check_positive_int(n, "shape") for n in shape)
    check_total(n_objects * rows * cols, "the grids (n_objects x shape)")
    if not 0.0 <= damaged_fraction <= 1.0:
        raise InputError(f"damaged_fraction must be in [0, 1], got {damaged_fraction!r}")
    for kind in damage_kinds:
        if kind not in DAMAGE_KINDS:
            raise InputError(f"damage kinds must be among {list(DAMAGE_KINDS)}, got {kind!r}")
    rng = check_random_state(renamed("random_state", random_state, "seed", seed))
    n_damaged = round(n_objects * damaged_fraction)
    damaged = np.zeros(n_objects, dtype=bool)
    damaged[rng.permutation(n_objects)[:n_damaged]] = True
    grids = np.zeros((n_objects, *shape), dtype=bool)
    target, damages, params = [], [], []
    for i in range(n_objects):
        label = classes[i % len(classes)]
        grid, info = _random_shape(rng, label, shape, radius_range)
        done: list[dict] = []
        if damaged[i] and damage_kinds:
            for _ in range(1 + int(rng.uniform() < 0.3)):
                for _attempt in range(10):
                    trial = grid.copy()
                    d = _stamp_damage(
                        rng, trial, damage_kinds[rng.randint(len(damage_kinds))], info
                    )
                    # keep damage that changes at least 4 pixels and leaves one piece
                    if d and d["pixels"] >= 4 and ndimage.label(trial, np.ones((3, 3)))[1] == 1:
                        grid = trial
                        done.append(d)
                        break
            damaged[i] = bool(done)
        grids[i] = grid
        target.append(label)
        damages.append(done)
        params.append(info)
    return Bunch(
        grids=grids, target=np.array(target), damaged=damaged, damages=damages, params=params
    )


def make_belt(
    n_objects: int,
    width: int = 256,
    *,
    gap: tuple[int, int] = (2, 20),
    damaged_fraction: float = 0.3,
    damage_kinds: Sequence[str] = ("hole", "bite"),
    radius_range: tuple[float, float] = (6.0, 20.0),
    lanes: int = 1,
    random_state: int | np.random.RandomState | None = None,
    seed: Any = UNSET,
) -> Bunch:
    """A belt image with objects passing one after another (or side by side in lanes).

    Parameters
    ----------
    n_objects : int
        Number of objects on the belt.
    width : int, default=256
        Pixels per line.
    gap : tuple of 2 ints, default=(2, 20)
        Range of empty lines between consecutive objects in a lane.
    damaged_fraction, damage_kinds, radius_range
        As in :func:`make_objects`.
    lanes : int, default=1
        Objects travel in this many side-by-side lanes of ``width // lanes``
        pixels each, so several objects can be under the sensor at once.
    random_state : int, RandomState or None
        Seed for a reproducible belt.
    seed : deprecated
        Old name of ``random_state``, removed in the next release.

    Returns
    -------
    belt : Bunch
        ``image`` (n_lines, width) bool; ``target`` the class of each object;
        ``damaged`` bool per object; ``boxes`` (n_objects, 4) int
        ``(row0, col0, row1, col1)`` half-open boxes of the objects on the belt.

    Examples
    --------
    >>> b = make_belt(3, width=64, random_state=1)
    >>> b.image.shape[1], b.target.shape, b.boxes.shape
    (64, (3,), (3, 4))
    """
    n_objects = check_positive_int(n_objects, "n_objects", maximum=MAX_SAMPLES)
    width = check_positive_int(width, "width")
    lanes = check_positive_int(lanes, "lanes")
    lane_w = width // lanes
    if lane_w < 2 * radius_range[1] + 4:
        raise InputError(
            f"lanes of {lane_w} pixels are too narrow for objects of circumradius up to "
            f"{radius_range[1]}; use a wider belt, fewer lanes or a smaller radius_range"
        )
    rng = check_random_state(renamed("random_state", random_state, "seed", seed))
    side = int(np.ceil(2 * radius_range[1])) + 4
    objs = make_objects(
        n_objects,
        shape=(side, lane_w),
        damaged_fraction=damaged_fraction,
        damage_kinds=damage_kinds,
        radius_range=radius_range,
        random_state=rng,
    )
    order = rng.permutation(n_objects)
    objs.grids, objs.target = objs.grids[order], objs.target[order]
    objs.damaged = objs.damaged[order]
    lane_end = np.zeros(lanes, dtype=int)
    placed = []
    for g in objs.grids:
        rr = np.nonzero(g.any(axis=1))[0]
        crop = g[rr[0] : rr[-1] + 1]
        lane = int(np.argmin(lane_end))
        top = lane_end[lane] + int(rng.randint(gap[0], gap[1] + 1))
        placed.append((top, lane * lane_w, crop))
        lane_end[lane] = top + crop.shape[0]
    height = int(lane_end.max()) + int(gap[0]) + 1
    check_total(height * width, "the belt image (rows x width)")
    image = np.zeros((height, width), dtype=bool)
    box_rows = []
    for top, left, crop in placed:
        image[top : top + crop.shape[0], left : left + crop.shape[1]] |= crop
        cols = np.nonzero(crop.any(axis=0))[0]
        box_rows.append((top, left + cols[0], top + crop.shape[0], left + cols[-1] + 1))
    boxes = np.array(box_rows, dtype=int).reshape(-1, 4)
    return Bunch(image=image, target=objs.target, damaged=objs.damaged, boxes=boxes)
