"""The code in docs/wrapping.md runs."""

import pytest

from docs_helpers import run_python_blocks


def test_wrapping_guide_code_runs():
    namespace = run_python_blocks("wrapping.md", min_blocks=4)
    assert namespace["w"].laps == pytest.approx(1.0)
    assert namespace["two"].angles.shape == (2, 16)
