"""Classifiers: the default TentacleClassifier; the thesis pipeline, PNN, RBF, MLP, shift 1-NN."""

from ._fourier import FourierClassifier
from ._mlp import FixedEpochsMLPClassifier, modern_mlp, thesis_mlp
from ._outline import OutlineClassifier
from ._pnn import PNNClassifier
from ._rbf import RBFNetworkClassifier
from ._retrieval import bullseye_score, shape_distances
from ._shift_nn import ShiftNNClassifier
from ._tentacle import TentacleClassifier

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
