"""The MuJoCo side of ``play``: the scene, Webots-like motors, and the stepping loop.

The only package that imports :mod:`mujoco` (lazily, inside functions, through :func:`.api.mj`,
typed by the Protocols of :mod:`.api`: MuJoCo ships no stubs). One concept per module:
:mod:`.scene` (what a compiled scene holds), :mod:`.build` (building it), :mod:`.start` (its
start state), :mod:`.topology` (the robot's tree: limbs, end effector), :mod:`.probe`
(self-collision), :mod:`.stepping` (running it), :mod:`.shapes` (its shapes, for a recording),
:mod:`.api` (the typed surface of MuJoCo, the installed version, the warnings' names).

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

May import mujoco (through :func:`.api.mj`), the rest of ``sim``, ``kinematics``, ``motionfmt``
and the top-level modules.
"""

from motiontool.sim._mujoco.api import mujoco_version, warning_label, warning_labels
from motiontool.sim._mujoco.build import (
    BOX_HEIGHT_M,
    FALLBACK_MAX_TORQUE,
    FALLBACK_MAX_VELOCITY,
    build_scene,
)
from motiontool.sim._mujoco.scene import TOOL_SITE_PATTERN, GeomClass, Scene
from motiontool.sim._mujoco.shapes import scene_shapes
from motiontool.sim._mujoco.start import SPAWN_CLEARANCE_M
from motiontool.sim._mujoco.stepping import run, run_chunks, tool_poses
from motiontool.sim._mujoco.topology import link_tree

__all__ = [
    "BOX_HEIGHT_M",
    "FALLBACK_MAX_TORQUE",
    "FALLBACK_MAX_VELOCITY",
    "SPAWN_CLEARANCE_M",
    "TOOL_SITE_PATTERN",
    "GeomClass",
    "Scene",
    "build_scene",
    "link_tree",
    "mujoco_version",
    "run",
    "run_chunks",
    "scene_shapes",
    "tool_poses",
    "warning_label",
    "warning_labels",
]
