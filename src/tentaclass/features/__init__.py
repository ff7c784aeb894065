"""Descriptors: joint angles -> turning function -> Fourier features."""

from .fourier import dft_layer, fourier_features
from .lap import last_lap
from .outline import SIGNATURES, outline_to_series, znormalize
from .transformers import AngleSpectrum, FourierFeatures, LastLap
from .turning import canonical_direction, periodic_signal, turning_function

__all__ = [
    "SIGNATURES",
    "AngleSpectrum",
    "FourierFeatures",
    "LastLap",
    "canonical_direction",
    "dft_layer",
    "fourier_features",
    "last_lap",
    "outline_to_series",
    "periodic_signal",
    "turning_function",
    "znormalize",
]
