"""The MuJoCo side of ``play``: the scene, Webots-like motors, and the stepping loop.

The only module that imports :mod:`mujoco` (lazily, inside functions).

Scene (built with :class:`mujoco.MjSpec` from the robot's model file): a floor plane, a light and
the robot. A free-flying robot (the Nao) stands in its zero pose with its lowest point
:data:`SPAWN_CLEARANCE_M` above the floor (the Nao's torso then sits at 0.334 m, the Webots PROTO
spawn height); ``lying-front`` lays it face down instead, ``lying-back`` face up. A fixed-base
robot (the UR5e) stands on a 0.6 m wooden box, its base on the top face, as in Webots'
``ure.wbt``.

Motors (see :mod:`motiontool.sim.motor` for the control law): Webots hands the P controller's
velocity command to an ODE joint motor, i.e. a velocity constraint whose force is bounded by
maxTorque, solved together with the contacts. MuJoCo has no such motor, so each motor joint is
coupled through a fixed tendon ``q_joint - q_driver`` to an extra *driver* hinge (on a body of its
own, with a huge armature so that the tendon force does not slow it down), whose velocity is set
to the command every control step; the tendon's ``frictionloss`` = maxTorque turns it into a
velocity constraint ``dq_joint/dt = command`` with a force bounded by maxTorque, solved with the
contacts. Plain ``<velocity>`` actuators with a force range chatter once the torque saturates and
make the walks fall (``docs/simulation.md``). Joint ranges are not hard stops (Webots' PROTOs
have none): targets are clipped, the joints themselves are free.
"""

from __future__ import annotations

import enum
import math
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

from motiontool.motionfmt.errors import MotionToolError
from motiontool.motionfmt.extras import require
from motiontool.sim.motor import MotorLimits, velocity_command
from motiontool.sim.trace import BodyShapes, ContactEvent, Shape, Trace

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.kinematics.robots import RobotSpec

__all__ = [
    "BOX_HEIGHT_M",
    "FALLBACK_MAX_TORQUE",
    "FALLBACK_MAX_VELOCITY",
    "SPAWN_CLEARANCE_M",
    "TOOL_SITE_PATTERN",
    "GeomClass",
    "Scene",
    "build_scene",
    "mujoco_version",
    "run",
    "scene_shapes",
    "tool_poses",
]

Start = Literal["standing", "lying-front", "lying-back"]

SPAWN_CLEARANCE_M = 1e-4
"""Gap between a free-flying robot's lowest point and the floor at spawn, m (the Webots Nao PROTO
spawns its torso at 0.334 m, its FSR soles being 0.3339 m below the torso origin)."""

BOX_HEIGHT_M = 0.6
"""Edge of the wooden box a fixed-base robot stands on, m (Webots ``WoodenBox`` default size)."""

MS_PER_S = 1000.0
"""Milliseconds in a second."""

STEP_RATIO_SLACK = 1e-9
"""Rounding slack when dividing the control step by the physics step: a 20 ms step over 2 ms is
10 substeps even where the float quotient comes out a hair above 10."""

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

FLOOR_TIMECONST_S = 0.02
"""Time constant of the floor contacts, s (MuJoCo's default; 0.005 to 0.05 walk the same)."""

SOLVER_TOLERANCE = 1e-10
"""Newton solver tolerance. At MuJoCo's default (1e-8) the solver stops before the contact and
motor forces balance: a Nao standing still jitters and its feet wander 2 mm in 6 s; at 1e-10
they stay within 0.05 mm, at no extra cost (measured)."""


TOOL_SITE_PATTERN = re.compile(
    r"tool|tcp|(?:^|[_\W])ee(?:$|[_\W])|end_?effector|flange|attachment", re.IGNORECASE
)
"""A site of a fixed-base robot whose name matches this is its end effector (the UR5e's
``tool_slot``, the Webots ``toolSlot``); without one, the last body of the chain is."""


def warning_label(enum_name: str) -> str:
    """The report key of a MuJoCo warning, from its ``mjtWarning`` name: ``mjWARN_BADQACC``
    -> ``bad_qacc``, ``mjWARN_CONTACTFULL`` -> ``contact_full``, ``mjWARN_CNSTRFULL`` ->
    ``constraint_full`` (a name this does not know comes out lower-cased)."""
    word = enum_name.removeprefix("mjWARN_").lower().replace("cnstr", "constraint")
    word = re.sub(r"^bad(?=.)", "bad_", word)
    return re.sub(r"(?<=[a-z])full$", "_full", word)


def _mj() -> Any:
    """The mujoco module, or a one-line error naming ``motiontool[sim]``."""
    return require("mujoco", "sim", "simulation (motiontool play, batch)")


def warning_labels() -> dict[int, str]:
    """Index in ``MjData.warning`` -> report key, for every warning of the installed MuJoCo
    (read from ``mujoco.mjtWarning``, so that a version that adds or reorders warnings is
    labelled right)."""
    mujoco = _mj()

    members = mujoco.mjtWarning.__members__
    return {
        int(value): warning_label(name)
        for name, value in sorted(members.items(), key=lambda item: int(item[1]))
        if name.startswith("mjWARN_")
    }


def mujoco_version() -> str:
    """The MuJoCo version string."""
    mujoco = _mj()

    return str(mujoco.__version__)


class GeomClass(enum.IntEnum):
    """What a geom of the scene is, for the contact bookkeeping (:attr:`Scene.geom_class`)."""

    FLOOR = 0
    FOOT = 1  # a foot geometry of the robot (``RobotSpec.feet``)
    ROBOT = 2  # any other robot geometry
    SCENE = 3  # any other scene geometry (the UR5e's box)


ROBOT_CLASSES = (GeomClass.FOOT, GeomClass.ROBOT)
"""The classes of robot geometries."""


@dataclass(eq=False)
class Scene:
    """A compiled scene and the indices the stepping loop needs.

    Attributes:
        model, data: the MuJoCo model and its data (at the start state).
        robot: the robot.
        joints: the J motors (model order) and ``limits`` their limits (torque scaled).
        qpos_adr: (J,) int, qpos address of each motor joint.
        driver_dof: (J,) int, dof address of each motor's driver hinge.
        control_substeps: physics steps per control step.
        root_body: the robot's root body id.
        floating: whether the root is free-flying.
        robot_bodies: (B,) int, ids of the robot's bodies (root first).
        body_limbs: limb of each robot body (same order).
        joint_limbs: limb of each motor joint.
        geom_class: (ngeom,) int, the :class:`GeomClass` of each geom.
        foot_geoms: (F,) int, the foot geometries (``RobotSpec.feet``).
        probe: the self-collision probe (a copy of the model where only the candidate pairs of
            robot geometries collide), or None if the robot has fewer than two bodies.
        tool: the end effector of a fixed-base robot: ``(name, "site" | "body", id)``, or None
            (a free-flying robot): a site of the robot named like :data:`TOOL_SITE_PATTERN`
            (the deepest one), else the last body of the chain (going down from the root
            while a body has exactly one child).
    """

    model: Any
    data: Any
    robot: RobotSpec
    joints: tuple[str, ...]
    limits: MotorLimits
    qpos_adr: npt.NDArray[np.intp]
    driver_dof: npt.NDArray[np.intp]
    control_substeps: int
    root_body: int
    floating: bool
    robot_bodies: npt.NDArray[np.intp]
    body_limbs: tuple[str, ...]
    joint_limbs: tuple[str, ...]
    geom_class: npt.NDArray[np.intp]
    foot_geoms: npt.NDArray[np.intp]
    probe: tuple[Any, Any] | None = None
    tool: tuple[str, str, int] | None = None
    _names: dict[int, str] = field(default_factory=dict)

    @property
    def physics_step_s(self) -> float:
        return float(self.model.opt.timestep)

    @property
    def control_step_s(self) -> float:
        return float(self.model.opt.timestep) * self.control_substeps

    def body_name(self, body: int) -> str:
        if body not in self._names:
            self._names[body] = str(self.model.body(body).name)
        return self._names[body]

    def geom_name(self, geom: int) -> str:
        name = str(self.model.geom(geom).name)
        return name or f"geom{geom}"


# ------------------------------------------------------------------------------- building


def build_scene(
    robot: RobotSpec,
    control_step_ms: int,
    *,
    physics_step_ms: float = 2.0,
    start: Start = "standing",
    start_joints: dict[str, float] | None = None,
    floor_friction: float = 1.0,
    mass_scale: float = 1.0,
    torque_scale: float = 1.0,
    start_yaw_deg: float = 0.0,
    p_gain: float = 10.0,
) -> Scene:
    """Compile the scene of ``robot`` at its start state.

    Args:
        robot: the robot (its ``model_path`` is read with :meth:`mujoco.MjSpec.from_file`).
        control_step_ms: the control period (Webots' basicTimeStep), ms.
        physics_step_ms: the largest MuJoCo step, ms; the step used divides the control step.
        start: ``standing`` (zero pose, upright), ``lying-front`` (face down) or
            ``lying-back`` (face up; lying: free-flying robots only).
        start_joints: initial motor positions, rad (m), overriding the zero pose.
        floor_friction: Coulomb friction coefficient between the robot and the floor (pyramidal
            cone); 1.0 walks (docs/simulation.md; Webots' coulombFriction 7 makes MuJoCo's
            pyramidal cone grip so hard that every walk falls).
        mass_scale: factor on every robot body's mass and inertia.
        torque_scale: factor on every motor's maxTorque.
        start_yaw_deg: heading of the robot at start, degrees about +z.
        p_gain: P gain of the position controller, 1/s.
    """
    substeps = _substeps(control_step_ms, physics_step_ms)
    dt = control_step_ms / MS_PER_S / substeps
    spec = _load_spec(robot, dt)
    roots, floating = _robot_roots(spec, robot)
    _scale_masses(spec, mass_scale)
    _add_floor(spec, floor_friction)
    if not floating:
        _add_box(spec, roots)
    limits = _motor_limits(robot, torque_scale, p_gain)
    _add_motors(spec, robot.joint_names, limits.max_torque, dt)
    model = _compile_as_designed(spec, robot)
    scene = _scene(model, robot, limits, substeps, roots, floating)
    _set_start_state(scene, start, start_joints or {}, start_yaw_deg)
    scene.probe = _self_collision_probe(spec, model, scene)
    scene.tool = None if floating else _tool_frame(model, scene.root_body, scene.robot_bodies)
    return scene


def _substeps(control_step_ms: int, physics_step_ms: float) -> int:
    """Physics steps per control step: the fewest whose step is at most ``physics_step_ms``."""
    if control_step_ms <= 0:
        raise MotionToolError(f"control step must be positive, got {control_step_ms} ms")
    if not physics_step_ms > 0:
        raise MotionToolError(f"physics step must be positive, got {physics_step_ms} ms")
    return max(1, math.ceil(control_step_ms / physics_step_ms - STEP_RATIO_SLACK))


def _load_spec(robot: RobotSpec, dt: float) -> Any:
    """The robot's model as an :class:`mujoco.MjSpec`, with the simulation options, no actuators
    (the motors are modelled by :func:`_add_motors`) and a physics step of ``dt`` s."""
    mujoco = _mj()
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


def _robot_roots(spec: Any, robot: RobotSpec) -> tuple[list[Any], bool]:
    """The robot's top bodies, and whether it is free-flying (a URDF of a free-flying robot
    gets its free joint here)."""
    mujoco = _mj()
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


def _scale_masses(spec: Any, mass_scale: float) -> None:
    """Every body's mass and inertia times ``mass_scale``."""
    if mass_scale == 1.0:
        return
    for body in spec.bodies:
        if body.name != "world":
            body.mass = body.mass * mass_scale
            body.fullinertia = [v * mass_scale for v in body.fullinertia]
            body.inertia = [v * mass_scale for v in body.inertia]


def _add_floor(spec: Any, friction: float) -> None:
    """The floor plane (its friction and contact softness win over the robot's geoms) and a
    light."""
    mujoco = _mj()
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


def _add_box(spec: Any, roots: Sequence[Any]) -> None:
    """The wooden box a fixed-base robot stands on; the robot moved onto its top face."""
    mujoco = _mj()
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
    spec: Any, motors: Sequence[str], max_torque: npt.NDArray[np.float64], dt: float
) -> None:
    """Free the motor joints (no hard stops) and couple each to its driver hinge through a
    tendon whose friction loss is the motor's maxTorque (see the module docstring)."""
    mujoco = _mj()
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


def _compile_as_designed(spec: Any, robot: RobotSpec) -> Any:
    """The compiled model, where robot bodies whose geometries already touch in the zero pose
    (a URDF's links, which MuJoCo collides by default) are part of the design: they never
    collide (``spec`` gets the exclusions)."""
    mujoco = _mj()
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
    model: Any,
    robot: RobotSpec,
    limits: MotorLimits,
    substeps: int,
    roots: Sequence[Any],
    floating: bool,
) -> Scene:
    """The scene of ``model`` (fresh data, at the zero pose) and its indices."""
    mujoco = _mj()
    import numpy as np

    motors = robot.joint_names
    root_ids = {int(model.body(r.name).id) for r in roots}
    root_body = int(model.body(roots[0].name).id)
    bodies = [b for b in range(1, model.nbody) if _in_subtree(model, b, root_ids)]
    robot_bodies = np.array(bodies, dtype=np.intp)
    joint_limbs, body_limbs = _limbs(model, motors, root_body, robot_bodies)
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
    model: Any, robot_bodies: set[int], feet: npt.NDArray[np.intp]
) -> npt.NDArray[np.intp]:
    """The :class:`GeomClass` of every geom of ``model``."""
    import numpy as np

    classes = np.full(model.ngeom, GeomClass.SCENE, dtype=np.intp)
    for g in range(model.ngeom):
        if model.geom_bodyid[g] in robot_bodies:
            classes[g] = GeomClass.ROBOT
    classes[model.geom("floor").id] = GeomClass.FLOOR
    classes[feet] = GeomClass.FOOT
    return classes


def _set_start_state(
    scene: Scene, start: Start, start_joints: dict[str, float], start_yaw_deg: float
) -> None:
    """Put ``scene.data`` at the start state: the motors at ``start_joints``; a free-flying
    robot turned by the yaw, laid down if asked, its lowest point :data:`SPAWN_CLEARANCE_M`
    above the floor."""
    mujoco = _mj()
    model, data = scene.model, scene.data
    for name, value in start_joints.items():
        if name in scene.joints:
            data.qpos[scene.qpos_adr[scene.joints.index(name)]] = value
    if scene.floating:
        _place_free_robot(scene, start, start_yaw_deg)
    elif start != "standing":
        raise MotionToolError(
            f"start {start} needs a free-flying robot; {scene.robot.name} is fixed"
        )
    elif start_yaw_deg:
        raise MotionToolError("a start yaw needs a free-flying robot")
    mujoco.mj_forward(model, data)


def _place_free_robot(scene: Scene, start: Start, start_yaw_deg: float) -> None:
    """Orient the free joint (yaw, then lying face down or up) and lower the robot onto the
    floor."""
    mujoco = _mj()
    model, data = scene.model, scene.data
    free_adr = int(model.jnt_qposadr[model.body_jntadr[scene.root_body]])
    quat = _quat_about_z(math.radians(start_yaw_deg))
    if start == "lying-front":  # face down: the torso's x axis points to the floor
        quat = _quat_mul(quat, (math.cos(math.pi / 4), 0.0, math.sin(math.pi / 4), 0.0))
    elif start == "lying-back":  # face up: the torso's x axis points to the sky
        quat = _quat_mul(quat, (math.cos(math.pi / 4), 0.0, -math.sin(math.pi / 4), 0.0))
    data.qpos[free_adr + 3 : free_adr + 7] = quat
    mujoco.mj_kinematics(model, data)
    in_robot = set(scene.robot_bodies.tolist())
    robot_geoms = [g for g in range(model.ngeom) if model.geom_bodyid[g] in in_robot]
    lowest = _lowest_point(model, data, robot_geoms)
    data.qpos[free_adr + 2] += SPAWN_CLEARANCE_M - lowest


def _tool_frame(model: Any, root: int, bodies: npt.NDArray[np.intp]) -> tuple[str, str, int] | None:
    """The end effector of a fixed-base robot (see :class:`Scene`)."""
    in_robot = set(bodies.tolist())

    def depth(body: int) -> int:
        n = 0
        while body != 0:
            body, n = int(model.body_parentid[body]), n + 1
        return n

    sites = [
        s
        for s in range(model.nsite)
        if int(model.site_bodyid[s]) in in_robot and TOOL_SITE_PATTERN.search(model.site(s).name)
    ]
    if sites:
        site = max(sites, key=lambda s: (depth(int(model.site_bodyid[s])), -s))
        return str(model.site(site).name), "site", site
    if root not in in_robot:
        return None
    body = root
    while True:
        children = [b for b in in_robot if int(model.body_parentid[b]) == body]
        if len(children) != 1:
            return str(model.body(body).name), "body", body
        body = children[0]


def _compile(spec: Any, robot: RobotSpec) -> Any:
    try:
        return spec.compile()
    except ValueError as exc:  # MuJoCo's compile errors carry its own message
        raise MotionToolError(f"MuJoCo cannot compile the scene of {robot.name}: {exc}") from exc


def _resolve_package_meshes(spec: Any, model_path: Path) -> None:
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
    one: ``e = exp(-pi z / sqrt(1 - z^2))``, so ``z = -ln e / sqrt(pi^2 + ln^2 e)``."""
    log_e = math.log(restitution)
    return -log_e / math.sqrt(math.pi**2 + log_e**2)


def _positive(value: float, fallback: float) -> float:
    """``value`` if it is a positive number, else ``fallback``."""
    return value if math.isfinite(value) and value > 0 else fallback


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


def _in_subtree(model: Any, body: int, roots: set[int]) -> bool:
    while body != 0:
        if body in roots:
            return True
        body = int(model.body_parentid[body])
    return False


def _lowest_point(model: Any, data: Any, geoms: Sequence[int]) -> float:
    """Lowest z (m) of the given geoms (exact for primitives, bounding box otherwise)."""
    mujoco = _mj()

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


def _limbs(
    model: Any, motors: Sequence[str], root: int, bodies: npt.NDArray[np.intp]
) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """(limb of each motor, limb of each robot body): :func:`motiontool.kinematics.limbs.limb_of`
    by name; a motor whose name does not say takes the branch of the tree it hangs on (the
    root's child body), or ``arm`` when every motor hangs on one branch (a serial arm)."""
    from motiontool.kinematics.limbs import limb_of

    def top(body: int) -> int:
        while body != 0 and int(model.body_parentid[body]) != root and body != root:
            body = int(model.body_parentid[body])
        return body

    def generic(body: int) -> str:
        if body == root or body == 0:
            return str(model.body(root).name)
        return str(model.body(top(body)).name).removesuffix("_virtual")

    branches = {top(int(model.jnt_bodyid[model.joint(n).id])) for n in motors}

    def limb_of_joint(name: str) -> str:
        if len(branches) == 1:
            return limb_of(name, "arm")
        return limb_of(name, generic(int(model.jnt_bodyid[model.joint(name).id])))

    joint_limbs = tuple(limb_of_joint(n) for n in motors)
    body_limb: dict[int, str] = {}
    for name, limb in zip(motors, joint_limbs, strict=True):
        body_limb.setdefault(int(model.jnt_bodyid[model.joint(name).id]), limb)
    out = []
    for b in bodies.tolist():
        body = b
        while body not in body_limb and body != root and body != 0:
            body = int(model.body_parentid[body])
        out.append(body_limb.get(body, generic(b) if body != root else str(model.body(root).name)))
    return joint_limbs, tuple(out)


def _self_collision_probe(spec: Any, model: Any, scene: Scene) -> tuple[Any, Any] | None:
    """A copy of the scene where only candidate pairs of robot geometries collide.

    Candidates, as in :func:`motiontool.kinematics.build_model`: geometries on different robot
    bodies that are not adjacent (a body and its parent, skipping bodies without geometry such
    as the Nao's Hinge2Joint helper frames) and do not already touch at the zero pose.
    """
    mujoco = _mj()

    robot_geoms = [g for g in range(model.ngeom) if scene.geom_class[g] in ROBOT_CLASSES]
    if len({int(model.geom_bodyid[g]) for g in robot_geoms}) < 2:
        return None
    probe_spec = spec.copy()
    for geom in probe_spec.geoms:
        geom.contype = 0
        geom.conaffinity = 0
    names = {g: _geom_key(model, g) for g in robot_geoms}
    # Unnamed geoms get a name so that a pair can refer to them.
    spec_geoms = list(probe_spec.geoms)
    for g in robot_geoms:
        if not spec_geoms[g].name:
            spec_geoms[g].name = names[g]
    adjacent = _adjacency(model, {int(model.geom_bodyid[g]) for g in robot_geoms})
    pairs = []
    for i, ga in enumerate(robot_geoms):
        for gb in robot_geoms[i + 1 :]:
            ba, bb = int(model.geom_bodyid[ga]), int(model.geom_bodyid[gb])
            if ba != bb and not adjacent(ba, bb):
                pairs.append(probe_spec.add_pair(geomname1=names[ga], geomname2=names[gb]))
    if not pairs or not _drop_touching_pairs(probe_spec, pairs):
        return None
    probe = probe_spec.compile()
    return probe, mujoco.MjData(probe)


def _adjacency(model: Any, with_geometry: set[int]) -> Callable[[int, int], bool]:
    """Whether two bodies are adjacent: one is the other's parent, bodies without geometry
    (``with_geometry`` has the others) skipped."""

    def adjacent(a: int, b: int) -> bool:
        for child, parent in ((a, b), (b, a)):
            body = child
            while body != 0:
                body = int(model.body_parentid[body])
                if body == parent:
                    return True
                if body in with_geometry:
                    break
        return False

    return adjacent


def _drop_touching_pairs(probe_spec: Any, pairs: list[Any]) -> int:
    """Delete the ``pairs`` of ``probe_spec`` that already touch at the zero pose (part of the
    design); the number kept."""
    mujoco = _mj()
    probe = probe_spec.compile()
    probe_data = mujoco.MjData(probe)
    mujoco.mj_kinematics(probe, probe_data)
    mujoco.mj_collision(probe, probe_data)
    touching = {
        tuple(sorted((int(a), int(b)))) for a, b in probe_data.contact.geom[: probe_data.ncon]
    }
    kept = 0
    for pair, (name_a, name_b) in zip(
        pairs, [(p.geomname1, p.geomname2) for p in pairs], strict=True
    ):
        key = tuple(sorted((probe.geom(name_a).id, probe.geom(name_b).id)))
        if key in touching:
            probe_spec.delete(pair)
        else:
            kept += 1
    return kept


def _geom_key(model: Any, g: int) -> str:
    name = str(model.geom(g).name)
    return name or f"motiontool_geom_{g}"


# ------------------------------------------------------------------------------- stepping


def run(
    scene: Scene,
    targets: npt.NDArray[np.float64],
    commanded: npt.NDArray[np.bool_],
    *,
    record_bodies: bool = False,
) -> Trace:
    """Play ``targets`` (S, J), one row per control step, from the scene's start state.

    Args:
        scene: a freshly built scene (its data is stepped in place).
        targets: (S, J) target positions in force at each step (NaN-free), rad (m), before
            clipping to the motor limits.
        commanded: (S, J) bool, whether the motion sent the target at that step.
        record_bodies: also keep every robot body's pose at every frame (for a recording).

    An error MuJoCo raises (:class:`mujoco.FatalError`) stops the run: the trace keeps what was
    simulated and says why. Any other exception is a bug, and propagates.
    """
    mujoco = _mj()
    import numpy as np

    model, data = scene.model, scene.data
    trace = _new_trace(scene, targets, commanded, record_bodies)
    observe = _observer(scene, trace, record_bodies)
    limits, driver_dof, substeps = scene.limits, scene.driver_dof, scene.control_substeps
    position, velocity_cmd, torque = trace.position, trace.velocity_cmd, trace.torque
    try:
        observe(0)
        for k in range(len(targets)):
            command = velocity_command(limits, targets[k], position[k])  # Webots' motor law
            velocity_cmd[k] = command
            data.qvel[driver_dof] = command
            mujoco.mj_step(model, data, substeps)
            torque[k] = data.qfrc_constraint[driver_dof]
            np.negative(torque[k], out=torque[k])
            observe(k + 1)
            trace.steps_done = k + 1
    except mujoco.FatalError as exc:  # MuJoCo's own error: the report says why the run stopped
        trace.error = f"simulation stopped at step {trace.steps_done}: {exc}"
    trace.warnings = {name: int(data.warning[i].number) for i, name in warning_labels().items()}
    return trace if trace.steps_done == len(targets) else trace.truncated()


def _new_trace(
    scene: Scene,
    targets: npt.NDArray[np.float64],
    commanded: npt.NDArray[np.bool_],
    record_bodies: bool,
) -> Trace:
    """An empty trace for ``targets`` (S, J): S + 1 frames, zero-filled."""
    import numpy as np

    steps, n_joints = targets.shape
    n_frames = steps + 1
    body_frames = n_frames if record_bodies else 0
    feet, bodies = scene.foot_geoms, scene.robot_bodies
    return Trace(
        joints=scene.joints,
        control_step_s=scene.control_step_s,
        physics_step_s=scene.physics_step_s,
        time_s=np.arange(n_frames, dtype=np.float64) * scene.control_step_s,
        commanded=commanded,
        targets=targets,
        velocity_cmd=np.zeros((steps, n_joints)),
        torque=np.zeros((steps, n_joints)),
        position=np.zeros((n_frames, n_joints)),
        base_pos=np.zeros((n_frames, 3)),
        base_quat=np.zeros((n_frames, 4)),
        feet=tuple(scene.geom_name(int(g)) for g in feet),
        foot_pos=np.zeros((n_frames, len(feet), 3)),
        foot_contact=np.zeros((n_frames, len(feet)), dtype=bool),
        bodies=tuple(scene.body_name(int(b)) for b in bodies),
        body_pos=np.zeros((body_frames, len(bodies), 3)),
        body_quat=np.zeros((body_frames, len(bodies), 4)),
        tool=scene.tool[0] if scene.tool else "",
        tool_pos=np.zeros((n_frames, 3)) if scene.tool else None,
        tool_quat=np.zeros((n_frames, 4)) if scene.tool else None,
    )


def _observer(scene: Scene, trace: Trace, record_bodies: bool) -> Callable[[int], None]:
    """A function that measures the state of ``scene.data`` into frame ``frame`` of ``trace``:
    positions, poses, contacts, self-collisions."""
    data, feet, bodies = scene.data, scene.foot_geoms, scene.robot_bodies
    qpos_adr, root = scene.qpos_adr, scene.root_body
    read_tool = _tool_reader(scene, data, trace.tool_pos, trace.tool_quat)

    def observe(frame: int) -> None:
        trace.position[frame] = data.qpos[qpos_adr]
        if read_tool is not None:
            read_tool(frame)
        trace.base_pos[frame] = data.xpos[root]
        trace.base_quat[frame] = data.xquat[root]
        if len(feet):
            trace.foot_pos[frame] = data.geom_xpos[feet]
        if record_bodies:
            trace.body_pos[frame] = data.xpos[bodies]
            trace.body_quat[frame] = data.xquat[bodies]
        if data.ncon:
            _contacts(scene, data, frame, trace)
        if scene.probe is not None:
            _self_collisions(scene, data, frame, trace)

    return observe


def _tool_reader(
    scene: Scene,
    data: Any,
    pos: npt.NDArray[np.float64] | None,
    quat: npt.NDArray[np.float64] | None,
) -> Callable[[int], None] | None:
    """A function that copies the tool's pose of ``data`` into row ``frame`` of ``pos`` (m)
    and ``quat`` (w, x, y, z), or None without a tool."""
    if scene.tool is None or pos is None or quat is None:
        return None
    mujoco = _mj()
    _name, kind, index = scene.tool
    if kind == "site":

        def read_site(frame: int) -> None:
            pos[frame] = data.site_xpos[index]
            mujoco.mju_mat2Quat(quat[frame], data.site_xmat[index])

        return read_site

    def read_body(frame: int) -> None:
        pos[frame] = data.xpos[index]
        quat[frame] = data.xquat[index]

    return read_body


def tool_poses(
    scene: Scene, q: npt.NDArray[np.float64]
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """Forward kinematics of the tool: its world pose for each row of motor positions.

    MuJoCo's own ``mj_kinematics`` on a scratch ``MjData`` of the scene's model, so that the
    commanded and the measured poses come from one model in one world frame (the arm on its
    box), with no second model to keep in step.

    Args:
        scene: a scene with a tool (:attr:`Scene.tool`).
        q: (N, J) motor positions, rad (m), in ``scene.joints`` order.

    Returns:
        positions (N, 3), m, and orientations (N, 4), unit quaternions (w, x, y, z).
    """
    mujoco = _mj()
    import numpy as np

    if scene.tool is None:
        raise MotionToolError(f"{scene.robot.name} has no end effector (a free-flying robot)")
    model = scene.model
    data = mujoco.MjData(model)
    rows = np.asarray(q, dtype=np.float64).reshape(-1, len(scene.joints))
    pos = np.zeros((len(rows), 3))
    quat = np.zeros((len(rows), 4))
    read = _tool_reader(scene, data, pos, quat)
    assert read is not None
    for i, row in enumerate(rows):
        data.qpos[scene.qpos_adr] = row
        mujoco.mj_kinematics(model, data)
        read(i)
    return pos, quat


def _contacts(scene: Scene, data: Any, frame: int, trace: Trace) -> None:
    """Foot-floor contacts into ``foot_contact``; every other robot contact into events."""
    cls = scene.geom_class
    seen: dict[tuple[str, str, str], float] = {}
    for (g1, g2), d in zip(data.contact.geom.tolist(), data.contact.dist.tolist(), strict=True):
        if cls[g1] not in ROBOT_CLASSES:
            g1, g2 = g2, g1
        if cls[g1] not in ROBOT_CLASSES:
            continue  # scene-scene
        if cls[g1] == GeomClass.FOOT and cls[g2] == GeomClass.FLOOR:
            trace.foot_contact[frame, int((scene.foot_geoms == g1).argmax())] = True
            continue
        key = _contact_event_key(scene, g1, g2)
        seen[key] = max(seen.get(key, 0.0), max(0.0, -d))
    for (kind, body, other), depth in seen.items():
        trace.events.append(ContactEvent(frame, kind, body, other, depth))  # type: ignore[arg-type]


def _contact_event_key(scene: Scene, robot_geom: int, other_geom: int) -> tuple[str, str, str]:
    """(kind, robot body, other) of a contact between a robot geom and another geom that is not
    a foot on the floor (see :class:`~motiontool.sim.trace.ContactEvent`)."""
    model = scene.model
    body = scene.body_name(int(model.geom_bodyid[robot_geom]))
    other_class = scene.geom_class[other_geom]
    if other_class in ROBOT_CLASSES:  # the model collides the robot with itself (Webots' UR5e)
        other = scene.body_name(int(model.geom_bodyid[other_geom]))
        return "touch", min(body, other), max(body, other)
    if other_class == GeomClass.FLOOR:
        return ("scene" if not scene.floating else "ground"), body, "floor"
    return "scene", body, scene.geom_name(other_geom)


def _self_collisions(scene: Scene, data: Any, frame: int, trace: Trace) -> None:
    mujoco = _mj()

    assert scene.probe is not None
    probe, probe_data = scene.probe
    probe_data.qpos[:] = data.qpos
    mujoco.mj_kinematics(probe, probe_data)
    mujoco.mj_collision(probe, probe_data)
    if not probe_data.ncon:
        return
    seen: dict[tuple[str, str], float] = {}
    for (g1, g2), d in zip(
        probe_data.contact.geom.tolist(), probe_data.contact.dist.tolist(), strict=True
    ):
        a = scene.body_name(int(probe.geom_bodyid[g1]))
        b = scene.body_name(int(probe.geom_bodyid[g2]))
        key = (a, b) if a < b else (b, a)
        seen[key] = max(seen.get(key, 0.0), max(0.0, -d))
    for (a, b), depth in seen.items():
        trace.events.append(ContactEvent(frame, "self", a, b, depth))


# ------------------------------------------------------------------------------- geometry


def scene_shapes(scene: Scene) -> list[BodyShapes]:
    """Every body with collision geometry: the robot's (posed every frame) and the scene's."""
    mujoco = _mj()

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
