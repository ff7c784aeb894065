"""Exceptions and warnings raised by tentaclass.

Every error the library raises on purpose derives from :class:`TentaclassError`;
errors about bad input also derive from :class:`ValueError`, so callers that
already catch ``ValueError`` keep working.
"""


class TentaclassError(Exception):
    """Base class of every error raised on purpose by tentaclass."""


class InputError(TentaclassError, ValueError):
    """An argument has the wrong shape, type or value."""


class ShapeError(InputError):
    """An array argument has the wrong number of dimensions or the wrong size."""


class ModelFileError(TentaclassError, ValueError):
    """A model file is damaged, foreign, or from an unknown format version."""


class ModelFileNotFoundError(ModelFileError, FileNotFoundError):
    """No file at a model's path: a :class:`ModelFileError` and a ``FileNotFoundError``."""


class TentaclassWarning(UserWarning):
    """Recoverable problem: tentaclass carried on, but the result may surprise."""


__all__ = [
    "InputError",
    "ModelFileError",
    "ModelFileNotFoundError",
    "ShapeError",
    "TentaclassError",
    "TentaclassWarning",
]
