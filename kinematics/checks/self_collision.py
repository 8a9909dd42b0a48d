"""MT307: self-collision of the robot's bodies at every keyframe and segment midpoint."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from motiontool.errors import MissingExtraError
from motiontool.extras import require_installed
from motiontool.kinematics.checks._table import (
    GroupingCheck,
    Table,
    cell,
    configurations,
    fmt_ms,
    runs,
)
from motiontool.kinematics.checks.registry import DEFAULT_PENETRATION_TOLERANCE_MM, CheckOptions
from motiontool.kinematics.robots import RobotSpec
from motiontool.motionfmt.diagnostics import SELF_COLLISION, Diagnostic, Severity
from motiontool.motionfmt.findings import Findings, in_order
from motiontool.motionfmt.grouping import MAX_RUNS
from motiontool.motionfmt.reader import ReadResult
from motiontool.motionfmt.units import MM_PER_M

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.kinematics.distinct_rows import Known

__all__ = ["DEFAULT_PENETRATION_TOLERANCE_MM", "Collision"]

_POSES = 8192
"""Keyframes whose configurations (and the segment midpoints after them) are scanned at a time:
the arrays of a block, not of the whole file, are held (:func:`scan_self_collisions`)."""


class Collision(GroupingCheck):
    """MT307: self-collision at every keyframe and segment midpoint (one diagnostic per pair
    of bodies and run of consecutive checked instants; grouped, one per pair where it has more
    than :data:`~motiontool.motionfmt.grouping.MAX_RUNS` runs)."""

    def __init__(
        self, spec: RobotSpec, penetration_tolerance_mm: float = DEFAULT_PENETRATION_TOLERANCE_MM
    ) -> None:
        super().__init__(spec)
        self.tolerance_mm = penetration_tolerance_mm
        self._known: Known | None = None
        """The contacts at each configuration met (the first ones), by every motion this check
        scans: a cycle met again, or the rows an edit left as they were (``motiontool server``
        keeps its checks from one version to the next), are not scanned again."""

    @classmethod
    def for_run(cls, spec: RobotSpec, options: CheckOptions) -> Collision:
        """The check of ``spec`` with the run's tolerance."""
        return cls(spec, options.penetration_tolerance_mm)

    def _check(self, result: ReadResult, *, group: bool) -> Findings:
        import numpy as np

        from motiontool.kinematics.collision import Known, body_joints, scan_self_collisions

        # Pinocchio is imported only for the pairs numpy cannot clear (kinematics.collision).
        what = "the collision check"
        require_installed("pinocchio", "kinematics", what)
        table = self.table(result)
        if not table.motors:
            return Findings.of([])
        n_poses = table.times.shape[0]
        times = np.empty(2 * n_poses - 1)
        by_pair: dict[tuple[str, str], dict[int, float]] = {}
        if self._known is None:
            self._known = Known()
        known = self._known
        for lo in range(0, n_poses, _POSES):  # configuration 2 * lo is the block's first
            q, times[2 * lo : 2 * lo + 2 * _POSES] = configurations(
                table, self.spec, lo, lo + _POSES
            )
            try:
                contacts = scan_self_collisions(
                    self.spec,
                    q,
                    penetration_tolerance_m=self.tolerance_mm / MM_PER_M,
                    fingers_in_hand=True,
                    known=known,
                )
            except MissingExtraError as exc:  # installed, but it (or coal) fails to import
                raise MissingExtraError(exc.module, exc.extra, what, exc.library) from exc
            for c in contacts:
                by_pair.setdefault((c.body_a, c.body_b), {})[2 * lo + c.config] = c.depth_m
            del contacts
        found = []
        for pair, depths in sorted(by_pair.items()):
            each = runs(sorted(depths), 1)
            if group and len(each) > MAX_RUNS:  # one finding for them all
                found.append((pair, depths, [i for run in each for i in run], len(each)))
            else:
                found.extend((pair, depths, run, 1) for run in each)
        at = [(max(run, key=depths.__getitem__) + 1) // 2 for _pair, depths, run, _n in found]
        joints = body_joints(self.spec, fingers_in_hand=True) if found else {}
        return in_order(
            np.array(at, dtype=np.intp),
            np.full(len(at), -1),
            lambda i: self._overlap(table, times, joints, *found[i]),
        )

    def _overlap(
        self,
        table: Table,
        times: npt.NDArray[np.float64],
        joints: dict[str, str | None],
        pair: tuple[str, str],
        depths: dict[int, float],
        run: list[int],
        n_runs: int = 1,
    ) -> Diagnostic:
        """MT307 for the bodies ``pair`` overlapping over the checked instants ``run`` (indices
        in ``times``, ms; consecutive, or ``n_runs`` runs of them), by ``depths`` (m) at
        each; each body named with the motor that carries it (``joints``), the joint a user
        edits."""
        deepest = max(run, key=lambda i: depths[i])
        depth_mm = depths[deepest] * MM_PER_M
        at = self._instant(table, times, deepest)
        start, end = fmt_ms(times[run[0]]), fmt_ms(times[run[-1]])
        span = "" if len(run) == 1 else f"; they overlap from {start} to {end}"
        if n_runs > 1:
            span = (
                f"; they overlap at {len(run):,} instants in {n_runs:,} runs, from {start} to {end}"
            )
        a, b = (_body(joints.get(body), body) for body in pair)
        return cell(
            table,
            SELF_COLLISION,
            Severity.WARNING,
            (deepest + 1) // 2,
            None,
            f"{a} and {b} overlap by {depth_mm:.1f} mm at {at}{span}",
            f"overlaps under {self.tolerance_mm:g} mm are ignored as artefacts of the "
            "coarse collision shapes; a simulator with self-collision off lets the "
            f"bodies pass through each other, the real {self.spec.name} does not",
            time_ms=math.floor(times[deepest]),
        )

    @staticmethod
    def _instant(table: Table, times: npt.NDArray[np.float64], index: int) -> str:
        if index % 2 == 0:
            return f"{fmt_ms(times[index])} (pose '{table.result.pose_names[index // 2]}')"
        p = index // 2
        return (
            f"{fmt_ms(times[index])}, halfway from {int(table.times[p])} ms to "
            f"{int(table.times[p + 1])} ms"
        )


def _body(joint: str | None, body: str) -> str:
    """A body as MT307 names it: ``RWristYaw body 'r_hand'``, ``root body 'torso'``."""
    return f"{joint or 'root'} body '{body}'"
