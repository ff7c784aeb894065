"""Build the bundled default models: src/tentaclass/data/default-<n_links>.tcm.

Deterministic: the same code gives the same files. For each chain length,
wraps of the four thesis classes (square, circle, equilateral triangle,
rectangles of aspect 2-4) by one chain of unit links are generated with
``tentaclass.datasets.chain_wraps`` (0.45-3.2 laps, a stand-off of 0-3.5
links, joint noise up to 0.025 rad, random rotation, start and direction,
taut and hug), a recogniser is trained on them, and a rejection threshold is
set on a held-out set of wraps (1 % false rejections).

Usage::

    python benchmarks/build_default_models.py            # all bundled lengths
    python benchmarks/build_default_models.py --links 16 # one
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
from threadpoolctl import threadpool_limits

from tentaclass.datasets import chain_wraps
from tentaclass.io import rejection_threshold, save_model
from tentaclass.shapes import circle, rectangle, square, triangle

LINKS = (16, 32, 40, 64)
OUT = Path(__file__).resolve().parents[1] / "src" / "tentaclass" / "data"
SETTINGS = {
    "link_length": 1.0,
    "laps": (0.45, 3.2),
    "offset": (0.0, 3.5),  # a distance; the links are of unit length
    "noise": (0.0, 0.025),
    "mode": "both",
}
#: Training wraps per class (short chains see less of each lap, so get more).
PER_CLASS = {16: 1600}
DEFAULT_PER_CLASS = 400


def thesis_outlines() -> tuple[list[np.ndarray], np.ndarray]:
    """The thesis classes as outlines, repeated so that each class has 5 of 14."""
    base = [(square(1.0), "square"), (circle(1.0), "circle"), (triangle(side=1.0), "triangle")]
    outlines, labels = [], []
    for o, label in base:
        outlines += [o] * 5
        labels += [label] * 5
    for aspect in (2.0, 2.5, 3.0, 3.5, 4.0):
        outlines.append(rectangle(aspect, 1.0))
        labels.append("rectangle")
    return outlines, np.array(labels)


def recogniser():
    """The recogniser the bundled models use."""
    from sklearn.pipeline import make_pipeline, make_union
    from sklearn.preprocessing import StandardScaler

    from tentaclass.classifiers import PNNClassifier
    from tentaclass.features import AngleSpectrum, FourierFeatures, LastLap

    features = make_union(
        AngleSpectrum(9), make_pipeline(LastLap(), FourierFeatures(8, detrend=True))
    )
    return make_pipeline(features, StandardScaler(), PNNClassifier(spread="auto"))


def training_wraps(outlines, n_links: int, n_wraps: int, seed: int):
    """Half the wraps at stand-offs drawn from the range, half at whole links.

    A base standing exactly on the object or a whole number of links away
    gives arrays of their own (no short first link), so those are drawn too.
    """
    from sklearn.utils import Bunch

    parts = [chain_wraps(outlines, n_links, n_wraps=n_wraps // 2, random_state=seed, **SETTINGS)]
    whole = [k for k in range(int(SETTINGS["offset"][1]) + 1)]
    for k in whole:
        settings = {**SETTINGS, "offset": (float(k), float(k))}
        parts.append(
            chain_wraps(
                outlines,
                n_links,
                n_wraps=max(1, n_wraps // (2 * len(whole))),
                random_state=seed + 100 + k,
                **settings,
            )
        )
    return Bunch(
        data=np.concatenate([p.data for p in parts]),
        outline=np.concatenate([p.outline for p in parts]),
        n_failed=sum(p.n_failed for p in parts),
    )


def build(n_links: int, seed: int = 0):
    """Model and info for one chain length."""
    outlines, labels = thesis_outlines()
    n_wraps = PER_CLASS.get(n_links, DEFAULT_PER_CLASS) // 5  # 5 outlines per class
    train = training_wraps(outlines, n_links, n_wraps, seed)
    model = recogniser().fit(train.data, labels[train.outline])
    held = chain_wraps(outlines, n_links, n_wraps=10, random_state=seed + 1, **SETTINGS)
    accuracy = float(np.mean(model.predict(held.data) == labels[held.outline]))
    info = {
        "chain": {"n_links": n_links, **SETTINGS, "n_wraps": n_wraps, "random_state": seed},
        "classes": sorted(set(labels.tolist())),
        "reject_below": rejection_threshold(model, held.data, 0.01),
        "training": {
            "n_samples": len(train.data),
            "n_failed": train.n_failed,
            "held_out_accuracy": accuracy,
        },
        "description": "The thesis's four classes, for the bundled 'tentaclass classify'.",
    }
    return model, info


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--links", type=int, nargs="*", default=list(LINKS))
    args = parser.parse_args()
    OUT.mkdir(parents=True, exist_ok=True)
    with threadpool_limits(1):
        for n in args.links:
            t0 = time.perf_counter()
            model, info = build(n)
            path = save_model(model, OUT / f"default-{n}.tcm", info=info)
            print(
                f"{path.name}: {info['training']['n_samples']} wraps, held-out accuracy "
                f"{info['training']['held_out_accuracy']:.4f}, reject below "
                f"{info['reject_below']:.3g}, {path.stat().st_size / 1024:.0f} KiB, "
                f"{time.perf_counter() - t0:.0f} s"
            )


if __name__ == "__main__":
    main()
