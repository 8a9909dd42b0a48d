"""The start state of a scene: the motors at their start positions; a free-flying robot turned
by the start yaw, laid face down or up if asked, its lowest point just above the floor."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

from motiontool.errors import MotionToolError
from motiontool.sim._mujoco.api import mj
from motiontool.sim._mujoco.scene import Scene
from motiontool.sim.start import StartState

if TYPE_CHECKING:
    from motiontool.sim._mujoco.api import MjData, MjModel


SPAWN_CLEARANCE_M = 1e-4
"""Gap between a free-flying robot's lowest point and the floor at spawn, m (the Webots Nao PROTO
spawns its torso at 0.334 m, its FSR soles being 0.3339 m below the torso origin)."""


def set_start_state(
    scene: Scene,
    start: StartState,
    start_joints: dict[str, float],
    start_yaw_deg: float,
    start_xy: tuple[float, float] = (0.0, 0.0),
) -> None:
    """Put ``scene.data`` at the start state: the motors at ``start_joints``; a free-flying
    robot at ``start_xy`` (m), turned by the yaw, laid down if asked, its lowest point
    :data:`SPAWN_CLEARANCE_M` above the floor."""
    mujoco = mj()
    model, data = scene.model, scene.data
    for name, value in start_joints.items():
        if name in scene.joints:
            data.qpos[scene.qpos_adr[scene.joints.index(name)]] = value
    if scene.floating:
        _place_free_robot(scene, start, start_yaw_deg, start_xy)
    elif start.lying:
        raise MotionToolError(
            f"start {start} needs a free-flying robot; {scene.robot.name} is fixed"
        )
    elif start_yaw_deg:
        raise MotionToolError("a start yaw needs a free-flying robot")
    elif start_xy != (0.0, 0.0):
        raise MotionToolError("a start position needs a free-flying robot")
    mujoco.mj_forward(model, data)


def _place_free_robot(
    scene: Scene, start: StartState, start_yaw_deg: float, start_xy: tuple[float, float]
) -> None:
    """Orient the free joint (yaw, then lying face down or up) and lower the robot onto the
    floor."""
    mujoco = mj()
    model, data = scene.model, scene.data
    free_adr = int(model.jnt_qposadr[model.body_jntadr[scene.root_body]])
    quat = _quat_about_z(math.radians(start_yaw_deg))
    if start is StartState.LYING_FRONT:  # face down: the torso's x axis points to the floor
        quat = _quat_mul(quat, (math.cos(math.pi / 4), 0.0, math.sin(math.pi / 4), 0.0))
    elif start is StartState.LYING_BACK:  # face up: the torso's x axis points to the sky
        quat = _quat_mul(quat, (math.cos(math.pi / 4), 0.0, -math.sin(math.pi / 4), 0.0))
    data.qpos[free_adr : free_adr + 2] = start_xy
    data.qpos[free_adr + 3 : free_adr + 7] = quat
    mujoco.mj_kinematics(model, data)
    in_robot = set(scene.robot_bodies.tolist())
    robot_geoms = [g for g in range(model.ngeom) if model.geom_bodyid[g] in in_robot]
    lowest = lowest_point(model, data, robot_geoms)
    data.qpos[free_adr + 2] += SPAWN_CLEARANCE_M - lowest


def lowest_point(model: MjModel, data: MjData, geoms: Sequence[int]) -> float:
    """Lowest z (m) of the given geoms (exact for primitives, bounding box otherwise)."""
    mujoco = mj()

    lowest = math.inf
    for g in geoms:
        kind = int(model.geom_type[g])
        size = model.geom_size[g]
        rot = data.geom_xmat[g].reshape(3, 3)
        z = float(data.geom_xpos[g][2])
        if kind == mujoco.mjtGeom.mjGEOM_SPHERE:
            low = z - size[0]
        elif kind == mujoco.mjtGeom.mjGEOM_CAPSULE:
            low = z - abs(rot[2, 2]) * size[1] - size[0]
        elif kind == mujoco.mjtGeom.mjGEOM_CYLINDER:
            low = z - abs(rot[2, 2]) * size[1] - size[0] * math.sqrt(max(0.0, 1 - rot[2, 2] ** 2))
        else:  # box, ellipsoid (bounding box), mesh: the oriented bounding box
            aabb = model.geom_aabb[g]
            centre = data.geom_xpos[g] + rot @ aabb[:3]
            low = float(centre[2]) - float(sum(abs(rot[2, i]) * aabb[3 + i] for i in range(3)))
        lowest = min(lowest, float(low))
    return lowest


def _quat_about_z(angle: float) -> tuple[float, float, float, float]:
    return (math.cos(angle / 2), 0.0, 0.0, math.sin(angle / 2))


def _quat_mul(a: Sequence[float], b: Sequence[float]) -> tuple[float, float, float, float]:
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return (
        aw * bw - ax * bx - ay * by - az * bz,
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
    )
