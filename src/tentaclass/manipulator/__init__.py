"""Planar n-link manipulator: kinematics, dynamics and simulation, batched.

:class:`PlanarChain` holds the link parameters; its methods take joint arrays
of shape ``(..., n_links)`` and vectorise over the leading axes.
"""

from .chain import PlanarChain
from .kinematics import ChainKinematics
from .simulation import Trajectory

__all__ = ["ChainKinematics", "PlanarChain", "Trajectory"]
