"""The code in docs/manipulator.md runs."""

import re
from pathlib import Path

import pytest

DOC = Path(__file__).resolve().parents[2] / "docs" / "manipulator.md"


@pytest.mark.skipif(not DOC.exists(), reason="docs not shipped")
def test_guide_code_blocks_run():
    blocks = re.findall(r"```python\n(.*?)```", DOC.read_text(), flags=re.DOTALL)
    assert len(blocks) >= 3
    namespace: dict = {}
    exec(compile("\n".join(blocks), str(DOC), "exec"), namespace)
    assert namespace["held"].q.shape == (501, 16)
