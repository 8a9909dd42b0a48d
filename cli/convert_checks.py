"""The robot checks of ``motiontool convert``: every export is checked against the robot before
anything is written.

The motion is checked as ``validate`` checks it (unknown joints MT301, limits MT302/MT305/MT306,
velocities MT303/MT304 at the control step), on the input file itself for a ``.motion`` and on
the motion it holds for the other formats, each finding placed at the input's line and column
(a CSV row has the line its pose would have in a ``.motion``; a ``.npz`` has no lines: the pose
and joint are named). An error stops the export; so does a warning when the file drives a real
robot. An unknown joint is one error at its header cell where the robot was named or the file
drives a robot (:func:`refuse_unknown_joints`). What the export sends (a URScript's
``servoj`` targets, NAOqi's keys as NAOqi interpolates them) is checked too: within the limits,
and no faster than maxVelocity from one target to the next, with validate's slack for float
rounding (:data:`~motiontool.kinematics.checks.EPS`).
"""

from __future__ import annotations

import enum
import math
from typing import TYPE_CHECKING

from motiontool.errors import MotionSyntaxError, MotionToolError
from motiontool.kinematics.checks import COUPLING_TOLERANCE, EPS, Limits, UnknownJoints, Velocity
from motiontool.kinematics.robots import RobotSpec, fmt_name, unknown_joint_message
from motiontool.motionfmt.convert.base import Imported, Recording, RobotStream
from motiontool.motionfmt.convert.joint_map import disagreement, to_ros
from motiontool.motionfmt.diagnostics import Diagnostic, Severity
from motiontool.motionfmt.reader import read_bytes
from motiontool.motionfmt.units import MS_PER_S
from motiontool.motionfmt.validate import run_check
from motiontool.motionfmt.writer import format_motion

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.motionfmt.motion import Motion

__all__ = [
    "ArmLimits",
    "beyond_max_error",
    "cell_at",
    "file_findings",
    "motion_findings",
    "real_arm_findings",
    "refuse_short_lead_in",
    "refuse_split_joints",
    "refuse_unknown_joints",
    "robot_limits",
    "stream_findings",
]


class ArmLimits(enum.StrEnum):
    """What a program for a real arm is checked against: the real arm's limits, or the
    Webots model's."""

    REAL = "real"
    WEBOTS = "webots"


def _where(d: Diagnostic, imported: Imported, motion: Motion) -> str:
    """``path:line:col`` of a finding in the input file (a synthetic .motion's pose line is
    the CSV row's line), or ``path: pose N (T ms)`` where the format has no lines."""
    if imported.cells is None and imported.read is not None:
        return f"{d.path}:{d.line}:{d.column}"
    pose = d.line - 2
    joint = motion.column(d.joint) if d.joint in motion.joints else None
    if imported.cells is not None and imported.header is not None and joint is not None:
        if pose < 0:
            return f"{imported.path}:1:{int(imported.header[joint])}"
        line, col = (int(x) for x in imported.cells[pose, joint])
        return f"{imported.path}:{line}:{col}"
    if pose < 0:
        return f"{imported.path}: header"
    return f"{imported.path}: pose {pose} ({int(motion.times_ms[pose])} ms)"


def refuse_unknown_joints(imported: Imported, spec: RobotSpec) -> None:
    """Raise at the first joint of the input that is not a motor of ``spec``: one line at its
    header cell (``wave.csv:1:9: unknown joint 'HeadYw' for robot nao; did you mean
    'HeadYaw'?``), or naming the file where the format has no lines (``.npz``)."""
    for j, name in enumerate(imported.motion.joints):
        if name in spec:
            continue
        message = unknown_joint_message(fmt_name(name), spec)
        if imported.read is not None:
            column = imported.read.header_spans()[j][0]
            raise MotionSyntaxError(message, imported.path, 1, column)
        if imported.header is not None:
            raise MotionSyntaxError(message, imported.path, 1, int(imported.header[j]))
        raise MotionToolError(f"'{imported.path}': {message}")


def cell_at(imported: Imported, pose: int, j: int | None) -> tuple[int, int] | None:
    """(line, column) in the input of motion column ``j``'s cell at ``pose`` (of its time where
    None: a CSV row's first column), or None where the format has no lines (``.npz``, a
    bag)."""
    if imported.read is not None:
        line, col, _ = imported.read.cell_span(pose, j)
        return line, col
    if imported.cells is not None:
        line, col = (int(x) for x in imported.cells[pose, 0 if j is None else j])
        return line, 1 if j is None else col
    return None


def _cell_error(imported: Imported, pose: int, j: int, message: str) -> MotionToolError:
    """``message`` at the input's cell of motion column ``j`` at ``pose`` (``path:line:col``),
    or naming the pose where the format has no lines (``.npz``, a bag)."""
    at = cell_at(imported, pose, j)
    if at is not None:
        return MotionSyntaxError(message, imported.path, *at)
    return MotionToolError(f"'{imported.path}': pose {pose}: {message}")


def refuse_split_joints(imported: Imported, joint_map: tuple[tuple[str, str], ...]) -> None:
    """Raise where joints that go to one ROS name (a Nao's phalanges to ``LHand``, a joint
    map's many-to-one) differ by more than the real NAO's coupling tolerance
    (:data:`~motiontool.kinematics.checks.COUPLING_TOLERANCE`): a ROS joint has one position.
    One error at the first cell that differs (``grip.motion:3:42: LPhalanx7 = 0.1 rad at 400
    ms is not LPhalanx1's 0.8 rad: ...``)."""
    motion = imported.motion
    names = to_ros(motion.joints, joint_map)
    found = disagreement(motion.values, names, COUPLING_TOLERANCE + EPS)
    if found is None:
        return
    pose, lead, j = found

    def value(k: int) -> str:
        v = float(motion.values[pose, k])
        return "*" if math.isnan(v) else f"{v:.6g} rad"

    a, b = fmt_name(motion.joints[j]), fmt_name(motion.joints[lead])
    raise _cell_error(
        imported,
        pose,
        j,
        f"{a} = {value(j)} at {int(motion.times_ms[pose])} ms is not {b}'s {value(lead)}: "
        f"both go to ROS joint {fmt_name(names[j])!r}, which has one position; keep them apart "
        f'in --joint-map ({a} = "{a}")',
    )


def file_findings(imported: Imported) -> list[str]:
    """What ``validate`` finds in a ``.motion`` input as it reads it (a joint named twice,
    MT205, ...), one ``where: severity CODE: message`` line each, in file order; none for the
    other formats (their readers refuse what they cannot hold). Never blocking: Webots plays
    the file, and the export sends what it plays."""
    if imported.read is None:
        return []
    return [
        f"{d.path}:{d.line}:{d.column}: {d.severity} {d.code}: {d.message}"
        for d in imported.read.diagnostics
    ]


def refuse_short_lead_in(motion: Motion, spec: RobotSpec, lead_in_ms: int, option: str) -> None:
    """Raise where the real robot cannot reach the first pose in ``lead_in_ms`` (ms) plus the
    first pose's time at its joints' maxVelocity, from where the checks take a motor to start
    (0, as every motor of the Webots models starts), as the motion itself is checked; the
    message gives the shortest lead-in that can (whole ms)."""
    worst: tuple[float, str, float, str] | None = None  # (ms needed, joint, maxVelocity, unit)
    first = motion.values[0]
    for j, name in enumerate(motion.joints):
        q = float(first[j])
        if name not in spec or math.isnan(q):
            continue
        joint = spec.joint(name)
        if not math.isfinite(joint.max_velocity) or joint.max_velocity <= 0:
            continue
        needed = abs(q) / joint.max_velocity * MS_PER_S
        if worst is None or needed > worst[0]:
            worst = (needed, name, joint.max_velocity, joint.unit)
    start_ms = int(motion.times_ms[0])  # the export's first time: this plus the lead-in
    if worst is None or (lead_in_ms + start_ms) * (1 + EPS) >= worst[0]:
        return
    needed, name, velocity, unit = worst
    shortest = math.ceil(needed / (1 + EPS)) - start_ms
    raise MotionToolError(
        f"{option} {lead_in_ms} ms: robot {spec.name} cannot reach the first pose in it from "
        f"where its motors start (0 {unit}): {fmt_name(name)} needs {needed:.3g} ms at its "
        f"maxVelocity {velocity:.6g} {unit}/s; give {option} {shortest} "
        "or more"
    )


def motion_findings(
    imported: Imported, spec: RobotSpec, timestep_ms: int, *, for_robot: bool
) -> tuple[list[str], list[str]]:
    """validate's limit, velocity and joint checks on the motion to export, their findings
    grouped as validate groups them by default (a run of one code on one joint is one).

    Returns:
        (blocking, other): one ``where: severity CODE: message`` line per finding; blocking
        ones stop the export (errors, and warnings when ``for_robot``).
    """
    motion = imported.motion
    source = imported.read
    if source is None:
        text = format_motion(motion).encode("utf-8", "surrogateescape")
        source = read_bytes(text, imported.path)
    blocking: list[str] = []
    other: list[str] = []
    for check in (UnknownJoints(spec), Limits(spec), Velocity(spec, timestep_ms)):
        for d in run_check(check, source, group=True):  # grouped, as validate reports them
            line = f"{_where(d, imported, motion)}: {d.severity} {d.code}: {d.message}"
            stops = d.severity is Severity.ERROR or (for_robot and d.severity is Severity.WARNING)
            (blocking if stops else other).append(line)
    return blocking, other


def beyond_max_error(r: Recording | None, option: str) -> list[str]:
    """One line where the motion made of a recording is farther from it than ``option``
    (``--max-error``) allows though every sample on a whole ms was kept; else none."""
    if r is None or r.within():
        return []
    d = r.deviation
    return [
        f"{option} {r.max_error_rad:.6g} rad: every sample kept, the motion is "
        f"{d.max_rad:.6g} rad from {r.against} ({d.joint} at {d.at_ms} ms)"
    ]


def robot_limits(limits: ArmLimits | None, spec: RobotSpec | None, option: str) -> RobotSpec | None:
    """The robot a program for a real arm is checked against: the real arm
    (:func:`~motiontool.kinematics.real_ur5e.real_arm`) where ``limits`` is ``real``, or is
    None and the real arm is known; else ``spec`` (the Webots model's limits)."""
    from motiontool.kinematics.real_ur5e import REAL_ARMS, real_arm

    if spec is None or limits is ArmLimits.WEBOTS:
        return spec
    if spec.name in REAL_ARMS:
        return real_arm(spec)
    if limits is ArmLimits.REAL:
        known = ", ".join(sorted(REAL_ARMS))
        raise MotionToolError(
            f"{option} real: the real arm's limits are known for {known}, not for robot "
            f"{spec.name}; give {option} webots to check against its model"
        )
    return spec


def real_arm_findings(
    stream: RobotStream, keyframes: bool, timestep_ms: int, what: str
) -> list[str]:
    """What a URScript program asks of the real arm beyond its speed, acceleration and
    control cycle (:mod:`motiontool.kinematics.real_ur5e`): ``movej``'s trapezoids with
    ``keyframes``, else the ``servoj`` stream's accelerations and ``t``."""
    from motiontool.kinematics.real_ur5e import movej_findings, servoj_findings

    if keyframes:
        return movej_findings(stream, what)
    return servoj_findings(stream, timestep_ms, what)


def stream_findings(stream: RobotStream, spec: RobotSpec, what: str) -> list[str]:
    """What the export sends, against ``spec``: every target within the joint's limits and
    reached from the previous one no faster than maxVelocity. One line per joint at fault,
    naming its first target out of its limits and its fastest move (the first of them), with
    their times (ms of Webots' playback time). The stream is read a chunk at a time."""
    joints = [_JointStream(name, spec) for name in stream.joints]
    for times_ms, targets in stream.chunks():
        for k, joint in enumerate(joints):
            joint.update(times_ms, targets[:, k])
    return [line for joint in joints for line in joint.lines(what, spec)]


class _JointStream:
    """One joint's column of a stream, seen a chunk of rows at a time: its first target out
    of its limits and its fastest move between two consecutive rows that both send one."""

    def __init__(self, name: str, spec: RobotSpec) -> None:
        self.name = name
        self.joint = spec.joint(name) if name in spec else None
        self.beyond: tuple[float, int] | None = None  # (target, time ms)
        self.fastest: tuple[float, int, int] | None = None  # (rad/s, from ms, to ms)
        self.last: tuple[float, int] | None = None  # the previous chunk's last row (NaN: none)

    def update(self, times_ms: npt.NDArray[np.int64], q: npt.NDArray[np.float64]) -> None:
        """Take the rows ``times_ms`` (S,), targets ``q`` (S,) (rad, m; NaN: none sent)."""
        import numpy as np

        joint = self.joint
        if joint is None or q.shape[0] == 0:
            return
        sent = ~np.isnan(q)
        if self.beyond is None:
            with np.errstate(invalid="ignore"):
                beyond = sent & ((q < joint.lower - EPS) | (q > joint.upper + EPS))
            if beyond.any():
                i = int(np.argmax(beyond))
                self.beyond = (float(q[i]), int(times_ms[i]))
        if math.isfinite(joint.max_velocity):
            if self.last is not None:  # the move from the previous chunk's last row
                q = np.concatenate(([self.last[0]], q))
                times_ms = np.concatenate(([self.last[1]], times_ms))
                sent = ~np.isnan(q)
            self._moves(times_ms, q, sent, joint.max_velocity)
        self.last = (float(q[-1]), int(times_ms[-1]))

    def _moves(
        self,
        times_ms: npt.NDArray[np.int64],
        q: npt.NDArray[np.float64],
        sent: npt.NDArray[np.bool_],
        max_velocity: float,
    ) -> None:
        import numpy as np

        if q.shape[0] < 2:
            return
        t = times_ms.astype(np.float64) / MS_PER_S
        both = sent[1:] & sent[:-1]
        with np.errstate(invalid="ignore", divide="ignore"):
            speed = np.where(both, np.abs(np.diff(q)) / np.diff(t), 0.0)
        fast = speed > max_velocity * (1 + EPS)
        if fast.any():
            i = int(np.argmax(np.where(fast, speed, -1.0)))
            if self.fastest is None or speed[i] > self.fastest[0]:  # the first of the fastest
                self.fastest = (float(speed[i]), int(times_ms[i]), int(times_ms[i + 1]))

    def lines(self, what: str, spec: RobotSpec) -> list[str]:
        """The report's lines for this joint (none when it is at no fault)."""
        joint = self.joint
        if joint is None:
            return [f"{what}: {self.name} is not a motor of robot {spec.name}"]
        out = []
        if self.beyond is not None:
            value, at = self.beyond
            out.append(
                f"{what}: {self.name} = {value!r} {joint.unit} at {at} ms is "
                f"outside [{joint.lower:.6g}, {joint.upper:.6g}] {joint.unit}"
            )
        if self.fastest is not None:
            speed, a, b = self.fastest
            out.append(
                f"{what}: {self.name} moves at {speed:.6g} {joint.unit}/s from "
                f"{a} ms to {b} ms, faster than its "
                f"maxVelocity {joint.max_velocity:.6g} {joint.unit}/s"
            )
        return out
