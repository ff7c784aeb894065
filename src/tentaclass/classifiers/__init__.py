"""Classifiers: the default TentacleClassifier; the thesis pipeline, PNN, RBF, MLP, shift 1-NN."""

from ._fourier import FourierClassifier
from ._mlp import FixedEpochsMLPClassifier, modern_mlp, thesis_mlp
from ._pnn import PNNClassifier
from ._rbf import RBFNetworkClassifier
from ._shift_nn import ShiftNNClassifier
from ._tentacle import TentacleClassifier

__all__ = [
    "FixedEpochsMLPClassifier",
    "FourierClassifier",
    "PNNClassifier",
    "RBFNetworkClassifier",
    "ShiftNNClassifier",
    "TentacleClassifier",
    "modern_mlp",
    "thesis_mlp",
]
