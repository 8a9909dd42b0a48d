"""Loading a robot file into Pinocchio: the model, its motors and limits, its collision geometry
with the self-collision pairs, cached once per process (per file version)."""

from __future__ import annotations

import functools
import math
import threading
import warnings
from pathlib import Path
from typing import Literal

from motiontool.errors import MotionToolError
from motiontool.kinematics._pinocchio.api import (
    Data,
    GeometryData,
    GeometryModel,
    Model,
    pin_module,
)
from motiontool.kinematics.robots import JointSpec, RobotSpec

__all__ = ["Built", "build", "build_model", "built", "joint_table", "model_key"]


def _load_error(path: Path, exc: Exception) -> MotionToolError:
    first = str(exc).strip().splitlines()
    detail = first[-1] if first else type(exc).__name__
    return MotionToolError(f"cannot load robot model '{path}': {detail}")


@functools.lru_cache(maxsize=32)
def _model(path: Path, fmt: str, floating_base: bool | None, stamp: int) -> Model:
    """Kinematic/dynamic model of a file (``stamp`` = mtime, so an edited file is reloaded)."""
    pin = pin_module()
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


class Built:
    """A built model, its collision geometry (with the self-collision pairs) and per-thread
    work buffers (creating a GeometryData costs more than a whole collision check).

    The buffers' GJK starts from coal's default guess every time, not from the last answer
    (Pinocchio's default): with a cached guess a distance depends on what was computed before
    it, by up to 1e-6 m, so that the deepest of two near-equal overlaps, and the text of a
    finding, changed between two checks of one file in one process."""

    __slots__ = ("_local", "geoms", "model")

    def __init__(self, model: Model, geoms: GeometryModel) -> None:
        self.model = model
        self.geoms = geoms
        self._local = threading.local()

    def buffers(self) -> tuple[Data, GeometryData]:
        found: tuple[Data, GeometryData] | None = getattr(self._local, "buffers", None)
        if found is None:
            geom_data = pin_module().GeometryData(self.geoms)
            with warnings.catch_warnings():  # coal marks the flag deprecated; it still decides
                warnings.simplefilter("ignore", DeprecationWarning)
                for request in (*geom_data.distanceRequests, *geom_data.collisionRequests):
                    request.enable_cached_gjk_guess = False
            found = (self.model.createData(), geom_data)
            self._local.buffers = found
        return found


@functools.lru_cache(maxsize=16)
def build(path: Path, fmt: str, floating_base: bool | None, stamp: int) -> Built:
    pin = pin_module()
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
    return Built(model, geoms)


def build_model(spec: RobotSpec) -> tuple[Model, GeometryModel]:
    """Pinocchio model and collision geometry of ``spec``, built once per process.

    The geometry model already holds the self-collision pairs that :func:`self_collisions`
    checks: every pair of geometries on different bodies except (1) adjacent bodies, i.e. a
    body and its parent, where bodies without geometry (the Nao's Hinge2Joint helper frames)
    are skipped so that torso-head and torso-upper-arm count as adjacent, and (2) pairs that
    already touch at the zero pose (all motors at 0), which are part of the design.

    ``nao`` and ``nao-v5`` share one model: the overrides change limits, not kinematics.
    Changing the returned objects changes them for every later caller.
    """
    loaded = built(spec)
    return loaded.model, loaded.geoms


def built(spec: RobotSpec) -> Built:
    """The cached :class:`Built` of ``spec``'s model file."""
    return build(*model_key(spec))


def model_key(spec: RobotSpec) -> tuple[Path, str, bool | None, int]:
    """What a model is cached by: its file, format, free-flyer choice and modification time."""
    floating = spec.floating_base if spec.model_format == "urdf" else None
    return spec.model_path, spec.model_format, floating, _stamp(spec.model_path)


def _add_self_collision_pairs(model: Model, geoms: GeometryModel) -> None:
    pin = pin_module()
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
