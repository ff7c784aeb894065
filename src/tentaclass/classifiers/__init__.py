"""Classifiers: PNN and the end-to-end tentacle classifier."""

from ._pnn import PNNClassifier
from ._tentacle import TentacleClassifier

__all__ = ["PNNClassifier", "TentacleClassifier"]
