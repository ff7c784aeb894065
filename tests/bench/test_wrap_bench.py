"""The wrap benchmark script runs (tiny sizes): it does not rot."""

import importlib.util
from pathlib import Path

BENCH = Path(__file__).resolve().parents[2] / "benchmarks" / "bench_wrap.py"


def test_bench_wrap_smoke(capsys):
    spec = importlib.util.spec_from_file_location("bench_wrap", BENCH)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    rows = module.main(n_outlines=3, starts_per_outline=4, ns=(16,), modes=("taut", "hug"))
    assert [(r["mode"], r["n"]) for r in rows] == [("taut", 16), ("hug", 16)]
    assert all(r["wraps_per_s"] > 0 for r in rows)
    assert "wraps / s" in capsys.readouterr().out
