"""Descriptors: joint angles -> turning function -> Fourier features."""

from typing import TYPE_CHECKING

from .._lazy import lazy_exports
from .fourier import dft_layer, fourier_features
from .lap import last_lap
from .laps import LapSplit, split_laps
from .outline import SIGNATURES, outline_to_series, znormalize
from .turning import canonical_direction, periodic_signal, turning_function

if TYPE_CHECKING:
    from ._transform_core import AngleSpectrumCore as AngleSpectrumCore
    from ._transform_core import FourierFeaturesCore as FourierFeaturesCore
    from ._transform_core import LastLapCore as LastLapCore
    from .transformers import AngleSpectrum, FourierFeatures, LastLap

# the scikit-learn transformers load scikit-learn on first use; their cores
# (not public: what they compute, free of scikit-learn) serve model files
__getattr__, __dir__ = lazy_exports(
    __name__,
    {
        **dict.fromkeys(["AngleSpectrum", "FourierFeatures", "LastLap"], "transformers"),
        **dict.fromkeys(
            ["AngleSpectrumCore", "FourierFeaturesCore", "LastLapCore"], "_transform_core"
        ),
    },
    globals(),
)

__all__ = [
    "SIGNATURES",
    "AngleSpectrum",
    "FourierFeatures",
    "LapSplit",
    "LastLap",
    "canonical_direction",
    "dft_layer",
    "fourier_features",
    "last_lap",
    "outline_to_series",
    "periodic_signal",
    "split_laps",
    "turning_function",
    "znormalize",
]
