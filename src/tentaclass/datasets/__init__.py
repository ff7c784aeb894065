"""Built-in and generated data: the thesis's arrays and grids, wraps of shapes, UCR outlines."""

from ._thesis import THESIS_CLASSES, reference_tentacle, thesis_scanner, thesis_tentacle
from ._ucr import UCR_SHAPES, ucr_shapes
from ._wraps import PROTOCOLS, chain_wraps, clear_cache, mpeg7_tentacle, synthetic_tentacle

__all__ = [
    "PROTOCOLS",
    "THESIS_CLASSES",
    "UCR_SHAPES",
    "chain_wraps",
    "clear_cache",
    "mpeg7_tentacle",
    "reference_tentacle",
    "synthetic_tentacle",
    "thesis_scanner",
    "thesis_tentacle",
    "ucr_shapes",
]
