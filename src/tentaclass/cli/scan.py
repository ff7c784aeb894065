"""``tentaclass scan``: belt rows -> one JSON line per object, as the belt runs.

Reads rows from FILE (or ``-`` for stdin) as text lines of 0/1, a PBM image,
a grey-level PNG or TIFF image (8 or 16 bit), or a raw stream with ``--width``:
one byte, 0 or 1, per pixel, or grey levels of ``--dtype`` as a line camera
delivers them; or generates a belt with ``--simulate N``. Grey levels are
thresholded (``--threshold``, ``--polarity``; by default chosen from the first
rows and reported in the summary). Every object is written to stdout as one
JSON line (flushed) as soon as it has passed the sensor. A summary goes to
stderr as one line (``--summary json`` writes it as a last JSON line on stdout
instead, under the key ``"summary"``); when no object was found, a line on
stderr says so with the threshold used. Bad input ends with a one-line error
on stderr and exit code 1; objects already written stay written.
"""

from __future__ import annotations

import json
import sys
from collections import Counter
from pathlib import Path
from typing import IO, Any

import click
import numpy as np

from .._validation import MAX_AXIS, MAX_INT64, MAX_SAMPLES
from ..errors import TentaclassError
from .options import (
    OutputFile,
    class_count_key,
    files_options,
    finite,
    note,
    progress_bar,
    random_state_option,
    refuse_unused,
    scheduler_option,
)


class _CountingReader:
    """Binary file wrapper that reports bytes read to a callback (progress bar)."""

    def __init__(self, fh: IO[bytes], callback: Any):
        self._fh, self._cb = fh, callback

    def read(self, n: int = -1) -> bytes:
        data = self._fh.read(n)
        self._cb(len(data))
        return data


def _progress(total: int | None, enabled: bool) -> Any:
    return progress_bar(counts="bytes") if enabled and total else None


def _one_line(exc: BaseException) -> str:
    text = str(exc)
    return text.splitlines()[0] if text else repr(exc)


def _emit(objects: list, stats: Counter, out: list | None) -> None:
    for obj in objects:
        click.echo(json.dumps(obj.to_dict()))
        stats["objects"] += 1
        stats["accepted" if obj.accept else "rejected"] += 1
        stats[class_count_key(obj.label)] += 1
        for d in obj.defects:
            stats[f"defect:{d.kind}"] += 1
        if out is not None:
            out.append(obj)


def _chunks(source: Any, keep: list | None) -> Any:
    """The chunks of ``source``, also kept (as arrays) in ``keep`` for the figure."""
    for chunk in source:
        if keep is not None:
            keep.append(chunk if isinstance(chunk, np.ndarray) else np.frombuffer(chunk, np.uint8))
        yield chunk


@click.command()
@click.argument("file", required=False, type=click.Path(dir_okay=False, allow_dash=True))
@click.option(
    "--format",
    "fmt",
    type=click.Choice(["text", "pbm", "png", "tiff", "raw"]),
    help="Input format; default detected from the first bytes.",
)
@click.option(
    "--width",
    type=click.IntRange(min=1, max=MAX_AXIS),
    help="Pixels per row (required for raw bytes; belt width for --simulate).",
)
@click.option(
    "--dtype",
    type=click.Choice(["uint8", "uint16", "float32", "float64"]),
    help="Raw input of grey levels of this type (little endian); without it raw "
    "input is one byte, 0 or 1, per pixel.",
)
@click.option(
    "--threshold",
    default="auto",
    show_default=True,
    help="Grey level separating objects from the belt: a number, 'fixed' or "
    "'adaptive' (a running belt level per column, for uneven light), 'binary' "
    "(0/1 rows) or 'auto' (chosen from the first rows).",
)
@click.option(
    "--polarity",
    type=click.Choice(["auto", "dark", "light"]),
    default="auto",
    show_default=True,
    help="Objects darker or lighter than the belt.",
)
@click.option(
    "--contrast",
    type=click.FloatRange(min=0, min_open=True),
    callback=finite,
    help="Least difference from the belt level of an object pixel (default from the data).",
)
@click.option(
    "--model",
    "model_file",
    type=click.Path(dir_okay=False, path_type=Path),
    help="A model saved with ScannerModel.save (.tcm); default the thesis's classes.",
)
@click.option(
    "--max-height",
    type=click.IntRange(min=1, max=MAX_INT64),
    default=1024,
    show_default=True,
    help="Objects taller than this (rows) are reported as too tall.",
)
@click.option(
    "--min-area",
    type=click.IntRange(min=1, max=MAX_INT64),
    default=1,
    show_default=True,
    help="Ignore objects of fewer pixels (sensor speckle).",
)
@click.option(
    "--nominal-size",
    type=click.FloatRange(min=0, min_open=True),
    callback=finite,
    help="Nominal object length in pixels; objects off by more than the tolerance are rejected.",
)
@click.option(
    "--size-tolerance",
    type=click.FloatRange(min=0),
    callback=finite,
    default=0.1,
    show_default=True,
    help="Allowed relative deviation from --nominal-size.",
)
@click.option(
    "--annotate",
    type=OutputFile(figure=True),
    help="Draw the belt with boxes, labels and defect marks to this PNG "
    "(keeps the whole belt in memory).",
)
@click.option(
    "--simulate",
    type=click.IntRange(min=1, max=MAX_SAMPLES),
    metavar="N",
    help="Scan a generated belt of N random objects (some damaged) instead of FILE.",
)
@random_state_option("Seed of --simulate.")
@click.option(
    "--write-belt",
    type=OutputFile(),
    help="With --simulate: also save the generated belt as a PBM file.",
)
@click.option(
    "--chunk-rows",
    type=click.IntRange(min=1, max=MAX_AXIS),
    default=1024,
    show_default=True,
    help="Rows read and processed per step.",
)
@click.option(
    "--summary",
    type=click.Choice(["stderr", "json"]),
    default="stderr",
    show_default=True,
    help="Where the final summary goes.",
)
@files_options(".jsonl: one JSON line per object")
@scheduler_option
def scan(
    file: str | None,
    fmt: str | None,
    width: int | None,
    dtype: str | None,
    threshold: str,
    polarity: str,
    contrast: float | None,
    model_file: Path | None,
    max_height: int,
    min_area: int,
    nominal_size: float | None,
    size_tolerance: float,
    annotate: Path | None,
    simulate: int | None,
    random_state: int,
    write_belt: Path | None,
    chunk_rows: int,
    summary: str,
    files: str | None = None,
    out_dir: Path | None = None,
    scheduler: str | None = None,
) -> None:
    """Classify and inspect objects on a conveyor belt: FILE (or - for stdin).

    Writes one JSON line per object (id, first_row, last_row, bbox, area,
    label, confidence, defects, accept, reasons, ...) as soon as the object has
    passed. Objects are 8-connected groups of 1-pixels.
    """
    from ..scanner import LineScanner, ScannerModel
    from ..scanner.io import read_rows, write_pbm
    from ..scanner.simulate import make_belt

    ctx = click.get_current_context()
    if threshold not in ("auto", "binary", "fixed", "adaptive"):
        try:
            level = float(threshold)
        except ValueError:
            raise click.BadParameter(
                f"{threshold!r}: a number, auto, binary, fixed or adaptive",
                param_hint="--threshold",
            ) from None
        if not np.isfinite(level):  # nan, inf and numbers beyond float64 (1e400)
            raise click.BadParameter(
                f"must be a finite number or auto, binary, fixed or adaptive, got {threshold!r}",
                param_hint="--threshold",
            )
        threshold = level  # type: ignore[assignment]
    if simulate is None:
        refuse_unused(ctx, ("random_state", "seed", "write_belt"), "needs --simulate")
    if files is not None or scheduler is not None:
        from ._files import scan_many

        return scan_many(locals())
    refuse_unused(ctx, ("out_dir",), "needs --files")
    if (file is None) == (simulate is None):
        raise click.UsageError("give either FILE (or - for stdin) or --simulate N")
    if simulate is not None:
        refuse_unused(ctx, ("fmt", "dtype"), "describes an input file; --simulate has none")
    stats: Counter = Counter()
    kept: list | None = [] if annotate is not None else None
    belt_rows: list[np.ndarray] | None = [] if annotate is not None else None
    progress = None
    opened: IO[bytes] | None = None
    try:
        model = ScannerModel.load(model_file) if model_file is not None else None
        if simulate is not None:
            try:  # a belt the options cannot make is a usage error, as wrap's objects are
                belt = make_belt(
                    simulate,
                    width or 256,
                    random_state=random_state,
                    lanes=max(1, (width or 256) // 128),
                )
            except (TentaclassError, ValueError) as exc:
                raise click.UsageError(_one_line(exc)) from None
            if write_belt is not None:
                write_pbm(write_belt, belt.image)
            source: Any = (
                belt.image[i : i + chunk_rows] for i in range(0, belt.image.shape[0], chunk_rows)
            )
            belt_width = belt.image.shape[1]
        else:
            if file is None:  # excluded above: exactly one of FILE and --simulate
                raise click.UsageError("give either FILE (or - for stdin) or --simulate N")
            if file == "-":
                try:
                    fh: Any = click.open_file("-", "rb")
                except RuntimeError:  # no standard input at all (closed)
                    raise TentaclassError("cannot read standard input: it is closed") from None
                total = None
            else:
                try:
                    fh = opened = open(file, "rb")  # closed in finally below
                except OSError as exc:
                    raise TentaclassError(f"cannot open {file}: {exc.strerror or exc}") from exc
                total = Path(file).stat().st_size
            progress = _progress(total, sys.stderr.isatty())
            if progress is not None:
                progress.start()
                task = progress.add_task("scanning", total=total)
                fh = _CountingReader(fh, lambda n: progress.advance(task, n))
            source = read_rows(fh, fmt=fmt, width=width, chunk_rows=chunk_rows, dtype=dtype)
            belt_width = width
        scanner = None
        try:
            for chunk in _chunks(source, belt_rows):
                if scanner is None:
                    w = belt_width or (chunk.shape[1] if isinstance(chunk, np.ndarray) else None)
                    if w is None:
                        raise TentaclassError("raw input needs the row width (--width)")
                    scanner = LineScanner(
                        w,
                        model,
                        max_height=max_height,
                        min_area=min_area,
                        threshold=threshold,
                        polarity=polarity,
                        contrast=contrast,
                        nominal_size=nominal_size,
                        size_tolerance=size_tolerance,
                    )
                _emit(scanner.feed(chunk), stats, kept)
        except (TentaclassError, ValueError, OSError):
            # report what the complete rows before the error hold, then the error
            if scanner is not None:
                _emit(scanner.flush(), stats, kept)
            raise
        if scanner is None:
            raise TentaclassError("empty stream: no rows found")
        _emit(scanner.close(), stats, kept)
        rows, ignored = scanner.rows_seen, scanner.n_ignored
        rule = scanner.threshold_
    except (TentaclassError, ValueError, OSError) as exc:
        raise click.ClickException(_one_line(exc)) from None
    finally:
        if progress is not None:
            progress.stop()
        if opened is not None:
            opened.close()
    if annotate is not None and belt_rows is not None and kept is not None:
        from ..plot.scanner import save_belt_figure

        image = (
            np.concatenate(belt_rows)
            if all(r.ndim == 2 for r in belt_rows)
            else np.concatenate(belt_rows).reshape(-1, scanner.width).astype(bool)
        )
        try:
            save_belt_figure(image, kept, annotate)
        except (ValueError, OSError) as exc:
            raise click.ClickException(f"cannot write {annotate}: {_one_line(exc)}") from None
    result: dict[str, Any] = {
        "rows": rows,
        "ignored": ignored,
        "objects": stats["objects"],
        "accepted": stats["accepted"],
        "rejected": stats["rejected"],
        "classes": {k[6:]: v for k, v in sorted(stats.items()) if k.startswith("class:")},
        "defects": {k[7:]: v for k, v in sorted(stats.items()) if k.startswith("defect:")},
        "threshold": rule.to_dict() if rule is not None else None,
    }
    if not stats["objects"]:
        how = rule.describe() if rule is not None else "no threshold"
        note(
            f"no object found in {rows} rows ({how}); if the belt is not empty, "
            "try --polarity or --threshold"
        )
    if summary == "json":
        click.echo(json.dumps({"summary": result}))
    else:
        classes = ", ".join(f"{k} {v}" for k, v in result["classes"].items()) or "none"
        how = f"; {rule.describe()}" if rule is not None and rule.mode != "binary" else ""
        note(
            f"scanned {rows} rows: {result['objects']} objects, {result['accepted']} accepted, "
            f"{result['rejected']} rejected ({classes}){how}"
        )
