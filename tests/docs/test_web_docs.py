"""The code in docs/web.md runs and says what it shows."""

from docs_helpers import run_python_blocks


def test_guide_code_blocks_run():
    ns = run_python_blocks("web.md", min_blocks=1)
    assert ns["outline"].shape == (128, 2)
    assert ns["answer"].label == "arrow"
    assert ns["state"] == "multiple"
    assert ns["full_lap"] and ns["chain_answer"].label == "heart"
