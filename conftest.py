"""Doctests of the MuJoCo-backed modules need the ``physics`` extra: skip them without it."""

import importlib.util
from pathlib import Path

_PHYSICS = [Path("src/tentaclass/physics"), Path("src/tentaclass/plot/physics.py")]


def pytest_ignore_collect(collection_path, config):
    """Skip the physics modules' doctests when MuJoCo is not installed."""
    if importlib.util.find_spec("mujoco") is not None:
        return None
    rel = Path(collection_path).resolve()
    root = Path(__file__).resolve().parent
    return any(rel == root / p or root / p in rel.parents for p in _PHYSICS) or None
