"""Generated tentacle data: the thesis's classes and MPEG-7 silhouettes, wrapped.

Everything is deterministic given ``random_state``. The wraps come from
:func:`tentaclass.wrapping.wrap_many`; this module only draws the objects and
the wrap parameters, and for MPEG-7 finds the link length that closes one lap.
"""

from __future__ import annotations

import hashlib
import inspect
import json
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, Literal, overload

import numpy as np
from shapely.geometry import Polygon
from sklearn.utils import Bunch

from .. import _dask
from .._cache import cache_dir, load_npz, save_npz
from .._deprecation import UNSET, renamed
from .._typing import ArrayLike
from .._validation import (
    MAX_LINKS,
    MAX_SAMPLES,
    MIN_LINK_FRACTION,
    check_choice,
    check_laps,
    check_noise,
    check_positive_float,
    check_positive_int,
    check_total,
)
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
    return lo, check_noise(hi, shown=noise)


def _range(value: tuple[float, float], name: str, *, allow_zero: bool) -> tuple[float, float]:
    try:
        lo, hi = value
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


def _support_laps(
    batch: Any, outlines: Sequence[np.ndarray], lengths: np.ndarray, mode: str, mirror: bool
) -> np.ndarray:
    """Laps the chain made along its support, from the start point to its last joint.

    Every joint after the approach is projected onto the support (the convex
    hull in ``"taut"`` mode, the outline's closing in ``"hug"`` mode) and the
    steps between them, each the shorter way round, are added up, over the
    support's length: 1.0 exactly when the chain is back at its start point,
    steady as the chain advances (the heading-based
    :attr:`~tentaclass.WrapBatch.laps` stands still along straight edges and
    jumps at corners), and joints in the air past a corner count where they
    hang.
    """
    import shapely

    from ..shapes import as_outline
    from ..wrapping._surface import build_surface

    flip = np.array([-1.0, 1.0]) if mirror else np.ones(2)
    out = np.full(len(outlines), np.nan)
    for i, outline in enumerate(outlines):
        last = int(batch.n_placed[i])
        first = min(int(batch.offset_links[i]), last)
        pts = np.vstack([batch.start_point[i], batch.joints[i, first : last + 1]])
        if not np.all(np.isfinite(pts)):
            continue
        surf = build_surface(as_outline(outline), mode, 0.0, 0.0, mirror, float(lengths[i]))
        ring = shapely.LinearRing(surf.curve(0))
        at = shapely.line_locate_point(ring, shapely.points(pts * flip)) / ring.length
        step = np.diff(at)
        out[i] = np.sum(step - np.round(step))
    return out


def _wrap_both_ways(outlines, n_links, lengths, starts, offsets, cw, mode="taut", centres=None,
                    along=False):  # fmt: skip
    """wrap_many over rows with per-row direction.

    Returns angles (b, n), laps (b,), winding (b,) around ``centres`` (NaN if
    not given) and complete (b,). With ``along`` the third output is instead
    the laps counted along the support (:func:`_support_laps`).
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
        if along:
            winding[rows] = _support_laps(b, [outlines[i] for i in rows], lengths[rows], mode, flag)
        elif centres is not None:
            winding[rows] = _winding(np.nan_to_num(b.joints), centres[rows])
    return angles, laps, winding, complete


def _wrap_rows(outlines, n_links, lengths, starts, offsets, cw, mode="taut", centres=None,
               along=False):  # fmt: skip
    """:func:`_wrap_both_ways`, but a wrap the generator refuses fails alone.

    ``wrap_many`` raises for a whole batch when one wrap is impossible (a
    straight approach through the object, a link longer than the object); then
    the rows are wrapped one by one and the refused ones come back as NaN rows
    with ``complete`` False, so that the caller can count them.
    """
    args = (n_links, lengths, starts, offsets, cw, mode, centres, along)
    try:
        return _wrap_both_ways(outlines, *args)
    except InputError:
        pass
    m = len(outlines)
    angles = np.full((m, n_links), np.nan)
    laps, winding = np.full(m, np.nan), np.full(m, np.nan)
    complete = np.zeros(m, bool)
    for i in range(m):
        c = None if centres is None else centres[i : i + 1]
        try:
            a, lp, w, ok = _wrap_both_ways([outlines[i]], n_links, lengths[i : i + 1],
                                           starts[i : i + 1], offsets[i : i + 1], cw[i : i + 1],
                                           mode, c, along)  # fmt: skip
        except InputError:
            continue
        angles[i], laps[i], winding[i], complete[i] = a[0], lp[0], w[0], ok[0]
    return angles, laps, winding, complete


#: Fixed chain: a wrap within this many laps of its target is taken.
_LAP_TOL = 0.01


def _fixed_chain_wraps(outlines, n_links, lap_target, offsets, starts, cw, mode, iterations=8):
    """Wraps of one chain of unit links, each object scaled to take ``lap_target`` laps.

    The laps are counted along the support the chain lies on
    (:func:`_support_laps`): the convex hull in ``"taut"`` mode, in ``"hug"``
    mode the outline with the concavities narrower than a link bridged, which
    is shorter than the outline and changes with the object's size. So the
    objects (centred, any size) are first scaled so that the outline, or its
    hull, is ``(n_links - offset) / lap_target`` long, then the scale is
    searched for up to ``iterations`` more wraps per object: the laps made
    fall as the object grows, about in inverse proportion, so each step
    rescales by ``laps / lap_target`` within the bracket the wraps so far
    have found (halving it, on a log scale, where that step leaves it). An
    object stops at ``_LAP_TOL`` from its target; the wrap nearest its target
    is kept (the laps jump where a larger object lets the chain into a
    concavity, so a few land farther).

    Returns angles (b, n_links) with NaN after the last placed link, the laps
    made along the support (b,), complete (b,), the scale applied to each
    outline (b,) and the laps by the last link's heading
    (:attr:`tentaclass.WrapBatch.laps`, b,).
    """
    m = len(outlines)
    polys = [Polygon(o) for o in outlines]
    support = np.array([p.convex_hull.length if mode == "taut" else p.length for p in polys])
    scale = np.maximum(n_links - offsets, 1.0) / lap_target / support
    small, large = np.zeros(m), np.full(m, np.inf)  # scales known to give too many, too few laps
    angles = np.full((m, n_links), np.nan)
    laps, along, best = np.full(m, np.nan), np.full(m, np.nan), np.full(m, np.inf)
    done, kept = np.zeros(m, bool), np.full(m, np.nan)
    todo = np.arange(m)
    for it in range(iterations + 1):
        rows = [outlines[i] * scale[i] for i in todo]
        a, lp, got, ok = _wrap_rows(rows, n_links, np.ones(todo.size), starts[todo],
                                    offsets[todo], cw[todo], mode, along=True)  # fmt: skip
        if it == 0:  # kept if no wrap of the object ever rests on its support
            angles[todo], laps[todo], done[todo], kept[todo] = a, lp, ok, scale[todo]
        err = np.where(ok & np.isfinite(got), np.abs(got - lap_target[todo]), np.inf)
        better = err < best[todo]
        up = todo[better]
        angles[up], laps[up], along[up], done[up] = a[better], lp[better], got[better], ok[better]
        best[up], kept[up] = err[better], scale[up]
        if it == iterations:
            break
        # where no joint rests on the support, the heading tells the way
        got = np.where(np.isfinite(got), got, lp)
        fine = ok & np.isfinite(got) & (got > 0.05)
        many = fine & (got > lap_target[todo])
        small[todo[many]] = np.maximum(small[todo[many]], scale[todo[many]])
        few = fine & ~many
        large[todo[few]] = np.minimum(large[todo[few]], scale[todo[few]])
        step = scale[todo] * np.where(fine, got, 1.0) / lap_target[todo]
        lo, hi = small[todo], large[todo]
        inside = fine & (step > lo) & (step < hi)
        with np.errstate(invalid="ignore"):
            halve = np.where(lo > 0, np.sqrt(lo * hi), 0.5 * hi)
        halve = np.where(np.isfinite(hi), halve, 2 * lo)
        # a jammed or refused wrap: another size nearby
        scale[todo] = np.where(inside, step, np.where(fine, halve, 0.9 * scale[todo]))
        todo = todo[best[todo] > _LAP_TOL]
        if todo.size == 0:
            break
    laps = np.where(done, laps, np.nan)
    # no joint on the support at any size tried (the chain stood off it): the heading's count
    along = np.where(done, np.where(np.isfinite(along), along, laps), np.nan)
    return angles, along, done, kept, laps


@overload
def synthetic_tentacle(
    n_samples: int,
    n_links: int = ...,
    *,
    laps: tuple[float, float] = ...,
    offset: tuple[float, float] = ...,
    noise: float | tuple[float, float] = ...,
    mode: str = ...,
    random_state: int = ...,
    return_X_y: Literal[False] = ...,
    client: object = ...,
    offset_links: Any = ...,
    seed: Any = ...,
) -> Bunch: ...


@overload
def synthetic_tentacle(
    n_samples: int,
    n_links: int = ...,
    *,
    laps: tuple[float, float] = ...,
    offset: tuple[float, float] = ...,
    noise: float | tuple[float, float] = ...,
    mode: str = ...,
    random_state: int = ...,
    return_X_y: Literal[True],
    client: object = ...,
    offset_links: Any = ...,
    seed: Any = ...,
) -> tuple[np.ndarray, np.ndarray]: ...


def synthetic_tentacle(
    n_samples: int,
    n_links: int = 16,
    *,
    laps: tuple[float, float] = (1.0, 2.0),
    offset: tuple[float, float] = (0.0, 3.0),
    noise: float | tuple[float, float] = (0.0, 0.05),
    mode: str = "taut",
    random_state: int = 0,
    return_X_y: bool = False,
    client: object = None,
    offset_links: Any = UNSET,
    seed: Any = UNSET,
) -> Bunch | tuple:
    """Wraps of random squares, circles, triangles and rectangles by one chain.

    One chain of ``n_links`` unit links; each sample draws a class, a size such
    that the chain covers ``laps`` laps after its approach, a rectangle aspect
    ratio in [1.2, 4] or triangle angles (all >= 25 degrees), a rotation, a
    start point, a direction, a stand-off from ``offset`` and a
    joint-noise sigma from ``noise``.

    Parameters
    ----------
    n_samples : int
    n_links : int, default=16
    laps : (float, float), default=(1, 2)
        Range of laps wrapped; use ``(0.5, 0.95)`` for partial wraps.
    offset : (float, float), default=(0, 3)
        Range of the base's stand-off from the object, a distance; the links
        are of unit length, so it is also the number of links the approach
        takes (:attr:`tentaclass.Wrap.offset_links`, rounded up).
    noise : float or (float, float), default=(0, 0.05)
        Joint-noise sigma in radians, or the range it is drawn from.
    mode : {"taut", "hug"}, default="taut"
    random_state : int, default=0
    return_X_y : bool, default=False
        Return ``(data, target)`` instead of a Bunch.
    client : distributed.Client, optional
        Generate the wraps on this Dask cluster; the result is the same.
    offset_links, seed : optional
        Deprecated aliases of ``offset`` and ``random_state``.

    Returns
    -------
    data : Bunch
        ``data`` (n_samples, n_links) angles, ``target`` (n_samples,) class,
        ``laps`` (n_samples,) laps wrapped after the approach, counted along the
        convex hull or the hug support (1.0 exactly back at the start point; the
        object is sized until they are within 0.01 of the laps drawn), ``offset`` (n_samples,)
        stand-off (a distance, in link lengths), ``noise`` (n_samples,) sigma used, ``complete``
        (n_samples,) False where the generator could not place every link (the
        row is NaN after the last placed link; count it as an error).

    Examples
    --------
    >>> d = synthetic_tentacle(8, 16, random_state=1)
    >>> d.data.shape, set(d.target.tolist()) <= {'circle', 'rectangle', 'square', 'triangle'}
    ((8, 16), True)
    >>> X, y = synthetic_tentacle(8, 16, random_state=1, return_X_y=True)
    >>> X.shape, y.shape
    ((8, 16), (8,))
    """
    offset = renamed("offset", offset, "offset_links", offset_links, default=(0.0, 3.0))
    random_state = renamed("random_state", random_state, "seed", seed, default=0)
    n_samples = check_positive_int(n_samples, "n_samples", maximum=MAX_SAMPLES)
    n_links = check_positive_int(n_links, "n_links", minimum=3, maximum=MAX_LINKS)
    check_total(n_samples * n_links, "the angles (n_samples x n_links)")
    nlo, nhi = _noise_range(noise)
    laps = _range(laps, "laps", allow_zero=False)
    offset = _range(offset, "offset", allow_zero=True)
    _check_random_state(random_state)
    check_choice(mode, "mode", ("taut", "hug"))
    rng = np.random.default_rng(random_state)
    cls = rng.choice(THESIS_CLASSES, n_samples)
    lap_target = rng.uniform(*laps, n_samples)
    off = rng.uniform(*offset, n_samples)
    outlines = [_random_outline(c, 1.0, rng) for c in cls]
    starts = rng.uniform(0, 1, n_samples)
    cw = rng.random(n_samples) < 0.5
    sigma = rng.uniform(nlo, nhi, n_samples)
    angles, got_laps, done, _, _ = _dask.split_rows(
        _fixed_chain_wraps, outlines, n_links, lap_target, off, starts, cw, mode, client=client
    )
    angles = angles + rng.normal(0.0, 1.0, angles.shape) * sigma[:, None]
    if return_X_y:
        return angles, cls
    descr = "Synthetic wraps of the four thesis classes by one chain of unit links."
    return Bunch(data=angles, target=cls, laps=got_laps, offset=off, noise=sigma, complete=done,
                 DESCR=descr)  # fmt: skip


def _check_random_state(value: object) -> None:
    """Wraps are cached by their seed: an integer, not a Generator."""
    check_positive_int(value, "random_state", minimum=0)


def _generator_digest() -> str:
    """Hash of the wrap generator's source: a changed generator never reads old wraps.

    Covers the wrapping package and the functions here that make the wraps, not
    this module's docstrings or its other datasets.
    """
    from .. import wrapping

    h = hashlib.sha256()
    for f in sorted(Path(wrapping.__file__).parent.glob("*.py")):
        h.update(f.read_bytes())
    for func in (
        _winding,
        _support_laps,
        _wrap_both_ways,
        _wrap_rows,
        _fixed_chain_wraps,
        _rotated,
        _fixed_chain_mpeg7,
        _bisect_lengths,
        _closure_gaps,
        _one_lap_wraps,
    ):
        h.update(inspect.getsource(func).encode())
    return h.hexdigest()[:16]


#: Version of the cached wraps: raised whenever the wraps themselves change (the
#: protocols, what the draws and the search mean, or the taut and hug links), even
#: where the hash of the generator's source would tell the change too.
_WRAPS_VERSION = 3


def _wrap_cache_key(folder: str | Path, params: dict) -> dict:
    """The wrap cache's key: the parameters, the folder's files and the code that made them.

    The package version, ``_WRAPS_VERSION`` and the hash of the
    generator's source: wraps cached by another version of any of them are
    never read.
    """
    from .. import __version__

    return {**params, "version": __version__, "wraps_version": _WRAPS_VERSION,
            "code": _generator_digest(), **_folder_key(folder)}  # fmt: skip


def _cache_path(key: dict) -> Path:
    digest = hashlib.sha256(json.dumps(key, sort_keys=True).encode()).hexdigest()[:16]
    return cache_dir() / f"mpeg7-wraps-{digest}.npz"


def _folder_key(folder: str | Path) -> dict:
    """What the silhouettes in a folder are: its path and every file's name, size and mtime."""
    path = Path(folder).expanduser().resolve()
    files = sorted(path.glob("*.png"), key=lambda f: f.name.lower())
    return {
        "folder": str(path),
        "files": [[f.name, f.stat().st_size, f.stat().st_mtime_ns] for f in files],
    }


def clear_cache() -> int:
    """Delete every cached wrap file; returns how many were removed.

    Examples
    --------
    >>> isinstance(clear_cache(), int)
    True
    """
    removed = 0
    for f in cache_dir().glob("mpeg7-wraps-*.npz"):
        f.unlink(missing_ok=True)
        removed += 1
    return removed


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


PROTOCOLS = ("one-lap", "fixed-chain")


def _rotated(outline: np.ndarray, theta: float) -> np.ndarray:
    c, s = np.cos(theta), np.sin(theta)
    centred = outline - outline.mean(axis=0)
    return centred @ np.array([[c, s], [-s, c]])


def _fixed_chain_mpeg7(
    outlines: Sequence[np.ndarray],
    n_links: int,
    mode: str,
    copies: int,
    seed: int,
    laps: tuple[float, float],
    offset: tuple[float, float],
    progress: bool = False,
    chunk: int = 50,
    client: object = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Noise-free fixed-chain wraps of every outline, copy after copy.

    Generated in chunks of ``chunk`` wraps (each wrap is independent, so the
    result does not depend on it), with a rich progress bar on stderr if
    ``progress``.
    """
    rng = np.random.default_rng(seed)
    m = len(outlines) * copies
    lap_target = rng.uniform(*laps, m)
    off = rng.uniform(*offset, m)
    starts = rng.uniform(0, 1, m)
    cw = rng.random(m) < 0.5
    theta = rng.uniform(0, 2 * np.pi, m)
    rows = [_rotated(outlines[i % len(outlines)], t) for i, t in zip(range(m), theta, strict=True)]
    angles = np.full((m, n_links), np.nan)
    got, done = np.full(m, np.nan), np.zeros(m, bool)
    bar = None
    if progress:
        from rich.progress import Progress

        bar = Progress(transient=True)
        bar.start()
        task = bar.add_task(f"wrapping ({mode})", total=m)
    try:
        for lo in range(0, m, chunk):
            part = slice(lo, lo + chunk)
            angles[part], got[part], done[part], _, _ = _dask.split_rows(
                _fixed_chain_wraps,
                rows[part],
                n_links,
                lap_target[part],
                off[part],
                starts[part],
                cw[part],
                mode,
                client=client,
            )
            if bar is not None:
                bar.update(task, completed=min(lo + chunk, m))
    finally:
        if bar is not None:
            bar.stop()
    return angles, got, done, off


def mpeg7_tentacle(
    folder: str | Path,
    n_links: int = 64,
    mode: str = "taut",
    *,
    protocol: str = "one-lap",
    laps: tuple[float, float] = (1.2, 2.0),
    offset: tuple[float, float] = (0.0, 2.0),
    noise: float = 0.0,
    copies: int = 1,
    random_state: int = 0,
    max_vertices: int = 1000,
    cache: bool = True,
    n_jobs: int | None = None,
    progress: bool = False,
    client: object = None,
    offset_links: Any = UNSET,
    seed: Any = UNSET,
) -> Bunch:
    """Tentacle wraps of every MPEG-7 Part B silhouette.

    Two protocols:

    - ``"fixed-chain"``: what a robot meets. One chain of ``n_links`` unit
      links; each silhouette is rotated at random and scaled at random so that
      the chain wraps a number of laps drawn from ``laps`` after an approach
      from a stand-off drawn from ``offset``, from a random start point in a
      random direction. The laps are those of the chain's own path (a hugging
      chain bridges the concavities narrower than a link, so its lap is
      shorter than the outline): each silhouette is resized, a few wraps
      each, until the chain makes them to within 0.01 lap.
      Wraps the generator cannot complete are kept, flagged in ``complete``:
      score them as errors.
    - ``"one-lap"``: the link length is tuned per silhouette (by bisection) so
      that the chain closes exactly one lap, with no approach. No chain does
      that on a robot: results on it are an upper bound.

    Parameters
    ----------
    folder : path
        The MPEG-7 CE-Shape-1 Part B folder (see :func:`tentaclass.shapes.load_mpeg7`).
    n_links : int, default=64
    mode : {"taut", "hug"}, default="taut"
    protocol : {"one-lap", "fixed-chain"}, default="one-lap"
    laps : (float, float), default=(1.2, 2.0)
        Fixed chain: range of the laps wrapped after the approach;
        ``(0.5, 0.95)`` gives partial wraps.
    offset : (float, float), default=(0, 2)
        Fixed chain: range of the base's stand-off from the object, a
        distance; the links are of unit length, so it is also the number of
        links of the approach (rounded up).
    noise : float, default=0.0
        Joint-noise sigma in radians.
    copies : int, default=1
        Wraps per silhouette, each with its own draws. Copy 0 is the one to
        score; the others can serve as extra training data.
    random_state : int, default=0
    max_vertices : int, default=1000
        Outlines are resampled to at most this many vertices first.
    cache : bool, default=True
        Keep the outlines and the noise-free wraps on disk
        (``$XDG_CACHE_HOME/tentaclass`` or ``~/.cache/tentaclass``, files
        ``mpeg7-wraps-*.npz``). The key covers the folder, every file's name,
        size and modification time, all parameters but ``noise``, the package
        version, the protocols' version and the generator's code, so an
        upgrade never reads wraps an older version made. ``False`` reads and
        writes nothing; :func:`clear_cache` deletes the cached wraps.
    n_jobs : int, optional
        One-lap protocol: processes for the bisection, as in joblib (-1 all
        cores, None one). The wraps do not depend on it.
    progress : bool, default=False
        Fixed chain: show a progress bar (rich, on stderr) while wrapping.
    client : distributed.Client, optional
        Generate the wraps on this Dask cluster; the wraps are the same.
    offset_links, seed : optional
        Deprecated aliases of ``offset`` and ``random_state``.

    Returns
    -------
    data : Bunch
        ``data`` (1400 * copies, n_links), ``target`` class names, ``groups``
        the silhouette's index, ``wrap_index`` the copy number, ``names`` file
        names, ``complete`` False where the wrap failed (the chain jammed
        before placing every link, or the generator refused it; the row is NaN
        after the last placed link), ``laps`` the laps wrapped after the
        approach, counted along the support the chain lies on (fixed chain;
        NaN for the one-lap protocol), ``offset`` the stand-off (a distance, in
        link lengths),
        ``closure_gap`` how far (in links) the noise-free chain's last joint
        ends from its first. One-lap protocol: from some start points no link
        length closes the lap; such wraps are retried from up to eight other
        random start points and the best kept.

    Examples
    --------
    On the whole folder this wraps all 1400 silhouettes; here two of them:

    >>> import shutil, tempfile
    >>> from pathlib import Path
    >>> mpeg7 = Path("../shared/data/mpeg7-part-b")
    >>> folder = Path(tempfile.mkdtemp())
    >>> for name in ["apple-1.png", "bat-1.png"] if mpeg7.is_dir() else []:
    ...     _ = shutil.copy(mpeg7 / name, folder)
    >>> if mpeg7.is_dir():
    ...     d = mpeg7_tentacle(folder, 64, "hug", protocol="fixed-chain", cache=False)
    ...     print(d.data.shape, d.target.tolist())
    ... else:
    ...     print((2, 64), ["apple", "bat"])
    (2, 64) ['apple', 'bat']
    >>> shutil.rmtree(folder)
    """
    offset = renamed("offset", offset, "offset_links", offset_links, default=(0.0, 2.0))
    random_state = renamed("random_state", random_state, "seed", seed, default=0)
    n_links = check_positive_int(n_links, "n_links", minimum=3, maximum=MAX_LINKS)
    copies = check_positive_int(copies, "copies", maximum=MAX_SAMPLES)
    noise = check_positive_float(noise, "noise", allow_zero=True)
    check_choice(mode, "mode", ("taut", "hug"))
    check_choice(protocol, "protocol", PROTOCOLS)
    laps = _range(laps, "laps", allow_zero=False)
    offset = _range(offset, "offset", allow_zero=True)
    _check_random_state(random_state)
    outlines, labels, names = load_mpeg7(folder, max_vertices=max_vertices, cache=cache)
    params = {"n": n_links, "mode": mode, "copies": copies, "seed": int(random_state),
              "mv": max_vertices, "protocol": protocol}  # fmt: skip
    if protocol == "fixed-chain":
        params.update(laps=list(laps), offset=list(offset))
    path = _cache_path(_wrap_cache_key(folder, params))
    n_shapes = len(outlines)
    check_total(n_shapes * copies * n_links, "the angles (shapes x copies x n_links)")
    stored = load_npz(path, "angles", "laps", "complete", "offset") if cache else None
    if stored is not None:
        angles, got, done, off = stored
    else:
        if protocol == "fixed-chain":
            angles, got, done, off = _fixed_chain_mpeg7(
                outlines,
                n_links,
                mode,
                copies,
                random_state,
                laps,
                offset,
                progress,
                chunk=50 if client is None else 1000,
                client=client,
            )
        else:
            with _dask.on_client(client):
                jobs = -1 if client is not None else n_jobs
                angles = _one_lap_wraps(outlines, n_links, mode, copies, random_state, n_jobs=jobs)
            done = np.all(np.isfinite(angles), axis=1)
            got, off = np.full(len(angles), np.nan), np.zeros(len(angles))
        if cache:
            save_npz(path, angles=angles, laps=got, complete=done, offset=off)
    gap = _closure_gaps(angles)
    gap[~done] = np.nan
    rng = np.random.default_rng([random_state, 1])
    if noise > 0:
        angles = angles + rng.normal(0.0, noise, angles.shape)
    what = f"one-lap wraps of {n_links} tuned links"
    if protocol == "fixed-chain":
        what = f"one chain of {n_links} unit links, {laps[0]:g}-{laps[1]:g} laps"
    return Bunch(
        complete=done,
        closure_gap=gap,
        data=angles,
        laps=got,
        offset=off,
        target=np.tile(labels, copies),
        groups=np.tile(np.arange(n_shapes), copies),
        wrap_index=np.repeat(np.arange(copies), n_shapes),
        names=np.tile(np.array(names), copies),
        DESCR=f"MPEG-7 Part B, {mode} wraps: {what}.",
    )


def _diameter(outline: np.ndarray) -> float:
    from scipy.spatial import ConvexHull, QhullError

    try:
        hull = outline[ConvexHull(outline).vertices]
    except QhullError:
        hull = outline
    d = hull[:, None, :] - hull[None, :, :]
    return float(np.sqrt((d**2).sum(-1)).max())


def check_chain_settings(
    n_links: int,
    link_length: float,
    *,
    laps: tuple[float, float] | None,
    diameters: tuple[float, float] | None,
    offset: tuple[float, float],
    noise: float | tuple[float, float],
    mode: str,
) -> tuple[
    tuple[float, float] | None, tuple[float, float] | None, tuple[float, float], tuple[float, float]
]:
    """:func:`chain_wraps`' ranges, checked against the chain before any outline is read.

    ``n_links`` and ``link_length`` are already checked. Returns ``laps``,
    ``diameters``, ``offset`` and the noise range as ``(low, high)`` pairs
    (``None`` for the one of ``laps`` and ``diameters`` not given).

    Examples
    --------
    >>> check_chain_settings(16, 1.0, laps=(1, 9), diameters=None, offset=(0, 2), noise=0,
    ...                      mode="taut")
    Traceback (most recent call last):
    ...
    tentaclass.errors.InputError: laps: 16 links cannot close 9 laps (at most 8: 2 links per lap)
    """
    if (laps is None) == (diameters is None):
        raise InputError("give either laps or diameters (the other None)")
    if laps is not None:
        laps = _range(laps, "laps", allow_zero=False)
        check_laps(laps[1], n_links)
    if diameters is not None:
        diameters = _range(diameters, "diameters", allow_zero=False)
        if diameters[1] > 1 / MIN_LINK_FRACTION:
            raise InputError(
                f"diameters must be at most {1 / MIN_LINK_FRACTION:g} link lengths (links "
                f"shorter than {MIN_LINK_FRACTION:g} of an object cannot be placed on it), "
                f"got {diameters!r}"
            )
        if diameters[0] < 1.0:
            raise InputError(
                f"diameters must be at least 1 link length (a link must fit across the "
                f"object), got {diameters!r}"
            )
    offset = _range(offset, "offset", allow_zero=True)
    if offset[1] / link_length >= n_links - 2:
        raise InputError(
            f"offset must stay below (n_links - 2) * link_length = "
            f"{(n_links - 2) * link_length:g} so that links reach the object, got {offset!r}"
        )
    noise_range = _noise_range(noise)
    check_choice(mode, "mode", ("taut", "hug", "both"))
    return laps, diameters, offset, noise_range


def chain_wraps(
    outlines: Sequence[ArrayLike],
    n_links: int,
    link_length: float = 1.0,
    *,
    n_wraps: int = 50,
    laps: tuple[float, float] | None = (1.0, 2.0),
    diameters: tuple[float, float] | None = None,
    offset: tuple[float, float] = (0.0, 2.0),
    noise: float | tuple[float, float] = 0.0,
    mode: str = "taut",
    random_state: int = 0,
    progress: Callable[[int, int], None] | None = None,
    offset_links: Any = UNSET,
) -> Bunch:
    """Wraps of given outlines by one fixed chain, as a robot would measure them.

    Each outline is wrapped ``n_wraps`` times by the same chain of ``n_links``
    links of ``link_length``: every wrap draws a size (so that the chain
    covers ``laps`` laps after its approach, or so that the object's diameter
    is in ``diameters``), a rotation, a start point, a direction, a stand-off
    from ``offset`` and a joint-noise sigma from ``noise``. Wraps
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
    offset : (float, float), default=(0, 2)
        Range of the base's stand-off from the object, a distance in the units
        of ``link_length``; the approach takes ``ceil(offset / link_length)``
        links.
    noise : float or (float, float), default=0
        Joint-noise sigma in radians, or the range it is drawn from.
    mode : {"taut", "hug", "both"}, default="taut"
        How the chain lies on concave outlines; ``"both"`` draws one per wrap.
    random_state : int, default=0
    progress : callable, optional
        Called as ``progress(done, total)`` while the wraps are generated.
    offset_links : (float, float), optional
        Deprecated: the stand-off range in links, ``offset / link_length``.

    Returns
    -------
    data : Bunch
        ``data`` (n, n_links) joint angles; ``outline`` (n,) index of the
        outline wrapped; ``laps`` (counted along the support the chain lies on,
        1.0 exactly back at the start point), ``offset`` (a distance),
        ``noise``, ``mode`` (n,) per wrap; ``n_failed``, the number of wraps
        left out.

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
    n_links = check_positive_int(n_links, "n_links", minimum=3, maximum=MAX_LINKS)
    ell = check_positive_float(link_length, "link_length")
    n_wraps = check_positive_int(n_wraps, "n_wraps", maximum=MAX_SAMPLES)
    n_total = len(shapes) * n_wraps
    check_total(n_total, "the wraps (outlines x n_wraps)", maximum=MAX_SAMPLES, unit="samples")
    check_total(n_total * n_links, "the angles (outlines x n_wraps x n_links)")
    if offset_links is not UNSET:
        links = _range(offset_links, "offset_links", allow_zero=True)
        offset = renamed("offset", offset, "offset_links", (links[0] * ell, links[1] * ell),
                         default=(0.0, 2.0))  # fmt: skip
    laps, diameters, offset, (nlo, nhi) = check_chain_settings(
        n_links, ell, laps=laps, diameters=diameters, offset=offset, noise=noise, mode=mode
    )
    rng = np.random.default_rng(check_positive_int(random_state, "random_state", minimum=0))
    total = len(shapes) * n_wraps
    index = np.repeat(np.arange(len(shapes)), n_wraps)
    off = rng.uniform(offset[0] / ell, offset[1] / ell, total)  # in links
    starts = rng.uniform(0, 1, total)
    cw = rng.random(total) < 0.5
    sigma = rng.uniform(nlo, nhi, total)
    hug = rng.random(total) < 0.5 if mode == "both" else np.full(total, mode == "hug")
    theta = rng.uniform(0, 2 * np.pi, total)
    # joint angles do not depend on the scale: wrap with unit links, objects in link lengths
    unit = [(s - s.mean(axis=0)) / _diameter(s) for s in shapes]  # diameter 1
    objs = [_rotated(unit[i], t) for i, t in zip(index, theta, strict=True)]
    if laps is not None:
        target = rng.uniform(*laps, total)
    elif diameters is not None:
        size = rng.uniform(*diameters, total)
        objs = [o * d for o, d in zip(objs, size, strict=True)]
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
            args = (starts[sub], cw[sub], "hug" if flag else "taut")
            if laps is not None:  # scaled until the chain makes the laps
                a, g, ok, _, _ = _fixed_chain_wraps(objs_sub, n_links, target[sub], off[sub], *args)
            else:
                a, _, g, ok = _wrap_rows(objs_sub, n_links, np.ones(sub.size), args[0], off[sub],
                                         args[1], args[2], along=True)  # fmt: skip
            out[sub], got[sub], done[sub] = a, g, ok
        if progress is not None:
            progress(int(rows[-1]) + 1, total)
    done &= np.isfinite(out).all(axis=1)
    out = out + rng.normal(0.0, 1.0, out.shape) * sigma[:, None]
    return Bunch(
        data=out[done],
        outline=index[done],
        laps=got[done],
        offset=off[done] * ell,
        noise=sigma[done],
        mode=np.where(hug, "hug", "taut")[done],
        n_failed=int((~done).sum()),
        DESCR=f"Wraps of {len(shapes)} outlines by one chain of {n_links} links of {ell:g}.",
    )
