"""MT308: static balance at keyframes (the centre of mass against the feet's support polygon)."""

from __future__ import annotations

from motiontool.extras import require
from motiontool.kinematics.checks._table import RobotCheck, Table, cell, configurations, runs
from motiontool.motionfmt.diagnostics import OFF_BALANCE, Diagnostic, Severity
from motiontool.motionfmt.reader import ReadResult

__all__ = ["Balance"]


class Balance(RobotCheck):
    """MT308: static balance at keyframes (centre of mass against the feet's support polygon)."""

    def __call__(self, result: ReadResult) -> list[Diagnostic]:
        from motiontool.kinematics._pinocchio import com_and_support

        require("pinocchio", "kinematics", "the balance check")
        table = self.table(result)
        if not table.motors:
            return []
        q, _times = configurations(table, self.spec)
        names = self.spec.joint_names
        margins = [
            com_and_support(self.spec, dict(zip(names, row.tolist(), strict=True))).margin_mm
            for row in q[0::2]
        ]
        outside = [p for p, m in enumerate(margins) if m < 0.0]
        return [_outside(table, margins, run) for run in runs(outside, 1)]


def _outside(table: Table, margins: list[float], run: list[int]) -> Diagnostic:
    """MT308 for the consecutive poses ``run`` whose centre of mass is outside the support
    polygon (``margins``: each pose's distance inside it, mm)."""
    worst = min(run, key=lambda p: margins[p])
    span = (
        ""
        if len(run) == 1
        else f"; outside from {int(table.times[run[0]])} ms to {int(table.times[run[-1]])} ms"
    )
    return cell(
        table,
        OFF_BALANCE,
        Severity.WARNING,
        worst,
        None,
        f"centre of mass {-margins[worst]:.1f} mm outside the support polygon of the "
        f"feet at {int(table.times[worst])} ms (pose "
        f"'{table.result.pose_names[worst]}'){span}",
        "a static estimate with the torso upright and the lowest foot on the floor: "
        "held still in this pose the robot tips over; a dynamic move may still pass",
    )
