import importlib.util
from pathlib import Path

BENCH = Path(__file__).resolve().parents[2] / "benchmarks" / "bench_scanner.py"
EXAMPLE = Path(__file__).resolve().parents[2] / "benchmarks" / "scanner_defect_curve.py"


def _load(path):
    spec = importlib.util.spec_from_file_location(path.stem, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_benchmark_runs_tiny(capsys):
    result = _load(BENCH).main(n_lines=600, width=256, per_1000=20, chunk_rows=128, repeat=1)
    assert result["objects_found"] == result["objects_placed"] > 0
    assert result["scanner_lines_per_s"] > 0 and result["ndimage_label_lines_per_s"] > 0
    assert '"lines": 600' in capsys.readouterr().out


def test_defect_curve_example_runs_tiny(tmp_path):
    summary = _load(EXAMPLE).main(n=24, seed=1, out=str(tmp_path / "curve.png"))
    assert summary["objects"] == 24
    assert (tmp_path / "curve.png").exists()
