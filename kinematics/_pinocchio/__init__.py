"""The Pinocchio adapter: the only package that imports pinocchio (lazily, inside functions).

Models are built once per process and cached. Conventions for every function here:

* ``q_by_joint`` maps motor names to positions (rad for hinges, m for slides); motors left out
  stay at 0. Values must be finite.
* Poses are evaluated with a free-flying root (the Nao's torso) at the world origin, upright:
  a quasi-static view in which gravity is along -z of the root frame.

One concept per module: :mod:`.model` (loading a file, its motors, the collision pairs),
:mod:`.configuration` (motor positions to Pinocchio's ``q``, forward kinematics),
:mod:`.self_collision` (pairs in contact and their depths), :mod:`.balance` (centre of mass and
support polygon, with the plane geometry in :mod:`.hull`) and :mod:`.tables` (the model as numpy
arrays for batched kinematics, with the shapes in :mod:`.shapes`).

May import pinocchio (through :func:`.api.pin_module`), the rest of ``kinematics``, ``motionfmt``
and the top-level modules.
"""

from motiontool.kinematics._pinocchio.balance import Balance, com_and_support, sole_heights
from motiontool.kinematics._pinocchio.configuration import body_positions, configurations
from motiontool.kinematics._pinocchio.model import build_model, joint_table
from motiontool.kinematics._pinocchio.self_collision import (
    geometry_centers,
    pair_signed_distances,
    self_collision_depths,
    self_collisions,
)
from motiontool.kinematics._pinocchio.shapes import BOX, CAPSULE, CYLINDER, OTHER, SPHERE
from motiontool.kinematics._pinocchio.tables import (
    FIXED,
    PRISMATIC,
    REVOLUTE,
    KinematicTables,
    joint_motion,
    kinematic_tables,
)

__all__ = [
    "BOX",
    "CAPSULE",
    "CYLINDER",
    "FIXED",
    "OTHER",
    "PRISMATIC",
    "REVOLUTE",
    "SPHERE",
    "Balance",
    "KinematicTables",
    "body_positions",
    "build_model",
    "com_and_support",
    "configurations",
    "geometry_centers",
    "joint_motion",
    "joint_table",
    "kinematic_tables",
    "pair_signed_distances",
    "self_collision_depths",
    "self_collisions",
    "sole_heights",
]
