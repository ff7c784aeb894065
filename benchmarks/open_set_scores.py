"""Offline harness for open-set novelty scores of ``TentacleClassifier``.

``collect`` fits ``TentacleClassifier(reject=0.05)`` once per fold (the
folds and unseen classes of ``bench_recognition.py --only open-set``) and
keeps, for the held-out training wraps and for the test wraps, every
member's class distances; ``evaluate`` then scores candidate novelty
scores cheaply: the share of unseen objects rejected at the limit giving
5 % false rejections on held-out training wraps, and AUROC on the test fold.

Run: ``python benchmarks/open_set_scores.py collect --folds 3 --dir DIR``
then ``python benchmarks/open_set_scores.py evaluate --dir DIR``.
"""

from __future__ import annotations

import argparse
import pickle
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_recognition import MPEG7, UNSEEN, _fixed_chain_folds

MEMBERS = ("lap", "exact", "spectrum", "elastic", "last")


def collect(folds: int, out: Path, every: int = 1, start: int = 0) -> None:
    """Fit once per fold and save every member's class distances (npz per fold)."""
    from tentaclass import TentacleClassifier
    from tentaclass.classifiers import _tentacle
    from tentaclass.classifiers import _tentacle_core as _core
    from tentaclass.datasets import mpeg7_tentacle
    from tentaclass.features import last_lap, split_laps

    d = mpeg7_tentacle(MPEG7, 64, "hug", protocol="fixed-chain", laps=(1.2, 2.0),
                       offset=(0.0, 2.0), random_state=0)  # fmt: skip
    unseen = np.isin(d.target, UNSEEN)
    out.mkdir(parents=True, exist_ok=True)
    for i, (tr, te) in enumerate(_fixed_chain_folds(d, folds)):
        if i < start:
            continue
        tr = tr[~unseen[tr] & d.complete[tr]][::every]
        te = te[::every]
        kept: dict = {}
        choose = _tentacle._choose_weights

        def spy(members, y, _choose=choose, _kept=kept):
            _kept["train"] = members
            _kept["y"] = y
            return _choose(members, y)

        _tentacle._choose_weights = spy
        t0 = time.perf_counter()
        try:
            clf = TentacleClassifier(reject=0.05).fit(d.data[tr], d.target[tr], groups=d.groups[tr])
        finally:
            _tentacle._choose_weights = choose
        with open(out / f"fold{i}.pkl", "wb") as fh:
            pickle.dump((clf, kept), fh)
        te = te[d.complete[te]]
        Xv = _core._three_or_more(d.data[te].astype(float))
        split = split_laps(Xv, clf.n_points)
        closed = split.closed & _core._closes(Xv, split)
        # every member, whatever its weight (the last-lap outlines kept again)
        X3 = _core._three_or_more(d.data[tr].astype(float))
        clf.last_heights_, clf.last_complexity_ = _tentacle._elastic_descriptors(
            last_lap(X3, clf.n_points)[0]
        )
        w = clf.weights_
        clf.weights_ = np.array([1.0, 1.0, float(clf.spectrum_ is not None), 1.0, 1.0])
        te_members = clf._closed_members(Xv[closed], split.lap[closed])
        clf.weights_ = w
        pred = clf.predict(d.data[te])
        arrays = {
            "y_train": kept["y"],
            "y_test": np.searchsorted(
                clf.classes_, np.where(unseen[te], clf.classes_[0], d.target[te])
            ),
            "unseen": unseen[te][closed],
            "unseen_all": unseen[te],
            "pred_unknown": pred == "unknown",
            "closed": closed,
            "weights": clf.weights_,
            "scale": np.array([clf.scale_, clf.temperature_]),
            "coef": clf.reject_coef_,
            "threshold": np.array([clf.reject_threshold_]),
            "spread": clf.class_spread_,
        }
        arrays["y_test"] = arrays["y_test"][closed]
        for name, tr_m, te_m in zip(MEMBERS, kept["train"], te_members, strict=True):
            if tr_m is not None and te_m is not None:
                arrays[f"train_{name}"] = tr_m
                arrays[f"test_{name}"] = te_m
        np.savez(out / f"fold{i}.npz", **arrays)
        print(f"fold {i}: {time.perf_counter() - t0:.0f} s, closed {closed.mean():.3f}", flush=True)


if __name__ == "__main__":
    p = argparse.ArgumentParser()
    p.add_argument("what", choices=["collect", "evaluate"])
    p.add_argument("--folds", type=int, default=3)
    p.add_argument("--start", type=int, default=0)
    p.add_argument("--every", type=int, default=1)
    p.add_argument("--dir", type=Path, default=Path("open-set-scores"))
    a = p.parse_args()
    if a.what == "collect":
        collect(a.folds, a.dir, a.every, a.start)
