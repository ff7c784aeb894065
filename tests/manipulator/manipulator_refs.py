"""Shared helpers for the manipulator tests: random chains and references."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np

from tentaclass.manipulator import PlanarChain


def random_chain(rng: np.random.Generator, n: int, gravity: float = 9.81) -> PlanarChain:
    """A chain with random lengths, masses, centres of mass and inertias."""
    return PlanarChain(
        link_lengths=rng.uniform(0.2, 2.0, n),
        masses=rng.uniform(0.1, 3.0, n),
        com=rng.uniform(0.0, 1.0, n),
        inertia=rng.uniform(0.0, 0.5, n),
        gravity=gravity,
    )


def _load_bench_dynamics():
    path = Path(__file__).resolve().parents[2] / "benchmarks" / "bench_dynamics.py"
    spec = importlib.util.spec_from_file_location("bench_dynamics", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


#: The Pinocchio reference chain, built in one place: the dynamics benchmark.
pinocchio_model = _load_bench_dynamics().pinocchio_model


def double_pendulum(chain: PlanarChain, q, qd):
    """Textbook closed forms of H, h and g for a 2-link chain."""
    l1 = chain.link_lengths[0]
    lc1, lc2 = chain.com * chain.link_lengths
    m1, m2 = chain.masses
    i1, i2 = chain.inertia
    g = chain.gravity
    q1, q2 = q
    qd1, qd2 = qd
    c2 = np.cos(q2)
    h11 = i1 + i2 + m1 * lc1**2 + m2 * (l1**2 + lc2**2 + 2 * l1 * lc2 * c2)
    h12 = i2 + m2 * (lc2**2 + l1 * lc2 * c2)
    h22 = i2 + m2 * lc2**2
    k = m2 * l1 * lc2 * np.sin(q2)
    mass = np.array([[h11, h12], [h12, h22]])
    cor = np.array([-k * (2 * qd1 * qd2 + qd2**2), k * qd1**2])
    grav = np.array(
        [
            g * (m1 * lc1 + m2 * l1) * np.cos(q1) + g * m2 * lc2 * np.cos(q1 + q2),
            g * m2 * lc2 * np.cos(q1 + q2),
        ]
    )
    return mass, cor, grav
