"""tentaclass: recognise objects from one-dimensional data arrays.

The data flow is arrays -> descriptors -> classifiers -> reports:

- :mod:`tentaclass.geometry`: joint angles <-> points of a planar chain;
- :mod:`tentaclass.features`: turning function, periodic signal, Fourier features;
- :mod:`tentaclass.classifiers`: the default :class:`TentacleClassifier` (any wrap of a
  fixed chain), the thesis's :class:`FourierClassifier`, PNN and more;
- :mod:`tentaclass.datasets`: the thesis's arrays and grids;
- :mod:`tentaclass.report`: results as columns / JSON;
- :mod:`tentaclass.shapes`, :func:`wrap`: object outlines and the joint angles a chain
  wrapped around them measures; :func:`grasp_state` reads laps and offset back;
- :mod:`tentaclass.manipulator`: kinematics and dynamics of the planar n-link chain;
- :mod:`tentaclass.scanner`: the linear object scanner (classes and defects on a belt);
- :mod:`tentaclass.io`: model files (arrays + JSON, never pickle);
- :mod:`tentaclass.plot`: every figure (matplotlib, imported lazily).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ._lazy import lazy_exports

if TYPE_CHECKING:
    from . import shapes
    from ._dask import read_parquet_rows
    from .classifiers import (
        FourierClassifier,
        OutlineClassifier,
        PNNClassifier,
        RBFNetworkClassifier,
        ShiftNNClassifier,
        TentacleClassifier,
        bullseye_score,
        modern_mlp,
        shape_distances,
        thesis_mlp,
    )
    from .features import (
        FourierFeatures,
        canonical_direction,
        dft_layer,
        fourier_features,
        outline_to_series,
        periodic_signal,
        split_laps,
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
    "FourierClassifier",
    "FourierFeatures",
    "GraspState",
    "Inspection",
    "LineScanner",
    "OutlineClassifier",
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
    "bullseye_score",
    "canonical_direction",
    "capture_error",
    "closing_link_length",
    "dft_layer",
    "fourier_features",
    "grasp_state",
    "load_model",
    "max_link_length",
    "modern_mlp",
    "outline_to_series",
    "periodic_signal",
    "points_to_angles",
    "read_parquet_rows",
    "resample_closed",
    "save_model",
    "shape_distances",
    "shapes",
    "split_laps",
    "thesis_mlp",
    "turning_function",
    "wrap",
    "wrap_many",
]

# Public name -> the subpackage that defines it. Subpackages are imported on
# first use, so that ``import tentaclass`` (and the CLI's start) stays light:
# scikit-learn, matplotlib and scipy.stats load only when something needs them.
_HOME = {
    "FourierClassifier": "classifiers",
    "OutlineClassifier": "classifiers",
    "bullseye_score": "classifiers",
    "shape_distances": "classifiers",
    "outline_to_series": "features",
    "split_laps": "features",
    "ChainKinematics": "manipulator",
    "Defect": "scanner",
    "FourierFeatures": "features",
    "GraspState": "wrapping",
    "Inspection": "scanner",
    "LineScanner": "scanner",
    "PNNClassifier": "classifiers",
    "PlanarChain": "manipulator",
    "RBFNetworkClassifier": "classifiers",
    "ScannedObject": "scanner",
    "ScannerModel": "scanner",
    "ShiftNNClassifier": "classifiers",
    "TentacleClassifier": "classifiers",
    "Trajectory": "manipulator",
    "Wrap": "wrapping",
    "WrapBatch": "wrapping",
    "angles_to_points": "geometry",
    "canonical_direction": "features",
    "capture_error": "wrapping",
    "closing_link_length": "wrapping",
    "dft_layer": "features",
    "fourier_features": "features",
    "grasp_state": "wrapping",
    "load_model": "io",
    "max_link_length": "wrapping",
    "modern_mlp": "classifiers",
    "periodic_signal": "features",
    "points_to_angles": "geometry",
    "read_parquet_rows": "_dask",
    "resample_closed": "geometry",
    "save_model": "io",
    "thesis_mlp": "classifiers",
    "turning_function": "features",
    "wrap": "wrapping",
    "wrap_many": "wrapping",
}

_HOME["shapes"] = "shapes"
__getattr__, __dir__ = lazy_exports(__name__, _HOME, globals())
