"""One job per input file for ``classify --files`` and ``scan --files``.

Each job reads its file block by block (memory bounded by the block, not the
file), writes its output next to the others under a temporary name, and
renames it when the file is done (:func:`tentaclass._dask.atomic_output`); the
jobs run here or on a Dask cluster (:func:`tentaclass._dask.map_files`).
"""

from __future__ import annotations

import contextlib
import functools
import glob
import json
from collections import Counter
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np

from .._dask import atomic_output, in_slices
from .._lazy import import_extra
from .._validation import check_angle_range, check_total_turn
from ..io._deploy import predict_with_proba
from ..report import classification_table
from .options import class_count_key, make_folder, parse_angle_rows, read_angle_file

#: Arrays read, featurised and classified per step.
BLOCK_ROWS = 65536

ANGLE_SUFFIXES = (".parquet", ".npy", ".csv", ".txt")

#: Fewest joint angles of a wrap (a closed chain has at least three links).
MIN_JOINTS = 3


def expand(pattern: str, suffixes: tuple[str, ...] | None = None) -> list[Path]:
    """Files matching a glob pattern (``**`` recurses), sorted; an error if none."""
    paths = sorted(Path(p) for p in glob.glob(pattern, recursive=True) if Path(p).is_file())
    if suffixes is not None:
        paths = [p for p in paths if p.suffix.lower() in suffixes]
    if not paths:
        kinds = f" ({', '.join(suffixes)})" if suffixes else ""
        raise ValueError(f"no files{kinds} match {pattern!r}")
    stems = Counter(p.stem for p in paths)
    twice = sorted(s for s, c in stems.items() if c > 1)
    if twice:
        raise ValueError(f"files share the name {twice[0]!r} (without their suffix): "
                         "their outputs would overwrite each other")  # fmt: skip
    return paths


def output_paths(inputs: list[Path], out_dir: Path, suffix: str) -> list[Path]:
    """``out_dir/<stem><suffix>`` for each input; creates ``out_dir``."""
    make_folder(out_dir, "--out-dir")
    return [out_dir / f"{p.stem}{suffix}" for p in inputs]


def _parquet_file(path: Path) -> Any:
    """A Parquet file of one numeric column per joint angle (``pyarrow.parquet.ParquetFile``)."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    try:
        pf = pq.ParquetFile(path)
    except (pa.ArrowException, OSError) as exc:
        raise ValueError(f"{path}: not a readable Parquet file ({exc})") from None
    bad = [f.name for f in pf.schema_arrow if not pa.types.is_floating(f.type)
           and not pa.types.is_integer(f.type)]  # fmt: skip
    if bad:
        raise ValueError(f"{path}: column {bad[0]!r} is not numeric; expected one "
                         "numeric column per joint angle")  # fmt: skip
    return pf


def _npy_file(path: Path) -> np.ndarray:
    """A ``.npy`` file memory-mapped as (n_arrays, n_joints); a 1-D file is one array."""
    with open(path, "rb") as fh:
        if fh.read(6) != b"\x93NUMPY":
            raise ValueError(f"{path}: not a readable .npy file (no .npy header)")
    try:
        arr = np.load(path, mmap_mode="r", allow_pickle=False)
    except (ValueError, OSError) as exc:
        raise ValueError(f"{path}: not a readable .npy file ({exc})") from None
    if arr.ndim == 1:
        arr = arr.reshape(1, -1) if arr.size else arr.reshape(0, 0)
    if arr.ndim != 2 or not np.issubdtype(arr.dtype, np.number) or np.iscomplexobj(arr):
        raise ValueError(
            f"{path}: expected a 2-D array of real numbers, got {arr.dtype} {arr.shape}"
        )
    return arr


def chain_length(path: Path) -> int | None:
    """Angles per array of an angle file, from its header or first row; None without rows."""
    suffix = path.suffix.lower()
    if suffix == ".parquet":
        pf = _parquet_file(path)
        return len(pf.schema_arrow) if pf.metadata.num_rows else None
    if suffix == ".npy":
        arr = _npy_file(path)
        return arr.shape[1] if arr.shape[0] else None
    try:
        with open(path, encoding="utf-8-sig") as fh:
            return parse_angle_rows(fh, str(path), first=True).shape[1] or None
    except UnicodeDecodeError:
        raise ValueError(f"{path}: not a text file") from None


def angle_blocks(path: Path, rows: int | None = None) -> Iterator[np.ndarray]:
    """Joint-angle arrays of a Parquet, ``.npy`` or text/CSV file, ``rows`` at a time.

    Parquet: one numeric column per joint angle, read by record batches;
    ``.npy``: memory-mapped; text/CSV: read whole (see ``read_angle_file``).
    """
    rows = BLOCK_ROWS if rows is None else rows
    suffix = path.suffix.lower()
    if suffix == ".parquet":
        # one thread: one file per worker process, one worker per core
        for batch in _parquet_file(path).iter_batches(batch_size=rows, use_threads=False):
            yield np.column_stack([c.to_numpy(zero_copy_only=False) for c in batch.columns]
                                  ).astype(np.float64, copy=False)  # fmt: skip
    elif suffix == ".npy":
        arr = _npy_file(path)
        for lo in range(0, arr.shape[0], rows):
            yield np.asarray(arr[lo : lo + rows], dtype=np.float64)
    else:
        yield read_angle_file(path)


def classify_file(src: Path, dst: Path, models: dict[int, Any]) -> int:
    """Classify every array of ``src`` into ``dst`` (Parquet or CSV); returns the count.

    ``models`` maps a chain length to its model (see :func:`classify_files`);
    a file without arrays gets an empty table with the columns of the first.
    ``dst`` gets the columns of :func:`tentaclass.report.classification_table`
    (``index`` counting from 0 over the whole file) and appears only when the
    whole file is done.
    """
    import pyarrow as pa
    import pyarrow.csv as pcsv
    import pyarrow.parquet as pq

    n_joints = chain_length(src)
    model = next(iter(models.values())) if n_joints is None else models.get(n_joints)
    if model is None:  # a text file that changed since classify_files looked
        raise ValueError(f"{src}: arrays of {n_joints} joint angles, but the model expects "
                         f"{sorted(models)[0]}")  # fmt: skip
    done = 0
    writer = None
    with atomic_output(dst, "wb") as fh, contextlib.ExitStack() as stack:
        for X in angle_blocks(src) if n_joints is not None else ():
            _check_block(src, X, int(model.n_features_in_), done)
            labels, proba = in_slices(functools.partial(predict_with_proba, model), X)
            table = classification_table(labels, proba, model.classes_)
            table["index"] = table["index"] + done
            batch = pa.table(table)
            if writer is None:
                writer = (pq.ParquetWriter(fh, batch.schema) if dst.suffix == ".parquet"
                          else pcsv.CSVWriter(fh, batch.schema))  # fmt: skip
                stack.callback(writer.close)  # before the file closes, also on failure
            writer.write_table(batch)
            done += X.shape[0]
        if writer is None:  # no arrays: the columns alone, a valid empty table
            k = len(model.classes_)
            empty = pa.table(classification_table(np.zeros(0, str), np.zeros((0, k)),
                                                  model.classes_))  # fmt: skip
            if dst.suffix == ".parquet":
                pq.write_table(empty, fh)
            else:
                pcsv.write_csv(empty, fh)
    return done


def _check_block(src: Path, X: np.ndarray, n_joints: int | None, done: int) -> None:
    """Refuse a block of another chain length, NaN or angles too large to be radians."""
    if X.shape[1] != n_joints:
        raise ValueError(f"{src}: arrays of {X.shape[1]} joint angles, but the model "
                         f"expects {n_joints}")  # fmt: skip
    bad = ~np.isfinite(X).all(axis=1)
    if bad.any():
        raise ValueError(f"{src}: array {done + int(np.flatnonzero(bad)[0])} holds NaN or "
                         "infinite angles")  # fmt: skip
    check_angle_range(X, str(src), first=done)
    check_total_turn(X, str(src), first=done)


def scan_file(src: Path, dst: Path, model: Any, settings: dict) -> dict:
    """Scan one belt file into ``dst``, one JSON line per object; returns its summary."""
    from ..errors import TentaclassError
    from ..scanner import LineScanner
    from ..scanner.io import read_rows

    stats: Counter = Counter()
    scanner = None
    with open(src, "rb") as fh, atomic_output(dst) as out:
        for chunk in read_rows(fh, fmt=settings.get("fmt"), width=settings.get("width"),
                               chunk_rows=settings.get("chunk_rows", 1024),
                               dtype=settings.get("dtype")):  # fmt: skip
            if scanner is None:
                w = settings.get("width") or (chunk.shape[1] if isinstance(chunk, np.ndarray)
                                              else None)  # fmt: skip
                if w is None:
                    raise TentaclassError(f"{src}: raw input needs the row width (--width)")
                scanner = LineScanner(w, model, **settings.get("scanner", {}))
            _write_objects(scanner.feed(chunk), out, stats)
        if scanner is None:
            raise TentaclassError(f"{src}: empty stream, no rows found")
        _write_objects(scanner.close(), out, stats)
    return {
        "file": str(src), "rows": scanner.rows_seen, "ignored": scanner.n_ignored,
        "objects": stats["objects"], "accepted": stats["accepted"],
        "rejected": stats["objects"] - stats["accepted"],
        "classes": {k[6:]: v for k, v in sorted(stats.items()) if k.startswith("class:")},
    }  # fmt: skip


def _write_objects(objects: list, out: Any, stats: Counter) -> None:
    for obj in objects:
        out.write(json.dumps(obj.to_dict()) + "\n")
        stats["objects"] += 1
        stats["accepted"] += bool(obj.accept)
        stats[class_count_key(obj.label)] += 1


def classify_files(pattern: str, out_dir: Path, client: Any,
                   model: Any) -> list[tuple[Path, Path, int]]:  # fmt: skip
    """``classify --files``: every matching file -> ``out_dir/<stem>.labels.{parquet,csv}``.

    Every file's chain length is read first (a Parquet schema, a ``.npy``
    header, a text file's first row), and files whose length differs from
    ``model``'s are refused before any work starts. With ``model`` None each
    length gets the model ``classify`` uses without ``--model``: the bundled
    one, else the one-lap reference shapes, with a warning on stderr (once per
    length, from :func:`tentaclass.cli.classify.builtin_model`).
    Files without arrays give an empty table with the model's columns.
    """
    import_extra("pyarrow", "dask", "classify --files writes with pyarrow", error=ValueError)
    inputs = expand(pattern, ANGLE_SUFFIXES)
    lengths = [chain_length(p) for p in inputs]
    expects = None if model is None else int(model.n_features_in_)
    for path, k in zip(inputs, lengths, strict=True):
        if k is not None and expects is not None and k != expects:
            raise ValueError(f"{path}: arrays of {k} joint angles, but the model expects "
                             f"{expects}")  # fmt: skip
        if k is not None and k < MIN_JOINTS:
            raise ValueError(f"{path}: arrays of {k} joint angles; a wrap has at least "
                             f"{MIN_JOINTS}")  # fmt: skip
    if model is not None:
        models = {expects: model}
    else:
        from ..io import bundled_links
        from .classify import builtin_model

        found = sorted({k for k in lengths if k is not None}) or bundled_links()[:1]
        models = {k: builtin_model(k)[0] for k in found}
    outputs = [
        out_dir / f"{p.stem}.labels{'.parquet' if p.suffix.lower() == '.parquet' else '.csv'}"
        for p in inputs
    ]
    make_folder(out_dir, "--out-dir")
    from .._dask import map_files

    counts = map_files(classify_file, inputs, outputs, models, client=client)
    return list(zip(inputs, outputs, counts, strict=True))


def scan_files(pattern: str, out_dir: Path, client: Any, model: Any,
               settings: dict) -> list[dict]:  # fmt: skip
    """``scan --files``: every matching belt file -> ``out_dir/<stem>.jsonl``; the summaries."""
    inputs = expand(pattern)
    from .._dask import map_files

    return map_files(scan_file, inputs, output_paths(inputs, out_dir, ".jsonl"), model, settings,
                     client=client)  # fmt: skip


def scan_many(opts: dict) -> None:
    """``scan --files`` (optionally ``--scheduler``): the command's options in, files out."""
    import click

    from .options import dask_client, note

    if opts["files"] is None or opts["file"] is not None or opts["simulate"] is not None:
        raise click.UsageError("--scheduler works with --files GLOB (not FILE or --simulate)")
    if opts["annotate"] is not None:
        raise click.UsageError("--annotate draws one belt; it does not go with --files")
    if opts["out_dir"] is None:
        raise click.UsageError("--files needs --out-dir, the folder for the per-belt results")
    from ..scanner import ScannerModel

    model = ScannerModel.load(opts["model_file"]) if opts["model_file"] is not None else None
    keys = ("max_height", "min_area", "nominal_size", "size_tolerance", "threshold", "polarity",
            "contrast")  # fmt: skip
    settings = {"fmt": opts["fmt"], "width": opts["width"], "chunk_rows": opts["chunk_rows"],
                "dtype": opts["dtype"], "scanner": {k: opts[k] for k in keys}}  # fmt: skip
    with dask_client(opts["scheduler"]) as client:
        done = scan_files(opts["files"], opts["out_dir"], client, model, settings)
    for s in done:
        line = json.dumps({"summary": s}) if opts["summary"] == "json" else (
            f"{s['file']}: {s['rows']} rows, {s['objects']} objects, {s['accepted']} accepted, "
            f"{s['rejected']} rejected")  # fmt: skip
        if opts["summary"] == "json":
            click.echo(line)
        else:
            note(line)
