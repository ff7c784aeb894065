"""The figures of docs/physics.md: still grasps with their contacts, and an animation.

Run: ``python benchmarks/physics_figures.py`` (writes docs/images/physics_*.png/gif).
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from tentaclass import PlanarChain, grasp_state, wrap
from tentaclass.physics import grasp
from tentaclass.plot.physics import animate_grasp, plot_grasp
from tentaclass.shapes import circle, polygon, square

OUT = Path(__file__).resolve().parents[1] / "docs" / "images"
C_SHAPE = polygon([(0, 0), (6, 0), (6, 1), (2, 1), (2, 3), (4, 3), (4, 4), (0, 4)])


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    cases = [
        ("square, 16 links", square(3.6), 1.0, 16, 0.1),
        ("circle, 16 links", circle(16 / (2 * np.pi)), 1.0, 16, 0.0),
        ("C, links 0.5 (fit the opening)", C_SHAPE, 0.5, 30, 0.02),
        ("C, links 3.5 (bridge it)", C_SHAPE, 3.5, 6, 0.02),
    ]
    fig, axes = plt.subplots(2, 4, figsize=(16, 8))
    for (title, o, ln, n, st), top, bottom in zip(cases, axes[0], axes[1], strict=True):
        g = grasp(o, PlanarChain([ln] * n), start=st)
        plot_grasp(g, o, ax=top)
        top.set_title(f"physical: {title}\n{grasp_state(g.angles).state.item()}, "
                      f"{g.laps:.2f} laps")  # fmt: skip
        w = wrap(o, n, ln, start=st, mode="hug")
        plot_grasp(w, o, ax=bottom, color="tab:orange")
        note = "" if w.complete else " (jammed)"
        bottom.set_title(f"geometric hug wrap\n{w.laps:.2f} laps{note}")
    fig.tight_layout()
    fig.savefig(OUT / "physics_grasps.png", dpi=70)
    plt.close(fig)

    g = grasp(square(3.6), PlanarChain([1.0] * 16), start=0.1, frames=2)
    keep = np.unique(np.linspace(0, len(g.frames) - 1, 60).round()).astype(int)
    g = type(g)(**{**g.__dict__, "frames": g.frames[keep]})
    fig, ax = plt.subplots(figsize=(4, 4))
    anim = animate_grasp(g, square(3.6), ax=ax)
    ax.set_title("16 links closing on a square")
    anim.save(OUT / "physics_square.gif", writer="pillow", fps=15, dpi=60)
    plt.close(fig)


if __name__ == "__main__":
    main()
