"""MT301: header joints that are not motors of the robot (Webots ignores them, with a warning)."""

from __future__ import annotations

import difflib

from motiontool.kinematics.checks._table import (
    WordedCheck,
    fmt_name,
    header_diagnostic,
)
from motiontool.kinematics.robots import unknown_joint_message
from motiontool.motionfmt.diagnostics import UNKNOWN_JOINT, Diagnostic, Severity
from motiontool.motionfmt.reader import ReadResult

__all__ = ["UnknownJoints"]


class UnknownJoints(WordedCheck):
    """MT301: header joints that are not motors of the robot (Webots ignores them); the hint
    of a name with no close motor says how to name another robot, in the front end's words."""

    def __call__(self, result: ReadResult) -> list[Diagnostic]:
        return [
            self._unknown(result, j)
            for j, name in enumerate(result.joints)
            if name not in self.motor_index
        ]

    def _unknown(self, result: ReadResult, j: int) -> Diagnostic:
        spec = self.spec
        name = result.joints[j]
        close = difflib.get_close_matches(name, spec.joint_names, n=1)
        if close:
            message = unknown_joint_message(fmt_name(name), spec)
            hint = f"Webots ignores this column (with a warning); rename it '{close[0]}'"
        else:
            message = f"unknown joint '{fmt_name(name)}' for robot {spec.name}"
            hint = (
                f"Webots ignores this column (with a warning); robot {spec.name}'s motors: "
                + ", ".join(spec.joint_names)
                + f"; or {self.wording.name_robot('another')}"
            )
        return header_diagnostic(result, j, UNKNOWN_JOINT, Severity.WARNING, message, hint)
