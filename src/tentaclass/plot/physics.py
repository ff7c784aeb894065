"""Figures of physical grasps: the final pose with its contacts, and the closing as an animation.

matplotlib is imported lazily; functions take ``ax=None`` (a new figure) and
return their artists, and never call ``plt.show()``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from .._typing import ArrayLike
from .._validation import check_positive_int
from ..shapes import as_outline
from ..wrapping import Wrap
from ._axes import axes_or_new, check_wrap
from .wrapping import plot_wrap

if TYPE_CHECKING:
    from matplotlib.animation import FuncAnimation
    from matplotlib.axes import Axes

__all__ = ["animate_grasp", "plot_grasp"]


def _link_width(ax: Axes, thickness: float) -> float:
    """Line width in points that draws a link ``thickness`` wide in data units."""
    fig = ax.figure
    fig.canvas.draw_idle()
    x0, x1 = ax.get_xlim()
    width_in = ax.get_window_extent().width / fig.dpi
    return max(0.5, thickness / abs(x1 - x0) * width_in * 72)


def plot_grasp(
    g: Wrap, outline: ArrayLike, ax: Axes | None = None, **kwargs: Any
) -> dict[str, Any]:
    """Draw the object and the chain at rest, with its contact points (on :func:`plot_wrap`).

    Parameters
    ----------
    g : PhysicalGrasp or Wrap
        A grasp from :func:`tentaclass.physics.grasp` (a plain :class:`Wrap`
        works too: its contact joints are drawn instead of contact points).
    outline : array_like of shape (n_points, 2)
        The object.
    ax : matplotlib Axes, optional
    **kwargs
        Passed to the links' ``plot`` call (e.g. ``color``).

    Returns
    -------
    artists : dict
        As :func:`~tentaclass.plot.plot_wrap`; ``"contacts"`` marks MuJoCo's
        contact points when the grasp has them.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from tentaclass import wrap
    >>> from tentaclass.shapes import triangle
    >>> art = plot_grasp(wrap(triangle(side=3), 9, 1.0), triangle(side=3))
    >>> art["links"].get_xydata().shape
    (10, 2)
    """
    check_wrap(g, "g")
    ax = axes_or_new(ax)
    p = as_outline(outline)
    j = np.asarray(g.joints)
    lo, hi = np.minimum(p.min(0), j.min(0)), np.maximum(p.max(0), j.max(0))
    pad = 0.08 * float(np.max(hi - lo))
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal")
    thickness = float(getattr(g, "thickness", 0.0))
    style = {"color": "tab:blue", "solid_capstyle": "round", "alpha": 0.8}
    if thickness > 0:  # draw the links as thick as they are
        style["lw"] = _link_width(ax, thickness)
    art = plot_wrap(g, p, ax=ax, **(style | kwargs))
    art["joints"].set_color("k")
    pts = getattr(g, "contact_points", None)
    if pts is not None and len(pts):  # where MuJoCo's contacts are, not the contact joints
        art["contacts"].set_offsets(np.asarray(pts).reshape(-1, 2))
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    return art


def animate_grasp(
    g: Wrap, outline: ArrayLike, ax: Axes | None = None, interval: int = 40, **kwargs: Any
) -> FuncAnimation:
    """An animation of the chain closing on the object (``g.frames``).

    Parameters
    ----------
    g : PhysicalGrasp
        A grasp recorded with ``frames > 0``.
    outline : array_like of shape (n_points, 2)
    ax : matplotlib Axes, optional
    interval : int, default=40
        Milliseconds between frames.
    **kwargs
        Passed to the links' ``plot`` call.

    Returns
    -------
    animation : matplotlib.animation.FuncAnimation
        Save it with ``animation.save("grasp.gif", writer="pillow")``.

    Raises
    ------
    InputError
        The grasp has no recorded frames.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from tentaclass import PlanarChain
    >>> from tentaclass.physics import grasp
    >>> from tentaclass.shapes import square
    >>> g = grasp(square(4), PlanarChain([1.0] * 16), frames=20)
    >>> anim = animate_grasp(g, square(4))
    >>> html = anim.to_jshtml()  # or anim.save("grasp.gif", writer="pillow")
    >>> len(g.frames) > 2
    True
    """
    from matplotlib.animation import FuncAnimation
    from matplotlib.figure import SubFigure

    from ..errors import InputError

    check_wrap(g, "g")
    frames = np.asarray(getattr(g, "frames", np.zeros((0,))))
    if frames.ndim != 3 or len(frames) == 0:
        raise InputError("the grasp has no frames: run grasp(..., frames=k) with k > 0")
    interval = check_positive_int(interval, "interval")
    ax = axes_or_new(ax)
    art = plot_grasp(g, outline, ax=ax, **kwargs)
    j_all = frames.reshape(-1, 2)
    lo, hi = np.minimum(j_all.min(0), ax.get_xlim()[0]), j_all.max(0)
    p = as_outline(outline)
    lo, hi = np.minimum(lo, p.min(0)), np.maximum(hi, p.max(0))
    pad = 0.05 * float(np.max(hi - lo))
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    art["contacts"].set_visible(False)

    def update(i: int) -> tuple[Any, Any, Any]:
        f = frames[i]
        art["links"].set_data(f[:, 0], f[:, 1])
        art["joints"].set_offsets(f)
        art["contacts"].set_visible(i == len(frames) - 1)
        return art["links"], art["joints"], art["contacts"]

    fig = ax.figure
    if isinstance(fig, SubFigure):  # the animation redraws and saves the whole figure
        fig = fig.figure
    return FuncAnimation(fig, update, frames=len(frames), interval=interval, blit=False)
