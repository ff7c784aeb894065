"""Built-in data: the thesis's joint-angle arrays and scanner grids."""

from ._thesis import THESIS_CLASSES, reference_tentacle, thesis_scanner, thesis_tentacle

__all__ = ["THESIS_CLASSES", "reference_tentacle", "thesis_scanner", "thesis_tentacle"]
