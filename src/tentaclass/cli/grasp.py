"""``tentaclass grasp``: close a simulated tentacle on an object in MuJoCo, print its angles."""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING

import click
import numpy as np

from ..errors import InputError, TentaclassError
from .options import OutputFile, finite, json_option, note, object_options, placement_options
from .wrap import _outline

if TYPE_CHECKING:
    from ..physics import PhysicalGrasp

#: Most frames an animation gets (the recorded ones are thinned to this).
MAX_FRAMES = 80


def _save_figures(
    g: PhysicalGrasp, outline: np.ndarray, plot: Path | None, gif: Path | None
) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..plot.physics import animate_grasp, plot_grasp

    title = f"{len(g.angles)} links, {g.laps:.2f} laps" + ("" if g.complete else " (incomplete)")
    if plot is not None:
        fig, ax = plt.subplots(figsize=(5, 5))
        plot_grasp(g, outline, ax=ax)
        ax.set_title(title)
        fig.savefig(plot, dpi=120, bbox_inches="tight")
        plt.close(fig)
    if gif is not None:
        keep = np.unique(np.linspace(0, len(g.frames) - 1, min(MAX_FRAMES, len(g.frames))).round())
        thin = type(g)(**{**g.__dict__, "frames": g.frames[keep.astype(int)]})
        fig, ax = plt.subplots(figsize=(4, 4))
        anim = animate_grasp(thin, outline, ax=ax)
        ax.set_title(title)
        anim.save(gif, writer="pillow", fps=20, dpi=80)
        plt.close(fig)


@click.command()
@object_options("grasp")
@click.option("--links", type=click.IntRange(min=1), default=16, show_default=True)
@click.option("--link-length", type=click.FloatRange(min=0, min_open=True), callback=finite,
              help="Link length (default: the perimeter over the number of links).")  # fmt: skip
@placement_options
@click.option("--thickness", type=click.FloatRange(min=0, min_open=True), callback=finite,
              help="Link diameter (default a tenth of a link).")  # fmt: skip
@click.option("--friction", type=click.FloatRange(min=0), default=0.0, show_default=True,
              callback=finite)  # fmt: skip
@click.option("--plot", "plot", type=OutputFile(figure=True),
              help="Save the final pose with its contacts (PNG, PDF, SVG).")  # fmt: skip
@click.option("--gif", type=OutputFile(suffixes=(".gif",)),
              help="Save an animation of the chain closing (GIF).")  # fmt: skip
@json_option
def grasp(shape: str | None, size: str | None, vertices: str | None, mask: Path | None,
          links: int, link_length: float | None, start: float, direction: str, offset: float,
          thickness: float | None, friction: float, plot: Path | None, gif: Path | None,
          as_json: bool) -> None:  # fmt: skip
    """Close a simulated tentacle of LINKS links on an object and print its joint angles.

    The chain unrolls link after link in MuJoCo, each link curling until a
    contact stops it. The angles are printed space-separated, as `tentaclass
    classify` reads them, followed by the grasp state read back from the
    angles alone. Needs the physics extra (pip install 'tentaclass[physics]').
    """
    from .._validation import check_reach
    from ..manipulator import PlanarChain
    from ..wrapping import grasp_state

    try:
        from ..physics import grasp as do_grasp
        from ..physics._model import check_chain_depth

        check_chain_depth(links)

        outline = _outline(shape, size, vertices, mask)
        if link_length is None:
            perimeter = float(np.sum(np.hypot(*(np.roll(outline, -1, axis=0) - outline).T)))
            link_length = perimeter / links
        check_reach(offset, links, link_length)  # wrap's rule: the library says "incomplete"
        g = do_grasp(
            outline, PlanarChain([link_length] * links), start=start, direction=direction,
            offset=offset, thickness=thickness, friction=friction, frames=2 if gif else 0,
        )  # fmt: skip
        if not np.all(np.isfinite(g.angles)):  # the library flags it: say why, not "NaN"
            raise InputError(f"the grasp failed: {g.reason}")
        state = grasp_state(g.angles)
        if plot is not None or gif is not None:
            _save_figures(g, outline, plot, gif)
    except ImportError as exc:
        raise click.ClickException(str(exc).splitlines()[0]) from None
    except (TentaclassError, ValueError, OSError) as exc:
        raise click.UsageError(str(exc).splitlines()[0] if str(exc) else repr(exc)) from None
    if as_json:
        click.echo(json.dumps({
            "angles": g.angles.tolist(), "joints": g.joints.tolist(),
            "contact": g.contact.tolist(), "link_length": link_length, "laps": g.laps,
            "offset_links": g.offset_links, "complete": g.complete, "reason": g.reason,
            "sim_time": g.sim_time,
            "grasp": {"state": state.state.item(), "laps": float(state.laps),
                      "offset_links": int(state.offset_links)},
        }))  # fmt: skip
        return
    click.echo(" ".join(f"{a:.10g}" for a in g.angles))
    remark = "" if g.complete else f" (incomplete: {g.reason})"
    note(f"grasp: {state.state.item()}, {float(state.laps):.2f} laps, offset "
         f"{int(state.offset_links)} links, {g.sim_time:.2f} s simulated{remark}")  # fmt: skip
