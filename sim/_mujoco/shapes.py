"""The collision shapes of a scene's bodies, for a recording."""

from __future__ import annotations

from motiontool.sim._mujoco.api import mj
from motiontool.sim._mujoco.scene import Scene
from motiontool.sim.trace import BodyShapes, Shape


def scene_shapes(scene: Scene) -> list[BodyShapes]:
    """Every body with collision geometry: the robot's (posed every frame) and the scene's."""
    mujoco = mj()

    model = scene.model
    kinds = {
        mujoco.mjtGeom.mjGEOM_PLANE: "plane",
        mujoco.mjtGeom.mjGEOM_SPHERE: "sphere",
        mujoco.mjtGeom.mjGEOM_CAPSULE: "capsule",
        mujoco.mjtGeom.mjGEOM_ELLIPSOID: "ellipsoid",
        mujoco.mjtGeom.mjGEOM_CYLINDER: "cylinder",
        mujoco.mjtGeom.mjGEOM_BOX: "box",
    }
    limb_of = dict(zip(scene.robot_bodies.tolist(), scene.body_limbs, strict=True))
    out = []
    for body in range(model.nbody):
        shapes = []
        for g in range(
            model.body_geomadr[body], model.body_geomadr[body] + model.body_geomnum[body]
        ):
            kind = kinds.get(int(model.geom_type[g]))
            size = [float(v) for v in model.geom_size[g]]
            if kind is None:  # a mesh: its bounding box
                kind = "box"
                aabb = model.geom_aabb[g]
                size = [float(v) for v in aabb[3:]]
            shapes.append(
                Shape(
                    kind=kind,
                    size=(size[0], size[1], size[2]),
                    pos=tuple(float(v) for v in model.geom_pos[g]),  # type: ignore[arg-type]
                    quat=tuple(float(v) for v in model.geom_quat[g]),  # type: ignore[arg-type]
                    name=str(model.geom(g).name),
                )
            )
        if shapes:
            out.append(
                BodyShapes(
                    name=scene.body_name(body) if body else "world",
                    limb=limb_of.get(body, ""),
                    robot=body in limb_of,
                    shapes=tuple(shapes),
                )
            )
    return out
