"""Input checks for the public API.

Every public function validates its input here, once, at the boundary; the
private kernels behind it assume clean arrays.
"""

from __future__ import annotations

import numbers
import os
import warnings
from collections.abc import Collection, Iterable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ._typing import ArrayLike, FloatArray
from .errors import InputError, ShapeError, TentaclassWarning


def as_float_array(
    x: ArrayLike, name: str, *, min_ndim: int = 0, allow_nonfinite: bool = False
) -> FloatArray:
    """Convert ``x`` to a float64 array and check its rank and values.

    Numbers only: booleans, text, dates and masked values are refused, although
    NumPy would convert them (``True`` to 1.0, ``"2"`` to 2.0, a date to its
    seconds, a masked value to whatever lies under the mask).

    >>> as_float_array(np.array([0.0, 1.0]) > 0, "q")
    Traceback (most recent call last):
    ...
    tentaclass.errors.InputError: q must hold numbers, got booleans (dtype bool)
    """
    try:
        if np.iscomplexobj(x):
            raise InputError(f"{name} must hold real numbers, got complex values")
        if isinstance(x, np.ma.MaskedArray) and np.ma.is_masked(x):
            raise InputError(
                f"{name} holds {int(np.ma.count_masked(x))} masked value(s): fill or drop them"
            )
        arr = np.asarray(x)
        _check_number_kind(arr, name)
        arr = np.asarray(arr, dtype=np.float64)
    except InputError:
        raise
    except (TypeError, ValueError) as exc:
        ragged = ragged_error(x, name, exc)
        if ragged is not exc:
            raise ragged from None
        raise InputError(
            f"{name} must be an array of numbers; could not convert it: {exc}"
        ) from exc
    if arr.ndim < min_ndim:
        raise ShapeError(
            f"{name} must have at least {min_ndim} dimension(s), got an array of shape {arr.shape}"
        )
    if not allow_nonfinite and not np.all(np.isfinite(arr)):
        bad = int(np.count_nonzero(~np.isfinite(arr)))
        raise InputError(f"{name} contains {bad} NaN or infinite value(s)")
    return arr


def _check_number_kind(arr: np.ndarray, name: str) -> None:
    """Refuse an array whose values are not numbers: bool, text, dates, raw bytes."""
    kind = arr.dtype.kind
    if kind in "iuf":
        return
    if kind == "b":
        raise InputError(f"{name} must hold numbers, got booleans (dtype bool)")
    if kind != "O":
        raise InputError(f"{name} must hold numbers, got dtype {arr.dtype}")
    for value in arr.flat:  # Python objects: what float() would read but is no number
        if isinstance(value, bool | np.bool_ | str | bytes):
            raise InputError(f"{name} must hold numbers, got {type(value).__name__} {value!r:.40}")


def as_angle_array(
    q: ArrayLike,
    name: str = "joint_angles",
    *,
    min_joints: int = 3,
    bounded: bool = True,
    check_values: bool = True,
) -> FloatArray:
    """Joint-angle array of shape ``(..., n_joints)`` with finite values.

    Checks rank before size: a scalar is refused, the last axis must hold at
    least ``min_joints`` angles and no axis may be empty. With ``bounded`` the
    angles must lie within ``MAX_ANGLE`` (see :func:`check_angle_range`).
    ``check_values=False`` leaves the values to the caller, who passes their
    least and greatest to :func:`check_angle_values` (a kernel that reads the
    array anyway finds them at little cost).
    """
    arr = as_float_array(q, name, min_ndim=1, allow_nonfinite=True)
    if arr.size == 0:
        raise ShapeError(f"{name} is empty (shape {arr.shape})")
    if arr.shape[-1] < min_joints:
        raise ShapeError(
            f"{name} must hold at least {min_joints} angles along its last axis, "
            f"got {arr.shape[-1]} (shape {arr.shape})"
        )
    if check_values:
        # two reductions and no temporary array: min and max are NaN if any value is
        check_angle_values(arr, name, float(arr.min()), float(arr.max()), bounded=bounded)
    return arr


def check_angle_values(
    q: FloatArray, name: str, lo: float, hi: float, *, bounded: bool = True
) -> None:
    """Refuse NaN, infinity and (with ``bounded``) angles beyond ``MAX_ANGLE`` in ``q``.

    ``lo`` and ``hi`` are ``q.min()`` and ``q.max()`` (NaN if any value is):
    ``q`` itself is read again only to name what is wrong.

    >>> check_angle_values(np.r_[np.nan, 1.0], "q", np.nan, np.nan)
    Traceback (most recent call last):
    ...
    tentaclass.errors.InputError: q contains 1 NaN or infinite value(s)
    """
    if not (np.isfinite(lo) and np.isfinite(hi)):
        bad = int(np.count_nonzero(~np.isfinite(q)))
        raise InputError(f"{name} contains {bad} NaN or infinite value(s)")
    if bounded and not (-MAX_ANGLE <= lo and hi <= MAX_ANGLE):
        check_angle_range(q, name)


#: Largest joint angle, radians: 2**20 (about a million) turns. No joint of a chain
#: turns that far (a chain of ``n`` links closes at most ``n / 2`` laps), and beyond
#: it float64 holds an angle's direction to worse than 1e-9 rad.
MAX_ANGLE = 2 * np.pi * 2**20


def check_angle_range(q: FloatArray, name: str, *, first: int = 0) -> None:
    """Refuse joint angles beyond ``MAX_ANGLE`` (2**20 turns) in magnitude.

    Such numbers are a unit mix-up (encoder counts, say) or garbage: their
    features are meaningless numbers that grow with them until they overflow.
    ``q`` has shape ``(..., n_joints)``; the message names the first array
    (row, counted from ``first``) holding such an angle.

    >>> check_angle_range(np.r_[1e300, np.zeros(17)], "q")
    Traceback (most recent call last):
    ...
    tentaclass.errors.InputError: q holds an angle of 1e+300 rad, beyond 2**20 turns \
(6.588e+06 rad): are these joint angles in radians?
    >>> check_angle_range(np.full((3, 4), -1e7), "a.npy", first=10)
    Traceback (most recent call last):
    ...
    tentaclass.errors.InputError: a.npy: array 10 holds an angle of -1e+07 rad, beyond 2**20 \
turns (6.588e+06 rad): are these joint angles in radians?
    """
    flat = q.reshape(-1, q.shape[-1])
    if flat.size and -MAX_ANGLE <= flat.min() and flat.max() <= MAX_ANGLE:
        return  # (a NaN makes min and max NaN and both comparisons false)
    # "not <=" refuses NaN too, for a caller that did not check finiteness
    bad = ~(np.abs(flat) <= MAX_ANGLE)
    if bad.any():
        row, col = np.argwhere(bad)[0]
        where = name if q.ndim == 1 else f"{name}: array {first + int(row)}"
        raise InputError(
            f"{where} holds an angle of {flat[row, col]:.4g} rad, beyond 2**20 turns "
            f"({MAX_ANGLE:.4g} rad): are these joint angles in radians?"
        )


def check_total_turn(q: FloatArray, name: str, *, first: int = 0) -> None:
    """Refuse joint angles that turn more in total than a chain of their length can.

    Each joint turns at most pi either way (a link folded back onto the one
    before it), so ``n`` angles turn at most ``n * pi``: ``n / 2`` laps. More
    is a unit mix-up, degrees or milliradians read as radians. ``q`` has shape
    ``(..., n_joints)``; the message names the first array beyond the bound
    (row, counted from ``first``).

    >>> square = np.tile([0.0, 0.0, 0.0, 90.0], 4)  # in degrees
    >>> check_total_turn(square, "q")
    Traceback (most recent call last):
    ...
    tentaclass.errors.InputError: q turns 57.3 laps in total, more than 16 joints can \
(8 laps, pi each): are these joint angles in radians?
    """
    flat = q.reshape(-1, q.shape[-1])
    n = flat.shape[1]
    turn = np.abs(flat.sum(axis=1))
    bad = ~(turn <= n * np.pi * (1 + 1e-9))
    if bad.any():
        row = int(np.flatnonzero(bad)[0])
        where = name if q.ndim == 1 else f"{name}: array {first + row}"
        raise InputError(
            f"{where} turns {turn[row] / (2 * np.pi):.3g} laps in total, more than {n} joints "
            f"can ({n / 2:g} laps, pi each): are these joint angles in radians?"
        )


def as_points_array(points: ArrayLike, name: str = "points", *, min_points: int = 2) -> FloatArray:
    """Point array of shape ``(..., n_points, 2)`` with finite values."""
    arr = as_float_array(points, name, min_ndim=2, allow_nonfinite=True)
    if arr.shape[-1] != 2:
        raise ShapeError(f"{name} must have shape (..., n_points, 2), got shape {arr.shape}")
    if arr.shape[-2] < min_points:
        raise ShapeError(
            f"{name} must hold at least {min_points} points, "
            f"got {arr.shape[-2]} (shape {arr.shape})"
        )
    if arr.size == 0:
        raise ShapeError(f"{name} is empty (shape {arr.shape})")
    if not np.all(np.isfinite(arr)):
        bad = int(np.count_nonzero(~np.isfinite(arr)))
        raise InputError(f"{name} contains {bad} NaN or infinite value(s)")
    return arr


#: Largest joint-noise sigma, radians: a sigma above a turn leaves nothing of the angles.
MAX_NOISE = 2 * np.pi


def check_noise(value: object, name: str = "noise", shown: object = None) -> float:
    """A joint-noise sigma in radians: a finite number in ``[0, MAX_NOISE]`` (2*pi).

    ``shown`` is what the message quotes (default ``value``).

    >>> check_noise(1e300)
    Traceback (most recent call last):
    ...
    tentaclass.errors.InputError: noise must be at most 2*pi radians (a sigma above a turn \
leaves nothing of the angles), got 1e+300
    """
    sigma = check_positive_float(value, name, allow_zero=True)
    if sigma > MAX_NOISE:
        raise InputError(
            f"{name} must be at most 2*pi radians (a sigma above a turn leaves nothing of the "
            f"angles), got {value if shown is None else shown!r}"
        )
    return sigma


#: Largest count the compiled kernels take (a signed 64-bit integer).
MAX_INT64 = 2**63 - 1

#: Most links a chain may have (and angles a resampled lap): beyond it the arrays no
#: longer fit a sensible memory.
MAX_LINKS = 100_000

#: Largest size of one array axis read from a file (a row's pixels, rows per chunk).
MAX_AXIS = 2**31 - 1

#: Most points along one outline or series a function builds (resampled outlines,
#: polygons, circles, outline series, grids of candidate lengths).
MAX_POINTS = 1_000_000

#: Most samples (wraps, strokes, objects) one call of a data generator draws: far
#: beyond one machine's training sets (a million 64-link wraps is 512 MB), so only
#: a count no call could finish is refused.
MAX_SAMPLES = 100_000_000

#: Most values one generated array may hold (8 GB of float64, 1 GB of pixels):
#: samples times links, objects times pixels, rows times width.
MAX_VALUES = 1_000_000_000


def check_total(count: int, what: str, *, maximum: int = MAX_VALUES, unit: str = "values") -> None:
    """Refuse a product of counts above ``maximum`` (by default :data:`MAX_VALUES`).

    >>> check_total(10**6 * 10**5, "the angles (n_samples x n_links)")
    Traceback (most recent call last):
    ...
    tentaclass.errors.InputError: the angles (n_samples x n_links) would hold \
100,000,000,000 values, more than the 1,000,000,000 allowed
    """
    if count > maximum:
        raise InputError(f"{what} would hold {count:,} {unit}, more than the {maximum:,} allowed")


def check_positive_int(
    value: object, name: str, *, minimum: int = 1, maximum: int = MAX_INT64
) -> int:
    """An integer (not bool) in ``[minimum, maximum]``.

    >>> check_positive_int(10**21, "min_area")
    Traceback (most recent call last):
    ...
    tentaclass.errors.InputError: min_area must be at most 9,223,372,036,854,775,807, \
got 1,000,000,000,000,000,000,000
    """
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise InputError(f"{name} must be an integer, got {value!r}")
    number = int(value)
    if number < minimum:
        raise InputError(f"{name} must be at least {minimum}, got {number}")
    if number > maximum:
        raise InputError(f"{name} must be at most {maximum:,}, got {number:,}")
    return number


def check_seed(
    value: object, name: str = "random_state", *, allow_none: bool = True
) -> int | np.random.Generator | None:
    """A seed: an integer >= 0, a NumPy Generator, or None (fresh entropy).

    ``allow_none=False`` asks for a reproducible seed: an integer or a Generator.
    """
    if isinstance(value, np.random.Generator) or (value is None and allow_none):
        return value
    if isinstance(value, numbers.Integral) and not isinstance(value, bool) and int(value) >= 0:
        return int(value)
    what = "None, an integer >= 0 or" if allow_none else "an integer >= 0 or"
    raise InputError(f"{name} must be {what} a numpy Generator, got {value!r}")


def as_generator(
    value: object, name: str = "random_state", *, allow_none: bool = True
) -> np.random.Generator:
    """The NumPy Generator of a seed (see :func:`check_seed`).

    Examples
    --------
    >>> float(as_generator(3).random()) == float(np.random.default_rng(3).random())
    True
    """
    return np.random.default_rng(check_seed(value, name, allow_none=allow_none))


def check_positive_float(value: object, name: str, *, allow_zero: bool = False) -> float:
    """A finite real number > 0 (or >= 0 with ``allow_zero``)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise InputError(f"{name} must be a number, got {value!r}")
    v = float(value)
    if not np.isfinite(v) or v < 0 or (v == 0 and not allow_zero):
        bound = ">= 0" if allow_zero else "> 0"
        raise InputError(f"{name} must be a finite number {bound}, got {value!r}")
    return v


def check_one_value(value: ArrayLike, name: str, hint: str = "") -> None:
    """Refuse an array where one number is expected (a number's errors come later).

    ``hint`` follows the message, e.g. what to use for many values.

    >>> check_one_value([1.0, 2.0], "link_length", " (use wrap_many)")
    Traceback (most recent call last):
    ...
    tentaclass.errors.InputError: link_length must be one number, got 2 values (use wrap_many)
    """
    try:
        ndim = np.ndim(value)
    except ValueError:  # a ragged sequence
        ndim = None
    if ndim == 0 or isinstance(value, (str, bytes)):
        return
    size = None if ndim is None else int(np.size(value))
    count = "a ragged sequence" if size is None else f"{size} value{'' if size == 1 else 's'}"
    raise InputError(f"{name} must be one number, got {count}{hint}")


def cap_count(requested: int | None, available: int, name: str, what: str) -> int:
    """``requested``, or ``available`` with a warning when fewer are available.

    ``None`` takes ``available`` without a warning.

    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     cap_count(50, 10, "n_centers", "distinct training samples")
    10
    >>> print(caught[0].message)
    n_centers=50 is more than the 10 distinct training samples: using 10
    """
    if requested is None:
        return available
    if requested > available:
        warnings.warn(
            f"{name}={requested} is more than the {available} {what}: using {available}",
            TentaclassWarning,
            stacklevel=3,
        )
        return available
    return requested


def as_path(value: object, name: str = "path") -> Path:
    """A file or folder name: a non-empty ``str`` or ``os.PathLike``, as a Path.

    >>> as_path(None, "path")
    Traceback (most recent call last):
    ...
    tentaclass.errors.InputError: path must be a file name (str or os.PathLike), got None
    """
    if isinstance(value, str) and not value:
        raise InputError(f"{name} is an empty string: give a file name")
    if isinstance(value, (str, os.PathLike)):
        try:
            return Path(value)
        except TypeError:  # an os.PathLike of bytes
            pass
    raise InputError(f"{name} must be a file name (str or os.PathLike), got {value!r}")


def as_list_of(value: object, name: str, kind: type) -> list[Any]:
    """``value`` as a list whose items are all ``kind`` instances.

    >>> as_list_of(3, "values", float)
    Traceback (most recent call last):
    ...
    tentaclass.errors.InputError: values must be a sequence of float, got int
    >>> as_list_of([1.0, "2"], "values", float)
    Traceback (most recent call last):
    ...
    tentaclass.errors.InputError: values[1] must be a float, got str
    """
    what = kind.__name__
    if isinstance(value, (str, bytes, kind)) or not isinstance(value, Iterable):
        raise InputError(f"{name} must be a sequence of {what}, got {type(value).__name__}")
    items = list(value)
    for i, item in enumerate(items):
        if not isinstance(item, kind):
            raise InputError(f"{name}[{i}] must be a {what}, got {type(item).__name__}")
    return items


def check_finite_float(value: object, name: str) -> float:
    """A finite real number (not bool) of any sign."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise InputError(f"{name} must be a finite number, got {value!r}")
    v = float(value)
    if not np.isfinite(v):
        raise InputError(f"{name} must be a finite number, got {value!r}")
    return v


def check_frequency_count(value: object, top: int, name: str, top_text: str) -> int:
    """How many of ``top`` frequencies to keep: a count, or a fraction of them.

    An integer (or integral float) must lie in ``[1, top]``; any other float is
    a fraction in (0, 1) of ``top``, rounded, at least 1. ``top_text`` names
    ``top`` in the error message (e.g. ``"floor(n_joints / 2)"``).
    """
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise InputError(f"{name} must be a number, got {value!r}")
    count = float(value)
    if not count.is_integer():
        if not 0 < count < 1:
            raise InputError(f"a fractional {name} must lie in (0, 1), got {value}")
        count = max(1, round(count * top))
    if not 1 <= count <= top:
        raise InputError(f"{name} must be between 1 and {top_text} = {top}, got {value!r}")
    return int(count)


def _row_lengths(x: object) -> str | None:
    """Where a nested sequence is ragged: ``"16 and 15, rows 0 and 3"``, or None.

    Compares the lengths of all the rows at one depth before going deeper; a
    row below the first level is named by its indices, ``[1, 0]``.
    """
    if isinstance(x, np.ndarray) and x.dtype != object:
        return None  # rectangular by construction: no walk over its elements
    level: list[tuple[tuple[int, ...], Any]] = [((), x)]
    while True:
        sizes = [
            None if isinstance(obj, (str, bytes)) or not hasattr(obj, "__len__") else len(obj)
            for _, obj in level
        ]
        for (path, _), size in zip(level, sizes, strict=True):
            if size != sizes[0]:
                show = ["a number" if z is None else str(z) for z in (sizes[0], size)]
                rows = [str(p[0]) if len(p) == 1 else str(list(p)) for p in (level[0][0], path)]
                return f"{show[0]} and {show[1]}, rows {rows[0]} and {rows[1]}"
        if not sizes[0]:
            return None
        level = [((*path, i), row) for path, obj in level for i, row in enumerate(obj)]


def as_rectangular_array(x: ArrayLike, name: str) -> np.ndarray:
    """``np.asarray(x)``, with an error naming ``name`` when rows differ in length.

    >>> as_rectangular_array([[1, 2, 3], [4, 5]], "X")
    Traceback (most recent call last):
    ...
    tentaclass.errors.ShapeError: X: rows have different lengths (3 and 2, rows 0 and 1)
    """
    try:
        return np.asarray(x)
    except ValueError as exc:
        raise ragged_error(x, name, exc) from None


def ragged_error(x: object, name: str, exc: Exception) -> Exception:
    """The error for ``x`` that NumPy could not make an array of (``exc``).

    A :class:`ShapeError` naming ``name`` and the row lengths when ``x`` is a
    ragged nested sequence, else ``exc`` itself.
    """
    where = _row_lengths(x)
    if where is None:
        return exc
    return ShapeError(f"{name}: rows have different lengths ({where})")


def as_binary_grid(grid: ArrayLike, name: str = "grid") -> np.ndarray:
    """Binary image of shape ``(..., rows, cols)``: bool, or numbers that are all 0 or 1."""
    arr = as_rectangular_array(grid, name)
    if arr.ndim < 2:
        raise ShapeError(f"{name} must have at least 2 dimensions, got shape {arr.shape}")
    if arr.size == 0:
        raise ShapeError(f"{name} is empty (shape {arr.shape})")
    if arr.dtype == bool:
        return arr
    if not (np.issubdtype(arr.dtype, np.number)):
        raise InputError(f"{name} must hold 0/1 or bool values, got dtype {arr.dtype}")
    ok = (arr == 0) | (arr == 1)
    if not np.all(ok):
        bad = arr[~ok].ravel()[0].item()  # a Python number: "2", not "np.int64(2)"
        raise InputError(f"{name} must hold only 0 and 1, found {bad!r}")
    return arr.astype(bool)


def as_belt_image(image: ArrayLike, name: str = "image") -> np.ndarray:
    """A 2-D belt image: bool for 0/1 (or bool) values, else finite grey levels as float64.

    >>> as_belt_image([[0, 1], [1, 0]]).dtype, as_belt_image([[0, 200], [90, 0]]).dtype
    (dtype('bool'), dtype('float64'))
    """
    arr = as_rectangular_array(image, name)
    if arr.ndim != 2 or arr.size == 0:
        raise ShapeError(f"{name} must be a non-empty 2-D array (rows, width), got {arr.shape}")
    if arr.dtype == bool:
        return arr
    if not np.issubdtype(arr.dtype, np.number) or np.iscomplexobj(arr):
        raise InputError(f"{name} must hold bool or grey-level numbers, got dtype {arr.dtype}")
    if np.all((arr == 0) | (arr == 1)):
        return arr.astype(bool)
    grey = arr.astype(np.float64)
    if not np.all(np.isfinite(grey)):
        raise InputError(f"{name} holds NaN or infinite grey levels")
    return grey


def check_X(estimator: Any, X: ArrayLike, *, reset: bool = True, **kwargs: Any) -> np.ndarray:
    """scikit-learn's ``validate_data`` for ``X`` alone, typed: the checked array.

    Records (``reset=True``) or checks ``n_features_in_`` on ``estimator``.
    """
    from sklearn.utils.validation import validate_data

    try:
        return validate_data(estimator, X, reset=reset, **kwargs)
    except ValueError as exc:
        raise _input_error(ragged_error(X, "X", exc)) from None


def check_fitted_X(estimator: Any, X: ArrayLike) -> FloatArray:
    """``X`` for a fitted ``estimator``: float64 rows of its ``n_features_in_`` values.

    Raises scikit-learn's ``NotFittedError`` before ``fit``, and the errors of
    :func:`check_X` (with ``reset=False``) for the array.
    """
    from sklearn.utils.validation import check_is_fitted

    check_is_fitted(estimator)
    return check_X(estimator, X, dtype=np.float64, reset=False)


def check_X_y(
    estimator: Any, X: ArrayLike, y: ArrayLike, **kwargs: Any
) -> tuple[np.ndarray, np.ndarray]:
    """scikit-learn's ``validate_data`` for a training set ``(X, y)``, typed."""
    from sklearn.utils.validation import validate_data

    try:
        return validate_data(estimator, X, y, **kwargs)
    except ValueError as exc:
        raise _input_error(ragged_error(X, "X", exc)) from None


def check_distance_scale(X: FloatArray, name: str = "X") -> None:
    """Refuse features so large that squared distances between rows overflow float64.

    >>> check_distance_scale(np.full((2, 16), 1e160))
    Traceback (most recent call last):
    ...
    tentaclass.errors.InputError: X holds a value of 1e+160: squared distances between \
rows of 16 features overflow float64 beyond about 1.68e+153; scale the features
    """
    if X.size == 0:
        return
    top = float(np.max(np.abs(X)))
    limit = float(np.sqrt(np.finfo(np.float64).max / X.shape[-1])) / 2
    if top > limit:
        raise InputError(
            f"{name} holds a value of {top:.4g}: squared distances between rows of "
            f"{X.shape[-1]} features overflow float64 beyond about {limit:.3g}; scale the "
            "features"
        )


def check_targets(y: ArrayLike) -> None:
    """scikit-learn's ``check_classification_targets``, raising :class:`InputError`.

    >>> check_targets([0.5, 1.5])
    Traceback (most recent call last):
    ...
    tentaclass.errors.InputError: Unknown label type: continuous. ...
    """
    from sklearn.utils.multiclass import check_classification_targets

    try:
        check_classification_targets(y)
    except ValueError as exc:
        raise _input_error(exc) from None
    except TypeError:  # labels of kinds that do not sort together (str and int, None)
        kinds = sorted({type(v).__name__ for v in np.asarray(y, dtype=object).ravel()})
        raise InputError(
            f"y mixes labels of kinds that cannot be sorted together ({', '.join(kinds)}): "
            "give labels of one kind, all strings or all integers"
        ) from None


def class_indices(y: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Sorted class labels of ``y`` and the index of each sample's class.

    A classifier learns to tell classes apart: one class is refused.

    Raises :class:`~tentaclass.errors.InputError` unless ``y`` holds
    classification targets of at least two classes.
    """
    check_targets(y)
    classes, y_idx = np.unique(y, return_inverse=True)
    if classes.size < 2:
        raise InputError(f"y must hold at least 2 classes, got one class: {classes.tolist()}")
    return classes, y_idx


def check_unknown_label(unknown_label: object, classes: np.ndarray) -> None:
    """Refuse a rejection label that is also a class: a rejection would read as that class.

    >>> check_unknown_label("unknown", np.array(["cat", "unknown"]))
    Traceback (most recent call last):
    ...
    tentaclass.errors.InputError: unknown_label 'unknown' is one of the classes: a rejected \
sample could not be told from that class; choose another unknown_label (or rename the class)
    """
    if any(c == unknown_label for c in classes.tolist()):
        raise InputError(
            f"unknown_label {unknown_label!r} is one of the classes: a rejected sample could "
            "not be told from that class; choose another unknown_label (or rename the class)"
        )


def _input_error(exc: Exception) -> Exception:
    """``exc`` as an :class:`InputError` with its message (tentaclass errors are kept)."""
    if isinstance(exc, InputError):
        return exc
    return InputError(str(exc))


def check_spread(
    value: object, name: str = "spread", *, minimum: float = 1e-150, maximum: float = 1e150
) -> float | str:
    """A kernel width: ``"auto"`` or a finite number in ``[minimum, maximum]``.

    The defaults keep ``(1 / spread) ** 2`` and ``spread ** 2`` finite in float64.
    """
    if isinstance(value, str) and value == "auto":
        return value
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise InputError(f"{name} must be 'auto' or a finite number > 0, got {value!r}")
    v = float(value)
    if not (np.isfinite(v) and v > 0):
        raise InputError(f"{name} must be 'auto' or a finite number > 0, got {value!r}")
    if v < minimum:
        raise InputError(f"{name} {value!r} is too small: it must be at least {minimum:g}")
    if v > maximum:
        raise InputError(f"{name} {value!r} is too large: it must be at most {maximum:g}")
    return v


def check_flag(value: object, name: str) -> bool:
    """A boolean (``bool`` or ``numpy.bool_``): a string such as ``"no"`` would read as true.

    Examples
    --------
    >>> check_flag(np.True_, "detrend")
    True
    >>> check_flag("no", "detrend")
    Traceback (most recent call last):
    ...
    tentaclass.errors.InputError: detrend must be True or False, got 'no'
    """
    if not isinstance(value, (bool, np.bool_)):
        raise InputError(f"{name} must be True or False, got {value!r}")
    return bool(value)


def check_choice(value: object, name: str, choices: Collection[str]) -> str:
    """One of the strings ``choices``; the error lists them.

    Examples
    --------
    >>> check_choice("fft", "method", ("matmul", "fft"))
    'fft'
    >>> check_choice("FFT", "method", ("matmul", "fft"))
    Traceback (most recent call last):
    ...
    tentaclass.errors.InputError: method must be one of 'matmul', 'fft', got 'FFT'
    """
    if not isinstance(value, str) or value not in choices:
        listed = ", ".join(repr(c) for c in choices)
        raise InputError(f"{name} must be one of {listed}, got {value!r}")
    return value


def check_fraction(value: object, name: str) -> float:
    """A number in ``[0, 1]`` (not bool)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not 0 <= float(value) <= 1:
        raise InputError(f"{name} must be a number in [0, 1], got {value!r}")
    return float(value)


# A chain against an object: what wrap, wrap_many and the physical grasps refuse alike.


#: Shortest link, as a fraction of the object's diameter: float64 places joints on
#: the outline to about 1e-16 of its size, so shorter links lose the object's turns.
MIN_LINK_FRACTION = 1e-12


def check_links_fit(link_lengths: ArrayLike, diameter: float) -> None:
    """Refuse links longer than the object's diameter, or too short to place on it.

    A link rests with both ends on the object (or on the laps of the chain
    around it), so its length cannot exceed the longest chord of the outline;
    a link shorter than ``MIN_LINK_FRACTION`` of the diameter ends where it
    starts in float64, and the turns at the object's corners are lost.

    Examples
    --------
    >>> check_links_fit([1.0, 2.5], 2.0)
    Traceback (most recent call last):
    ...
    tentaclass.errors.InputError: link_length 2.5 is longer than the object's diameter 2: \
a link must fit between two points of the outline (use link_length <= 2)
    >>> check_links_fit([1e-20], 2.0)
    Traceback (most recent call last):
    ...
    tentaclass.errors.InputError: link_length 1e-20 is too short for an object of diameter 2: \
below 1e-12 of its size the joints cannot be placed apart (use link_length >= 2e-12)
    """
    ls = np.asarray(link_lengths, dtype=np.float64)
    too_long = ls > diameter
    if np.any(too_long):
        raise InputError(
            f"link_length {ls[too_long].flat[0]:g} is longer than the object's diameter "
            f"{diameter:g}: a link must fit between two points of the outline "
            f"(use link_length <= {diameter:g})"
        )
    shortest = MIN_LINK_FRACTION * diameter
    too_short = ls < shortest
    if np.any(too_short):
        raise InputError(
            f"link_length {ls[too_short].flat[0]:g} is too short for an object of diameter "
            f"{diameter:g}: below {MIN_LINK_FRACTION:g} of its size the joints cannot be placed "
            f"apart (use link_length >= {shortest:g})"
        )


def check_thickness_fits(thickness: float, diameter: float) -> None:
    """Refuse a chain thicker than the object's diameter: it could not lie on it.

    >>> check_thickness_fits(3.0, 2.0)
    Traceback (most recent call last):
    ...
    tentaclass.errors.InputError: thickness 3 is larger than the object (diameter 2): a chain \
that thick cannot lie on it (use thickness <= 2)
    """
    if thickness > diameter:
        raise InputError(
            f"thickness {thickness:g} is larger than the object (diameter {diameter:g}): "
            f"a chain that thick cannot lie on it (use thickness <= {diameter:g})"
        )


def check_thickness_builds(thickness: float, diameter: float) -> None:
    """Refuse links too thin to build as bodies: below ``MIN_LINK_FRACTION`` of the diameter.

    A geometric wrap takes such a thickness as none; a physical chain's links
    are built from it, and the outline grown by half of it is the outline
    itself in float64.

    >>> check_thickness_builds(1e-300, 2.0)
    Traceback (most recent call last):
    ...
    tentaclass.errors.InputError: thickness 1e-300 is too thin for an object of diameter 2: \
below 1e-12 of its size the links cannot be built (use thickness >= 2e-12)
    """
    thinnest = MIN_LINK_FRACTION * diameter
    if thickness < thinnest:
        raise InputError(
            f"thickness {thickness:g} is too thin for an object of diameter {diameter:g}: "
            f"below {MIN_LINK_FRACTION:g} of its size the links cannot be built "
            f"(use thickness >= {thinnest:g})"
        )


def check_laps(laps: float, n_links: int) -> None:
    """Refuse more laps than a chain can close: every lap takes at least two links.

    >>> check_laps(9.0, 16)
    Traceback (most recent call last):
    ...
    tentaclass.errors.InputError: laps: 16 links cannot close 9 laps (at most 8: 2 links per lap)
    """
    if n_links / laps < 2:
        raise InputError(
            f"laps: {n_links} links cannot close {laps:g} laps (at most {n_links / 2:g}: "
            "2 links per lap)"
        )


def check_reach(offset: ArrayLike, n_links: int, link_length: ArrayLike) -> None:
    """Refuse a base farther from the object than the chain is long.

    ``offset`` and ``link_length`` broadcast together (one per wrap).

    >>> check_reach(10.0, 8, 1.0)
    Traceback (most recent call last):
    ...
    tentaclass.errors.InputError: offset 10 is longer than the chain (8 links of 1, 8): the chain \
cannot reach the object (use offset <= n_links * link_length)
    """
    off, ls = np.broadcast_arrays(np.atleast_1d(offset), np.atleast_1d(link_length))
    reach = n_links * ls
    if np.any(off > reach):
        q = int(np.argmax(off > reach))
        raise InputError(
            f"offset {off[q]:g} is longer than the chain ({n_links} links of {ls[q]:g}, "
            f"{reach[q]:g}): the chain cannot reach the object (use offset <= n_links * "
            "link_length)"
        )


#: Bounds of a link's mass, and of its inertia about its centre of mass, in a
#: physical grasp's units (kilograms, and metres scaled to a mean link length of 1).
#: The controller's joint servos and damping act in those units: a chain of
#: 1e16 kg links does not come to rest, at 1e21 kg it does not move at all (and
#: would read as a grasp at rest), and MuJoCo refuses bodies below 1e-14 kg.
MIN_GRASP_MASS, MAX_GRASP_MASS = 1e-12, 1e12


def check_grasp_masses(masses: FloatArray, inertia: FloatArray) -> None:
    """Refuse link masses or inertias a physical grasp's controller cannot move.

    ``inertia`` is in the simulation's units (lengths scaled to a mean link
    length of 1). Masses must lie in ``[MIN_GRASP_MASS, MAX_GRASP_MASS]`` and
    inertias must not exceed ``MAX_GRASP_MASS``.

    >>> check_grasp_masses(np.r_[1.0, 1e300], np.r_[0.1, 0.1])
    Traceback (most recent call last):
    ...
    tentaclass.errors.InputError: masses: link 1 weighs 1e+300, outside [1e-12, 1e+12] where \
the grasp's controller can move the chain (masses in kg, links of mean length 1): \
express them in other units
    """
    limit = "where the grasp's controller can move the chain (masses in kg, links of mean length 1)"
    bad = ~((masses >= MIN_GRASP_MASS) & (masses <= MAX_GRASP_MASS))
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise InputError(
            f"masses: link {i} weighs {masses[i]:.4g}, outside [{MIN_GRASP_MASS:g}, "
            f"{MAX_GRASP_MASS:g}] {limit}: express them in other units"
        )
    bad = ~(inertia <= MAX_GRASP_MASS)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise InputError(
            f"inertia: link {i} has inertia {inertia[i]:.4g}, above {MAX_GRASP_MASS:g} "
            f"{limit}: express them in other units"
        )


# Planar chain (tentaclass.manipulator): link parameters, joint arrays, time grids.


def check_link_parameters(**params: ArrayLike | None) -> tuple[int, dict[str, FloatArray]]:
    """Scalars or 1-D arrays of one common length ``n``, at least one array.

    Returns ``n`` and read-only float copies of shape ``(n,)`` (``None`` skipped).
    """
    arrays: dict[str, FloatArray] = {}
    n = None
    for name, value in params.items():
        if value is None:
            continue
        arr = as_float_array(value, name)
        if arr.ndim > 1:
            raise ShapeError(f"{name} must be a number or a 1-D array, got shape {arr.shape}")
        if arr.ndim == 1:
            if arr.size == 0:
                raise ShapeError(f"{name} is empty")
            if n is None:
                n = arr.size
            elif arr.size != n:
                sizes = {k: v.size for k, v in arrays.items() if v.ndim == 1}
                raise ShapeError(
                    f"{name} has {arr.size} entries but the chain has {n} links (from {sizes})"
                )
        arrays[name] = arr
    if n is None:
        raise InputError(
            "link_lengths must list one length per link (e.g. [1.0] * n_links) "
            "unless masses, com or inertia do"
        )
    out = {}
    for name, arr in arrays.items():
        out[name] = np.array(np.broadcast_to(arr, (n,)))
        out[name].flags.writeable = False
    return n, out


def as_joint_arrays(n: int, **arrays: ArrayLike) -> list[FloatArray]:
    """Finite arrays of shape ``(..., n)``, broadcast to their common batch shape."""
    out = []
    for name, value in arrays.items():
        arr = as_angle_array(value, name, min_joints=1, bounded=False)
        if arr.shape[-1] != n:
            raise ShapeError(
                f"{name} must have {n} entries along its last axis (one per link of the "
                f"chain), got shape {arr.shape}"
            )
        out.append(arr)
    try:
        shape = np.broadcast_shapes(*(a.shape for a in out))
    except ValueError:
        shapes = ", ".join(f"{k} {a.shape}" for k, a in zip(arrays, out, strict=True))
        raise ShapeError(f"the batch shapes of {shapes} do not broadcast") from None
    return [np.broadcast_to(a, shape) for a in out]


def as_times(t: ArrayLike) -> FloatArray:
    """A non-empty, strictly increasing 1-D array of finite times."""
    arr = as_float_array(t, "t", min_ndim=1)
    if arr.ndim != 1 or arr.size == 0:
        raise ShapeError(f"t must be a non-empty 1-D array of times, got shape {arr.shape}")
    if np.any(np.diff(arr) <= 0):
        raise InputError("t must be strictly increasing")
    return arr


def as_torques(value: ArrayLike, shape: tuple[int, ...]) -> FloatArray:
    """The output of a torque function, broadcast to the state's shape."""
    if value is None:
        raise InputError("torque_fn(t, q, qd) returned None: it must return the joint torques")
    tau = as_float_array(value, "torque_fn(t, q, qd)")
    try:
        return np.broadcast_to(tau, shape)
    except ValueError:
        raise ShapeError(
            f"torque_fn(t, q, qd) returned shape {tau.shape}, which does not broadcast "
            f"to the state's shape {shape}"
        ) from None


def as_binary_grid_2d(grid: Any, name: str = "grid") -> np.ndarray:
    """One 2-D binary grid (see :func:`as_binary_grid`)."""
    arr = as_binary_grid(grid, name)
    if arr.ndim != 2:
        raise InputError(f"{name} must be 2-D (rows, cols), got shape {arr.shape}")
    return arr


def as_object_mask(mask: Any, name: str = "mask") -> np.ndarray:
    """One 2-D binary grid (see :func:`as_binary_grid`) holding at least one object pixel.

    >>> as_object_mask(np.zeros((2, 3), bool))
    Traceback (most recent call last):
    ...
    tentaclass.errors.InputError: mask holds no object pixels (shape (2, 3))
    """
    arr = as_binary_grid_2d(mask, name)
    if not arr.any():
        raise InputError(f"{name} holds no object pixels (shape {arr.shape})")
    return arr


def as_grid_list(grids: Any, name: str = "grids") -> list[np.ndarray]:
    """Validate a 3-D array or a sequence of 2-D binary grids (shapes may differ)."""
    if isinstance(grids, np.ndarray) and grids.ndim == 3:
        seq = list(grids)
    elif isinstance(grids, np.ndarray) or not isinstance(grids, Sequence):
        raise InputError(
            f"{name} must be a sequence of 2-D grids or a 3-D array, got {type(grids).__name__}"
            + (f" of shape {grids.shape}" if isinstance(grids, np.ndarray) else "")
        )
    else:
        seq = list(grids)
    out = []
    for i, g in enumerate(seq):
        arr = as_binary_grid(g, f"{name}[{i}]")
        if arr.ndim != 2:
            raise InputError(f"{name}[{i}] must be 2-D, got shape {arr.shape}")
        if not arr.any():
            raise InputError(f"{name}[{i}] holds no object pixels")
        out.append(arr)
    if not out:
        raise InputError(f"{name} is empty")
    return out
