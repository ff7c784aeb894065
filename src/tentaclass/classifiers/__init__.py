"""Classifiers: the default TentacleClassifier; the thesis pipeline, PNN, RBF, MLP, shift 1-NN.

Every name loads its module (and scikit-learn) on first use. The ``...Core``
classes (not public) hold what the estimators compute to predict, free of
scikit-learn: model files predict with them (:mod:`tentaclass.io._light`).
"""

from typing import TYPE_CHECKING

from .._lazy import lazy_exports

if TYPE_CHECKING:
    from ._fourier import FourierClassifier
    from ._mlp import FixedEpochsMLPClassifier, modern_mlp, thesis_mlp
    from ._outline import OutlineClassifier
    from ._pnn import PNNClassifier
    from ._pnn_core import PNNCore as PNNCore
    from ._rbf import RBFNetworkClassifier
    from ._retrieval import bullseye_score, shape_distances
    from ._shift_core import ShiftCore as ShiftCore
    from ._shift_nn import ShiftNNClassifier
    from ._tentacle import TentacleClassifier
    from ._tentacle_core import TentacleCore as TentacleCore

__getattr__, __dir__ = lazy_exports(
    __name__,
    {
        "FixedEpochsMLPClassifier": "_mlp",
        "FourierClassifier": "_fourier",
        "OutlineClassifier": "_outline",
        "PNNClassifier": "_pnn",
        "RBFNetworkClassifier": "_rbf",
        "ShiftNNClassifier": "_shift_nn",
        "TentacleClassifier": "_tentacle",
        "bullseye_score": "_retrieval",
        "modern_mlp": "_mlp",
        "shape_distances": "_retrieval",
        "thesis_mlp": "_mlp",
        "PNNCore": "_pnn_core",
        "ShiftCore": "_shift_core",
        "TentacleCore": "_tentacle_core",
    },
    globals(),
)

__all__ = [
    "FixedEpochsMLPClassifier",
    "FourierClassifier",
    "OutlineClassifier",
    "PNNClassifier",
    "RBFNetworkClassifier",
    "ShiftNNClassifier",
    "TentacleClassifier",
    "bullseye_score",
    "modern_mlp",
    "shape_distances",
    "thesis_mlp",
]
