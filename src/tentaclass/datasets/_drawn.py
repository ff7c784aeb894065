"""Hand-drawn-like strokes of outlines: what a person draws with a mouse, finger or pen."""

from __future__ import annotations

from typing import Any

import numpy as np
from sklearn.utils import Bunch

from .._deprecation import UNSET, renamed
from .._validation import MAX_SAMPLES, as_generator, check_positive_int, check_total
from ..errors import InputError
from ..geometry import resample_closed

__all__ = ["DRAWN_CLASSES", "drawn_shapes"]

#: Classes :func:`drawn_shapes` draws: the four thesis shapes and five more.
DRAWN_CLASSES = (
    "square",
    "circle",
    "triangle",
    "rectangle",
    "star",
    "ellipse",
    "L-shape",
    "arrow",
    "heart",
)


def _ring(n: int) -> np.ndarray:
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    return np.stack([np.cos(t), np.sin(t)], axis=1)


def _template(cls: str, rng: np.random.Generator) -> np.ndarray:
    """A counter-clockwise outline of the class, about unit size, with random proportions."""
    if cls == "square":
        return np.array([(0, 0), (1, 0), (1, 1), (0, 1)], float)
    if cls == "rectangle":
        a = rng.uniform(1.7, 2.6)
        return np.array([(0, 0), (a, 0), (a, 1), (0, 1)], float)
    if cls == "circle":
        return _ring(128)
    if cls == "ellipse":
        return _ring(128) * [rng.uniform(1.7, 2.5), 1.0]
    if cls == "triangle":
        # roughly equilateral: each corner moved by up to 10 % of the side
        base = _ring(3)
        return base + rng.uniform(-0.1, 0.1, (3, 2)) * np.sqrt(3)
    if cls == "star":
        inner = rng.uniform(0.38, 0.5)
        t = np.pi / 2 + np.arange(10) * np.pi / 5
        r = np.where(np.arange(10) % 2 == 0, 1.0, inner)
        return np.stack([r * np.cos(t), r * np.sin(t)], axis=1)
    if cls == "L-shape":
        w, h = rng.uniform(0.9, 1.2), rng.uniform(1.3, 1.7)
        tx, ty = rng.uniform(0.35, 0.5), rng.uniform(0.35, 0.5)
        return np.array([(0, 0), (w, 0), (w, ty), (tx, ty), (tx, h), (0, h)], float)
    if cls == "arrow":
        length = rng.uniform(1.6, 2.2)
        shaft, head_w, head_l = (
            rng.uniform(0.22, 0.32),
            rng.uniform(0.8, 1.0),
            rng.uniform(0.5, 0.7),
        )
        s, hw, x0 = shaft / 2, head_w / 2, length - head_l
        return np.array(
            [(0, -s), (x0, -s), (x0, -hw), (length, 0), (x0, hw), (x0, s), (0, s)], float
        )
    if cls == "heart":
        t = np.linspace(0, 2 * np.pi, 160, endpoint=False)
        x = 16 * np.sin(t) ** 3
        y = 13 * np.cos(t) - 5 * np.cos(2 * t) - 2 * np.cos(3 * t) - np.cos(4 * t)
        return np.stack([x, y], axis=1)[::-1] / 16.0
    raise InputError(f"unknown class {cls!r}; choose from {', '.join(DRAWN_CLASSES)}")


def _smooth_noise(n: int, scale: float, rng: np.random.Generator, n_waves: int) -> np.ndarray:
    """Slow random wobble: a few random sinusoids along the stroke, shape (n, 2)."""
    s = np.linspace(0, 1, n)[:, None]
    out = np.zeros((n, 2))
    for k in range(1, n_waves + 1):
        amp = rng.normal(0, scale / k, (1, 2))
        out += amp * np.sin(2 * np.pi * k * s + rng.uniform(0, 2 * np.pi, (1, 2)))
    return out


def _draw_one(cls: str, rng: np.random.Generator) -> np.ndarray:
    outline = _template(cls, rng)
    outline = outline - outline.mean(axis=0)
    outline /= np.ptp(outline, axis=0).max()
    dense = resample_closed(outline, 400)
    if rng.random() < 0.5:  # drawn clockwise
        dense = dense[::-1]
    dense = np.roll(dense, rng.integers(len(dense)), axis=0)
    # arc-length position of each sample: uneven speed (slower at corners, where the
    # turn is sharp, plus random slow and fast stretches), from start to past the end
    edges = np.roll(dense, -1, axis=0) - dense
    heading = np.arctan2(edges[:, 1], edges[:, 0])
    turn = np.abs(np.angle(np.exp(1j * (np.roll(heading, -1) - heading))))
    slowness = 1.0 + 40.0 * np.convolve(turn, np.ones(9) / 9, mode="same")
    slowness *= np.exp(_smooth_noise(len(dense), 0.6, rng, 3)[:, 0])
    end = 1.0 + (rng.uniform(0.02, 0.15) if rng.random() < 0.5 else -rng.uniform(0.0, 0.1))
    n_samples = int(rng.integers(40, 200))
    # the pen's time at each step of arc length; points come at equal time steps
    clock = np.concatenate([[0.0], np.cumsum(np.tile(slowness, 2))])
    steps = np.arange(len(clock), dtype=float)
    t = np.linspace(0.0, np.interp(end * len(dense), steps, clock), n_samples)
    idx = np.interp(t, clock, steps)
    k = np.floor(idx).astype(int)
    w = (idx - k)[:, None]
    pts = dense[k % len(dense)] * (1 - w) + dense[(k + 1) % len(dense)] * w
    # wobble along the stroke, then jitter of each point
    pts = pts + _smooth_noise(n_samples, 0.015, rng, 4) + rng.normal(0, 0.008, pts.shape)
    # random size (50-400 px), rotation, position; screen coordinates (y down)
    ang = rng.uniform(0, 2 * np.pi)
    rot = np.array([[np.cos(ang), -np.sin(ang)], [np.sin(ang), np.cos(ang)]])
    size = rng.uniform(80, 400)
    pts = pts @ rot.T * size + rng.uniform(250, 350, 2)
    return np.round(pts * [1, -1] + [0, 600], 1)


def drawn_shapes(
    n_per_class: int = 20,
    *,
    classes: tuple[str, ...] | None = None,
    random_state: int = 0,
    seed: Any = UNSET,
) -> Bunch:
    """Strokes as a person draws outlines with a mouse, finger or pen.

    Each stroke is one pointer trace around an outline of its class, as a
    canvas records it: points sampled at a steady rate while the pen moves at
    an uneven speed, so their spacing varies.

    Parameters
    ----------
    n_per_class : int, default=20
        Strokes of each class.
    classes : tuple of str, optional
        Classes to draw, from :data:`DRAWN_CLASSES` (the default: all of them).
    random_state : int, default=0
    seed : int, optional
        Deprecated alias of ``random_state``.

    Returns
    -------
    data : Bunch
        ``strokes``, a list of ``(n_points, 2)`` float arrays in screen pixels
        (``y`` grows downwards), and ``target`` (n_strokes,) the class names.

    Notes
    -----
    What varies from stroke to stroke:

    - proportions: rectangles 1.7-2.6 times as long as high, ellipses 1.7-2.5,
      triangles' corners moved by up to 10 % of the side, star inner radius
      0.38-0.5 of the outer, L-shape and arrow arm and head sizes;
    - size (50-400 px across), rotation (any angle), position, start point
      and direction (clockwise or counter-clockwise, equally often);
    - speed: slower at corners and in random stretches; 40-200 points per
      stroke, so the spacing between points is uneven;
    - the end: half of the strokes overshoot the start by 2-12 % of the
      perimeter, the others stop short of it, leaving a gap of up to 6 %;
    - wobble (a few slow random waves, about 2 % of the size) and jitter
      (0.6 % of the size per point).

    Examples
    --------
    >>> d = drawn_shapes(2, random_state=1)
    >>> len(d.strokes), d.target[:3].tolist()
    (18, ['square', 'square', 'circle'])
    >>> d.strokes[0].ndim, d.strokes[0].shape[1]
    (2, 2)
    """
    n_per_class = check_positive_int(n_per_class, "n_per_class", maximum=MAX_SAMPLES)
    if classes is None:
        classes = DRAWN_CLASSES
    classes = tuple(classes)
    unknown = [c for c in classes if c not in DRAWN_CLASSES]
    if unknown or not classes:
        raise InputError(
            f"classes must be names from {', '.join(DRAWN_CLASSES)}, got {list(classes)!r}"
        )
    random_state = renamed("random_state", random_state, "seed", seed, default=0)
    rng = as_generator(random_state, allow_none=False)
    check_total(
        n_per_class * len(classes),
        "the strokes (n_per_class x classes)",
        maximum=MAX_SAMPLES,
        unit="samples",
    )
    target = np.repeat(np.array(classes), n_per_class)
    strokes = [_draw_one(str(c), rng) for c in target]
    return Bunch(
        strokes=strokes,
        target=target,
        DESCR="Hand-drawn-like strokes of outlines (screen pixels, y down).",
    )
