"""The chain and the object in MuJoCo: physical grasps (optional extra ``physics``).

:func:`grasp` closes a :class:`tentaclass.PlanarChain` on an object with a torque
controller and returns the joint angles at rest as a :class:`tentaclass.Wrap`,
so classifiers and :func:`tentaclass.grasp_state` read it like a geometric wrap.
:func:`build_model` gives the MuJoCo model itself. Needs ``pip install
'tentaclass[physics]'`` (MuJoCo); importing this package works without it,
building a model does not. :func:`quasi_static_grasp` is the same grasp in its
quasi-static limit, geometry only (no MuJoCo needed): fast enough to generate
training wraps that look like physical ones.
"""

from ._batch import grasp_many
from ._controller import CurlController
from ._decompose import convex_pieces
from ._grasp import PhysicalGrasp, grasp
from ._model import MAX_LINKS, ChainModel, build_model, chain_mjcf
from ._quasi import quasi_static_grasp

__all__ = [
    "MAX_LINKS",
    "ChainModel",
    "CurlController",
    "PhysicalGrasp",
    "build_model",
    "chain_mjcf",
    "convex_pieces",
    "grasp",
    "grasp_many",
    "quasi_static_grasp",
]
