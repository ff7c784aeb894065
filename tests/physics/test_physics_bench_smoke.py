"""The physics benchmark scripts run (tiny sizes): they do not rot."""

import importlib.util
from pathlib import Path

import pytest

pytest.importorskip("mujoco", reason="needs the physics extra: pip install mujoco")

BENCH = Path(__file__).resolve().parents[2] / "benchmarks"


def load(name):
    spec = importlib.util.spec_from_file_location(name, BENCH / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_bench_physics_smoke(tmp_path, capsys):
    out = load("bench_physics").main(["--grasps", "1", "--links", "8", "--repeat", "1", "--jobs",
                                      "1", "--folder", str(tmp_path / "absent")])  # fmt: skip
    assert set(out["best"]) == {"serial", "parallel", "geometric"}
    assert "grasps / s" in capsys.readouterr().out


def test_physics_agreement_smoke(tmp_path, capsys):
    args = ["--mpeg7", "0", "--thesis", "8", "--train", "200", "--jobs", "1"]
    out = load("physics_agreement").main([*args, "--out", str(tmp_path / "a.json")])
    assert set(out["thesis"]) == {"square", "circle", "rectangle", "triangle"}
    assert out["sim_to_real"]["n"] == 8
    assert (tmp_path / "a.json").exists()
    assert "chord-shape-nn" in capsys.readouterr().out
