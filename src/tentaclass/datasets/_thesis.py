"""The thesis's hand-typed data, with its typing errors corrected.

Tentacle case: closed single wraps of 16 or 64 unit links (thesis section 3.4
and ``CLASSIFY.m``). Scanner case: 5 x 5 binary grids (thesis
``twodimensional.m``). The corrections: the triangle turns by ``2*pi/3`` and
has as many entries as the other shapes; every class has its own examples and
exactly one label each.
"""

from __future__ import annotations

import numpy as np
from sklearn.utils import Bunch

from .._thesis_data import (
    SCANNER_TEST,
    THESIS_CLASSES,
    grid_from_text,
    scanner_training_grids,
)
from .._validation import MAX_POINTS, MAX_SAMPLES, check_positive_int, check_total
from ..errors import InputError

__all__ = ["THESIS_CLASSES", "reference_tentacle", "thesis_scanner", "thesis_tentacle"]


def _runs(zeros: list[int], turn: float) -> list[float]:
    """Runs of straight links, each closed by one turn."""
    out: list[float] = []
    for z in zeros:
        out += [0.0] * z + [turn]
    return out


def _tentacle_arrays(n_links: int) -> dict[str, list[float]]:
    quarter, third = np.pi / 2, 2 * np.pi / 3
    if n_links == 16:
        return {
            "square": _runs([3, 3, 3, 3], quarter),
            "circle": [np.pi / 8] * 16,
            "triangle": _runs([4, 4, 5], third),
            "rectangle": _runs([5, 1, 5, 1], quarter),
        }
    return {
        "square": _runs([15, 15, 15, 15], quarter),
        "circle": [np.pi / 32] * 64,
        "triangle": _runs([20, 21, 20], third),
        "rectangle": _runs([23, 7, 23, 7], quarter),
    }


def thesis_tentacle(n_links: int = 16, *, return_X_y: bool = False) -> Bunch | tuple:
    """The thesis's four joint-angle arrays: square, circle, triangle, rectangle.

    Parameters
    ----------
    n_links : {16, 64}, default=16
        Chain length: the 16-link arrays of thesis section 3.4 or the 64-link
        arrays of its CLASSIFY.m.
    return_X_y : bool, default=False
        Return ``(data, target)`` instead of a Bunch.

    Returns
    -------
    data : Bunch
        ``data`` (4, n_links) joint angles in radians, each a closed single
        counter-clockwise wrap (sum ``2*pi``) of unit links; ``target`` (4,)
        class names; ``target_names`` the classes in the thesis's order.

    Examples
    --------
    >>> import numpy as np
    >>> d = thesis_tentacle(16)
    >>> d.data.shape, d.target.tolist()
    ((4, 16), ['square', 'circle', 'triangle', 'rectangle'])
    >>> np.allclose(d.data.sum(axis=1), 2 * np.pi)
    True
    """
    n_links = check_positive_int(n_links, "n_links")
    if n_links not in (16, 64):
        raise InputError(f"n_links must be 16 or 64 (the thesis's arrays), got {n_links}")
    arrays = _tentacle_arrays(n_links)
    data = np.array([arrays[c] for c in THESIS_CLASSES], dtype=np.float64)
    target = np.array(THESIS_CLASSES)
    if return_X_y:
        return data, target
    return Bunch(
        data=data,
        target=target,
        target_names=np.array(THESIS_CLASSES),
        DESCR=f"Thesis tentacle arrays, {n_links} unit links, closed single wraps.",
    )


def thesis_scanner() -> Bunch:
    """The thesis's 5 x 5 scanner grids: 16 training examples and the test grids.

    Returns
    -------
    data : Bunch
        ``grids`` (16, 5, 5) bool training grids (rows top to bottom, four per
        class); ``target`` (16,) class names; ``target_names`` the classes;
        ``test_grids`` (5, 5, 5) bool; ``test_names`` a description of each;
        ``test_target`` the class a person would give (``""`` if none fits);
        ``thesis_answer`` what the thesis's network answered (``""`` if not
        reported).

    Examples
    --------
    >>> d = thesis_scanner()
    >>> d.grids.shape, d.test_grids.shape
    ((16, 5, 5), (5, 5, 5))
    >>> d.test_names[0], str(d.test_target[0]), str(d.thesis_answer[0])
    ('square with a hole', 'square', 'triangle')
    >>> int(d.test_grids[0].sum())
    23
    """
    grids, target = scanner_training_grids()
    return Bunch(
        grids=grids,
        target=target,
        target_names=np.array(THESIS_CLASSES),
        test_grids=np.stack([grid_from_text(t[1]) for t in SCANNER_TEST]),
        test_names=[t[0] for t in SCANNER_TEST],
        test_target=np.array([t[2] or "" for t in SCANNER_TEST]),
        thesis_answer=np.array([t[3] or "" for t in SCANNER_TEST]),
        DESCR="Thesis scanner grids (twodimensional.m), 5 x 5, rows top to bottom.",
    )


def _reference_outlines() -> dict[str, np.ndarray]:
    """Counter-clockwise outlines of the thesis's four classes, perimeter 1."""
    from ..shapes import circle, rectangle, square, triangle

    polys = {
        "square": square(1.0),
        "circle": circle(1.0, 256),
        "triangle": triangle(side=1.0),
        "rectangle": rectangle(3.0, 1.0),
    }
    out = {}
    for name, p in polys.items():
        perimeter = np.linalg.norm(np.roll(p, -1, axis=0) - p, axis=1).sum()
        out[name] = p / perimeter
    return out


def reference_tentacle(
    n_links: int, n_starts: int = 8, *, return_X_y: bool = False
) -> Bunch | tuple:
    """Joint angles of the four thesis classes for a chain of any length.

    Each outline (unit square, circle, equilateral triangle, 3:1 rectangle) is
    sampled at ``n_links`` points equally spaced by arc length, from
    ``n_starts`` start points spread over one link, and turned into the joint
    angles of the closed chain through those points. At 16 and 64 links the
    first start point reproduces the square, circle and rectangle of
    :func:`thesis_tentacle` up to a cyclic shift; the triangle's corners fall
    between joints, as they do on a real chain, so its turns are split.

    Parameters
    ----------
    n_links : int
        Number of links, at least 3.
    n_starts : int, default=8
        Start points per class, at fractions ``0, 1/n_starts, ...`` of one link.
    return_X_y : bool, default=False
        Return ``(data, target)`` instead of a Bunch.

    Returns
    -------
    data : Bunch
        ``data`` (4 * n_starts, n_links) and ``target`` (4 * n_starts,).

    Examples
    --------
    >>> X, y = reference_tentacle(16, n_starts=2, return_X_y=True)
    >>> X.shape, y[:3].tolist()
    ((8, 16), ['square', 'square', 'circle'])
    """
    from ..geometry import points_to_angles, resample_closed

    n_links = check_positive_int(n_links, "n_links", minimum=3, maximum=MAX_POINTS)
    n_starts = check_positive_int(n_starts, "n_starts", maximum=MAX_SAMPLES)
    check_total(4 * n_starts * n_links, "the angles (4 n_starts x n_links)")
    data, target = [], []
    for name, outline in _reference_outlines().items():
        closed = np.vstack([outline, outline[:1]])
        seg = np.linalg.norm(np.diff(closed, axis=0), axis=1)
        s = np.concatenate([[0], np.cumsum(seg)])
        for i in range(n_starts):
            shift = i / (n_starts * n_links)
            # start the outline at arc length `shift` by inserting that point first
            x = np.interp(shift, s, closed[:, 0])
            y = np.interp(shift, s, closed[:, 1])
            after = outline[s[:-1] > shift]
            before = outline[s[:-1] <= shift]
            rotated = np.vstack([[(x, y)], after, before])
            if np.allclose(rotated[0], rotated[-1]):
                rotated = rotated[:-1]
            pts = resample_closed(rotated, n_links)
            data.append(points_to_angles(pts))
            target.append(name)
    X, y = np.array(data), np.array(target)
    if return_X_y:
        return X, y
    return Bunch(data=X, target=y, target_names=np.array(THESIS_CLASSES))
