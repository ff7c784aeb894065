"""The benchmark scripts run (tiny sizes, seconds): they do not rot."""

import importlib.util
from pathlib import Path

import pytest

BENCH = Path(__file__).resolve().parents[2] / "benchmarks"


def load(name):
    spec = importlib.util.spec_from_file_location(name, BENCH / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_bench_fourier_smoke(capsys):
    rows = load("bench_fourier").main(n_arrays=300, ns=(16, 64), loop_arrays=50, repeat=1)
    assert [(r["threads"], r["n"]) for r in rows] == [(1, 16), (1, 64), ("all", 16), ("all", 64)]
    assert all(r["ours"] > 0 for r in rows)
    out = capsys.readouterr().out
    assert "bare matmul" in out and "BLAS threads" in out and "load average" in out


def test_bench_pnn_smoke(capsys):
    rows = load("bench_pnn").main(n_train=600, n_test=400, n_features=8, n_classes=3, repeat=1)
    assert [r["dtype"] for r in rows][:2] == ["float64", "float32"]
    assert [r["threads"] for r in rows][:2] == [1, 1]
    assert all(r["pnn"] > 0 and r["knn"] > 0 and r["bare"] > 0 for r in rows)
    out = capsys.readouterr().out
    assert "1-NN / PNN" in out and "load average" in out
    load("bench_pnn").components(n_train=3000, n_test=200, repeat=1, centres=0.0)
    out = capsys.readouterr().out
    assert "compiled exp + sum" in out and "NumPy exp" in out and "load average" in out


def test_bench_shift_nn_smoke(capsys):
    pytest.importorskip("aeon", reason="needs the bench extra (aeon)")
    rows = load("bench_shift_nn").main(n_train=60, n_test=20, repeat=1, n_classes=3)
    assert rows and all(float(r[2]) > 0 and float(r[4]) > 0 for r in rows)
    assert "predict / MiniRocket" in capsys.readouterr().out


def test_bench_recognition_quick(tmp_path, capsys):
    load("bench_recognition").main(quick=True, out=tmp_path)
    assert "| thesis |" in capsys.readouterr().out
    assert (tmp_path / "quick.md").exists()


def test_mpeg7_ceiling_smoke(mpeg7_folder, tmp_path, capsys):
    import shutil

    for cls in ("apple", "Bone", "key"):
        files = sorted(mpeg7_folder.glob(f"{cls}-*.png"))[:10]
        assert len(files) == 10
        for f in files:
            shutil.copy(f, tmp_path / f.name)
    rows = load("mpeg7_ceiling").main(folder=tmp_path, points=(64,))
    acc = dict(((kind, n), a) for kind, n, a in rows)
    # three distinct classes: the outline tells them apart, the hull nearly so
    assert acc["outline", 64] >= 0.9 and acc["hull", 64] >= 0.7
    assert "exact hull" in capsys.readouterr().out


def test_bench_physics_smoke(tmp_path, capsys):
    pytest.importorskip("mujoco", reason="needs the physics extra: pip install mujoco")
    args = ["--grasps", "1", "--links", "8", "--repeat", "1", "--jobs", "1"]
    out = load("bench_physics").main([*args, "--folder", str(tmp_path / "absent")])
    assert set(out["best"]) == {"serial", "parallel", "quasi", "geometric"}
    assert "grasps / s" in capsys.readouterr().out


def test_physics_agreement_smoke(tmp_path, capsys):
    pytest.importorskip("mujoco", reason="needs the physics extra: pip install mujoco")
    out = load("physics_agreement").main(
        ["--mpeg7", "0", "--jobs", "1", "--out", str(tmp_path / "a.json")]
    )
    assert set(out["thesis"]) == {"square", "circle", "rectangle", "triangle"}
    assert (tmp_path / "a.json").exists()


def test_physics_sim_to_real_smoke(tmp_path, capsys):
    pytest.importorskip("mujoco", reason="needs the physics extra: pip install mujoco")
    args = ["--part", "thesis", "--thesis", "8", "--train", "48", "--jobs", "1"]
    out = load("physics_sim_to_real").main([*args, "--out", str(tmp_path / "s.json")])
    assert (tmp_path / "s.json").exists()
    assert "TentacleClassifier()" in capsys.readouterr().out
    assert out["thesis"]
