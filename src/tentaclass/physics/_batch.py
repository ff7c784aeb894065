"""Many physical grasps at once, in worker processes."""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import Any, cast

import numpy as np

from .._typing import ArrayLike
from ..errors import InputError
from ..manipulator import PlanarChain
from ._grasp import PhysicalGrasp, grasp
from ._quasi import quasi_static_grasp

__all__ = ["grasp_many"]

#: What ``grasp_many`` can run.
METHODS = ("mujoco", "quasi-static")


def grasp_many(
    outlines: ArrayLike | Sequence[ArrayLike],
    chain: PlanarChain | Sequence[PlanarChain],
    starts: ArrayLike = 0.0,
    *,
    offset: ArrayLike = 0.0,
    direction: str | Sequence[str] = "ccw",
    method: str = "mujoco",
    n_jobs: int | None = None,
    **kwargs: Any,
) -> list[PhysicalGrasp]:
    """Physical grasps of many objects or from many start points.

    Parameters
    ----------
    outlines : array_like of shape (n_points, 2), or a sequence of them
        One outline (the batch runs over ``starts`` and ``offset``) or one per
        grasp.
    chain : PlanarChain or sequence of PlanarChain
        One chain for every grasp, or one per grasp.
    starts, offset : float or array_like of shape (n_grasps,)
        Broadcast against the outlines.
    direction : str or sequence of str, default="ccw"
        One direction, or one per grasp.
    method : {"mujoco", "quasi-static"}, default="mujoco"
        :func:`grasp` (simulated in MuJoCo) or :func:`quasi_static_grasp`
        (its quasi-static limit, geometry only: for training data).
    n_jobs : int, optional
        Worker processes, as in joblib: -1 all cores, None one (unless a
        ``joblib.parallel_config`` block says otherwise). Results do not
        depend on it.
    **kwargs
        Passed to :func:`grasp` (or :func:`quasi_static_grasp`).

    Returns
    -------
    grasps : list of PhysicalGrasp

    Examples
    --------
    >>> from tentaclass import PlanarChain
    >>> from tentaclass.shapes import circle
    >>> gs = grasp_many(circle(1.0), PlanarChain([0.39] * 16), starts=[0.0, 0.5])
    >>> [g.complete for g in gs]
    [True, True]
    >>> qs = grasp_many(circle(1.0), PlanarChain([0.39] * 16), [0.0, 0.5], method="quasi-static")
    >>> [round(g.laps, 1) for g in qs]
    [1.0, 1.0]
    """
    if method not in METHODS:
        raise InputError(f"method must be one of {', '.join(map(repr, METHODS))}, got {method!r}")
    fn = grasp if method == "mujoco" else quasi_static_grasp
    single = isinstance(outlines, np.ndarray) and outlines.ndim == 2
    if not single and isinstance(outlines, Sequence) and outlines:
        single = np.ndim(outlines[0]) == 1
    st = np.atleast_1d(np.asarray(starts, dtype=float))
    off = np.atleast_1d(np.asarray(offset, dtype=float))
    if st.ndim != 1 or off.ndim != 1:
        raise InputError("starts and offset must be scalars or 1-D arrays")
    # numpy's ArrayLike cannot say "a sequence of array_likes": the checks above
    # tell one outline from many, the casts record their outcome
    rows: list[ArrayLike]
    if single:
        b = int(np.broadcast_shapes(st.shape, off.shape)[0])
        rows = [cast(ArrayLike, outlines)] * b
    else:
        rows = list(cast(Iterable[ArrayLike], outlines))
        b = len(rows)
    try:
        st, off = np.broadcast_to(st, (b,)), np.broadcast_to(off, (b,))
    except ValueError:
        raise InputError(
            f"starts ({st.size}) and offset ({off.size}) must have one value or one per grasp ({b})"
        ) from None
    dirs = [direction] * b if isinstance(direction, str) else list(direction)
    if len(dirs) != b:
        raise InputError(f"direction has {len(dirs)} entries for {b} grasps")
    if isinstance(chain, PlanarChain):
        chains = [chain] * b
    elif isinstance(chain, Sequence) and not isinstance(chain, str):
        chains = list(chain)
        bad = next((c for c in chains if not isinstance(c, PlanarChain)), None)
        if bad is not None:
            raise InputError(f"chain must hold PlanarChain objects, got {type(bad).__name__}")
    else:
        raise InputError(
            f"chain must be a PlanarChain or a sequence of them, got {type(chain).__name__}"
        )
    if len(chains) != b:
        raise InputError(f"chain has {len(chains)} entries for {b} grasps")
    jobs = [(rows[i], chains[i], float(st[i]), float(off[i]), dirs[i]) for i in range(b)]
    if n_jobs in (None, 1):
        return [fn(o, c, start=t, offset=f, direction=d, **kwargs) for o, c, t, f, d in jobs]
    from joblib import Parallel, delayed

    return Parallel(n_jobs=n_jobs)(
        delayed(fn)(o, c, start=t, offset=f, direction=d, **kwargs) for o, c, t, f, d in jobs
    )
