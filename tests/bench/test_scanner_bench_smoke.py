import importlib.util
from pathlib import Path

BENCH = Path(__file__).resolve().parents[2] / "benchmarks" / "bench_scanner.py"
EXAMPLE = Path(__file__).resolve().parents[2] / "benchmarks" / "scanner_defect_curve.py"


def _load(path):
    spec = importlib.util.spec_from_file_location(path.stem, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_benchmark_runs_tiny(capsys, monkeypatch):
    module = _load(BENCH)
    monkeypatch.setitem(module.BELTS, "tiny", (300, 6, (5.0, 9.0)))
    (result,) = module.main(belts=("tiny",), repeat=1, chunk_rows=64, threads=(1,))
    assert result["objects"] == result["placed"] > 0
    assert result["chunks_lines_per_s"] > 0 and result["label_lines_per_s"] > 0
    out = capsys.readouterr().out
    assert "| tiny | 300 / 6 |" in out and "load average" in out


def test_defect_curve_example_runs_tiny(tmp_path):
    summary = _load(EXAMPLE).main(n=24, seed=1, out=str(tmp_path / "curve.png"))
    assert summary["objects"] == 24
    assert (tmp_path / "curve.png").exists()
