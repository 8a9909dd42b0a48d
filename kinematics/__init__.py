"""Robot models and kinematics: joint limits, forward kinematics, self-collision, balance.

Importing this package is cheap: Pinocchio (and numpy) are imported only when a function that
needs them runs, so looking up a built-in robot's joint table never loads them.

``robot_checks`` / ``RobotChecks`` (:mod:`~motiontool.kinematics.checks`) are the robot checks of
``motiontool validate``; ``scan_self_collisions`` checks many configurations at once.
"""

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
    builtin_robots,
    detect_robot,
    erd_robot_names,
    load_robot,
    models_dir,
    pick_robot,
    resolve_robot,
    robot_choices,
    unknown_joint_message,
)

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
