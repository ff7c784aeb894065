"""Configurations per second: tentaclass's batched dynamics vs Pinocchio in a loop.

Run with ``.venv/bin/python benchmarks/bench_dynamics.py``. For each chain size,
the same random configurations go once through :class:`PlanarChain` as one
batch and once through Pinocchio (C++), called from a Python loop. Pinocchio's
``crba`` result is used as returned (upper triangle only), which favours it.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from _timing import best_time, markdown_table

from tentaclass.manipulator import PlanarChain


def pinocchio_model(chain: PlanarChain):
    """The same chain in Pinocchio's model API: revolute-z joints along x."""
    import pinocchio as pin

    model = pin.Model()
    parent = 0
    for i in range(chain.n_links):
        offset = 0.0 if i == 0 else chain.link_lengths[i - 1]
        placement = pin.SE3(np.eye(3), np.array([offset, 0.0, 0.0]))
        joint = model.addJoint(parent, pin.JointModelRZ(), placement, f"joint{i + 1}")
        lever = np.array([chain.com[i] * chain.link_lengths[i], 0.0, 0.0])
        inertia = pin.Inertia(chain.masses[i], lever, np.diag([0.0, 0.0, chain.inertia[i]]))
        model.appendBodyToJoint(joint, inertia, pin.SE3.Identity())
        parent = joint
    model.gravity = pin.Motion(np.array([0.0, -chain.gravity, 0.0, 0.0, 0.0, 0.0]))
    return model, model.createData()


def _time_chain(n: int, batch: int, repeat: int, rng: np.random.Generator) -> list[dict]:
    import pinocchio as pin

    chain = PlanarChain(
        rng.uniform(0.2, 2.0, n), rng.uniform(0.1, 3.0, n), rng.uniform(0.0, 1.0, n)
    )
    model, data = pinocchio_model(chain)
    q = rng.uniform(-np.pi, np.pi, (batch, n))
    qd = rng.normal(size=(batch, n))
    qdd = rng.normal(size=(batch, n))
    cases = [
        (
            "H (mass matrix)",
            lambda: chain.mass_matrix(q),
            lambda: [pin.crba(model, data, x) for x in q],
        ),
        (
            "h + g (bias torques)",
            lambda: chain.bias_torques(q, qd),
            lambda: [pin.nonLinearEffects(model, data, x, v) for x, v in zip(q, qd, strict=True)],
        ),
        (
            "inverse dynamics",
            lambda: chain.inverse_dynamics(q, qd, qdd),
            lambda: [pin.rnea(model, data, x, v, a) for x, v, a in zip(q, qd, qdd, strict=True)],
        ),
    ]
    rows = []
    for name, ours, theirs in cases:
        ours_rate = batch / best_time(ours, repeat)
        pin_rate = batch / best_time(theirs, repeat)
        rows.append(
            {
                "quantity": name,
                "n": n,
                "tentaclass": ours_rate,
                "pinocchio": pin_rate,
                "ratio": ours_rate / pin_rate,
            }
        )
    return rows


def main(batch: int = 10_000, ns: Sequence[int] = (16, 64), repeat: int = 3) -> list[dict]:
    """Time H, h + g and inverse dynamics; print a markdown table and return its rows."""
    rng = np.random.default_rng(0)
    rows = [row for n in ns for row in _time_chain(n, batch, repeat, rng)]
    print(f"Configurations per second, batch of {batch}, best of {repeat}:\n")
    header = ["quantity", "n", "tentaclass (batched numpy)", "Pinocchio (loop)", "ratio"]
    table = [
        [
            r["quantity"],
            r["n"],
            f"{r['tentaclass']:,.0f}",
            f"{r['pinocchio']:,.0f}",
            f"{r['ratio']:.2f}",
        ]
        for r in rows
    ]
    print(markdown_table(header, table))
    return rows


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--batch", type=int, default=10_000)
    parser.add_argument("--ns", type=int, nargs="+", default=[16, 64])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    main(batch=args.batch, ns=args.ns, repeat=args.repeat)
