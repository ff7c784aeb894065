"""Array type aliases shared by the public API."""

import numpy as np
from numpy.typing import ArrayLike, NDArray

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]
IntArray = NDArray[np.intp]

__all__ = ["ArrayLike", "BoolArray", "FloatArray", "IntArray"]
