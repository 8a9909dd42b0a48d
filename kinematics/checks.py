"""Robot checks for ``validate``: what a motion asks of a robot, against what the robot can do.

:func:`robot_checks` builds the :data:`~motiontool.motionfmt.validate.Check` callables that
:func:`motiontool.motionfmt.validate_paths` runs on every file Webots accepts;
:class:`RobotChecks` picks the robot per file (``--robot auto``) or uses a named one.

How a motion is read here (the Webots player, ``../shared/FORMAT.md``):

* A column whose name is not a motor of the robot is ignored by Webots (with a warning): MT301.
  Of two columns with one name, the later drives the motor (MT205); the earlier is not checked.
* ``*`` sends no command: the joint holds its previous target. A ``*`` cell is never checked
  itself; where a check needs the whole robot's configuration (collision, balance, the real
  NAO's rules), a joint takes its last commanded target, and a joint that this motion has not
  commanded yet sits at its initial position, 0 (every motor of the Webots PROTOs starts at 0).
* Webots clamps a target outside ``[minPosition, maxPosition]`` to the range (and warns at every
  step). Limits are reported on the value as written (MT302); the configuration checks use the
  clamped value, what the robot actually does, so one bad value is not reported twice.

Limits and velocities are read from the :class:`~motiontool.kinematics.RobotSpec` alone: only
the collision and balance checks load Pinocchio, when they first run.
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from motiontool.kinematics.mirror_check import UnmirroredCopy
from motiontool.kinematics.robots import (
    AUTO,
    NONE,
    JointSpec,
    NoRobotDetectedError,
    RobotSpec,
    pick_robot,
    robot_choices,
    unknown_joint_message,
)
from motiontool.motionfmt.diagnostics import Diagnostic, Severity
from motiontool.motionfmt.errors import MissingExtraError, MotionToolError
from motiontool.motionfmt.extras import install_hint, require
from motiontool.motionfmt.player import hold_targets
from motiontool.motionfmt.reader import ReadResult

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

__all__ = [
    "CHECKS",
    "COUPLING_TOLERANCE",
    "DEFAULT_CHECKS",
    "DEFAULT_PENETRATION_TOLERANCE_MM",
    "RobotChecks",
    "parse_checks",
    "robot_checks",
]

#: Every check name, in the order they run.
CHECKS = ("limits", "velocity", "collision", "balance")
#: What ``validate`` runs unless told otherwise (balance is opt-in).
DEFAULT_CHECKS = ("limits", "velocity", "collision")

DEFAULT_PENETRATION_TOLERANCE_MM = 15.0
"""Self-collisions shallower than this (mm) are not reported.

The Webots robots' collision shapes are bounding primitives, larger than the bodies they stand
for: the Nao's forearm is a capsule, its foot force sensor a 147 x 89 mm box with sharp corners.
In the motions that ship with Webots (``tests/data/corpus/webots``), played as Webots plays them
(targets clamped to the motor limits), such shapes overlap by at most 10.0 mm: the two foot boxes
in the turns (TurnLeft40, TurnRight40, TurnLeft180), the head capsule and an arm raised within
its limits by 7.2 mm (HandWaveLeft, HandsUp) and 6.3 mm (HandHighLeft, HandWave). Those motions
are how the robot is meant to move, so overlaps of that size are artefacts of the shapes. (Left
unclamped, HandWaveLeft's LShoulderRoll of -0.5 rad, past the -0.314 rad limit, would put the
elbow 25 mm into the head: that value is reported as a limit error instead.) Bodies that really
meet go deeper: a hand saluting at the forehead 25 mm into the head, a right forearm folded
across the belly 33 mm into the torso, its hand 49 mm. 15 mm is the artefact ceiling, 10.0 mm,
plus half of it as a margin, well below the real contacts measured. It was chosen once, from
those measurements; ``--collision-tolerance`` sets another (0 reports every overlap).
"""

COUPLING_TOLERANCE = 1e-3
"""Largest difference (rad) between two joints one motor drives on the real robot (nao-v5).

The ROS naoV50 URDF makes the finger joints follow the hand with a multiplier of 0.999899, a
difference of 1e-4 rad at most over their [0, 1] range; 1e-3 rad also allows values written with
3 decimals. Anything larger cannot be played by one motor."""

_EPS = 1e-9  # relative slack on velocity comparisons, for values that sit exactly at a limit


def parse_checks(names: str | Iterable[str]) -> tuple[str, ...]:
    """Check names from ``'limits,velocity'`` (or an iterable of such strings), in run order.

    ``all`` selects every check. Raises :class:`MotionToolError` naming the valid choices.
    """
    items = [names] if isinstance(names, str) else list(names)
    wanted: set[str] = set()
    for item in items:
        for raw in item.split(","):
            name = raw.strip().lower()
            if not name:
                continue
            if name == "all":
                wanted.update(CHECKS)
            elif name in CHECKS:
                wanted.add(name)
            else:
                close = difflib.get_close_matches(name, CHECKS, n=1)
                hint = f"did you mean '{close[0]}'? " if close else ""
                raise MotionToolError(
                    f"unknown check '{raw.strip()}'; {hint}choose from {', '.join(CHECKS)} or all"
                )
    if not wanted:
        raise MotionToolError(f"no check named; choose from {', '.join(CHECKS)} or all")
    return tuple(c for c in CHECKS if c in wanted)


# --------------------------------------------------------------------------- formatting


def _num(x: float) -> str:
    return f"{x:.6g}"


def _ms(x: float) -> str:
    return f"{x:.0f} ms" if float(x).is_integer() else f"{x:.1f} ms"


def _span(names: Sequence[str]) -> str:
    """``RPhalanx1..8`` for numbered names with one stem, else the names comma-separated."""
    stem = names[0].rstrip("0123456789")
    if len(names) > 2 and all(n.startswith(stem) and n[len(stem) :].isdigit() for n in names):
        return f"{names[0]}..{names[-1][len(stem) :]}"
    return ", ".join(names)


def _name(name: str) -> str:
    """A joint name for a message (undecodable bytes escaped)."""
    return name.encode("utf-8", "surrogateescape").decode("utf-8", "backslashreplace")


# --------------------------------------------------------------------------- the file's table


@dataclass
class _Table:
    """A file's poses against one robot's motors.

    ``cols`` are the columns that drive a motor of the robot (the later one of a duplicate
    name), ``motors`` the index in ``spec.joints`` of each, in the same order.
    """

    result: ReadResult
    times: npt.NDArray[np.int64]  # (P,) ms
    values: npt.NDArray[np.float64]  # (P, J), NaN for '*'
    cols: list[int]
    motors: list[int]
    _held: npt.NDArray[np.float64] | None = field(default=None, repr=False)
    _commanded: npt.NDArray[np.bool_] | None = field(default=None, repr=False)

    @property
    def commanded(self) -> npt.NDArray[np.bool_]:
        """(P, J) bool: the cell's value is sent to the motor at (or right after) its pose
        time: it is a number and the first or last pose, or a neighbouring pose's cell is a
        number too (Webots sends nothing over a segment that touches a '*')."""
        if self._commanded is None:
            import numpy as np

            defined = self.result.commanded  # a 'nan' cell is a command, unlike '*'
            near = np.zeros_like(defined)
            near[[0, -1]] = True
            near[1:] |= defined[:-1]
            near[:-1] |= defined[1:]
            self._commanded = defined & near
        return self._commanded

    @property
    def held(self) -> npt.NDArray[np.float64]:
        """(P, J) float64: each joint's target at each pose, its last commanded value where the
        cell sends none, NaN before the motion first commands it."""
        if self._held is None:
            self._held = hold_targets(self.values, self.commanded).targets
        return self._held


def _table(result: ReadResult, spec: RobotSpec, motor_index: dict[str, int]) -> _Table:
    import numpy as np

    n_poses, n_cols = len(result.times_ms), len(result.joints)
    values = np.asarray(result.rows, dtype=np.float64).reshape(n_poses, n_cols)
    last = {name: j for j, name in enumerate(result.joints)}  # the later column wins
    cols = sorted(j for name, j in last.items() if name in motor_index)
    return _Table(
        result=result,
        times=np.asarray(result.times_ms, dtype=np.int64),
        values=values,
        cols=cols,
        motors=[motor_index[result.joints[j]] for j in cols],
    )


def _cell(
    table: _Table,
    code: str,
    severity: Severity,
    pose: int,
    col: int | None,
    message: str,
    hint: str | None = None,
    *,
    time_ms: int | None = None,
) -> Diagnostic:
    """A diagnostic on the cell of ``pose`` in column ``col`` (its time token if None)."""
    result = table.result
    line, column, end = result.cell_span(pose, col)
    return Diagnostic(
        code=code,
        severity=severity,
        path=result.path,
        line=line,
        column=column,
        message=message,
        hint=hint,
        joint=None if col is None else result.joints[col],
        time_ms=int(table.times[pose]) if time_ms is None else time_ms,
        end_column=end,
    )


# --------------------------------------------------------------------------- the checks


class _RobotCheck:
    """Shared state of one robot's checks: the spec and its motor lookup."""

    def __init__(self, spec: RobotSpec) -> None:
        self.spec = spec
        self.motor_index = {name: i for i, name in enumerate(spec.joint_names)}

    def table(self, result: ReadResult) -> _Table:
        return _table(result, self.spec, self.motor_index)


def _name_robot(robot_option: str | None, which: str = "the") -> str:
    """How a hint tells the user to name a robot: ``name the robot explicitly``, or ``name the
    robot with --robot`` where the caller says how its user names one (``robot_option``)."""
    return f"name {which} robot " + (f"with {robot_option}" if robot_option else "explicitly")


class UnknownJoints(_RobotCheck):
    """MT301: header joints that are not motors of the robot (Webots ignores them); the hint
    of a name with no close motor says how to name another robot (``robot_option``: what the
    caller's user gives, e.g. the CLI's ``--robot``)."""

    def __init__(self, spec: RobotSpec, robot_option: str | None = None) -> None:
        super().__init__(spec)
        self.robot_option = robot_option

    def __call__(self, result: ReadResult) -> list[Diagnostic]:
        spec = self.spec
        unknown = [j for j, name in enumerate(result.joints) if name not in self.motor_index]
        if not unknown:
            return []
        spans = result.header_spans()
        out = []
        for j in unknown:
            name = result.joints[j]
            column, end = spans[j] if j < len(spans) else (1, None)
            close = difflib.get_close_matches(name, spec.joint_names, n=1)
            if close:
                message = unknown_joint_message(_name(name), spec)
                hint = f"Webots ignores this column (with a warning); rename it '{close[0]}'"
            else:
                message = f"unknown joint '{_name(name)}' for robot {spec.name}"
                hint = (
                    f"Webots ignores this column (with a warning); robot {spec.name}'s motors: "
                    + ", ".join(spec.joint_names)
                    + f"; or {_name_robot(self.robot_option, 'another')}"
                )
            out.append(
                Diagnostic(
                    code="MT301",
                    severity=Severity.WARNING,
                    path=result.path,
                    line=1,
                    column=column,
                    message=message,
                    hint=hint,
                    joint=name,
                    end_column=end,
                )
            )
        return out


class Limits(_RobotCheck):
    """MT302 position limits, and the real robot's rules where the spec has them (nao-v5):
    MT305 the HeadPitch range that depends on HeadYaw, MT306 joints one motor drives."""

    def __call__(self, result: ReadResult) -> list[Diagnostic]:
        import numpy as np

        table = self.table(result)
        if not table.cols:
            return []
        spec = self.spec
        joints = [spec.joints[m] for m in table.motors]
        lower = np.array([j.lower for j in joints])
        upper = np.array([j.upper for j in joints])
        values = table.values[:, table.cols]
        with np.errstate(invalid="ignore"):
            below = values < lower
            above = values > upper
        out = []
        real = spec.overrides_path is not None
        for pose, k in zip(*np.nonzero(below | above), strict=True):
            joint = joints[k]
            value = float(values[pose, k])
            is_low = bool(below[pose, k])
            bound = joint.lower if is_low else joint.upper
            where = "below its lower" if is_low else "above its upper"
            u = joint.unit
            rng = f"[{_num(joint.lower)}, {_num(joint.upper)}] {u}"
            hint = (
                f"the real robot's range is {rng} (robot {spec.name})"
                if real
                else f"Webots clamps the target to the motor's range {rng}, and warns"
            )
            out.append(
                _cell(
                    table,
                    "MT302",
                    Severity.ERROR,
                    int(pose),
                    table.cols[k],
                    f"{_name(joint.name)} = {_num(value)} {u} at {int(table.times[pose])} ms is "
                    f"{where} limit {_num(bound)} {u} by {_num(abs(value - bound))} {u}",
                    hint,
                )
            )
        flagged = {(d.line, d.joint) for d in out}
        if spec.head_pitch_envelope:
            out.extend(self._head_envelope(table, lower, upper, flagged))
        if spec.coupled_joints:
            out.extend(self._coupled(table, lower, upper))
        return out

    def _configuration(
        self, table: _Table, lower: npt.NDArray[np.float64], upper: npt.NDArray[np.float64]
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.bool_]]:
        """(held targets clamped to the limits, 0 before a first command) (P, K), and which
        cells are commanded (P, K), for the robot's columns."""
        import numpy as np

        held = np.clip(table.held[:, table.cols], lower, upper)
        return np.nan_to_num(held, nan=0.0), table.commanded[:, table.cols]

    def _head_envelope(
        self,
        table: _Table,
        lower: npt.NDArray[np.float64],
        upper: npt.NDArray[np.float64],
        flagged: set[tuple[int, str | None]],
    ) -> list[Diagnostic]:
        import numpy as np

        names = [self.spec.joints[m].name for m in table.motors]
        if "HeadPitch" not in names and "HeadYaw" not in names:
            return []
        held, commanded = self._configuration(table, lower, upper)
        n_poses = held.shape[0]
        k_pitch = names.index("HeadPitch") if "HeadPitch" in names else None
        k_yaw = names.index("HeadYaw") if "HeadYaw" in names else None
        pitch = held[:, k_pitch] if k_pitch is not None else np.zeros(n_poses)
        yaw = held[:, k_yaw] if k_yaw is not None else np.zeros(n_poses)
        rows = np.array(self.spec.head_pitch_envelope)
        lo = np.interp(yaw, rows[:, 0], rows[:, 1])
        hi = np.interp(yaw, rows[:, 0], rows[:, 2])
        any_command = np.zeros(n_poses, dtype=bool)
        for k in (k_pitch, k_yaw):
            if k is not None:
                any_command |= commanded[:, k]
        out = []
        for pose in np.flatnonzero(any_command & ((pitch < lo) | (pitch > hi))):
            on_pitch = k_pitch is not None and bool(commanded[pose, k_pitch])
            k = k_pitch if on_pitch else k_yaw
            if k is None:
                continue  # unreachable: any_command holds for one of the two
            col = table.cols[k]
            line = table.result.cell_span(int(pose), col)[0]
            if (line, table.result.joints[col]) in flagged:
                continue  # already outside the fixed range: reported once
            p, y = float(pitch[pose]), float(yaw[pose])
            bound = float(lo[pose]) if p < lo[pose] else float(hi[pose])
            where = "below" if p < lo[pose] else "above"
            out.append(
                _cell(
                    table,
                    "MT305",
                    Severity.ERROR,
                    int(pose),
                    col,
                    f"HeadPitch = {_num(p)} rad at HeadYaw = {_num(y)} rad "
                    f"({int(table.times[pose])} ms) is {where} {_num(bound)} rad, the real "
                    f"robot's limit at that yaw, by {_num(abs(p - bound))} rad",
                    f"at HeadYaw = {_num(y)} rad the real NAO's head pitches within "
                    f"[{_num(float(lo[pose]))}, {_num(float(hi[pose]))}] rad "
                    "(its shell hits the shoulders beyond)",
                )
            )
        return out

    def _coupled(
        self, table: _Table, lower: npt.NDArray[np.float64], upper: npt.NDArray[np.float64]
    ) -> list[Diagnostic]:
        import numpy as np

        names = [self.spec.joints[m].name for m in table.motors]
        held, commanded = self._configuration(table, lower, upper)
        n_poses = held.shape[0]
        followers: dict[str, list[str]] = {}
        for leader, follower in self.spec.coupled_joints:
            followers.setdefault(leader, []).append(follower)
        out = []
        for leader, group in followers.items():
            members = [leader, *group]
            if not any(m in names for m in members):
                continue  # the motion never commands this motor
            ks = [names.index(m) if m in names else None for m in members]
            q = np.stack([held[:, k] if k is not None else np.zeros(n_poses) for k in ks], 1)
            cmd = np.stack(
                [commanded[:, k] if k is not None else np.zeros(n_poses, bool) for k in ks], 1
            )
            off = np.abs(q[:, 1:] - q[:, :1]) > COUPLING_TOLERANCE + _EPS
            for pose in np.flatnonzero(off.any(axis=1) & cmd.any(axis=1)):
                differing = [members[i + 1] for i in np.flatnonzero(off[pose])]
                first = 1 + int(np.flatnonzero(off[pose])[0])
                at = next((i for i in (first, 0, *range(1, len(members))) if cmd[pose, i]), first)
                k_at = ks[at]
                col = table.cols[k_at] if k_at is not None else None
                lead = float(q[pose, 0])
                spread = float(np.abs(q[pose, 1:] - lead).max())
                shown = ", ".join(
                    f"{_name(m)} = {_num(float(q[pose, members.index(m)]))}" for m in differing
                )
                if len(members) > 2:  # fingers: the real hand opens and closes as one
                    severity = Severity.WARNING
                    what = (
                        f"the real robot's hand has one motor for {_span(members)}: it opens "
                        "and closes all the fingers together"
                    )
                else:
                    severity = Severity.ERROR
                    what = f"one motor drives {' and '.join(members)} on the real robot"
                out.append(
                    _cell(
                        table,
                        "MT306",
                        severity,
                        int(pose),
                        col,
                        f"{shown} rad at {int(table.times[pose])} ms "
                        f"{'differ' if len(differing) > 1 else 'differs'} from "
                        f"{_name(leader)} = {_num(lead)} rad by up to {_num(spread)} rad: {what}",
                        f"write the same value in the {len(members)} columns"
                        + ("" if None not in ks else " (a joint missing from the file sits at 0)"),
                    )
                )
        return out


class Velocity(_RobotCheck):
    """MT303 keyframe segments faster than maxVelocity; MT304 the command stream at the
    controller time step (target jumps after a ``*`` stretch, one step per segment)."""

    def __init__(self, spec: RobotSpec, timestep_ms: int | None = None) -> None:
        super().__init__(spec)
        self.timestep_ms = timestep_ms or spec.default_timestep_ms

    def __call__(self, result: ReadResult) -> list[Diagnostic]:
        import numpy as np

        table = self.table(result)
        joints = [self.spec.joints[m] for m in table.motors]
        limited = [k for k, j in enumerate(joints) if math.isfinite(j.max_velocity)]
        if not limited or table.times.shape[0] < 2:
            return []
        cols = [table.cols[k] for k in limited]
        vmax = np.array([joints[k].max_velocity for k in limited])
        values = table.values[:, cols]
        dt_ms = np.diff(table.times).astype(np.float64)
        with np.errstate(invalid="ignore"):
            speed = np.abs(np.diff(values, axis=0)) / (dt_ms[:, None] / 1000.0)
            fast = speed > vmax * (1.0 + _EPS)  # NaN (a '*' end) compares False
        out = []
        for seg, i in zip(*np.nonzero(fast), strict=True):
            joint = joints[limited[i]]
            u = joint.unit
            delta = abs(float(values[seg + 1, i] - values[seg, i]))
            need_ms = delta / joint.max_velocity * 1000.0
            t0, t1 = int(table.times[seg]), int(table.times[seg + 1])
            out.append(
                _cell(
                    table,
                    "MT303",
                    Severity.WARNING,
                    int(seg) + 1,
                    cols[i],
                    f"{_name(joint.name)} moves {_num(delta)} {u} in {t1 - t0} ms "
                    f"({t0} ms to {t1} ms): {_num(float(speed[seg, i]))} {u}/s, above its "
                    f"maximum velocity {_num(joint.max_velocity)} {u}/s by "
                    f"{_num(float(speed[seg, i]) - joint.max_velocity)} {u}/s; the motor "
                    f"needs {_ms(round(need_ms, 1))} and falls {_ms(round(need_ms - (t1 - t0), 1))}"
                    " behind",
                    "Webots caps the motor's speed at maxVelocity, so the joint arrives late; "
                    f"give this move at least {math.ceil(need_ms)} ms",
                )
            )
        out.extend(self._stream(table, joints, limited, cols, fast))
        return out

    def _stream(
        self,
        table: _Table,
        joints: Sequence[JointSpec],
        limited: list[int],
        cols: list[int],
        fast: npt.NDArray[np.bool_],
    ) -> list[Diagnostic]:
        """The sampled command stream, one diagnostic per joint and segment."""
        import numpy as np

        from motiontool.motionfmt.player import sample

        step = self.timestep_ms
        stream = sample(table.result.motion, step)
        elapsed = stream.elapsed_ms
        times = table.times
        last_seg = times.shape[0] - 2
        defined = table.result.commanded[:, cols]
        # fast_before[s, i]: how many of joint i's segments before s are MT303 segments.
        fast_before = np.zeros((fast.shape[0] + 1, fast.shape[1]), dtype=np.int64)
        np.cumsum(fast, axis=0, out=fast_before[1:])
        worst: dict[tuple[int, int], tuple[float, int, int, int]] = {}
        for i, col in enumerate(cols):
            vmax = joints[limited[i]].max_velocity
            steps = np.flatnonzero(stream.commanded[:, col])
            if steps.shape[0] < 2:
                continue
            per_step = np.abs(np.diff(stream.targets[steps, col])) / (step / 1000.0)
            n = np.flatnonzero(per_step > vmax * (1.0 + _EPS))
            if n.size == 0:
                continue
            k0, k1 = steps[n], steps[n + 1]
            at0, at1 = elapsed[k0], elapsed[k1]
            jump = k1 - k0 > 1
            # After a '*' stretch, the first number after the last command restarts the joint.
            numbered = np.flatnonzero(defined[:, i])
            after = np.searchsorted(times[numbered], at0, "right")
            restart = numbered[np.minimum(after, numbered.shape[0] - 1)]
            # Otherwise the steps of a segment MT303 already reports are left to it.
            seg_start = np.clip(np.searchsorted(times, at0, "right") - 1, 0, last_seg)
            seg_end = np.clip(np.searchsorted(times, at1, "left") - 1, 0, last_seg)
            covered = fast_before[seg_end + 1, i] - fast_before[seg_start, i] > 0
            poses = np.where(jump, restart, seg_end + 1)
            keep = jump | ~covered
            for m in np.flatnonzero(keep):
                key = (i, int(poses[m]))
                speed = float(per_step[n[m]])
                if key not in worst or speed > worst[key][0]:
                    worst[key] = (speed, int(at0[m]), int(at1[m]), int(k1[m] - k0[m]))
        out = []
        for (i, pose), (speed, e0, e1, gap) in sorted(worst.items()):
            joint = joints[limited[i]]
            name = _name(joint.name)
            u = joint.unit
            vmax = joint.max_velocity
            delta = speed * step / 1000.0
            lag = delta / vmax * 1000.0 - step
            if gap > 1:
                what = (
                    f"{name} gets no command from {e0 + step} ms to {e1 - step} ms ('*'), then "
                    f"its target jumps by {_num(delta)} {u} at {e1} ms, within one {step} ms "
                    "controller step"
                )
                hint = "write values instead of '*' so that the joint moves there gradually"
            else:
                what = (
                    f"at the {step} ms controller step, {name}'s target moves {_num(delta)} {u} "
                    f"from {e0} ms to {e1} ms"
                )
                hint = "spread the move over more time"
            out.append(
                _cell(
                    table,
                    "MT304",
                    Severity.WARNING,
                    pose,
                    cols[i],
                    f"{what}: {_num(speed)} {u}/s, above its maximum velocity {_num(vmax)} {u}/s "
                    f"by {_num(speed - vmax)} {u}/s; the motor falls {_ms(round(lag, 1))} behind",
                    hint,
                    time_ms=e1,
                )
            )
        return out


def _configurations(
    table: _Table, spec: RobotSpec
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """Whole-robot configurations at every keyframe and segment midpoint, in that order.

    Returns (Q (2P-1, M) float64 in ``spec.joints`` order, times (2P-1,) float64 ms): row 2p is
    pose p, row 2p+1 halfway to pose p+1. Held targets where a cell sends no command, 0 for a
    joint not commanded yet or not in the file, everything clamped to the motor limits.
    """
    import numpy as np

    n_poses = table.times.shape[0]
    held = table.held[:, table.cols]
    values = table.values[:, table.cols]
    mid = (values[:-1] + values[1:]) / 2.0
    mid = np.where(np.isnan(mid), held[:-1], mid)
    rows = np.empty((2 * n_poses - 1, len(table.cols)))
    rows[0::2] = held
    rows[1::2] = mid
    q = np.zeros((rows.shape[0], len(spec.joints)))
    q[:, table.motors] = np.nan_to_num(rows, nan=0.0)
    lower = np.array([j.lower for j in spec.joints])
    upper = np.array([j.upper for j in spec.joints])
    q = np.clip(q, lower, upper)
    times = np.empty(rows.shape[0])
    times[0::2] = table.times
    times[1::2] = (table.times[:-1] + table.times[1:]) / 2.0
    return q, times


def _runs(indices: Sequence[int], step: int) -> list[list[int]]:
    """Group sorted ``indices`` into runs of consecutive values ``step`` apart."""
    runs: list[list[int]] = []
    for i in indices:
        if runs and i - runs[-1][-1] == step:
            runs[-1].append(i)
        else:
            runs.append([i])
    return runs


class Collision(_RobotCheck):
    """MT307: self-collision at every keyframe and segment midpoint (one diagnostic per pair
    of bodies and run of consecutive checked instants)."""

    def __init__(
        self, spec: RobotSpec, penetration_tolerance_mm: float = DEFAULT_PENETRATION_TOLERANCE_MM
    ) -> None:
        super().__init__(spec)
        self.tolerance_mm = penetration_tolerance_mm

    def __call__(self, result: ReadResult) -> list[Diagnostic]:
        from motiontool.kinematics.collision import scan_self_collisions

        require("pinocchio", "kinematics", "the collision check")
        table = self.table(result)
        if not table.cols:
            return []
        q, times = _configurations(table, self.spec)
        contacts = scan_self_collisions(
            self.spec,
            q,
            penetration_tolerance_m=self.tolerance_mm / 1000.0,
            fingers_in_hand=True,
        )
        by_pair: dict[tuple[str, str], dict[int, float]] = {}
        for c in contacts:
            by_pair.setdefault((c.body_a, c.body_b), {})[c.config] = c.depth_m
        out = []
        for (a, b), depths in sorted(by_pair.items()):
            for run in _runs(sorted(depths), 1):
                deepest = max(run, key=lambda i: depths[i])
                depth_mm = depths[deepest] * 1000.0
                at = self._instant(table, times, deepest)
                span = (
                    ""
                    if len(run) == 1
                    else f"; they overlap from {_ms(times[run[0]])} to {_ms(times[run[-1]])}"
                )
                out.append(
                    _cell(
                        table,
                        "MT307",
                        Severity.WARNING,
                        (deepest + 1) // 2,
                        None,
                        f"{a} and {b} overlap by {depth_mm:.1f} mm at {at}{span}",
                        f"overlaps under {self.tolerance_mm:g} mm are ignored as artefacts of the "
                        "coarse collision shapes; a simulator with self-collision off lets the "
                        f"bodies pass through each other, the real {self.spec.name} does not",
                        time_ms=math.floor(times[deepest]),
                    )
                )
        return out

    @staticmethod
    def _instant(table: _Table, times: npt.NDArray[np.float64], index: int) -> str:
        if index % 2 == 0:
            return f"{_ms(times[index])} (pose '{table.result.pose_names[index // 2]}')"
        p = index // 2
        return (
            f"{_ms(times[index])}, halfway from {int(table.times[p])} ms to "
            f"{int(table.times[p + 1])} ms"
        )


class Balance(_RobotCheck):
    """MT308: static balance at keyframes (centre of mass against the feet's support polygon)."""

    def __call__(self, result: ReadResult) -> list[Diagnostic]:
        from motiontool.kinematics._pinocchio import com_and_support

        require("pinocchio", "kinematics", "the balance check")
        table = self.table(result)
        if not table.cols:
            return []
        q, _times = _configurations(table, self.spec)
        names = self.spec.joint_names
        margins = [
            com_and_support(self.spec, dict(zip(names, row.tolist(), strict=True))).margin_mm
            for row in q[0::2]
        ]
        outside = [p for p, m in enumerate(margins) if m < 0.0]
        out = []
        for run in _runs(outside, 1):
            worst = min(run, key=lambda p: margins[p])
            span = (
                ""
                if len(run) == 1
                else f"; outside from {int(table.times[run[0]])} ms to "
                f"{int(table.times[run[-1]])} ms"
            )
            out.append(
                _cell(
                    table,
                    "MT308",
                    Severity.WARNING,
                    worst,
                    None,
                    f"centre of mass {-margins[worst]:.1f} mm outside the support polygon of the "
                    f"feet at {int(table.times[worst])} ms (pose "
                    f"'{table.result.pose_names[worst]}'){span}",
                    "a static estimate with the torso upright and the lowest foot on the floor: "
                    "held still in this pose the robot tips over; a dynamic move may still pass",
                )
            )
        return out


def robot_checks(
    spec: RobotSpec,
    checks: Iterable[str] = DEFAULT_CHECKS,
    *,
    timestep_ms: int | None = None,
    penetration_tolerance_mm: float = DEFAULT_PENETRATION_TOLERANCE_MM,
    robot_option: str | None = None,
) -> list[Callable[[ReadResult], list[Diagnostic]]]:
    """The checks of ``spec`` for :func:`motiontool.motionfmt.validate_paths`.

    Args:
        spec: the robot.
        checks: names from :data:`CHECKS`; the unknown-joint check (MT301) and the
            unmirrored-copy note (MT309) always run, and the real robot's rules (``nao-v5``)
            run with ``limits``.
        timestep_ms: controller time step (ms) of the sampled command stream checked by
            ``velocity``; the robot's ``default_timestep_ms`` if None.
        penetration_tolerance_mm: see :data:`DEFAULT_PENETRATION_TOLERANCE_MM` (mm, >= 0).
        robot_option: how the user names a robot (the CLI: ``--robot``), for hints; None:
            hints say "name the robot explicitly".

    Raises:
        MotionToolError: an unknown check name, a negative tolerance, or ``balance`` for a
            robot without feet.
    """
    names = parse_checks(list(checks))
    if not penetration_tolerance_mm >= 0:
        raise MotionToolError(
            f"the collision tolerance must be a depth >= 0 mm, got {penetration_tolerance_mm}"
        )
    if "balance" in names and not spec.feet:
        raise MotionToolError(
            f"robot {spec.name} has no feet: the balance check needs a humanoid model with "
            "sole geometries (nao, nao-v5); leave 'balance' out of --checks"
        )
    out: list[Callable[[ReadResult], list[Diagnostic]]] = [UnknownJoints(spec, robot_option)]
    out.append(UnmirroredCopy(spec))  # MT309, a note; reads a sibling file only if one exists
    if "limits" in names:
        out.append(Limits(spec))
    if "velocity" in names:
        out.append(Velocity(spec, timestep_ms))
    if "collision" in names:
        out.append(Collision(spec, penetration_tolerance_mm))
    if "balance" in names:
        out.append(Balance(spec))
    return out


# --------------------------------------------------------------------------- robot selection


class RobotChecks:
    """The robot checks of one ``validate`` run, as one :data:`Check`.

    ``robot='auto'`` picks, per file, the built-in robot that has the most of the header's
    joints, at least half of them (:func:`~motiontool.kinematics.robots.pick_robot`; the others
    get MT301 with a did-you-mean, and the joints it has are checked); a file no built-in robot
    fits is checked at syntax level only and gets an MT901 note whose hint says how to name a
    robot (``robot_option``: what the caller's user gives, the CLI's ``--robot``; None: "name
    the robot explicitly") and the robots to choose from. ``'none'`` checks nothing. Any other
    ``robot`` is loaded once (:func:`~motiontool.kinematics.load_robot`) and checks every
    file. Robots and their models are loaded once per process.

    A check whose library is not installed (collision and balance need Pinocchio,
    ``motiontool[kinematics]``) is skipped for the rest of the run, with one MT902 note on the
    first file it would have checked; the others still run.

    Attributes:
        used: for every file checked, the robot it was checked against (None: skipped).
        skipped: the checks skipped for a missing library, by name, with the error that says
            which extra to install.
    """

    def __init__(
        self,
        robot: str = "auto",
        checks: Iterable[str] = DEFAULT_CHECKS,
        *,
        timestep_ms: int | None = None,
        penetration_tolerance_mm: float = DEFAULT_PENETRATION_TOLERANCE_MM,
        robot_option: str | None = None,
    ) -> None:
        self.robot = robot
        self.robot_option = robot_option
        self.checks = parse_checks(list(checks))
        self.timestep_ms = timestep_ms
        self.penetration_tolerance_mm = penetration_tolerance_mm
        self.used: dict[str, RobotSpec | None] = {}
        self.skipped: dict[str, MissingExtraError] = {}
        self._by_robot: dict[str, list[Callable[[ReadResult], list[Diagnostic]]]] = {}
        self._specs: dict[str, RobotSpec] = {}
        spec = None if robot == AUTO else pick_robot(robot)  # UnknownRobotError: exit early
        if spec is not None:
            self._checks_for(spec, strict=True)

    def _checks_for(
        self, spec: RobotSpec, *, strict: bool = False
    ) -> list[Callable[[ReadResult], list[Diagnostic]]]:
        if spec.name not in self._by_robot:
            names = self.checks
            if not strict and not spec.feet:
                names = tuple(c for c in names if c != "balance")
            self._specs[spec.name] = spec
            self._by_robot[spec.name] = robot_checks(
                spec,
                names,
                timestep_ms=self.timestep_ms,
                penetration_tolerance_mm=self.penetration_tolerance_mm,
                robot_option=self.robot_option,
            )
        return self._by_robot[spec.name]

    def spec_for(self, result: ReadResult) -> RobotSpec | None:
        """The robot ``result`` is checked against, or None (auto, no built-in robot fits)."""
        if self.robot != AUTO:
            return next(iter(self._specs.values()), None)
        return pick_robot(AUTO, result.joints)

    def __call__(self, result: ReadResult) -> list[Diagnostic]:
        if self.robot == NONE:
            return []
        spec = self.spec_for(result)
        self.used[result.path] = spec
        if spec is None:
            return [_skipped(result, self.robot_option)]
        out = []
        for check in self._checks_for(spec):
            name = _CHECK_NAMES.get(type(check))
            if name in self.skipped:
                continue
            try:
                out.extend(check(result))
            except MissingExtraError as exc:
                if name is None:
                    raise
                self.skipped[name] = exc
                out.append(_skipped_for_extra(result, name, exc))
        if "balance" in self.checks and not spec.feet:
            out.append(
                Diagnostic(
                    "MT901",
                    Severity.INFO,
                    result.path,
                    1,
                    1,
                    f"balance check skipped: robot {spec.name} has no feet",
                )
            )
        return out


_CHECK_NAMES: dict[type, str] = {Collision: "collision", Balance: "balance"}
"""The checks that need an extra (Pinocchio), by class: skipped with MT902 when it is missing."""


def _skipped_for_extra(result: ReadResult, name: str, exc: MissingExtraError) -> Diagnostic:
    """MT902, once a run: check ``name`` is skipped because its library is not installed."""
    return Diagnostic(
        code="MT902",
        severity=Severity.INFO,
        path=result.path,
        line=1,
        column=1,
        message=f"{name} check skipped: {exc.library} is not installed; every file of this run "
        f"is checked without it",
        hint=install_hint(exc.extra),
    )


def _skipped(result: ReadResult, robot_option: str | None) -> Diagnostic:
    """MT901 for a file :func:`~motiontool.kinematics.detect_robot` finds no robot for: no
    built-in robot has half of its joints, or two robots with different motors have as many
    (:class:`~motiontool.kinematics.robots.NoRobotDetectedError` says which); the hint says
    how to name a robot and the robots to choose from."""
    spans = result.header_spans()
    joints = result.joints
    why = NoRobotDetectedError(joints)
    where = why.missing[0] if why.missing else 0
    column, end = spans[where] if where < len(spans) else (1, None)
    return Diagnostic(
        code="MT901",
        severity=Severity.INFO,
        path=result.path,
        line=1,
        column=column,
        message=f"robot checks skipped: {why.detail}; checked at syntax level only",
        hint=f"{_name_robot(robot_option)} ({robot_choices()})",
        joint=joints[where] if joints else None,
        end_column=end,
    )
