"""Figures of joint-angle arrays: the thesis's 2 x 2 panel and its parts.

matplotlib is imported lazily; every function takes an optional ``ax`` and
returns the artists it drew, never calling ``plt.show()``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .._typing import ArrayLike
from .._validation import as_angle_array
from ..errors import ShapeError
from ..features import fourier_features, periodic_signal, turning_function
from ..geometry import angles_to_points
from ._axes import axes_or_new, without_rounding_noise

__all__ = [
    "plot_features",
    "plot_periodic_signal",
    "plot_shape",
    "plot_thesis_panel",
    "plot_turning",
]


def _one_on(q: ArrayLike, ax: Any) -> tuple[np.ndarray, Any]:
    """The one joint-angle array to draw, and the axes to draw it on (new for ``None``)."""
    q = as_angle_array(q, "q")
    if q.ndim != 1:
        raise ShapeError(
            f"plotting takes one joint-angle array of shape (n_joints,), got {q.shape}"
        )
    return q, axes_or_new(ax)


def _label(ax: Any, x: str, y: str, title: str) -> None:
    ax.set_xlabel(x)
    ax.set_ylabel(y)
    ax.set_title(title)


def plot_shape(q: ArrayLike, ax: Any = None, **kwargs: Any) -> list:
    """Draw the chain traced by the joint angles (unit links); returns the lines."""
    q, ax = _one_on(q, ax)
    p = angles_to_points(q)
    kwargs.setdefault("marker", "o")
    lines = ax.plot(p[:, 0], p[:, 1], **kwargs)
    ax.plot(p[:1, 0], p[:1, 1], "s", color="black", label="base")
    ax.set_aspect("equal", adjustable="datalim")
    _label(ax, "x [link lengths]", "y [link lengths]", "shape")
    return lines


def plot_turning(q: ArrayLike, ax: Any = None, **kwargs: Any) -> list:
    """Draw the turning function t_k as a step plot; returns the lines."""
    q, ax = _one_on(q, ax)
    lines = ax.step(np.arange(1, q.size + 1), turning_function(q), where="post", **kwargs)
    _label(ax, "link k", "t_k [rad]", "turning function")
    return lines


def plot_periodic_signal(q: ArrayLike, ax: Any = None, **kwargs: Any) -> list:
    """Draw the periodic signal E_k = t_k - 2 pi k / n (eq 4.5); returns the lines."""
    q, ax = _one_on(q, ax)
    e = without_rounding_noise(periodic_signal(q), 2 * np.pi)
    lines = ax.plot(np.arange(1, q.size + 1), e, marker=".", **kwargs)
    ax.axhline(0, color="grey", lw=0.5)
    if not e.any():  # a regular polygon: show the zero line on a readable scale
        ax.set_ylim(-1, 1)
    _label(ax, "link k", "E_k [rad]", "periodic signal")
    return lines


def plot_features(q: ArrayLike, ax: Any = None, **kwargs: Any) -> Any:
    """Bar chart of the Fourier features |DFT(E)|_k; returns the bar container."""
    q, ax = _one_on(q, ax)
    f = without_rounding_noise(fourier_features(q), 2 * np.pi * q.size)
    bars = ax.bar(np.arange(1, f.size + 1), f, **kwargs)
    if not f.any():  # a regular polygon: every feature is zero
        ax.set_ylim(0, 1)
        ax.text(0.5, 0.5, "all zero", transform=ax.transAxes, ha="center", color="0.4")
    _label(ax, "frequency k", "|DFT(E)|", "feature vector")
    return bars


def plot_thesis_panel(q: ArrayLike, title: str = "", fig: Any = None) -> Any:
    """The thesis's 2 x 2 figure: shape, turning function, periodic signal, features.

    Parameters
    ----------
    q : array_like of shape (n_joints,)
    title : str, default=""
        Figure title, e.g. the class name.
    fig : matplotlib.figure.Figure, optional
        Figure to draw into; a new one (not registered with pyplot) by default.

    Returns
    -------
    fig : matplotlib.figure.Figure
    """
    if fig is None:
        from matplotlib.figure import Figure

        fig = Figure(figsize=(9, 7), layout="constrained")
    axes = fig.subplots(2, 2)
    plot_shape(q, axes[0, 0])
    plot_turning(q, axes[0, 1])
    plot_periodic_signal(q, axes[1, 0])
    plot_features(q, axes[1, 1])
    if title:
        fig.suptitle(title)
    return fig
