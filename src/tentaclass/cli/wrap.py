"""``tentaclass wrap``: simulate a tentacle wrapped around an object, print its joint angles."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import click
import numpy as np

from ..errors import TentaclassError
from .options import (
    OutputFile,
    finite,
    image_outline,
    json_option,
    noise_option,
    note,
    object_options,
    placement_options,
    random_state_option,
)


def _numbers(text: str | None, name: str) -> list[float] | None:
    if text is None:
        return None
    try:
        return [float(t) for t in text.replace(",", " ").split()]
    except ValueError:
        raise click.BadParameter(f"{text!r} is not a list of numbers", param_hint=name) from None


def _outline(
    shape: str | None, size: str | None, vertices: str | None, mask: Path | None
) -> np.ndarray:
    from .. import shapes

    if mask is not None:
        if shape is not None:
            raise click.UsageError("give either --shape or --mask, not both")
        if size is not None or vertices is not None:
            flag = "--size" if size is not None else "--vertices"
            raise click.UsageError(f"{flag} does not go with --mask (the image gives the object)")
        try:
            return image_outline(mask)
        except (TentaclassError, ValueError, OSError) as exc:
            # the file's content is bad input, as for the other commands' files: exit code 1
            raise click.ClickException(str(exc).splitlines()[0]) from None
    shape = shape or "square"
    if vertices is not None and shape not in ("polygon", "triangle"):
        raise click.UsageError(f"--vertices is for --shape polygon or triangle, not {shape}")
    if vertices is not None and size is not None:
        raise click.UsageError("give either --size or --vertices, not both")
    if shape in ("polygon", "triangle") and vertices is not None:
        pts = _numbers(vertices, "--vertices") or []
        if len(pts) % 2:
            raise click.BadParameter("needs x,y pairs", param_hint="--vertices")
        xy = np.reshape(np.asarray(pts, dtype=float), (-1, 2))
        return shapes.triangle(xy) if shape == "triangle" else shapes.polygon(xy)
    if shape == "polygon":
        raise click.UsageError("--shape polygon needs --vertices 'x,y x,y x,y ...'")
    dims = _numbers(size, "--size") or [4.0]
    if size is not None and not _numbers(size, "--size"):
        raise click.BadParameter("is empty", param_hint="--size")
    if shape == "rectangle":
        if len(dims) > 2:
            raise click.BadParameter("a rectangle takes 'W' or 'W,H'", param_hint="--size")
        w, h = (dims * 2)[:2] if len(dims) == 1 else dims[:2]
        return shapes.rectangle(w, h if len(dims) > 1 else w / 3)
    if len(dims) != 1:
        raise click.BadParameter(f"{shape} takes one size", param_hint="--size")
    makers: dict[str, Any] = {"square": shapes.square, "circle": shapes.circle,
                              "triangle": lambda s: shapes.triangle(side=s)}  # fmt: skip
    return makers[shape](dims[0])


@click.command()
@object_options("wrap")
@click.option("--links", type=click.IntRange(min=1), default=16, show_default=True)
@click.option("--link-length", type=float, callback=finite, help="Link length (default 1).")
@click.option(
    "--laps",
    type=click.FloatRange(min=0, min_open=True),
    callback=finite,
    help="Choose the link length so the chain turns about this many laps (on a polygon the "
    "turn steps at the corners: the grasp line says the laps reached).",
)
@placement_options
@click.option("--mode", type=click.Choice(["taut", "hug"]), default="taut", show_default=True)
@click.option("--thickness", type=click.FloatRange(min=0), default=0.0, show_default=True,
              callback=finite)  # fmt: skip
@noise_option(0.0, "Joint noise standard deviation (radians, at most 2*pi).")
@random_state_option("Seed of the noise [default: fresh].", default=None)
@click.option("--plot", "plot", type=OutputFile(figure=True),
              help="Save a figure of the wrap (PNG, PDF, SVG).")  # fmt: skip
@json_option
def wrap(shape: str | None, size: str | None, vertices: str | None, mask: Path | None,
         links: int, link_length: float | None, laps: float | None, start: float,
         direction: str, mode: str, offset: float, thickness: float, noise: float,
         random_state: int | None, plot: Path | None, as_json: bool) -> None:  # fmt: skip
    """Wrap a tentacle of LINKS links around an object and print its joint angles.

    The angles are printed space-separated, as `tentaclass classify` reads
    them, followed by the grasp state read back from the angles alone.
    """
    from ..wrapping import grasp_state, link_length_for_laps
    from ..wrapping import wrap as do_wrap

    try:
        outline = _outline(shape, size, vertices, mask)
        kw: dict[str, Any] = {"start": start, "direction": direction, "mode": mode,
                              "offset": offset, "thickness": thickness}  # fmt: skip
        if laps is not None:
            if link_length is not None:
                raise click.UsageError("give either --link-length or --laps, not both")
            if links / laps < 2:
                raise click.BadParameter(
                    f"{links} links cannot close {laps:g} laps (at most {links / 2:g}: "
                    "2 links per lap)",
                    param_hint="--laps",
                )
            try:
                link_length = link_length_for_laps(
                    outline, links, laps, start=start, direction=direction, mode=mode,
                    offset=offset,
                )  # fmt: skip
            except ValueError as exc:  # a usage error, as laps that need more links are
                raise click.BadParameter(str(exc).splitlines()[0], param_hint="--laps") from None
        elif link_length is None:
            link_length = 1.0
        w = do_wrap(outline, links, link_length, noise=noise, random_state=random_state, **kw)
        g = grasp_state(w.angles) if len(w.angles) else None
        if plot is not None:
            import matplotlib

            matplotlib.use("Agg")
            import matplotlib.pyplot as plt

            from ..plot.wrapping import plot_wrap

            fig, ax = plt.subplots(figsize=(5, 5))
            plot_wrap(w, outline, ax=ax)
            ax.set_title(f"{len(w.angles)} links of {link_length:.4g}, {w.laps:.2f} laps")
            fig.savefig(plot, dpi=120, bbox_inches="tight")
            plt.close(fig)
    except (TentaclassError, ValueError, OSError) as exc:
        raise click.UsageError(str(exc).splitlines()[0] if str(exc) else repr(exc)) from None
    state = g.state.item() if g is not None else "partial"
    if as_json:
        click.echo(json.dumps({
            "angles": w.angles.tolist(), "joints": w.joints.tolist(),
            "contact": w.contact.tolist(), "link_length": link_length, "laps": w.laps,
            "offset_links": w.offset_links, "complete": w.complete,
            "grasp": {"state": state,
                      "laps": float(g.laps) if g is not None else 0.0,
                      "offset_links": int(g.offset_links) if g is not None else 0},
        }))  # fmt: skip
        return
    click.echo(" ".join(f"{a:.10g}" for a in w.angles))
    remark = "" if w.complete else " (chain stopped early: no next contact)"
    if g is not None:
        note(f"grasp: {state}, {float(g.laps):.2f} laps, offset {int(g.offset_links)} "
             f"links{remark}")  # fmt: skip
