"""Old names kept for one release, with a warning naming the new one.

Functions take a renamed argument with :func:`renamed` (a
``DeprecationWarning``); scikit-learn estimators, whose constructor must store
its arguments unchanged, take it with :func:`renamed_param` in ``fit`` (a
``FutureWarning``, as scikit-learn does), and keep a renamed fitted attribute
with :func:`renamed_attribute`.
"""

from __future__ import annotations

import warnings
from typing import Any

from .errors import InputError

#: Default of a deprecated function argument: tells "not given" from any value.
UNSET: Any = object()

#: Default of a deprecated estimator parameter (a string, as scikit-learn requires).
DEPRECATED = "deprecated"


def _message(old: str, new: str) -> str:
    return f"{old} is deprecated and will be removed in the next release; use {new} instead"


def renamed(new: str, new_value: Any, old: str, old_value: Any, *, default: Any = None) -> Any:
    """The value of argument ``new``, taking it from its old name ``old`` if given there.

    Warns with :class:`DeprecationWarning` when ``old`` is used, and refuses both at once.
    """
    if old_value is UNSET:
        return new_value
    warnings.warn(_message(f"{old}=", f"{new}="), DeprecationWarning, stacklevel=3)
    if new_value is not default and new_value != default:
        raise InputError(f"give {new}= only, not {old}= as well")
    return old_value


def renamed_param(estimator: Any, new: str, old: str, *, default: Any = None) -> Any:
    """The value of estimator parameter ``new``, from its old name ``old`` if that was set.

    Warns with :class:`FutureWarning` when ``old`` is not ``"deprecated"``,
    and refuses both at once.
    """
    old_value = getattr(estimator, old)
    new_value = getattr(estimator, new)
    if isinstance(old_value, str) and old_value == DEPRECATED:
        return new_value
    warnings.warn(_message(f"{old}=", f"{new}="), FutureWarning, stacklevel=3)
    if new_value is not default and new_value != default:
        raise InputError(f"give {new}= only, not {old}= as well")
    return old_value


def renamed_attribute(new: str, old: str) -> property:
    """A read-only alias ``old`` of the fitted attribute ``new`` that warns (FutureWarning)."""

    def get(self: Any) -> Any:
        value = getattr(self, new)  # AttributeError before fit, as for ``new``
        warnings.warn(_message(old, new), FutureWarning, stacklevel=2)
        return value

    return property(get, doc=f"Deprecated alias of ``{new}``.")
