"""Classifiers: PNN, RBF network, MLP presets, shift-invariant 1-NN, tentacle pipeline."""

from ._mlp import FixedEpochsMLPClassifier, modern_mlp, thesis_mlp
from ._outline import OutlineClassifier
from ._pnn import PNNClassifier
from ._rbf import RBFNetworkClassifier
from ._retrieval import bullseye_score, shape_distances
from ._shift_nn import ShiftNNClassifier
from ._tentacle import TentacleClassifier

__all__ = [
    "FixedEpochsMLPClassifier",
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
