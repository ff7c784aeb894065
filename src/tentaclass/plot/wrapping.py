"""Figures of wraps: the tentacle on its object, grasping spectra, sampling error.

matplotlib is imported lazily; every function takes ``ax`` (None: a new figure)
and returns its artists, and never calls ``plt.show()``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from .._typing import ArrayLike
from .._validation import as_float_array
from ..errors import InputError
from ..features import fourier_features
from ..shapes import as_outline
from ..wrapping import Wrap
from ._axes import axes_or_new, check_wrap

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = ["grasp_spectrum", "plot_capture_error", "plot_grasp_spectra", "plot_wrap"]


def plot_wrap(w: Wrap, outline: ArrayLike, ax: Axes | None = None, **kwargs: Any) -> dict[str, Any]:
    """Draw the object and the chain on it: links, joints, contacts and the base.

    Parameters
    ----------
    w : Wrap
    outline : array_like of shape (n_points, 2)
        The object that was wrapped.
    ax : matplotlib Axes, optional
    **kwargs
        Passed to the links' ``plot`` call (e.g. ``color``, ``lw``).

    Returns
    -------
    artists : dict
        ``"object"`` (Polygon patch), ``"links"`` (Line2D), ``"joints"`` and
        ``"contacts"`` (PathCollection), ``"base"`` (Line2D).

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from tentaclass.shapes import square
    >>> from tentaclass.wrapping import wrap
    >>> art = plot_wrap(wrap(square(4), 12, 1.0, offset=2), square(4))
    >>> sorted(art)
    ['base', 'contacts', 'joints', 'links', 'object']
    """
    from matplotlib.patches import Polygon

    check_wrap(w)
    p = as_outline(outline)
    ax = axes_or_new(ax)
    obj = ax.add_patch(
        Polygon(p, closed=True, facecolor="0.85", edgecolor="0.4", lw=0.8, label="object")
    )
    style: dict[str, Any] = {"color": "tab:red", "lw": 1.5, "label": "links"} | kwargs
    (links,) = ax.plot(w.joints[:, 0], w.joints[:, 1], **style)
    xy, touching = w.joints[1:], w.joints[w.contact]
    joints = ax.scatter(xy[:, 0], xy[:, 1], s=12, color="tab:red", zorder=3, label="joints")
    contacts = ax.scatter(touching[:, 0], touching[:, 1], s=30, facecolors="none",
                          edgecolors="tab:blue", zorder=4, label="contacts")  # fmt: skip
    (base,) = ax.plot(*w.joints[0], "ks", ms=7, label="base")
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.legend(loc="best", fontsize="small")
    return {"object": obj, "links": links, "joints": joints, "contacts": contacts, "base": base}


def grasp_spectrum(q: ArrayLike) -> np.ndarray:
    """``|DFT(E)|`` at ``k = 1..n/2`` with ``E_k = t_k - 2 pi k / n`` (thesis eq 4.5).

    The Fourier features (:func:`tentaclass.fourier_features`) without mapping
    clockwise wraps to counter-clockwise ones: partial, single and multiple
    wraps differ in exactly this spectrum.

    Examples
    --------
    >>> bool(np.allclose(grasp_spectrum(np.full(16, np.pi / 8)), 0))
    True
    """
    return fourier_features(q, canonicalize=False)


def plot_grasp_spectra(
    arrays: Mapping[str, ArrayLike], ax: Axes | None = None, **kwargs: Any
) -> list[Any]:
    """Grouped bar chart of :func:`grasp_spectrum` for several joint-angle arrays.

    Parameters
    ----------
    arrays : mapping of label -> array_like of shape (n_joints,)
        E.g. ``{"partial": q1, "once": q2, "multiple": q3}``, all of one length.
    ax : matplotlib Axes, optional
    **kwargs
        Passed to every ``bar`` call.

    Returns
    -------
    bars : list of BarContainer, one per array.
    """
    if not isinstance(arrays, Mapping):
        raise InputError(
            f"arrays must be a mapping of label -> joint angles, got {type(arrays).__name__}"
        )
    spectra = {k: grasp_spectrum(v) for k, v in arrays.items()}
    ax = axes_or_new(ax)
    width = 0.8 / max(len(spectra), 1)
    out = []
    for i, (label, s) in enumerate(spectra.items()):
        k = np.arange(1, len(s) + 1)
        out.append(ax.bar(k + (i - (len(spectra) - 1) / 2) * width, s, width, label=label,
                          **kwargs))  # fmt: skip
    ax.set_xlabel("frequency k")
    ax.set_ylabel("|DFT(E)|")
    ax.legend()
    return out


def plot_capture_error(
    curves: Mapping[str, tuple[ArrayLike, ArrayLike]],
    ax: Axes | None = None,
    marks: Mapping[str, Sequence[float]] | None = None,
    **kwargs: Any,
) -> dict[str, Any]:
    """Capture error against link length, one line per outline.

    Parameters
    ----------
    curves : mapping of label -> (link_lengths, errors)
        Link lengths in units of the outline's size (circle: radius, square: side).
    ax : matplotlib Axes, optional
    marks : mapping of label -> link lengths, optional
        Vertical guide lines (the thesis's rules, e.g. ``{"r": [1.0]}``).

    Returns
    -------
    artists : dict of label -> Line2D (guides under ``"mark: <label>"``).
    """
    if not isinstance(curves, Mapping):
        raise InputError(
            f"curves must be a mapping of label -> (link_lengths, errors), got "
            f"{type(curves).__name__}"
        )
    lines = {}
    for label, curve in curves.items():
        if not (isinstance(curve, Sequence) and len(curve) == 2):
            raise InputError(f"curves[{label!r}] must be a pair (link_lengths, errors)")
        x = as_float_array(curve[0], f"curves[{label!r}] link_lengths", allow_nonfinite=True)
        y = as_float_array(curve[1], f"curves[{label!r}] errors", allow_nonfinite=True)
        if x.ndim != 1 or x.shape != y.shape:
            raise InputError(
                f"curves[{label!r}]: link_lengths and errors must be 1-D arrays of one length, "
                f"got shapes {x.shape} and {y.shape}"
            )
        lines[label] = (x, y)
    ax = axes_or_new(ax)
    out: dict[str, Any] = {}
    for label, (x, y) in lines.items():
        (out[label],) = ax.plot(x, y, marker=".", label=label, **kwargs)
    for label, xs in (marks or {}).items():
        for j, x_mark in enumerate(xs):
            out[f"mark: {label}" + (f" {j}" if j else "")] = ax.axvline(
                x_mark, color="0.5", ls=":", lw=1)  # fmt: skip
            # inside the axes, just below the top: clear of the title above
            ax.annotate(label, (x_mark, 0.98), xycoords=("data", "axes fraction"), fontsize=8,
                        xytext=(3, 0), textcoords="offset points", ha="left", va="top")  # fmt: skip
    ax.set_xlabel("link length / object size")
    ax.set_ylabel("Hausdorff error / diameter")
    ax.legend()
    return out
