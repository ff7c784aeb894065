"""The on-disk cache of decoded outlines and generated wraps.

One folder, ``$XDG_CACHE_HOME/tentaclass`` (or ``~/.cache/tentaclass``), and
one way to write to it: a file appears whole or not at all, even when several
processes (pytest-xdist or Dask workers, two shells) fill the same entry at
once.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import Any

import numpy as np


def cache_dir() -> Path:
    """The folder the caches live in (not created here)."""
    return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "tentaclass"


def save_npz(path: Path, **arrays: Any) -> None:
    """Write ``arrays`` to ``path`` (``np.savez``) through a temporary file of its own.

    Each writer has a temporary name of its own in the same folder and renames
    it over ``path`` when it is complete: readers see the old file or the new
    one, never a part of one, and two writers never write into one file.

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> folder = Path(tempfile.mkdtemp())
    >>> save_npz(folder / "a.npz", x=np.arange(3))
    >>> np.load(folder / "a.npz")["x"].tolist(), sorted(p.name for p in folder.iterdir())
    ([0, 1, 2], ['a.npz'])
    """
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}-", suffix=".tmp.npz", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as f:
            np.savez(f, **arrays)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def load_npz(path: Path, *names: str) -> tuple[np.ndarray, ...] | None:
    """The arrays ``names`` of the cache file ``path``, or None if there is none.

    A file removed between the look and the read (another process clearing
    the cache) counts as none.

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> folder = Path(tempfile.mkdtemp())
    >>> load_npz(folder / "a.npz", "x") is None
    True
    >>> save_npz(folder / "a.npz", x=np.arange(3))
    >>> [a.tolist() for a in load_npz(folder / "a.npz", "x")]
    [[0, 1, 2]]
    """
    try:
        with np.load(path, allow_pickle=False) as f:
            return tuple(f[name] for name in names)
    except FileNotFoundError:
        return None
