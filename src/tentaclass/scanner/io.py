"""Reading belt rows from files and streams, writing belts for tests and demos.

Formats (detected from the first bytes unless given):

``text``
    One row per line, characters ``0`` and ``1`` (spaces and tabs between
    them are ignored; empty lines and lines starting with ``#`` are skipped).
``pbm``
    Netpbm bitmap, plain (``P1``) or raw (``P4``); ``1`` (black) is object.
``png``, ``tiff``
    A grey-level image of 1, 8 or 16 bits (colour is converted to 8-bit grey),
    yielded as bool, uint8 or uint16 rows for the scanner to threshold. It is
    read whole (these formats cannot be streamed row by row with the libraries
    at hand).
``raw``
    Rows of ``width`` pixels back to back, no header (``width`` must be
    given): one byte, ``0`` or ``1``, per pixel, or with ``dtype`` grey
    levels of that type (e.g. ``uint8``, ``uint16``, ``float32``; little
    endian) as a line camera delivers them.

:func:`read_rows` yields chunks for :meth:`LineScanner.feed
<tentaclass.scanner.LineScanner.feed>` as they are read, so a belt of any
length streams through in bounded memory (except PNG).
"""

from __future__ import annotations

import io
import re
from collections.abc import Iterator
from pathlib import Path
from typing import IO, Any

import numpy as np

from .._validation import MAX_AXIS, check_positive_int
from ..errors import InputError

__all__ = ["FORMATS", "detect_format", "read_belt", "read_rows", "write_pbm", "write_text"]

FORMATS: tuple[str, ...] = ("text", "pbm", "png", "tiff", "raw")
"""Input formats :func:`read_rows` understands."""

_PNG_MAGIC = b"\x89PNG"
_TIFF_MAGIC = (b"II*\x00", b"MM\x00*")
#: Most bytes read from a file at a time: what a header claims is not yet known to be there.
_MAX_READ = 2**26
RAW_DTYPES: tuple[str, ...] = ("uint8", "uint16", "float32", "float64")
"""Pixel types of raw grey-level streams."""


def detect_format(head: bytes, width: int | None = None) -> str:
    r"""Format of a stream from its first bytes.

    ``P1``/``P4`` -> pbm, the PNG or TIFF signature -> png or tiff, otherwise
    raw when a ``width`` is given, else text.

    Examples
    --------
    >>> detect_format(b"P4\n8 2\n"), detect_format(b"0110\n"), detect_format(b"\x00\x01", 2)
    ('pbm', 'text', 'raw')
    """
    if head.startswith((b"P1", b"P4")):
        return "pbm"
    if head[:1] == b"P" and head[1:2] in (b"2", b"3", b"5", b"6"):
        raise InputError(
            f"unsupported Netpbm image {head[:2].decode()}: only bitmaps (PBM, P1 or P4) are read"
        )
    if head.startswith(_PNG_MAGIC):
        return "png"
    if head.startswith(_TIFF_MAGIC):
        return "tiff"
    return "raw" if width is not None else "text"


def _open(source: Any) -> tuple[IO[bytes], bool]:
    if isinstance(source, str | Path):
        try:
            return open(source, "rb"), True
        except OSError as exc:
            raise InputError(f"cannot open {source}: {exc.strerror or exc}") from exc
    if hasattr(source, "read"):
        return source, False
    raise InputError(f"source must be a path or a binary file object, got {type(source).__name__}")


class _Peeked(io.RawIOBase):
    """A binary stream with some already-read bytes put back in front."""

    def __init__(self, head: bytes, rest: IO[bytes]):
        self._head, self._rest = head, rest

    def readable(self) -> bool:
        return True

    def readinto(self, b: Any) -> int:
        if self._head:
            n = min(len(b), len(self._head))
            b[:n] = self._head[:n]
            self._head = self._head[n:]
            return n
        data = self._rest.read(len(b))
        b[: len(data)] = data
        return len(data)


def _text_rows(fh: IO[bytes], width: int | None, chunk_rows: int) -> Iterator[np.ndarray]:
    chunk: list[np.ndarray] = []
    row = 0
    for lineno, raw in enumerate(io.TextIOWrapper(fh, encoding="latin-1"), 1):
        if lineno == 1:  # a UTF-8 byte-order mark, as text editors on Windows write
            raw = raw.removeprefix("\xef\xbb\xbf")
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        line = line.replace(" ", "").replace("\t", "")
        arr = np.frombuffer(line.encode("latin-1"), dtype=np.uint8) - ord("0")
        if arr.size and arr.max() > 1:
            j = int(np.argmax(arr > 1))
            raise InputError(f"line {lineno} (row {row}), column {j}: {line[j]!r}, expected 0 or 1")
        if width is None:
            width = arr.size
        if arr.size != width:
            raise InputError(f"line {lineno} (row {row}) has {arr.size} pixels, expected {width}")
        chunk.append(arr.astype(bool))
        row += 1
        if len(chunk) >= chunk_rows:
            yield np.stack(chunk)
            chunk = []
    if chunk:
        yield np.stack(chunk)


_PBM_TOKEN = re.compile(rb"\s*(?:#[^\n]*\n\s*)*(\S+)")


def _pbm_rows(fh: IO[bytes], width: int | None, chunk_rows: int) -> Iterator[np.ndarray]:
    # The header is short; read enough for it, then stream the raster.
    head = fh.read(4096)
    pos = 0
    tokens: list[bytes] = []
    while len(tokens) < 3:
        m = _PBM_TOKEN.match(head, pos)
        if not m:
            raise InputError("not a valid PBM file: incomplete header")
        tokens.append(m.group(1))
        pos = m.end()
    magic = tokens[0]
    try:
        w, h = int(tokens[1]), int(tokens[2])
    except ValueError:
        raise InputError(f"not a valid PBM file: bad size {tokens[1]!r} x {tokens[2]!r}") from None
    if w <= 0 or h < 0:
        raise InputError(f"not a valid PBM file: size {w} x {h}")
    if w > MAX_AXIS:
        raise InputError(f"PBM file {w:,} pixels wide: rows of at most {MAX_AXIS:,} are read")
    if width is not None and width != w:
        raise InputError(f"the PBM file is {w} pixels wide, but --width {width} was given")
    if magic == b"P4":
        rest = io.BufferedReader(_Peeked(head[pos + 1 :], fh))  # one whitespace byte ends it
        row_bytes = (w + 7) // 8
        # a header's size is a claim: read at most _MAX_READ bytes at a time towards it
        chunk_rows = max(1, min(chunk_rows, _MAX_READ // row_bytes))
        done = 0
        while done < h:
            n = min(chunk_rows, h - done)
            data = rest.read(n * row_bytes) or b""
            got = len(data) // row_bytes
            if got:
                bits = np.unpackbits(
                    np.frombuffer(data[: got * row_bytes], np.uint8).reshape(got, row_bytes),
                    axis=1,
                )[:, :w]
                yield bits.astype(bool)
                done += got
            if got < n:
                raise InputError(f"truncated PBM file: {h} rows in the header, only {done} found")
        return
    # P1: whitespace-separated (or packed) digits
    body = head[pos:] + fh.read()
    body = re.sub(rb"#[^\n]*", b"", body)
    digits = np.frombuffer(re.sub(rb"\s+", b"", body), dtype=np.uint8) - ord("0")
    if digits.size and digits.max() > 1:
        k = int(np.argmax(digits > 1))
        raise InputError(f"PBM row {k // w}, column {k % w}: not 0 or 1")
    if digits.size < w * h:
        raise InputError(
            f"truncated PBM file: {h} rows in the header, only {digits.size // w} found"
        )
    img = digits[: w * h].reshape(h, w).astype(bool)
    for i in range(0, h, chunk_rows):
        yield img[i : i + chunk_rows]


def _image_rows(fh: IO[bytes], fmt: str, chunk_rows: int) -> Iterator[np.ndarray]:
    from PIL import Image

    name = fmt.upper()
    try:
        with Image.open(fh) as im:
            mode = im.mode
            if mode in ("1", "L", "I;16", "I;16L", "I;16B"):
                img = np.asarray(im)
            elif mode in ("RGB", "RGBA", "LA", "P", "CMYK", "YCbCr"):
                img = np.asarray(im.convert("L"))
            else:
                depth = {"I": "32-bit integer", "F": "32-bit float"}.get(mode, f"mode {mode}")
                raise InputError(
                    f"cannot read the {name} image: {depth} pixels; "
                    "expected a 1, 8 or 16-bit grey (or colour) image"
                )
    except (MemoryError, InputError):
        raise
    except Image.UnidentifiedImageError as exc:
        raise InputError(f"cannot read the {name} image: not an image Pillow can identify") from exc
    except Exception as exc:
        # Pillow reports damaged images as OSError, SyntaxError, zlib.error, ...
        raise InputError(f"cannot read the {name} image: {type(exc).__name__}: {exc}") from exc
    if img.ndim != 2:
        raise InputError(f"cannot read the {name} image: shape {img.shape}, expected 2-D")
    if img.dtype.byteorder == ">":
        img = img.astype(img.dtype.newbyteorder("="))
    for i in range(0, img.shape[0], chunk_rows):
        yield img[i : i + chunk_rows]


def _raw_rows(
    fh: IO[bytes], width: int, chunk_rows: int, dtype: str | None
) -> Iterator[bytes | np.ndarray]:
    if dtype is None:
        size = width * chunk_rows
        while True:
            data = fh.read(size)
            if not data:
                return
            yield data
    dt = np.dtype(dtype).newbyteorder("<")
    row_bytes = width * dt.itemsize
    rest, row = b"", 0
    while True:
        data = fh.read(row_bytes * chunk_rows)
        if not data:
            break
        data = rest + data
        n = len(data) // row_bytes
        rest = data[n * row_bytes :]
        if n:
            rows = np.frombuffer(data[: n * row_bytes], dt).reshape(n, width)
            yield rows.astype(dt.newbyteorder("="))
            row += n
    if rest:
        raise InputError(
            f"truncated stream: row {row} has only {len(rest)} of {row_bytes} bytes "
            f"({width} pixels of {dt.name})"
        )


def read_rows(
    source: Any,
    *,
    fmt: str | None = None,
    width: int | None = None,
    chunk_rows: int = 1024,
    dtype: str | None = None,
) -> Iterator[np.ndarray | bytes]:
    r"""Chunks of belt rows from a file or stream, as they are read.

    Parameters
    ----------
    source : str, Path or binary file object
        Where to read; a file object is not closed.
    fmt : {"text", "pbm", "png", "tiff", "raw"}, optional
        Format; default detected from the first bytes (:func:`detect_format`).
    width : int, optional
        Pixels per row: required for raw bytes, checked for the others.
    chunk_rows : int, default=1024
        Rows per chunk.
    dtype : {"uint8", "uint16", "float32", "float64"}, optional
        Pixel type of raw grey-level input; without it raw input is one byte,
        0 or 1, per pixel.

    Yields
    ------
    chunk : ndarray of shape (n_rows, width), or bytes
        bool for text and PBM, the image's type (bool, uint8 or uint16) for
        PNG and TIFF, ``dtype`` for raw grey levels. Raw 0/1 input yields
        ``bytes`` (rows may be cut at chunk ends; the
        :class:`~tentaclass.scanner.LineScanner` joins them and reports a
        truncated last row).

    Raises
    ------
    InputError
        On unreadable input, naming the line or row.

    Examples
    --------
    >>> import io
    >>> [c.astype(int).tolist() for c in read_rows(io.BytesIO(b"0110\n1111\n"))]
    [[[0, 1, 1, 0], [1, 1, 1, 1]]]
    """
    chunk_rows = check_positive_int(chunk_rows, "chunk_rows", maximum=MAX_AXIS)
    if width is not None:
        width = check_positive_int(width, "width", maximum=MAX_AXIS)
    if fmt is not None and fmt not in FORMATS:
        raise InputError(f"fmt must be one of {list(FORMATS)}, got {fmt!r}")
    if dtype is not None and dtype not in RAW_DTYPES:
        raise InputError(f"dtype must be one of {list(RAW_DTYPES)}, got {dtype!r}")
    fh, owned = _open(source)
    try:
        head = fh.read(8) or b""
        fmt = fmt or detect_format(head, width)
        stream = io.BufferedReader(_Peeked(head, fh))
        if fmt == "text":
            yield from _text_rows(stream, width, chunk_rows)
        elif fmt == "pbm":
            yield from _pbm_rows(stream, width, chunk_rows)
        elif fmt in ("png", "tiff"):
            for chunk in _image_rows(stream, fmt, chunk_rows):
                if width is not None and chunk.shape[1] != width:
                    raise InputError(
                        f"the {fmt.upper()} image is {chunk.shape[1]} pixels wide, "
                        f"but --width {width} was given"
                    )
                yield chunk
        else:
            if width is None:
                raise InputError("raw input needs the row width (--width)")
            yield from _raw_rows(stream, width, chunk_rows, dtype)
    finally:
        if owned:
            fh.close()


def read_belt(
    source: Any, *, fmt: str | None = None, width: int | None = None, dtype: str | None = None
) -> np.ndarray:
    """A whole belt image, shape (n_rows, width) (see :func:`read_rows`).

    bool for binary formats, the pixel type for grey-level images and streams.

    Examples
    --------
    >>> import io
    >>> read_belt(io.BytesIO(bytes([0, 1, 1, 0, 1, 1])), width=3).astype(int).tolist()
    [[0, 1, 1], [0, 1, 1]]
    """
    chunks = list(read_rows(source, fmt=fmt, width=width, dtype=dtype))
    if not chunks:
        raise InputError("empty stream: no rows found")
    if isinstance(chunks[0], bytes):
        if width is None:  # read_rows gives bytes only for raw input, which has a width
            raise InputError("raw input needs the row width (--width)")
        data = b"".join(c for c in chunks if isinstance(c, bytes))  # raw: every chunk is bytes
        if len(data) % width:
            raise InputError(
                f"truncated stream: row {len(data) // width} has only "
                f"{len(data) % width} of {width} bytes"
            )
        arr = np.frombuffer(data, np.uint8).reshape(-1, width)
        if arr.max(initial=0) > 1:
            i, j = np.argwhere(arr > 1)[0]
            raise InputError(f"row {i}, column {j}: byte value {arr[i, j]}, expected 0 or 1")
        return arr.astype(bool)
    return np.concatenate(chunks)


def write_pbm(path: str | Path | IO[bytes], image: Any) -> None:
    """Write a binary image as a raw PBM (``P4``) file.

    Examples
    --------
    >>> import io, numpy as np
    >>> buf = io.BytesIO()
    >>> write_pbm(buf, np.eye(3, dtype=bool))
    >>> read_belt(io.BytesIO(buf.getvalue())).astype(int).tolist()
    [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
    """
    img = np.asarray(image, dtype=bool)
    if img.ndim != 2:
        raise InputError(f"image must be 2-D, got shape {img.shape}")
    h, w = img.shape
    data = f"P4\n{w} {h}\n".encode() + np.packbits(img, axis=1).tobytes()
    if hasattr(path, "write"):
        path.write(data)
    else:
        Path(path).write_bytes(data)


def write_text(path: str | Path | IO[str], image: Any) -> None:
    r"""Write a binary image as text, one line of ``0``/``1`` per row.

    Examples
    --------
    >>> import io, numpy as np
    >>> buf = io.StringIO()
    >>> write_text(buf, np.eye(2, dtype=bool))
    >>> buf.getvalue()
    '10\n01\n'
    """
    img = np.asarray(image, dtype=bool)
    if img.ndim != 2:
        raise InputError(f"image must be 2-D, got shape {img.shape}")
    text = "".join("".join("1" if v else "0" for v in row) + "\n" for row in img)
    if hasattr(path, "write"):
        path.write(text)
    else:
        Path(path).write_text(text)
