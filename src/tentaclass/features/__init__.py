"""Descriptors: joint angles -> turning function -> Fourier features."""

from .fourier import dft_layer, fourier_features
from .transformers import FourierFeatures
from .turning import canonical_direction, periodic_signal, turning_function

__all__ = [
    "FourierFeatures",
    "canonical_direction",
    "dft_layer",
    "fourier_features",
    "periodic_signal",
    "turning_function",
]
