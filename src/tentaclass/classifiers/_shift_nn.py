"""Nearest neighbour under the best cyclic shift, by FFT cross-correlation."""

from __future__ import annotations

import numpy as np
from sklearn.base import BaseEstimator, ClassifierMixin

from .._dask import DaskMixin
from .._typing import ArrayLike, FloatArray
from .._validation import (
    check_choice,
    check_finite_float,
    check_fitted_X,
    check_frequency_count,
    check_targets,
    check_X_y,
)
from ..errors import InputError
from ._shift_core import ShiftCore

__all__ = ["ShiftNNClassifier"]


class ShiftNNClassifier(ShiftCore, DaskMixin, ClassifierMixin, BaseEstimator):
    """1-NN whose distance is minimised over cyclic shifts (and mirror images).

    ``d(a, b)^2 = min_s || a - roll(b, s) ||^2`` for periodic signals ``a`` and
    ``b`` of one length: the start point does not matter, but unlike ``|DFT|``
    features the phases between harmonics still do, so shapes whose spectra
    have equal magnitudes are told apart. All shifts are scored at once by a
    circular cross-correlation through the FFT, ``O(n log n)`` per pair.

    Parameters
    ----------
    signal : {"turning", "shape", "raw"}, default="turning"
        ``"turning"``: rows are joint angles; compare their detrended periodic
        turning signals (direction canonicalised). ``"shape"``: rows are joint
        angles of closed one-lap wraps; rebuild the joint polygon (closure
        errors spread evenly over the links, centred, unit size) and compare
        polygons under the best cyclic shift *and rotation* - a Procrustes
        distance over start points. ``"raw"``: rows are already periodic
        signals (e.g. centroid-distance profiles); compare them as they are.
    mirror : bool, default=True
        Also try each training signal reversed in time (a mirror image of the
        outline), and keep the better match.
    center : bool, default=True
        Remove each signal's mean first (a rotation of the object adds a
        constant to the turning signal).
    n_harmonics : int or float, optional
        Compare only frequencies ``1 .. n_harmonics`` (and the mean, unless
        ``center``); default all. A float in (0, 1) keeps that fraction of the
        ``floor(n_points / 2)`` frequencies, so one setting serves chains of any
        length. Chord sampling aliases fine detail into the high frequencies.
    weight_power : float, default=0.0
        Scale frequency ``k`` by ``k ** weight_power`` before comparing. Joint
        noise is white in the angles, so in the turning signal (their running
        sum) it falls like ``1 / k``: a power between 0.5 and 1 with the lowest
        half of the frequencies (``n_harmonics=0.5``) is what held up best on
        taut MPEG-7 wraps with 0.05 rad noise (BENCHMARKS.md).
    closure : {"spread", "chord"}, default="spread"
        How ``signal="shape"`` closes a chain that does not end where it began.
        ``"spread"``: set the total turn to one lap and remove the end-point gap
        linearly along the chain - right when the gap is joint noise, which it
        spreads evenly. ``"chord"``: close the polygon with the straight gap
        from the last joint to the first and resample it to equal arc lengths -
        right for clean encoders on a chain that stopped short of, or ran past,
        its start (the best on clean hugging MPEG-7 wraps, far worse than
        ``"spread"`` with joint noise; BENCHMARKS.md).

    Attributes
    ----------
    classes_ : ndarray of shape (n_classes,)
    n_features_in_ : int

    Examples
    --------
    >>> import numpy as np
    >>> X = np.array([np.sin(np.linspace(0, 2 * np.pi, 16, endpoint=False) * k) for k in (1, 2)])
    >>> clf = ShiftNNClassifier(signal="raw").fit(X, ["one", "two"])
    >>> clf.predict(np.roll(X, 5, axis=1)).tolist()
    ['one', 'two']
    """

    def __init__(
        self,
        signal: str = "turning",
        mirror: bool = True,
        center: bool = True,
        n_harmonics: int | float | None = None,
        weight_power: float = 0.0,
        closure: str = "spread",
    ):
        self.closure = closure
        self.signal = signal
        self.mirror = mirror
        self.center = center
        self.n_harmonics = n_harmonics
        self.weight_power = weight_power

    def _frequency_weights(self, n: int, complex_signal: bool) -> FloatArray:
        k = np.abs(np.fft.fftfreq(n, 1.0 / n)) if complex_signal else np.arange(n // 2 + 1)
        w = np.maximum(k, 1.0) ** check_finite_float(self.weight_power, "weight_power")
        if self.n_harmonics is None:
            return w
        h = check_frequency_count(self.n_harmonics, n // 2, "n_harmonics", "floor(n_points / 2)")
        return np.where(k <= h, w, 0.0)

    def fit(self, X: ArrayLike, y: ArrayLike) -> ShiftNNClassifier:
        """Store the training signals' spectra.

        Parameters
        ----------
        X : array_like of shape (n_samples, n_points)
        y : array_like of shape (n_samples,)

        Returns
        -------
        self : ShiftNNClassifier
        """
        check_choice(self.signal, "signal", ("turning", "shape", "raw"))
        check_choice(self.closure, "closure", ("spread", "chord"))
        for name in ("mirror", "center"):
            if not isinstance(getattr(self, name), bool | np.bool_):
                raise InputError(f"{name} must be True or False, got {getattr(self, name)!r}")
        X, y = check_X_y(self, X, y, dtype=np.float64)
        least = 3 if (self.signal == "shape" and self.closure == "chord") else 2
        if self.signal != "raw" and X.shape[1] < least:
            raise InputError(
                f"signal={self.signal!r} needs at least {least} joint angles, "
                f"got {X.shape[1]} feature(s)"
            )
        check_targets(y)
        self.classes_, self.labels_ = np.unique(y, return_inverse=True)
        s = self._signals(X)
        self.weights_ = self._frequency_weights(X.shape[1], np.iscomplexobj(s))
        self.spectra_, self.norms_ = self._spectrum(s)
        return self

    def shift_distances(self, X: ArrayLike) -> FloatArray:
        """Squared shift-invariant distances to every training signal.

        Parameters
        ----------
        X : array_like of shape (n_queries, n_points)

        Returns
        -------
        d2 : ndarray of shape (n_queries, n_train)
        """
        return self._shift_distances(check_fitted_X(self, X))

    def predict(self, X: ArrayLike) -> np.ndarray:
        """Class of the nearest training signal, shape (n_queries,).

        The same as the class at ``argmin(shift_distances(X), axis=1)``, but
        the exact distance (an inverse FFT per training signal) is computed
        only for the training signals a lower bound cannot rule out: the
        distance between the magnitude spectra, which no shift, mirror image
        or rotation changes, bounds the shift distance from below.
        """
        nearest = self._nearest(check_fitted_X(self, X))
        return self.classes_[self.labels_[nearest]]
