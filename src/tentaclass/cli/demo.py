"""``tentaclass demo``: the thesis's tentacle experiment, done right."""

from __future__ import annotations

from pathlib import Path

import click
import numpy as np

from ..classifiers import FourierClassifier
from ..datasets import thesis_tentacle
from .options import Folder, make_folder, noise_option, random_state_option


def perturbed_variants(
    X: np.ndarray, y: np.ndarray, noise: float, n_noisy: int, seed: int
) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Every start point, both directions, and noisy copies of each array."""
    n = X.shape[1]
    shifts = np.stack([np.roll(X, k, axis=1) for k in range(n)], axis=1)  # (4, n, n)
    starts = shifts.reshape(-1, n)
    y_starts = np.repeat(y, n)
    reverse = -starts[:, ::-1]
    rng = np.random.default_rng(seed)
    noisy = np.repeat(starts, n_noisy, axis=0)
    noisy = noisy + rng.normal(0.0, noise, noisy.shape)
    return {
        "thesis arrays": (X, y),
        "every start point": (starts, y_starts),
        "other direction": (reverse, y_starts),
        f"joint noise {noise:g} rad": (noisy, np.repeat(y_starts, n_noisy)),
    }


def write_wrap_figures(out: Path) -> list[Path]:
    """Figures of the physical side: wraps, grasping spectra, sampling rule."""
    from matplotlib.figure import Figure

    from .. import shapes
    from ..plot.wrapping import plot_capture_error, plot_grasp_spectra, plot_wrap
    from ..wrapping import capture_error, wrap

    paths = []
    sq = shapes.square(4.0)
    angles = np.linspace(0, 2 * np.pi, 10, endpoint=False)
    radii = np.where(np.arange(10) % 2 == 0, 1.0, 0.45)
    star = shapes.polygon(np.stack([radii * np.cos(angles), radii * np.sin(angles)], axis=1))
    fig = Figure(figsize=(14, 5.2), layout="constrained")
    ax = fig.subplots(1, 3)
    plot_wrap(wrap(sq, 16, 1.0), sq, ax=ax[0])
    ax[0].set_title("square 4 x 4, 16 links of 1:\nthe thesis's array")
    plot_wrap(wrap(sq, 16, 1.3, start=0.1, offset=2.0), sq, ax=ax[1])
    ax[1].set_title("base 2 away, 16 links of 1.3:\n1.3 laps")
    plot_wrap(wrap(star, 40, 0.12, mode="hug"), star, ax=ax[2])
    ax[2].set_title("star, 40 links of 0.12 hugging it:\npart of one lap")
    paths.append(out / "wraps.png")
    fig.savefig(paths[-1], dpi=90)

    fig = Figure(figsize=(8, 4), layout="constrained")
    ax = fig.subplots()
    plot_grasp_spectra(
        {
            "partial (0.6 lap)": wrap(sq, 64, 0.15).angles,
            "once": wrap(sq, 64, 0.25).angles,
            "twice": wrap(sq, 64, 0.5).angles,
        },
        ax=ax,
    )
    ax.set_title("grasping spectra of a square, 64 links")
    paths.append(out / "grasp_spectra.png")
    fig.savefig(paths[-1], dpi=90)

    ls = np.unique(np.concatenate([np.linspace(0.05, 1.4, 40), [0.125, 0.25, 0.5, 1.0]]))
    curves = {
        "circle, l / r": (ls, [capture_error(shapes.circle(1.0, 360), x) for x in ls]),
        "square, l / a": (ls, [capture_error(shapes.square(1.0), x) for x in ls]),
        "star (hug), l / outer radius": (
            ls[ls <= 0.9],
            [capture_error(star, x, mode="hug") for x in ls[ls <= 0.9]],
        ),
    }
    fig = Figure(figsize=(8, 4), layout="constrained")
    ax = fig.subplots()
    plot_capture_error(curves, ax=ax, marks={"a/4": [0.25], "a/2": [0.5], "l = r, a": [1.0]})
    ax.set_title("what a chain of links captures (thesis 4.5)")
    paths.append(out / "capture_error.png")
    fig.savefig(paths[-1], dpi=90)
    return paths


@click.command()
@click.option(
    "--out",
    type=Folder(),
    default=Path("out"),
    show_default=True,
    help="Folder for the figures.",
)
@noise_option(0.02, "Joint-noise sigma of the perturbed copies, radians (at most 2*pi).")
@random_state_option("Seed of the perturbed variants.")
@click.option("--no-figures", is_flag=True, help="Skip writing figures.")
def demo(out: Path, noise: float, random_state: int, no_figures: bool) -> None:
    """Train on the thesis's four shapes and classify perturbed variants.

    Prints the thesis arrays' classes and, per kind of perturbation, how many
    variants are classified correctly; writes the thesis's 2 x 2 figure per
    shape (shape, turning function, periodic signal, feature vector) to OUT.
    """
    from rich.console import Console
    from rich.table import Table

    if not no_figures:
        make_folder(out, "--out")
    console = Console()
    for n_links in (16, 64):
        X, y = thesis_tentacle(n_links, return_X_y=True)
        model = FourierClassifier(detrend=True).fit(X, y)
        table = Table(title=f"Thesis shapes, {n_links} links: trained on the 4 arrays")
        for col in ("variants", "arrays", "correct", "accuracy"):
            table.add_column(col, justify="right" if col != "variants" else "left")
        for name, (Xv, yv) in perturbed_variants(X, y, noise, 8, random_state).items():
            pred = model.predict(Xv)
            ok = int(np.sum(pred == yv))
            table.add_row(name, str(len(yv)), str(ok), f"{ok / len(yv):.1%}")
        console.print(table)
        proba = model.predict_proba(X)
        for label, p, truth in zip(model.predict(X), proba.max(axis=1), y, strict=True):
            console.print(f"  {truth:<10} -> {label.upper():<10} (p = {p:.3f})")
    if not no_figures:
        from ..plot.features import plot_thesis_panel

        X, y = thesis_tentacle(16, return_X_y=True)
        for q, name in zip(X, y, strict=True):
            fig = plot_thesis_panel(q, title=f"{name.upper()} (16 links)")
            path = out / f"thesis_{name}.png"
            fig.savefig(path, dpi=100)
            console.print(f"wrote {path}")
        for path in write_wrap_figures(out):
            console.print(f"wrote {path}")
