"""Descriptors: joint angles -> turning function -> Fourier features."""

from .fourier import dft_layer, fourier_features
from .lap import last_lap
from .laps import LapSplit, split_laps
from .transformers import AngleSpectrum, FourierFeatures, LastLap
from .turning import canonical_direction, periodic_signal, turning_function

__all__ = [
    "AngleSpectrum",
    "FourierFeatures",
    "LapSplit",
    "LastLap",
    "canonical_direction",
    "dft_layer",
    "fourier_features",
    "last_lap",
    "periodic_signal",
    "split_laps",
    "turning_function",
]
