"""Building the scene (:func:`build_scene`) with :class:`mujoco.MjSpec` from the robot's model
file: the simulation options, a floor and a light, the box under a fixed-base robot, and the
Webots-like motors (see the package docstring)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from motiontool.errors import MotionToolError
from motiontool.motionfmt.units import MS_PER_S
from motiontool.sim._mujoco.api import mj
from motiontool.sim._mujoco.probe import (
    collide_self,
    self_collides,
    self_collision_pairs,
    self_collision_probe,
)
from motiontool.sim._mujoco.scene import GeomClass, Scene
from motiontool.sim._mujoco.start import set_start_state
from motiontool.sim._mujoco.topology import in_subtree, limbs, tool_frame
from motiontool.sim.motor import DEFAULT_P_GAIN, MotorLimits
from motiontool.sim.physics import substeps_at_most
from motiontool.sim.start import StartState

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.kinematics.robots import RobotSpec
    from motiontool.sim._mujoco.api import MjModel, MjsBody, MjSpec
    from motiontool.sim.world_run import Ground


FALLBACK_MAX_VELOCITY = 10.0
"""maxVelocity, rad/s (m/s), of a motor whose model gives none (or not a positive number)."""


FALLBACK_MAX_TORQUE = 10.0
"""maxTorque, N·m (N), of a motor whose model gives none (or not a positive number)."""


DRIVER_PREFIX = "motiontool_driver_"
"""Name of the driver body and hinge of motor ``k``: this prefix and ``k``."""


DRIVER_ARMATURE = 1e6
"""Armature of each driver hinge, kg·m²: a motor torque of 15 N·m changes its speed by
3e-8 rad/s per 2 ms step, and its speed is set again every control step."""


DRIVER_MASS_KG = 1e-3
"""Mass of each driver body, kg (its armature, not its mass, keeps its speed)."""


DRIVER_INERTIA_KG_M2 = 1e-6
"""Principal inertias of each driver body, kg·m²."""


MOTOR_SOLIMP = (0.99, 0.99, 0.001, 0.5, 2.0)
"""solimp of the motor constraints: nearly hard, as ODE's joint motors."""


MOTOR_TIMECONST_STEPS = 2.0
"""Time constant of the motor constraints, in physics steps (MuJoCo's smallest stable value)."""


FLOOR_GRID_M = 0.05
"""Grid spacing of the (infinite) floor plane, m: drawing only."""


FLOOR_SPIN_ROLL_FRICTION = (0.005, 0.0001)
"""Torsional (m) and rolling (m) friction of the floor contacts: MuJoCo's defaults."""


LIGHT_HEIGHT_M = 4.0
"""Height of the light above the floor, m: drawing only."""


FLOOR_BOUNCE = 0.3
"""Restitution of robot-floor contacts (Webots ``nao_demo.wbt`` / ``nao_robocup.wbt``
contactProperties bounce 0.3), realised as the damping ratio of MuJoCo's contact spring (the
walks are insensitive to it, measured). Webots' bounceVelocity (3 mm/s) has no MuJoCo equivalent."""


WORLD_DAMPING_RATIO = 1.0
"""Damping ratio of the contacts with a world's supports: critical (MuJoCo's default), not one
made of the world's ``bounce``. ODE (Webots) reverses only impacts faster than ``bounceVelocity``
(0.01 m/s by default), once, and its resting contacts are overdamped (``softERP`` 0.2,
``softCFM`` 0.001); a MuJoCo damping ratio acts on every contact at every step: at the 0.22 of
Webots' default bounce 0.5 the standing feet ring on the wrestling ring, HandWave's feet creep
8 mm in 61 s and SideStepRightLoop falls (docs/simulation.md, *Contact damping in a world*)."""


FLOOR_TIMECONST_S = 0.02
"""Time constant of the floor contacts, s (MuJoCo's default; 0.005 to 0.05 walk the same)."""


SOLVER_TOLERANCE = 1e-10
"""Newton solver tolerance. At MuJoCo's default (1e-8) the solver stops before the contact and
motor forces balance: a Nao standing still jitters and its feet wander 2 mm in 6 s; at 1e-10
they stay within 0.05 mm, at no extra cost (measured)."""


BOX_HEIGHT_M = 0.6
"""Edge of the wooden box a fixed-base robot stands on, m (Webots ``WoodenBox`` default size)."""


def build_scene(
    robot: RobotSpec,
    control_step_ms: int,
    *,
    physics_step_ms: float = 2.0,
    start: StartState = StartState.STANDING,
    start_joints: dict[str, float] | None = None,
    floor_friction: float = 1.0,
    mass_scale: float = 1.0,
    torque_scale: float = 1.0,
    start_yaw_deg: float = 0.0,
    p_gain: float = DEFAULT_P_GAIN,
    ground: Sequence[Ground] = (),
    gravity: tuple[float, float, float] | None = None,
    start_xy: tuple[float, float] = (0.0, 0.0),
    self_collision: bool | None = None,
) -> Scene:
    """Compile the scene of ``robot`` at its start state.

    Args:
        robot: the robot (its ``model_path`` is read with :meth:`mujoco.MjSpec.from_file`).
        control_step_ms: the control period (Webots' basicTimeStep), ms.
        physics_step_ms: the largest MuJoCo step, ms; the step used divides the control step.
        start: the start state (lying: free-flying robots only).
        start_joints: initial motor positions, rad (m), overriding the zero pose.
        floor_friction: Coulomb friction coefficient between the robot and the floor (pyramidal
            cone); 1.0 walks (docs/simulation.md; Webots' coulombFriction 7 makes MuJoCo's
            pyramidal cone grip so hard that every walk falls).
        mass_scale: factor on every robot body's mass and inertia.
        torque_scale: factor on every motor's maxTorque.
        start_yaw_deg: heading of the robot at start, degrees about +z.
        p_gain: P gain of the position controller, 1/s.
        ground: what the robot stands on, from a Webots world
            (:func:`motiontool.sim.world_run.world_run`); empty: a floor plane at z = 0 with
            ``floor_friction``. Each keeps its own friction; their contacts are critically damped.
        gravity: m/s², z up (None: MuJoCo's default, -9.81 m/s² on z).
        start_xy: where a free-flying robot starts, m.
        self_collision: whether the robot's parts collide with each other (Webots'
            ``selfCollision``, by its rule: :func:`~motiontool.sim._mujoco.probe.
            self_collision_pairs`); None: as the robot's model has it (the Nao's: no, the
            UR5e's: yes). :attr:`Scene.self_collision` says which.
    """
    substeps = substeps_at_most(control_step_ms, physics_step_ms)
    dt = control_step_ms / MS_PER_S / substeps
    spec = _load_spec(robot, dt)
    roots, floating = _robot_roots(spec, robot)
    _scale_masses(spec, mass_scale)
    _add_surroundings(spec, roots, floating, ground, floor_friction, gravity)
    limits = _motor_limits(robot, torque_scale, p_gain)
    _add_motors(spec, robot.joint_names, limits.max_torque, dt)
    scene = _compiled_scene(spec, robot, limits, substeps, roots, floating, self_collision)
    set_start_state(scene, StartState(start), start_joints or {}, start_yaw_deg, start_xy)
    scene.tool = None if floating else tool_frame(scene.model, scene.root_body, scene.robot_bodies)
    return scene


def _add_surroundings(
    spec: MjSpec,
    roots: Sequence[MjsBody],
    floating: bool,
    ground: Sequence[Ground],
    floor_friction: float,
    gravity: tuple[float, float, float] | None,
) -> None:
    """The world around the robot (see :func:`build_scene` for the arguments): gravity, the
    floor plane (or a world's ground) and the light, and the box under a fixed-base robot."""
    if gravity is not None:
        spec.option.gravity = list(gravity)
    if not any(g.kind == "plane" for g in ground):
        _add_floor(spec, floor_friction)  # and the light
    else:
        spec.worldbody.add_light(name="sun", pos=[0.0, 0.0, LIGHT_HEIGHT_M], dir=[0.0, 0.0, -1.0])
    _add_ground(spec, ground)
    if not floating:
        _add_box(spec, roots)


def _compiled_scene(
    spec: MjSpec,
    robot: RobotSpec,
    limits: MotorLimits,
    substeps: int,
    roots: Sequence[MjsBody],
    floating: bool,
    self_collision: bool | None,
) -> Scene:
    """The scene of ``spec`` compiled, at the zero pose: self-collision as ``self_collision``
    asks (None: as the model has it; recompiled otherwise), with the probe of the self-collision
    pairs of the model as designed (see :func:`build_scene`)."""
    model = _compile_as_designed(spec, robot)
    scene = _scene(model, robot, limits, substeps, roots, floating)
    pairs = self_collision_pairs(spec, model, scene)
    probe = self_collision_probe(spec, model, pairs)
    if self_collision is not None:
        collide_self(spec, model, scene, pairs, self_collision)
        model = _compile(spec, robot)
        scene = _scene(model, robot, limits, substeps, roots, floating)
    scene.self_collision = self_collides(model, scene)
    scene.touch_fails = self_collision is None  # the model's own: see Scene.touch_fails
    scene.probe = probe
    return scene


def _load_spec(robot: RobotSpec, dt: float) -> MjSpec:
    """The robot's model as an :class:`mujoco.MjSpec`, with the simulation options, no actuators
    (the motors are modelled by :func:`_add_motors`) and a physics step of ``dt`` s."""
    mujoco = mj()
    try:
        spec = mujoco.MjSpec.from_file(str(robot.model_path))
    except ValueError as exc:  # MuJoCo's parse errors carry its own message
        raise MotionToolError(f"MuJoCo cannot read '{robot.model_path}': {exc}") from exc
    _resolve_package_meshes(spec, robot.model_path)
    spec.option.timestep = dt
    spec.option.jacobian = mujoco.mjtJacobian.mjJAC_DENSE  # sparse diverged: docs/simulation.md
    spec.option.cone = mujoco.mjtCone.mjCONE_PYRAMIDAL
    spec.option.tolerance = SOLVER_TOLERANCE
    spec.compiler.balanceinertia = True
    spec.compiler.fusestatic = False  # MuJoCo's URDF import would fuse a fixed base away
    for actuator in list(spec.actuators):
        spec.delete(actuator)
    return spec


def _robot_roots(spec: MjSpec, robot: RobotSpec) -> tuple[list[MjsBody], bool]:
    """The robot's top bodies, and whether it is free-flying (a URDF of a free-flying robot
    gets its free joint here)."""
    mujoco = mj()
    joint_specs = {j.name for j in spec.joints}
    missing = [n for n in robot.joint_names if n not in joint_specs]
    if missing:
        raise MotionToolError(
            f"MuJoCo model of robot {robot.name} has no joint named {', '.join(missing)}"
        )
    roots = list(spec.worldbody.bodies)
    if not roots:
        raise MotionToolError(f"robot model '{robot.model_path}' has no body")
    floating = any(j.type == mujoco.mjtJoint.mjJNT_FREE for j in roots[0].joints)
    if robot.floating_base and not floating and len(roots) == 1:  # a URDF: no free joint
        roots[0].add_freejoint()
        floating = True
    return roots, floating


def _scale_masses(spec: MjSpec, mass_scale: float) -> None:
    """Every body's mass and inertia times ``mass_scale``."""
    if mass_scale == 1.0:
        return
    for body in spec.bodies:
        if body.name != "world":
            body.mass = body.mass * mass_scale
            body.fullinertia = [v * mass_scale for v in body.fullinertia]
            body.inertia = [v * mass_scale for v in body.inertia]


def _add_floor(spec: MjSpec, friction: float) -> None:
    """The floor plane (its friction and contact softness win over the robot's geoms) and a
    light."""
    mujoco = mj()
    floor = spec.worldbody.add_geom(
        name="floor",
        type=mujoco.mjtGeom.mjGEOM_PLANE,
        size=[0.0, 0.0, FLOOR_GRID_M],
        rgba=[0.6, 0.6, 0.6, 1.0],
    )
    floor.friction = [friction, *FLOOR_SPIN_ROLL_FRICTION]
    floor.priority = 1  # its friction and solref win over the robot geoms' defaults
    floor.solref = [FLOOR_TIMECONST_S, _damping_ratio(FLOOR_BOUNCE)]
    floor.contype = 1
    floor.conaffinity = 1
    spec.worldbody.add_light(name="sun", pos=[0.0, 0.0, LIGHT_HEIGHT_M], dir=[0.0, 0.0, -1.0])


def _add_ground(spec: MjSpec, ground: Sequence[Ground]) -> None:
    """The supports of a world: planes and boxes whose friction and critically damped contacts
    win over the robot's (the first plane is the ``floor`` geom)."""
    mujoco = mj()
    kinds = {"plane": mujoco.mjtGeom.mjGEOM_PLANE, "box": mujoco.mjtGeom.mjGEOM_BOX}
    for g in ground:
        if g.kind == "plane":  # MuJoCo's planes are unbounded where a size is 0
            size = [g.size[0] / 2, g.size[1] / 2, FLOOR_GRID_M]
        else:
            size = [g.size[0] / 2, g.size[1] / 2, g.size[2] / 2]
        geom = spec.worldbody.add_geom(
            name=g.name,
            type=kinds[g.kind],
            size=size,
            pos=list(g.center),
            quat=[math.cos(g.yaw_rad / 2), 0.0, 0.0, math.sin(g.yaw_rad / 2)],
            rgba=[0.6, 0.6, 0.6, 1.0] if g.kind == "plane" else [0.8, 0.75, 0.65, 1.0],
        )
        geom.friction = [g.friction, *FLOOR_SPIN_ROLL_FRICTION]
        geom.priority = 1
        geom.solref = [FLOOR_TIMECONST_S, WORLD_DAMPING_RATIO]
        geom.contype = 1
        geom.conaffinity = 1


def _add_box(spec: MjSpec, roots: Sequence[MjsBody]) -> None:
    """The wooden box a fixed-base robot stands on; the robot moved onto its top face."""
    mujoco = mj()
    half = BOX_HEIGHT_M / 2
    box = spec.worldbody.add_geom(
        name="wooden_box",
        type=mujoco.mjtGeom.mjGEOM_BOX,
        size=[half, half, half],
        pos=[0.0, 0.0, half],
        rgba=[0.63, 0.45, 0.25, 1.0],
    )
    box.contype = 1
    box.conaffinity = 1
    for body in roots:
        body.pos = [body.pos[0], body.pos[1], body.pos[2] + BOX_HEIGHT_M]


def _motor_limits(robot: RobotSpec, torque_scale: float, p_gain: float) -> MotorLimits:
    """The motors' limits; a maxVelocity or maxTorque that is not a positive number is
    :data:`FALLBACK_MAX_VELOCITY` / :data:`FALLBACK_MAX_TORQUE`."""
    import numpy as np

    joints = [robot.joint(n) for n in robot.joint_names]
    return MotorLimits(
        np.array([j.lower for j in joints], dtype=np.float64),
        np.array([j.upper for j in joints], dtype=np.float64),
        np.array([_positive(j.max_velocity, FALLBACK_MAX_VELOCITY) for j in joints]),
        np.array([_positive(j.max_torque, FALLBACK_MAX_TORQUE) for j in joints]) * torque_scale,
        p_gain,
    )


def _add_motors(
    spec: MjSpec, motors: Sequence[str], max_torque: npt.NDArray[np.float64], dt: float
) -> None:
    """Free the motor joints (no hard stops) and couple each to its driver hinge through a
    tendon whose friction loss is the motor's maxTorque (see the module docstring)."""
    mujoco = mj()
    joint_specs = {j.name: j for j in spec.joints}
    for name in motors:
        joint = joint_specs[name]
        joint.limited = mujoco.mjtLimited.mjLIMITED_FALSE
        joint.actfrclimited = mujoco.mjtLimited.mjLIMITED_FALSE
    for k, name in enumerate(motors):
        driver = spec.worldbody.add_body(name=f"{DRIVER_PREFIX}{k}", mass=DRIVER_MASS_KG)
        driver.inertia = [DRIVER_INERTIA_KG_M2] * 3
        driver.explicitinertial = True
        driver.add_joint(
            name=f"{DRIVER_PREFIX}{k}",
            type=mujoco.mjtJoint.mjJNT_HINGE,
            axis=[0.0, 0.0, 1.0],
            armature=DRIVER_ARMATURE,
        )
        tendon = spec.add_tendon(name=f"motiontool_motor_{k}")
        tendon.wrap_joint(name, 1.0)
        tendon.wrap_joint(f"{DRIVER_PREFIX}{k}", -1.0)
        tendon.frictionloss = float(max_torque[k])
        tendon.solref_friction = [MOTOR_TIMECONST_STEPS * dt, 1.0]
        tendon.solimp_friction = list(MOTOR_SOLIMP)


def _compile_as_designed(spec: MjSpec, robot: RobotSpec) -> MjModel:
    """The compiled model, where robot bodies whose geometries already touch in the zero pose
    (a URDF's links, which MuJoCo collides by default) are part of the design: they never
    collide (``spec`` gets the exclusions)."""
    mujoco = mj()
    model = _compile(spec, robot)
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    mujoco.mj_collision(model, data)
    designed = {
        tuple(sorted((int(model.geom_bodyid[a]), int(model.geom_bodyid[b]))))
        for a, b in data.contact.geom.tolist()
    }
    designed = {p for p in designed if 0 not in p and p[0] != p[1]}
    if not designed:
        return model
    for a, b in sorted(designed):
        spec.add_exclude(bodyname1=model.body(a).name, bodyname2=model.body(b).name)
    return _compile(spec, robot)


def _scene(
    model: MjModel,
    robot: RobotSpec,
    limits: MotorLimits,
    substeps: int,
    roots: Sequence[MjsBody],
    floating: bool,
) -> Scene:
    """The scene of ``model`` (fresh data, at the zero pose) and its indices."""
    mujoco = mj()
    import numpy as np

    motors = robot.joint_names
    root_ids = {int(model.body(r.name).id) for r in roots}
    root_body = int(model.body(roots[0].name).id)
    bodies = [b for b in range(1, model.nbody) if in_subtree(model, b, root_ids)]
    robot_bodies = np.array(bodies, dtype=np.intp)
    joint_limbs, body_limbs = limbs(model, motors, root_body, robot_bodies)
    feet = np.array([model.geom(f).id for f in robot.feet], dtype=np.intp)
    return Scene(
        model=model,
        data=mujoco.MjData(model),
        robot=robot,
        joints=motors,
        limits=limits,
        qpos_adr=np.array([model.jnt_qposadr[model.joint(n).id] for n in motors], dtype=np.intp),
        driver_dof=np.array(
            [model.jnt_dofadr[model.joint(f"{DRIVER_PREFIX}{k}").id] for k in range(len(motors))],
            dtype=np.intp,
        ),
        control_substeps=substeps,
        root_body=root_body,
        floating=floating,
        robot_bodies=robot_bodies,
        body_limbs=body_limbs,
        joint_limbs=joint_limbs,
        geom_class=_geom_classes(model, set(bodies), feet),
        foot_geoms=feet,
    )


def _geom_classes(
    model: MjModel, robot_bodies: set[int], feet: npt.NDArray[np.intp]
) -> npt.NDArray[np.intp]:
    """The :class:`GeomClass` of every geom of ``model``."""
    import numpy as np

    classes = np.full(model.ngeom, GeomClass.SCENE, dtype=np.intp)
    for g in range(model.ngeom):
        if model.geom_bodyid[g] in robot_bodies:
            classes[g] = GeomClass.ROBOT
    for g in range(model.ngeom):  # the floor, and a world's other supports (floor:NAME)
        name = str(model.geom(g).name)
        if name == "floor" or name.startswith("floor:"):
            classes[g] = GeomClass.FLOOR
    classes[feet] = GeomClass.FOOT
    return classes


def _compile(spec: MjSpec, robot: RobotSpec) -> MjModel:
    try:
        return spec.compile()
    except ValueError as exc:  # MuJoCo's compile errors carry its own message
        raise MotionToolError(f"MuJoCo cannot compile the scene of {robot.name}: {exc}") from exc


def _resolve_package_meshes(spec: MjSpec, model_path: Path) -> None:
    """Point ``package://<pkg>/<path>`` mesh files of a URDF at the files: ``<dir>/<pkg>/<path>``
    for the first folder above the model that has it (as ROS' share/ layout)."""
    for mesh in spec.meshes:
        name = str(mesh.file)
        if not name.startswith("package://"):
            continue
        relative = name[len("package://") :]
        for folder in model_path.resolve().parents:
            if (folder / relative).is_file():
                mesh.file = str(folder / relative)
                break


def _damping_ratio(restitution: float) -> float:
    """Damping ratio of a spring-damper contact whose coefficient of restitution is the given
    one: ``e = exp(-pi z / sqrt(1 - z^2))``, so ``z = -ln e / sqrt(pi^2 + ln^2 e)`` (1, critical
    damping, for no bounce)."""
    if restitution <= 0:
        return 1.0
    log_e = math.log(restitution)
    return -log_e / math.sqrt(math.pi**2 + log_e**2)


def _positive(value: float, fallback: float) -> float:
    """``value`` if it is a positive number, else ``fallback``."""
    return value if math.isfinite(value) and value > 0 else fallback
