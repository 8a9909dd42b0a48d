"""The typed surface of Pinocchio (and coal) that motiontool uses: Protocols, not the library.

Pinocchio ships no type stubs, so ``pinocchio`` reads as ``Any`` to mypy and nothing written
against it would be checked. These Protocols name every attribute and function the adapter and
:mod:`motiontool.kinematics.ik` / :mod:`motiontool.kinematics.export` touch, with the types
Pinocchio 3 and 4 give them (arrays are float64, positions in m, angles in rad). The module
object itself comes from :func:`pin_module`: the one place where the untyped library enters.
Anything the code needs beyond these is added here first, so mypy checks every use.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Protocol, cast

from motiontool.extras import require

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    #: A vector (q, v, a position) or a matrix, float64.
    Array = npt.NDArray[np.float64]

__all__ = [
    "SE3",
    "CollisionGeometry",
    "Data",
    "Frame",
    "GeometryData",
    "GeometryModel",
    "GeometryObject",
    "Inertia",
    "JointModel",
    "Model",
    "Pinocchio",
    "pin_module",
]


class SE3(Protocol):
    """A rigid placement: ``rotation`` (3, 3), ``translation`` (3,) m, ``homogeneous`` (4, 4)."""

    @property
    def rotation(self) -> Array: ...
    @property
    def translation(self) -> Array: ...
    @property
    def homogeneous(self) -> Array: ...
    def act(self, point: Array) -> Array: ...
    def actInv(self, other: SE3) -> SE3: ...
    def inverse(self) -> SE3: ...


class _Axis(Protocol):
    @property
    def axis(self) -> Array: ...


class JointModel(Protocol):
    """One joint: its sizes in q and v and where it starts in them."""

    @property
    def nq(self) -> int: ...
    @property
    def nv(self) -> int: ...
    @property
    def idx_q(self) -> int: ...
    @property
    def idx_v(self) -> int: ...
    def shortname(self) -> str: ...
    def extract(self) -> _Axis: ...


class Frame(Protocol):
    """A frame (``type`` is a ``FrameType``: compare ``str(type)`` with ``"BODY"``, ...)."""

    @property
    def name(self) -> str: ...
    @property
    def parentJoint(self) -> int: ...
    @property
    def parentFrame(self) -> int: ...
    @property
    def type(self) -> object: ...
    @property
    def placement(self) -> SE3: ...


class Inertia(Protocol):
    """Mass (kg), centre of mass ``lever`` (3,) m, ``inertia`` (3, 3) kg·m² about it."""

    @property
    def mass(self) -> float: ...
    @property
    def lever(self) -> Array: ...
    @property
    def inertia(self) -> Array: ...


class Data(Protocol):
    """Work buffers of a model; ``oMf`` holds the frames' world placements once computed."""

    @property
    def oMf(self) -> Sequence[SE3]: ...


class Model(Protocol):
    """A kinematic tree; index 0 of the joint tables is the universe."""

    @property
    def njoints(self) -> int: ...
    @property
    def nframes(self) -> int: ...
    @property
    def joints(self) -> Sequence[JointModel]: ...
    @property
    def names(self) -> Sequence[str]: ...
    @property
    def parents(self) -> Sequence[int]: ...
    @property
    def frames(self) -> Sequence[Frame]: ...
    @property
    def jointPlacements(self) -> Sequence[SE3]: ...
    @property
    def inertias(self) -> Sequence[Inertia]: ...
    @property
    def lowerPositionLimit(self) -> Array: ...
    @property
    def upperPositionLimit(self) -> Array: ...
    @property
    def velocityLimit(self) -> Array: ...
    @property
    def effortLimit(self) -> Array: ...
    def createData(self) -> Data: ...
    def getJointId(self, name: str) -> int: ...
    def getFrameId(self, name: str) -> int: ...


class CollisionGeometry(Protocol):
    """A coal geometry. Its shape is ``type(geometry).__name__`` (``Sphere``, ``Box``,
    ``Capsule``, ``Cylinder``, a mesh's ``BVHModelOBBRSS``, ...); the sizes (m) exist on the
    shapes that have them, so read them only after checking the name."""

    radius: float
    halfLength: float
    halfSide: Array
    aabb_center: Array
    aabb_radius: float

    def computeLocalAABB(self) -> None: ...


class GeometryObject(Protocol):
    """A collision geometry, the joint and frame that carry it, and its placement there."""

    @property
    def name(self) -> str: ...
    @property
    def parentJoint(self) -> int: ...
    @property
    def parentFrame(self) -> int: ...
    @property
    def placement(self) -> SE3: ...
    @property
    def geometry(self) -> CollisionGeometry: ...
    @property
    def meshPath(self) -> str: ...
    @property
    def meshScale(self) -> Array: ...


class CollisionPair(Protocol):
    @property
    def first(self) -> int: ...
    @property
    def second(self) -> int: ...


class GeometryModel(Protocol):
    """The collision geometries of a model and the pairs checked against each other."""

    @property
    def geometryObjects(self) -> Sequence[GeometryObject]: ...
    @property
    def collisionPairs(self) -> Sequence[CollisionPair]: ...
    def addCollisionPair(self, pair: CollisionPair) -> None: ...
    def removeCollisionPair(self, pair: CollisionPair) -> None: ...
    def getGeometryId(self, name: str) -> int: ...


class _Contact(Protocol):
    @property
    def penetration_depth(self) -> float: ...


class _CollisionResult(Protocol):
    def isCollision(self) -> bool: ...
    def numContacts(self) -> int: ...
    def getContact(self, index: int) -> _Contact: ...


class _DistanceResult(Protocol):
    @property
    def min_distance(self) -> float: ...


class _QueryRequest(Protocol):
    """coal's settings of one pair's distance or collision query."""

    enable_cached_gjk_guess: bool


class GeometryData(Protocol):
    """Work buffers of a geometry model: world placements ``oMg``, one result and one request
    of each kind per pair."""

    @property
    def oMg(self) -> Sequence[SE3]: ...
    @property
    def collisionResults(self) -> Sequence[_CollisionResult]: ...
    @property
    def distanceRequests(self) -> Sequence[_QueryRequest]: ...
    @property
    def collisionRequests(self) -> Sequence[_QueryRequest]: ...


class _Motion(Protocol):
    @property
    def vector(self) -> Array: ...


class _FrameTypes(Protocol):
    @property
    def BODY(self) -> object: ...


#: The classes again, under names that :class:`Pinocchio`'s constructors (``GeometryData``, ...)
#: do not hide.
_GeometryData = GeometryData
_SE3 = SE3
_CollisionPair = CollisionPair


class Pinocchio(Protocol):
    """The ``pinocchio`` module, as far as motiontool uses it."""

    COLLISION: object
    LOCAL: object
    LOCAL_WORLD_ALIGNED: object
    FrameType: _FrameTypes

    def neutral(self, model: Model) -> Array: ...
    def buildModelFromUrdf(self, path: str, *root_joint: object) -> Model: ...
    def buildModelFromMJCF(self, path: str) -> Model: ...
    def JointModelFreeFlyer(self) -> object: ...
    def buildGeomFromUrdf(
        self, model: Model, path: str, kind: object, *, package_dirs: list[str]
    ) -> GeometryModel: ...
    def buildGeomFromMJCF(self, model: Model, path: str, kind: object) -> GeometryModel: ...
    def GeometryData(self, geoms: GeometryModel) -> _GeometryData: ...
    def CollisionPair(self, first: int, second: int) -> _CollisionPair: ...
    def SE3(self, rotation: Array, translation: Array) -> _SE3: ...
    def computeCollisions(
        self,
        model: Model,
        data: Data,
        geoms: GeometryModel,
        geom_data: _GeometryData,
        q: Array,
        stop_at_first_collision: bool,
    ) -> bool: ...
    def computeCollision(
        self, geoms: GeometryModel, geom_data: _GeometryData, pair: int
    ) -> bool: ...
    def computeDistance(
        self, geoms: GeometryModel, geom_data: _GeometryData, pair: int
    ) -> _DistanceResult: ...
    def forwardKinematics(self, model: Model, data: Data, q: Array) -> None: ...
    def framesForwardKinematics(self, model: Model, data: Data, q: Array) -> None: ...
    def updateFramePlacement(self, model: Model, data: Data, frame_id: int) -> _SE3: ...
    def updateGeometryPlacements(
        self, model: Model, data: Data, geoms: GeometryModel, geom_data: _GeometryData, *q: Array
    ) -> None: ...
    def centerOfMass(self, model: Model, data: Data, q: Array, subtree: bool) -> Array: ...
    def computeFrameJacobian(
        self, model: Model, data: Data, q: Array, frame_id: int, reference: object
    ) -> Array: ...
    def log6(self, placement: _SE3) -> _Motion: ...
    def Jlog6(self, placement: _SE3) -> Array: ...


def pin_module(what: str = "collision, balance and URDF/MJCF robot models") -> Pinocchio:
    """The ``pinocchio`` module, or a :class:`MissingExtraError` saying that ``what`` needs the
    ``kinematics`` extra.

    The one point where the untyped library enters: what the code uses of it is
    :class:`Pinocchio`."""
    return cast("Pinocchio", require("pinocchio", "kinematics", what))
