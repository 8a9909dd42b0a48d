"""A model's kinematic tree and collision geometry as plain numpy arrays (batched kinematics).

:func:`kinematic_tables` reads them from Pinocchio once per process and robot; from there
:mod:`motiontool.kinematics.collision` evaluates forward kinematics for many configurations at
once without Pinocchio.
"""

from __future__ import annotations

import functools
import math
import re
from pathlib import Path
from typing import TYPE_CHECKING, NamedTuple

from motiontool.kinematics._pinocchio.shapes import OTHER, bounding_sphere, shape
from motiontool.kinematics.robots import RobotSpec

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.kinematics._pinocchio.api import GeometryModel, JointModel, Model

__all__ = ["FIXED", "PRISMATIC", "REVOLUTE", "KinematicTables", "joint_motion", "kinematic_tables"]

#: Joint kinds in :class:`KinematicTables`.
FIXED, REVOLUTE, PRISMATIC = 0, 1, 2

_FINGER = re.compile(r"phalanx|finger", re.IGNORECASE)
_AXES = {"X": (1.0, 0.0, 0.0), "Y": (0.0, 1.0, 0.0), "Z": (0.0, 0.0, 1.0)}


class KinematicTables(NamedTuple):
    """A model's kinematic tree and collision geometry as plain numpy arrays.

    Enough to evaluate forward kinematics for many configurations at once in numpy
    (:mod:`motiontool.kinematics.collision`) without a Python loop per configuration. Model
    joints are in Pinocchio's order (a parent before its children); index 0 is the universe.

    Attributes:
        joint_parent: (nj,) int64, parent joint of each joint (the universe's is 0).
        joint_rotation: (nj, 3, 3) float64, joint placement in the parent joint frame.
        joint_translation: (nj, 3) float64, m, same placement.
        joint_axis: (nj, 3) float64, unit motion axis in the joint frame (zero if fixed).
        joint_kind: (nj,) int64, :data:`REVOLUTE`, :data:`PRISMATIC` or :data:`FIXED` (the
            universe, a free-flyer root held at the origin, and joints that are not motors).
        joint_motor: (nj,) int64, index of the joint's motor in ``spec.joints``, or -1.
        exact: False if the model has joints this table cannot move (e.g. mimic joints), so
            batched kinematics would hold them at their neutral position.
        geom_joint: (G,) int64, joint that carries each collision geometry.
        geom_rotation: (G, 3, 3) float64, geometry placement in its joint's frame.
        geom_translation: (G, 3) float64, m.
        geom_radius: (G,) float64, m, radius of a sphere about the geometry's origin that
            encloses it (exact for spheres, capsules, cylinders and boxes; from the local
            axis-aligned bounding box otherwise, about its centre ``geom_center``).
        geom_center: (G, 3) float64, m, centre of that sphere in the geometry frame.
        geom_shape: (G,) int64, :data:`~.shapes.SPHERE`, ``BOX``, ``CAPSULE``,
            ``CYLINDER`` (aligned with the geometry's z axis), or ``OTHER`` (a mesh:
            only its bounding sphere is known here).
        geom_size: (G, 3) float64, m: half sizes of a box; (radius, half length, 0) of a
            capsule or cylinder; (radius, 0, 0) of a sphere or of the bounding sphere (OTHER).
        geom_body: G body (MJCF) or link (URDF) names: the frame holding each geometry.
        geom_limb: G names for reports: the body, except that a finger (a body moved by a
            joint named like ``*Phalanx*`` or ``*finger*``) counts as part of its hand.
        pair_first, pair_second: (K,) int64, the geometries of each self-collision pair
            checked (see :func:`build_model`); index k is also Pinocchio's pair index.
        pair_motors: (K, M) bool: the motors whose motion changes the pose of the pair's two
            geometries relative to each other (joints on the tree path between them).
        pair_group: (K,) int64, index in ``group_joints`` of the pair's two joints.
        group_joints: (P, 2) int64, the distinct (joint, joint) of the pairs' geometries.
        joint_center: (nj, 3) float64, m, centre (joint frame) of a sphere enclosing every
            geometry the joint carries (its geometries' bounding spheres).
        joint_radius: (nj,) float64, m, its radius (0 for a joint without geometry).
    """

    joint_parent: npt.NDArray[np.int64]
    joint_rotation: npt.NDArray[np.float64]
    joint_translation: npt.NDArray[np.float64]
    joint_axis: npt.NDArray[np.float64]
    joint_kind: npt.NDArray[np.int64]
    joint_motor: npt.NDArray[np.int64]
    exact: bool
    geom_joint: npt.NDArray[np.int64]
    geom_rotation: npt.NDArray[np.float64]
    geom_translation: npt.NDArray[np.float64]
    geom_radius: npt.NDArray[np.float64]
    geom_center: npt.NDArray[np.float64]
    geom_shape: npt.NDArray[np.int64]
    geom_size: npt.NDArray[np.float64]
    geom_body: tuple[str, ...]
    geom_limb: tuple[str, ...]
    pair_first: npt.NDArray[np.int64]
    pair_second: npt.NDArray[np.int64]
    pair_motors: npt.NDArray[np.bool_]
    pair_group: npt.NDArray[np.int64]
    group_joints: npt.NDArray[np.int64]
    joint_center: npt.NDArray[np.float64]
    joint_radius: npt.NDArray[np.float64]


def kinematic_tables(spec: RobotSpec) -> KinematicTables:
    """The :class:`KinematicTables` of ``spec``'s model, built once per process and robot."""
    # The model builder is imported where tables are built: stored tables need none of it.
    from motiontool.kinematics._pinocchio.model import model_key

    return _tables(spec.name, spec.joint_names, *model_key(spec))


class _Joints(NamedTuple):
    """The joint columns of :class:`KinematicTables` (same names without ``joint_``)."""

    parent: npt.NDArray[np.int64]
    rotation: npt.NDArray[np.float64]
    translation: npt.NDArray[np.float64]
    axis: npt.NDArray[np.float64]
    kind: npt.NDArray[np.int64]
    motor: npt.NDArray[np.int64]
    exact: bool


class _Geoms(NamedTuple):
    """The geometry columns of :class:`KinematicTables` (same names without ``geom_``)."""

    joint: npt.NDArray[np.int64]
    rotation: npt.NDArray[np.float64]
    translation: npt.NDArray[np.float64]
    radius: npt.NDArray[np.float64]
    center: npt.NDArray[np.float64]
    shape: npt.NDArray[np.int64]
    size: npt.NDArray[np.float64]
    body: tuple[str, ...]
    limb: tuple[str, ...]


class _Pairs(NamedTuple):
    """The collision-pair columns of :class:`KinematicTables`."""

    first: npt.NDArray[np.int64]
    second: npt.NDArray[np.int64]
    motors: npt.NDArray[np.bool_]
    group: npt.NDArray[np.int64]
    group_joints: npt.NDArray[np.int64]


@functools.lru_cache(maxsize=16)
def _tables(
    name: str,
    motors: tuple[str, ...],
    path: Path,
    fmt: str,
    floating_base: bool | None,
    stamp: int,
) -> KinematicTables:
    """``name`` keys the cache only: two robots on one file differ in their motors."""
    from motiontool.kinematics._pinocchio.model import build

    loaded = build(path, fmt, floating_base, stamp)
    model, geoms = loaded.model, loaded.geoms
    joints = _joint_arrays(model, motors)
    geom = _geometry_arrays(model, geoms, joints.parent)
    pairs = _pair_arrays(geoms, geom.joint, joints, len(motors))
    joint_center, joint_radius = _joint_spheres(model.njoints, geom)
    for array in (*joints[:6], geom.joint, geom.rotation):
        array.flags.writeable = False
    return KinematicTables(
        joint_parent=joints.parent,
        joint_rotation=joints.rotation,
        joint_translation=joints.translation,
        joint_axis=joints.axis,
        joint_kind=joints.kind,
        joint_motor=joints.motor,
        exact=joints.exact,
        geom_joint=geom.joint,
        geom_rotation=geom.rotation,
        geom_translation=geom.translation,
        geom_radius=geom.radius,
        geom_center=geom.center,
        geom_shape=geom.shape,
        geom_size=geom.size,
        geom_body=geom.body,
        geom_limb=geom.limb,
        pair_first=pairs.first,
        pair_second=pairs.second,
        pair_motors=pairs.motors,
        pair_group=pairs.group,
        group_joints=pairs.group_joints,
        joint_center=joint_center,
        joint_radius=joint_radius,
    )


def _joint_arrays(model: Model, motors: tuple[str, ...]) -> _Joints:
    """The tree: each joint's parent, placement, and motion if it is one of ``motors``."""
    import numpy as np

    nj = model.njoints
    motor_index = {m: i for i, m in enumerate(motors)}
    parent = np.zeros(nj, dtype=np.int64)
    rotation = np.tile(np.eye(3), (nj, 1, 1))
    translation = np.zeros((nj, 3))
    axis = np.zeros((nj, 3))
    kind = np.full(nj, FIXED, dtype=np.int64)
    motor = np.full(nj, -1, dtype=np.int64)
    exact = True
    for jid in range(1, nj):
        joint = model.joints[jid]
        parent[jid] = model.parents[jid]
        placement = model.jointPlacements[jid]
        rotation[jid] = placement.rotation
        translation[jid] = placement.translation
        short = joint.shortname()
        name_j = model.names[jid]
        if short == "JointModelFreeFlyer" or name_j not in motor_index:
            exact = exact and (short == "JointModelFreeFlyer" or joint.nv == 0)
            continue
        motor[jid] = motor_index[name_j]
        kind_j, axis_j = joint_motion(joint, short)
        if kind_j == FIXED:
            exact = False
        kind[jid] = kind_j
        axis[jid] = axis_j
    return _Joints(parent, rotation, translation, axis, kind, motor, exact)


def _geometry_arrays(model: Model, geoms: GeometryModel, parent: npt.NDArray[np.int64]) -> _Geoms:
    """Each collision geometry's joint, placement, shape, bounding sphere, body and limb."""
    import numpy as np

    objects = geoms.geometryObjects
    n_geoms = len(objects)
    bounds = [bounding_sphere(o.geometry) for o in objects]
    shapes = [shape(o.geometry) for o in objects]
    radius = np.array([r for _c, r in bounds], dtype=np.float64).reshape(n_geoms)
    kinds = np.array([k for k, _s in shapes], dtype=np.int64).reshape(n_geoms)
    size = np.array([s for _k, s in shapes], dtype=np.float64).reshape(n_geoms, 3)
    other = kinds == OTHER
    size[other, 0] = radius[other]
    body = tuple(model.frames[o.parentFrame].name for o in objects)
    return _Geoms(
        joint=np.array([o.parentJoint for o in objects], dtype=np.int64).reshape(n_geoms),
        rotation=np.array([o.placement.rotation for o in objects]).reshape(n_geoms, 3, 3),
        translation=np.array([o.placement.translation for o in objects]).reshape(n_geoms, 3),
        radius=radius,
        center=np.array([c for c, _r in bounds], dtype=np.float64).reshape(n_geoms, 3),
        shape=kinds,
        size=size,
        body=body,
        limb=_limbs(model, geoms, body, parent),
    )


def _limbs(
    model: Model,
    geoms: GeometryModel,
    body: tuple[str, ...],
    parent: npt.NDArray[np.int64],
) -> tuple[str, ...]:
    """The body of each geometry, except that a finger's geometry counts as its hand's."""
    joint_body = {
        f.parentJoint: f.name
        for f in reversed(list(model.frames))
        if str(f.type) == "BODY" and str(model.frames[f.parentFrame].type) == "JOINT"
    }
    limbs = []
    for obj, name in zip(geoms.geometryObjects, body, strict=True):
        j = obj.parentJoint
        while j > 0 and _FINGER.search(model.names[j]):
            j = int(parent[j])
        limbs.append(name if j == obj.parentJoint else joint_body.get(j, name))
    return tuple(limbs)


def _pair_arrays(
    geoms: GeometryModel, geom_joint: npt.NDArray[np.int64], joints: _Joints, n_motors: int
) -> _Pairs:
    """The self-collision pairs, the motors that move each, and their (joint, joint) groups."""
    import numpy as np

    pairs = [(p.first, p.second) for p in geoms.collisionPairs]
    first = np.array([a for a, _b in pairs], dtype=np.int64)
    second = np.array([b for _a, b in pairs], dtype=np.int64)
    ancestors = []
    for jid in range(len(joints.parent)):
        chain = set()
        j = jid
        while j != 0:
            chain.add(j)
            j = int(joints.parent[j])
        ancestors.append(chain)
    pair_motors = np.zeros((len(pairs), n_motors), dtype=bool)
    for k, (a, b) in enumerate(pairs):
        for jid in ancestors[int(geom_joint[a])] ^ ancestors[int(geom_joint[b])]:
            if joints.motor[jid] >= 0:
                pair_motors[k, joints.motor[jid]] = True
    keys = np.stack([geom_joint[first], geom_joint[second]], axis=1).reshape(-1, 2)
    group_joints, pair_group = np.unique(keys, axis=0, return_inverse=True)
    return _Pairs(
        first=first,
        second=second,
        motors=pair_motors,
        group=pair_group.reshape(-1).astype(np.int64),
        group_joints=group_joints.astype(np.int64).reshape(-1, 2),
    )


def _joint_spheres(
    nj: int, geom: _Geoms
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """One sphere per joint around all the geometries it carries (centre in the joint frame,
    radius, m): the broad phase over joint pairs comes first."""
    import numpy as np

    local = geom.translation + np.einsum("gij,gj->gi", geom.rotation, geom.center)
    joint_center = np.zeros((nj, 3))
    joint_radius = np.zeros(nj)
    for jid in np.unique(geom.joint):
        on = geom.joint == jid
        lo = (local[on] - geom.radius[on, None]).min(axis=0)
        hi = (local[on] + geom.radius[on, None]).max(axis=0)
        joint_center[jid] = (lo + hi) / 2.0
        joint_radius[jid] = (
            np.linalg.norm(local[on] - joint_center[jid], axis=1) + geom.radius[on]
        ).max()
    return joint_center, joint_radius


def joint_motion(joint: JointModel, short: str) -> tuple[int, tuple[float, float, float]]:
    """(kind, unit axis) of a 1-DoF Pinocchio joint; (FIXED, 0) for anything else."""
    for prefix, kind in (
        ("JointModelRUB", REVOLUTE),
        ("JointModelR", REVOLUTE),
        ("JointModelP", PRISMATIC),
    ):
        rest = short[len(prefix) :]
        if short.startswith(prefix) and rest in _AXES:
            return kind, _AXES[rest]
    unaligned = {
        "JointModelRevoluteUnaligned": REVOLUTE,
        "JointModelRevoluteUnboundedUnaligned": REVOLUTE,
        "JointModelPrismaticUnaligned": PRISMATIC,
    }
    if short in unaligned:
        a = [float(x) for x in joint.extract().axis]
        norm = math.sqrt(sum(x * x for x in a)) or 1.0
        return unaligned[short], (a[0] / norm, a[1] / norm, a[2] / norm)
    return FIXED, (0.0, 0.0, 0.0)
