"""The code in docs/manipulator.md runs."""

from docs_helpers import run_python_blocks


def test_guide_code_blocks_run():
    namespace = run_python_blocks("manipulator.md", min_blocks=3)
    assert namespace["held"].q.shape == (501, 16)
