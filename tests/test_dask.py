"""Every entry point on a 2-process Dask cluster gives the single-process results.

One LocalCluster serves the whole module. A dask result is compared with the
same function applied to the same blocks in this process (bit for bit) and
with one call on the whole array (the matrix products of a block may round
differently from those of the whole batch in the last bit, so: to 1e-12).
"""

from __future__ import annotations

import json
import os

import numpy as np
import pytest
from click.testing import CliRunner

distributed = pytest.importorskip("distributed")
da = pytest.importorskip("dask.array")
db = pytest.importorskip("dask.bag")
pa = pytest.importorskip("pyarrow")
pq = pytest.importorskip("pyarrow.parquet")

import tentaclass as tc  # noqa: E402
from tentaclass import _dask  # noqa: E402
from tentaclass.cli.main import cli  # noqa: E402
from tentaclass.datasets import reference_tentacle, synthetic_tentacle  # noqa: E402
from tentaclass.errors import InputError  # noqa: E402
from tentaclass.features import canonical_direction, last_lap, periodic_signal  # noqa: E402
from tentaclass.shapes import circle, rectangle, square, triangle  # noqa: E402

pytestmark = [
    pytest.mark.filterwarnings("ignore::ResourceWarning"),
    pytest.mark.filterwarnings("ignore::DeprecationWarning"),
    pytest.mark.filterwarnings("ignore:Port .* is already in use:UserWarning"),
    pytest.mark.filterwarnings("ignore:Creating scratch directories:UserWarning"),
]


@pytest.fixture(scope="module")
def client():
    cluster = _dask.local_cluster(2)  # the cluster of --scheduler local
    with distributed.Client(cluster) as c:
        c.run(lambda: __import__("tentaclass.cli.main"))  # warm the workers up once
        yield c
    cluster.close()


@pytest.fixture(scope="module")
def data():
    X, y = reference_tentacle(16, n_starts=10, return_X_y=True)
    rng = np.random.default_rng(0)
    Xn = X[rng.integers(0, len(X), 300)] + rng.normal(0.0, 0.03, (300, 16))
    return X, y, Xn


@pytest.fixture(scope="module")
def tentacle(data):
    """``TentacleClassifier()`` fitted on ``data``, shared (the tests only read it)."""
    X, y, _ = data
    return tc.TentacleClassifier().fit(X, y)


def per_block(func, X, rows):
    return np.concatenate([func(X[i : i + rows]) for i in range(0, len(X), rows)])


@pytest.mark.parametrize(
    "func",
    [
        lambda q: tc.fourier_features(q, 6, detrend=True),
        tc.turning_function,
        lambda q: periodic_signal(q, detrend=True),
        canonical_direction,
        lambda q: last_lap(q, n_out=12)[0],
    ],
    ids=["fourier_features", "turning_function", "periodic_signal", "canonical", "last_lap"],
)
def test_descriptors_on_cluster(client, data, func):
    _, _, Xn = data
    lazy = func(da.from_array(Xn, chunks=(64, 5)))
    assert isinstance(lazy, da.Array) and lazy.chunks[0] == (64, 64, 64, 64, 44)
    got = client.compute(lazy).result()
    np.testing.assert_array_equal(got, per_block(func, Xn, 64))
    np.testing.assert_allclose(got, func(Xn), rtol=1e-12, atol=1e-12)


def test_descriptor_tuple_output_and_leading_axes(client, data):
    _, _, Xn = data
    q = Xn.reshape(3, 100, 16)
    lap, closed = last_lap(da.from_array(q, chunks=(2, 30, 16)), n_out=12)
    assert lap.shape == (3, 100, 12) and closed.dtype == bool
    ref_lap, ref_closed = last_lap(q, n_out=12)
    lap, closed = client.compute([lap, closed], sync=True)
    np.testing.assert_array_equal(closed, ref_closed)
    np.testing.assert_allclose(lap, ref_lap, rtol=1e-12, atol=1e-12)


def test_estimators_on_cluster(client, data):
    X, y, Xn = data
    dX = da.from_array(Xn, chunks=(50, 16))
    clf = tc.FourierClassifier(detrend=True, spread=0.5).fit(X, y)
    F = tc.fourier_features(X)
    pnn = tc.PNNClassifier(spread=0.3).fit(F, y)
    rbf = tc.RBFNetworkClassifier().fit(F, y)
    shift = tc.ShiftNNClassifier().fit(X, y)
    feats = tc.FourierFeatures(n_harmonics=5).fit(X)
    labels = client.compute(clf.predict(dX)).result()
    np.testing.assert_array_equal(labels, clf.predict(Xn))
    np.testing.assert_allclose(
        client.compute(clf.predict_proba(dX)).result(), clf.predict_proba(Xn), atol=1e-12
    )
    dF = tc.fourier_features(dX)
    for est in (pnn, rbf):
        np.testing.assert_array_equal(
            client.compute(est.predict(dF)).result(), est.predict(tc.fourier_features(Xn))
        )
    np.testing.assert_array_equal(client.compute(shift.predict(dX)).result(), shift.predict(Xn))
    np.testing.assert_array_equal(
        client.compute(feats.transform(dX)).result(), per_block(feats.transform, Xn, 50)
    )


def test_read_parquet_rows(client, data, tmp_path):
    """Row groups become blocks; the rows and the predictions equal those read by dask.dataframe."""
    dd = pytest.importorskip("dask.dataframe")
    X, y, Xn = data
    names = [f"q{j}" for j in range(16)]
    paths = [tmp_path / "a.parquet", tmp_path / "b.parquet"]
    pq.write_table(pa.table(dict(zip(names, Xn[:200].T, strict=True))), paths[0], row_group_size=64)
    pq.write_table(pa.table(dict(zip(names, Xn[200:].T, strict=True))), paths[1], row_group_size=64)
    rows = tc.read_parquet_rows(paths, block_rows=None)
    assert rows.chunks == ((64, 64, 64, 8, 64, 36), (16,))
    np.testing.assert_array_equal(client.compute(rows).result(), Xn)
    theirs = dd.read_parquet(paths, split_row_groups=True).to_dask_array()
    clf = tc.FourierClassifier(detrend=True, spread=0.5).fit(X, y)
    ours, theirs = client.compute([clf.predict(rows), clf.predict(theirs)], sync=True)
    np.testing.assert_array_equal(ours, theirs)
    # each row group is read by the task that classifies it: one task per row group
    for lazy in (clf.predict(rows), clf.predict_proba(rows), clf.transform(rows)):
        assert len(lazy.__dask_graph__().layers) == 1
        assert len(dict(lazy.__dask_graph__())) == rows.numblocks[0]
        assert lazy.chunks[0] == rows.chunks[0]
    proba = client.compute(clf.predict_proba(rows)).result()
    cuts = np.cumsum(rows.chunks[0])[:-1]
    expect = np.concatenate([clf.predict_proba(b) for b in np.split(Xn, cuts)])
    np.testing.assert_array_equal(proba, expect)
    # any other array of rows (here the rows times one) takes the read tasks as inputs
    sliced = clf.predict(rows * 1.0)
    assert len(sliced.__dask_graph__().layers) > 1
    np.testing.assert_array_equal(client.compute(sliced).result(), ours)
    np.testing.assert_array_equal(
        tc.read_parquet_rows(paths[0], columns=["q3", "q0"]).compute(), Xn[:200, [3, 0]]
    )
    # row groups joined into blocks of at most 128 rows, never across files; the row
    # method still handles one row group at a time, so its results are the same bits
    joined = tc.read_parquet_rows(paths, block_rows=128)
    assert joined.chunks == ((128, 72, 100), (16,))
    assert tc.read_parquet_rows(paths).chunks == ((200, 100), (16,))
    np.testing.assert_array_equal(client.compute(joined).result(), Xn)
    lazy = clf.predict_proba(joined)
    assert len(dict(lazy.__dask_graph__())) == 3 and lazy.chunks[0] == joined.chunks[0]
    np.testing.assert_array_equal(client.compute(lazy).result(), expect)
    np.testing.assert_array_equal(client.compute(clf.predict(joined)).result(), ours)
    for bad in (0, -5, 2.5, True):
        with pytest.raises(tc.errors.InputError, match="block_rows must be a positive integer"):
            tc.read_parquet_rows(paths, block_rows=bad)
    with pytest.raises(tc.errors.InputError, match="no column 'z'"):
        tc.read_parquet_rows(paths, columns=["z"])
    (tmp_path / "bad.parquet").write_text("not parquet")
    with pytest.raises(tc.errors.InputError, match="not a readable Parquet file"):
        tc.read_parquet_rows([tmp_path / "bad.parquet"])
    with pytest.raises(tc.errors.InputError, match="no Parquet files"):
        tc.read_parquet_rows([])


def test_read_parquet_rows_types_and_imports(tmp_path):
    """Integers and nulls convert; a worker reading a row group does not import pandas."""
    import subprocess
    import sys

    path = tmp_path / "m.parquet"
    table = {"a": pa.array([1, 2, 3], pa.int32()), "b": pa.array([1.5, None, 2.0])}
    pq.write_table(pa.table(table), path)
    np.testing.assert_array_equal(
        tc.read_parquet_rows(path).compute(scheduler="sync"), [[1, 1.5], [2, np.nan], [3, 2.0]]
    )
    probe = (
        "import sys, numpy as np; from tentaclass._dask import _read_row_group; "
        f"x = _read_row_group({str(path)!r}, 0, ['a', 'b'], np.dtype(float)); "
        "print(x[:, 0].tolist(), 'pandas' in sys.modules)"
    )
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["[1.0,", "2.0,", "3.0]", "False"]


def test_read_parquet_rows_names_a_path_that_is_not_a_file_name():
    with pytest.raises(InputError, match=r"paths must be a file name .*, got None"):
        tc.read_parquet_rows([None])


def test_estimator_agrees_with_dask_ml(client, data):
    """An independent implementation of block-wise predict: dask-ml's ParallelPostFit."""
    wrappers = pytest.importorskip("dask_ml.wrappers")
    X, y, Xn = data
    clf = tc.FourierClassifier(spread=0.5).fit(X, y)
    dX = da.from_array(Xn, chunks=(70, 16))
    theirs = wrappers.ParallelPostFit(estimator=clf).predict_proba(dX)
    ours, theirs = client.compute([clf.predict_proba(dX), theirs], sync=True)
    np.testing.assert_array_equal(ours, theirs)


def test_estimator_checks_eagerly(tentacle):
    with pytest.raises(ValueError, match="12 features"):
        tentacle.predict(da.zeros((10, 12), chunks=5))
    with pytest.raises(ValueError, match="n_harmonics"):
        tc.fourier_features(da.zeros((10, 16), chunks=5), n_harmonics=9)


def test_wrap_many_chunked(client):
    starts = np.linspace(0, 1, 60, endpoint=False)
    ref = tc.wrap_many(rectangle(3.0, 1.0), 16, 0.5, starts=starts, offset=0.7)
    lazy = tc.wrap_many(
        rectangle(3.0, 1.0), 16, 0.5, starts=da.from_array(starts, chunks=25), offset=0.7
    )
    assert isinstance(lazy.angles, da.Array) and lazy.angles.chunks[0] == (25, 25, 10)
    names = ["angles", "joints", "contact", "lap", "laps", "complete", "closure_gap", "n_placed"]
    got = client.compute([getattr(lazy, k) for k in names], sync=True)
    for k, v in zip(names, got, strict=True):
        np.testing.assert_array_equal(v, getattr(ref, k), err_msg=k)


def test_wrap_many_noise_per_block(client):
    """Noise seeds follow the blocks: the same on 2 workers as in one process."""
    starts = da.from_array(np.linspace(0, 1, 40, endpoint=False), chunks=10)
    lazy = tc.wrap_many(square(4.0), 16, 1.0, starts=starts, noise=0.05, random_state=7)
    on_cluster = client.compute(lazy.angles).result()
    in_process = lazy.angles.compute(scheduler="sync")
    np.testing.assert_array_equal(on_cluster, in_process)
    clean = tc.wrap_many(square(4.0), 16, 1.0, starts=np.linspace(0, 1, 40, endpoint=False))
    assert 0.03 < np.std(on_cluster - clean.angles) < 0.07


def test_wrap_many_bag_of_outlines(client):
    outlines = [square(4.0), circle(2.0), triangle([(0, 0), (4, 0), (1, 3)]), square(3.0)]
    lazy = tc.wrap_many(db.from_sequence(outlines, npartitions=3), 12, 0.6)
    got = client.compute(lazy.angles).result()
    np.testing.assert_array_equal(got, tc.wrap_many(outlines, 12, 0.6).angles)


def test_synthetic_tentacle_on_client(client):
    ref = synthetic_tentacle(40, 16, random_state=3)
    got = synthetic_tentacle(40, 16, random_state=3, client=client)
    np.testing.assert_array_equal(got.data, ref.data)
    np.testing.assert_array_equal(got.target, ref.target)
    np.testing.assert_array_equal(got.laps, ref.laps)


def test_mpeg7_bisection_on_client(client):
    """The MPEG-7 wraps' bisection through joblib's Dask backend (a few outlines)."""
    from tentaclass.datasets._wraps import _one_lap_wraps

    outlines = [square(4.0), rectangle(3.0, 1.0), circle(2.0), triangle([(0, 0), (4, 0), (1, 3)])]
    ref = _one_lap_wraps(outlines, 16, "taut", 1, 5)
    with _dask.on_client(client):
        got = _one_lap_wraps(outlines, 16, "taut", 1, 5, n_jobs=-1)
    np.testing.assert_array_equal(got, ref)


# -- command line ------------------------------------------------------------------------------


def _write_logs(folder, Xn):
    for i in range(3):
        part = Xn[i * 100 : (i + 1) * 100]
        table = pa.table({f"q{j}": part[:, j] for j in range(part.shape[1])})
        pq.write_table(table, folder / f"log{i}.parquet", row_group_size=30)
    np.save(folder / "log3.npy", Xn[:40])
    np.savetxt(folder / "log4.csv", Xn[:10], delimiter=",")


def _run(*args):
    return CliRunner().invoke(cli, [str(a) for a in args])


def test_train_and_classify_files(client, data, tmp_path):
    X, y, Xn = data
    np.savez(tmp_path / "train.npz", X=X, y=y)
    address = client.scheduler.address
    model = tmp_path / "m.tcm"
    res = _run("train", "--data", tmp_path / "train.npz", "--out", model, "--scheduler", address)
    assert res.exit_code == 0, res.output
    assert "training accuracy 1.000" in res.output
    logs = tmp_path / "logs"
    logs.mkdir()
    _write_logs(logs, Xn)
    outs = {}
    for name, extra in (("here", []), ("cluster", ["--scheduler", address])):
        res = _run(
            "classify",
            "--model",
            model,
            "--files",
            f"{logs}/log*",
            "--out-dir",
            tmp_path / name,
            *extra,
        )
        assert res.exit_code == 0, res.output
        outs[name] = sorted(p.name for p in (tmp_path / name).iterdir())
    assert (
        outs["here"]
        == outs["cluster"]
        == [
            "log0.labels.parquet",
            "log1.labels.parquet",
            "log2.labels.parquet",
            "log3.labels.csv",
            "log4.labels.csv",
        ]
    )
    for name in outs["here"]:
        assert (tmp_path / "here" / name).read_bytes() == (tmp_path / "cluster" / name).read_bytes()
    table = pq.read_table(tmp_path / "cluster" / "log1.labels.parquet").to_pandas()
    assert table["index"].tolist() == list(range(100))
    assert table["label"].tolist() == tc.load_model(model).predict(Xn[100:200]).tolist()


@pytest.mark.scanner  # its kernels compile on the scanner tests' worker
def test_scan_files(client, tmp_path):
    from tentaclass.scanner.io import write_pbm
    from tentaclass.scanner.simulate import make_belt

    belts = tmp_path / "belts"
    belts.mkdir()
    for i in range(3):
        write_pbm(belts / f"belt{i}.pbm", make_belt(6, 128, random_state=i).image)
    for name, extra in (("here", []), ("cluster", ["--scheduler", client.scheduler.address])):
        res = _run("scan", "--files", f"{belts}/*.pbm", "--out-dir", tmp_path / name, *extra)
        assert res.exit_code == 0, res.output
    for i in range(3):
        here = (tmp_path / "here" / f"belt{i}.jsonl").read_text()
        assert here == (tmp_path / "cluster" / f"belt{i}.jsonl").read_text()
        single = _run("scan", belts / f"belt{i}.pbm")
        assert here.splitlines() == single.stdout.splitlines()
        assert len(here.splitlines()) == 6 and json.loads(here.splitlines()[0])["label"]


def test_bench_on_scheduler(client, tmp_path):
    common = [
        "bench",
        "--dataset",
        "synthetic",
        "--links",
        16,
        "--samples",
        40,
        "--methods",
        "fourier-1nn",
        "--folds",
        2,
    ]
    here = _run(*common, "--out", tmp_path / "a")
    there = _run(*common, "--out", tmp_path / "b", "--scheduler", client.scheduler.address)
    assert here.exit_code == 0 and there.exit_code == 0, there.output

    def accuracy(res):
        return [line.split("|")[2] for line in res.stdout.splitlines() if "fourier-1nn" in line]

    assert accuracy(here) == accuracy(there) != []


# -- bad input ---------------------------------------------------------------------------------


def test_unreachable_scheduler(monkeypatch, tmp_path):
    monkeypatch.setattr(_dask, "CONNECT_TIMEOUT", 1.0)
    res = _run(
        "classify",
        "--files",
        f"{tmp_path}/*.npy",
        "--out-dir",
        tmp_path,
        "--scheduler",
        "tcp://127.0.0.1:9",
    )
    assert res.exit_code == 1
    assert res.output.strip().splitlines()[-1].startswith("Error: cannot reach the Dask scheduler")
    res = _run("scan", "--files", "x", "--out-dir", tmp_path, "--scheduler", "somewhere")
    assert res.exit_code == 1 and "tcp://host:8786" in res.output
    assert "Traceback" not in res.output


def test_files_of_another_chain_length(client, data, tentacle, tmp_path):
    Xn = data[2]
    model = tmp_path / "m.tcm"
    tc.save_model(tentacle, model)
    logs = tmp_path / "logs"
    logs.mkdir()
    np.save(logs / "a.npy", Xn[:20])
    pq.write_table(pa.table({f"q{j}": Xn[:20, j] for j in range(12)}), logs / "b.parquet")
    res = _run(
        "classify",
        "--model",
        model,
        "--files",
        f"{logs}/*",
        "--out-dir",
        tmp_path / "out",
        "--scheduler",
        client.scheduler.address,
    )
    assert res.exit_code == 1
    assert res.output.strip().splitlines()[-1] == (
        f"Error: {logs / 'b.parquet'}: arrays of 12 joint angles, but the model expects 16"
    )
    assert not (tmp_path / "out").exists()  # refused before any work


def test_map_files_twice_with_the_same_arguments(client):
    """Back-to-back calls sharing an argument each get it (no call loses the other's copy)."""
    job = "{} -> {} with {}".format
    ins, outs = ["a", "b"], ["A", "B"]
    for _ in range(4):
        got = _dask.map_files(job, ins, outs, 5, client=client, progress=False)
        assert got == ["a -> A with 5", "b -> B with 5"]


def test_failing_file_leaves_no_output(client, data, tmp_path, monkeypatch):
    """A file that fails half way: its output never appears, not even in part."""
    _, _, Xn = data
    bad = Xn[:100].copy()
    bad[80, 3] = np.nan
    logs = tmp_path / "logs"
    logs.mkdir()
    pq.write_table(pa.table({f"q{j}": bad[:, j] for j in range(16)}), logs / "bad.parquet")
    from tentaclass.cli import _files

    monkeypatch.setattr(_files, "BLOCK_ROWS", 32)  # in this process: fails in block 3
    res = _run("classify", "--files", f"{logs}/*", "--out-dir", tmp_path / "out")
    assert res.exit_code == 1 and "array 80 holds NaN" in res.output
    assert list((tmp_path / "out").iterdir()) == []
    res = _run(
        "classify",
        "--files",
        f"{logs}/*",
        "--out-dir",
        tmp_path / "out2",
        "--scheduler",
        client.scheduler.address,
    )
    assert res.exit_code == 1 and "array 80 holds NaN" in res.output
    assert list((tmp_path / "out2").iterdir()) == []


class _DieOnce(distributed.WorkerPlugin):
    """Kills the worker process the first time it starts a classify task."""

    def __init__(self, marker):
        self.marker = str(marker)

    def transition(self, key, start, finish, **kwargs):
        if finish == "executing" and "classify_file" in str(key):
            try:
                fd = os.open(self.marker, os.O_CREAT | os.O_EXCL)
            except FileExistsError:
                return
            os.close(fd)
            os._exit(1)


def test_worker_dies_mid_job(client, data, tmp_path):
    _, _, Xn = data
    logs = tmp_path / "logs"
    logs.mkdir()
    _write_logs(logs, Xn)
    client.register_plugin(_DieOnce(tmp_path / "died"), name="die-once")
    try:
        res = _run(
            "classify",
            "--files",
            f"{logs}/*.parquet",
            "--out-dir",
            tmp_path / "out",
            "--scheduler",
            client.scheduler.address,
        )
    finally:
        client.unregister_worker_plugin("die-once")
    assert (tmp_path / "died").exists()  # a worker did die
    assert res.exit_code == 0, res.output  # its task ran again on another worker
    here = _run("classify", "--files", f"{logs}/*.parquet", "--out-dir", tmp_path / "ref")
    assert here.exit_code == 0
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == [
        f"log{i}.labels.parquet" for i in range(3)
    ]
    for i in range(3):
        name = f"log{i}.labels.parquet"
        got, ref = (pq.read_table(tmp_path / d / name).to_pydict() for d in ("out", "ref"))
        assert got.keys() == ref.keys() and got["label"] == ref["label"]
        for key in got:  # the PNN's sums are tiled by thread count: the last bits may differ
            if key.startswith("p"):
                np.testing.assert_allclose(got[key], ref[key], rtol=1e-12, atol=1e-300)
    client.wait_for_workers(2, timeout=30)


@pytest.mark.parametrize(
    ("client", "match"),
    [
        ("localhost:8786", r"got str \(to use a scheduler at an address, pass distributed.Client"),
        (1, "client must be a distributed.Client or None, got int$"),
    ],
)
def test_a_client_that_is_not_a_client_is_refused(client, match):
    # was an AttributeError ('str' object has no attribute 'scheduler_info')
    with pytest.raises(InputError, match=match):
        synthetic_tentacle(5, client=client)


def test_wrap_many_refuses_unknown_chunk_sizes():
    starts = da.linspace(0.0, 0.5, 4, chunks=2)
    unknown = starts[starts > -1]  # boolean indexing: chunk sizes NaN
    with pytest.raises(InputError, match=r"unknown ones .*: call \.compute_chunk_sizes\(\)"):
        tc.wrap_many(square(1.0), 16, 0.2, starts=unknown)
    known = unknown.compute_chunk_sizes()
    got = tc.wrap_many(square(1.0), 16, 0.2, starts=known).angles.compute()
    np.testing.assert_array_equal(got, tc.wrap_many(square(1.0), 16, 0.2, starts=starts).angles)
