"""Robot checks for ``validate``: what a motion asks of a robot, against what the robot can do.

:func:`robot_checks` builds the :data:`~motiontool.motionfmt.validate.Check` callables that
:func:`motiontool.motionfmt.validate_paths` runs on every file Webots accepts;
:class:`RobotChecks` picks the robot per file (``robot='auto'``) or uses a named one. One check
per module (:mod:`.joints`, :mod:`.limits`, :mod:`.velocity`, :mod:`.self_collision`,
:mod:`.balance`, and :mod:`.unmirrored` for the unmirrored-copy note);
:mod:`.registry` lists them with the codes each reports (:data:`CHECK_REGISTRY`),
:mod:`.runner` picks and runs them.

How a motion is read here (the Webots player, ``docs/webots-format.md``):

* A column whose name is not a motor of the robot is ignored by Webots (with a warning): MT301.
* ``*`` sends no command: the joint holds its previous target. A ``*`` cell is never checked
  itself; where a check needs the whole robot's configuration (collision, balance, the real
  NAO's rules), a joint takes its last commanded target, and a joint that this motion has not
  commanded yet sits at its initial position, 0 (every motor of the Webots PROTOs starts at 0).
* Of two columns with one name (MT205), Webots sends both, in column order: the later column's
  command wins where it sends one, and the earlier one's reaches the motor where the later sends
  none (``*``). The checks check the cell the motor gets, of either column.
* Webots clamps a target outside ``[minPosition, maxPosition]`` to the range (and warns at every
  step). Limits are reported on the value as written (MT302); the configuration checks use the
  clamped value, what the robot actually does, so one bad value is not reported twice.

Limits and velocities are read from the :class:`~motiontool.kinematics.RobotSpec` alone: only
the collision and balance checks load Pinocchio, when they first run.

May import the rest of ``kinematics`` (its Pinocchio adapter inside functions), ``motionfmt``
and the top-level modules.
"""

from __future__ import annotations

import typing

from motiontool.lazy_names import lazy_names as _lazy_names

if typing.TYPE_CHECKING:
    from motiontool.kinematics.checks._table import EPS
    from motiontool.kinematics.checks.balance import Balance
    from motiontool.kinematics.checks.joints import UnknownJoints
    from motiontool.kinematics.checks.limits import COUPLING_TOLERANCE, Limits
    from motiontool.kinematics.checks.registry import (
        CHECK_REGISTRY,
        CHECKS,
        DEFAULT_CHECKS,
        DEFAULT_PENETRATION_TOLERANCE_MM,
        CheckEntry,
        parse_checks,
    )
    from motiontool.kinematics.checks.runner import CheckUnavailableError, RobotChecks, robot_checks
    from motiontool.kinematics.checks.self_collision import Collision
    from motiontool.kinematics.checks.velocity import Velocity
    from motiontool.kinematics.checks.wording import PLAIN_WORDING, Wording

#: Where each name lives: imported on first use (PEP 562), so that the registry's names
#: (``CHECKS``, ``parse_checks``: the ``--checks`` help) come without the checks themselves.
_HOMES: dict[str, str] = {
    "EPS": "motiontool.kinematics.checks._table",
    "Balance": "motiontool.kinematics.checks.balance",
    "UnknownJoints": "motiontool.kinematics.checks.joints",
    "COUPLING_TOLERANCE": "motiontool.kinematics.checks.limits",
    "Limits": "motiontool.kinematics.checks.limits",
    "CHECK_REGISTRY": "motiontool.kinematics.checks.registry",
    "CHECKS": "motiontool.kinematics.checks.registry",
    "DEFAULT_CHECKS": "motiontool.kinematics.checks.registry",
    "DEFAULT_PENETRATION_TOLERANCE_MM": "motiontool.kinematics.checks.registry",
    "CheckEntry": "motiontool.kinematics.checks.registry",
    "parse_checks": "motiontool.kinematics.checks.registry",
    "CheckUnavailableError": "motiontool.kinematics.checks.runner",
    "RobotChecks": "motiontool.kinematics.checks.runner",
    "robot_checks": "motiontool.kinematics.checks.runner",
    "Collision": "motiontool.kinematics.checks.self_collision",
    "Velocity": "motiontool.kinematics.checks.velocity",
    "PLAIN_WORDING": "motiontool.kinematics.checks.wording",
    "Wording": "motiontool.kinematics.checks.wording",
}

__all__ = [
    "CHECKS",
    "CHECK_REGISTRY",
    "COUPLING_TOLERANCE",
    "DEFAULT_CHECKS",
    "DEFAULT_PENETRATION_TOLERANCE_MM",
    "EPS",
    "PLAIN_WORDING",
    "Balance",
    "CheckEntry",
    "CheckUnavailableError",
    "Collision",
    "Limits",
    "RobotChecks",
    "UnknownJoints",
    "Velocity",
    "Wording",
    "parse_checks",
    "robot_checks",
]


__getattr__, __dir__ = _lazy_names(__name__, _HOMES)
