"""``tentaclass serve``: a page to draw objects, wrap a tentacle around them and name them.

:func:`create_app` needs the optional ``web`` extra (FastAPI, uvicorn):
``pip install 'tentaclass[web]'``. :class:`Recognizer`, the model behind the
page, needs only the library.
"""

from typing import TYPE_CHECKING, Any

from ._recognizer import (
    MIN_EXAMPLES,
    N_LINKS,
    OUTLINE_POINTS,
    Answer,
    Recognizer,
    build_model,
    outline_angles,
)

if TYPE_CHECKING:
    from ._app import create_app

__all__ = [
    "MIN_EXAMPLES",
    "N_LINKS",
    "OUTLINE_POINTS",
    "Answer",
    "Recognizer",
    "build_model",
    "create_app",
    "outline_angles",
]


def __getattr__(name: str) -> Any:
    if name == "create_app":
        from .._lazy import import_extra

        return import_extra(
            f"{__name__}._app", "web", "the web page needs the 'web' extra"
        ).create_app
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
