"""What ``play --world`` applies of a Webots world to a MuJoCo run (:func:`world_run`), and the
report's ``world`` object that says so, field by field.

Applied: ``basicTimeStep`` as the control step (unless ``--timestep``), with MuJoCo's finer
physics step kept (the largest of at most 2 ms that divides it, or ``--physics-step``: ODE steps
at ``basicTimeStep`` in Webots, which makes the walks fall in MuJoCo, docs/simulation.md);
``gravity``; for each support (``Floor``, static boxes and planes) the ``coulombFriction`` of
the ``ContactProperties`` between the robot's feet and its material (Webots' defaults when none
matches; ``--friction`` wins); the robot's ``translation`` (x, y; it is set
on the surface below it) and ``rotation`` (about the vertical: the start yaw). The whole scene
is lowered so that the surface the robot starts on is at z = 0: heights in the report are
measured from it.

The robot's ``selfCollision`` turns self-collision physics on or off (unless
``--[no-]self-collision``; :func:`motiontool.sim._mujoco.probe.collide_self`).

Not applied, and said: ``ERP``, ``CFM``, ``softCFM``, ``softERP`` and ``bounceVelocity`` (MuJoCo's
contacts and constraints are set by solref / solimp, not ODE's numbers), ``bounce`` (ODE bounces
only impacts faster than ``bounceVelocity``; MuJoCo's damping ratio would make every contact
ring, resting feet included: the world's contacts are critically damped, docs/simulation.md),
a rotation that is not about the vertical, and the nodes the reader skipped.

Pure Python: the MuJoCo side takes :class:`Ground` and the start position.
"""

from __future__ import annotations

import hashlib
import math
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from motiontool.errors import MotionToolError
from motiontool.sim.world import ContactProps, Support, World, read_world

__all__ = ["Ground", "WorldRun", "world_of", "world_run", "world_run_options"]


@dataclass(frozen=True)
class Ground:
    """A support as the MuJoCo scene builds it (z up, m; heights from the robot's surface).

    Attributes:
        name: the geom's name (``floor`` for the first plane).
        kind: ``plane`` or ``box``.
        center, size, yaw_rad: as :class:`motiontool.sim.world.Support`'s, lowered.
        friction: robot-ground Coulomb friction coefficient.
    """

    name: str
    kind: str
    center: tuple[float, float, float]
    size: tuple[float, float, float]
    yaw_rad: float
    friction: float


@dataclass(frozen=True)
class WorldRun:
    """What a world changes in a run.

    Attributes:
        world: the world read.
        control_step_ms: the control step it gives (``basicTimeStep``), ms.
        gravity: m/s², z up.
        ground: the supports, lowered so that the robot's surface is at z = 0.
        start_xy: the robot's start position, m (world frame).
        start_yaw_deg: its start heading, degrees.
        surface: the support the robot starts on, and its top's height in the world, m.
        contact: the contact properties between the feet and that support.
    """

    world: World
    control_step_ms: int
    gravity: tuple[float, float, float]
    ground: tuple[Ground, ...]
    start_xy: tuple[float, float]
    start_yaw_deg: float
    surface: tuple[str, float]
    contact: ContactProps

    def friction(self, given: float | None) -> float:
        """The friction of the surface the robot starts on (``given``: ``--friction``)."""
        return self.contact.coulomb_friction if given is None else given

    def ground_for(self, given: float | None, scale: float) -> tuple[Ground, ...]:
        """The supports with ``--friction`` (``given``) and the friction ``scale`` applied."""
        return tuple(
            Ground(
                g.name,
                g.kind,
                g.center,
                g.size,
                g.yaw_rad,
                (g.friction if given is None else given) * scale,
            )
            for g in self.ground
        )

    def report(
        self,
        *,
        control_step_ms: int,
        timestep_given: bool,
        physics_step_ms: float,
        friction_given: bool,
        self_collision_given: bool = False,
    ) -> dict[str, Any]:
        """The report's ``world`` object: the file and the sha256 of its bytes, the robot node,
        each field applied (with its value and unit) and each field or node not applied (with
        why)."""
        world, robot = self.world, self.world.robot
        said = _Said()
        step = world.basic_time_step_ms
        if timestep_given:
            said.not_applied("WorldInfo.basicTimeStep", step, "ms", "a control step was given")
        else:
            default = "" if "basicTimeStep" in world.written else " (Webots' default)"
            said.applied("WorldInfo.basicTimeStep", step, "ms", f"the control step{default}")
        said.not_applied(
            "WorldInfo.basicTimeStep as the physics step",
            step,
            "ms",
            f"MuJoCo steps at {physics_step_ms:g} ms, {control_step_ms / physics_step_ms:g} "
            "steps per control step: Webots' ODE steps at basicTimeStep, with which the walks "
            "fall in MuJoCo (docs/simulation.md)",
        )
        said.applied("WorldInfo.gravity", round(-self.gravity[2], 6), "m/s^2", "gravity, down")
        for name, value in (("ERP", world.erp), ("CFM", world.cfm)):
            said.not_applied(
                f"WorldInfo.{name}", value, None, "MuJoCo has no global ERP/CFM: solref/solimp"
            )
        self._contact(said, friction_given)
        self._robot(said, self_collision_given)
        for support, g in zip(world.supports, self.ground, strict=True):
            said.applied(
                f"{support.node} {support.name!r}.boundingObject",
                [round(v, 6) for v in g.size],
                "m",
                f"a {g.kind} the robot can stand on, top at {support.top_z:g} m"
                f" (friction {g.friction:g})",
            )
        return {
            "path": world.path,
            "sha256": hashlib.sha256(Path(world.path).read_bytes()).hexdigest(),
            "version": world.version,
            "robot_node": {"name": robot.name, "def": robot.def_name, "type": robot.type},
            "applied": said.done,
            "not_applied": said.not_done,
            "skipped_nodes": list(world.skipped),
        }

    def _contact(self, said: _Said, friction_given: bool) -> None:
        """What the feet-ground ``ContactProperties`` gave."""
        contact, foot = self.contact, self.world.robot.foot_material
        material = next(
            (s.material for s in self.world.supports if s.name == self.surface[0]), "default"
        )
        source = (
            f"from ContactProperties {contact.material1!r}/{contact.material2!r}, line "
            f"{contact.line}"
            if contact.line
            else f"Webots' default: no ContactProperties for {foot!r}/{material!r}"
        )
        friction = ("ContactProperties.coulombFriction", contact.coulomb_friction, None)
        if friction_given:
            said.not_applied(*friction, f"a friction was given: it wins ({source})")
        else:
            said.applied(*friction, f"robot-{self.surface[0]} friction, pyramidal cone ({source})")
        said.not_applied(
            "ContactProperties.bounce",
            contact.bounce,
            None,
            "ODE bounces only impacts faster than bounceVelocity; a MuJoCo contact's damping "
            "ratio acts on every contact, resting feet included: critically damped "
            f"(docs/simulation.md) ({source})",
        )
        for key, value, unit in (
            ("bounceVelocity", contact.bounce_velocity, "m/s"),
            ("softCFM", contact.soft_cfm, None),
            ("softERP", contact.soft_erp, None),
        ):
            said.not_applied(
                f"ContactProperties.{key}",
                value,
                unit,
                "MuJoCo's contacts are set by solref/solimp (docs/simulation.md), not ODE's",
            )

    def _robot(self, said: _Said, self_collision_given: bool) -> None:
        """What the robot node gave."""
        robot = self.world.robot
        node = f"{robot.type} {robot.name!r}"
        if robot.translation is not None:
            said.applied(
                f"{node}.translation",
                list(robot.translation),
                "m",
                f"start x, y; set on the {self.surface[0]} (top at {self.surface[1]:g} m), "
                "heights measured from it",
            )
        if robot.rotation is not None:
            if _yaw_deg(self.world) is None:
                said.not_applied(
                    f"{node}.rotation", list(robot.rotation), "rad", "not about the vertical"
                )
            else:
                said.applied(f"{node}.rotation", list(robot.rotation), "rad", "start yaw")
        collide = f"{node}.selfCollision", robot.self_collision, None
        if self_collision_given:
            said.not_applied(*collide, "a self-collision option was given: it wins")
        elif robot.self_collision:
            said.applied(
                *collide,
                "self-collision physics: the robot's parts collide with each other, but solids"
                " joined by a joint (Webots' rule)",
            )
        else:
            said.applied(*collide, "no self-collision physics: the robot's parts pass through")


class _Said:
    """The report's ``applied`` and ``not_applied`` lists, as they are said."""

    def __init__(self) -> None:
        self.done: list[dict[str, Any]] = []
        self.not_done: list[dict[str, Any]] = []

    def applied(self, name: str, value: Any, unit: str | None, how: str) -> None:
        self.done.append({"field": name, "value": value, "unit": unit, "applied_as": how})

    def not_applied(self, name: str, value: Any, unit: str | None, why: str) -> None:
        self.not_done.append({"field": name, "value": value, "unit": unit, "reason": why})


def _yaw_deg(world: World) -> float | None:
    """The robot's start yaw, degrees (None: its rotation is not about the vertical)."""
    rotation = world.robot.rotation
    if rotation is None or rotation[3] == 0.0:
        return 0.0
    ax, ay, az, angle = rotation
    norm = math.sqrt(ax * ax + ay * ay + az * az)
    if norm == 0 or not math.isclose(abs(az), norm, rel_tol=1e-6):
        return None
    return math.degrees(angle if az > 0 else -angle)


def world_run(world: World) -> WorldRun:
    """What ``world`` changes in a run (see the module docstring).

    Raises:
        MotionToolError: a ``basicTimeStep`` that is not a whole number of ms (the control
            step is one; pass ``--timestep``).
    """
    step = world.basic_time_step_ms
    if step != round(step) or step < 1:
        raise MotionToolError(
            f"{world.path}: basicTimeStep {step:g} ms is not a whole number of ms >= 1, which "
            "the control step must be; give the control step"
        )
    robot = world.robot
    x, y = (robot.translation[0], robot.translation[1]) if robot.translation else (0.0, 0.0)
    surface = _surface(world.supports, x, y)
    height = surface.top_at(x, y) if surface is not None else 0.0
    height = height or 0.0
    name = surface.name if surface is not None else "floor"
    ground = []
    planes = 0
    for s in world.supports:
        props = world.contact(s.material)
        planes += s.kind == "plane"
        geom = "floor" if s.kind == "plane" and planes == 1 else f"floor:{s.name}"
        ground.append(
            Ground(
                geom,
                s.kind,
                (s.center[0], s.center[1], s.center[2] - height),
                s.size,
                s.yaw_rad,
                props.coulomb_friction,
            )
        )
    contact = world.contact(surface.material if surface is not None else "default")
    return WorldRun(
        world=world,
        control_step_ms=round(step),
        gravity=world.gravity,
        ground=tuple(ground),
        start_xy=(x, y),
        start_yaw_deg=_yaw_deg(world) or 0.0,
        surface=(name, height),
        contact=contact,
    )


def _surface(supports: tuple[Support, ...], x: float, y: float) -> Support | None:
    """The support whose top is highest above (x, y), or None."""
    best: Support | None = None
    top = -math.inf
    for s in supports:
        z = s.top_at(x, y)
        if z is not None and z > top:
            best, top = s, z
    return best


def world_run_options(
    world: Path | None, robot_node: str | None, robots: Iterable[str]
) -> dict[str, Any]:
    """The world options of a batch run (:class:`~motiontool.sim.batch.RunSpec` options, and so
    its cache key): the world file, the sha256 of the files it reads (the world and its local
    PROTOs: a changed world is played again) and the robot node; none without a world.

    Raises:
        MotionToolError: a world that cannot be read, or has no robot node for one of
            ``robots`` (:func:`motiontool.sim.world.read_world`): before any run.
    """
    if world is None:
        if robot_node is not None:
            raise MotionToolError(f"robot node {robot_node!r} given without a world to find it in")
        return {}
    digest = hashlib.sha256()
    for robot in sorted(set(robots)):
        read = read_world(world, robot_node, robot)
        world_run(read)
        for path in read.files:
            digest.update(path.read_bytes())
    return {"world": str(world), "world_sha256": digest.hexdigest(), "robot_node": robot_node}


def world_of(options: dict[str, Any], robot: str) -> WorldRun | None:
    """The world a batch run plays in (its options from :func:`world_run_options`), or None."""
    if not options.get("world"):
        return None
    return world_run(read_world(options["world"], options.get("robot_node"), robot))
