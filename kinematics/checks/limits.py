"""MT302 position limits, and the real robot's rules where the spec has them (nao-v5): MT305
the HeadPitch range that depends on HeadYaw, MT306 joints one motor drives.

Webots clamps a target outside ``[minPosition, maxPosition]`` to the range (and warns at every
step). Limits are reported on the value as written (MT302); the real robot's rules check the
clamped value, what the robot actually does, so one bad value is not reported twice.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from motiontool.kinematics.checks._table import (
    EPS,
    GroupingCheck,
    PoseRuns,
    Table,
    cell,
    fmt_name,
    fmt_num,
    fmt_span,
    pose_runs,
)
from motiontool.kinematics.robots import JointSpec
from motiontool.motionfmt.diagnostics import (
    BEYOND_LIMITS,
    COUPLED_JOINTS,
    HEAD_PITCH_RANGE,
    Diagnostic,
    PoseFinding,
    Severity,
    Worst,
)
from motiontool.motionfmt.findings import Findings, in_order
from motiontool.motionfmt.grouping import group_findings, run_finding
from motiontool.motionfmt.reader import ReadResult

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

__all__ = ["COUPLING_TOLERANCE", "Limits"]

COUPLING_TOLERANCE = 1e-3
"""Largest difference (rad) between two joints one motor drives on the real robot (nao-v5).

The ROS naoV50 URDF makes the finger joints follow the hand with a multiplier of 0.999899, a
difference of 1e-4 rad at most over their [0, 1] range; 1e-3 rad also allows values written with
3 decimals. Anything larger cannot be played by one motor."""


class Limits(GroupingCheck):
    """MT302 position limits, and the real robot's rules where the spec has them (nao-v5):
    MT305 the HeadPitch range that depends on HeadYaw, MT306 joints one motor drives."""

    def _check(self, result: ReadResult, *, group: bool) -> Findings:
        import numpy as np

        table = self.table(result)
        if not table.motors:
            return Findings.of([])
        joints = [self.spec.joints[m] for m in table.motors]
        lower = np.array([j.lower for j in joints])
        upper = np.array([j.upper for j in joints])
        values = table.values
        with np.errstate(invalid="ignore"):
            below = values < lower
            outside = below | (values > upper)
        if group:
            parts: list[Sequence[Diagnostic]] = [self._beyond_runs(table, joints, below, outside)]
        else:
            poses, ks = np.nonzero(outside)
            lows = below[poses, ks]  # gathered: no (P, K) array is kept

            def beyond(i: int) -> Diagnostic:
                k = int(ks[i])
                return self._beyond(table, int(poses[i]), k, joints[k], bool(lows[i]))

            parts = [in_order(poses, table.source[poses, ks], beyond)]
        if self.spec.head_pitch_envelope or self.spec.coupled_joints:
            held, commanded = self._configuration(table, lower, upper)
            for per_pose in (
                self._head_envelope(table, held, commanded, outside),
                self._coupled(table, held, commanded),
            ):
                parts.append(group_findings(per_pose) if group else per_pose)
        return Findings.merge(parts)

    def _beyond(self, table: Table, pose: int, k: int, joint: JointSpec, low: bool) -> Diagnostic:
        """MT302 on motor ``k``'s cell at ``pose``, below its lower limit if ``low``."""
        value = float(table.values[pose, k])
        bound = joint.lower if low else joint.upper
        where = "below its lower" if low else "above its upper"
        u = joint.unit
        rng = f"[{fmt_num(joint.lower)}, {fmt_num(joint.upper)}] {u}"
        hint = (
            f"the real robot's range is {rng} (robot {self.spec.name})"
            if self.spec.overrides_path is not None
            else f"Webots clamps the target to the motor's range {rng}, and warns"
        )
        name = fmt_name(joint.name)
        return cell(
            table,
            BEYOND_LIMITS,
            Severity.ERROR,
            pose,
            table.col(pose, k),
            f"{name} = {fmt_num(value)} {u} at {int(table.times[pose])} ms is "
            f"{where} limit {fmt_num(bound)} {u} by {fmt_num(abs(value - bound))} {u}",
            hint,
            grouping=PoseFinding(
                pose, f"{name} {where} limit {fmt_num(bound)} {u}", value, u, abs(value - bound)
            ),
        )

    def _beyond_runs(
        self,
        table: Table,
        joints: list[JointSpec],
        below: npt.NDArray[np.bool_],
        outside: npt.NDArray[np.bool_],
    ) -> Findings:
        """MT302 grouped: one finding per run of consecutive poses of a motor on one side of
        its limits (:func:`~motiontool.motionfmt.grouping.run_finding`), made when read."""
        import numpy as np

        found = []  # PoseRuns and (motor, below) arrays, a set per motor and side
        for k, joint in enumerate(joints):
            for low, bound in ((True, joint.lower), (False, joint.upper)):
                mask = below[:, k] if low else outside[:, k] & ~below[:, k]
                if mask.any():
                    runs = pose_runs(mask, np.abs(table.values[:, k] - bound))
                    found.append(
                        (*runs, np.full(runs.first.shape, k), np.full(runs.first.shape, low))
                    )
        if not found:
            return Findings.of([])
        first, last, worst, count, n_runs, ks, lows = (
            np.concatenate(a) for a in zip(*found, strict=True)
        )

        def beyond_run(i: int) -> Diagnostic:
            k = int(ks[i])
            run = PoseRuns(first[i], last[i], worst[i], count[i], n_runs[i])
            return self._beyond_run(table, joints[k], k, bool(lows[i]), run)

        return in_order(first, table.source[first, ks], beyond_run)

    def _beyond_run(
        self, table: Table, joint: JointSpec, k: int, low: bool, run: PoseRuns
    ) -> Diagnostic:
        """MT302 on motor ``k`` over the poses of ``run`` (one run's scalars) on one side of
        its limits (below if ``low``): one finding, grouped if it covers more than a pose."""
        first, last, worst = int(run.first), int(run.last), int(run.worst)
        d = self._beyond(table, first, k, joint, low)
        if run.size == 1:
            return d
        span = table.result.cell_span
        line, column, _end = span(worst, table.col(worst, k))
        value = float(table.values[worst, k])
        w = Worst(value, joint.unit, line, column, int(table.times[worst]))
        last_line = span(last, table.col(last, k))[0]
        return run_finding(d, int(run.size), last_line, w, runs=int(run.runs))

    @staticmethod
    def _configuration(
        table: Table, lower: npt.NDArray[np.float64], upper: npt.NDArray[np.float64]
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.bool_]]:
        """(held targets clamped to the limits, 0 before a first command) (P, K), and which
        motors are commanded (P, K)."""
        import numpy as np

        held = np.clip(table.held, lower, upper)
        return np.nan_to_num(held, nan=0.0), table.commanded

    def _names(self, table: Table) -> list[str]:
        return [self.spec.joints[m].name for m in table.motors]

    def _head_envelope(
        self,
        table: Table,
        held: npt.NDArray[np.float64],
        commanded: npt.NDArray[np.bool_],
        outside: npt.NDArray[np.bool_],
    ) -> list[Diagnostic]:
        """MT305: HeadPitch outside the real robot's range at the HeadYaw it holds, where
        MT302 (``outside`` (P, K)) does not already report that cell."""
        import numpy as np

        names = self._names(table)
        k_pitch = names.index("HeadPitch") if "HeadPitch" in names else None
        k_yaw = names.index("HeadYaw") if "HeadYaw" in names else None
        if not self.spec.head_pitch_envelope or (k_pitch is None and k_yaw is None):
            return []
        zeros = np.zeros(held.shape[0])
        pitch = held[:, k_pitch] if k_pitch is not None else zeros
        yaw = held[:, k_yaw] if k_yaw is not None else zeros
        rows = np.array(self.spec.head_pitch_envelope)
        lo = np.interp(yaw, rows[:, 0], rows[:, 1])
        hi = np.interp(yaw, rows[:, 0], rows[:, 2])
        # The MT302 cells of the two head motors, as (line, joint): one bad value, one finding.
        flagged = {
            (table.result.cell_span(int(p), table.col(int(p), k))[0], names[k])
            for k in (k_pitch, k_yaw)
            if k is not None
            for p in np.flatnonzero(outside[:, k])
        }
        any_command = np.zeros(held.shape[0], dtype=bool)
        for k in (k_pitch, k_yaw):
            if k is not None:
                any_command |= commanded[:, k]
        out = []
        for pose in np.flatnonzero(any_command & ((pitch < lo) | (pitch > hi))):
            on_pitch = k_pitch is not None and bool(commanded[pose, k_pitch])
            k = k_pitch if on_pitch else k_yaw
            if k is None:
                continue  # unreachable: any_command holds for one of the two
            col = table.col(int(pose), k)
            line = table.result.cell_span(int(pose), col)[0]
            if (line, table.result.joints[col]) in flagged:
                continue  # already outside the fixed range: reported once
            envelope = (float(lo[pose]), float(hi[pose]))
            out.append(
                self._envelope_error(table, int(pose), col, pitch[pose], yaw[pose], envelope)
            )
        return out

    @staticmethod
    def _envelope_error(
        table: Table, pose: int, col: int, pitch: float, yaw: float, envelope: tuple[float, float]
    ) -> Diagnostic:
        """MT305 on ``col``'s cell at ``pose``: ``pitch`` outside ``envelope`` (rad) at ``yaw``."""
        p, y = float(pitch), float(yaw)
        lo, hi = envelope
        bound = lo if p < lo else hi
        where = "below" if p < lo else "above"
        return cell(
            table,
            HEAD_PITCH_RANGE,
            Severity.ERROR,
            pose,
            col,
            f"HeadPitch = {fmt_num(p)} rad at HeadYaw = {fmt_num(y)} rad "
            f"({int(table.times[pose])} ms) is {where} {fmt_num(bound)} rad, the real "
            f"robot's limit at that yaw, by {fmt_num(abs(p - bound))} rad",
            f"at HeadYaw = {fmt_num(y)} rad the real NAO's head pitches within "
            f"[{fmt_num(lo)}, {fmt_num(hi)}] rad (its shell hits the shoulders beyond)",
            grouping=PoseFinding(
                pose,
                f"HeadPitch {where} the real robot's limit at the HeadYaw it holds",
                p,
                "rad",
                abs(p - bound),
                hint="the real NAO's head pitch range narrows as HeadYaw turns (its shell "
                "hits the shoulders beyond)",
            ),
        )

    def _coupled(
        self, table: Table, held: npt.NDArray[np.float64], commanded: npt.NDArray[np.bool_]
    ) -> list[Diagnostic]:
        """MT306: joints one motor drives on the real robot, at different values."""
        followers: dict[str, list[str]] = {}
        for leader, follower in self.spec.coupled_joints:
            followers.setdefault(leader, []).append(follower)
        names = self._names(table)
        out = []
        for leader, group in followers.items():
            members = [leader, *group]
            if any(m in names for m in members):  # else the motion never commands this motor
                ks = [names.index(m) if m in names else None for m in members]
                out.extend(_Coupling(table, members, ks, held, commanded).diagnostics())
        return out


class _Coupling:
    """One motor of the real robot that drives ``members`` (the leader first), against the
    table's motors ``ks`` (None: a member the file does not name, held at 0)."""

    def __init__(
        self,
        table: Table,
        members: list[str],
        ks: list[int | None],
        held: npt.NDArray[np.float64],
        commanded: npt.NDArray[np.bool_],
    ) -> None:
        import numpy as np

        n_poses = held.shape[0]
        self.table, self.members, self.ks = table, members, ks
        self.q = np.stack([held[:, k] if k is not None else np.zeros(n_poses) for k in ks], 1)
        self.cmd = np.stack(
            [commanded[:, k] if k is not None else np.zeros(n_poses, bool) for k in ks], 1
        )

    def diagnostics(self) -> list[Diagnostic]:
        import numpy as np

        off = np.abs(self.q[:, 1:] - self.q[:, :1]) > COUPLING_TOLERANCE + EPS
        return [
            self._differ(int(pose), [1 + int(i) for i in np.flatnonzero(off[pose])])
            for pose in np.flatnonzero(off.any(axis=1) & self.cmd.any(axis=1))
        ]

    def _column(self, pose: int, first: int) -> int | None:
        """The file column to point at: the first differing member's, else the first commanded
        member's at ``pose`` (None: the time token)."""
        members = range(1, len(self.members))
        at = next((i for i in (first, 0, *members) if self.cmd[pose, i]), first)
        k = self.ks[at]
        return self.table.col(pose, k) if k is not None else None

    def _differ(self, pose: int, differing: list[int]) -> Diagnostic:
        """MT306 at ``pose``: the members at indices ``differing`` are off the leader's value."""
        members, q = self.members, self.q
        lead = float(q[pose, 0])
        spread = float(abs(q[pose, 1:] - lead).max())
        shown = ", ".join(
            f"{fmt_name(members[i])} = {fmt_num(float(q[pose, i]))}" for i in differing
        )
        if len(members) > 2:  # fingers: the real hand opens and closes as one
            names = fmt_span(members)
            severity = Severity.WARNING
            what = (
                f"the real robot's hand has one motor for {names}: it opens "
                "and closes all the fingers together"
            )
        else:
            names = " and ".join(members)
            severity = Severity.ERROR
            what = f"one motor drives {names} on the real robot"
        return cell(
            self.table,
            COUPLED_JOINTS,
            severity,
            pose,
            self._column(pose, differing[0]),
            f"{shown} rad at {int(self.table.times[pose])} ms "
            f"{'differ' if len(differing) > 1 else 'differs'} from "
            f"{fmt_name(members[0])} = {fmt_num(lead)} rad by up to {fmt_num(spread)} rad: {what}",
            f"write the same value in the {len(members)} columns"
            + ("" if None not in self.ks else " (a joint missing from the file sits at 0)"),
            grouping=PoseFinding(pose, f"{names} at different values", spread, "rad", spread),
        )
