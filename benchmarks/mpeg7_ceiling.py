"""How much of an MPEG-7 silhouette a one-lap wrap can show: oracle accuracies.

A taut chain lies on the convex hull, so a taut wrap carries the hull and
nothing else; a hugging chain follows the outline. This script classifies the
exact curves (no chain, no sampling by links, no noise) with the best matcher
we have - 1-NN under the best start point, rotation and mirror image of the
polygon (``ShiftNNClassifier(signal="shape")``) - in the stratified 10 folds
the recognition benchmark uses. What it reaches on the exact hull bounds what
any method can reach on taut wraps with that matcher.

Run: ``.venv/bin/python benchmarks/mpeg7_ceiling.py`` (needs ``../shared/data``).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from scipy.spatial import ConvexHull
from sklearn.model_selection import StratifiedKFold

from tentaclass import ShiftNNClassifier
from tentaclass.geometry import points_to_angles, resample_closed
from tentaclass.shapes import load_mpeg7

MPEG7 = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "mpeg7-part-b"


def curves(outlines, kind: str, n: int, rng) -> np.ndarray:
    """Each outline's hull or outline, ``n`` points from a random start, as angles."""
    out = np.empty((len(outlines), n))
    for i, p in enumerate(outlines):
        c = p[ConvexHull(p).vertices] if kind == "hull" else p
        c = np.roll(c, -rng.integers(len(c)), axis=0)
        out[i] = points_to_angles(resample_closed(c, n))
    return out


def main(folder: Path = MPEG7, points=(64, 256)) -> list[tuple[str, int, float]]:
    """Print (and return) the oracle accuracy of each curve and number of points."""
    if not Path(folder).is_dir():
        sys.exit(f"MPEG-7 data not found at {folder}")
    outlines, labels, _ = load_mpeg7(folder, max_vertices=1000)
    labels = np.asarray(labels)
    rng = np.random.default_rng(0)
    folds = list(StratifiedKFold(10, shuffle=True, random_state=0).split(outlines, labels))
    rows = []
    print("| curve | points | 10-fold accuracy |\n|---|---|---|")
    for kind in ("hull", "outline"):
        for n in points:
            X = curves(outlines, kind, n, rng)
            hits = [
                np.mean(ShiftNNClassifier(signal="shape").fit(X[tr], labels[tr]).predict(X[te])
                        == labels[te])
                for tr, te in folds
            ]  # fmt: skip
            print(f"| exact {kind} | {n} | {100 * np.mean(hits):.1f} % |", flush=True)
            rows.append((kind, n, float(np.mean(hits))))
    return rows


if __name__ == "__main__":
    main()
