"""Dask support in one place: lazy block-wise calls, per-block seeds, clients, file jobs.

Nothing here imports dask unless the caller already has: an argument is a dask
collection only if ``dask`` is in :data:`sys.modules` and
``dask.is_dask_collection`` says so. The hooks at the public boundaries are
one line each:

- :func:`blockwise` decorates a function of arrays of shape ``(..., n)``
  (the descriptors): a dask array in gives a dask array out, computed block
  by block with the function itself;
- :class:`DaskMixin` does the same for every estimator's ``predict``,
  ``predict_proba``, ``predict_log_proba``, ``transform`` and
  ``decision_function``;
- :func:`wrap_blocks` runs :func:`tentaclass.wrap_many` once per chunk of its
  parameter arrays (or per partition of a bag of outlines);
- :func:`read_parquet_rows` reads Parquet files as a dask array, one block
  per few row groups, with pyarrow alone in the tasks (no pandas, no dask.dataframe);
- :func:`scheduler` opens a client (a ``LocalCluster`` or a running
  scheduler) for the command line; :func:`map_files` runs one job per input
  file on it, each writing its output under a temporary name that is renamed
  only when the file is complete.

Nothing calls ``compute()``: the caller decides when and where to compute.
"""

from __future__ import annotations

import contextlib
import functools
import itertools
import math
import os
import re
import sys
import tempfile
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ._validation import as_path, check_seed
from .errors import InputError, TentaclassError

__all__ = [
    "DaskMixin",
    "SchedulerError",
    "atomic_output",
    "block_seeds",
    "blockwise",
    "is_dask_collection",
    "local_cluster",
    "map_files",
    "read_parquet_rows",
    "scheduler",
    "wrap_blocks",
]

#: Methods of an estimator that take ``X`` of shape (n_samples, n_features) row by row.
ROW_METHODS = ("predict", "predict_proba", "predict_log_proba", "transform", "decision_function")

#: Bytes of a block's rows handed to a row-wise function at a time (its first axis sliced):
#: 8 192 arrays of 16 joints. A classifier's temporaries for 65 536 arrays (about
#: 27 MiB) spill out of the core's cache to memory, whose bandwidth the worker
#: processes share: ``predict_proba`` in slices of 8 192 takes a fifth less CPU time.
SLICE_BYTES = 2**20
#: Rows per slice, at least, however wide the rows.
SLICE_MIN_ROWS = 256

#: Rows per block of :func:`read_parquet_rows`, at most, where row groups are joined.
#: 262 144 arrays of 16 joints are 32 MiB; four of the 65 536-row groups.
BLOCK_ROWS = 2**18

#: Seconds to wait for a scheduler address to answer.
CONNECT_TIMEOUT = 10.0

#: glibc malloc settings for local worker processes (set before they start). Dask's
#: default (``MALLOC_TRIM_THRESHOLD_=65536``) also fixes the mmap threshold at
#: 128 KiB, so every array a task allocates above that is mapped afresh and its
#: pages faulted in one by one: about a third more CPU time in ``predict`` on
#: 65 536 arrays. With both at 32 MiB, a block's arrays reuse the heap, and at
#: most 32 MiB of free heap is kept.
WORKER_MALLOC = {"MALLOC_TRIM_THRESHOLD_": 32 * 2**20, "MALLOC_MMAP_THRESHOLD_": 32 * 2**20}

#: Dask settings of a local cluster: fewer wake-ups of the scheduler, nannies and workers.
#: Dask's defaults suit a long-lived cluster watched from its dashboard: every worker
#: samples its own stack every 10 ms (the profiler), every event loop checks
#: itself every 20 ms, each nanny reads its worker's memory every 100 ms, the
#: scheduler's system monitor runs every 0.5 s and work stealing every second. On
#: two cores that costs 26 ms of CPU per second in the driver (client, scheduler,
#: nannies) and 20 ms per second in each idle worker of a 2-worker cluster, taken
#: from the tasks; with these settings 5 and 3 ms. The tasks of this package are uniform blocks,
#: queued on the scheduler (``worker-saturation``) and handed out one by one, so
#: stealing has nothing to balance.
LOCAL_CONFIG = {
    "distributed.worker.profile.enabled": False,
    "distributed.admin.tick.interval": "1s",
    "distributed.admin.system-monitor.interval": "5s",
    "distributed.worker.memory.monitor-interval": "500ms",
    "distributed.scheduler.work-stealing": False,
}

_ADDRESS = re.compile(r"^(tcp|tls|ucx|inproc|ws|wss)://[^\s/]+(:\d+)?/?$")


class SchedulerError(TentaclassError):
    """The Dask scheduler could not be reached, or the cluster lost the job."""


def is_dask_collection(x: object) -> bool:
    """True if ``x`` is a dask collection; never imports dask itself.

    Examples
    --------
    >>> is_dask_collection(np.zeros(3))
    False
    """
    dask = sys.modules.get("dask")
    return dask is not None and bool(dask.is_dask_collection(x))


def _as_dask_array(x: Any) -> Any:
    import dask.array as da

    if hasattr(x, "to_dask_array"):  # a dask DataFrame: row counts stay unknown
        x = x.to_dask_array()
    return da.asarray(x)


class _Blocks:
    """The per-block call: the function on one block (:func:`in_slices`), or empty outputs."""

    def __init__(self, func: Callable, metas: tuple[np.ndarray, ...], single: bool):
        self.func, self.metas, self.single = func, metas, single

    def __call__(self, block: np.ndarray) -> Any:
        if block.size == 0:
            out = tuple(np.empty(block.shape[:-1] + m.shape[1:], m.dtype) for m in self.metas)
        else:
            out = in_slices(self.func, block)
        return out[0] if self.single and isinstance(out, tuple) else out


def in_slices(func: Callable[[np.ndarray], Any], block: np.ndarray) -> Any:
    """``func(block)`` computed on slices of ``block``'s first axis, the outputs joined.

    Slices of about :data:`SLICE_BYTES` (at least :data:`SLICE_MIN_ROWS` rows):
    the function's temporaries for a slice stay in the core's cache and are
    held for one slice at a time. ``func`` must act on each row independently
    and return an array or a tuple of arrays with rows first.

    Examples
    --------
    >>> x = np.arange(2 * 10**5, dtype=float).reshape(-1, 2)
    >>> bool((in_slices(lambda b: b.sum(axis=1), x) == x.sum(axis=1)).all())
    True
    """
    if block.ndim < 2:
        return func(block)
    step = max(SLICE_MIN_ROWS, SLICE_BYTES // max(block[:1].nbytes, 1))
    parts = [func(block[i : i + step]) for i in range(0, len(block), step)]
    if len(parts) == 1:
        return parts[0]
    if isinstance(parts[0], tuple):
        return tuple(np.concatenate(p) for p in zip(*parts, strict=True))
    return np.concatenate(parts)


def apply_rows(func: Callable[[np.ndarray], Any], x: Any, name: str = "rows") -> Any:
    """``func`` applied lazily to each block of ``x`` along its leading axes.

    ``func`` maps an array of shape ``(..., n)`` to one array, or a tuple of
    arrays, of shape ``(..., *core)``. It is called once on one row (the turns of a
    regular polygon) first: that checks the arguments at once (errors are raised here, not at
    compute time) and gives each output's core shape and dtype, from which the
    output ``chunks`` and ``meta`` follow. The last axis of ``x`` is brought
    into one chunk; the leading axes keep their chunks.

    Parameters
    ----------
    func : callable
        Works on NumPy arrays; must act on every row independently.
    x : dask array or dask DataFrame
        Rows of ``n`` values (a DataFrame's columns become the last axis).
    name : str, default "rows"
        Prefix of the tasks' keys (shown on the dashboard).

    Returns
    -------
    dask array, or a tuple of them
        Lazy: nothing has been computed.

    Examples
    --------
    >>> import dask.array as da
    >>> x = da.ones((10, 4), chunks=(3, 2))
    >>> y = apply_rows(lambda b: b.sum(axis=-1, keepdims=True), x)
    >>> y.chunks
    ((3, 3, 3, 1), (1,))
    >>> y.sum().compute()
    np.float64(40.0)
    """
    import dask.array as da

    x = _as_dask_array(x)
    if x.ndim == 0:
        raise InputError("a dask array of rows needs at least one axis, got a scalar")
    n = x.shape[-1]
    if math.isnan(n):
        raise InputError("the last axis of a dask array of rows must have a known size")
    x = x.rechunk({x.ndim - 1: -1})
    # one row of a closed regular polygon: valid input for every angle function
    probe = func(np.full((1, n), 2 * np.pi / max(n, 1)).astype(x.dtype, copy=False))
    single = not isinstance(probe, tuple)
    outs = (probe,) if single else probe
    sizes: dict[str, int] = {}
    cores: list[str] = []
    for i, out in enumerate(outs):
        names = [f"o{i}_{j}" for j in range(out.ndim - 1)]
        sizes.update(zip(names, out.shape[1:], strict=True))
        cores.append("(" + ",".join(names) + ")")
    lead = (0,) * (x.ndim - 1)
    metas = tuple(np.empty(lead + out.shape[1:], out.dtype) for out in outs)
    blocks = _Blocks(func, tuple(np.empty((0, *o.shape[1:]), o.dtype) for o in outs), single)
    groups = _row_groups(x)
    if single and groups is not None:
        return _read_then(groups, blocks, x, probe, name)
    if single:
        # one task per block: the rows' axes keep their chunks, the last one
        # becomes the output's core axes (apply_gufunc would add two more tasks
        # per block, to take the output apart and to order its axes)
        rows = "".join(chr(ord("a") + i) for i in range(x.ndim - 1))
        core = "".join(chr(ord("A") + i) for i in range(probe.ndim - 1))
        return da.blockwise(
            blocks, rows + core, x, rows + "z",
            new_axes=dict(zip(core, probe.shape[1:], strict=True)),
            concatenate=True, dtype=probe.dtype, meta=metas[0], token=name,
        )  # fmt: skip
    return da.apply_gufunc(blocks, "(n)->" + ",".join(cores), x, output_sizes=sizes, meta=metas)


class _ReadThen:
    """One task per block: read its row groups one at a time, apply the per-block call to each.

    Only one row group's values and temporaries are held at a time, however
    many row groups the block joins; the outputs are concatenated.
    """

    def __init__(self, blocks: _Blocks, columns: list[str], dtype: np.dtype):
        self.blocks, self.columns, self.dtype = blocks, columns, dtype

    def __call__(self, where: tuple[str, tuple[int, ...]]) -> Any:
        path, groups = where
        outs = [self.blocks(_read_row_group(path, g, self.columns, self.dtype)) for g in groups]
        return outs[0] if len(outs) == 1 else np.concatenate(outs)


def _row_groups(x: Any) -> Any:
    """The row groups behind ``x`` if it is exactly :func:`read_parquet_rows`'s array, else None."""
    layers = x.__dask_graph__().layers
    deps = getattr(layers.get(x.name), "io_deps", {}) if len(layers) == 1 else {}
    found = [d for d in deps.values() if isinstance(d, _row_groups_class())]
    return found[0] if len(found) == 1 else None


def _read_then(groups: Any, blocks: _Blocks, x: Any, probe: np.ndarray, name: str) -> Any:
    """``blocks`` on each block of row groups of ``x``, read in the same task (no task per read)."""
    import dask.array as da
    from dask.base import tokenize
    from dask.blockwise import BlockwiseDepDict
    from dask.blockwise import blockwise as core_blockwise
    from dask.highlevelgraph import HighLevelGraph

    key = f"{name}-{tokenize(x.name, blocks)}"
    where = BlockwiseDepDict({(i,): spec for (i, _), spec in groups.mapping.items()},
                             numblocks=(len(groups.mapping),))  # fmt: skip
    core = "".join(chr(ord("A") + i) for i in range(probe.ndim - 1))
    layer = core_blockwise(
        _ReadThen(blocks, groups.columns, groups.dtype), key, "a" + core, where, "a",
        numblocks={}, new_axes=dict(zip(core, probe.shape[1:], strict=True)),
        _data_producer=True,
    )  # fmt: skip
    chunks = (x.chunks[0], *((c,) for c in probe.shape[1:]))
    meta = np.empty((0,) * probe.ndim, probe.dtype)
    graph = HighLevelGraph.from_collections(key, layer, dependencies=[])
    return da.Array(graph, key, chunks, meta=meta)


def blockwise(func: Callable) -> Callable:
    """Decorator: ``func(q, ...)`` on a dask array ``q`` runs lazily block by block.

    For NumPy input (or anything else that is not a dask collection) the
    function runs as before.
    """

    @functools.wraps(func)
    def dispatch(q: Any, *args: Any, **kwargs: Any) -> Any:
        if is_dask_collection(q):
            # ``dispatch`` is the module attribute, so workers import it by name
            call = functools.partial(_call_with_rows_first, dispatch, args, kwargs)
            return apply_rows(call, q, name=func.__name__)
        return func(q, *args, **kwargs)

    return dispatch


def _call_with_rows_first(func: Callable, args: tuple, kwargs: dict, block: np.ndarray) -> Any:
    return func(block, *args, **kwargs)


def _call_method(estimator: Any, name: str, args: tuple, kwargs: dict, block: np.ndarray) -> Any:
    return getattr(estimator, name)(block, *args, **kwargs)


def _lazy_method(name: str, method: Callable) -> Callable:
    @functools.wraps(method)
    def wrapper(self: Any, X: Any, *args: Any, **kwargs: Any) -> Any:
        if is_dask_collection(X):
            call = functools.partial(_call_method, self, name, args, kwargs)
            return apply_rows(call, X, name=f"{type(self).__name__}.{name}")
        return method(self, X, *args, **kwargs)

    wrapper._dask_rows = True  # type: ignore[attr-defined]
    return wrapper


class DaskMixin:
    """Estimators whose row-wise methods take dask arrays and return dask arrays.

    Every method named in :data:`ROW_METHODS` that a subclass defines or
    inherits as a plain function is wrapped: a dask array (or DataFrame) ``X``
    gives a lazy dask array computed block of rows by block of rows with the
    fitted estimator, which is checked at once on one row (a fitted
    estimator, the right number of features). Other input goes to the method
    unchanged.
    """

    def __init_subclass__(cls, **kwargs: Any):
        super().__init_subclass__(**kwargs)
        import inspect

        for name in ROW_METHODS:
            method = inspect.getattr_static(cls, name, None)
            if inspect.isfunction(method) and not getattr(method, "_dask_rows", False):
                setattr(cls, name, _lazy_method(name, method))


# -- seeds ---------------------------------------------------------------------------------------


def block_seeds(
    seed: int | np.random.Generator | None, n_blocks: int
) -> list[np.random.SeedSequence]:
    """One independent seed per block, from one seed: the same whoever runs the blocks.

    Parameters
    ----------
    seed : int, numpy Generator or None
        A Generator contributes one draw; None takes fresh entropy.
    n_blocks : int

    Returns
    -------
    list of numpy.random.SeedSequence

    Examples
    --------
    >>> a = [np.random.default_rng(s).random() for s in block_seeds(7, 3)]
    >>> b = [np.random.default_rng(s).random() for s in block_seeds(7, 3)]
    >>> a == b, len(set(a))
    (True, 3)
    """
    seed = check_seed(seed)
    if isinstance(seed, np.random.Generator):
        seed = int(seed.integers(2**63))
    return np.random.SeedSequence(seed).spawn(n_blocks)


# -- wraps ---------------------------------------------------------------------------------------

_WRAP_FIELDS = {  # name: (core shape given n_links, dtype)
    "angles": (lambda n: (n,), np.float64),
    "joints": (lambda n: (n + 1, 2), np.float64),
    "contact": (lambda n: (n + 1,), np.bool_),
    "lap": (lambda n: (n + 1,), np.int64),
    "laps": (lambda n: (), np.float64),
    "offset_links": (lambda n: (), np.int64),
    "heading": (lambda n: (), np.float64),
    "complete": (lambda n: (), np.bool_),
    "n_placed": (lambda n: (), np.int64),
    "closure_gap": (lambda n: (), np.float64),
    "start_point": (lambda n: (2,), np.float64),
}


def wants_blocks(outlines: object, *params: object) -> bool:
    """True if :func:`tentaclass.wrap_many` got a dask array or bag to run block by block."""
    return any(is_dask_collection(p) for p in (outlines, *params))


def _wrap_block(wrap_many, outlines, n_links, kwargs, seed, *params):
    """One block of wraps: NumPy parameters in, a dict of NumPy fields out."""
    if isinstance(outlines, list) and len(outlines) == 0:
        return {k: np.empty((0, *core(n_links)), dt) for k, (core, dt) in _WRAP_FIELDS.items()}
    names = ("link_length", "starts", "offset")
    given = {k: np.asarray(v) for k, v in zip(names, params, strict=True)}
    batch = wrap_many(outlines, n_links, **given, **kwargs, random_state=seed)
    return {k: getattr(batch, k) for k in _WRAP_FIELDS}


def wrap_blocks(wrap_many: Callable, outlines: Any, n_links: int, link_length: Any,
                starts: Any, offset: Any, seed: Any, **kwargs: Any) -> Any:  # fmt: skip
    """:func:`tentaclass.wrap_many` chunk by chunk: a ``WrapBatch`` of dask arrays.

    The blocks are the chunks of the dask parameter arrays (``link_length``,
    ``starts``, ``offset``: rechunked to the chunks of the first dask one), or
    the partitions of a dask bag of outlines. A list of outlines is split
    along with the parameters. Each block's noise comes from its own
    :func:`block_seeds` seed, so the result depends on the seed and the
    chunks, never on the workers.
    """
    import operator

    import dask
    import dask.array as da
    from dask.base import tokenize
    from dask.highlevelgraph import HighLevelGraph

    n = int(n_links)
    params = [link_length, starts, offset]
    if is_dask_collection(outlines):
        if any(is_dask_collection(p) or np.ndim(p) > 0 for p in params):
            raise InputError(
                "with a dask bag of outlines, link_length, starts and offset must be scalars"
            )
        parts = outlines.to_delayed()
        blocks = [(part, params, None) for part in parts]
    else:
        arrays = [p for p in params if is_dask_collection(p)]
        for p in arrays:
            if p.ndim != 1:
                raise InputError(f"a dask parameter array must be 1-D, got shape {p.shape}")
            if any(math.isnan(c) for c in p.chunks[0]):
                raise InputError(
                    "a dask parameter array must have known chunk sizes, got unknown ones "
                    "(NaN, e.g. after boolean indexing): call .compute_chunk_sizes() first"
                )
        chunks, size = arrays[0].chunks[0], arrays[0].shape[0]
        many = not (isinstance(outlines, np.ndarray) and outlines.ndim == 2) and not (
            isinstance(outlines, Sequence) and len(outlines) > 0 and np.ndim(outlines[0]) == 1
        )
        if many and len(outlines) != size:
            raise InputError(
                f"outlines: {len(outlines)} outlines for parameter arrays of {size} wraps"
            )
        bounds = np.cumsum((0, *chunks))
        cut = [
            p.rechunk((chunks,)).to_delayed().ravel().tolist()
            if is_dask_collection(p)
            else [np.broadcast_to(p, (size,))[a:b] for a, b in itertools.pairwise(bounds)]
            for p in params
        ]
        blocks = []
        for i, (a, b) in enumerate(itertools.pairwise(bounds)):
            rows = list(outlines[a:b]) if many else outlines
            blocks.append((rows, [c[i] for c in cut], b - a))
    seeds = block_seeds(seed, len(blocks)) if kwargs.get("noise", 0) > 0 else [None] * len(blocks)
    run = dask.delayed(_wrap_block, pure=True)
    results = [run(wrap_many, rows, n, kwargs, s, *ps)
               for (rows, ps, _), s in zip(blocks, seeds, strict=True)]  # fmt: skip
    rows_per_block = tuple(np.nan if count is None else count for _, _, count in blocks)
    token = tokenize([r.key for r in results])
    fields: dict[str, Any] = {}
    for k, (core, dt) in _WRAP_FIELDS.items():
        # each field's block i is item k of block i's result: one small task per block,
        # built here without a delayed object (and its token) per field and block
        name = f"wrap-{k}-{token}"
        inner = (0,) * len(core(n))
        layer: dict[Any, Any] = {
            (name, i, *inner): (operator.getitem, r.key, k) for i, r in enumerate(results)
        }
        graph = HighLevelGraph.from_collections(name, layer, dependencies=results)
        chunks = (rows_per_block, *((c,) for c in core(n)))
        fields[k] = da.Array(graph, name, chunks, meta=np.empty((0,) * len(chunks), dt))
    from .wrapping import WrapBatch

    batch = WrapBatch(**fields)
    object.__setattr__(batch, "_link_length", link_length)
    object.__setattr__(batch, "_direction", kwargs.get("direction", "ccw"))
    return batch


def check_client(client: Any) -> None:
    """Refuse a ``client`` that is neither None nor a ``distributed.Client``.

    >>> check_client("tcp://10.0.0.1:8786")
    Traceback (most recent call last):
    ...
    tentaclass.errors.InputError: client must be a distributed.Client or None, got str \
(to use a scheduler at an address, pass distributed.Client('tcp://10.0.0.1:8786'))
    """
    if client is None or all(
        callable(getattr(client, name, None)) for name in ("submit", "gather", "scheduler_info")
    ):
        return
    hint = f" (to use a scheduler at an address, pass distributed.Client({client!r}))"
    raise InputError(
        f"client must be a distributed.Client or None, got {type(client).__name__}"
        + (hint if isinstance(client, str) else "")
    )


def split_rows(func: Callable, *args: Any, client: Any = None, **kwargs: Any) -> Any:
    """``func(*args, **kwargs)`` run on slices of rows on ``client``, outputs joined.

    The row count is ``len(args[0])``; every positional argument of that length
    (list or array) is sliced, the others are passed whole. ``func`` must act
    on each row independently and return an array or a tuple of arrays with
    rows first: then the result is identical with or without a client and for
    any number of workers. Without a client ``func`` runs once, here.
    """
    check_client(client)
    if client is None:
        return func(*args, **kwargs)
    n = len(args[0])
    n_workers = max(1, len(client.scheduler_info(n_workers=-1).get("workers", {})))
    step = max(1, math.ceil(n / (4 * n_workers)))

    def rowwise(a: Any) -> bool:
        if isinstance(a, np.ndarray):
            return a.ndim > 0 and len(a) == n
        return isinstance(a, list) and len(a) == n

    calls = [[a[i : i + step] if rowwise(a) else a for a in args] for i in range(0, n, step)]
    futures = [client.submit(func, *c, pure=False, **kwargs) for c in calls]
    parts = client.gather(futures)
    if isinstance(parts[0], tuple):
        return tuple(np.concatenate(p) for p in zip(*parts, strict=True))
    return np.concatenate(parts)


@contextlib.contextmanager
def on_client(client: Any) -> Iterator[Any]:
    """``client`` as the default Dask client and the joblib backend (no-op for None)."""
    check_client(client)
    if client is None:
        yield None
        return
    import joblib

    with client.as_current(), joblib.parallel_config(backend="dask"):
        yield client


# -- clients -------------------------------------------------------------------------------------


def _check_address(address: str) -> str:
    if address == "local" or _ADDRESS.match(address):
        return address
    raise InputError(
        f"scheduler must be 'local' or an address such as tcp://host:8786, got {address!r}"
    )


def local_cluster(n_workers: int | None = None) -> Any:
    """A ``LocalCluster`` of single-threaded worker processes, as ``--scheduler local`` starts.

    One worker per core by default (``n_workers``), no dashboard port fixed
    (``:0``), worker logs at ERROR only, glibc malloc in the workers set by
    :data:`WORKER_MALLOC` (through Dask's ``distributed.nanny.pre-spawn-environ``,
    so that it applies from the process's start, restarts included), and the
    periodic bookkeeping of :data:`LOCAL_CONFIG` (the nannies hand it to their
    workers, restarts included). Settings the caller has made in
    ``dask.config`` for any of these keys win.

    Returns
    -------
    distributed.LocalCluster
        Close it (or use it as a context manager) when done.
    """
    import logging

    import dask
    from dask.distributed import LocalCluster

    settings: dict[str, Any] = {
        f"distributed.nanny.pre-spawn-environ.{k}": v for k, v in WORKER_MALLOC.items()
    }
    settings.update(LOCAL_CONFIG)
    with dask.config.set(_unless_set(settings)):
        return LocalCluster(
            n_workers=n_workers or os.cpu_count() or 1,
            threads_per_worker=1,
            processes=True,
            dashboard_address=":0",
            silence_logs=logging.ERROR,
        )


def _unless_set(settings: dict[str, Any]) -> dict[str, Any]:
    """The ``settings`` whose keys the user's Dask configuration leaves at Dask's defaults."""
    import dask

    defaults: dict[str, Any] = {}
    for config in dask.config.defaults:
        dask.config.update(defaults, config, priority="new")
    missing = object()
    return {
        key: value
        for key, value in settings.items()
        if dask.config.get(key, missing) == dask.config.get(key, missing, config=defaults)
    }


@contextlib.contextmanager
def scheduler(
    address: str | None,
    *,
    timeout: float | None = None,
    n_workers: int | None = None,
    echo: Callable[[str], None] | None = None,
) -> Iterator[Any]:
    """A Dask client for ``address``, as the default client and joblib backend.

    Parameters
    ----------
    address : str or None
        ``None``: no client, work stays in this process (yields None).
        ``"local"``: start a ``LocalCluster`` of worker processes, one per core
        (``n_workers``), one thread each. Otherwise the address of a running
        scheduler, e.g. ``tcp://host:8786``.
    timeout : float, optional
        Seconds to wait for the scheduler to answer; default
        :data:`CONNECT_TIMEOUT`.
    n_workers : int, optional
        Workers of a local cluster; default the number of cores.
    echo : callable, optional
        Receives one line naming the dashboard address.

    Yields
    ------
    distributed.Client or None

    Raises
    ------
    SchedulerError
        The address does not answer within ``timeout`` seconds.
    """
    if address is None:
        yield None
        return
    _check_address(address)
    timeout = CONNECT_TIMEOUT if timeout is None else timeout
    from dask.distributed import Client

    cluster = None
    try:
        if address == "local":
            cluster = local_cluster(n_workers)
            client = Client(cluster)
        else:
            client = Client(address, timeout=f"{timeout}s")
    except (OSError, TimeoutError) as exc:
        if cluster is not None:
            cluster.close()
        raise SchedulerError(
            f"cannot reach the Dask scheduler at {address} within {timeout:g} s "
            f"({type(exc).__name__}); is it running and is the address right?"
        ) from None
    try:
        if echo is not None:
            n = len(client.scheduler_info(n_workers=-1).get("workers", {}))
            if client.scheduler is None:
                raise SchedulerError(f"the Dask client for {address} has no scheduler connection")
            where = client.scheduler.address
            echo(f"dask: {n} workers at {where}, dashboard {client.dashboard_link}")
        with on_client(client):
            yield client
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


# -- Parquet rows --------------------------------------------------------------------------------


def _read_row_group(
    path: str, group: int | Sequence[int], columns: list[str], dtype: np.dtype
) -> np.ndarray:
    """Row group ``group`` (or the row groups ``group``, joined) of ``path`` as an array."""
    import pyarrow.parquet as pq

    # one thread: a worker runs one task per core already, and pyarrow's own
    # threads would take the next worker's core
    read = pq.ParquetFile(path)
    if isinstance(group, int):
        table = read.read_row_group(group, columns=columns, use_threads=False)
    else:
        table = read.read_row_groups(list(group), columns=columns, use_threads=False)
    out = np.empty((table.num_rows, len(columns)), dtype)
    for j, column in enumerate(table.columns):
        lo = 0
        for chunk in column.chunks:
            out[lo : lo + len(chunk), j] = _chunk_values(chunk)
            lo += len(chunk)
    return out


@functools.cache
def _row_groups_class() -> type:
    from dask.blockwise import BlockwiseDepDict

    class RowGroups(BlockwiseDepDict):
        """(path, row groups) per block, with the columns and dtype they are read as."""

        def __init__(self, mapping: dict, columns: list[str], dtype: np.dtype):
            super().__init__(mapping, numblocks=(len(mapping), 1))
            self.columns, self.dtype = columns, dtype

    return RowGroups


def _read_block(
    where: tuple[str, tuple[int, ...]], columns: list[str], dtype: np.dtype
) -> np.ndarray:
    return _read_row_group(*where, columns, dtype)


def _chunk_values(chunk: Any) -> np.ndarray:
    """A pyarrow array of numbers as NumPy values (nulls as NaN), from its buffer.

    (``Array.to_numpy`` imports pandas, which a worker reading numbers does not need.)
    """
    import pyarrow as pa

    kinds = {"f": pa.types.is_floating, "i": pa.types.is_signed_integer,
             "u": pa.types.is_unsigned_integer}  # fmt: skip
    kind = next((k for k, test in kinds.items() if test(chunk.type)), None)
    if kind is None:
        return chunk.to_numpy(zero_copy_only=False)
    validity, data = chunk.buffers()[:2]
    end = chunk.offset + len(chunk)
    values = np.frombuffer(data, f"={kind}{chunk.type.bit_width // 8}", end)[chunk.offset :]
    if chunk.null_count:
        bits = np.unpackbits(np.frombuffer(validity, np.uint8), count=end, bitorder="little")
        values = values.astype(np.float64)
        values[bits[chunk.offset :] == 0] = np.nan
    return values


def read_parquet_rows(
    paths: str | os.PathLike | Sequence[str | os.PathLike],
    columns: Sequence[str] | None = None,
    dtype: Any = np.float64,
    block_rows: int | None = BLOCK_ROWS,
) -> Any:
    """Rows of Parquet files as a lazy dask array: one block per few row groups.

    Each block is read by its task with pyarrow alone (no pandas, no
    dask.dataframe), so a worker holds one block at a time: memory is
    bounded by the block size, not by the data. An estimator's row method
    (``predict``, ``transform``, ...) on this array reads and handles a
    block's row groups one at a time, in one task: then a worker holds one row
    group's values at a time. The row counts come from the files' footers, so
    the chunks are known (unlike a dask DataFrame's).

    Parameters
    ----------
    paths : path or sequence of paths
        Parquet files with the same columns.
    columns : sequence of str, optional
        The columns to read, in this order (default: all of the first file's).
    dtype : numpy dtype, default float64
        Dtype of the array.
    block_rows : int or None, default 262144
        Consecutive row groups of a file are joined into one block as long as
        it stays within this many rows (a larger row group is a block of its
        own). Fewer, larger blocks leave less to the scheduler per row;
        ``None`` makes one block per row group.

    Returns
    -------
    dask array of shape (n_rows, n_columns)
        Chunked by blocks of row groups along the rows, one chunk along the columns.

    Raises
    ------
    InputError
        If ``paths`` is empty, a file is not readable Parquet, or lacks a
        column, or ``block_rows`` is not a positive integer.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> import pyarrow as pa, pyarrow.parquet as pq
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "q.parquet"
    >>> pq.write_table(pa.table({"q0": np.arange(5.0), "q1": -np.arange(5.0)}), path,
    ...                row_group_size=2)
    >>> x = read_parquet_rows([path], block_rows=None)
    >>> x.chunks
    ((2, 2, 1), (2,))
    >>> read_parquet_rows([path], block_rows=4).chunks
    ((4, 1), (2,))
    >>> x[:, 1].sum().compute()
    np.float64(-10.0)
    """
    import dask.array as da
    import pyarrow as pa
    import pyarrow.parquet as pq
    from dask.base import tokenize
    from dask.blockwise import blockwise as core_blockwise
    from dask.highlevelgraph import HighLevelGraph

    if isinstance(paths, (str, os.PathLike)):
        paths = [paths]
    files = [os.fspath(as_path(p, "paths")) for p in paths]
    if not files:
        raise InputError("paths: no Parquet files given")
    dtype = np.dtype(dtype)
    if block_rows is not None and (
        isinstance(block_rows, bool)
        or not isinstance(block_rows, (int, np.integer))
        or block_rows < 1
    ):
        raise InputError(f"block_rows must be a positive integer or None, got {block_rows!r}")
    limit = math.inf if block_rows is None else int(block_rows)
    blocks: list[tuple[str, tuple[int, ...]]] = []
    sizes: list[int] = []
    stamps: list[tuple[int, int]] = []
    for path in files:
        try:
            meta = pq.read_metadata(path)
            stamp = os.stat(path)
        except (OSError, pa.ArrowException) as exc:
            raise InputError(f"paths: {path} is not a readable Parquet file ({exc})") from None
        names = meta.schema.to_arrow_schema().names
        if columns is None:
            columns = names
        missing = [c for c in columns if c not in names]
        if missing:
            raise InputError(f"paths: {path} has no column {missing[0]!r} (it has {names})")
        stamps.append((stamp.st_mtime_ns, stamp.st_size))
        joined: list[int] = []
        for group in range(meta.num_row_groups):
            rows = meta.row_group(group).num_rows
            if not rows:
                continue
            if joined and (block_rows is None or sizes[-1] + rows > limit):
                joined = []
            if joined:
                joined.append(group)
                sizes[-1] += rows
                blocks[-1] = (path, tuple(joined))
            else:
                joined = [group]
                blocks.append((path, (group,)))
                sizes.append(rows)
    columns = list(columns or [])
    if not blocks:
        return da.empty((0, len(columns)), dtype=dtype)
    name = "read-parquet-rows-" + tokenize(files, stamps, columns, dtype.str, blocks)
    # a Blockwise layer that names its row groups: element-wise work on it fuses
    # with the reads, and a row method (predict, transform, ...) reads each row
    # group in its own task (apply_rows finds the row groups here)
    where = _row_groups_class()({(i, 0): spec for i, spec in enumerate(blocks)}, columns, dtype)
    layer = core_blockwise(
        _read_block, name, "ij", where, "ij", columns, None, dtype, None,
        numblocks={}, _data_producer=True,
    )  # fmt: skip
    chunks = (tuple(sizes), (len(columns),))
    return da.Array(
        HighLevelGraph.from_collections(name, layer, dependencies=[]),
        name,
        chunks,
        meta=np.empty((0, len(columns)), dtype),
    )


# -- one job per file ----------------------------------------------------------------------------


def _umask() -> int:
    """The process's file-creation mask, read without changing it where the system allows."""
    with contextlib.suppress(OSError, ValueError, IndexError):
        with open("/proc/self/status") as fh:
            for line in fh:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


@contextlib.contextmanager
def atomic_output(path: str | os.PathLike, mode: str = "w") -> Iterator[Any]:
    """Write ``path`` under a temporary name in its folder; rename it only on success.

    A reader never sees a half-written file under the final name: if the
    writer fails (or its process dies), the temporary file is removed (or left
    behind as ``.<name>.*.part``), and ``path`` keeps its old content, if any.
    The file gets the permissions ``open(path, "w")`` would give it.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "a.txt"
    >>> with atomic_output(out) as fh:
    ...     _ = fh.write("done")
    >>> out.read_text()
    'done'
    """
    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".part", dir=path.parent)
    try:
        with os.fdopen(fd, mode) as fh:
            # the permissions open() would give (mkstemp's are the owner's alone)
            keep = path.stat().st_mode & 0o7777 if path.exists() else 0o666 & ~_umask()
            os.fchmod(fh.fileno(), keep)
            yield fh
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def map_files(
    job: Callable[..., Any], inputs: Sequence[Path], outputs: Sequence[Path], *args: Any,
    client: Any = None, progress: bool = True,
) -> list[Any]:  # fmt: skip
    """``job(input, output, *args)`` for each file pair, on ``client`` if given.

    Without a client the files run one after the other in this process. With
    one, each file is one task (the arguments are sent to every worker once);
    Dask's progress bar goes to stderr. A worker that dies has its task rerun
    on another worker (up to the scheduler's ``allowed-failures``); a job that
    fails ends the run with a :class:`SchedulerError` or the job's own error,
    after the other files' tasks are cancelled. Jobs write their outputs with
    :func:`atomic_output`, so no output file is ever left half written.

    Returns
    -------
    list
        Each job's return value, in input order.
    """
    check_client(client)
    if client is None:
        return [job(i, o, *args) for i, o in zip(inputs, outputs, strict=True)]
    from distributed import progress as dask_progress
    from distributed.scheduler import KilledWorker

    # a key of its own per call: a previous call's copy of the same value may still be
    # on its way out of the cluster as this call starts
    shared = [client.scatter(a, broadcast=True, hash=False) for a in args]
    futures = client.map(job, list(inputs), list(outputs), *[[s] * len(inputs) for s in shared],
                         pure=False)  # fmt: skip
    try:
        if progress:
            with contextlib.redirect_stdout(sys.stderr):
                dask_progress(futures, scheduler=client.scheduler.address)
                print(file=sys.stderr)
        return client.gather(futures)
    except KilledWorker as exc:
        raise SchedulerError(
            f"workers died running {exc.task!r} again and again ({exc.last_worker}); "
            "its output was not written, the other files' outputs are complete"
        ) from None
    finally:
        client.cancel(futures)
