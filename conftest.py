"""Collection for the whole repository (tests/ and the doctests in src/).

Doctests of modules behind an optional extra run only where that extra is
installed; under pytest-xdist the tests sharing a costly set-up run on one
worker and the slow ones are handed out first.
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


@pytest.fixture(autouse=True)
def _private_cache(tmp_path_factory, monkeypatch):
    """Caches go to a temporary folder, never the user's ~/.cache or ~/aeon_data.

    Defined here so that it holds for the doctests in src/ as well as for tests/.

    Under pytest-xdist each worker has a temporary folder (and so caches) of its own.
    """
    base = tmp_path_factory.getbasetemp()
    monkeypatch.setenv("XDG_CACHE_HOME", str(base / "cache"))
    monkeypatch.setenv("AEON_DATA", str(base / "aeon_data"))


#: where the fixtures every test shares are defined (cheap: a folder's path, a thread limit)
_SHARED_FIXTURES = frozenset({"", "tests"})

#: thread pools of one worker: with one thread each, N workers keep N cores busy
#: instead of starting N times as many threads that spin while they wait for one another
_ONE_THREAD = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")


def pytest_configure(config):
    """Under ``pytest -n N`` (N > 1): the workers run one thread per pool.

    The variables are set in the controlling process before it starts the
    workers, so they hold before NumPy or BLAS load (and in the processes
    the tests start); values set by the user are kept. numba's parallel
    kernels run on one thread in each worker (its pool keeps its size, so a
    library may still ask for more, as aeon's MiniRocket does).
    """
    workers = getattr(config.option, "numprocesses", None)
    if isinstance(workers, int) and workers > 1:
        for name in _ONE_THREAD:
            os.environ.setdefault(name, "1")
    if os.environ.get("PYTEST_XDIST_WORKER") and "NUMBA_NUM_THREADS" not in os.environ:
        import numba

        numba.set_num_threads(1)  # for the thread that runs the tests


def _costly_scope(item):
    """Where the widest fixture a test needs beyond the shared ones is defined, or None.

    A module-, package- or session-scoped fixture is set up once per worker
    that runs a test needing it: the tests needing it run on one worker.
    """
    info = getattr(item, "_fixtureinfo", None)
    if info is None:  # doctests
        return None
    owners = [
        defs[-1].baseid
        for defs in info.name2fixturedefs.values()
        if defs and defs[-1].scope != "function" and defs[-1].baseid not in _SHARED_FIXTURES
    ]
    return min(owners, key=len) if owners else None


def _in_group(item, group):
    """Append ``@group`` to the test's node id: ``--dist loadgroup`` runs a group on one worker.

    It is what pytest-xdist does for an ``xdist_group`` mark, done here
    because pytest 9 keeps a node id in ``_id``, which xdist's assignment to
    ``_nodeid`` no longer reaches (the groups were split over the workers).
    """
    nodeid = f"{item.nodeid}@{group}"
    if hasattr(item, "_id"):
        from _pytest.nodeid import NodeId

        item._id = NodeId.parse(nodeid)
    else:
        item._nodeid = nodeid


def _group(item):
    """The group a test runs in under ``--dist loadgroup``, or None to run anywhere.

    The scanner's tests form one group: its numba kernels take about 25 s of
    CPU to compile on a fresh clone, once per worker that runs any of them
    (a test elsewhere that runs the scanner is marked ``scanner``: its own
    group joins this one, see ``pytest_collection_modifyitems``).
    So do the tests marked ``mpeg7``: each process decodes the 1400
    silhouettes once (about 8 s of CPU) and reads them from its cache after.
    """
    if item.get_closest_marker("mpeg7") is not None:
        return "mpeg7"
    path = item.nodeid.split("::")[0]
    if "scanner" in path:
        return "scanner"
    return _costly_scope(item) or ("scanner" if "scanner" in item.nodeid else None)


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(config, items):
    """Under pytest-xdist: costly set-ups once, and the long tests first.

    The tests of a module or package whose fixtures are set up once for all
    of them (a Dask cluster, a browser and a server, fitted models, generated
    MPEG-7 wraps) form one group that ``--dist loadgroup`` runs on one worker;
    so do the tests of the scanner (see ``_group``), with the groups of the
    tests marked ``scanner`` elsewhere.
    Workers take the next test as they become free, so the slow tests and the
    groups are handed out first rather than last on one worker while the
    other has nothing left to do. Every test still runs; only the order and
    the worker change.
    """
    if not os.environ.get("PYTEST_XDIST_WORKER"):
        return
    groups = {item.nodeid: _group(item) for item in items}
    items.sort(  # stable
        key=lambda item: (item.get_closest_marker("slow") is None, groups[item.nodeid] is None)
    )
    # a group holding a test that runs the scanner joins the scanner's group: the
    # scanner's kernels are compiled by one worker only
    marked = {item.nodeid for item in items if item.get_closest_marker("scanner")}
    joined = {groups[nodeid] for nodeid in marked} - {None}
    for nodeid, group in groups.items():
        if group in joined or nodeid in marked:
            groups[nodeid] = "scanner"
    if config.getvalue("loadgroup"):  # what xdist sets in a worker for --dist loadgroup
        for item in items:
            if groups[item.nodeid]:
                _in_group(item, groups[item.nodeid])
