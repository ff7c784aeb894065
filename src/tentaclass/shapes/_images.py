"""Outlines from images: a binary mask's object, and the MPEG-7 CE-Shape-1 Part B set."""

from __future__ import annotations

import functools
import hashlib
import warnings
from pathlib import Path

import numpy as np

from .._cache import cache_dir as _cache_root
from .._cache import load_npz, save_npz
from .._typing import ArrayLike, FloatArray
from .._validation import as_rectangular_array, check_positive_int
from ..errors import InputError, ShapeError, TentaclassWarning
from ..geometry import resample_closed
from ._outline import as_outline

__all__ = ["from_mask", "load_mpeg7", "read_silhouette"]


def from_mask(image: ArrayLike) -> FloatArray:
    """Outer outline of the largest object in a binary image, with sub-pixel vertices.

    Parameters
    ----------
    image : array_like of shape (rows, cols)
        Foreground is nonzero (or True). Other components (specks) and holes are
        ignored: the outline is the outer boundary of the largest 8-connected
        component, holes filled.

    Returns
    -------
    outline : ndarray of shape (n_points, 2)
        Counter-clockwise, in pixel units, ``x`` = column and ``y`` = -row (the
        image's downward row axis is flipped to give a right-handed frame).

    Raises
    ------
    InputError
        If the image is not 2-D or has no foreground.

    Notes
    -----
    ``skimage.measure.find_contours`` at level 0.5 on the zero-padded mask with
    ``fully_connected='high'`` (foreground pixels that touch diagonally stay
    joined, matching the 8-connected labelling); padding closes contours of
    objects that touch the image border.

    Examples
    --------
    >>> img = np.zeros((5, 6), bool)
    >>> img[1:4, 1:5] = True
    >>> out = from_mask(img)
    >>> float(np.ptp(out[:, 0])), float(np.ptp(out[:, 1]))  # 4 x 3 pixels, half-pixel edges
    (4.0, 3.0)
    """
    from scipy import ndimage
    from skimage import measure

    arr = as_rectangular_array(image, "image")
    if arr.ndim != 2:
        raise ShapeError(f"image must be a 2-D array, got shape {arr.shape}")
    if arr.dtype != bool:
        if not np.issubdtype(arr.dtype, np.number):
            raise InputError(f"image must be numeric or bool, got dtype {arr.dtype}")
        arr = np.nan_to_num(arr.astype(float)) != 0
    if not arr.any():
        raise InputError("image has no foreground pixels: there is no object to outline")
    labels, _ = ndimage.label(arr, structure=np.ones((3, 3), bool))
    sizes = np.bincount(labels.ravel())
    sizes[0] = 0
    k = int(np.argmax(sizes))
    box = ndimage.find_objects(labels, max_label=k)[k - 1]
    padded = np.pad(labels[box] == k, 1)
    # Fill holes: background (4-connected, dual to the 8-connected object) that
    # does not reach the padded border. One labelling; binary_fill_holes is slower.
    bg, _ = ndimage.label(~padded)
    padded |= bg != bg[0, 0]
    contours = measure.find_contours(padded.astype(float), 0.5, fully_connected="high")
    # With holes filled there is one contour: the outer boundary.
    c = max(contours, key=len)
    r0, c0 = box[0].start - 1.0, box[1].start - 1.0
    xy = np.stack([c[:, 1] + c0, -(c[:, 0] + r0)], axis=1)
    return as_outline(xy, "mask outline")


def read_silhouette(path: str | Path) -> np.ndarray:
    """Binary object mask of one MPEG-7 style PNG.

    Converts palette images through their palette, thresholds at half the
    maximum value, and takes as object the side that does not cover the border
    (more than 90 % foreground on the border means the file is stored inverted).

    Raises
    ------
    tentaclass.errors.InputError
        The file is not an image Pillow reads, is damaged, or is too large
        (Pillow's decompression-bomb limit).
    FileNotFoundError, IsADirectoryError, PermissionError
        No file to read at ``path``.
    """
    from PIL import Image

    try:
        with Image.open(path) as im:
            gray = np.asarray(im.convert("L"), dtype=float)
    except (FileNotFoundError, IsADirectoryError, PermissionError):
        raise
    except (OSError, ValueError, Image.DecompressionBombError) as exc:
        raise InputError(f"{path}: cannot read the image ({type(exc).__name__}: {exc})") from None
    top = gray.max()
    mask = gray > top / 2 if top > 0 else np.zeros(gray.shape, bool)
    border = np.concatenate([mask[0], mask[-1], mask[1:-1, 0], mask[1:-1, -1]])
    if border.mean() > 0.9:
        mask = ~mask
    return mask


def _cache_file(cache_dir: Path, files: list[Path], max_vertices: int | None) -> Path:
    """The outline cache's file: keyed on the files, ``max_vertices`` and the package version."""
    from .. import __version__

    h = hashlib.sha1(f"v1 {__version__} {max_vertices}".encode())
    for f in files:
        st = f.stat()
        h.update(f"{f.resolve()} {st.st_size} {st.st_mtime_ns}".encode())
    return cache_dir / f"mpeg7-{h.hexdigest()[:16]}.npz"


def _decode(
    files: list[Path], max_vertices: int | None
) -> tuple[list[np.ndarray | None], list[str]]:
    """Outlines of the readable files (None for the others), and what went wrong."""
    outlines: list[np.ndarray | None] = []
    bad: list[str] = []
    for f in files:
        try:
            outline = from_mask(read_silhouette(f))
        except (OSError, InputError) as exc:  # unreadable, truncated or empty image
            bad.append(f"{f.name} ({exc})")
            outlines.append(None)
            continue
        if max_vertices is not None and len(outline) > max_vertices:
            outline = as_outline(resample_closed(outline, max_vertices), f.name)
        outlines.append(outline)
    return outlines, bad


@functools.lru_cache(maxsize=4)
def _load_cached(
    folder: str, fingerprint: str, max_vertices: int | None, cache_dir: str | None
) -> tuple[tuple[np.ndarray, ...], tuple[tuple[str, ...], tuple[str, ...]], tuple[str, ...]]:
    files = sorted(Path(folder).glob("*.png"), key=lambda p: p.name.lower())
    store = _cache_file(Path(cache_dir), files, max_vertices) if cache_dir else None
    bad: list[str] = []
    stored = load_npz(store, "xy", "cuts") if store is not None else None
    if stored is not None:
        xy, cuts = stored
        decoded: list[np.ndarray | None] = [*np.split(xy, cuts[1:-1])]
    else:
        decoded, bad = _decode(files, max_vertices)
        if store is not None and decoded and not bad:
            cuts = np.cumsum([0] + [len(o) for o in decoded if o is not None])
            save_npz(store, xy=np.concatenate([o for o in decoded if o is not None]), cuts=cuts)
    kept = [(f, o) for f, o in zip(files, decoded, strict=True) if o is not None]
    for _, o in kept:
        o.setflags(write=False)
    names = tuple(f.name for f, _ in kept)
    labels = tuple(f.stem.rsplit("-", 1)[0] for f, _ in kept)
    return tuple(o for _, o in kept), (labels, names), tuple(bad)


def _fingerprint(folder: Path) -> str:
    """Names, sizes and modification times of the folder's images."""
    h = hashlib.sha1()
    for f in sorted(folder.glob("*.png")):
        st = f.stat()
        h.update(f"{f.name} {st.st_size} {st.st_mtime_ns}".encode())
    return h.hexdigest()


def load_mpeg7(
    folder: str | Path,
    *,
    max_vertices: int | None = None,
    cache: bool | str | Path = True,
) -> tuple[list[FloatArray], np.ndarray, list[str]]:
    """Outlines and class labels of MPEG-7 CE-Shape-1 Part B (1400 silhouettes, 70 classes).

    Parameters
    ----------
    folder : path
        Directory of ``<class>-<index>.png`` files. The class is the file name up
        to its last ``-``, kept as it is (case and zero padding differ between
        classes: ``Bone``, ``HCircle``, ``brick-01``, ``device9-1``).
    max_vertices : int, optional
        Resample outlines with more vertices to this many, equally spaced by arc
        length (:func:`tentaclass.resample_closed`).
    cache : bool or path, default=True
        Keep the decoded outlines in an ``.npz`` file (True: under
        ``$XDG_CACHE_HOME/tentaclass`` or ``~/.cache/tentaclass``; a path: in that
        directory; False: decode every time). The cache key covers every file's
        path, size and modification time and the package version, so edited
        files are decoded again, and so are all after an upgrade.

    Returns
    -------
    outlines : list of ndarray of shape (n_points_i, 2)
        Read-only counter-clockwise outlines in pixel units (see :func:`from_mask`).
    labels : ndarray of str, shape (n_shapes,)
    names : list of str
        File names, sorted case-insensitively.

    Warns
    -----
    TentaclassWarning
        Listing the images that could not be read or hold no object; they are
        left out and the others are returned.

    Notes
    -----
    Decoding all 1400 images takes about 10 s; results are also kept in memory
    per folder (and its files' names, sizes and modification times),
    ``max_vertices`` and ``cache``.
    """
    path = Path(folder).expanduser().resolve()
    if not path.is_dir():
        raise InputError(f"MPEG-7 folder {str(folder)!r} does not exist or is not a directory")
    if max_vertices is not None:
        max_vertices = check_positive_int(max_vertices, "max_vertices", minimum=3)
    if cache is True:
        cache_dir: str | None = str(_cache_root())
    elif cache is False or cache is None:
        cache_dir = None
    else:
        cache_dir = str(Path(cache).expanduser().resolve())
    outlines, (labels, names), bad = _load_cached(
        str(path), _fingerprint(path), max_vertices, cache_dir
    )
    if bad:
        warnings.warn(
            f"load_mpeg7 skipped {len(bad)} unreadable image(s) in {str(path)!r}: "
            + "; ".join(bad),
            TentaclassWarning,
            stacklevel=2,
        )
    if not outlines:
        what = "no readable .png files" if bad else "no .png files"
        raise InputError(f"{what} found in {str(path)!r}")
    return list(outlines), np.array(labels), list(names)
