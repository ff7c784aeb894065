"""MuJoCo models of a :class:`~tentaclass.PlanarChain` and of an extruded outline (MJCF)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from .._typing import ArrayLike, FloatArray
from .._validation import check_positive_float
from ..errors import InputError
from ..manipulator import PlanarChain
from ._decompose import convex_pieces

if TYPE_CHECKING:
    import mujoco

__all__ = ["MAX_LINKS", "ChainModel", "build_model", "chain_mjcf", "check_chain_depth"]

#: Most links of a chain MuJoCo can build: each link is a body nested in the
#: previous one, and MuJoCo's XML reader stops at 500 nested elements.
MAX_LINKS = 496

#: Inertia given to a link whose inertia about its centre of mass is 0
#: (MuJoCo refuses massless or inertia-free moving bodies), relative to m l^2.
_MIN_INERTIA = 1e-12


def _mujoco() -> Any:
    try:
        import mujoco
    except ImportError as exc:  # pragma: no cover - depends on the installation
        raise ImportError(
            "tentaclass.physics needs MuJoCo: pip install 'tentaclass[physics]'"
        ) from exc
    return mujoco


def check_chain_depth(n_links: int) -> None:
    """Refuse a chain of more links than MuJoCo can nest (:data:`MAX_LINKS`).

    >>> check_chain_depth(500)
    Traceback (most recent call last):
    ...
    tentaclass.errors.InputError: MuJoCo builds chains of at most 496 links (one body nested \
in the previous per link), got 500
    """
    if n_links > MAX_LINKS:
        raise InputError(f"MuJoCo builds chains of at most {MAX_LINKS} links (one body nested "
                         f"in the previous per link), got {n_links:,}")  # fmt: skip


def _f(x: float) -> str:
    return f"{float(x):.17g}"


def _vec(v: ArrayLike) -> str:
    return " ".join(_f(x) for x in np.ravel(v))


@dataclass(frozen=True)
class ChainModel:
    """A compiled MuJoCo model of a chain (and an object), with its bookkeeping.

    Attributes
    ----------
    model : mujoco.MjModel
    link_geoms : ndarray of int, shape (n_links,)
        Geom id of each link's capsule.
    object_geoms : ndarray of int, shape (n_pieces,)
        Geom ids of the object's convex pieces (empty without an object).
    lock_ids : ndarray of int, shape (n_links,)
        Equality constraint that can hold each joint at an angle (its
        ``eq_data[id, 0]``; inactive at first, see ``mujoco.MjData.eq_active``):
        the joint servos of :func:`tentaclass.physics.grasp`. Actuator ``i`` is a
        torque motor on joint ``i`` (``ctrl`` in N m).
    pieces : list of ndarray
        The object's convex pieces in the plane.
    """

    model: mujoco.MjModel
    link_geoms: np.ndarray
    object_geoms: np.ndarray
    lock_ids: np.ndarray
    pieces: list[FloatArray]


def chain_mjcf(
    chain: PlanarChain,
    outline: ArrayLike | None = None,
    *,
    base: ArrayLike = (0.0, 0.0),
    heading: float = 0.0,
    thickness: float = 0.0,
    damping: ArrayLike = 0.0,
    joint_range: tuple[float, float] | None = None,
    gravity: bool = False,
    friction: float = 0.0,
    timestep: float = 0.002,
    colliding: ArrayLike | None = None,
    pieces: list[FloatArray] | None = None,
) -> str:
    """MJCF (MuJoCo's XML) of a planar chain and, optionally, a fixed object.

    Parameters
    ----------
    chain : PlanarChain
        Link lengths, masses, centres of mass and inertias, taken exactly.
    outline : array_like of shape (n_points, 2), optional
        Object outline, extruded along z and fixed to the world. A non-convex
        outline is split into convex pieces (:func:`convex_pieces`), one mesh
        geom each, so it collides as itself and not as its convex hull.
    base : array_like of shape (2,), default=(0, 0)
        Position of the first joint.
    heading : float, default=0.0
        Direction (radians) of the base frame: ``q[0]`` is measured from it.
    thickness : float, default=0.0
        Diameter of the capsule around each link; 0 gives links that touch
        nothing (no geoms collide).
    damping : float or array_like of shape (n_links,), default=0.0
        Viscous joint damping (torque per angular velocity).
    joint_range : (float, float), optional
        Limits on every relative joint angle (radians); none by default.
    gravity : bool, default=False
        Apply the chain's gravity along -y; by default the plane has none
        (a chain lying on a table).
    friction : float, default=0.0
        Sliding friction coefficient of every contact (0: frictionless contacts
        that only push along the normal).
    timestep : float, default=0.002
        Integration step, seconds (implicit-in-velocity Euler). Contacts and
        joint locks are stiff springs with time constant ``2 * timestep``
        (MuJoCo's ``solref``), the stiffest it integrates stably.
    colliding : array_like of bool, shape (n_links,), optional
        Links that can touch anything (default all); the others pass through.
    pieces : list of ndarray, optional
        Convex pieces of ``outline`` computed before (skips the decomposition).

    Returns
    -------
    xml : str

    Notes
    -----
    Link ``i`` is a body whose frame sits on joint ``i`` with x along the link; its
    inertial frame is at ``com[i] * link_lengths[i]`` on x with
    ``diaginertia = (I, I, I)`` (only the z entry matters to hinges about z), so
    MuJoCo's ``M(q)`` and bias forces are exactly those of the chain. Adjacent
    links never collide (MuJoCo filters parent-child pairs); other links do.

    Examples
    --------
    >>> xml = chain_mjcf(PlanarChain([1.0, 1.0]))
    >>> xml.count('type="hinge"')
    2
    """
    if not isinstance(chain, PlanarChain):
        raise InputError(f"chain must be a PlanarChain, got {type(chain).__name__}")
    check_chain_depth(chain.n_links)
    n = chain.n_links
    thickness = check_positive_float(thickness, "thickness", allow_zero=True)
    friction = check_positive_float(friction, "friction", allow_zero=True)
    timestep = check_positive_float(timestep, "timestep")
    damp = np.broadcast_to(np.asarray(damping, dtype=float), (n,))
    if not np.all(np.isfinite(damp)) or np.any(damp < 0):
        raise InputError(f"damping must be finite and >= 0, got {damping!r}")
    coll = np.ones(n, bool) if colliding is None else np.broadcast_to(colliding, (n,))
    base = np.asarray(base, dtype=float)
    g = chain.gravity if gravity else 0.0
    limit = ""
    if joint_range is not None:
        lo, hi = (float(v) for v in joint_range)
        if not lo < hi:
            raise InputError(f"joint_range must be (low, high) with low < high, got {joint_range}")
        limit = f' limited="true" range="{_f(lo)} {_f(hi)}"'
    r = 0.5 * thickness
    out = [
        '<mujoco model="tentaclass">',
        '  <compiler angle="radian" inertiafromgeom="false" autolimits="true"/>',
        f'  <option timestep="{_f(timestep)}" gravity="0 {_f(-g)} 0" integrator="implicitfast"'
        ' cone="elliptic"/>',
        f'  <default><geom friction="{_f(friction)} 0.005 0.0001" condim="{3 if friction else 1}"'
        f' solref="{_f(2 * timestep)} 1" solimp="0.99 0.999 0.001"/></default>',
    ]
    object_pieces: list[FloatArray] = []
    if outline is not None:
        object_pieces = convex_pieces(outline) if pieces is None else pieces
        scale = float(np.ptp(np.concatenate(object_pieces), axis=0).max())
        h = 0.5 * scale + thickness
        out.append("  <asset>")
        for k, pc in enumerate(object_pieces):
            top = np.c_[pc, np.full(len(pc), h)]
            bottom = np.c_[pc, np.full(len(pc), -h)]
            out.append(f'    <mesh name="piece{k}" vertex="{_vec(np.r_[top, bottom])}"/>')
        out.append("  </asset>")
    out.append("  <worldbody>")
    if outline is not None:
        out.append('    <body name="object">')
        for k in range(len(object_pieces)):
            out.append(
                f'      <geom name="object{k}" type="mesh" mesh="piece{k}" contype="1"'
                ' conaffinity="1" group="1"/>'
            )
        out.append("    </body>")
    indent = "    "
    for i in range(n):
        ln, m = chain.link_lengths[i], chain.masses[i]
        inertia = max(chain.inertia[i], _MIN_INERTIA * m * ln * ln)
        pos = f"{_vec(base)} 0" if i == 0 else f"{_f(chain.link_lengths[i - 1])} 0 0"
        euler = f' euler="0 0 {_f(heading)}"' if i == 0 else ""
        out.append(f'{indent}<body name="link{i}" pos="{pos}"{euler}>')
        out.append(
            f'{indent}  <joint name="q{i}" type="hinge" axis="0 0 1" damping="{_f(damp[i])}"'
            f' armature="0"{limit}/>'
        )
        out.append(
            f'{indent}  <inertial pos="{_f(chain.com[i] * ln)} 0 0" mass="{_f(m)}"'
            f' diaginertia="{_f(inertia)} {_f(inertia)} {_f(inertia)}"/>'
        )
        if r > 0:
            ct = 1 if coll[i] else 0
            out.append(
                f'{indent}  <geom name="link{i}" type="capsule" fromto="0 0 0 {_f(ln)} 0 0"'
                f' size="{_f(r)}" contype="{ct}" conaffinity="{ct}" mass="0"/>'
            )
        indent += "  "
    for _ in range(n):
        indent = indent[:-2]
        out.append(f"{indent}</body>")
    out.append("  </worldbody>")
    out.append("  <equality>")
    for i in range(n):
        out.append(
            f'    <joint name="lock{i}" joint1="q{i}" polycoef="0 0 0 0 0" active="false"'
            f' solref="{_f(2 * timestep)} 1" solimp="0.9999 0.9999 0.001"/>'
        )
    out.append("  </equality>")
    out.append("  <actuator>")
    for i in range(n):
        out.append(f'    <motor name="motor{i}" joint="q{i}" gear="1"/>')
    out.append("  </actuator>")
    out.append("</mujoco>")
    return "\n".join(out)


def build_model(chain: PlanarChain, outline: ArrayLike | None = None, **kwargs: Any) -> ChainModel:
    """Compile the MuJoCo model of a chain and an optional object.

    Parameters
    ----------
    chain : PlanarChain
    outline : array_like of shape (n_points, 2), optional
    **kwargs
        As in :func:`chain_mjcf`.

    Returns
    -------
    ChainModel

    Examples
    --------
    >>> cm = build_model(PlanarChain([1.0, 1.0]))
    >>> cm.model.nv, cm.model.opt.gravity.tolist()
    (2, [0.0, 0.0, 0.0])
    """
    mujoco = _mujoco()
    if outline is not None and kwargs.get("pieces") is None:
        kwargs["pieces"] = convex_pieces(outline)
    xml = chain_mjcf(chain, outline, **kwargs)
    try:
        model = mujoco.MjModel.from_xml_string(xml)
    except ValueError as exc:
        msg = str(exc).strip().splitlines()[0].removeprefix("Error: ").strip()
        if "mesh volume is too small" in msg:
            msg = ("a convex piece of the object has too little volume for a MuJoCo mesh "
                   "(the object is too small against the links: scale it up or use shorter "
                   "links)")  # fmt: skip
        raise InputError(f"MuJoCo cannot build this chain or object: {msg}") from None
    n = chain.n_links
    names = [model.geom(i).name for i in range(model.ngeom)]
    link_geoms = np.array([names.index(f"link{i}") if f"link{i}" in names else -1
                           for i in range(n)])  # fmt: skip
    obj = np.array([i for i, nm in enumerate(names) if nm.startswith("object")], dtype=int)
    locks = np.array([model.equality(f"lock{i}").id for i in range(n)])
    return ChainModel(model, link_geoms, obj, locks, kwargs.get("pieces") or [])
