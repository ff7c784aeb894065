import os
from pathlib import Path

import matplotlib
import numpy as np
import pytest
from hypothesis import HealthCheck, settings

matplotlib.use("Agg")

# `make test` and CI: the same examples on every run. `make fuzz`: fresh ones, many more.
settings.register_profile(
    "ci",
    derandomize=True,
    deadline=None,
    print_blob=True,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.register_profile(
    "fuzz",
    max_examples=2000,
    deadline=None,
    print_blob=True,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))

# ../shared/data beside the clone, or wherever TENTACLASS_SHARED_DATA points
SHARED_DATA = Path(
    os.environ.get("TENTACLASS_SHARED_DATA")
    or Path(__file__).resolve().parents[1].parent / "shared" / "data"
)
MPEG7 = SHARED_DATA / "mpeg7-part-b"


@pytest.fixture(autouse=True, scope="session")
def _one_openmp_thread():
    """scikit-learn's OpenMP code (gradient-boosted trees, k-means) runs on one thread.

    Its threads spin while they wait: on a machine shared with other jobs one
    gradient-boosting fit took 20 times as long on two threads as on one. The
    results do not depend on the thread count; BLAS is left as it is.
    """
    import sklearn.ensemble  # noqa: F401  (loads the OpenMP runtime the limit applies to)
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1, user_api="openmp"):
        yield


@pytest.fixture
def rng():
    return np.random.default_rng(12345)


@pytest.fixture(scope="session")
def mpeg7_folder():
    if not MPEG7.is_dir():
        pytest.skip(
            f"MPEG-7 data not found at {MPEG7} (it lives in ../shared/data beside the clone)"
        )
    return MPEG7


os.environ.setdefault("MPLBACKEND", "Agg")


@pytest.fixture(autouse=True, scope="module")
def _fresh_worker_processes():
    """Each test module starts joblib's worker processes afresh.

    Workers left over from another module (after a Dask cluster or a server
    came and went in between) are shut down, never reused.
    """
    yield
    from joblib.externals.loky import reusable_executor

    executor = reusable_executor._executor  # None until a module used joblib's processes
    if executor is not None:
        executor.shutdown(wait=True, kill_workers=True)
