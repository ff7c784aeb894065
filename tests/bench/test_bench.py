import numpy as np
import pytest
from click.testing import CliRunner

from tentaclass.bench import METHODS, confusion_figure, make_method, results_markdown, run_benchmark
from tentaclass.bench._runner import _splits
from tentaclass.cli.main import cli
from tentaclass.datasets import reference_tentacle
from tentaclass.errors import InputError


def test_run_benchmark_on_reference_shapes():
    X, y = reference_tentacle(32, n_starts=10, return_X_y=True)
    results = run_benchmark(X, y, ["thesis", "fourier-1nn", "1nn-euclidean"], n_splits=5)
    acc = {r.method: r.accuracy for r in results}
    assert acc["thesis"] == 1.0 and acc["fourier-1nn"] == 1.0
    assert all(r.n_test == len(y) for r in results)
    table = results_markdown(results, "t")
    assert table.count("\n| ") == 4 and "100.0%" in table
    fig = confusion_figure(results[0])
    assert fig.get_axes()[0].get_title().startswith("thesis")


def test_groups_keep_objects_apart_and_extra_wraps_only_train():
    X, y = reference_tentacle(16, n_starts=12, return_X_y=True)
    groups = np.arange(len(y)) // 3  # 3 arrays per object
    is_eval = np.arange(len(y)) % 3 == 0
    (r,) = run_benchmark(X, y, ["fourier-1nn"], groups=groups, is_eval=is_eval, n_splits=4)
    assert r.n_test == is_eval.sum()


def test_official_split_and_failing_method_is_reported():
    X, y = reference_tentacle(16, n_starts=4, return_X_y=True)
    split = np.where(np.arange(len(y)) % 2 == 0, "train", "test")
    (r,) = run_benchmark(X, y, ["thesis"], split=split)
    assert r.n_test == len(y) // 2 and r.accuracy == 1.0
    with pytest.raises(ValueError, match="unknown method"):
        run_benchmark(X, y, ["nope"])
    with pytest.raises(ValueError, match="unknown method"):
        make_method("nope")


def test_bench_cli_smoke(tmp_path):
    r = CliRunner().invoke(
        cli,
        ["bench", "--dataset", "reference", "--links", "16", "--samples", "40", "--folds", "3",
         "--methods", "thesis,shift-nn,1nn-euclidean", "--out", str(tmp_path)],
        catch_exceptions=False,
    )  # fmt: skip
    assert r.exit_code == 0, r.output
    assert "| thesis |" in r.output
    assert (tmp_path / "reference.md").exists() and (tmp_path / "reference-confusion.png").exists()


def test_bench_cli_bad_method():
    r = CliRunner().invoke(cli, ["bench", "--methods", "thesis,bogus"])
    assert r.exit_code == 2 and "bogus" in r.output


@pytest.mark.parametrize(
    "args, message",
    [
        (["--methods", ""], "no method given"),  # ran and wrote an empty table
        (["--methods", ",,"], "no method given"),
        (["--noise", "nan"], "finite"),  # was "X contains 128 NaN or infinite value(s)"
        (["--noise", "inf"], "inf is not in the range 0<=x<=6.28"),
        (["--random-state", "-1"], "--random-state"),  # was "expected non-negative integer"
        (["--jobs", "0"], "--jobs"),
        (["--jobs", "-2"], "--jobs"),
        (["--laps", "2,1"], "low <= high"),
        (["--laps", "x"], "low,high"),
        (["--offset", "-1,2"], "low <= high"),
        (["--protocol", "tuned"], "--protocol"),
    ],
)
def test_bench_cli_bad_options(tmp_path, args, message):
    r = CliRunner().invoke(cli, ["bench", "--out", str(tmp_path / "out"), *args])
    assert r.exit_code == 2 and message in r.output
    assert "Traceback" not in r.output
    assert not (tmp_path / "out").exists()


def test_bench_cli_mpeg7_missing_folder(tmp_path):
    r = CliRunner().invoke(
        cli, ["bench", "--dataset", "mpeg7", "--data-dir", str(tmp_path / "none"),
              "--methods", "thesis", "--out", str(tmp_path / "out")]
    )  # fmt: skip
    assert r.exit_code == 1 and "does not exist" in r.output
    assert len(r.output.strip().splitlines()) == 1


def test_bench_cli_passes_jobs_to_the_generator(tmp_path, monkeypatch):
    import tentaclass.datasets

    seen = {}

    def fake(folder, links, **kw):
        seen.update(kw)
        raise InputError("stop here")

    monkeypatch.setattr(tentaclass.datasets, "mpeg7_tentacle", fake)
    r = CliRunner().invoke(cli, ["bench", "--dataset", "mpeg7", "--methods", "thesis",
                                 "--out", str(tmp_path / "out")])  # fmt: skip
    assert r.exit_code == 1 and "stop here" in r.output
    assert seen["protocol"] == "fixed-chain" and seen["laps"] == (1.2, 2.0)
    assert seen["offset"] == (0.0, 2.0) and seen["progress"] is True
    # the one-lap protocol's bisection runs in --jobs processes (the fixed chain has none)
    r = CliRunner().invoke(cli, ["bench", "--dataset", "mpeg7", "--protocol", "one-lap",
                                 "--jobs", "2", "--methods", "thesis",
                                 "--out", str(tmp_path / "out")])  # fmt: skip
    assert r.exit_code == 1 and "stop here" in r.output
    assert seen["n_jobs"] == 2 and seen["protocol"] == "one-lap"


def test_failed_wraps_count_as_errors_and_never_train():
    X, y = reference_tentacle(16, n_starts=10, return_X_y=True)
    failed = np.zeros(len(y), bool)
    failed[::4] = True
    X = X.copy()
    X[failed, 8:] = np.nan  # a chain that stopped after 8 links
    (r,) = run_benchmark(X, y, ["thesis"], failed=failed, n_splits=5)
    assert r.n_test == len(y)
    assert r.accuracy == pytest.approx(1 - failed.mean())  # every other wrap is right
    assert (r.y_pred == "failed").sum() == failed.sum()


def test_bench_cli_ucr_without_aeon_names_the_data_set(tmp_path, monkeypatch):
    import sys

    monkeypatch.setitem(sys.modules, "aeon", None)  # import aeon -> ImportError
    monkeypatch.setitem(sys.modules, "aeon.datasets", None)
    r = CliRunner().invoke(
        cli, ["bench", "--dataset", "ArrowHead", "--methods", "thesis",
              "--out", str(tmp_path / "out")]
    )  # fmt: skip
    assert r.exit_code == 1
    assert "'ArrowHead' needs aeon" in r.output and "pip install" in r.output
    assert len(r.output.strip().splitlines()) == 1


# OutlineClassifier compares z-normalised outline series; a circle's joint
# angles are constant and have no shape to normalise (it says so).
@pytest.mark.parametrize(
    "name", [m.name for m in METHODS.values() if m.ours and m.name != "outline"]
)
def test_each_of_our_methods_recognises_the_reference_shapes(name):
    # two folds: each method trains on half the wraps (all 15 measured at 100 %)
    X, y = reference_tentacle(32, n_starts=24, return_X_y=True)
    (r,) = run_benchmark(X, y, [name], n_splits=2)
    assert not r.error and r.accuracy >= 0.9, (r.error, r.accuracy)


def test_objects_that_are_never_scored_still_train():
    _, y = reference_tentacle(16, n_starts=12, return_X_y=True)
    groups = np.arange(len(y))
    is_eval = np.arange(len(y)) % 2 == 0  # half the objects are never scored
    folds = _splits(y, groups, is_eval, None, 4, 0)
    for tr, te in folds:
        assert set(np.flatnonzero(~is_eval)) <= set(tr)  # always in training
        assert not set(tr) & set(te)
    assert sorted(np.concatenate([te for _, te in folds])) == np.flatnonzero(is_eval).tolist()


def _toy_ucr(folder, n=12, length=40, seed=0):
    """Two classes of outline-like series (one bump or two), cyclically shifted at random."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0, 2 * np.pi, length, endpoint=False)
    folder.mkdir()
    for split in ("TRAIN", "TEST"):
        lines = []
        for i in range(n):
            label = 1 + i % 2
            series = 1 + 0.3 * np.cos(label * t) + rng.normal(0, 0.01, length)
            series = np.roll(series, rng.integers(length))
            lines.append("\t".join([str(label)] + [f"{v:.6f}" for v in series]))
        (folder / f"Toy_{split}.tsv").write_text("\n".join(lines) + "\n")


def test_bench_cli_runs_a_ucr_set_from_disk_on_its_official_split(tmp_path):
    _toy_ucr(tmp_path / "Toy")
    out = tmp_path / "out"
    r = CliRunner().invoke(
        cli, ["bench", "--dataset", "ucr", "--ucr-path", str(tmp_path), "--name", "Toy",
              "--methods", "shift-nn-raw,1nn-euclidean", "--out", str(out)]
    )  # fmt: skip
    assert r.exit_code == 0, r.output
    table = (out / "ucr-Toy.md").read_text()
    assert "Toy from" in table and "official" in table
    rows = {line.split("|")[1].strip(): line for line in table.splitlines() if "|" in line}
    # one bump or two, at any start: the shift-invariant matcher gets every test series
    assert "100.0" in rows["shift-nn-raw"], table


def test_bench_cli_ucr_needs_a_path_and_a_readable_set(tmp_path):
    r = CliRunner().invoke(cli, ["bench", "--dataset", "ucr", "--methods", "thesis"])
    assert r.exit_code == 1 and "--ucr-path" in r.output
    assert len(r.output.strip().splitlines()) == 1
    (tmp_path / "Empty").mkdir()
    r = CliRunner().invoke(cli, ["bench", "--dataset", "ucr", "--ucr-path",
                                 str(tmp_path / "Empty"), "--methods", "thesis"])  # fmt: skip
    assert r.exit_code == 1 and "Empty_TRAIN.tsv" in r.output
    assert len(r.output.strip().splitlines()) == 1


@pytest.mark.slow
def test_bench_outline_method_on_a_ucr_set(tmp_path):
    pytest.importorskip("aeon", reason="OutlineClassifier needs aeon (the outline extra)")
    _toy_ucr(tmp_path / "Toy", seed=1)
    out = tmp_path / "out"
    r = CliRunner().invoke(cli, ["bench", "--dataset", "ucr", "--ucr-path", str(tmp_path / "Toy"),
                                 "--methods", "outline", "--out", str(out)])  # fmt: skip
    assert r.exit_code == 0, r.output
    row = next(
        line for line in (out / "ucr-Toy.md").read_text().splitlines() if "| outline" in line
    )
    assert "100.0" in row, row
