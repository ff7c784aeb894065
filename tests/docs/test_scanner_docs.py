import doctest
from pathlib import Path

import pytest

GUIDE = Path(__file__).resolve().parents[2] / "docs" / "scanner.md"


@pytest.mark.skipif(not GUIDE.exists(), reason="user guide not present")
def test_user_guide_examples_run():
    flags = doctest.NORMALIZE_WHITESPACE | doctest.ELLIPSIS
    result = doctest.testfile(str(GUIDE), module_relative=False, optionflags=flags)
    assert result.failed == 0 and result.attempted > 10
