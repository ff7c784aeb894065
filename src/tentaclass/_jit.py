"""One compiled specialisation per argument type for the kernels of a module.

numba compiles a jitted function called from another one anew for each
constant passed to it (``f(x, 0)`` and ``f(x, 1)`` are typed as the literal
values 0 and 1, each its own specialisation), on top of the one for the plain
type that variables give. :func:`plain_calls` makes the calls between the
kernels of a module use the plain types only: the same machine code runs (the
constants are ordinary arguments instead of values folded in), compiled once.
"""

from __future__ import annotations

from collections.abc import Callable, MutableMapping
from typing import Any


def _plain(get_call_template: Callable[[Any, Any], Any], args: Any, kws: Any) -> Any:
    from numba.core import types

    return get_call_template(
        tuple(types.unliteral(a) for a in args),
        {k: types.unliteral(v) for k, v in kws.items()},
    )


def plain_calls(namespace: MutableMapping[str, Any]) -> int:
    """Type the calls to the kernels defined in ``namespace`` without literal constants.

    Parameters
    ----------
    namespace : mapping
        A module's ``globals()``; its numba dispatchers (those whose Python
        function was defined in that module) are changed in place.

    Returns
    -------
    int
        How many dispatchers were changed.

    Examples
    --------
    >>> import numba as nb
    >>> @nb.njit
    ... def _scale(x, k):
    ...     return x * k
    >>> @nb.njit
    ... def _twice(x):
    ...     return _scale(x, 2) + _scale(x, 3)
    >>> plain_calls({"__name__": __name__, "_scale": _scale})
    1
    >>> _twice(1.5)
    7.5
    >>> [str(s) for s in _scale.signatures]
    ['(float64, int64)']
    """
    from numba.core.dispatcher import Dispatcher

    module = namespace.get("__name__")
    changed = 0
    for obj in list(namespace.values()):
        if not isinstance(obj, Dispatcher) or getattr(obj.py_func, "__module__", None) != module:
            continue
        original = getattr(obj, "get_call_template", None)
        if original is not None:  # a numba without this hook compiles as before
            obj.get_call_template = lambda args, kws, _g=original: _plain(_g, args, kws)
            changed += 1
    return changed
