"""Result types of a wrap: one :class:`Wrap`, or a stacked :class:`WrapBatch`."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from .._typing import BoolArray, FloatArray, IntArray

__all__ = ["Wrap", "WrapBatch"]


@dataclass(frozen=True)
class Wrap:
    """One chain wrapped on an object (see :func:`wrap`).

    Attributes
    ----------
    angles : ndarray of shape (n_placed,)
        Relative joint angles ``q`` (noise included), as in
        :func:`tentaclass.angles_to_points` with ``heading``.
    joints : ndarray of shape (n_placed + 1, 2)
        Joint positions, ``joints[0]`` the base (noise-free geometry).
    contact : ndarray of bool, shape (n_placed + 1,)
        Joint rests on the object's outline (first lap only).
    lap : ndarray of int, shape (n_placed + 1,)
        Lap whose support the joint rests on (0 = the object); -1 for joints in
        the air (the approach, and link tips overhanging a corner).
    laps : float
        Turns around the object since the start point, ``(phi_n - phi_s) / 2pi``:
        ``phi_n`` is the last link's heading, ``phi_s`` the support's direction at
        the start point: without an offset the heading of the chord arriving
        there from one link length behind (so a closed single wrap gives exactly
        1.0), with one the direction of the support edge the approach meets
        (a quarter turn right of the approach, which runs along its inward
        normal).
    offset_links : int
        Links from the base to the start point on the support, ``ceil(offset / l)``.
    heading : float
        Reference direction of ``angles[0]``.
    complete : bool
        All requested links were placed (always True: a link the support cannot
        take folds in towards the object instead of ending the chain).
    closure_gap : float
        Distance from the start point to the nearest joint where the chain
        closes its first lap; NaN when ``laps < 1``.
    start_point : ndarray of shape (2,)
        Where the chain meets its support (the first contact).
    link_length : float
    direction : str
    """

    angles: FloatArray
    joints: FloatArray
    contact: BoolArray
    lap: IntArray
    laps: float
    offset_links: int
    heading: float
    complete: bool
    closure_gap: float
    start_point: FloatArray
    link_length: float
    direction: str


@dataclass(frozen=True)
class WrapBatch:
    """Stacked results of :func:`wrap_many`; rows beyond ``n_placed`` are NaN / -2."""

    angles: FloatArray  # (b, n)
    joints: FloatArray  # (b, n + 1, 2)
    contact: BoolArray  # (b, n + 1)
    lap: IntArray  # (b, n + 1)
    laps: FloatArray  # (b,)
    offset_links: IntArray  # (b,)
    heading: FloatArray  # (b,)
    complete: BoolArray  # (b,)
    n_placed: IntArray  # (b,)
    closure_gap: FloatArray  # (b,)
    start_point: FloatArray  # (b, 2)
    if TYPE_CHECKING:
        # set after construction with object.__setattr__: not dataclass fields
        _link_length: FloatArray = field(init=False, repr=False, compare=False)  # (b,)
        _direction: str = field(init=False, repr=False, compare=False)

    def __len__(self) -> int:
        return len(self.laps)

    def __getitem__(self, i: int) -> Wrap:
        """Row ``i`` as a :class:`Wrap`."""
        p = int(self.n_placed[i])
        return Wrap(
            angles=self.angles[i, :p],
            joints=self.joints[i, : p + 1],
            contact=self.contact[i, : p + 1],
            lap=self.lap[i, : p + 1],
            laps=float(self.laps[i]),
            offset_links=int(self.offset_links[i]),
            heading=float(self.heading[i]),
            complete=bool(self.complete[i]),
            closure_gap=float(self.closure_gap[i]),
            start_point=self.start_point[i],
            link_length=float(self._link_length[i]),
            direction=self._direction,
        )
