"""Parsing and options shared by the commands: angle lists, angle files, ``--scheduler``.

Angles are numbers or simple expressions of pi (``pi/2``, ``2*pi/3``,
``-pi/8``, ``2pi``), matched by a regular expression: nothing is evaluated.
"""

from __future__ import annotations

import contextlib
import functools
import re
from collections.abc import Callable, Iterable, Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar, cast

import click
import numpy as np

_NUM = r"(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?"
_ANGLE = re.compile(
    rf"^(?P<sign>[+-]?)(?:(?P<coef>{_NUM})\s*\*?\s*)?(?P<pi>pi|π)?(?:\s*/\s*(?P<den>{_NUM}))?$",
    re.IGNORECASE,
)
_SPLIT = re.compile(r"[\s,;]+")

if TYPE_CHECKING:
    from rich.progress import Progress

_Command = TypeVar("_Command", bound=Callable[..., Any])


def parse_angle(token: str) -> float:
    """One angle: a number or ``[sign][coef][*]pi[/den]``.

    >>> parse_angle("-pi/8") == -np.pi / 8, parse_angle("2*pi/3") == 2 * np.pi / 3
    (True, True)
    >>> parse_angle("0.5")
    0.5
    """
    m = _ANGLE.match(token.strip())
    if not m or (m["coef"] is None and m["pi"] is None):
        raise ValueError(
            f"{token!r} is not a number or an expression of pi such as pi/2, 2*pi/3, -pi/8"
        )
    value = float(m["coef"]) if m["coef"] is not None else 1.0
    if m["pi"]:
        value *= np.pi
    if m["den"] is not None:
        den = float(m["den"])
        if den == 0:
            raise ValueError(f"{token!r} divides by zero")
        value = value / den if np.isfinite(den) else np.inf  # pi/1e400 is not 0
    if not np.isfinite(value):  # 1e400, or 1e308*pi and 1/1e-320 beyond float64
        raise ValueError(f"{token!r} is too large: not a finite number")
    return -value if m["sign"] == "-" else value


def parse_angle_list(text: str) -> np.ndarray:
    """Angles separated by spaces, commas or semicolons, optionally in brackets.

    >>> parse_angle_list("[0 0 0 pi/2]").round(4).tolist()
    [0.0, 0.0, 0.0, 1.5708]
    """
    body = text.strip().strip("[]()").strip()
    tokens = [t for t in _SPLIT.split(body) if t]
    if not tokens:
        raise ValueError("the angle list is empty")
    return np.array([parse_angle(t) for t in tokens])


def load_npy(path: Path) -> np.ndarray:
    """The array of a ``.npy`` file; ValueError naming the file when it is not one.

    Arrays of Python objects (pickles) are refused.
    """
    with open(path, "rb") as fh:
        if fh.read(6) != b"\x93NUMPY":
            raise ValueError(f"{path}: not a readable .npy file (no .npy header)")
    try:
        return np.load(path, allow_pickle=False)
    except (ValueError, OSError) as exc:
        raise ValueError(f"{path}: not a readable .npy file ({exc})") from exc


def read_text(path: Path) -> str:
    """The text of the file ``path``, UTF-8; ValueError naming the file when it is not text.

    A leading byte-order mark (spreadsheets write one) is dropped.
    """
    try:
        return path.read_text(encoding="utf-8-sig")
    except UnicodeDecodeError:
        raise ValueError(f"{path}: not a text file") from None


def no_rows(source: object) -> ValueError:
    """The error for an angle file or stream without a single angle array."""
    return ValueError(f"{source}: no rows (no angle arrays in it)")


def read_angle_file(path: Path) -> np.ndarray:
    """Arrays of joint angles, one per row, from a text/CSV, ``.npy`` or Parquet file.

    A file without arrays is refused (:func:`no_rows`), whatever its kind.
    """
    suffix = path.suffix.lower()
    if suffix == ".parquet":
        from ._files import angle_blocks

        blocks = list(angle_blocks(path))
        if not blocks:
            raise no_rows(path)
        return np.vstack(blocks)
    if suffix == ".npy":
        arr = load_npy(path)
        if (
            arr.ndim not in (1, 2)
            or not np.issubdtype(arr.dtype, np.number)
            or np.iscomplexobj(arr)
        ):
            raise ValueError(
                f"{path}: expected a 1-D or 2-D array of real numbers, got {arr.dtype} {arr.shape}"
            )
        if arr.size == 0 and (arr.ndim == 1 or arr.shape[0] == 0):
            raise no_rows(path)
        return np.atleast_2d(arr.astype(np.float64))
    return parse_angle_rows(read_text(path).splitlines(), str(path))


def parse_angle_rows(lines: Iterable[str], source: str, *, first: bool = False) -> np.ndarray:
    """Angle arrays, one per line (``#`` starts a comment), as a 2-D array.

    With ``first``, only the first array, or none (shape ``(0, 0)``) in a
    file without arrays: a file's chain length, without reading it all.

    >>> parse_angle_rows(["0 0 pi", "# note", "pi 0 0"], "input").shape
    (2, 3)
    """
    rows = []
    for lineno, line in enumerate(lines, 1):
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        try:
            rows.append(parse_angle_list(line))
        except ValueError as exc:
            raise ValueError(f"{source}, line {lineno}: {exc}") from exc
        if first:
            break
    if not rows:
        if first:
            return np.zeros((0, 0))
        raise no_rows(source)
    lengths = {r.size for r in rows}
    if len(lengths) > 1:
        raise ValueError(f"{source}: rows have different numbers of angles {sorted(lengths)}")
    return np.vstack(rows)


class OutputFile(click.Path):
    """Click type for a file to write: not a folder, in a folder that exists.

    Checked when the command line is read, before any work is done.
    """

    def __init__(self, *, figure: bool = False, suffixes: tuple[str, ...] = ()) -> None:
        super().__init__(dir_okay=False, writable=True, path_type=Path)
        self.figure = figure
        self.suffixes = suffixes

    def convert(self, value, param, ctx):  # noqa: D102
        if value == "":  # Path("") is the current folder
            self.fail("the file name is empty", param, ctx)
        path = cast(Path, super().convert(value, param, ctx))
        if not path.absolute().parent.is_dir():
            self.fail(f"the folder {str(path.parent)!r} does not exist", param, ctx)
        suffix = path.suffix.lower()
        known = self.suffixes
        if self.figure and suffix:
            from matplotlib.backend_bases import FigureCanvasBase

            known = tuple(f".{k}" for k in FigureCanvasBase.get_supported_filetypes())
        if known and suffix not in known:
            self.fail(
                f"{str(path)!r}: cannot write {suffix or 'a file without a suffix'}; "
                f"use {', '.join(known)}",
                param,
                ctx,
            )
        return path


class Folder(click.Path):
    """Click type for a folder name (not a file's); an empty name is refused.

    ``Path("")`` is the current folder: an empty option value (an unset shell
    variable, say) would otherwise write into, or read, the current folder.
    """

    def __init__(self) -> None:
        super().__init__(file_okay=False, path_type=Path)

    def convert(self, value, param, ctx):  # noqa: D102
        if value == "":
            self.fail("the folder name is empty (give '.' for the current folder)", param, ctx)
        return super().convert(value, param, ctx)


class AngleList(click.ParamType):
    """Click type for an angle list given on the command line."""

    name = "ANGLES"

    def convert(self, value, param, ctx):  # noqa: D102
        if isinstance(value, np.ndarray):
            return value
        try:
            return parse_angle_list(value)
        except ValueError as exc:
            self.fail(str(exc), param, ctx)


def finite(ctx, param, value):
    """Click callback: refuse NaN and infinity for a float option."""
    if value is not None and not np.isfinite(value):
        raise click.BadParameter(f"must be a finite number, got {value}")
    return value


def note(message: str) -> None:
    """A line of information or warning on stderr, left out with ``tentaclass -q``."""
    ctx = click.get_current_context(silent=True)
    root = ctx.find_root() if ctx is not None else None
    if root is not None and isinstance(root.obj, dict) and root.obj.get("quiet"):
        return
    click.echo(message, err=True)


#: Other objects at least this fraction of the largest one's area make ``image_outline`` warn.
OTHER_OBJECT_SHARE = 0.1


def image_outline(path: Path) -> np.ndarray:
    """The outline of the largest object of an image file (``--mask``, ``--outlines``).

    Warns on stderr when the image holds other objects of at least
    :data:`OTHER_OBJECT_SHARE` of its area (they are left out), and refuses an
    image with no object in one line naming the file.
    """
    from scipy import ndimage

    from ..shapes import from_mask, read_silhouette

    try:
        mask = read_silhouette(path)
    except OSError as exc:
        raise ValueError(f"{path}: not a readable image ({exc.strerror or exc})") from None
    if not mask.any():
        raise ValueError(
            f"{path}: no object found (objects are the pixels on the other side of half the "
            "brightest level from the border): is the image blank, or the object too faint?"
        )
    labels, _ = ndimage.label(mask, structure=np.ones((3, 3), bool))
    sizes = np.sort(np.bincount(labels.ravel())[1:])[::-1]
    others = sizes[1:][sizes[1:] >= OTHER_OBJECT_SHARE * sizes[0]]
    if others.size:
        note(
            f"warning: {path}: {others.size + 1} objects; the largest ({sizes[0]:,} px) is used, "
            f"{others.size} other(s) of up to {others[0]:,} px left out: one object per image"
        )
    return from_mask(mask)


def given(ctx: click.Context, *names: str) -> list[str]:
    """The options among ``names`` (parameter names) set on the command line, as flags.

    An option left at its default is not listed, so a command can refuse
    options that have no effect in the mode it runs in.
    """
    from click.core import ParameterSource

    flags = {p.name: "/".join([p.opts[0], *p.secondary_opts]) for p in ctx.command.params}
    return [
        flags[name]
        for name in names
        if ctx.get_parameter_source(name) not in (None, ParameterSource.DEFAULT)
    ]


def refuse_unused(ctx: click.Context, names: Iterable[str], why: str) -> None:
    """A usage error naming the first of ``names`` set on the command line, with ``why``.

    ``why`` completes "--option ...", e.g. ``"needs --files"``.
    """
    used = given(ctx, *names)
    if used:
        raise click.UsageError(f"{used[0]} {why}")


def make_folder(path: Path, option: str) -> Path:
    """Create the output folder ``path`` (and its parents) before any work is done.

    A folder that cannot be made is a usage error naming ``option`` and the reason.
    """
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise click.BadParameter(
            f"cannot create the folder {str(path)!r}: {exc.strerror or exc}", param_hint=option
        ) from None
    return path


def number_option(
    name: str, type: click.FloatRange, default: float, help: str
) -> Callable[[_Command], _Command]:
    """A float option ``name`` in the range ``type``, finite, with its default shown."""
    return click.option(
        name, type=type, default=default, show_default=True, callback=finite, help=help
    )


def input_file_option(name: str, dest: str, help: str) -> Callable[[_Command], _Command]:
    """An option naming a file that must exist (a folder is refused), passed as a Path."""
    return click.option(
        name, dest, type=click.Path(exists=True, dir_okay=False, path_type=Path), help=help
    )


def noise_option(default: float, help: str) -> Callable[[_Command], _Command]:
    """``--noise``: a joint-noise sigma in radians, from 0 to ``MAX_NOISE`` (2*pi)."""
    from .._validation import MAX_NOISE

    return number_option("--noise", click.FloatRange(min=0, max=MAX_NOISE), default, help)


def object_options(verb: str) -> Callable[[_Command], _Command]:
    """The options that name an object (``--shape``, ``--size``, ``--vertices``, ``--mask``)."""

    def decorate(func: _Command) -> _Command:
        for option in reversed([
            click.option("--shape", type=click.Choice(["circle", "square", "rectangle",
                         "triangle", "polygon"]), help="Primitive object (default square)."),
            click.option("--size", help="Square side, circle radius, triangle side, or 'W,H' "
                         "of a rectangle ('W' alone: W by W/3) (default 4)."),
            click.option("--vertices", help="Polygon or triangle vertices: 'x,y x,y x,y ...'."),
            input_file_option("--mask", "mask", f"Binary image: {verb} its largest object."),
        ]):  # fmt: skip
            func = option(func)
        return func

    return decorate


def placement_options(func: _Command) -> _Command:
    """Where a chain starts on an object: ``--start``, ``--direction``, ``--offset``."""
    for option in reversed([
        click.option("--start", type=click.FloatRange(0, 1, max_open=True), default=0.0,
                     show_default=True, callback=finite,
                     help="Start point, fraction of the perimeter."),
        click.option("--direction", type=click.Choice(["ccw", "cw"]), default="ccw",
                     show_default=True),
        click.option("--offset", type=click.FloatRange(min=0), default=0.0, show_default=True,
                     callback=finite, help="Distance of the base from the object."),
    ]):  # fmt: skip
        func = option(func)
    return func


def json_option(func: _Command) -> _Command:
    """``--json``, passed as ``as_json``: print JSON instead of text."""
    return click.option("--json", "as_json", is_flag=True, help="Print JSON.")(func)


def random_state_option(help: str, default: int | None = 0) -> Callable[[_Command], _Command]:
    """``--random-state N`` (passed as ``random_state``), and its deprecated alias ``--seed``."""

    def decorate(func: _Command) -> _Command:
        @functools.wraps(func)
        def command(*args: Any, random_state: int | None, seed: int | None, **kwargs: Any) -> Any:
            if seed is not None:
                if random_state is not None:
                    raise click.UsageError("give --random-state only, not --seed as well")
                random_state = seed
            return func(*args, random_state=default if random_state is None else random_state,
                        **kwargs)  # fmt: skip

        shown = "" if default is None else f" [default: {default}]"
        command = click.option(
            "--seed", type=click.IntRange(min=0), default=None, hidden=True,
            deprecated="--seed will be removed in the next release; use --random-state",
        )(command)  # fmt: skip
        command = click.option(
            "--random-state", type=click.IntRange(min=0), default=None, help=help + shown
        )(command)
        return cast(_Command, command)

    return decorate


def scheduler_option(command: Callable) -> Callable:
    """Click decorator: the ``--scheduler`` option (``local`` or a scheduler address)."""
    return click.option(
        "--scheduler",
        metavar="local|ADDRESS",
        default=None,
        help="Run on a Dask cluster: 'local' starts one worker process per core and prints "
        "its dashboard address; tcp://host:8786 uses a running scheduler. Default: this "
        "process only.",
    )(command)


def files_options(suffix_help: str) -> Callable:
    """Click decorator: ``--files GLOB`` and ``--out-dir DIR`` (one output per input file)."""

    def decorate(command: Callable) -> Callable:
        command = click.option(
            "--out-dir",
            type=Folder(),
            default=None,
            help=f"With --files: folder for the outputs, one per input file ({suffix_help}); "
            "each appears only once its file is complete.",
        )(command)
        return click.option(
            "--files",
            "files",
            metavar="GLOB",
            default=None,
            help="Many input files, e.g. 'logs/**/*.parquet' (quote it); see --out-dir.",
        )(command)

    return decorate


def progress_bar(label: str = "{task.description}", *, counts: str = "items") -> Progress:
    """A rich progress bar on standard error, gone when it stops.

    ``label`` is the text before the bar (by default each task's description);
    ``counts`` is ``"items"`` (done / total) or ``"bytes"`` (a download size).
    """
    from rich.console import Console
    from rich.progress import (
        BarColumn,
        DownloadColumn,
        MofNCompleteColumn,
        Progress,
        TimeRemainingColumn,
    )

    return Progress(
        f"[progress.description]{label}",
        BarColumn(),
        DownloadColumn() if counts == "bytes" else MofNCompleteColumn(),
        TimeRemainingColumn(),
        console=Console(stderr=True),
        transient=True,
    )


@contextlib.contextmanager
def dask_client(address: str | None) -> Iterator[Any]:
    """The client for ``--scheduler`` (None without it); the dashboard goes to stderr."""
    if address is None:
        yield None
        return
    from .._dask import scheduler
    from .._lazy import import_extra

    import_extra("distributed", "dask", "--scheduler needs Dask", error=click.ClickException)
    with scheduler(address, echo=note) as client:
        yield client


def predict_on(model: Any, X: np.ndarray, client: Any, block_rows: int = 65536) -> np.ndarray:
    """``model.predict(X)``, in blocks of rows on the Dask cluster when ``client`` is given."""
    if client is None:
        return model.predict(X)
    import dask.array as da

    n_blocks = max(1, len(client.scheduler_info(n_workers=-1).get("workers", {})))
    rows = max(1, min(block_rows, -(-X.shape[0] // n_blocks)))
    return client.compute(model.predict(da.from_array(X, chunks=(rows, -1)))).result()


def class_count_key(label: object) -> str:
    """The scan summary's counter key of an object's class.

    An object rejected before it was classified (``label`` None, e.g. taller
    than ``--max-height``) counts as ``unclassified``.
    """
    return f"class:{'unclassified' if label is None else label}"
