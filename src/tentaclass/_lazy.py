"""Imports on first use: a package's public names, and the optional extras.

Keeps ``import tentaclass`` and the command line's start light: scikit-learn,
matplotlib and scipy.stats load only when a name that needs them is used.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping
from types import ModuleType
from typing import Any


def lazy_exports(
    package: str, homes: Mapping[str, str], namespace: dict[str, Any]
) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """``__getattr__`` and ``__dir__`` for ``package``.

    Parameters
    ----------
    package : str
        The package's ``__name__``.
    homes : mapping of str to str
        Public name -> the module (relative to ``package``) that defines it; a
        name that maps to itself is a submodule.
    namespace : dict
        The package's ``globals()``: each name is cached there once loaded.
    """

    def __getattr__(name: str) -> Any:
        home = homes.get(name)
        if home is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        module = importlib.import_module(f".{home}", package)
        value = module if home == name else getattr(module, name)
        namespace[name] = value
        return value

    def __dir__() -> list[str]:
        return sorted(set(namespace) | set(homes))

    return __getattr__, __dir__


def import_extra(
    name: str, extra: str, needs: str, *, error: Callable[[str], Exception] = ImportError
) -> ModuleType:
    """The module ``name`` of an optional extra, or ``error`` saying how to install it.

    Parameters
    ----------
    name : str
        Absolute module name, e.g. ``"aeon.datasets"``.
    extra : str
        The extra of tentaclass that installs it (``pip install 'tentaclass[extra]'``).
    needs : str
        What needs it, the start of the message: ``"the web page needs the 'web' extra"``.
    error : callable, default=ImportError
        The exception raised (from the ImportError) when the module is missing.

    Examples
    --------
    >>> import_extra("math", "none", "nothing").sqrt(4.0)
    2.0
    >>> import_extra("no_such_module", "web", "the page needs it")
    Traceback (most recent call last):
    ...
    ImportError: the page needs it: pip install 'tentaclass[web]'
    """
    try:
        return importlib.import_module(name)
    except ImportError as exc:
        raise error(f"{needs}: pip install 'tentaclass[{extra}]'") from exc
