"""Figures of wraps: the tentacle on its object, grasping spectra, sampling error.

matplotlib is imported lazily; every function takes ``ax=None`` (a new figure)
and returns its artists, and never calls ``plt.show()``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from .._typing import ArrayLike
from ..shapes import as_outline
from ..wrapping import Wrap

__all__ = ["grasp_spectrum", "plot_capture_error", "plot_grasp_spectra", "plot_wrap"]


def _axes(ax):
    if ax is None:
        import matplotlib.pyplot as plt

        _, ax = plt.subplots()
    return ax


def plot_wrap(w: Wrap, outline: ArrayLike, ax=None, **kwargs: Any) -> dict[str, Any]:
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

    ax = _axes(ax)
    p = as_outline(outline)
    obj = ax.add_patch(Polygon(p, closed=True, facecolor="0.85", edgecolor="0.4", lw=0.8))
    style = {"color": "tab:red", "lw": 1.5, "label": "links"} | kwargs
    (links,) = ax.plot(w.joints[:, 0], w.joints[:, 1], **style)
    joints = ax.scatter(*w.joints[1:].T, s=12, color="tab:red", zorder=3, label="joints")
    contacts = ax.scatter(*w.joints[w.contact].T, s=30, facecolors="none",
                          edgecolors="tab:blue", zorder=4, label="contacts")  # fmt: skip
    (base,) = ax.plot(*w.joints[0], "ks", ms=7, label="base")
    ax.set_aspect("equal")
    ax.autoscale_view()
    return {"object": obj, "links": links, "joints": joints, "contacts": contacts, "base": base}


def grasp_spectrum(q: ArrayLike) -> np.ndarray:
    """``|DFT(E)|`` at ``k = 1..n/2`` with ``E_k = t_k - 2 pi k / n`` (thesis eq 4.5).

    Not start-point or direction normalised beyond the magnitude: partial,
    single and multiple wraps differ in exactly this spectrum.

    Examples
    --------
    >>> bool(np.allclose(grasp_spectrum(np.full(16, np.pi / 8)), 0))
    True
    """
    q = np.asarray(q, float)
    n = q.shape[-1]
    e = np.cumsum(q, axis=-1) - 2 * np.pi * np.arange(1, n + 1) / n
    return np.abs(np.fft.fft(e, axis=-1))[..., 1 : n // 2 + 1]


def plot_grasp_spectra(arrays: Mapping[str, ArrayLike], ax=None, **kwargs: Any) -> list[Any]:
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
    ax = _axes(ax)
    spectra = {k: grasp_spectrum(v) for k, v in arrays.items()}
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
    curves: Mapping[str, tuple[Sequence[float], Sequence[float]]],
    ax=None,
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
    ax = _axes(ax)
    out: dict[str, Any] = {}
    for label, (x, y) in curves.items():
        (out[label],) = ax.plot(x, y, marker=".", label=label, **kwargs)
    for label, xs in (marks or {}).items():
        for j, x in enumerate(xs):
            out[f"mark: {label}" + (f" {j}" if j else "")] = ax.axvline(
                x, color="0.5", ls=":", lw=1)  # fmt: skip
            ax.annotate(label, (x, 1), xycoords=("data", "axes fraction"), fontsize=8,
                        ha="center", va="bottom")  # fmt: skip
    ax.set_xlabel("link length / object size")
    ax.set_ylabel("Hausdorff error / diameter")
    ax.legend()
    return out
