"""Old argument names kept for one release, with a DeprecationWarning."""

from __future__ import annotations

import warnings
from typing import Any

from .errors import InputError

#: Default of a deprecated argument: tells "not given" from any value.
UNSET: Any = object()


def renamed(new: str, new_value: Any, old: str, old_value: Any, *, default: Any = None) -> Any:
    """The value of argument ``new``, taking it from its old name ``old`` if given there.

    Warns with :class:`DeprecationWarning` when ``old`` is used, and refuses both at once.
    """
    if old_value is UNSET:
        return new_value
    warnings.warn(
        f"{old}= is deprecated and will be removed in the next release; use {new}= instead",
        DeprecationWarning,
        stacklevel=3,
    )
    if new_value is not default:
        raise InputError(f"give {new}= only, not {old}= as well")
    return old_value
