"""The Pinocchio adapter: the only module that imports pinocchio (lazily, inside functions).

Models are built once per process and cached. Conventions for every function here:

* ``q_by_joint`` maps motor names to positions (rad for hinges, m for slides); motors left out
  stay at 0. Values must be finite.
* Poses are evaluated with a free-flying root (the Nao's torso) at the world origin, upright:
  a quasi-static view in which gravity is along -z of the root frame.
"""

from __future__ import annotations

import functools
import math
import re
import threading
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal, NamedTuple

from motiontool.kinematics.robots import JointSpec, RobotSpec, unknown_joint_message
from motiontool.motionfmt.errors import MotionToolError
from motiontool.motionfmt.extras import require

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt
    import pinocchio as pin

__all__ = [
    "Balance",
    "KinematicTables",
    "body_positions",
    "build_model",
    "com_and_support",
    "configurations",
    "geometry_centers",
    "joint_table",
    "kinematic_tables",
    "pair_signed_distances",
    "self_collision_depths",
    "self_collisions",
    "sole_heights",
]

#: A foot whose lowest point is within this distance (m) of the floor supports the robot.
DEFAULT_CONTACT_TOLERANCE_M = 0.005


class Balance(NamedTuple):
    """Static balance of a pose.

    Attributes:
        com_xy: centre of mass projected on the floor, m, shape (2,) float64 (root frame).
        support_polygon: convex hull of the floor contact points of the supporting feet,
            counter-clockwise, m, shape (K, 2) float64 (K = 1 or 2 for a point or an edge).
        margin_mm: signed distance from ``com_xy`` to the polygon's boundary, mm: positive
            inside (statically stable), negative outside.
    """

    com_xy: npt.NDArray[np.float64]
    support_polygon: npt.NDArray[np.float64]
    margin_mm: float


# --------------------------------------------------------------------------- model building


def _pin() -> Any:
    return require("pinocchio", "kinematics", "collision, balance and URDF/MJCF robot models")


def _load_error(path: Path, exc: Exception) -> MotionToolError:
    first = str(exc).strip().splitlines()
    detail = first[-1] if first else type(exc).__name__
    return MotionToolError(f"cannot load robot model '{path}': {detail}")


@functools.lru_cache(maxsize=32)
def _model(path: Path, fmt: str, floating_base: bool | None, stamp: int) -> pin.Model:
    """Kinematic/dynamic model of a file (``stamp`` = mtime, so an edited file is reloaded)."""
    pin = _pin()
    try:
        if fmt == "urdf":
            if floating_base:
                return pin.buildModelFromUrdf(str(path), pin.JointModelFreeFlyer())
            return pin.buildModelFromUrdf(str(path))
        return pin.buildModelFromMJCF(str(path))
    except (RuntimeError, ValueError, OSError) as exc:
        raise _load_error(path, exc) from exc


def _stamp(path: Path) -> int:
    return path.stat().st_mtime_ns


def joint_table(
    path: Path, fmt: str, floating_base: bool | None
) -> tuple[tuple[JointSpec, ...], bool]:
    """The motors (1-DoF revolute and prismatic joints) of a URDF/MJCF file and their limits.

    Limits come from Pinocchio's ``lowerPositionLimit``, ``upperPositionLimit`` (rad or m;
    ±inf for continuous joints), ``velocityLimit`` (rad/s or m/s) and ``effortLimit``
    (N·m or N). Returns the joints and whether the model's root is free-flying.
    """
    model = _model(path, fmt, floating_base, _stamp(path))
    joints = []
    floating = False
    for jid in range(1, model.njoints):
        joint = model.joints[jid]
        short = joint.shortname()
        if short == "JointModelFreeFlyer":
            floating = True
        if joint.nv != 1:
            continue
        kind: Literal["hinge", "slide"]
        unit: Literal["rad", "m"]
        if short.startswith(("JointModelR", "JointModelRevolute")):
            kind, unit = "hinge", "rad"
        elif short.startswith(("JointModelP", "JointModelPrismatic")):
            kind, unit = "slide", "m"
        else:
            continue
        if joint.nq == 2:  # continuous joint stored as (cos, sin)
            lower, upper = -math.inf, math.inf
        else:
            lower = float(model.lowerPositionLimit[joint.idx_q])
            upper = float(model.upperPositionLimit[joint.idx_q])
        joints.append(
            JointSpec(
                name=model.names[jid],
                lower=lower,
                upper=upper,
                max_velocity=_given(model.velocityLimit[joint.idx_v]),
                max_torque=_given(model.effortLimit[joint.idx_v]),
                kind=kind,
                unit=unit,
            )
        )
    return tuple(joints), floating


def _given(limit: float) -> float:
    """A velocity or effort limit; 0 (what a URDF ``<limit velocity="0">`` or a missing value
    reads as) means 'not given', i.e. unbounded."""
    value = float(limit)
    return value if value > 0 else math.inf


def _package_dirs(path: Path) -> list[str]:
    """Folders that may resolve ``package://`` mesh URIs: the file's folder and its ancestors
    (example-robot-data's ``package://example-robot-data/robots/...`` needs ``share/``)."""
    return [str(path.parent), *(str(p) for p in path.parents[1:6])]


class _Built:
    """A built model, its collision geometry (with the self-collision pairs) and per-thread
    work buffers (creating a GeometryData costs more than a whole collision check)."""

    __slots__ = ("_local", "geoms", "model")

    def __init__(self, model: pin.Model, geoms: pin.GeometryModel) -> None:
        self.model = model
        self.geoms = geoms
        self._local = threading.local()

    def buffers(self) -> tuple[pin.Data, pin.GeometryData]:
        local = self._local
        if not hasattr(local, "data"):
            local.data = self.model.createData()
            local.geom_data = _pin().GeometryData(self.geoms)
        return local.data, local.geom_data


@functools.lru_cache(maxsize=16)
def _build(path: Path, fmt: str, floating_base: bool | None, stamp: int) -> _Built:
    pin = _pin()
    model = _model(path, fmt, floating_base, stamp)
    try:
        if fmt == "urdf":
            geoms = pin.buildGeomFromUrdf(
                model, str(path), pin.COLLISION, package_dirs=_package_dirs(path)
            )
        else:
            geoms = pin.buildGeomFromMJCF(model, str(path), pin.COLLISION)
    except (RuntimeError, ValueError, OSError) as exc:
        raise _load_error(path, exc) from exc
    _add_self_collision_pairs(model, geoms)
    return _Built(model, geoms)


def build_model(spec: RobotSpec) -> tuple[pin.Model, pin.GeometryModel]:
    """Pinocchio model and collision geometry of ``spec``, built once per process.

    The geometry model already holds the self-collision pairs that :func:`self_collisions`
    checks: every pair of geometries on different bodies except (1) adjacent bodies, i.e. a
    body and its parent, where bodies without geometry (the Nao's Hinge2Joint helper frames)
    are skipped so that torso-head and torso-upper-arm count as adjacent, and (2) pairs that
    already touch at the zero pose (all motors at 0), which are part of the design.

    ``nao`` and ``nao-v5`` share one model: the overrides change limits, not kinematics.
    Changing the returned objects changes them for every later caller.
    """
    built = _built(spec)
    return built.model, built.geoms


def _built(spec: RobotSpec) -> _Built:
    floating = spec.floating_base if spec.model_format == "urdf" else None
    return _build(spec.model_path, spec.model_format, floating, _stamp(spec.model_path))


def _add_self_collision_pairs(model: pin.Model, geoms: pin.GeometryModel) -> None:
    pin = _pin()
    objects = geoms.geometryObjects
    with_geometry = {obj.parentJoint for obj in objects}

    def adjacent(a: int, b: int) -> bool:
        for child, parent in ((a, b), (b, a)):
            j = child
            while j != 0:
                j = model.parents[j]
                if j == parent:
                    return True
                if j in with_geometry:
                    break
        return False

    for i in range(len(objects)):
        for k in range(i + 1, len(objects)):
            ja, jb = objects[i].parentJoint, objects[k].parentJoint
            if ja != jb and not adjacent(ja, jb):
                geoms.addCollisionPair(pin.CollisionPair(i, k))
    data = model.createData()
    geom_data = pin.GeometryData(geoms)
    pin.computeCollisions(model, data, geoms, geom_data, pin.neutral(model), False)
    # Copy the indices first: the pair objects are views into a vector that removal shifts.
    touching = [
        (pair.first, pair.second)
        for pair, result in zip(geoms.collisionPairs, geom_data.collisionResults, strict=True)
        if result.isCollision()
    ]
    for first, second in touching:
        geoms.removeCollisionPair(pin.CollisionPair(first, second))


# --------------------------------------------------------------------------- configurations


def _configuration(model: pin.Model, spec: RobotSpec, q_by_joint: Mapping[str, float]) -> Any:
    """Pinocchio configuration vector, shape (nq,) float64, for the named motor positions."""
    pin = _pin()
    q = pin.neutral(model)
    for name, value in q_by_joint.items():
        jid = model.getJointId(name)
        if jid >= model.njoints or name not in spec:
            raise MotionToolError(unknown_joint_message(name, spec))
        value = float(value)
        if not math.isfinite(value):
            raise MotionToolError(f"joint '{name}' of robot {spec.name}: {value} is not a position")
        joint = model.joints[jid]
        if joint.nq == 2:
            q[joint.idx_q : joint.idx_q + 2] = (math.cos(value), math.sin(value))
        else:
            q[joint.idx_q] = value
    return q


def body_positions(
    spec: RobotSpec, q_by_joint: Mapping[str, float]
) -> dict[str, npt.NDArray[np.float64]]:
    """World position (m, shape (3,) float64) of every body frame at the given pose."""
    pin = _pin()
    built = _built(spec)
    model = built.model
    data, _geom_data = built.buffers()
    pin.framesForwardKinematics(model, data, _configuration(model, spec, q_by_joint))
    return {
        frame.name: data.oMf[fid].translation.copy()
        for fid, frame in enumerate(model.frames)
        if frame.type == pin.FrameType.BODY
    }


# --------------------------------------------------------------------------- self-collision


def self_collision_depths(
    spec: RobotSpec, q_by_joint: Mapping[str, float]
) -> dict[tuple[str, str], float]:
    """Penetration depth (m, >= 0) of every pair of bodies in collision at the given pose.

    Keys are (body_a, body_b) with body_a < body_b, named after the bodies (MJCF) or links
    (URDF) holding the geometries; the depth is the deepest over their geometry pairs.
    Adjacent bodies and geometry pairs already touching at the zero pose are never reported
    (see :func:`build_model`).
    """
    pin = _pin()
    built = _built(spec)
    model, geoms = built.model, built.geoms
    data, geom_data = built.buffers()
    q = _configuration(model, spec, q_by_joint)
    if not pin.computeCollisions(model, data, geoms, geom_data, q, False):
        return {}
    objects = geoms.geometryObjects
    depths: dict[tuple[str, str], float] = {}
    for index, result in enumerate(geom_data.collisionResults):
        if not result.isCollision():
            continue
        pair = geoms.collisionPairs[index]
        a = model.frames[objects[pair.first].parentFrame].name
        b = model.frames[objects[pair.second].parentFrame].name
        key = (min(a, b), max(a, b))
        distance = pin.computeDistance(geoms, geom_data, index).min_distance
        depths[key] = max(depths.get(key, 0.0), max(0.0, -float(distance)))
    return dict(sorted(depths.items()))


def self_collisions(
    spec: RobotSpec,
    q_by_joint: Mapping[str, float],
    *,
    penetration_tolerance_m: float = 0.0,
) -> list[tuple[str, str]]:
    """Pairs of bodies whose collision geometries intersect at the given pose.

    Args:
        spec: the robot.
        q_by_joint: motor positions, rad or m (motors left out stay at 0).
        penetration_tolerance_m: report only pairs that penetrate at least this deep (m); 0
            reports every intersection. The Webots bounding primitives are coarse (an arm
            raised beside the head already overlaps it by a few mm), so a lint may want some.

    Returns sorted (body_a, body_b) pairs with body_a < body_b. Adjacent bodies and geometry
    pairs already touching at the zero pose are never reported (see :func:`build_model`).
    """
    return [
        pair
        for pair, depth in self_collision_depths(spec, q_by_joint).items()
        if depth >= penetration_tolerance_m
    ]


# --------------------------------------------------------------------------- balance

_BOX_SIGNS = [[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]


def _foot_corners(spec: RobotSpec, q_by_joint: Mapping[str, float]) -> tuple[Any, dict[str, Any]]:
    """(com (3,), {foot geometry name: its 8 box corners, shape (8, 3)}) in metres."""
    import numpy as np

    pin = _pin()
    if not spec.feet:
        raise MotionToolError(
            f"robot {spec.name} has no feet: the balance check needs a humanoid model with "
            "sole geometries (nao, nao-v5)"
        )
    built = _built(spec)
    model, geoms = built.model, built.geoms
    data, geom_data = built.buffers()
    q = _configuration(model, spec, q_by_joint)
    pin.forwardKinematics(model, data, q)
    pin.updateGeometryPlacements(model, data, geoms, geom_data)
    corners = {}
    for foot in spec.feet:
        gid = geoms.getGeometryId(foot)
        if gid >= len(geoms.geometryObjects):
            raise MotionToolError(f"robot {spec.name}: no collision geometry named '{foot}'")
        half = np.asarray(geoms.geometryObjects[gid].geometry.halfSide, dtype=np.float64)
        placement = geom_data.oMg[gid]
        corners[foot] = (
            np.asarray(_BOX_SIGNS, dtype=np.float64) * half
        ) @ placement.rotation.T + placement.translation
    com = pin.centerOfMass(model, data, q, False)
    return np.asarray(com, dtype=np.float64), corners


def sole_heights(spec: RobotSpec, q_by_joint: Mapping[str, float]) -> dict[str, float]:
    """Lowest point (m, world z, root at the origin) of each foot's sole geometry.

    For the Nao at the zero pose both are -0.3339: the torso origin is 0.3339 m above the floor.
    """
    _com, corners = _foot_corners(spec, q_by_joint)
    return {foot: float(points[:, 2].min()) for foot, points in corners.items()}


def com_and_support(
    spec: RobotSpec,
    q_by_joint: Mapping[str, float],
    *,
    contact_tolerance_m: float = DEFAULT_CONTACT_TOLERANCE_M,
) -> Balance:
    """Centre of mass, support polygon and stability margin of a pose (quasi-static).

    The floor is the lowest sole point at that pose. A foot whose lowest point is within
    ``contact_tolerance_m`` (m) of the floor supports the robot, through its sole corners that
    are within that distance too (a flat foot gives its 4 bottom corners, a tilted one an edge
    or a corner). The root stays upright at the origin (see the module docstring).

    Raises:
        MotionToolError: the robot has no feet (``spec.feet`` empty), or an unknown joint.
    """
    import numpy as np

    com, corners = _foot_corners(spec, q_by_joint)
    floor = min(float(points[:, 2].min()) for points in corners.values())
    contact: list[tuple[float, float]] = []
    for points in corners.values():
        if points[:, 2].min() <= floor + contact_tolerance_m:
            touching = points[points[:, 2] <= floor + contact_tolerance_m]
            contact.extend((float(x), float(y)) for x, y in touching[:, :2])
    hull = _convex_hull(contact)
    com_xy = np.array(com[:2], dtype=np.float64)
    margin_m = _signed_distance((float(com_xy[0]), float(com_xy[1])), hull)
    return Balance(com_xy, np.array(hull, dtype=np.float64).reshape(-1, 2), margin_m * 1000.0)


def _cross(o: Sequence[float], a: Sequence[float], b: Sequence[float]) -> float:
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


def _convex_hull(points: Sequence[tuple[float, float]]) -> list[tuple[float, float]]:
    """Counter-clockwise convex hull (Andrew's monotone chain); collinear points dropped."""
    pts = sorted(set(points))
    if len(pts) <= 2:
        return pts
    lower: list[tuple[float, float]] = []
    for p in pts:
        while len(lower) >= 2 and _cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    upper: list[tuple[float, float]] = []
    for p in reversed(pts):
        while len(upper) >= 2 and _cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return lower[:-1] + upper[:-1]


def _segment_distance(
    p: tuple[float, float], a: tuple[float, float], b: tuple[float, float]
) -> float:
    ax, ay = b[0] - a[0], b[1] - a[1]
    length2 = ax * ax + ay * ay
    t = (
        0.0
        if length2 == 0
        else max(0.0, min(1.0, ((p[0] - a[0]) * ax + (p[1] - a[1]) * ay) / length2))
    )
    return math.hypot(p[0] - (a[0] + t * ax), p[1] - (a[1] + t * ay))


def _signed_distance(p: tuple[float, float], hull: Sequence[tuple[float, float]]) -> float:
    """Distance (m) from ``p`` to the hull's boundary: positive inside, negative outside."""
    if len(hull) == 1:
        return -math.hypot(p[0] - hull[0][0], p[1] - hull[0][1])
    edges = list(zip(hull, [*hull[1:], hull[0]], strict=True))
    distance = min(_segment_distance(p, a, b) for a, b in edges)
    if len(hull) >= 3 and all(_cross(a, b, p) >= 0 for a, b in edges):
        return distance
    return -distance


# --------------------------------------------------------------------------- batched kinematics

#: Joint kinds in :class:`KinematicTables`.
FIXED, REVOLUTE, PRISMATIC = 0, 1, 2
#: Geometry shapes in :class:`KinematicTables`.
OTHER, SPHERE, BOX, CAPSULE, CYLINDER = 0, 1, 2, 3, 4

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
        geom_shape: (G,) int64, :data:`SPHERE`, :data:`BOX`, :data:`CAPSULE`,
            :data:`CYLINDER` (aligned with the geometry's z axis), or :data:`OTHER` (a mesh:
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
    return _tables(spec.name, spec.joint_names, *_built_key(spec))


def _built_key(spec: RobotSpec) -> tuple[Path, str, bool | None, int]:
    floating = spec.floating_base if spec.model_format == "urdf" else None
    return spec.model_path, spec.model_format, floating, _stamp(spec.model_path)


@functools.lru_cache(maxsize=16)
def _tables(
    name: str,
    motors: tuple[str, ...],
    path: Path,
    fmt: str,
    floating_base: bool | None,
    stamp: int,
) -> KinematicTables:
    import numpy as np

    built = _build(path, fmt, floating_base, stamp)
    model, geoms = built.model, built.geoms
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
        kind_j, axis_j = _joint_motion(joint, short)
        if kind_j == FIXED:
            exact = False
        kind[jid] = kind_j
        axis[jid] = axis_j
    objects = geoms.geometryObjects
    n_geoms = len(objects)
    geom_joint = np.array([o.parentJoint for o in objects], dtype=np.int64).reshape(n_geoms)
    geom_rotation = np.array([o.placement.rotation for o in objects]).reshape(n_geoms, 3, 3)
    geom_translation = np.array([o.placement.translation for o in objects]).reshape(n_geoms, 3)
    bounds = [_bounding_sphere(o.geometry) for o in objects]
    geom_center = np.array([c for c, _r in bounds], dtype=np.float64).reshape(n_geoms, 3)
    geom_radius = np.array([r for _c, r in bounds], dtype=np.float64).reshape(n_geoms)
    shapes = [_shape(o.geometry) for o in objects]
    geom_shape = np.array([k for k, _s in shapes], dtype=np.int64).reshape(n_geoms)
    geom_size = np.array([size for _k, size in shapes], dtype=np.float64).reshape(n_geoms, 3)
    other = geom_shape == OTHER
    geom_size[other, 0] = geom_radius[other]
    geom_body = tuple(model.frames[o.parentFrame].name for o in objects)
    joint_body = {
        f.parentJoint: f.name
        for f in reversed(list(model.frames))
        if str(f.type) == "BODY" and str(model.frames[f.parentFrame].type) == "JOINT"
    }
    limbs = []
    for obj, body in zip(objects, geom_body, strict=True):
        j = obj.parentJoint
        while j > 0 and _FINGER.search(model.names[j]):
            j = int(parent[j])
        limbs.append(body if j == obj.parentJoint else joint_body.get(j, body))
    geom_limb = tuple(limbs)
    pairs = [(p.first, p.second) for p in geoms.collisionPairs]
    first = np.array([a for a, _b in pairs], dtype=np.int64)
    second = np.array([b for _a, b in pairs], dtype=np.int64)
    ancestors = []
    for jid in range(nj):
        chain = set()
        j = jid
        while j != 0:
            chain.add(j)
            j = int(parent[j])
        ancestors.append(chain)
    pair_motors = np.zeros((len(pairs), len(motors)), dtype=bool)
    for k, (a, b) in enumerate(pairs):
        for jid in ancestors[int(geom_joint[a])] ^ ancestors[int(geom_joint[b])]:
            if motor[jid] >= 0:
                pair_motors[k, motor[jid]] = True
    # One sphere per joint around all the geometries it carries, and the pairs grouped by
    # their two joints: a broad phase over joint pairs first.
    local = geom_translation + np.einsum("gij,gj->gi", geom_rotation, geom_center)
    joint_center = np.zeros((nj, 3))
    joint_radius = np.zeros(nj)
    for jid in np.unique(geom_joint):
        on = geom_joint == jid
        lo = (local[on] - geom_radius[on, None]).min(axis=0)
        hi = (local[on] + geom_radius[on, None]).max(axis=0)
        joint_center[jid] = (lo + hi) / 2.0
        joint_radius[jid] = (
            np.linalg.norm(local[on] - joint_center[jid], axis=1) + geom_radius[on]
        ).max()
    keys = np.stack([geom_joint[first], geom_joint[second]], axis=1).reshape(-1, 2)
    group_joints, pair_group = np.unique(keys, axis=0, return_inverse=True)
    pair_group = pair_group.reshape(-1).astype(np.int64)
    for array in (parent, rotation, translation, axis, kind, motor, geom_joint, geom_rotation):
        array.flags.writeable = False
    return KinematicTables(
        joint_parent=parent,
        joint_rotation=rotation,
        joint_translation=translation,
        joint_axis=axis,
        joint_kind=kind,
        joint_motor=motor,
        exact=exact,
        geom_joint=geom_joint,
        geom_rotation=geom_rotation,
        geom_translation=geom_translation,
        geom_radius=geom_radius,
        geom_center=geom_center,
        geom_shape=geom_shape,
        geom_size=geom_size,
        geom_body=geom_body,
        geom_limb=geom_limb,
        pair_first=first,
        pair_second=second,
        pair_motors=pair_motors,
        pair_group=pair_group,
        group_joints=group_joints.astype(np.int64).reshape(-1, 2),
        joint_center=joint_center,
        joint_radius=joint_radius,
    )


def _joint_motion(joint: Any, short: str) -> tuple[int, tuple[float, float, float]]:
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


def _shape(geometry: Any) -> tuple[int, tuple[float, float, float]]:
    """(shape code, sizes in m) of a coal geometry, as :class:`KinematicTables` holds them."""
    kind = type(geometry).__name__
    if kind == "Sphere":
        return SPHERE, (float(geometry.radius), 0.0, 0.0)
    if kind == "Box":
        h = geometry.halfSide
        return BOX, (float(h[0]), float(h[1]), float(h[2]))
    if kind in ("Capsule", "Cylinder"):
        code = CAPSULE if kind == "Capsule" else CYLINDER
        return code, (float(geometry.radius), float(geometry.halfLength), 0.0)
    return OTHER, (0.0, 0.0, 0.0)


def _bounding_sphere(geometry: Any) -> tuple[tuple[float, float, float], float]:
    """(centre in the geometry frame, radius), m, of a sphere enclosing a coal geometry."""
    kind = type(geometry).__name__
    origin = (0.0, 0.0, 0.0)
    if kind == "Sphere":
        return origin, float(geometry.radius)
    if kind == "Capsule":
        return origin, float(geometry.radius) + float(geometry.halfLength)
    if kind == "Cylinder":
        return origin, math.hypot(float(geometry.radius), float(geometry.halfLength))
    if kind == "Box":
        return origin, math.sqrt(sum(float(h) ** 2 for h in geometry.halfSide))
    geometry.computeLocalAABB()
    c = geometry.aabb_center
    return (float(c[0]), float(c[1]), float(c[2])), float(geometry.aabb_radius)


def configurations(spec: RobotSpec, q_motors: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """Pinocchio configuration vectors, shape (N, nq) float64, for motor positions
    ``q_motors`` (N, M) float64 in ``spec.joints`` order (rad or m, finite)."""
    import numpy as np

    pin = _pin()
    model = _built(spec).model
    q = np.tile(np.asarray(pin.neutral(model), dtype=np.float64), (q_motors.shape[0], 1))
    for m, joint_spec in enumerate(spec.joints):
        jid = model.getJointId(joint_spec.name)
        if jid >= model.njoints:
            raise MotionToolError(unknown_joint_message(joint_spec.name, spec))
        joint = model.joints[jid]
        if joint.nq == 2:
            q[:, joint.idx_q] = np.cos(q_motors[:, m])
            q[:, joint.idx_q + 1] = np.sin(q_motors[:, m])
        else:
            q[:, joint.idx_q] = q_motors[:, m]
    return q


def geometry_centers(spec: RobotSpec, q_motors: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """World centres (N, G, 3) float64, m, of the geometries' bounding spheres, computed by
    Pinocchio one configuration at a time (for models :class:`KinematicTables` cannot move)."""
    import numpy as np

    pin = _pin()
    built = _built(spec)
    model, geoms = built.model, built.geoms
    data, geom_data = built.buffers()
    tables = kinematic_tables(spec)
    out = np.empty((q_motors.shape[0], len(geoms.geometryObjects), 3))
    for n, q in enumerate(configurations(spec, q_motors)):
        pin.updateGeometryPlacements(model, data, geoms, geom_data, q)
        for g, placement in enumerate(geom_data.oMg):
            out[n, g] = placement.act(tables.geom_center[g])
    return out


def pair_signed_distances(
    spec: RobotSpec,
    q_motors: npt.NDArray[np.float64],
    rows: npt.NDArray[np.int64],
    pairs: npt.NDArray[np.int64],
) -> npt.NDArray[np.float64]:
    """Signed distance (m; negative = penetration depth) of collision pair ``pairs[c]`` at
    configuration ``q_motors[rows[c]]``, shape (C,) float64.

    ``q_motors`` is (N, M) float64 in ``spec.joints`` order; ``rows`` and ``pairs`` are (C,)
    int arrays, ``pairs`` indexing :attr:`KinematicTables.pair_first`. Primitive pairs get
    the exact signed distance (GJK/EPA). Where coal gives no signed distance (intersecting
    meshes read as 0), the depth of the contact its collision test reports is used.
    """
    import numpy as np

    pin = _pin()
    built = _built(spec)
    model, geoms = built.model, built.geoms
    data, geom_data = built.buffers()
    out = np.empty(rows.shape[0], dtype=np.float64)
    if rows.shape[0] == 0:
        return out
    order = np.argsort(rows, kind="stable")
    q_all = configurations(spec, q_motors[np.unique(rows)])
    row_pos = {int(r): i for i, r in enumerate(np.unique(rows))}
    current = -1
    for c in order:
        row = int(rows[c])
        if row != current:
            pin.updateGeometryPlacements(model, data, geoms, geom_data, q_all[row_pos[row]])
            current = row
        k = int(pairs[c])
        distance = float(pin.computeDistance(geoms, geom_data, k).min_distance)
        if distance == 0.0 and pin.computeCollision(geoms, geom_data, k):  # meshes
            result = geom_data.collisionResults[k]
            depths = [
                float(result.getContact(i).penetration_depth) for i in range(result.numContacts())
            ]
            distance = min(distance, *(-abs(d) for d in depths)) if depths else distance
        out[c] = distance
    return out
