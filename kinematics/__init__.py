"""Robot models and kinematics: joint limits, forward kinematics, self-collision, balance.

Importing this package is cheap: Pinocchio (and numpy) are imported only when a function that
needs them runs, so looking up a built-in robot's joint table never loads them.

``robot_checks`` / ``RobotChecks`` (:mod:`~motiontool.kinematics.checks`) are the robot checks of
``motiontool validate``; ``scan_self_collisions`` checks many configurations at once. The
robot side of the transforms is here too: a robot's mirror map (:mod:`.mirror`) and the fixes
that need a robot (:mod:`.robot_fixes`).

May import ``motionfmt`` and the top-level modules; Pinocchio only in :mod:`._pinocchio`; never
``sim`` or ``cli``.
"""

import importlib
import typing

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

#: Where each name beyond the robots' lives: imported on first use (PEP 562), so that
#: ``validate`` does not import the Pinocchio adapter's typed surface or the model exporter.
#: No name here is also a submodule's (``builtin_robots`` is both: imported above, the
#: function replaces the submodule as the package's attribute, as it always did).
_HOMES: dict[str, str] = {
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


def __getattr__(name: str) -> object:
    home = _HOMES.get(name)
    if home is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(home), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
