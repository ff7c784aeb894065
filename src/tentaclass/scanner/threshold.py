"""Which pixels are object: binary rows, a fixed grey level or a per-column background.

A line camera gives grey levels; the belt is the majority of every column,
objects differ from it by a contrast well above the sensor noise, either
darker (``polarity="dark"``: dark objects on a light belt, or a backlit
belt) or lighter (``"light"``). :func:`choose_threshold` picks what is not
given from the first rows of a stream:

- the noise is the scaled median absolute difference of neighbouring pixels;
- the polarity is the side whose deviations reach farthest (ties: ``dark``);
- the contrast is half the way from the belt to the farthest deviation on
  that side, at least six times the noise (and at least one grey level for
  integer data); with no deviation beyond that (no object in the first rows),
  a quarter of the belt level, and the polarity ``dark``;
- the belt level of each column is the mean of its pixels that are not
  object (:func:`belt_levels`);
- the threshold is ``"fixed"`` (one level for the whole line) when the belt
  levels of the columns differ by less than half the contrast, else
  ``"adaptive"``: each column keeps a running estimate of its belt level
  (updated by ``rate`` from every pixel not taken as object), so that uneven
  illumination across the line, and slow drift along it, do not matter.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from ..errors import InputError

__all__ = ["POLARITIES", "THRESHOLD_MODES", "Threshold", "belt_levels", "choose_threshold"]

POLARITIES: tuple[str, ...] = ("auto", "dark", "light")
"""Polarity options: chosen from the data, dark objects, light objects."""
THRESHOLD_MODES: tuple[str, ...] = ("auto", "binary", "fixed", "adaptive")
"""Threshold options besides a number (a fixed level)."""


@dataclass(frozen=True)
class Threshold:
    """The rule that says which pixels are object.

    Attributes
    ----------
    mode : {"binary", "fixed", "adaptive"}
        ``binary``: rows of 0/1 (or bool), object where 1 (``light``) or 0
        (``dark``); ``fixed``: beyond ``level``; ``adaptive``: beyond the
        running belt level of the column by more than ``contrast``.
    polarity : {"dark", "light"}
        Objects darker or lighter than the belt.
    level : float
        The fixed level (``fixed``; 0.5 for ``binary``), else the median belt level.
    contrast : float
        Distance from the belt level (``adaptive``; for ``fixed``, from the
        median belt level to ``level``).
    background : tuple of 2 floats
        Lowest and highest belt level over the columns, from the first rows.
    rate : float
        Update rate of the running belt level per row (``adaptive``).
    """

    mode: str
    polarity: str
    level: float
    contrast: float
    background: tuple[float, float]
    rate: float = 0.02

    def describe(self) -> str:
        """One line for people, e.g. ``"dark objects, below 118.5 (fixed)"``.

        Examples
        --------
        >>> Threshold("fixed", "dark", 118.5, 60.0, (178.0, 179.0)).describe()
        'dark objects, below 118.5 (fixed threshold)'
        """
        side = "below" if self.polarity == "dark" else "above"
        if self.mode == "binary":
            one = int(self.polarity == "light")
            return f"{self.polarity} objects, binary rows (object = {one})"
        if self.mode == "fixed":
            return f"{self.polarity} objects, {side} {self.level:.6g} (fixed threshold)"
        lo, hi = self.background
        return (
            f"{self.polarity} objects, {side} the belt level of each column by more than "
            f"{self.contrast:.6g} (adaptive threshold; belt {lo:.6g} to {hi:.6g})"
        )

    def to_dict(self) -> dict[str, Any]:
        """Plain dict for JSON."""
        d = asdict(self)
        d["background"] = list(self.background)
        return d


def check_options(threshold: Any, polarity: Any, contrast: Any) -> None:
    """Validate the threshold options of a scanner."""
    if isinstance(threshold, str):
        if threshold not in THRESHOLD_MODES:
            raise InputError(
                f"threshold must be a number or one of {list(THRESHOLD_MODES)}, got {threshold!r}"
            )
    elif isinstance(threshold, bool) or not isinstance(threshold, int | float | np.number):
        raise InputError(f"threshold must be a number or a string, got {threshold!r}")
    elif not np.isfinite(threshold):
        raise InputError(f"threshold must be finite, got {threshold!r}")
    if polarity not in POLARITIES:
        raise InputError(f"polarity must be one of {list(POLARITIES)}, got {polarity!r}")
    if contrast is not None and (
        isinstance(contrast, bool)
        or not isinstance(contrast, int | float | np.number)
        or not contrast > 0
        or not np.isfinite(contrast)
    ):
        raise InputError(f"contrast must be a positive number, got {contrast!r}")


def choose_threshold(
    rows: Any,
    threshold: Any = "auto",
    polarity: str = "auto",
    contrast: float | None = None,
    rate: float = 0.02,
) -> Threshold:
    """Fill in the threshold options not given from the first rows of a stream.

    Parameters
    ----------
    rows : array_like of shape (n_rows, width)
        The first rows (numbers; validated by the caller).
    threshold : "auto", "binary", "fixed", "adaptive" or float
        ``"auto"``: ``binary`` if the rows hold only 0 and 1, else ``fixed``
        or ``adaptive`` as the illumination requires; a number: that fixed level.
    polarity : {"auto", "dark", "light"}
    contrast : float, optional
        Distance from the belt level an object pixel must have.
    rate : float
        Update rate of the running belt level (adaptive).

    Returns
    -------
    Threshold

    Examples
    --------
    A light belt (200) with a dark object (40), lit unevenly (+0 to +120):

    >>> import numpy as np
    >>> rows = np.full((8, 12), 200.0) + np.linspace(0, 120, 12)
    >>> rows[2:5, 3:6] = 40
    >>> t = choose_threshold(rows)
    >>> t.mode, t.polarity, round(t.contrast, 1)
    ('adaptive', 'dark', 107.3)
    >>> choose_threshold(rows > 100).mode   # 0/1 data
    'binary'
    """
    x = np.asarray(rows)
    is_int = x.dtype.kind in "biu"
    values01 = is_int and x.size and int(x.min()) >= 0 and int(x.max()) <= 1
    if threshold == "binary" or (threshold == "auto" and values01):
        pol = "light" if polarity == "auto" else polarity
        return Threshold("binary", pol, 0.5, 0.5, (0.0, 0.0), rate)
    xf = x.astype(np.float64)
    dev = xf - np.median(xf, axis=0)
    # noise from neighbouring pixels of a row: object edges are a minority there
    step = np.abs(np.diff(xf, axis=1)) if xf.shape[1] > 1 else np.abs(dev)
    sigma = 1.4826 / np.sqrt(2.0) * float(np.median(step))
    floor = max(6.0 * sigma, 1.0 if is_int else 0.0)
    dark_reach = float(np.max(-dev, initial=0.0))
    light_reach = float(np.max(dev, initial=0.0))
    if polarity == "auto":
        polarity = "light" if light_reach > dark_reach else "dark"
    reach = light_reach if polarity == "light" else dark_reach
    if contrast is None:
        if reach > floor:
            contrast = max(floor, 0.5 * reach)
        else:
            # no object in sight: a quarter of the belt level (a 12-bit camera's
            # data in uint16 would never reach a share of the type's range)
            contrast = max(floor, 0.25 * abs(float(np.median(xf))))
    bg = belt_levels(xf, polarity, float(contrast))
    glob = float(np.median(bg))
    sign = -1.0 if polarity == "dark" else 1.0
    background = (float(bg.min()), float(bg.max()))
    if not isinstance(threshold, str):
        level = float(threshold)
        return Threshold("fixed", polarity, level, abs(level - glob), background, rate)
    uneven = background[1] - background[0] > 0.5 * contrast
    if threshold == "adaptive" or (threshold == "auto" and uneven):
        return Threshold("adaptive", polarity, glob, float(contrast), background, rate)
    return Threshold("fixed", polarity, glob + sign * contrast, float(contrast), background, rate)


def belt_levels(rows: np.ndarray, polarity: str, contrast: float) -> np.ndarray:
    """Belt level of each column: the mean of its pixels that are not object.

    A pixel is object when it lies beyond its column's 80th percentile (dark
    objects; 20th for light ones) by more than ``contrast``, so that objects
    may cover most of a column; a column with no belt pixel gets the median
    level of the others.

    Examples
    --------
    >>> import numpy as np
    >>> rows = np.array([[10.0, 20.0], [10.0, 200.0], [12.0, 22.0]])
    >>> belt_levels(rows, "light", 50.0).tolist()
    [10.666666666666666, 21.0]
    """
    x = np.asarray(rows, dtype=np.float64)
    dev = x - np.percentile(x, 20.0 if polarity == "light" else 80.0, axis=0)
    belt = (dev <= contrast) if polarity == "light" else (dev >= -contrast)
    count = belt.sum(axis=0)
    total = np.where(belt, x, 0.0).sum(axis=0)
    levels = total / np.maximum(count, 1)
    if not count.all():
        levels[count == 0] = np.median(levels[count > 0]) if count.any() else np.median(x)
    return levels
