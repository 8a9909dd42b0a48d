"""A compiled scene (:class:`Scene`): the MuJoCo model and data, and the indices the stepping
loop needs; what each geom is (:class:`GeomClass`)."""

from __future__ import annotations

import enum
import re
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from motiontool.sim.motor import MotorLimits

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.kinematics.robots import RobotSpec
    from motiontool.sim._mujoco.api import MjData, MjModel


TOOL_SITE_PATTERN = re.compile(
    r"tool|tcp|(?:^|[_\W])ee(?:$|[_\W])|end_?effector|flange|attachment", re.IGNORECASE
)
"""A site of a fixed-base robot whose name matches this is its end effector (the UR5e's
``tool_slot``, the Webots ``toolSlot``); without one, the last body of the chain is."""


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
        self_collision: whether the robot's parts collide with each other in the simulation
            (self-collision physics).
        touch_fails: whether every touch between the robot's parts is a self-collision that
            fails the run: where the robot's model collides its parts (the UR5e: an arm that
            touches itself has crashed). Where a world or an option asked for the physics of a
            robot whose model does not (the Nao in the wrestling world), only a touch between
            two limbs is (:meth:`touch_counts`).
    """

    model: MjModel
    data: MjData
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
    probe: tuple[MjModel, MjData] | None = None
    tool: tuple[str, str, int] | None = None
    self_collision: bool = False
    touch_fails: bool = True
    _names: dict[int, str] = field(default_factory=dict)
    _limb_of: dict[str, str] = field(default_factory=dict)

    @property
    def physics_step_s(self) -> float:
        return float(self.model.opt.timestep)

    @property
    def control_step_s(self) -> float:
        return float(self.model.opt.timestep) * self.control_substeps

    def touch_counts(self, body_a: str, body_b: str) -> bool:
        """Whether a touch between robot bodies ``body_a`` and ``body_b`` (names) is a
        self-collision: always where :attr:`touch_fails`; else only between two limbs (a hand's
        fingers and its palm, a foot's sensor and its sole are one limb and touch as in
        Webots; an arm on the torso, one foot on the other are two)."""
        if self.touch_fails:
            return True
        if not self._limb_of:
            for body, limb in zip(self.robot_bodies.tolist(), self.body_limbs, strict=True):
                self._limb_of[self.body_name(int(body))] = limb.replace("Hand", "Arm")
        return self._limb_of.get(body_a, body_a) != self._limb_of.get(body_b, body_b)

    def body_name(self, body: int) -> str:
        if body not in self._names:
            self._names[body] = str(self.model.body(body).name)
        return self._names[body]

    def geom_name(self, geom: int) -> str:
        name = str(self.model.geom(geom).name)
        return name or f"geom{geom}"
