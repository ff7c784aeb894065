"""Built-in and generated data: thesis arrays and grids, wraps, drawn strokes, UCR outlines."""

from ._drawn import DRAWN_CLASSES, drawn_shapes
from ._thesis import THESIS_CLASSES, reference_tentacle, thesis_scanner, thesis_tentacle
from ._ucr import UCR_SHAPES, load_ucr, ucr_shapes
from ._wraps import PROTOCOLS, chain_wraps, clear_cache, mpeg7_tentacle, synthetic_tentacle

__all__ = [
    "DRAWN_CLASSES",
    "PROTOCOLS",
    "THESIS_CLASSES",
    "UCR_SHAPES",
    "chain_wraps",
    "clear_cache",
    "drawn_shapes",
    "load_ucr",
    "mpeg7_tentacle",
    "reference_tentacle",
    "synthetic_tentacle",
    "thesis_scanner",
    "thesis_tentacle",
    "ucr_shapes",
]
