"""Wrap a chain of rigid links around an object outline: the joint angles it measures."""

from ._api import wrap, wrap_many
from ._result import Wrap, WrapBatch

__all__ = ["Wrap", "WrapBatch", "wrap", "wrap_many"]
