"""Run the code in the user guides under docs/."""

import re
from pathlib import Path

DOCS = Path(__file__).resolve().parents[1] / "docs"


def run_python_blocks(name: str, min_blocks: int = 1) -> dict:
    """Execute every ```python block of docs/<name> in one namespace; return it."""
    path = DOCS / name
    blocks = re.findall(r"```python\n(.*?)```", path.read_text(), flags=re.DOTALL)
    assert len(blocks) >= min_blocks, f"{path} has {len(blocks)} python blocks"
    namespace: dict = {}
    for block in blocks:
        exec(compile(block, str(path), "exec"), namespace)
    return namespace
