"""Robot models and kinematics: joint limits, forward kinematics, self-collision, balance.

Importing this package is cheap: its names are imported when first used, and Pinocchio (and
numpy) only when a function that needs them runs, so looking up a built-in robot's joint table
never loads them.

``robot_checks`` / ``RobotChecks`` (:mod:`~motiontool.kinematics.checks`) are the robot checks of
``motiontool validate``; ``scan_self_collisions`` checks many configurations at once. The
robot side of the transforms is here too: a robot's mirror map (:mod:`.mirror`) and the fixes
that need a robot (:mod:`.robot_fixes`).

May import ``motionfmt`` and the top-level modules; Pinocchio only in :mod:`._pinocchio`; never
``sim`` or ``cli``.
"""

import typing

from motiontool.kinematics.builtin_robots import builtin_robots
from motiontool.lazy_names import lazy_names as _lazy_names

if typing.TYPE_CHECKING:
    from motiontool.kinematics._pinocchio import (
        Balance,
        body_positions,
        build_model,
        com_and_support,
        self_collision_depths,
        self_collisions,
        sole_heights,
    )
    from motiontool.kinematics.checks import (
        CHECKS,
        DEFAULT_CHECKS,
        DEFAULT_PENETRATION_TOLERANCE_MM,
        RobotChecks,
        parse_checks,
        robot_checks,
    )
    from motiontool.kinematics.collision import Contact, scan_self_collisions
    from motiontool.kinematics.export import mjcf_bytes, urdf_bytes
    from motiontool.kinematics.robots import (
        JointSpec,
        NoRobotDetectedError,
        RobotError,
        RobotSpec,
        UnknownRobotError,
        detect_robot,
        erd_robot_names,
        load_robot,
        models_dir,
        pick_robot,
        resolve_robot,
        robot_choices,
        unknown_joint_message,
    )

#: Where each name lives: imported on first use (PEP 562), so that a syntax-level
#: ``validate`` imports no robot spec and no check, and a robot run not the Pinocchio adapter's
#: typed surface or the model exporter. No name here is also a submodule's
#: (``builtin_robots`` is both: imported above, the function replaces the submodule as the
#: package's attribute, as it always did).
_HOMES: dict[str, str] = {
    "JointSpec": "motiontool.kinematics.robots",
    "NoRobotDetectedError": "motiontool.kinematics.robots",
    "RobotError": "motiontool.kinematics.robots",
    "RobotSpec": "motiontool.kinematics.robots",
    "UnknownRobotError": "motiontool.kinematics.robots",
    "detect_robot": "motiontool.kinematics.robots",
    "erd_robot_names": "motiontool.kinematics.robots",
    "load_robot": "motiontool.kinematics.robots",
    "models_dir": "motiontool.kinematics.robots",
    "pick_robot": "motiontool.kinematics.robots",
    "resolve_robot": "motiontool.kinematics.robots",
    "robot_choices": "motiontool.kinematics.robots",
    "unknown_joint_message": "motiontool.kinematics.robots",
    "Balance": "motiontool.kinematics._pinocchio",
    "body_positions": "motiontool.kinematics._pinocchio",
    "build_model": "motiontool.kinematics._pinocchio",
    "com_and_support": "motiontool.kinematics._pinocchio",
    "self_collision_depths": "motiontool.kinematics._pinocchio",
    "self_collisions": "motiontool.kinematics._pinocchio",
    "sole_heights": "motiontool.kinematics._pinocchio",
    "CHECKS": "motiontool.kinematics.checks",
    "DEFAULT_CHECKS": "motiontool.kinematics.checks",
    "DEFAULT_PENETRATION_TOLERANCE_MM": "motiontool.kinematics.checks",
    "RobotChecks": "motiontool.kinematics.checks",
    "parse_checks": "motiontool.kinematics.checks",
    "robot_checks": "motiontool.kinematics.checks",
    "Contact": "motiontool.kinematics.collision",
    "scan_self_collisions": "motiontool.kinematics.collision",
    "mjcf_bytes": "motiontool.kinematics.export",
    "urdf_bytes": "motiontool.kinematics.export",
}

__all__ = [
    "CHECKS",
    "DEFAULT_CHECKS",
    "DEFAULT_PENETRATION_TOLERANCE_MM",
    "Balance",
    "Contact",
    "JointSpec",
    "NoRobotDetectedError",
    "RobotChecks",
    "RobotError",
    "RobotSpec",
    "UnknownRobotError",
    "body_positions",
    "build_model",
    "builtin_robots",
    "com_and_support",
    "detect_robot",
    "erd_robot_names",
    "load_robot",
    "mjcf_bytes",
    "models_dir",
    "parse_checks",
    "pick_robot",
    "resolve_robot",
    "robot_checks",
    "robot_choices",
    "scan_self_collisions",
    "self_collision_depths",
    "self_collisions",
    "sole_heights",
    "unknown_joint_message",
    "urdf_bytes",
]


__getattr__, __dir__ = _lazy_names(__name__, _HOMES)
