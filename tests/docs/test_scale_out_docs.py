import doctest
from pathlib import Path

import pytest

GUIDE = Path(__file__).resolve().parents[2] / "docs" / "scale-out.md"

pytest.importorskip("dask.array")


@pytest.mark.skipif(not GUIDE.exists(), reason="guide not present")
def test_scale_out_examples_run():
    flags = doctest.NORMALIZE_WHITESPACE | doctest.ELLIPSIS
    result = doctest.testfile(str(GUIDE), module_relative=False, optionflags=flags)
    assert result.failed == 0 and result.attempted >= 10
