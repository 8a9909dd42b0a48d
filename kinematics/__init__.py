"""Robot models and kinematics: joint limits, forward kinematics, self-collision, balance.

Importing this package is cheap: Pinocchio (and numpy) are imported only when a function that
needs them runs, so looking up a built-in robot's joint table never loads them.
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
from motiontool.kinematics.robots import (
    JointSpec,
    RobotSpec,
    builtin_robots,
    detect_robot,
    erd_robot_names,
    load_robot,
    models_dir,
    unknown_joint_message,
)

__all__ = [
    "Balance",
    "JointSpec",
    "RobotSpec",
    "body_positions",
    "build_model",
    "builtin_robots",
    "com_and_support",
    "detect_robot",
    "erd_robot_names",
    "load_robot",
    "models_dir",
    "self_collision_depths",
    "self_collisions",
    "sole_heights",
    "unknown_joint_message",
]
