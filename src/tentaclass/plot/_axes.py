"""The one convention of every figure: ``ax=None`` makes a new figure."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..errors import InputError

if TYPE_CHECKING:
    from matplotlib.axes import Axes


def axes_or_new(ax: Axes | None) -> Axes:
    """``ax``, or the axes of a new pyplot figure when ``ax`` is None."""
    if ax is None:
        import matplotlib.pyplot as plt

        _, ax = plt.subplots()
    return ax


def without_rounding_noise(values: np.ndarray, scale: float) -> np.ndarray:
    """``values`` with entries below ``1e-9 * scale`` set to 0.

    Exact zeros (a circle's features) come out of floating point as 1e-15
    noise; drawn as they are, an autoscaled axis shows the noise as data.
    """
    return np.where(np.abs(values) < 1e-9 * scale, 0.0, values)


def check_wrap(w: object, name: str = "w") -> None:
    """Refuse a ``w`` that is not a :class:`~tentaclass.Wrap` (or a grasp, which is one)."""
    from ..wrapping import Wrap

    if not isinstance(w, Wrap):
        raise InputError(f"{name} must be a Wrap (from wrap or grasp), got {type(w).__name__}")
