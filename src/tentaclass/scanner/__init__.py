"""Linear object scanner: classify objects on a conveyor belt and flag damaged ones.

- :func:`inspect`: one object's binary grid -> :class:`Inspection` (class,
  position, size, defects, accept);
- :class:`ScannerModel`, :func:`default_model`: the classifier, saved and
  loaded without pickle;
- :class:`LineScanner`: rows from a line sensor, in chunks of any size ->
  :class:`ScannedObject` records as soon as each object has passed;
- :mod:`~tentaclass.scanner.simulate`: seeded generator of objects and belts;
- :mod:`~tentaclass.scanner.io`: reading rows from text, PBM/PNG and raw bytes;
- figures are in :mod:`tentaclass.plot.scanner`.
"""

from .defects import DefectSettings
from .inspection import inspect, inspect_many
from .model import ScannerModel, default_model
from .records import DEFECT_KINDS, Defect, Inspection, ScannedObject
from .stream import LineScanner

__all__ = [
    "DEFECT_KINDS",
    "Defect",
    "DefectSettings",
    "Inspection",
    "LineScanner",
    "ScannedObject",
    "ScannerModel",
    "default_model",
    "inspect",
    "inspect_many",
]
