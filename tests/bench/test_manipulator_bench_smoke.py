"""The dynamics benchmark script runs (tiny sizes)."""

import importlib.util
from pathlib import Path

import pytest

pytest.importorskip("pinocchio")

SCRIPT = Path(__file__).resolve().parents[2] / "benchmarks" / "bench_dynamics.py"


def test_bench_dynamics_runs(capsys):
    spec = importlib.util.spec_from_file_location("bench_dynamics", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    rows = module.main(batch=20, ns=(2, 5), repeat=1)
    assert [(r["quantity"], r["n"]) for r in rows] == [
        (q, n)
        for n in (2, 5)
        for q in ("H (mass matrix)", "h + g (bias torques)", "inverse dynamics")
    ]
    assert all(r["tentaclass"] > 0 and r["pinocchio"] > 0 for r in rows)
    out = capsys.readouterr().out
    assert "| quantity | n |" in out
    table = [line for line in out.splitlines() if line.startswith("|")]
    assert len(table) == 2 + len(rows)  # header, separator, one line per row
