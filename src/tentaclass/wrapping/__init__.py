"""Wrap a chain of rigid links around an object outline: the joint angles it measures.

Also what can be read back from those angles alone (:func:`grasp_state`) and how
finely a link of a given length samples an outline (:func:`capture_error`,
:func:`max_link_length`, :func:`closing_link_length`).
"""

from ._api import wrap, wrap_many
from ._grasp import GraspState, grasp_state
from ._result import Wrap, WrapBatch
from ._sampling import capture_error, closing_link_length, max_link_length

__all__ = [
    "GraspState",
    "Wrap",
    "WrapBatch",
    "capture_error",
    "closing_link_length",
    "grasp_state",
    "max_link_length",
    "wrap",
    "wrap_many",
]
