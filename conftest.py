"""Collection for the whole repository (tests/ and the doctests in src/).

Doctests of modules behind an optional extra run only where that extra is
installed; under pytest-xdist the slow tests are handed out first.
"""

import importlib.util
import os
from pathlib import Path

import pytest

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


#: Test modules whose module-scoped fixtures are costly to set up (a Dask cluster,
#: generated wraps): under ``pytest -n N --dist loadgroup`` each runs on one worker,
#: which sets its fixtures up once.
_XDIST_GROUPS = {
    "tests/test_dask.py": "dask-cluster",
    "tests/classifiers/test_tentacle_mpeg7.py": "mpeg7-wraps",
}


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(config, items):
    """Under pytest-xdist: the slow tests first, and costly modules on one worker each.

    Workers take the next test as they become free, so the long tests are
    started first (the longest a few minutes: `make test`'s wall time is at
    least the longest test's) rather than last on one worker while the other
    has nothing left to do. Every test still runs; only the order changes.
    """
    if not os.environ.get("PYTEST_XDIST_WORKER"):
        return
    for item in items:
        path = Path(item.path)
        group = (
            _XDIST_GROUPS.get(path.relative_to(_ROOT).as_posix())
            if path.is_relative_to(_ROOT)
            else None
        )
        if group:
            item.add_marker(pytest.mark.xdist_group(group))
    items.sort(key=lambda item: item.get_closest_marker("slow") is None)  # stable
