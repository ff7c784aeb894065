"""The scanner's classifier: grids -> descriptors -> PNN.

:class:`ScannerModel` learns classes from example grids (a handful per class
is enough). :func:`default_model` is the thesis's four classes, learned from
the thesis's 16 training grids *and* 400 generated clean shapes (see its
docstring). Models are saved without pickle, in the ``.tcm`` format of
:func:`tentaclass.io.save_model`.
"""

from __future__ import annotations

import json
import warnings
from collections.abc import Sequence
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np
from sklearn.base import BaseEstimator, ClassifierMixin, clone
from sklearn.exceptions import NotFittedError
from sklearn.neighbors import KNeighborsClassifier
from sklearn.utils.validation import check_is_fitted

from .._deprecation import DEPRECATED, renamed_param
from .._thesis_data import scanner_training_grids
from .._validation import MAX_POINTS, as_grid_list, as_object_mask, check_positive_int
from ..classifiers import PNNClassifier
from ..errors import InputError, ModelFileError
from ..features.fourier import _one_blas_thread
from .descriptors import (
    DESCRIPTOR_GROUPS,
    Geometry,
    Measures,
    feature_names,
    features_matrix,
    measure_many,
    measures_features,
)

__all__ = ["FORMAT_NAME", "FORMAT_VERSION", "ScannerModel", "default_model"]

#: From this many rows on, the classifier runs with BLAS on one thread.
_ONE_THREAD_MIN_ROWS = 64

FORMAT_NAME = "tentaclass-scanner-model"
"""Value of ``format`` in the metadata of the former ``.npz`` model files."""
FORMAT_VERSION = 1
"""The only version of the former ``.npz`` format."""

# Classifiers a former .npz model file can name: rebuilt from their JSON parameters.
_SAVABLE = {"PNNClassifier": PNNClassifier, "KNeighborsClassifier": KNeighborsClassifier}


def crop(grid: np.ndarray) -> tuple[np.ndarray, int, int]:
    """The grid cut to its object's bounding box, and the box's top-left corner.

    ``grid`` is 2-D, bool or 0 and 1, with at least one object pixel.
    """
    grid = as_object_mask(grid, "grid")
    rows = np.nonzero(grid.any(axis=1))[0]
    cols = np.nonzero(grid.any(axis=0))[0]
    return grid[rows[0] : rows[-1] + 1, cols[0] : cols[-1] + 1], int(rows[0]), int(cols[0])


class ScannerModel(ClassifierMixin, BaseEstimator):
    """Classifier of binary object grids, invariant to position, rotation and scale.

    Parameters
    ----------
    classifier : scikit-learn classifier, optional
        Applied to the descriptors as they are: they are all ratios on a
        scale of about 0 to 1, so no scaler is needed (a scaler would blow up
        whatever happens to vary little among the examples, such as the pixel
        scale when all examples have one size). Default
        ``PNNClassifier(spread=0.1)``, a probabilistic neural network with
        MATLAB newpnn's default spread. Any classifier
        :func:`tentaclass.io.save_model` holds can be saved.
    descriptors : sequence of {"hull", "outline", "region"}, default=("hull",)
        Descriptor groups (:mod:`tentaclass.scanner.descriptors`). ``"hull"``
        ignores holes and bites, so damaged objects keep their class; add
        ``"outline"`` or ``"region"`` for classes that differ by concavities
        or holes.
    n_points : int, default=64
        Chords of the walk around an outline.
    n_harmonics : int, default=4
        Fourier features per outline.
    n_coeffs : int, optional
        Deprecated alias of ``n_harmonics``.

    Attributes
    ----------
    classes_ : ndarray of shape (n_classes,)
        Class labels, sorted.
    features_ : ndarray of shape (n_samples, n_features)
        Descriptors of the training grids (saved with the model).
    labels_ : ndarray of shape (n_samples,)
        Their labels.
    sizes_ : ndarray of shape (n_samples, 2)
        ``(length, width)`` of each training object, in pixels.
    feature_names_ : list of str
        Names of the descriptor columns.
    classifier_ : classifier
        The fitted classifier.

    Examples
    --------
    >>> from tentaclass.datasets import thesis_scanner
    >>> d = thesis_scanner()
    >>> model = ScannerModel().fit(d.grids, d.target)
    >>> model.predict(d.grids[:4]).tolist()
    ['square', 'square', 'square', 'square']
    >>> model.score(d.grids, d.target)
    1.0
    """

    def __init__(
        self,
        classifier: Any = None,
        *,
        descriptors: Sequence[str] = ("hull",),
        n_points: int = 64,
        n_harmonics: int = 4,
        n_coeffs: Any = DEPRECATED,
    ):
        self.classifier = classifier
        self.descriptors = descriptors
        self.n_points = n_points
        self.n_harmonics = n_harmonics
        self.n_coeffs = n_coeffs

    # -- parameters --------------------------------------------------------------------------
    def _check_params(self) -> tuple[tuple[str, ...], int, int]:
        desc = (self.descriptors,) if isinstance(self.descriptors, str) else self.descriptors
        desc = tuple(desc)
        if not desc:
            raise InputError("descriptors must name at least one descriptor group")
        for d in desc:
            if d not in DESCRIPTOR_GROUPS:
                raise InputError(f"descriptors must be among {list(DESCRIPTOR_GROUPS)}, got {d!r}")
        n_points = check_positive_int(self.n_points, "n_points", minimum=8, maximum=MAX_POINTS)
        n_harmonics = renamed_param(self, "n_harmonics", "n_coeffs", default=4)
        n_harmonics = check_positive_int(n_harmonics, "n_harmonics")
        if n_harmonics > n_points // 2:
            raise InputError(f"n_harmonics must be at most n_points // 2 = {n_points // 2}")
        return desc, n_points, n_harmonics

    def _make_classifier(self) -> Any:
        return PNNClassifier(spread=0.1) if self.classifier is None else clone(self.classifier)

    # -- features ----------------------------------------------------------------------------
    def features(self, geometries: Sequence[Geometry]) -> np.ndarray:
        """Descriptor matrix of measured objects (see :func:`.descriptors.measure`)."""
        desc, n_points, n_harmonics = self._check_params()
        if not geometries:
            return np.empty((0, len(feature_names(desc, n_harmonics))))
        return features_matrix(geometries, desc, n_points=n_points, n_harmonics=n_harmonics)

    def _batch_features(self, measures: Measures) -> np.ndarray:
        """:meth:`features` of a measured batch (arrays, no per-object geometry)."""
        desc, n_points, n_harmonics = self._check_params()
        return measures_features(measures, desc, n_points, n_harmonics)

    def transform(self, grids: Any) -> np.ndarray:
        """Descriptors of each grid's object.

        Parameters
        ----------
        grids : sequence of 2-D binary arrays or array of shape (n_grids, rows, cols)

        Returns
        -------
        features : ndarray of shape (n_grids, n_features)
        """
        return self.features(measure_many([crop(g)[0] for g in as_grid_list(grids)])[0])

    # -- fitting -----------------------------------------------------------------------------
    def fit(self, grids: Any, labels: Any) -> ScannerModel:
        """Learn the classes from example grids, one object per grid.

        Parameters
        ----------
        grids : sequence of 2-D binary arrays or array of shape (n_grids, rows, cols)
            Example objects; grids may differ in size.
        labels : array_like of shape (n_grids,)
            Class name of each grid (strings).

        Returns
        -------
        self : ScannerModel
        """
        grids = as_grid_list(grids)
        geoms = measure_many([crop(g)[0] for g in grids])[0]
        sizes = np.array([[g.length, g.width] for g in geoms], dtype=float)
        return self._fit_features(self.features(geoms), labels, sizes)

    def _fit_features(self, X: np.ndarray, labels: Any, sizes: np.ndarray) -> ScannerModel:
        desc, _, n_harmonics = self._check_params()
        y = np.asarray(labels)
        if y.ndim != 1 or y.shape[0] != X.shape[0]:
            raise InputError(
                f"labels must be 1-D with one label per grid ({X.shape[0]}), got shape {y.shape}"
            )
        y = y.astype(str)
        classes = np.unique(y)
        if classes.size < 2:
            raise InputError(f"labels must hold at least 2 classes, got {classes.tolist()}")
        self.classifier_ = self._make_classifier().fit(X, y)
        self.classes_ = classes
        self.features_ = X
        self.labels_ = y
        self.sizes_ = sizes
        self.feature_names_ = feature_names(desc, n_harmonics)
        self.n_features_in_ = X.shape[1]
        return self

    # -- prediction --------------------------------------------------------------------------
    def predict_features_proba(self, X: np.ndarray) -> np.ndarray:
        """Class probabilities from a descriptor matrix (columns in :attr:`classes_` order)."""
        if not hasattr(self, "classifier_"):  # (check_is_fitted costs more than a small batch)
            check_is_fitted(self)
        if X.shape[0] >= _ONE_THREAD_MIN_ROWS:
            # the classifier's products are thin: BLAS threads only cost here
            with _one_blas_thread():
                proba = self.classifier_.predict_proba(X)
        else:
            proba = self.classifier_.predict_proba(X)
        order = np.searchsorted(self.classes_, self.classifier_.classes_)
        out = np.zeros((X.shape[0], self.classes_.size))
        out[:, order] = proba
        return out

    def predict_proba(self, grids: Any) -> np.ndarray:
        """Class probabilities of each grid's object.

        Returns
        -------
        proba : ndarray of shape (n_grids, n_classes)
        """
        check_is_fitted(self)
        return self.predict_features_proba(self.transform(grids))

    def predict(self, grids: Any) -> np.ndarray:
        """Class of each grid's object.

        Returns
        -------
        labels : ndarray of shape (n_grids,)
        """
        return self.classes_[np.argmax(self.predict_proba(grids), axis=1)]

    def nominal_sizes(self) -> dict[str, tuple[float, float]]:
        """Median ``(length, width)`` of each class's training objects, in pixels.

        Examples
        --------
        >>> from tentaclass.datasets import thesis_scanner
        >>> d = thesis_scanner()
        >>> ScannerModel().fit(d.grids, d.target).nominal_sizes()["square"]
        (3.5, 3.5)
        """
        check_is_fitted(self)
        medians = {str(c): np.median(self.sizes_[self.labels_ == c], axis=0) for c in self.classes_}
        return {c: (float(m[0]), float(m[1])) for c, m in medians.items()}

    # -- files -------------------------------------------------------------------------------
    def save(self, path: str | Path) -> None:
        """Write the model to a ``.tcm`` model file (see :func:`tentaclass.io.save_model`).

        The file holds the descriptor settings, the training descriptors
        (``features_``), labels and sizes, and the fitted classifier, as
        arrays plus JSON, in the format every tentaclass model uses.

        Raises
        ------
        InputError
            If the classifier is not one that model files can hold.
        """
        from ..io import save_model

        check_is_fitted(self)
        self._check_params()
        save_model(self, path)

    @classmethod
    def load(cls, path: str | Path) -> ScannerModel:
        """Read a model written by :meth:`save`, checking everything.

        Files in the scanner's former ``.npz`` format are still read, with a
        ``DeprecationWarning``: save them again to convert them.

        Raises
        ------
        ModelFileError
            If the file is missing (:class:`~tentaclass.errors.ModelFileNotFoundError`),
            a directory, not a model file, from an unknown format
            version, holds another kind of model, or its contents are
            inconsistent.

        Examples
        --------
        >>> import tempfile, os
        >>> from tentaclass.datasets import thesis_scanner
        >>> d = thesis_scanner()
        >>> model = ScannerModel().fit(d.grids, d.target)
        >>> path = os.path.join(tempfile.mkdtemp(), "model.tcm")
        >>> model.save(path)
        >>> ScannerModel.load(path).predict(d.grids[4:6]).tolist()
        ['circle', 'circle']
        """
        from ..io import load_model
        from ..io._model_file import model_path

        path = model_path(path)
        if _is_legacy_npz(path):
            model = cls._load_npz(path)
            warnings.warn(
                f"{path}: the scanner's .npz model format is deprecated and will not be "
                "read in the next release; save the model again to write a .tcm file",
                DeprecationWarning,
                stacklevel=2,
            )
            return model
        model = load_model(path)
        if not isinstance(model, cls):
            raise ModelFileError(f"{path}: holds a {type(model).__name__}, not a scanner model")
        try:
            check_is_fitted(model)
            model._check_params()
        except (InputError, NotFittedError) as exc:
            raise ModelFileError(f"{path}: not a usable scanner model ({exc})") from None
        return model

    @classmethod
    def _load_npz(cls, path: Path) -> ScannerModel:
        """Read the former ``.npz`` format (features, labels, sizes, JSON metadata)."""
        try:
            with open(path, "rb") as fh:
                npz = np.load(fh, allow_pickle=False)
                if not isinstance(npz, np.lib.npyio.NpzFile):
                    raise ModelFileError(f"{path}: not a model file (a bare .npy array)")
                with npz:
                    arrays = {k: npz[k] for k in npz.files}
        except ModelFileError:
            raise
        except Exception as exc:
            # A damaged archive fails in many ways (BadZipFile on a CRC mismatch,
            # zlib.error inside the deflate stream, NotImplementedError on a bad
            # compression method, ...): whatever fails while reading is a bad file.
            raise ModelFileError(
                f"{path}: not a readable model file ({type(exc).__name__}: {exc})"
            ) from exc
        return cls._from_arrays(arrays, str(path))

    @classmethod
    def _from_arrays(cls, arrays: dict[str, np.ndarray], where: str) -> ScannerModel:
        def bad(msg: str) -> ModelFileError:
            return ModelFileError(f"{where}: {msg}")

        missing = {"features", "labels", "sizes", "metadata"} - set(arrays)
        if missing:
            raise bad(f"not a scanner model file (missing {sorted(missing)})")
        meta_arr = arrays["metadata"]
        if meta_arr.ndim != 0 or meta_arr.dtype.kind != "U":
            raise bad("metadata must be a JSON string")
        try:
            meta = json.loads(str(meta_arr))
        except json.JSONDecodeError as exc:
            raise bad(f"metadata is not valid JSON ({exc})") from exc
        if not isinstance(meta, dict) or meta.get("format") != FORMAT_NAME:
            raise bad(f"not a {FORMAT_NAME} file")
        if meta.get("version") != FORMAT_VERSION:
            raise bad(
                f"unknown format version {meta.get('version')!r}; this release reads "
                f"version {FORMAT_VERSION}"
            )
        X, y, sizes = arrays["features"], arrays["labels"], arrays["sizes"]
        if X.dtype != np.float64 or X.ndim != 2 or not np.all(np.isfinite(X)):
            raise bad("features must be a finite 2-D float64 array")
        if y.dtype.kind != "U" or y.shape != (X.shape[0],):
            raise bad(f"labels must be {X.shape[0]} strings, got {y.dtype} {y.shape}")
        if sizes.dtype != np.float64 or sizes.shape != (X.shape[0], 2):
            raise bad(f"sizes must be float64 of shape ({X.shape[0]}, 2)")
        clf_meta = meta.get("classifier")
        if not isinstance(clf_meta, dict) or clf_meta.get("name") not in _SAVABLE:
            raise bad(f"classifier must be one of {sorted(_SAVABLE)}")
        try:
            clf = _SAVABLE[clf_meta["name"]](**clf_meta.get("params", {}))
            model = cls(
                clf,
                descriptors=tuple(meta["descriptors"]),
                n_points=meta["n_points"],
                n_harmonics=meta["n_coeffs"],
            )
            desc, _, n_harmonics = model._check_params()
        except (KeyError, TypeError, InputError) as exc:
            raise bad(f"invalid settings ({exc})") from exc
        names = feature_names(desc, n_harmonics)
        if meta.get("feature_names") != names or X.shape[1] != len(names):
            raise bad("feature columns do not match the descriptor settings")
        if sorted(set(y.tolist())) != meta.get("classes"):
            raise bad("labels do not match the classes in the metadata")
        try:
            return model._fit_features(X, y, sizes)
        except (InputError, ValueError) as exc:
            raise bad(f"cannot rebuild the classifier ({exc})") from exc


@lru_cache(maxsize=1)
def _default_model() -> ScannerModel:
    from .simulate import make_objects

    thesis_grids, thesis_target = scanner_training_grids()
    gen = make_objects(400, damaged_fraction=0.0, radius_range=(4.0, 28.0), random_state=0)
    grids = list(thesis_grids) + list(gen.grids)
    labels = np.concatenate([thesis_target, gen.target])
    return ScannerModel().fit(grids, labels)


def default_model() -> ScannerModel:
    """The thesis's four classes: square, circle, triangle, rectangle.

    Trained (once per process, in about a second, deterministic) on

    - the thesis's 16 training grids (5 x 5, :func:`~tentaclass.datasets.thesis_scanner`)
      as they are: the pixel-square hull needs no upsampling;
    - 400 generated clean shapes (:func:`~tentaclass.scanner.simulate.make_objects`,
      seed 0), 100 per class, in 64 x 64 grids at random positions, rotations
      and sizes (circumradius 4-28 pixels); rectangles have aspect 1.6-2.6.

    Returns
    -------
    model : ScannerModel
        A shared fitted instance: do not refit it (``clone`` it instead).

    Examples
    --------
    >>> default_model().classes_.tolist()
    ['circle', 'rectangle', 'square', 'triangle']
    """
    return _default_model()


def _is_legacy_npz(path: Path) -> bool:
    """Whether ``path`` is a zip holding ``metadata.npy`` (the former scanner format)."""
    import zipfile

    try:
        with zipfile.ZipFile(path) as zf:
            names = zf.namelist()
    except Exception:  # whatever a damaged zip raises: load_model names the problem
        return False
    return "metadata.npy" in names and "metadata.json" not in names
