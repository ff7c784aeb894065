"""Classifiers: PNN, RBF network, MLP presets, shift-invariant 1-NN, tentacle pipeline."""

from ._mlp import FixedEpochsMLPClassifier, modern_mlp, thesis_mlp
from ._pnn import PNNClassifier
from ._rbf import RBFNetworkClassifier
from ._shift_nn import ShiftNNClassifier
from ._tentacle import TentacleClassifier

__all__ = [
    "FixedEpochsMLPClassifier",
    "PNNClassifier",
    "RBFNetworkClassifier",
    "ShiftNNClassifier",
    "TentacleClassifier",
    "modern_mlp",
    "thesis_mlp",
]
