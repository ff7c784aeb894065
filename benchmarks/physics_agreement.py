"""Physical grasps (MuJoCo) against geometric hug wraps, and the sim-to-real check.

Run: ``python benchmarks/physics_agreement.py [--mpeg7 200] [--thesis 200] [--jobs 2]``.

1. Agreement: for the four thesis shapes (16 links) and ``--mpeg7`` MPEG-7
   silhouettes (64 links, the link length that closes one hug lap, a random
   start), the physical grasp's joint angles against ``wrap(mode="hug")`` of
   the same chain, start and direction: per joint (|dq|, wrapped to [-pi, pi]),
   laps, and the lap's shape (the largest distance between the two joint
   polylines, rebuilt from the angles alone, in link lengths).
2. Sim-to-real: a ``TentacleClassifier`` trained only on geometric wraps
   (``synthetic_tentacle``) classifies ``--thesis`` random thesis objects from
   their geometric wraps and from their physical grasps; the goal is
   physical accuracy >= 95 % of geometric accuracy.

Prints markdown tables; ``--out FILE`` also writes the numbers as JSON.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np
import shapely

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _timing import markdown_table

from tentaclass import (
    PlanarChain,
    ShiftNNClassifier,
    TentacleClassifier,
    angles_to_points,
    shapes,
    wrap,
)
from tentaclass.datasets import synthetic_tentacle
from tentaclass.physics import grasp_many
from tentaclass.wrapping import closing_link_length

MPEG7 = (Path(__file__).resolve().parents[1] / "../shared/data/mpeg7-part-b").resolve()


def _dq(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    n = min(len(a), len(b))
    return np.abs(np.angle(np.exp(1j * (a[:n] - b[:n]))))


def _shape_gap(a: np.ndarray, b: np.ndarray) -> float:
    """Hausdorff distance between the joint polylines rebuilt from the angles (unit links)."""
    pa, pb = angles_to_points(a), angles_to_points(b)
    return float(shapely.hausdorff_distance(shapely.LineString(pa), shapely.LineString(pb)))


def compare(outlines, n_links, lengths, starts, dirs, jobs):
    """Physical vs geometric hug wraps of each outline; per-row numbers."""
    rows = []
    t0 = time.perf_counter()
    physical = []
    for o, ln, s, d in zip(outlines, lengths, starts, dirs, strict=True):
        physical.append((o, ln, s, d))
    from joblib import Parallel, delayed

    from tentaclass.physics import grasp

    phys = Parallel(n_jobs=jobs)(
        delayed(grasp)(o, PlanarChain([ln] * n_links), start=s, direction=d)
        for o, ln, s, d in physical
    )
    elapsed = time.perf_counter() - t0
    for (o, ln, s, d), g in zip(physical, phys, strict=True):
        w = wrap(o, n_links, ln, start=s, direction=d, mode="hug")
        dq = _dq(g.angles, w.angles)
        rows.append({
            "complete_phys": bool(g.complete), "complete_geo": bool(w.complete),
            "reason": g.reason, "dq_median": float(np.median(dq)),
            "dq_mean": float(np.mean(dq)), "dq_p90": float(np.quantile(dq, 0.9)),
            "laps_phys": float(g.laps), "laps_geo": float(w.laps),
            "shape_gap": _shape_gap(g.angles, w.angles) if w.complete else float("nan"),
            "sim_time": float(g.sim_time), "steps": int(g.steps),
        })  # fmt: skip
    return rows, elapsed


def _closing_length(outline, start, direction, n_links=64):
    """Link length closing one hug lap; the perimeter over n where no length does."""
    try:
        return closing_link_length(outline, n_links, start=start, direction=direction,
                                   mode="hug")[0]  # fmt: skip
    except ValueError:
        return float(shapely.Polygon(outline).length / n_links)


def summarise(name, rows):
    ok = [r for r in rows if r["complete_phys"] and r["complete_geo"]]
    if not ok:
        return [name, 0, len(rows), "-", "-", "-", "-", "-"]
    med = np.median([r["dq_median"] for r in ok])
    mean = np.mean([r["dq_mean"] for r in ok])
    p90 = np.median([r["dq_p90"] for r in ok])
    dl = np.median([abs(r["laps_phys"] - r["laps_geo"]) for r in ok])
    gap = np.nanmedian([r["shape_gap"] for r in ok])
    return [name, len(ok), len(rows), f"{med:.3f}", f"{mean:.3f}", f"{p90:.3f}", f"{dl:.3f}",
            f"{gap:.2f}"]  # fmt: skip


HEADER = ["objects", "compared", "grasped", "median abs dq (rad)", "mean abs dq", "p90 abs dq",
          "abs dlaps", "shape gap (links)"]  # fmt: skip


def thesis_shapes():
    return {
        "square": shapes.square(4.0),
        "circle": shapes.circle(16 / (2 * np.pi)),
        "rectangle": shapes.rectangle(5.0, 3.0),
        "triangle": shapes.triangle(side=16 / 3),
    }


def random_object(cls, rng, laps):
    """A thesis-class object whose perimeter unit links wrap ``laps`` times."""
    if cls == "square":
        p = shapes.square(1.0)
    elif cls == "circle":
        p = shapes.circle(1.0, n_points=256)
    elif cls == "rectangle":
        p = shapes.rectangle(float(rng.uniform(1.2, 4.0)), 1.0)
    else:
        while True:
            a, b = np.deg2rad(rng.uniform(25, 130, 2))
            if np.pi - a - b > np.deg2rad(25):
                break
        c = np.array([np.cos(a), np.sin(a)]) * np.sin(b) / np.sin(a + b)
        p = shapes.triangle([(0.0, 0.0), (1.0, 0.0), tuple(c)])
    p = p - p.mean(axis=0)
    p = p * (16 / laps) / shapely.Polygon(p).length
    th = rng.uniform(0, 2 * np.pi)
    return p @ np.array([[np.cos(th), np.sin(th)], [-np.sin(th), np.cos(th)]])


def sim_to_real(n_objects, jobs, seed=1, n_train=4000):
    rng = np.random.default_rng(seed)
    classes = ["circle", "rectangle", "square", "triangle"]
    y = rng.choice(classes, n_objects)
    laps = rng.uniform(1.0, 1.3, n_objects)
    objs = [random_object(c, rng, lp) for c, lp in zip(y, laps, strict=True)]
    starts = rng.uniform(0, 1, n_objects)
    dirs = np.where(rng.random(n_objects) < 0.5, "ccw", "cw")
    train = synthetic_tentacle(n_train, 16, laps=(1.0, 1.3), offset=(0.0, 0.0),
                               noise=(0.0, 0.05), random_state=seed + 100)  # fmt: skip
    geo = np.array([wrap(o, 16, 1.0, start=s, direction=d, mode="hug").angles
                    for o, s, d in zip(objs, starts, dirs, strict=True)])  # fmt: skip
    t0 = time.perf_counter()
    phys = grasp_many(objs, PlanarChain([1.0] * 16), starts, direction=list(dirs), n_jobs=jobs)
    elapsed = time.perf_counter() - t0
    pa = np.array([g.angles for g in phys])
    done = np.array([g.complete for g in phys])
    out = {"n": n_objects, "complete": int(done.sum()), "seconds": elapsed, "methods": {}}
    recognisers = {
        "chord-shape-nn": ShiftNNClassifier(signal="shape", closure="chord"),
        "TentacleClassifier()": TentacleClassifier(),
    }
    for name, clf in recognisers.items():
        clf.fit(train.data, train.target)
        acc_geo = float(np.mean(clf.predict(geo) == y))
        acc_phys = float(np.mean(clf.predict(pa) == y))
        per_class = {
            c: (float(np.mean(clf.predict(geo[y == c]) == c)),
                float(np.mean(clf.predict(pa[y == c]) == c)))
            for c in classes
        }  # fmt: skip
        out["methods"][name] = {"acc_geo": acc_geo, "acc_phys": acc_phys,
                                "ratio": acc_phys / acc_geo, "per_class": per_class}  # fmt: skip
    out["laps_phys_median"] = float(np.median([g.laps for g in phys]))
    return out


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--mpeg7", type=int, default=200)
    ap.add_argument("--thesis", type=int, default=200)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--train", type=int, default=4000, help="geometric training wraps")
    ap.add_argument("--out")
    ap.add_argument(
        "--mpeg7-folder",
        type=Path,
        default=MPEG7,
        help="MPEG-7 CE-Shape-1 Part B (default ../shared/data/mpeg7-part-b)",
    )
    args = ap.parse_args(argv)
    out = {}
    rng = np.random.default_rng(0)
    th = thesis_shapes()
    rows, _ = compare(list(th.values()), 16, [1.0] * 4, [0.1] * 4, ["ccw"] * 4, args.jobs)
    out["thesis"] = dict(zip(th, rows, strict=True))
    table = [summarise(k, [r]) for k, r in zip(th, rows, strict=True)]
    if args.mpeg7 and args.mpeg7_folder.is_dir():
        outlines, _, names = shapes.load_mpeg7(args.mpeg7_folder, max_vertices=1000)
        idx = np.sort(rng.choice(len(outlines), args.mpeg7, replace=False))
        starts = rng.uniform(0, 1, len(idx))
        dirs = np.where(rng.random(len(idx)) < 0.5, "ccw", "cw")
        sel = [outlines[i] for i in idx]
        from joblib import Parallel, delayed

        lengths = Parallel(n_jobs=args.jobs)(
            delayed(_closing_length)(o, s, d) for o, s, d in zip(sel, starts, dirs, strict=True)
        )
        rows, elapsed = compare(sel, 64, lengths, starts, dirs, args.jobs)
        out["mpeg7"] = {"rows": rows, "names": [names[i] for i in idx], "seconds": elapsed}
        table.append(summarise(f"MPEG-7 ({len(idx)}, 64 links)", rows))
        reasons = [r["reason"] for r in rows if not r["complete_phys"]]
        print("incomplete physical grasps:", len(reasons), reasons[:5])
        print(f"physical grasps: {elapsed:.0f} s with {args.jobs} processes; sim time "
              f"median {np.median([r['sim_time'] for r in rows]):.1f} s")  # fmt: skip
    print(markdown_table(HEADER, table))
    if args.thesis:
        s2r = sim_to_real(args.thesis, args.jobs, n_train=args.train)
        out["sim_to_real"] = s2r
        print(
            f"{s2r['n']} objects, {s2r['complete']} complete grasps, "
            f"{s2r['seconds']:.0f} s, median physical laps {s2r['laps_phys_median']:.2f}"
        )
        print(markdown_table(
            ["recogniser (trained on geometric wraps)", "geometric acc", "physical acc", "ratio"],
            [[k, f"{100 * v['acc_geo']:.1f} %", f"{100 * v['acc_phys']:.1f} %",
              f"{v['ratio']:.3f}"] for k, v in s2r["methods"].items()],
        ))  # fmt: skip
        for k, v in s2r["methods"].items():
            print(k, "per class (geometric, physical):", v["per_class"])
    if args.out:
        Path(args.out).write_text(json.dumps(out, indent=1))
    return out


if __name__ == "__main__":
    main()
