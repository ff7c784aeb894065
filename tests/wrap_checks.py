"""Shared helpers for the wrap / grasp tests: data location and link geometry checks."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import shapely

MPEG7 = (Path(__file__).resolve().parents[1] / "../shared/data/mpeg7-part-b").resolve()
needs_mpeg7 = pytest.mark.skipif(
    not MPEG7.is_dir(), reason=f"MPEG-7 Part B not found at {MPEG7} (shared data absent)"
)


def crossing_links(outline: np.ndarray, joints: np.ndarray, rel_tol: float = 1e-7) -> np.ndarray:
    """Per link: does it have points both inside and outside the object (beyond a tolerance)?"""
    poly = shapely.Polygon(outline)
    d = rel_tol * float(np.ptp(outline, axis=0).max())
    inner, outer = poly.buffer(-d), poly.buffer(d)
    lines = shapely.linestrings(np.stack([joints[:-1], joints[1:]], axis=1))
    inside = shapely.length(shapely.intersection(lines, inner)) > 0
    outside = shapely.length(shapely.difference(lines, outer)) > 0
    return inside & outside


def link_length(outline: np.ndarray, frac: float) -> float:
    """A link ``frac`` of the perimeter long, at most 0.95 of the object's largest extent."""
    largest = float(np.ptp(outline, axis=0).max())
    return min(frac * shapely.LinearRing(outline).length, 0.95 * largest)
