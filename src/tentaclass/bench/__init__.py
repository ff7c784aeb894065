"""Benchmark harness: accuracy and speed of methods on a dataset, side by side."""

from ._methods import METHODS, make_method, method_names
from ._runner import BenchResult, confusion_figure, results_markdown, run_benchmark

__all__ = [
    "METHODS",
    "BenchResult",
    "confusion_figure",
    "make_method",
    "method_names",
    "results_markdown",
    "run_benchmark",
]
