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
arrays for batched kinematics, with the shapes in :mod:`.shapes`). The package's names are
imported when first used (:mod:`motiontool.lazy_names`): the collision check reads a robot's
stored tables (:class:`.tables.KinematicTables` and the shape codes) without importing the
rest, the typed Protocols of :mod:`.api` included.

May import pinocchio (through :func:`.api.pin_module`), the rest of ``kinematics``, ``motionfmt``
and the top-level modules.
"""

import typing

from motiontool.lazy_names import lazy_names as _lazy_names

if typing.TYPE_CHECKING:
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

#: Where each name lives: imported on first use (PEP 562), so that the collision check's numpy
#: side (the tables and their shape codes) imports neither the Protocols of :mod:`.api` nor
#: the modules that call Pinocchio. No name here is also a submodule's.
_HOMES: dict[str, str] = {
    "Balance": "motiontool.kinematics._pinocchio.balance",
    "com_and_support": "motiontool.kinematics._pinocchio.balance",
    "sole_heights": "motiontool.kinematics._pinocchio.balance",
    "body_positions": "motiontool.kinematics._pinocchio.configuration",
    "configurations": "motiontool.kinematics._pinocchio.configuration",
    "build_model": "motiontool.kinematics._pinocchio.model",
    "joint_table": "motiontool.kinematics._pinocchio.model",
    "geometry_centers": "motiontool.kinematics._pinocchio.self_collision",
    "pair_signed_distances": "motiontool.kinematics._pinocchio.self_collision",
    "self_collision_depths": "motiontool.kinematics._pinocchio.self_collision",
    "self_collisions": "motiontool.kinematics._pinocchio.self_collision",
    "BOX": "motiontool.kinematics._pinocchio.shapes",
    "CAPSULE": "motiontool.kinematics._pinocchio.shapes",
    "CYLINDER": "motiontool.kinematics._pinocchio.shapes",
    "OTHER": "motiontool.kinematics._pinocchio.shapes",
    "SPHERE": "motiontool.kinematics._pinocchio.shapes",
    "FIXED": "motiontool.kinematics._pinocchio.tables",
    "PRISMATIC": "motiontool.kinematics._pinocchio.tables",
    "REVOLUTE": "motiontool.kinematics._pinocchio.tables",
    "KinematicTables": "motiontool.kinematics._pinocchio.tables",
    "joint_motion": "motiontool.kinematics._pinocchio.tables",
    "kinematic_tables": "motiontool.kinematics._pinocchio.tables",
}

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


__getattr__, __dir__ = _lazy_names(__name__, _HOMES)
