"""Generated tentacle data: the thesis's classes and MPEG-7 silhouettes, wrapped.

Everything is deterministic given ``seed``. The wraps come from
:func:`tentaclass.wrapping.wrap_many`; this module only draws the objects and
the wrap parameters, and for MPEG-7 finds the link length that closes one lap.
"""

from __future__ import annotations

import hashlib
import inspect
import json
import numbers
import os
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np
from shapely.geometry import Polygon
from sklearn.utils import Bunch

from .._typing import ArrayLike
from .._validation import check_positive_float, check_positive_int
from ..errors import InputError
from ..geometry import angles_to_points
from ..shapes import circle, load_mpeg7, rectangle, square, triangle
from ..wrapping import wrap_many
from ._thesis import THESIS_CLASSES


def _noise_range(noise: float | tuple[float, float]) -> tuple[float, float]:
    lo, hi = (noise, noise) if np.isscalar(noise) else tuple(noise)  # type: ignore[arg-type]
    lo = check_positive_float(lo, "noise", allow_zero=True)
    hi = check_positive_float(hi, "noise", allow_zero=True)
    if hi < lo:
        raise InputError(f"noise range must be (low, high) with low <= high, got {noise!r}")
    return lo, hi


def _range(value: tuple[float, float], name: str, *, allow_zero: bool) -> tuple[float, float]:
    try:
        lo, hi = value  # type: ignore[misc]
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a pair (low, high), got {value!r}") from None
    lo = check_positive_float(lo, name, allow_zero=allow_zero)
    hi = check_positive_float(hi, name, allow_zero=allow_zero)
    if hi < lo:
        raise InputError(f"{name} range must be (low, high) with low <= high, got {value!r}")
    return lo, hi


def _random_outline(cls: str, perimeter: float, rng: np.random.Generator) -> np.ndarray:
    """One object of a thesis class with the given perimeter, randomly rotated."""
    if cls == "square":
        p = square(1.0)
    elif cls == "circle":
        p = circle(1.0, n_points=256)
    elif cls == "rectangle":
        p = rectangle(float(rng.uniform(1.2, 4.0)), 1.0)
    else:  # a triangle of random angles, none below 25 degrees
        while True:
            a, b = np.deg2rad(rng.uniform(25, 130, 2))
            if np.pi - a - b > np.deg2rad(25):
                break
        c = np.array([np.cos(a), np.sin(a)]) * np.sin(b) / np.sin(a + b)
        p = triangle([(0.0, 0.0), (1.0, 0.0), tuple(c)])
    p = p - p.mean(axis=0)
    p *= perimeter / Polygon(p).length
    theta = rng.uniform(0, 2 * np.pi)
    rot = np.array([[np.cos(theta), np.sin(theta)], [-np.sin(theta), np.cos(theta)]])
    return p @ rot


def _winding(joints: np.ndarray, centre: np.ndarray) -> np.ndarray:
    """Turns the joints make around an interior point: continuous in the link length."""
    d = joints - centre[:, None, :]
    ang = np.unwrap(np.arctan2(d[..., 1], d[..., 0]), axis=1)
    return np.abs(ang[:, -1] - ang[:, 0]) / (2 * np.pi)


def _wrap_both_ways(outlines, n_links, lengths, starts, offsets, cw, mode="taut", centres=None):
    """wrap_many over rows with per-row direction.

    Returns angles (b, n), laps (b,), winding (b,) around ``centres`` (NaN if
    not given) and complete (b,).
    """
    angles = np.empty((len(outlines), n_links))
    laps = np.empty(len(outlines))
    winding = np.full(len(outlines), np.nan)
    complete = np.empty(len(outlines), bool)
    for flag, direction in ((False, "ccw"), (True, "cw")):
        rows = np.flatnonzero(cw == flag)
        if rows.size == 0:
            continue
        b = wrap_many([outlines[i] for i in rows], n_links, lengths[rows], starts[rows],
                      direction=direction, offset=offsets[rows], mode=mode)  # fmt: skip
        angles[rows] = b.angles
        laps[rows] = b.laps
        complete[rows] = b.complete
        if centres is not None:
            winding[rows] = _winding(np.nan_to_num(b.joints), centres[rows])
    return angles, laps, winding, complete


def synthetic_tentacle(
    n_samples: int,
    n_links: int = 16,
    *,
    laps: tuple[float, float] = (1.0, 2.0),
    offset_links: tuple[float, float] = (0.0, 3.0),
    noise: float | tuple[float, float] = (0.0, 0.05),
    seed: int = 0,
) -> Bunch:
    """Wraps of random squares, circles, triangles and rectangles.

    Each sample draws a class, a size such that the chain covers ``laps`` laps
    after its approach, a rectangle aspect ratio in [1.2, 4] or triangle
    angles (all >= 25 degrees), a rotation, a start point, a direction, an
    offset of ``offset_links`` links and a joint-noise sigma from ``noise``.
    Links have length 1.

    Parameters
    ----------
    n_samples : int
    n_links : int, default=16
    laps : (float, float), default=(1, 2)
        Range of laps wrapped; use ``(0.5, 1.0)`` for partial wraps.
    offset_links : (float, float), default=(0, 3)
        Range of the base's stand-off, in link lengths.
    noise : float or (float, float), default=(0, 0.05)
        Joint-noise sigma in radians, or the range it is drawn from.
    seed : int, default=0

    Returns
    -------
    data : Bunch
        ``data`` (n_samples, n_links) angles, ``target`` (n_samples,) class,
        ``laps`` (n_samples,) laps actually wrapped, ``offset`` (n_samples,)
        stand-off in links, ``noise`` (n_samples,) sigma used.

    Examples
    --------
    >>> d = synthetic_tentacle(8, 16, seed=1)
    >>> d.data.shape, set(d.target.tolist()) <= {'circle', 'rectangle', 'square', 'triangle'}
    ((8, 16), True)
    """
    n_samples = check_positive_int(n_samples, "n_samples")
    n_links = check_positive_int(n_links, "n_links", minimum=3)
    nlo, nhi = _noise_range(noise)
    laps = _range(laps, "laps", allow_zero=False)
    offset_links = _range(offset_links, "offset_links", allow_zero=True)
    if isinstance(seed, bool) or not isinstance(seed, numbers.Integral) or seed < 0:
        raise InputError(f"seed must be an integer >= 0, got {seed!r}")
    rng = np.random.default_rng(seed)
    cls = rng.choice(THESIS_CLASSES, n_samples)
    lap_target = rng.uniform(*laps, n_samples)
    off = rng.uniform(*offset_links, n_samples)
    perimeter = np.maximum(n_links - off, 3.0) / lap_target
    outlines = [_random_outline(c, p, rng) for c, p in zip(cls, perimeter, strict=True)]
    starts = rng.uniform(0, 1, n_samples)
    cw = rng.random(n_samples) < 0.5
    sigma = rng.uniform(nlo, nhi, n_samples)
    ones = np.ones(n_samples)
    # Chords are shorter than the arcs they span: rescale once so that the chain
    # covers the drawn number of laps.
    _, got_laps, _, done = _wrap_both_ways(outlines, n_links, ones, starts, off, cw)
    scale = np.where(done & (got_laps > 0), got_laps / lap_target, 1.0)
    outlines = [o * f for o, f in zip(outlines, scale, strict=True)]
    angles, got_laps, _, _ = _wrap_both_ways(outlines, n_links, ones, starts, off, cw)
    angles = angles + rng.normal(0.0, 1.0, angles.shape) * sigma[:, None]
    return Bunch(data=angles, target=cls, laps=got_laps, offset=off, noise=sigma,
                 DESCR="Synthetic wraps of the four thesis classes (unit links).")  # fmt: skip


def _generator_digest() -> str:
    """Hash of the wrap generator's source: a changed generator never reads old wraps.

    Covers the wrapping package and the functions here that make the wraps, not
    this module's docstrings or its other datasets.
    """
    from .. import wrapping

    h = hashlib.sha256()
    for f in sorted(Path(wrapping.__file__).parent.glob("*.py")):
        h.update(f.read_bytes())
    for func in (_winding, _wrap_both_ways, _bisect_lengths, _closure_gaps, _one_lap_wraps):
        h.update(inspect.getsource(func).encode())
    return h.hexdigest()[:16]


def _cache_path(key: dict) -> Path:
    base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "tentaclass"
    digest = hashlib.sha256(json.dumps(key, sort_keys=True).encode()).hexdigest()[:16]
    return base / f"mpeg7-wraps-{digest}.npz"


def _one_lap_lengths(outlines, n_links, starts, cw, mode, n_jobs=None, chunk=32):
    """Per wrap, the link length whose last joint lands on the start point.

    Runs :func:`_bisect_lengths` on chunks of wraps (few enough that their hug
    surfaces stay cached from one bisection step to the next), in ``n_jobs``
    processes. The chunks are independent, so the result does not depend on
    ``n_jobs``.
    """
    from joblib import Parallel, delayed

    parts = [slice(i, i + chunk) for i in range(0, len(outlines), chunk)]
    done = Parallel(n_jobs=n_jobs)(
        delayed(_bisect_lengths)(outlines[p], n_links, starts[p], cw[p], mode) for p in parts
    )
    return np.concatenate(done) if done else np.zeros(0)


def _bisect_lengths(outlines, n_links, starts, cw, mode, iterations=22):
    """Bisection on the link length until the last joint lands on the start point.

    The bisection watches how far the joints have wound around a point inside
    the object, which grows steadily with the link length; the heading-based
    ``laps`` of a wrap stands still along straight edges and jumps at corners.
    """
    polys = [Polygon(o) for o in outlines]
    centres = np.array([
        (p.convex_hull.centroid if mode == "taut" else p.representative_point()).coords[0]
        for p in polys
    ])  # fmt: skip
    support = np.array([p.convex_hull.length if mode == "taut" else p.length for p in polys])
    diameter = np.array([np.ptp(o, axis=0).max() for o in outlines]) * 0.999
    lo = 0.5 * support / n_links  # chain of half the support: short of one lap
    hi = np.minimum(1.5 * support / n_links, diameter)
    zero = np.zeros(len(outlines))
    for _ in range(iterations):
        mid = 0.5 * (lo + hi)
        _, _, wind, complete = _wrap_both_ways(
            outlines, n_links, mid, starts, zero, cw, mode, centres
        )
        over = (wind >= 1) | ~complete
        hi = np.where(over, mid, hi)
        lo = np.where(over, lo, mid)
    return lo


def _closure_gaps(angles):
    """Distance from the last joint to the first, in links (NaN rows -> inf)."""
    joints = angles_to_points(np.nan_to_num(angles))
    gap = np.hypot(*(joints[:, -1] - joints[:, 0]).T)
    return np.where(np.all(np.isfinite(angles), axis=1), gap, np.inf)


def _one_lap_wraps(outlines, n_links, mode, copies, seed, retries=8, max_gap=0.5, n_jobs=None):
    """Noise-free one-lap wraps, copy after copy; NaN rows where a chain jammed.

    From some start points no link length closes the lap: the last joint jumps
    past the start as the link length crosses the width of a concavity the
    chain can enter (hug mode), or a link tip overhangs a corner there. Such
    wraps (gap above ``max_gap`` links) are tried again from up to ``retries``
    other random start points, keeping the best.
    """
    rng = np.random.default_rng(seed)
    m = len(outlines) * copies
    rows = [outlines[i] for _ in range(copies) for i in range(len(outlines))]
    starts = rng.uniform(0, 1, m)
    cw = rng.random(m) < 0.5
    angles = np.full((m, n_links), np.nan)
    gap = np.full(m, np.inf)
    todo = np.arange(m)
    for attempt in range(retries + 1):
        sub = [rows[i] for i in todo]
        st = starts[todo] if attempt == 0 else rng.uniform(0, 1, todo.size)
        lengths = _one_lap_lengths(sub, n_links, st, cw[todo], mode, n_jobs)
        a, _, _, done = _wrap_both_ways(sub, n_links, lengths, st, np.zeros(todo.size), cw[todo],
                                        mode)  # fmt: skip
        a[~done] = np.nan  # the chain jammed (hug mode): no full array
        g = _closure_gaps(a)
        better = g < gap[todo]
        angles[todo[better]], gap[todo[better]] = a[better], g[better]
        todo = np.flatnonzero(gap > max_gap)
        if todo.size == 0:
            break
    return angles


def mpeg7_tentacle(
    folder: str | Path,
    n_links: int = 64,
    mode: str = "taut",
    *,
    noise: float = 0.0,
    copies: int = 1,
    seed: int = 0,
    max_vertices: int = 1000,
    cache: bool = True,
    n_jobs: int | None = None,
) -> Bunch:
    """One-lap tentacle wraps of every MPEG-7 Part B silhouette.

    Each silhouette is wrapped from a random start point in a random direction
    by ``n_links`` equal links whose length closes exactly one lap (found by
    bisection), in the given mode, and joint noise is added.

    Parameters
    ----------
    folder : path
        The MPEG-7 CE-Shape-1 Part B folder (see :func:`tentaclass.shapes.load_mpeg7`).
    n_links : int, default=64
    mode : {"taut", "hug"}, default="taut"
    noise : float, default=0.0
        Joint-noise sigma in radians.
    copies : int, default=1
        Wraps per silhouette, each from its own start point and direction. Copy
        0 is the one to score; the others can serve as extra training data.
    seed : int, default=0
    max_vertices : int, default=1000
        Outlines are resampled to at most this many vertices first.
    cache : bool, default=True
        Keep the outlines and the noise-free wraps on disk
        (``$XDG_CACHE_HOME/tentaclass`` or ``~/.cache/tentaclass``): the
        bisection takes a while for 1400 shapes. ``False`` writes nothing.
    n_jobs : int, optional
        Processes for the bisection, as in joblib: -1 all cores, None one
        (unless a ``joblib.parallel_config`` block says otherwise). The wraps
        do not depend on it.

    Returns
    -------
    data : Bunch
        ``data`` (1400 * copies, n_links), ``target`` class names, ``groups``
        the silhouette's index, ``wrap_index`` the copy number, ``names`` file names,
        ``complete`` False where the chain jammed before placing every link
        (possible in ``"hug"`` mode; those rows are NaN - drop them, or drop
        their silhouettes with ``groups``), ``closure_gap`` how far (in links)
        the noise-free chain's last joint ends from its first. From some start
        points no link length closes the lap (in ``"hug"`` mode the last joint
        jumps as the link length crosses the width of a concavity the chain can
        enter); such wraps are retried from up to eight other random start
        points and the best kept, so a few silhouettes keep a gap of a link or
        more.
    """
    n_links = check_positive_int(n_links, "n_links", minimum=3)
    copies = check_positive_int(copies, "copies")
    noise = check_positive_float(noise, "noise", allow_zero=True)
    if mode not in ("taut", "hug"):
        raise InputError(f"mode must be 'taut' or 'hug', got {mode!r}")
    outlines, labels, names = load_mpeg7(folder, max_vertices=max_vertices, cache=cache)
    key = {"n": n_links, "mode": mode, "copies": copies, "seed": seed, "mv": max_vertices,
           "files": len(names), "code": _generator_digest()}  # fmt: skip
    path = _cache_path(key)
    if cache and path.exists():
        with np.load(path, allow_pickle=False) as f:
            angles = f["angles"]
    else:
        angles = _one_lap_wraps(outlines, n_links, mode, copies, seed, n_jobs=n_jobs)
        if cache:
            path.parent.mkdir(parents=True, exist_ok=True)
            np.savez(path, angles=angles)
    gap = _closure_gaps(angles)
    rng = np.random.default_rng([seed, 1])
    if noise > 0:
        angles = angles + rng.normal(0.0, noise, angles.shape)
    n_shapes = len(outlines)
    complete = np.all(np.isfinite(angles), axis=1)
    gap[~complete] = np.nan
    return Bunch(
        complete=complete,
        closure_gap=gap,
        data=angles,
        target=np.tile(labels, copies),
        groups=np.tile(np.arange(n_shapes), copies),
        wrap_index=np.repeat(np.arange(copies), n_shapes),
        names=np.tile(np.array(names), copies),
        DESCR=f"MPEG-7 Part B, one-lap {mode} wraps of {n_links} links.",
    )


def _diameter(outline: np.ndarray) -> float:
    from scipy.spatial import ConvexHull, QhullError

    try:
        hull = outline[ConvexHull(outline).vertices]
    except QhullError:
        hull = outline
    d = hull[:, None, :] - hull[None, :, :]
    return float(np.sqrt((d**2).sum(-1)).max())


def chain_wraps(
    outlines: Sequence[ArrayLike],
    n_links: int,
    link_length: float = 1.0,
    *,
    n_wraps: int = 50,
    laps: tuple[float, float] | None = (1.0, 2.0),
    diameters: tuple[float, float] | None = None,
    offset_links: tuple[float, float] = (0.0, 2.0),
    noise: float | tuple[float, float] = 0.0,
    mode: str = "taut",
    random_state: int = 0,
    progress: Callable[[int, int], None] | None = None,
) -> Bunch:
    """Wraps of given outlines by one fixed chain, as a robot would measure them.

    Each outline is wrapped ``n_wraps`` times by the same chain of ``n_links``
    links of ``link_length``: every wrap draws a size (so that the chain
    covers ``laps`` laps after its approach, or so that the object's diameter
    is in ``diameters``), a rotation, a start point, a direction, a stand-off
    of ``offset_links`` links and a joint-noise sigma from ``noise``. Wraps
    that stop early are left out (``outline`` tells which remain).

    Parameters
    ----------
    outlines : sequence of array_like of shape (n_points, 2)
        Simple polygons; only their shape matters (they are rescaled).
    n_links : int
        Links of the chain (at least 3).
    link_length : float, default=1.0
    n_wraps : int, default=50
        Wraps per outline.
    laps : (float, float), optional
        Range of laps the chain covers after its approach; default (1, 2).
        Give ``None`` with ``diameters`` to draw sizes instead.
    diameters : (float, float), optional
        Range of object diameters (largest distance between two outline
        points), in the units of ``link_length``; the number of laps then
        follows from the size.
    offset_links : (float, float), default=(0, 2)
        Range of the base's stand-off from the object, in link lengths.
    noise : float or (float, float), default=0
        Joint-noise sigma in radians, or the range it is drawn from.
    mode : {"taut", "hug", "both"}, default="taut"
        How the chain lies on concave outlines; ``"both"`` draws one per wrap.
    random_state : int, default=0
    progress : callable, optional
        Called as ``progress(done, total)`` while the wraps are generated.

    Returns
    -------
    data : Bunch
        ``data`` (n, n_links) joint angles; ``outline`` (n,) index of the
        outline wrapped; ``laps``, ``offset`` (in links), ``noise``, ``mode``
        (n,) per wrap; ``n_failed``, the number of wraps left out.

    Examples
    --------
    >>> from tentaclass.shapes import square, triangle
    >>> d = chain_wraps([square(1.0), triangle(side=1.0)], 16, n_wraps=5, laps=(1.0, 1.5))
    >>> d.data.shape, d.outline.tolist(), d.n_failed
    ((10, 16), [0, 0, 0, 0, 0, 1, 1, 1, 1, 1], 0)
    >>> bool(((d.laps > 0.9) & (d.laps < 1.6)).all())
    True
    """
    from ..shapes import as_outline

    shapes = [as_outline(o, f"outlines[{i}]") for i, o in enumerate(outlines)]
    if not shapes:
        raise InputError("outlines is empty: give at least one outline")
    n_links = check_positive_int(n_links, "n_links", minimum=3)
    ell = check_positive_float(link_length, "link_length")
    n_wraps = check_positive_int(n_wraps, "n_wraps")
    if (laps is None) == (diameters is None):
        raise InputError("give either laps or diameters (the other None)")
    if laps is not None:
        laps = _range(laps, "laps", allow_zero=False)
    if diameters is not None:
        diameters = _range(diameters, "diameters", allow_zero=False)
        if diameters[0] < 1.0:
            raise InputError(
                f"diameters must be at least 1 link length (a link must fit across the "
                f"object), got {diameters!r}"
            )
    offset_links = _range(offset_links, "offset_links", allow_zero=True)
    if offset_links[1] >= n_links - 2:
        raise InputError(
            f"offset_links must stay below n_links - 2 = {n_links - 2} so that links reach "
            f"the object, got {offset_links!r}"
        )
    nlo, nhi = _noise_range(noise)
    if mode not in ("taut", "hug", "both"):
        raise InputError(f"mode must be 'taut', 'hug' or 'both', got {mode!r}")
    if isinstance(random_state, bool) or not isinstance(random_state, numbers.Integral):
        raise InputError(f"random_state must be an integer, got {random_state!r}")
    rng = np.random.default_rng(int(random_state))
    total = len(shapes) * n_wraps
    index = np.repeat(np.arange(len(shapes)), n_wraps)
    off = rng.uniform(*offset_links, total)
    starts = rng.uniform(0, 1, total)
    cw = rng.random(total) < 0.5
    sigma = rng.uniform(nlo, nhi, total)
    hug = rng.random(total) < 0.5 if mode == "both" else np.full(total, mode == "hug")
    theta = rng.uniform(0, 2 * np.pi, total)
    unit = []
    for s in shapes:  # centred, perimeter 1, and the diameter of that
        c = s - s.mean(axis=0)
        c = c / Polygon(c).length
        unit.append((c, _diameter(c)))
    if laps is not None:
        target = rng.uniform(*laps, total)
        size = (n_links - off) * ell / target  # perimeter
    else:
        target = np.full(total, np.nan)
        size = rng.uniform(*diameters, total) * ell / np.array([unit[i][1] for i in index])
    # a link must fit across the object
    size = np.maximum(size, 1.02 * ell / np.array([unit[i][1] for i in index]))
    objs = []
    for i in range(total):
        c, s = np.cos(theta[i]), np.sin(theta[i])
        rot = np.array([[c, s], [-s, c]])
        objs.append(unit[index[i]][0] * size[i] @ rot)
    lengths = np.full(total, ell)
    out = np.full((total, n_links), np.nan)
    got = np.zeros(total)
    done = np.zeros(total, bool)
    chunk = 64
    for lo in range(0, total, chunk):
        rows = np.arange(lo, min(lo + chunk, total))
        for flag in (False, True):
            sub = rows[hug[rows] == flag]
            if sub.size == 0:
                continue
            objs_sub = [objs[i] for i in sub]
            mode_sub = "hug" if flag else "taut"
            if laps is not None:  # chords are shorter than arcs: rescale once
                _, g, _, ok = _wrap_both_ways(
                    objs_sub, n_links, lengths[sub], starts[sub], off[sub] * ell, cw[sub], mode_sub
                )
                for j, i in enumerate(sub):
                    if ok[j] and g[j] > 0:
                        f = max(g[j] / target[i], 1.02 * ell / (unit[index[i]][1] * size[i]))
                        objs[i] = objs[i] * f
                objs_sub = [objs[i] for i in sub]
            a, g, _, ok = _wrap_both_ways(
                objs_sub, n_links, lengths[sub], starts[sub], off[sub] * ell, cw[sub], mode_sub
            )
            out[sub], got[sub], done[sub] = a, g, ok
        if progress is not None:
            progress(int(rows[-1]) + 1, total)
    done &= np.isfinite(out).all(axis=1)
    out = out + rng.normal(0.0, 1.0, out.shape) * sigma[:, None]
    return Bunch(
        data=out[done],
        outline=index[done],
        laps=got[done],
        offset=off[done],
        noise=sigma[done],
        mode=np.where(hug, "hug", "taut")[done],
        n_failed=int((~done).sum()),
        DESCR=f"Wraps of {len(shapes)} outlines by one chain of {n_links} links of {ell:g}.",
    )
