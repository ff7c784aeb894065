"""Hypothesis strategies shared by the tests."""

import os

import numpy as np
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

FUZZ_FACTOR = 25


def examples(n):
    """``n`` examples in the deterministic suite, many more under ``make fuzz``."""
    return n * FUZZ_FACTOR if os.environ.get("HYPOTHESIS_PROFILE") == "fuzz" else n


@st.composite
def closed_laps(draw, min_n=3, max_n=64):
    """Joint angles of one closed counter-clockwise lap: sum(q) == 2 pi."""
    n = draw(st.integers(min_n, max_n))
    # |q| stays below pi, so the angles a chain measures equal the ones drawn
    a = min(1.0, (np.pi - 2 * np.pi / n) / 2 - 0.01)
    noise = draw(hnp.arrays(np.float64, n, elements=st.floats(-a, a, allow_nan=False)))
    q = 2 * np.pi / n + noise - noise.mean()
    return q
