"""tentaclass: recognise objects from one-dimensional data arrays.

The data flow is arrays -> descriptors -> classifiers -> reports:

- :mod:`tentaclass.geometry`: joint angles <-> points of a planar chain;
- :mod:`tentaclass.features`: turning function, periodic signal, Fourier features;
- :mod:`tentaclass.classifiers`: PNN and the end-to-end :class:`TentacleClassifier`;
- :mod:`tentaclass.datasets`: the thesis's arrays and grids;
- :mod:`tentaclass.report`: results as columns / JSON;
- :mod:`tentaclass.shapes`, :func:`wrap`: object outlines and the joint angles a chain
  wrapped around them measures; :func:`grasp_state` reads laps and offset back;
- :mod:`tentaclass.manipulator`: kinematics and dynamics of the planar n-link chain;
- :mod:`tentaclass.scanner`: the linear object scanner (classes and defects on a belt);
- :mod:`tentaclass.io`: model files (arrays + JSON, never pickle);
- :mod:`tentaclass.plot`: every figure (matplotlib, imported lazily).
"""

from . import shapes
from .classifiers import (
    PNNClassifier,
    RBFNetworkClassifier,
    ShiftNNClassifier,
    TentacleClassifier,
    modern_mlp,
    thesis_mlp,
)
from .features import (
    FourierFeatures,
    canonical_direction,
    dft_layer,
    fourier_features,
    periodic_signal,
    turning_function,
)
from .geometry import angles_to_points, points_to_angles, resample_closed
from .io import load_model, save_model
from .manipulator import ChainKinematics, PlanarChain, Trajectory
from .scanner import Defect, Inspection, LineScanner, ScannedObject, ScannerModel
from .wrapping import (
    GraspState,
    Wrap,
    WrapBatch,
    capture_error,
    closing_link_length,
    grasp_state,
    max_link_length,
    wrap,
    wrap_many,
)

__version__ = "0.1.0"

__all__ = [
    "ChainKinematics",
    "Defect",
    "FourierFeatures",
    "GraspState",
    "Inspection",
    "LineScanner",
    "PNNClassifier",
    "PlanarChain",
    "RBFNetworkClassifier",
    "ScannedObject",
    "ScannerModel",
    "ShiftNNClassifier",
    "TentacleClassifier",
    "Trajectory",
    "Wrap",
    "WrapBatch",
    "__version__",
    "angles_to_points",
    "canonical_direction",
    "capture_error",
    "closing_link_length",
    "dft_layer",
    "fourier_features",
    "grasp_state",
    "load_model",
    "max_link_length",
    "modern_mlp",
    "periodic_signal",
    "points_to_angles",
    "resample_closed",
    "save_model",
    "shapes",
    "thesis_mlp",
    "turning_function",
    "wrap",
    "wrap_many",
]
