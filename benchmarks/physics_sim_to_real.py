"""Sim-to-real: recognisers trained only on generated wraps, tested on physical grasps.

Run: ``python benchmarks/physics_sim_to_real.py [--part thesis|mpeg7|both] [--jobs 2]``.

Goal: physical accuracy >= 95 % of geometric accuracy, for the thesis's four
classes (16 links) and for MPEG-7 (64 links). Every held-out object is wrapped
geometrically (``wrap(mode="hug")``) and grasped physically
(:func:`tentaclass.physics.grasp`) by the same chain from the same start point
in the same direction; a wrap or grasp that did not complete counts as an
error. The recognisers never see a physical grasp.

* thesis: 200 random objects of the four classes (``--thesis``; size so that
  16 unit links wrap 1.0-1.3 laps of the perimeter, rectangle aspect 1.2-4,
  triangle angles >= 25 degrees, random rotation, start and direction, no
  approach); training: ``synthetic_tentacle(4000, 16, laps=(1.0, 1.3),
  offset=(0, 0), noise=(0, 0.05))``.
* mpeg7: a stratified subset of ``--per-class`` silhouettes per class held
  out (seed 0); each scaled so that 64 unit links wrap 1.2-2 laps (drawn),
  rotated, random start and direction, no approach; training:
  ``chain_wraps`` of the other silhouettes (``--copies`` wraps each,
  ``--train-laps`` laps, 1.2-2 by default, approach 0-2 links), ``groups``
  passed to ``fit``.

Prints markdown tables; ``--out FILE`` writes the numbers as JSON, ``--arrays
DIR`` keeps the generated arrays (and reuses them when present).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np
import shapely
from threadpoolctl import threadpool_limits

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _timing import markdown_table
from physics_agreement import random_object

from tentaclass import PlanarChain, ShiftNNClassifier, TentacleClassifier, shapes, wrap
from tentaclass.datasets import chain_wraps, synthetic_tentacle
from tentaclass.physics import grasp_many

MPEG7 = (Path(__file__).resolve().parents[1] / "../shared/data/mpeg7-part-b").resolve()
CLASSES = ["circle", "rectangle", "square", "triangle"]


def recognisers():
    return {
        "TentacleClassifier()": TentacleClassifier(),
        'ShiftNNClassifier(signal="shape", closure="chord")': ShiftNNClassifier(
            signal="shape", closure="chord"
        ),
    }


def _cached(arrays, name, make):
    """``make()`` (a dict of arrays), kept in ``arrays/name.npz`` when ``arrays`` is given."""
    if arrays is None:
        return make()
    path = Path(arrays) / f"{name}.npz"
    if path.exists():
        with np.load(path, allow_pickle=False) as f:
            return {k: f[k] for k in f.files}
    out = make()
    path.parent.mkdir(parents=True, exist_ok=True)
    np.savez(path, **out)
    return out


def _test_pair(objs, n_links, starts, dirs, jobs):
    """Geometric hug wraps and physical grasps of the same objects, starts and directions."""
    geo = [wrap(o, n_links, 1.0, start=s, direction=d, mode="hug")
           for o, s, d in zip(objs, starts, dirs, strict=True)]  # fmt: skip
    t0 = time.perf_counter()
    phys = grasp_many(objs, PlanarChain([1.0] * n_links), starts, direction=list(dirs), n_jobs=jobs)
    seconds = time.perf_counter() - t0

    def rows(ws):  # incomplete wraps may stop early: NaN after the last placed link
        out = np.full((len(ws), n_links), np.nan)
        for i, w in enumerate(ws):
            a = np.asarray(w.angles, dtype=float)[:n_links]
            out[i, : len(a)] = a
        return out

    return {
        "geo": rows(geo),
        "geo_ok": np.array([w.complete for w in geo]),
        "geo_laps": np.array([w.laps for w in geo], dtype=float),
        "phys": rows(phys),
        "phys_ok": np.array([g.complete for g in phys]),
        "phys_laps": np.array([g.laps for g in phys], dtype=float),
        "phys_reason": np.array([g.reason for g in phys]),
        "seconds": np.float64(seconds),
    }


def _quasi_test(objs, n_links, starts, dirs, jobs):
    """Quasi-static grasps of the test objects (same chain, starts and directions)."""
    gs = grasp_many(objs, PlanarChain([1.0] * n_links), starts, direction=list(dirs),
                    method="quasi-static", n_jobs=jobs)  # fmt: skip
    return {
        "quasi": np.array([g.angles for g in gs]),
        "quasi_ok": np.array([g.complete for g in gs]),
    }


def score(clf, X, ok, y):
    """Accuracy with every incomplete wrap counted as an error; predictions (None where failed)."""
    ok = ok & np.isfinite(X).all(axis=1)
    pred = np.full(len(y), None, dtype=object)
    if ok.any():
        pred[ok] = clf.predict(X[ok])
    return float(np.mean(pred == y)), pred


def evaluate(trains, test, y):
    """Every recogniser trained on each training set, scored on the test pairs."""
    return {k: _evaluate(t, test, y) for k, t in trains.items()}


def _evaluate(train, test, y):
    out = {}
    for name, clf in recognisers().items():
        kw = {"groups": train["groups"]} if isinstance(clf, TentacleClassifier) else {}
        clf.fit(train["X"], train["y"], **kw)
        acc_geo, pg = score(clf, test["geo"], test["geo_ok"], y)
        acc_phys, pp = score(clf, test["phys"], test["phys_ok"], y)
        acc_quasi, _ = score(clf, test["quasi"], test["quasi_ok"], y)
        both = test["geo_ok"] & test["phys_ok"]
        out[name] = {
            "acc_geo": acc_geo,
            "acc_phys": acc_phys,
            "acc_quasi": acc_quasi,
            "ratio": acc_phys / acc_geo if acc_geo else float("nan"),
            "acc_geo_both_ok": float(np.mean(pg[both] == y[both])),
            "acc_phys_both_ok": float(np.mean(pp[both] == y[both])),
            "per_class": {
                str(c): [float(np.mean(pg[y == c] == c)), float(np.mean(pp[y == c] == c))]
                for c in np.unique(y)
            }
            if len(np.unique(y)) <= 8
            else {},
        }
    return out


# ---------------------------------------------------------------- thesis classes
def thesis(n_objects, jobs, arrays, seed=1, n_train=4000):
    def objects():
        rng = np.random.default_rng(seed)
        y = rng.choice(CLASSES, n_objects)
        laps = rng.uniform(1.0, 1.3, n_objects)
        objs = [random_object(c, rng, lp) for c, lp in zip(y, laps, strict=True)]
        starts = rng.uniform(0, 1, n_objects)
        dirs = np.where(rng.random(n_objects) < 0.5, "ccw", "cw")
        return y, objs, starts, dirs

    def make_test():
        y, objs, starts, dirs = objects()
        return {"y": y, **_test_pair(objs, 16, starts, dirs, jobs)}

    def make_quasi_test():
        _, objs, starts, dirs = objects()
        return _quasi_test(objs, 16, starts, dirs, jobs)

    def make_train():
        d = synthetic_tentacle(n_train, 16, laps=(1.0, 1.3), offset=(0.0, 0.0),
                               noise=(0.0, 0.05), random_state=seed + 100)  # fmt: skip
        return {"X": d.data, "y": d.target, "groups": np.arange(len(d.target))}

    def make_quasi():
        rng = np.random.default_rng(seed + 200)
        y = rng.choice(CLASSES, n_train)
        laps = rng.uniform(1.0, 1.3, n_train)
        objs = [random_object(c, rng, lp) for c, lp in zip(y, laps, strict=True)]
        starts = rng.uniform(0, 1, n_train)
        dirs = np.where(rng.random(n_train) < 0.5, "ccw", "cw")
        sigma = rng.uniform(0.0, 0.05, n_train)
        gs = grasp_many(objs, PlanarChain([1.0] * 16), starts, direction=list(dirs),
                        method="quasi-static", n_jobs=jobs)  # fmt: skip
        ok = np.array([g.complete for g in gs])
        X = np.array([g.angles for g in gs]) + rng.normal(0, 1, (n_train, 16)) * sigma[:, None]
        return {"X": X[ok], "y": y[ok], "groups": n_train + np.flatnonzero(ok)}  # own objects

    test = _cached(arrays, f"thesis-test-{n_objects}-{seed}", make_test)
    test.update(_cached(arrays, f"thesis-quasi-test-{n_objects}-{seed}", make_quasi_test))
    hug = _cached(arrays, f"thesis-train-{n_train}-{seed}", make_train)
    t0 = time.perf_counter()
    quasi = _cached(arrays, f"thesis-quasi-{n_train}-{seed}", make_quasi)
    print(f"thesis quasi-static training wraps: {time.perf_counter() - t0:.0f} s", file=sys.stderr)
    trains = _training_sets(hug, quasi)
    return _summary(test, trains, evaluate(trains, test, test["y"]))


def _training_sets(hug, quasi):
    both = {k: np.concatenate([hug[k], quasi[k]]) for k in ("X", "y", "groups")}
    return {"hug": hug, "quasi-static": quasi, "hug + quasi-static": both}


# ---------------------------------------------------------------------- MPEG-7
def mpeg7_split(labels, per_class, seed=0):
    """Indices of the held-out test silhouettes (``per_class`` per class) and of the others."""
    rng = np.random.default_rng(seed)
    test_idx = np.sort(np.concatenate([
        rng.choice(np.flatnonzero(labels == c), per_class, replace=False) for c in np.unique(labels)
    ]))  # fmt: skip
    return test_idx, np.setdiff1d(np.arange(len(labels)), test_idx)


def mpeg7_test_objects(outlines, labels, per_class, seed=0, n_links=64):
    """The held-out test objects, placed: (indices, objects, starts, directions, target laps).

    The draws follow the choice of the test silhouettes from the same seed.
    """
    test_idx, _ = mpeg7_split(labels, per_class, seed)
    m = len(test_idx)
    r = np.random.default_rng(seed)
    for c in np.unique(labels):
        r.choice(np.flatnonzero(labels == c), per_class, replace=False)
    target = r.uniform(1.2, 2.0, m)
    theta = r.uniform(0, 2 * np.pi, m)
    starts = r.uniform(0, 1, m)
    dirs = np.where(r.random(m) < 0.5, "ccw", "cw")
    objs = []
    for i, t, th, s, d in zip(test_idx, target, theta, starts, dirs, strict=True):
        o = _placed(outlines[i], th, n_links / t)
        w = wrap(o, n_links, 1.0, start=s, direction=d, mode="hug")  # rescale once by laps made
        if w.complete and np.isfinite(w.laps) and w.laps > 0.05:
            o = o * w.laps / t
        objs.append(o)
    return test_idx, objs, starts, dirs, target


def mpeg7(
    folder, per_class, copies, quasi_copies, jobs, arrays, seed=0, n_links=64, train_laps=(1.2, 2.0)
):
    outlines, labels, _ = shapes.load_mpeg7(folder, max_vertices=1000)
    labels = np.asarray(labels)
    test_idx, train_idx = mpeg7_split(labels, per_class, seed)

    def objects():
        return mpeg7_test_objects(outlines, labels, per_class, seed, n_links)[1:]

    def make_test():
        objs, starts, dirs, target = objects()
        out = _test_pair(objs, n_links, starts, dirs, jobs)
        return {"y": labels[test_idx], "index": test_idx, "target_laps": target, **out}

    def make_quasi_test():
        objs, starts, dirs, _ = objects()
        return _quasi_test(objs, n_links, starts, dirs, jobs)

    def make_train():
        d = chain_wraps([outlines[i] for i in train_idx], n_links, n_wraps=copies,
                        laps=train_laps, offset=(0.0, 2.0), mode="hug",
                        random_state=seed + 100)  # fmt: skip
        return {"X": d.data, "y": labels[train_idx][d.outline], "groups": train_idx[d.outline],
                "n_failed": np.int64(d.n_failed)}  # fmt: skip

    def make_quasi():
        qrng = np.random.default_rng(seed + 200)
        idx = np.repeat(train_idx, quasi_copies)
        m = len(idx)
        target = qrng.uniform(1.2, 2.0, m)
        theta = qrng.uniform(0, 2 * np.pi, m)
        starts = qrng.uniform(0, 1, m)
        dirs = np.where(qrng.random(m) < 0.5, "ccw", "cw")
        objs = [_placed(outlines[i], th, n_links / t)
                for i, t, th in zip(idx, target, theta, strict=True)]  # fmt: skip
        gs = grasp_many(objs, PlanarChain([1.0] * n_links), starts, direction=list(dirs),
                        method="quasi-static", n_jobs=jobs)  # fmt: skip
        ok = np.array([g.complete for g in gs])
        X = np.array([g.angles for g in gs])
        fails = np.int64((~ok).sum())
        return {"X": X[ok], "y": labels[idx][ok], "groups": idx[ok], "n_failed": fails}

    t0 = time.perf_counter()
    test = _cached(arrays, f"mpeg7-test-{per_class}-{seed}", make_test)
    test.update(_cached(arrays, f"mpeg7-quasi-test-{per_class}-{seed}", make_quasi_test))
    print(f"MPEG-7 test pairs ready in {time.perf_counter() - t0:.0f} s", file=sys.stderr)
    laps_tag = "" if tuple(train_laps) == (1.2, 2.0) else f"-laps{train_laps[0]}-{train_laps[1]}"
    hug = _cached(arrays, f"mpeg7-train-{copies}-{seed}{laps_tag}", make_train)
    print(f"MPEG-7 hug training wraps ready in {time.perf_counter() - t0:.0f} s", file=sys.stderr)
    trains = {"hug": hug}
    if quasi_copies:
        quasi = _cached(arrays, f"mpeg7-quasi-{quasi_copies}-{seed}", make_quasi)
        print(f"MPEG-7 quasi-static wraps in {time.perf_counter() - t0:.0f} s", file=sys.stderr)
        trains = _training_sets(hug, quasi)
    out = _summary(test, trains, evaluate(trains, test, test["y"]))
    out["train_silhouettes"] = len(train_idx)
    out["train_failed"] = {k: int(v.get("n_failed", 0)) for k, v in trains.items()}
    return out


def _placed(outline, theta, perimeter):
    """``outline`` centred, rotated by ``theta`` and scaled to ``perimeter``."""
    o = outline - outline.mean(axis=0)
    c, sn = np.cos(theta), np.sin(theta)
    return o @ np.array([[c, sn], [-sn, c]]) * (perimeter / shapely.Polygon(outline).length)


def _summary(test, trains, res):
    return {
        "n_test": len(test["y"]),
        "n_train": {k: len(t["y"]) for k, t in trains.items()},
        "geo_complete": int(test["geo_ok"].sum()),
        "phys_complete": int(test["phys_ok"].sum()),
        "quasi_complete": int(test["quasi_ok"].sum()),
        "phys_reasons": sorted({str(r) for r in test["phys_reason"] if r}),
        "geo_laps_median": float(np.nanmedian(test["geo_laps"])),
        "phys_laps_median": float(np.nanmedian(test["phys_laps"])),
        "grasp_seconds": float(test["seconds"]),
        "methods": res,
    }


def report(name, s):
    print(
        f"\n{name}: {s['n_test']} test objects ({s['geo_complete']} geometric and "
        f"{s['phys_complete']} physical and {s['quasi_complete']} quasi-static complete), "
        f"training wraps {s['n_train']}; median laps "
        f"geometric {s['geo_laps_median']:.2f}, physical {s['phys_laps_median']:.2f}; "
        f"grasps {s['grasp_seconds']:.0f} s"
    )
    rows = [[t, k, f"{100 * v['acc_geo']:.1f} %", f"{100 * v['acc_phys']:.1f} %",
             f"{v['ratio']:.3f}",
             f"{100 * v['acc_geo_both_ok']:.1f} % / {100 * v['acc_phys_both_ok']:.1f} %",
             f"{100 * v['acc_quasi']:.1f} %"]
            for t, res in s["methods"].items() for k, v in res.items()]  # fmt: skip
    print(markdown_table(
        ["training wraps", "recogniser", "geometric", "physical", "ratio",
         "both complete: geometric / physical", "quasi-static test grasps"], rows))  # fmt: skip
    for t, res in s["methods"].items():
        for k, v in res.items():
            if v["per_class"]:
                print(t, k, "per class (geometric, physical):", v["per_class"])


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--part", choices=["thesis", "mpeg7", "both"], default="both")
    ap.add_argument("--thesis", type=int, default=200, help="thesis test objects")
    ap.add_argument("--train", type=int, default=4000,
                    help="thesis training wraps of each kind (hug, quasi-static)")  # fmt: skip
    ap.add_argument("--per-class", type=int, default=2, help="MPEG-7 test silhouettes per class")
    ap.add_argument("--copies", type=int, default=2, help="MPEG-7 training wraps per silhouette")
    ap.add_argument("--train-laps", type=float, nargs=2, default=(1.2, 2.0),
                    help="laps of the MPEG-7 hug training wraps")  # fmt: skip
    ap.add_argument("--quasi-copies", type=int, default=1,
                    help="MPEG-7 quasi-static training wraps per silhouette (0: none)")  # fmt: skip
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--arrays", help="directory keeping the generated arrays")
    ap.add_argument("--out")
    ap.add_argument("--mpeg7-folder", type=Path, default=MPEG7)
    args = ap.parse_args(argv)
    out = {}
    with threadpool_limits(1):
        if args.part in ("thesis", "both"):
            out["thesis"] = thesis(args.thesis, args.jobs, args.arrays, n_train=args.train)
            report("Thesis classes, 16 links", out["thesis"])
        if args.part in ("mpeg7", "both"):
            if not args.mpeg7_folder.is_dir():
                print(f"MPEG-7 not found at {args.mpeg7_folder}: skipped", file=sys.stderr)
            else:
                out["mpeg7"] = mpeg7(args.mpeg7_folder, args.per_class, args.copies,
                                     args.quasi_copies, args.jobs, args.arrays,
                                     train_laps=tuple(args.train_laps))  # fmt: skip
                report("MPEG-7, 64 links", out["mpeg7"])
    if args.out:
        Path(args.out).write_text(json.dumps(out, indent=1))
    return out


if __name__ == "__main__":
    main()
