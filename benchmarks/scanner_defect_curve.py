"""Generated 64 x 64 objects: classification accuracy and the defect recall / false-alarm curve.

The four thesis classes at random positions, rotations and sizes; half of
them damaged with random holes and bites (also broken corners). Sweeping the
decision thresholds of :class:`~tentaclass.scanner.DefectSettings` - the
smallest defect area (``min_area``) and the smallest depth (``min_depth``),
one at a time, the other at its default - traces recall (damaged objects
rejected) against false alarms (clean objects rejected). Run::

    .venv/bin/python benchmarks/scanner_defect_curve.py --n 2000 --out scanner_curve.png
"""

from __future__ import annotations

import argparse
import json

import numpy as np

from tentaclass.scanner import DefectSettings, default_model, inspect_many
from tentaclass.scanner.defects import find_defects
from tentaclass.scanner.descriptors import measure
from tentaclass.scanner.model import crop
from tentaclass.scanner.simulate import make_objects


def rejection_rates(
    data, labels: np.ndarray, settings: list[DefectSettings]
) -> tuple[np.ndarray, np.ndarray]:
    """Recall and false-alarm rate of the defect decision for each of ``settings``."""
    prepared = []
    for grid in data.grids:
        mask, top, left = crop(grid)
        extent = (-top, -left, grid.shape[0] - top, grid.shape[1] - left)
        prepared.append((measure(mask), extent))
    recall, false_alarms = [], []
    for s in settings:
        flagged = np.array(
            [
                bool(find_defects(g, str(label), s, extent=extent))
                for (g, extent), label in zip(prepared, labels, strict=True)
            ]
        )
        recall.append(flagged[data.damaged].mean())
        false_alarms.append(flagged[~data.damaged].mean())
    return np.array(recall), np.array(false_alarms)


def main(n: int = 2000, seed: int = 2024, out: str | None = None) -> dict:
    """Run on ``n`` generated objects; save the curve to ``out`` if given."""
    data = make_objects(n, damaged_fraction=0.5, random_state=seed)
    results = inspect_many(data.grids, default_model())
    predicted = np.array([r.label for r in results])
    rejected = np.array([not r.accept for r in results])
    areas = [1, 2, 3, 4, 6, 8, 12, 16, 24, 32, 48]
    depths = [1.0, 1.25, 1.5, 2.0, 2.5, 3.0, 4.0]
    by_area = rejection_rates(data, predicted, [DefectSettings(min_area=a) for a in areas])
    by_depth = rejection_rates(data, predicted, [DefectSettings(min_depth=d) for d in depths])
    summary = {
        "objects": n,
        "damaged": int(data.damaged.sum()),
        "accuracy": float((predicted == data.target).mean()),
        "accuracy_damaged": float((predicted == data.target)[data.damaged].mean()),
        "recall_default": float(rejected[data.damaged].mean()),
        "false_alarms_default": float(rejected[~data.damaged].mean()),
        "default_min_area": DefectSettings().min_area,
        "default_min_depth": DefectSettings().min_depth,
        "curve_min_area": {
            str(a): [float(r), float(f)] for a, r, f in zip(areas, *by_area, strict=True)
        },
        "curve_min_depth": {
            str(d): [float(r), float(f)] for d, r, f in zip(depths, *by_depth, strict=True)
        },
    }
    if out is not None:
        import matplotlib

        matplotlib.use("Agg")
        from matplotlib.figure import Figure

        fig = Figure(figsize=(5.5, 4.5))
        ax = fig.add_subplot()
        for (rec, fa), values, name, unit in (
            (by_area, areas, "min_area", "px"),
            (by_depth, depths, "min_depth", "px deep"),
        ):
            ax.plot(
                100 * fa, 100 * rec, "o-", ms=3, label=f"{name} {values[0]} ... {values[-1]} {unit}"
            )
            for v, x, y in zip(values, fa, rec, strict=True):
                ax.annotate(
                    f"{v:g}",
                    (100 * x, 100 * y),
                    fontsize=7,
                    xytext=(4, -9),
                    textcoords="offset points",
                )
        ax.plot(
            100 * summary["false_alarms_default"],
            100 * summary["recall_default"],
            "r*",
            ms=12,
            label="default settings",
        )
        ax.axvline(2, color="gray", ls=":", lw=1)
        ax.axhline(95, color="gray", ls=":", lw=1)
        ax.set_xlabel("false alarms: clean objects rejected (%)")
        ax.set_ylabel("recall: damaged objects rejected (%)")
        ax.set_xlim(-0.5, max(10.0, 100 * float(by_depth[1].max()) + 2))
        ax.set_ylim(80, 100.5)
        ax.set_title(f"{n} generated objects, accuracy {100 * summary['accuracy']:.2f}%")
        ax.legend(loc="lower right")
        fig.tight_layout()
        fig.savefig(out, dpi=110)
    print(json.dumps(summary, indent=2))
    return summary


if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--n", type=int, default=2000)
    p.add_argument("--seed", type=int, default=2024)
    p.add_argument("--out", default="scanner_curve.png")
    a = p.parse_args()
    main(a.n, a.seed, a.out)
