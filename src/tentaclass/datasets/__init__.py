"""Built-in and generated data: the thesis's arrays and grids, wraps of shapes, UCR outlines."""

from ._thesis import THESIS_CLASSES, reference_tentacle, thesis_scanner, thesis_tentacle
from ._ucr import UCR_SHAPES, ucr_shapes
from ._wraps import chain_wraps, mpeg7_tentacle, synthetic_tentacle

__all__ = [
    "THESIS_CLASSES",
    "UCR_SHAPES",
    "chain_wraps",
    "mpeg7_tentacle",
    "reference_tentacle",
    "synthetic_tentacle",
    "thesis_scanner",
    "thesis_tentacle",
    "ucr_shapes",
]
