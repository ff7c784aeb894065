"""Doctests of modules behind an optional extra run only where that extra is installed."""

import importlib.util
from pathlib import Path

_ROOT = Path(__file__).resolve().parent

#: module or package (relative to the repository) -> the import its extra brings
_EXTRAS = {
    "src/tentaclass/physics": "mujoco",
    "src/tentaclass/plot/physics.py": "mujoco",
    "src/tentaclass/web/_app.py": "fastapi",
    "src/tentaclass/classifiers/_outline.py": "aeon",
}


def pytest_ignore_collect(collection_path, config):
    """Skip the doctests of a module whose optional extra is missing."""
    path = Path(collection_path).resolve()
    for rel, module in _EXTRAS.items():
        target = _ROOT / rel
        if (path == target or target in path.parents) and importlib.util.find_spec(module) is None:
            return True
    return None
