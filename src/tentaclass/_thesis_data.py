"""The thesis's hand-typed data that library modules also need.

Kept apart from :mod:`tentaclass.datasets`, which is for users, so that the
library does not import it.
"""

from __future__ import annotations

import numpy as np

THESIS_CLASSES: tuple[str, ...] = ("square", "circle", "triangle", "rectangle")
"""Class names in the thesis's order (its output labels SQUARE, CIRCLE, ...)."""


def grid_from_text(rows: str) -> np.ndarray:
    return np.array([[c == "1" for c in r] for r in rows.split("/")], dtype=bool)


# Training grids of twodimensional.m, four per class (the printed listing
# garbles some of them; the smaller and shifted examples are reconstructed).
SCANNER_TRAIN = {
    "square": [
        "11111/11111/11111/11111/11111",
        "11110/11110/11110/11110/00000",
        "00000/01110/01110/01110/00000",
        "00000/00110/00110/00000/00000",
    ],
    "circle": [
        "00100/01110/11111/01110/00100",
        "00000/00100/01110/00100/00000",
        "01110/11111/11111/11111/01110",
        "00000/00000/00100/00000/00000",
    ],
    "triangle": [
        "00000/00000/00100/01110/11111",
        "00100/01110/11111/00000/00000",
        "10000/11000/11100/11000/10000",
        "00000/00000/00000/00100/01110",
    ],
    "rectangle": [
        "00000/11111/11111/11111/11111",
        "00000/00000/00000/11111/11111",
        "11110/11110/11110/11110/11110",
        "01100/01100/01100/01100/01100",
    ],
}

# Test grids of twodimensional.m: (name, grid, correct class, thesis's answer).
SCANNER_TEST = [
    ("square with a hole", "11111/11011/11011/11111/11111", "square", "triangle"),
    ("partial object", "00000/00000/11100/11100/11100", "square", "square"),
    ("square with a slot", "00000/11011/11011/11111/11111", "rectangle", None),
    ("left block", "11000/11000/11000/11000/11111", None, None),
    ("shifted block", "00000/00111/00111/00111/00000", "square", None),
]


def scanner_training_grids() -> tuple[np.ndarray, np.ndarray]:
    """The 16 training grids (5 x 5 bool, four per class) and their classes."""
    grids = [grid_from_text(rows) for c in THESIS_CLASSES for rows in SCANNER_TRAIN[c]]
    target = [c for c in THESIS_CLASSES for _ in SCANNER_TRAIN[c]]
    return np.stack(grids), np.array(target)
