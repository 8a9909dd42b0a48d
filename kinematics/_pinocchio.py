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
import threading
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal, NamedTuple

from motiontool.kinematics.robots import JointSpec, RobotSpec, unknown_joint_message
from motiontool.motionfmt.errors import MotionToolError

if TYPE_CHECKING:
    import numpy as np
    import pinocchio as pin

__all__ = [
    "Balance",
    "body_positions",
    "build_model",
    "com_and_support",
    "joint_table",
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

    com_xy: np.ndarray
    support_polygon: np.ndarray
    margin_mm: float


# --------------------------------------------------------------------------- model building


def _pin() -> Any:
    import pinocchio

    return pinocchio


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


def body_positions(spec: RobotSpec, q_by_joint: Mapping[str, float]) -> dict[str, np.ndarray]:
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
