"""The code in docs/outline.md runs and shows what it says."""

import numpy as np
import pytest

pytest.importorskip("aeon", reason="needs the outline extra: pip install 'tentaclass[outline]'")

from docs_helpers import run_python_blocks


def test_outline_guide_code_runs():
    ns = run_python_blocks("outline.md", min_blocks=3)
    assert ns["s"].shape == (128,) and abs(ns["s"].mean() - 1) < 1e-9
    assert ns["clf"].predict(ns["query"]).tolist() == ["two lobes", "three lobes"]
    np.testing.assert_allclose(np.diag(ns["D"]), 0.0)
