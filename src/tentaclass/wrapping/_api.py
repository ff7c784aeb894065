"""Public entry points: :func:`wrap` and :func:`wrap_many`."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, cast

import numpy as np
import shapely

from .. import _dask
from .._deprecation import UNSET, renamed
from .._typing import ArrayLike, FloatArray
from .._validation import (
    MAX_LINKS,
    check_links_fit,
    check_noise,
    check_one_value,
    check_positive_float,
    check_positive_int,
    check_reach,
    check_thickness_fits,
)
from ..errors import InputError
from ..shapes import as_outline
from ._result import Wrap, WrapBatch
from ._surface import (
    Surface,
    build_surface,
    outline_diameter,
    point_at_fraction,
)

__all__ = ["MAX_LINKS", "Wrap", "WrapBatch", "wrap", "wrap_many"]

_MODES = ("taut", "hug")

#: A stretch of support within this fraction of a link of the outline counts as
#: resting on the object: links between two joints on it are chords (they may
#: cut the cap they span) and are not tested for crossing.
SLACK = 0.05
_DIRECTIONS = ("ccw", "cw")


def _choice(value: object, name: str, options: tuple[str, ...]) -> str:
    if not isinstance(value, str) or value.lower() not in options:
        raise InputError(f"{name} must be one of {', '.join(map(repr, options))}, got {value!r}")
    return value.lower()


def _as_batch(x: ArrayLike, name: str, b: int | None, lo: float, hi: float | None) -> FloatArray:
    try:
        arr = np.asarray(x, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{name} must be a number or an array of numbers") from exc
    if arr.ndim > 1:
        raise InputError(f"{name} must be a scalar or 1-D, got shape {arr.shape}")
    if arr.size == 0:
        raise InputError(f"{name} is empty: give a number or at least one value")
    if not np.all(np.isfinite(arr)):
        raise InputError(f"{name} contains NaN or infinite values")
    if np.any(arr < lo) or (hi is not None and np.any(arr >= hi)):
        rng = f"in [{lo:g}, {hi:g})" if hi is not None else f">= {lo:g}"
        raise InputError(f"{name} must be {rng}, got {x!r}")
    if b is not None and arr.size not in (1, b):
        raise InputError(f"{name} has {arr.size} values for {b} wraps: give one value or {b}")
    return arr if b is None else np.broadcast_to(arr, (b,)).copy()


def _inward_normal(curve: FloatArray, e: int, t: float) -> FloatArray:
    """Inward normal of the support edge that leaves the point (edge ``e`` at ``t``)."""
    m = len(curve)
    if t >= 1 - 1e-9:
        e = (e + 1) % m
    d = curve[(e + 1) % m] - curve[e]
    return np.array([-d[1], d[0]]) / np.hypot(*d)


def _run(
    surf: Surface,
    outline: FloatArray,
    n: int,
    ls: FloatArray,
    starts: FloatArray,
    offsets: FloatArray,
    mirror: bool,
) -> dict:
    b = len(ls)
    c_count = len(surf.off) - 1
    p0 = point_at_fraction(outline, starts)
    if mirror:
        p0 = p0 * [-1.0, 1.0]
    es = np.empty((b, c_count), np.int64)
    spt = np.empty((b, c_count, 2))
    from . import _kernel  # numba: imported (and compiled) on first use

    e0, t0, s0 = _kernel.locate(p0, np.ascontiguousarray(surf.curve(0)))
    es[:, 0], spt[:, 0] = e0, s0
    for c in range(1, c_count):
        ec, _, sc = _kernel.locate(s0, np.ascontiguousarray(surf.curve(c)))
        es[:, c], spt[:, c] = ec, sc
    th0 = surf.theta[surf.off[0] + e0]
    approach = offsets > 0
    bases = s0.copy()
    app_th = th0 + np.pi / 2
    turn = np.zeros(len(offsets))
    rows = np.flatnonzero(approach)
    if rows.size:
        nin = np.array([_inward_normal(surf.curve(0), int(e0[q]), float(t0[q])) for q in rows])
        turn[rows] = _free_approach(surf, s0[rows], nin, offsets[rows])
        a = np.arctan2(nin[:, 1], nin[:, 0]) + turn[rows]
        bases[rows] = s0[rows] - offsets[rows, None] * np.stack([np.cos(a), np.sin(a)], axis=1)
        app_th[rows] = a + np.round((app_th[rows] - a) / (2 * np.pi)) * 2 * np.pi
    max_search = offsets + surf.max_perimeter + 2 * ls
    check = 3 if surf.mode == "hug" else 2
    eps = 1e-12 * surf.scale * surf.scale
    joints, contact, lap, phi, status, placed, phi_v = _kernel.walk_many(
        n, ls, surf.pts, surf.off, surf.theta, surf.dev, surf.outline, eps, es, spt, th0,
        bases, app_th, approach, check, surf.n_laps, max_search, SLACK, 1e-9 * surf.scale,
        0.5 * surf.perimeter, surf.vidx,
    )  # fmt: skip
    return {
        "joints": joints, "contact": contact, "lap": lap, "phi": phi, "status": status,
        "placed": placed, "phi_v": phi_v, "start": s0, "turn": turn,
    }  # fmt: skip


#: Approach directions tried, as turns away from the support's normal at the
#: start point: the straight approach first, then ever wider on both sides.
_TURNS = np.concatenate([[0.0], np.stack([d := np.linspace(0.05, 1.5, 30), -d], 1).ravel()])


def _free_approach(
    surf: Surface, starts: FloatArray, inward: FloatArray, offsets: FloatArray
) -> FloatArray:
    """Turn of each approach away from the normal so that it stays outside the object.

    The base stands ``offset`` from the start point along the outward normal;
    where that straight approach would pass through another part of a
    non-convex object, the approach turns (up to 86 degrees either way) to the
    nearest direction that clears it. If none does, the straight one is kept and
    the walk lets its links rest on the object where they meet it.
    """
    body = shapely.Polygon(surf.outline)
    shapely.prepare(body)
    turn = np.zeros(len(starts))
    todo = np.arange(len(starts))
    base_angle = np.arctan2(inward[:, 1], inward[:, 0])
    tol = 1e-9 * surf.scale
    for t in _TURNS:
        a = base_angle[todo] + t
        ends = starts[todo] - offsets[todo, None] * np.stack([np.cos(a), np.sin(a)], axis=1)
        paths = shapely.linestrings(np.stack([ends, starts[todo]], axis=1))
        meet = shapely.relate_pattern(paths, body, "T********")  # interiors meet
        if meet.any():
            meet[meet] = shapely.length(shapely.intersection(paths[meet], body)) > tol
        turn[todo[~meet]] = t
        todo = todo[meet]
        if todo.size == 0:
            break
    return turn


def _geom_locate(points, curve):
    from ._geom import locate

    return locate(points, curve)


def _outline_list(outlines: ArrayLike | Sequence[ArrayLike]) -> list[ArrayLike] | None:
    """The outlines of a batch, or None when ``outlines`` is one outline (rows of points)."""
    if isinstance(outlines, np.ndarray):
        return None if outlines.ndim == 2 else list(outlines)
    if isinstance(outlines, Sequence) and len(outlines) > 0 and np.ndim(outlines[0]) != 1:
        return list(outlines)
    return None


def wrap_many(
    outlines: ArrayLike | Sequence[ArrayLike],
    n_links: int,
    link_length: ArrayLike,
    starts: ArrayLike = 0.0,
    *,
    direction: str = "ccw",
    offset: ArrayLike = 0.0,
    mode: str = "taut",
    noise: float = 0.0,
    random_state: int | np.random.Generator | None = None,
    thickness: float = 0.0,
    seed: Any = UNSET,
) -> WrapBatch:
    """Many wraps at once: one outline with many start points, or many outlines.

    Parameters
    ----------
    outlines : array_like of shape (n_points, 2), or a sequence of them
        One outline (the batch runs over ``starts``, ``link_length`` and
        ``offset``, broadcast together), or one outline per wrap.
    n_links, link_length, starts, direction, offset, mode, noise, random_state, thickness
        As in :func:`wrap`; ``link_length``, ``starts`` and ``offset`` may be
        1-D arrays (one value per wrap).
    seed : int or numpy.random.Generator, optional
        Deprecated alias of ``random_state``.

    Returns
    -------
    WrapBatch
        Stacked arrays with a leading batch axis; ``batch[i]`` is a :class:`Wrap`.
        Wraps that stopped early are padded with NaN (angles, joints) and -2 (lap).

    Examples
    --------
    >>> from tentaclass.shapes import circle
    >>> b = wrap_many(circle(1.0), 16, 0.39, starts=np.linspace(0, 1, 100, endpoint=False))
    >>> b.angles.shape, bool(b.complete.all())
    ((100, 16), True)
    """
    seed = renamed("random_state", random_state, "seed", seed)
    n = check_positive_int(n_links, "n_links")
    if n > MAX_LINKS:
        raise InputError(f"n_links must be at most {MAX_LINKS:,}, got {n:,}")
    direction = _choice(direction, "direction", _DIRECTIONS)
    mode = _choice(mode, "mode", _MODES)
    noise = check_noise(noise)
    thickness = check_positive_float(thickness, "thickness", allow_zero=True)
    if _dask.wants_blocks(outlines, link_length, starts, offset):  # lazy, chunk by chunk
        kw = {"direction": direction, "mode": mode, "noise": noise, "thickness": thickness}
        return _dask.wrap_blocks(wrap_many, outlines, n, link_length, starts, offset, seed, **kw)
    many = _outline_list(outlines)
    if many is None:
        # one outline: numpy's ArrayLike does not cover every sequence of points
        shapes = [as_outline(cast(ArrayLike, outlines))]
        ls = _as_batch(link_length, "link_length", None, 0.0, None)
        st = _as_batch(starts, "starts", None, 0.0, 1.0)
        off = _as_batch(offset, "offset", None, 0.0, None)
        sizes = {a.size for a in (ls, st, off)} - {1}
        if len(sizes) > 1:
            raise InputError(
                f"link_length, starts and offset have {ls.size}, {st.size} and {off.size} "
                "values: give each one value or the same number of values"
            )
        b = max(sizes, default=1)
        groups = [np.arange(b)]
        if mode == "hug":  # the support depends on the link length
            lb = np.broadcast_to(ls, (b,))
            groups = [np.flatnonzero(lb == v) for v in np.unique(lb)]
            shapes = shapes * len(groups)
    else:
        shapes = [as_outline(o, f"outlines[{i}]") for i, o in enumerate(many)]
        b = len(shapes)
        groups = [np.array([i]) for i in range(b)]
    ls = _as_batch(link_length, "link_length", b, 0.0, None)
    st = _as_batch(starts, "starts", b, 0.0, 1.0)
    off = _as_batch(offset, "offset", b, 0.0, None)
    if np.any(ls <= 0):
        raise InputError(f"link_length must be > 0, got {link_length!r}")
    check_reach(off, n, ls)
    mirror = direction == "cw"
    out = {
        "joints": np.full((b, n + 1, 2), np.nan),
        "contact": np.zeros((b, n + 1), bool),
        "lap": np.full((b, n + 1), -2, np.int64),
        "phi": np.full((b, n + 1), np.nan),
        "status": np.zeros(b, np.int64),
        "placed": np.zeros(b, np.int64),
        "phi_v": np.zeros(b),
        "start": np.zeros((b, 2)),
        "turn": np.zeros(b),
    }
    on_start = np.zeros(b, bool)
    scales = np.zeros(b)
    for outline, rows in zip(shapes, groups, strict=True):
        if thickness > 0:
            check_thickness_fits(thickness, outline_diameter(outline))
        surf = build_surface(
            outline, mode, thickness, float(n * ls[rows].max()), mirror, float(ls[rows][0])
        )
        check_links_fit(ls[rows], surf.diameter)
        res = _run(surf, outline, n, ls[rows], st[rows], off[rows], mirror)
        for key, val in res.items():
            out[key][rows] = val
        e0, _, _ = _geom_locate(res["start"], np.ascontiguousarray(surf.curve(0)))
        on_start[rows] = surf.dev[e0] <= 1e-9 * surf.scale
        scales[rows] = surf.scale
    return _finish(out, n, ls, off, mirror, noise, seed, on_start, scales, direction)


def _finish(
    out: dict[str, np.ndarray],
    n: int,
    ls: FloatArray,
    off: FloatArray,
    mirror: bool,
    noise: float,
    seed: int | np.random.Generator | None,
    on_start: np.ndarray,
    scales: FloatArray,
    direction: str,
) -> WrapBatch:
    b = len(ls)
    joints, lap, phi, placed = out["joints"], out["lap"], out["phi"], out["placed"]
    s0 = out["start"]
    contact = out["contact"]
    # A joint that lands exactly on the start point at the end of the approach.
    at_start = (lap == -1) & (np.hypot(*np.moveaxis(joints - s0[:, None], -1, 0))
                              < 1e-9 * scales[:, None])  # fmt: skip
    contact |= at_start & on_start[:, None]
    lap[at_start] = 0
    angles = np.diff(phi, axis=1)
    heading = phi[:, 0].copy()
    offset_links = np.where(off > 0, np.ceil(off / ls - 1e-9), 0).astype(np.int64)
    rows = np.arange(b)
    last = phi[rows, placed]
    # Laps count from the direction of the support at the start point: the chord
    # arriving there (closed arrays sum to 2 pi) or, after an approach along the
    # inward normal, the edge direction (a quarter turn right of the approach).
    ref = np.where(off > 0, phi[:, 0] - out["turn"] - np.pi / 2, out["phi_v"])
    laps = np.where(placed >= offset_links, (last - ref) / (2 * np.pi), 0.0)
    has = (lap >= 1).any(axis=1)
    first = np.argmax(lap >= 1, axis=1)
    d_first = np.hypot(*(joints[rows, first] - s0).T)
    prev = np.maximum(first - 1, 0)
    d_prev = np.where(lap[rows, prev] == 0, np.hypot(*(joints[rows, prev] - s0).T), np.inf)
    d_last = np.hypot(*(joints[rows, placed] - s0).T)
    closed_now = (placed > offset_links) & (d_last <= 1e-9 * scales)
    gap = np.where(has, np.minimum(d_first, d_prev), np.where(closed_now, d_last, np.nan))
    if mirror:
        joints[..., 0] *= -1
        s0 = s0 * [-1.0, 1.0]
        angles = -angles
        heading = np.pi - heading
    heading = np.pi - np.mod(np.pi - heading, 2 * np.pi)
    if noise > 0:
        try:
            rng = np.random.default_rng(seed)
        except (TypeError, ValueError):
            raise InputError(
                f"random_state must be None, an integer >= 0 or a numpy Generator, got {seed!r}"
            ) from None
        angles = angles + rng.normal(0.0, noise, angles.shape)
    batch = WrapBatch(
        angles=angles,
        joints=joints,
        contact=contact,
        lap=lap,
        laps=laps,
        offset_links=offset_links,
        heading=heading,
        complete=out["status"] == 0,  # _kernel.STATUS_COMPLETE
        n_placed=placed,
        closure_gap=gap,
        start_point=s0,
    )
    object.__setattr__(batch, "_link_length", ls)
    object.__setattr__(batch, "_direction", direction)
    return batch


def wrap(
    outline: ArrayLike,
    n_links: int,
    link_length: float,
    start: float = 0.0,
    direction: str = "ccw",
    offset: float = 0.0,
    mode: str = "taut",
    noise: float = 0.0,
    random_state: int | np.random.Generator | None = None,
    thickness: float = 0.0,
    seed: Any = UNSET,
) -> Wrap:
    """Joint angles of a chain of ``n_links`` equal links wrapped around an object.

    Parameters
    ----------
    outline : array_like of shape (n_points, 2)
        Closed simple outline (any orientation; see :mod:`tentaclass.shapes`).
    n_links : int
        Number of links, at least 1.
    link_length : float
        Length ``l`` of every link, ``0 < l <=`` the object's diameter.
    start : float, default=0.0
        Start point as a fraction of the perimeter in [0, 1), measured
        counter-clockwise from the outline's first point.
    direction : {"ccw", "cw"}, default="ccw"
        Walking direction. ``"cw"`` is the mirror image: its angles sum to
        ``-2*pi`` per lap.
    offset : float, default=0.0
        Distance of the base from the support (the thesis's epsilon), along the
        inward normal at the start point (turned away from the object where
        that line would pass through it): the first ``ceil(offset / l)`` links
        reach straight towards the start point, then the chain wraps.
    mode : {"taut", "hug"}, default="taut"
        Support of the first lap: ``"taut"`` the convex hull (a chain pulled
        tight), ``"hug"`` the outline itself, into every concavity a link can
        enter.
    noise : float, default=0.0
        Standard deviation (radians) of Gaussian joint-sensor noise added to the
        angles; ``joints`` stay noise-free.
    random_state : int or numpy.random.Generator, optional
        Makes the noise reproducible.
    thickness : float, default=0.0
        Chain thickness: lap ``k`` lies on the support offset outward by
        ``k * thickness`` (shapely buffer, round joins). 0 (or below ``1e-9``
        of the object's extent): later laps lie on the first lap's support.
    seed : int or numpy.random.Generator, optional
        Deprecated alias of ``random_state``.

    Returns
    -------
    Wrap

    Raises
    ------
    InputError
        Bad outline (NaN, fewer than 3 distinct points, zero area,
        self-intersection), ``link_length`` <= 0 or longer than the object's
        diameter, ``n_links`` < 1 or above :data:`MAX_LINKS`, ``start`` outside
        [0, 1), unknown mode, an ``offset`` longer than the chain, a
        ``thickness`` larger than the object.

    Notes
    -----
    **Contact model.** The joints are the chain's contact points; each link is a
    rigid straight bar. From the current joint the next joint is the first point
    further along the support (in the walking direction) at distance ``l``
    (circle-segment intersection searched forward). Between two contacts a link
    may cut the stretch of outline it spans (the detail finer than a link that
    the chain cannot sense, thesis section 4.5), but it never *crosses* the
    object: it does not pass from outside to inside through the outline
    between its joints. Where the next chord would, the link instead rests on
    the vertex it passes that lies furthest clockwise seen from its joint (for
    a ccw walk: the tangent point), and its tip stays in the air beyond that
    corner; the following link reaches down from there. Every link is placed:
    where the support offers no next joint (a link longer than the space
    around it), the link folds in towards the object, turning clockwise from
    nearly a half turn left of the previous link until it meets the object or
    an earlier link (the first link, which has no earlier link to fold onto,
    turns on away from the object to the first place it rests free), and the
    walk goes on from the support point nearest its tip. Later laps lie on
    the support offset by ``thickness`` per lap, joined to the previous lap
    at the start point. Where the straight approach
    would pass through another part of the object, it turns (by up to 86
    degrees either way) to the nearest direction that clears it.

    **Angles.** ``angles[i]`` is the turn at joint ``i`` from link ``i`` to link
    ``i + 1`` (``angles[0]`` from ``heading``), so that
    ``angles_to_points(w.angles, l, base=w.joints[0], heading=w.heading)``
    rebuilds ``w.joints``. With an offset, ``heading`` is the approach
    direction (``angles[0] = 0``). Without one, ``heading`` is the direction of
    the chord arriving at the start point from one link length behind it:
    for a closed single wrap that is the last link, so ``angles[0]`` is the
    turn at the first joint relative to the last link and the angles are the
    thesis's closed arrays (they sum to ``2*pi``).

    **Thin parts.** A link's direction is only known modulo ``2*pi``; each
    heading is taken on the branch closest to the support's tangent direction
    between the link's two ends. Turns around a part thinner than a link are
    therefore close to ``+pi`` for a ccw walk (never ``-pi``), and the angles
    of every full lap sum to exactly ``2*pi``.

    Examples
    --------
    >>> from tentaclass.shapes import square
    >>> w = wrap(square(4), 16, 1.0)
    >>> np.round(w.angles / (np.pi / 2), 6) + 0.0
    array([1., 0., 0., 0., 1., 0., 0., 0., 1., 0., 0., 0., 1., 0., 0., 0.])
    >>> w.laps, w.complete
    (1.0, True)
    >>> wrap(square(4), 8, 1.0, offset=2.0).offset_links
    2
    """
    for name, value in (("link_length", link_length), ("start", start), ("offset", offset)):
        check_one_value(value, name, " (wrap is one wrap by a chain of equal links; wrap_many "
                        "takes one value per wrap)")  # fmt: skip
    batch = wrap_many(
        outline, n_links, link_length, start, direction=direction, offset=offset, mode=mode,
        noise=noise, random_state=renamed("random_state", random_state, "seed", seed),
        thickness=thickness,
    )  # fmt: skip
    return batch[0]
