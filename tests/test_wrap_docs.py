"""The code in docs/wrapping.md runs."""

import re
from pathlib import Path

import pytest

DOC = Path(__file__).resolve().parents[1] / "docs" / "wrapping.md"


@pytest.mark.skipif(not DOC.exists(), reason="docs not shipped")
def test_wrapping_guide_code_runs():
    blocks = re.findall(r"```python\n(.*?)```", DOC.read_text(), flags=re.S)
    assert len(blocks) >= 4
    namespace: dict = {}
    for block in blocks:
        exec(compile(block, str(DOC), "exec"), namespace)
    assert namespace["w"].laps == pytest.approx(1.0)
    assert namespace["two"].angles.shape == (2, 16)
