"""What the fitted transformers compute, free of scikit-learn.

The transformers of :mod:`tentaclass.features.transformers` inherit it; a
model file is evaluated with it without importing scikit-learn
(:mod:`tentaclass.io._light`). ``_transform`` takes checked arrays.
"""

from __future__ import annotations

import numpy as np

from .._typing import FloatArray
from .fourier import fourier_features
from .lap import last_lap


class FourierFeaturesCore:
    """``|DFT|`` of the periodic turning signal, frequencies ``1 .. n_harmonics_``."""

    n_harmonics_: int
    detrend: bool
    normalize: bool
    weight_power: float

    def _transform(self, X: FloatArray) -> FloatArray:
        features = fourier_features(
            X, self.n_harmonics_, detrend=self.detrend, normalize=self.normalize
        )
        if self.weight_power:
            features *= np.arange(1, self.n_harmonics_ + 1) ** float(self.weight_power)
        return features


class LastLapCore:
    """The last full lap, resampled to ``n_out_`` links."""

    n_out_: int

    def _transform(self, X: FloatArray) -> FloatArray:
        return last_lap(X, self.n_out_)[0]


class AngleSpectrumCore:
    """``|rfft(q)| / n_joints``, frequencies ``0 .. n_harmonics_ - 1``."""

    n_harmonics_: int

    def _transform(self, X: FloatArray) -> FloatArray:
        return np.abs(np.fft.rfft(X, axis=1)[:, : self.n_harmonics_]) / X.shape[1]
