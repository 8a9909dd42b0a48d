"""The typed surface of MuJoCo that motiontool uses: Protocols, not the library.

MuJoCo (4.0, as tested here) ships no type stubs (no ``py.typed``, no ``.pyi``), so ``mujoco``
reads as ``Any`` to mypy and nothing written against it would be checked. These Protocols name
every attribute and function the adapter (:mod:`motiontool.sim._mujoco`) and its users touch,
with the types the bindings give them (their docstrings carry the signatures): arrays are
float64 (positions in m, angles in rad, quaternions w, x, y, z) or int32 (ids and addresses).
The module object itself comes from :func:`mj`: the one place where the untyped library enters.
Anything the code needs beyond these is added here first, so that mypy checks every use.

They are types only: the objects are MuJoCo's own, so a call through them costs what it cost
before (no wrapper between the stepping loop and ``mj_step``). What is read from the installed
MuJoCo itself is here too: its version (:func:`mujoco_version`) and its warnings' names
(:func:`warning_labels`).
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Protocol, cast

from motiontool.extras import require

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    #: A float64 array: a vector, a (N, 3) table of positions, ...
    Array = npt.NDArray[np.float64]
    #: An int32 array of ids or addresses, as MuJoCo's model tables hold them.
    IntArray = npt.NDArray[np.int32]

__all__ = [
    "EnumValue",
    "MjData",
    "MjModel",
    "MjSpec",
    "MjsBody",
    "MjsGeom",
    "MjsJoint",
    "MjsMesh",
    "MjsPair",
    "MjsTendon",
    "MuJoCo",
    "mj",
    "mujoco_version",
    "warning_label",
    "warning_labels",
]


class EnumValue(Protocol):
    """A member of a MuJoCo enum (``mjtGeom.mjGEOM_BOX``, ...: a pybind11 enum, which hashes
    and compares equal to its int value), or the plain int an option reads back as."""

    def __int__(self) -> int: ...


class _Option(Protocol):
    timestep: float  # s


class _NamedView(Protocol):
    """``model.body(i)``, ``model.joint("name")``, ...: one element of a model table."""

    @property
    def id(self) -> int: ...
    @property
    def name(self) -> str: ...


class _GeomView(_NamedView, Protocol):
    @property
    def friction(self) -> Array: ...  # (3,): sliding, torsional (m), rolling (m)


class MjModel(Protocol):
    """A compiled model: sizes, the tables the adapter reads (index = element id), views."""

    @property
    def opt(self) -> _Option: ...
    @property
    def nbody(self) -> int: ...
    @property
    def ngeom(self) -> int: ...
    @property
    def nsite(self) -> int: ...
    @property
    def body_parentid(self) -> IntArray: ...
    @property
    def body_jntadr(self) -> IntArray: ...
    @property
    def body_jntnum(self) -> IntArray: ...
    @property
    def body_geomadr(self) -> IntArray: ...
    @property
    def body_geomnum(self) -> IntArray: ...
    @property
    def jnt_bodyid(self) -> IntArray: ...
    @property
    def jnt_qposadr(self) -> IntArray: ...
    @property
    def jnt_dofadr(self) -> IntArray: ...
    @property
    def geom_bodyid(self) -> IntArray: ...
    @property
    def geom_type(self) -> IntArray: ...
    @property
    def geom_contype(self) -> IntArray: ...
    @property
    def geom_conaffinity(self) -> IntArray: ...
    @property
    def pair_geom1(self) -> IntArray: ...
    @property
    def pair_geom2(self) -> IntArray: ...
    @property
    def geom_size(self) -> Array: ...  # (ngeom, 3), m
    @property
    def geom_aabb(self) -> Array: ...  # (ngeom, 6): centre, half sizes, m, in the geom frame
    @property
    def geom_pos(self) -> Array: ...  # (ngeom, 3), m, in the body frame
    @property
    def geom_quat(self) -> Array: ...  # (ngeom, 4), w x y z, in the body frame
    @property
    def site_bodyid(self) -> IntArray: ...
    def body(self, key: int | str) -> _NamedView: ...
    def joint(self, key: int | str) -> _NamedView: ...
    def geom(self, key: int | str) -> _GeomView: ...
    def site(self, key: int | str) -> _NamedView: ...


class _Contacts(Protocol):
    @property
    def geom(self) -> IntArray: ...  # (ncon, 2)
    @property
    def dist(self) -> Array: ...  # (ncon,), m: negative is penetration


class _WarningStat(Protocol):
    @property
    def number(self) -> int: ...


class _Warnings(Protocol):
    """``MjData.warning``: indexed by ``mjtWarning``, not iterable (no ``__iter__``)."""

    def __getitem__(self, index: int) -> _WarningStat: ...
    def __len__(self) -> int: ...


class MjData(Protocol):
    """The state of a model and what MuJoCo computed from it (world poses, contacts, warnings)."""

    @property
    def qpos(self) -> Array: ...
    @property
    def qvel(self) -> Array: ...
    @property
    def qfrc_constraint(self) -> Array: ...
    @property
    def xpos(self) -> Array: ...  # (nbody, 3), m
    @property
    def xquat(self) -> Array: ...  # (nbody, 4), w x y z
    @property
    def geom_xpos(self) -> Array: ...
    @property
    def geom_xmat(self) -> Array: ...  # (ngeom, 9), row-major
    @property
    def site_xpos(self) -> Array: ...
    @property
    def site_xmat(self) -> Array: ...
    @property
    def ncon(self) -> int: ...
    @property
    def contact(self) -> _Contacts: ...
    @property
    def warning(self) -> _Warnings: ...


class MjsJoint(Protocol):
    name: str
    type: EnumValue  # mjtJoint
    limited: EnumValue  # mjtLimited
    actfrclimited: EnumValue  # mjtLimited


class MjsGeom(Protocol):
    name: str
    priority: int
    contype: int
    conaffinity: int

    @property
    def friction(self) -> Array: ...
    @friction.setter
    def friction(self, value: Sequence[float]) -> None: ...
    @property
    def solref(self) -> Array: ...
    @solref.setter
    def solref(self, value: Sequence[float]) -> None: ...


class MjsTendon(Protocol):
    frictionloss: float  # N·m (N)

    @property
    def solref_friction(self) -> Array: ...
    @solref_friction.setter
    def solref_friction(self, value: Sequence[float]) -> None: ...
    @property
    def solimp_friction(self) -> Array: ...
    @solimp_friction.setter
    def solimp_friction(self, value: Sequence[float]) -> None: ...
    def wrap_joint(self, name: str, coef: float) -> object: ...


class MjsMesh(Protocol):
    file: str


class MjsPair(Protocol):
    @property
    def geomname1(self) -> str: ...
    @property
    def geomname2(self) -> str: ...


class MjsBody(Protocol):
    """A body of a spec (``spec.worldbody`` is one): its children, inertia and placement."""

    name: str
    mass: float  # kg
    explicitinertial: bool

    @property
    def joints(self) -> Sequence[MjsJoint]: ...
    @property
    def bodies(self) -> Sequence[MjsBody]: ...
    @property
    def pos(self) -> Array: ...
    @pos.setter
    def pos(self, value: Sequence[float]) -> None: ...
    @property
    def inertia(self) -> Array: ...
    @inertia.setter
    def inertia(self, value: Sequence[float]) -> None: ...
    @property
    def fullinertia(self) -> Array: ...
    @fullinertia.setter
    def fullinertia(self, value: Sequence[float]) -> None: ...
    def add_body(self, *, name: str, mass: float) -> MjsBody: ...
    def add_freejoint(self) -> MjsJoint: ...
    def add_joint(
        self, *, name: str, type: EnumValue, axis: Sequence[float], armature: float
    ) -> MjsJoint: ...
    def add_geom(
        self,
        *,
        name: str,
        type: EnumValue,
        size: Sequence[float],
        rgba: Sequence[float],
        pos: Sequence[float] = ...,
        quat: Sequence[float] = ...,
    ) -> MjsGeom: ...
    def add_light(self, *, name: str, pos: Sequence[float], dir: Sequence[float]) -> object: ...


class _SpecOption(Protocol):
    timestep: float  # s
    gravity: Sequence[float]  # m/s², z up
    jacobian: EnumValue  # mjtJacobian
    cone: EnumValue  # mjtCone
    tolerance: float
    disableflags: int  # mjtDisableBit


class _Compiler(Protocol):
    balanceinertia: bool
    fusestatic: bool


class MjSpec(Protocol):
    """An editable model (read from a file, then changed and compiled)."""

    @property
    def option(self) -> _SpecOption: ...
    @property
    def compiler(self) -> _Compiler: ...
    @property
    def worldbody(self) -> MjsBody: ...
    @property
    def bodies(self) -> Sequence[MjsBody]: ...
    @property
    def joints(self) -> Sequence[MjsJoint]: ...
    @property
    def geoms(self) -> Sequence[MjsGeom]: ...
    @property
    def meshes(self) -> Sequence[MjsMesh]: ...
    @property
    def actuators(self) -> Sequence[object]: ...
    def add_tendon(self, *, name: str) -> MjsTendon: ...
    def add_pair(self, *, geomname1: str, geomname2: str) -> MjsPair: ...
    def add_exclude(self, *, bodyname1: str, bodyname2: str) -> object: ...
    def delete(self, element: object) -> None: ...
    def copy(self) -> MjSpec: ...
    def compile(self) -> MjModel: ...


class _SpecClass(Protocol):
    def from_file(self, filename: str) -> MjSpec: ...


class _Enum(Protocol):
    @property
    def __members__(self) -> Mapping[str, EnumValue]: ...


class _Geoms(Protocol):
    mjGEOM_PLANE: EnumValue
    mjGEOM_SPHERE: EnumValue
    mjGEOM_CAPSULE: EnumValue
    mjGEOM_ELLIPSOID: EnumValue
    mjGEOM_CYLINDER: EnumValue
    mjGEOM_BOX: EnumValue


class _Joints(Protocol):
    mjJNT_FREE: EnumValue
    mjJNT_HINGE: EnumValue


class _Limited(Protocol):
    mjLIMITED_FALSE: EnumValue


class _Jacobians(Protocol):
    mjJAC_DENSE: EnumValue


class _Cones(Protocol):
    mjCONE_PYRAMIDAL: EnumValue


class _DisableBits(Protocol):
    mjDSBL_FILTERPARENT: EnumValue


#: The classes again, under a name that :class:`MuJoCo`'s constructor ``MjData`` does not hide.
_MjData = MjData


class MuJoCo(Protocol):
    """The ``mujoco`` module, as far as motiontool uses it."""

    __version__: str
    MjSpec: _SpecClass
    FatalError: type[Exception]
    mjtWarning: _Enum
    mjtGeom: _Geoms
    mjtJoint: _Joints
    mjtLimited: _Limited
    mjtJacobian: _Jacobians
    mjtCone: _Cones
    mjtDisableBit: _DisableBits

    def MjData(self, model: MjModel) -> _MjData: ...
    def mj_step(self, m: MjModel, d: _MjData, nstep: int = 1) -> None: ...
    def mj_forward(self, m: MjModel, d: _MjData) -> None: ...
    def mj_kinematics(self, m: MjModel, d: _MjData) -> None: ...
    def mj_collision(self, m: MjModel, d: _MjData) -> None: ...
    def mju_mat2Quat(self, quat: Array, mat: Array) -> None: ...


def mj() -> MuJoCo:
    """The ``mujoco`` module, or a one-line error naming ``motiontool[sim]``.

    The one point where the untyped library enters: what the code uses of it is
    :class:`MuJoCo`."""
    return cast("MuJoCo", require("mujoco", "sim", "simulation (motiontool play, batch)"))


def warning_label(enum_name: str) -> str:
    """The report key of a MuJoCo warning, from its ``mjtWarning`` name: ``mjWARN_BADQACC``
    -> ``bad_qacc``, ``mjWARN_CONTACTFULL`` -> ``contact_full``, ``mjWARN_CNSTRFULL`` ->
    ``constraint_full`` (a name this does not know comes out lower-cased)."""
    word = enum_name.removeprefix("mjWARN_").lower().replace("cnstr", "constraint")
    word = re.sub(r"^bad(?=.)", "bad_", word)
    return re.sub(r"(?<=[a-z])full$", "_full", word)


def warning_labels() -> dict[int, str]:
    """Index in ``MjData.warning`` -> report key, for every warning of the installed MuJoCo
    (read from ``mujoco.mjtWarning``, so that a version that adds or reorders warnings is
    labelled right)."""
    mujoco = mj()

    members = mujoco.mjtWarning.__members__
    return {
        int(value): warning_label(name)
        for name, value in sorted(members.items(), key=lambda item: int(item[1]))
        if name.startswith("mjWARN_")
    }


def mujoco_version() -> str:
    """The MuJoCo version string."""
    mujoco = mj()

    return str(mujoco.__version__)
