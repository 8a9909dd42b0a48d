"""MT303 keyframe segments faster than a motor's maximum velocity; MT304 the command stream at
the controller time step (target jumps after a ``*`` stretch, one step per segment)."""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator, Sequence
from typing import TYPE_CHECKING, NamedTuple

from motiontool.kinematics.checks._stream_steps import (
    LastStream,
    Step,
    member,
    merged,
    step_times,
    steps_read,
    within,
)
from motiontool.kinematics.checks._table import (
    EPS,
    GroupingCheck,
    PoseRuns,
    Table,
    cell,
    fmt_ms,
    fmt_name,
    fmt_num,
    pose_runs,
)
from motiontool.kinematics.checks.registry import CheckOptions
from motiontool.kinematics.robots import JointSpec, RobotSpec
from motiontool.motionfmt.diagnostics import (
    STREAM_TOO_FAST,
    TOO_FAST,
    Diagnostic,
    PoseFinding,
    Severity,
    Worst,
)
from motiontool.motionfmt.findings import Findings, in_order
from motiontool.motionfmt.grouping import group_findings, run_finding
from motiontool.motionfmt.player import Held, commands_at, hold_targets
from motiontool.motionfmt.reader import ReadResult
from motiontool.motionfmt.units import MS_PER_S

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

__all__ = ["Velocity"]

_STREAM_CHUNK = 1 << 13
"""Controller steps of the command stream the velocity check reads at a time (a few MB of arrays
for a Nao, whatever the motion's duration; it reads the steps around each pose,
:func:`~motiontool.kinematics.checks._stream_steps.steps_read`)."""

_SEGMENTS = 1 << 14
"""Keyframe segments whose values are compared at a time: what the check keeps of the whole
motion is, per joint and segment, the move and whether it is too fast (9 bytes)."""


class _Sent(NamedTuple):
    """The S steps that send one motor a target, (S,) each."""

    elapsed: npt.NDArray[np.int64]
    """Their playback times, ms."""
    targets: npt.NDArray[np.float64]
    """The targets sent then."""
    after: npt.NDArray[np.intp]
    """How many poses are at or before each step's time (``searchsorted`` right)."""
    at_or_after: npt.NDArray[np.intp]
    """How many poses are before each step's time (``searchsorted`` left)."""


class Velocity(GroupingCheck):
    """MT303 keyframe segments faster than maxVelocity; MT304 the command stream at the
    controller time step (target jumps after a ``*`` stretch, one step per segment).

    A segment is the one that Webots interpolates: of two columns with one name, the later one
    with a number at both ends; the stream is what the motor gets (the later column's command
    where it sends one, else the earlier's)."""

    def __init__(self, spec: RobotSpec, timestep_ms: int | None = None) -> None:
        super().__init__(spec)
        self.timestep_ms = timestep_ms or spec.default_timestep_ms
        self._last: LastStream | None = None
        """The stream findings on the last file checked, for its next version (see
        :class:`~motiontool.kinematics.checks._stream_steps.LastStream`)."""

    @classmethod
    def for_run(cls, spec: RobotSpec, options: CheckOptions) -> Velocity:
        """The check of ``spec`` at the run's controller step."""
        return cls(spec, options.timestep_ms)

    def at_times(
        self,
        result: ReadResult,
        keep: Callable[[npt.NDArray[np.int64]], npt.NDArray[np.bool_]],
    ) -> Findings:
        """The findings of ``self(result)`` (one per segment or step) whose time (ms) ``keep``
        keeps, given the times of many; a segment's finding not kept is never made (a file
        of random values has millions)."""
        return self._check(result, group=False, keep=keep)

    def _check(
        self,
        result: ReadResult,
        *,
        group: bool,
        keep: Callable[[npt.NDArray[np.int64]], npt.NDArray[np.bool_]] | None = None,
    ) -> Findings:
        import numpy as np

        table = self.table(result)
        joints = [self.spec.joints[m] for m in table.motors]
        limited = [k for k, j in enumerate(joints) if math.isfinite(j.max_velocity)]
        if not limited or table.times.shape[0] < 2:
            return Findings.of([])
        driver, delta, fast = self._segments(table, joints, limited)
        steps = self._stream(table, joints, limited, fast)
        if group:
            found = self._segment_runs(table, [joints[k] for k in limited], driver, delta, fast)
            return Findings.merge([found, group_findings(steps)])
        if keep is not None:  # a segment's finding is at its end pose's time (cell)
            fast = fast & keep(table.times[1:])[:, None]
            steps = [d for d, k in zip(steps, keep(_times(steps)), strict=True) if k]
        segs, ii = np.nonzero(fast)
        cols, moves = driver[segs, ii], delta[segs, ii]  # gathered: no (S, I) array is kept

        def segment(n: int) -> Diagnostic:
            joint = joints[limited[int(ii[n])]]
            return self._segment(table, joint, int(segs[n]), int(cols[n]), float(moves[n]))

        return Findings.merge([in_order(segs + 1, cols, segment), steps])

    @staticmethod
    def _segments(
        table: Table, joints: Sequence[JointSpec], limited: list[int]
    ) -> tuple[npt.NDArray[np.int32], npt.NDArray[np.float64], npt.NDArray[np.bool_]]:
        """(S, I) for each motor of ``limited`` and keyframe segment: the file column that
        drives it (:meth:`Table.segments`), how far it moves (NaN where no column drives it),
        and whether faster than its maximum velocity; a block of :data:`_SEGMENTS` segments
        at a time (no (S, K) array)."""
        import numpy as np

        vmax = np.array([joints[k].max_velocity for k in limited])
        n_segments = table.times.shape[0] - 1
        driver = np.empty((n_segments, len(limited)), dtype=np.int32)
        delta = np.empty(driver.shape)
        fast = np.empty(driver.shape, dtype=np.bool_)
        dt_s = np.diff(table.times).astype(np.float64) / MS_PER_S
        for lo in range(0, n_segments, _SEGMENTS):
            hi = min(lo + _SEGMENTS, n_segments)
            driving = table.segments(lo, hi)
            start, end = table.segment_values(lo, hi, driving)
            driver[lo:hi] = driving[0][:, limited]
            with np.errstate(invalid="ignore", over="ignore"):
                moved = np.abs(end[:, limited] - start[:, limited])
                speed = moved / dt_s[lo:hi, None]
                # NaN (a '*' or 'nan' end) compares False; an 'inf' end, or finite ends too
                # far apart for a double (1e308 to -1e308: no time they could take), is left
                # to MT302.
                fast[lo:hi] = np.isfinite(speed) & (speed > vmax * (1.0 + EPS))
            delta[lo:hi] = moved
        return driver, delta, fast

    @classmethod
    def _segment_runs(
        cls,
        table: Table,
        joints: list[JointSpec],
        driver: npt.NDArray[np.int32],
        delta: npt.NDArray[np.float64],
        fast: npt.NDArray[np.bool_],
    ) -> Findings:
        """MT303 grouped: one finding per run of consecutive fast segments of a joint
        (:func:`~motiontool.motionfmt.grouping.run_finding`), made when read; ``joints``,
        ``driver``, ``delta`` and ``fast`` (S, I): the joints with a maximum velocity."""
        import numpy as np

        dt_s = np.diff(table.times).astype(np.float64) / MS_PER_S
        found = []  # PoseRuns and joint arrays of segments, a set per joint
        for i, joint in enumerate(joints):
            if fast[:, i].any():
                with np.errstate(over="ignore"):  # a move of 1e308 rad in 1 ms: inf rad/s
                    excess = delta[:, i] / dt_s - joint.max_velocity
                runs = pose_runs(fast[:, i], excess)
                found.append((*runs, np.full(runs.first.shape, i)))
        if not found:
            return Findings.of([])
        first, last, worst, count, n_runs, ii = (
            np.concatenate(a) for a in zip(*found, strict=True)
        )

        # What each run's finding needs, gathered: the findings keep no (S, I) array.
        at = {"first": first, "last": last, "worst": worst}
        columns = {name: driver[index, ii] for name, index in at.items()}
        moves = {name: delta[index, ii] for name, index in at.items()}

        def segment_run(n: int) -> Diagnostic:
            run = PoseRuns(first[n], last[n], worst[n], count[n], n_runs[n])
            cols = {name: int(c[n]) for name, c in columns.items()}
            deltas = {name: float(d[n]) for name, d in moves.items()}
            return cls._segment_run(table, joints[int(ii[n])], (cols, deltas), run)

        return in_order(first + 1, columns["first"], segment_run)

    @classmethod
    def _segment_run(
        cls,
        table: Table,
        joint: JointSpec,
        gathered: tuple[dict[str, int], dict[str, float]],
        run: PoseRuns,
    ) -> Diagnostic:
        """MT303 on ``joint`` over the segments of ``run`` (one run's scalars); ``gathered``:
        the driving column and the move of its first, last and worst segments. One finding,
        grouped if it covers more than a segment."""
        cols, deltas = gathered
        first, last, worst = int(run.first), int(run.last), int(run.worst)
        d = cls._segment(table, joint, first, cols["first"], deltas["first"])
        if run.size == 1:
            return d
        span = table.result.cell_span
        line, column, _end = span(worst + 1, cols["worst"])
        t0, t1 = int(table.times[worst]), int(table.times[worst + 1])
        speed = deltas["worst"] / ((t1 - t0) / MS_PER_S)
        w = Worst(speed, f"{joint.unit}/s", line, column, t1)
        last_line = span(last + 1, cols["last"])[0]
        _speed, _need_ms, over, need = cls._move(joint, deltas["worst"], t1 - t0)
        amount = _amount(joint.unit, over, need, t1 - t0)
        return run_finding(d, int(run.size), last_line, w, runs=int(run.runs), amount=amount)

    @staticmethod
    def _segment(table: Table, joint: JointSpec, seg: int, col: int, delta: float) -> Diagnostic:
        """MT303: ``joint`` moves ``delta`` over segment ``seg``, interpolating column ``col``."""
        u = joint.unit
        vmax = joint.max_velocity
        t0, t1 = int(table.times[seg]), int(table.times[seg + 1])
        speed, need_ms, over, need = Velocity._move(joint, delta, t1 - t0)
        return cell(
            table,
            TOO_FAST,
            Severity.WARNING,
            seg + 1,
            col,
            f"{fmt_name(joint.name)} moves {fmt_num(delta)} {u} in {t1 - t0} ms "
            f"({t0} ms to {t1} ms): {fmt_num(speed)} {u}/s, above its maximum velocity "
            f"{fmt_num(vmax)} {u}/s by {over} {u}/s; the motor needs "
            f"{need} and falls {fmt_ms(round(need_ms - (t1 - t0), 1))} behind",
            "Webots caps the motor's speed at maxVelocity, so the joint arrives late; "
            f"give this move at least {_at_least(need_ms)}",
            grouping=PoseFinding(
                seg + 1,
                f"{fmt_name(joint.name)} faster than its maximum velocity {fmt_num(vmax)} {u}/s",
                speed,
                f"{u}/s",
                speed - vmax,
                noun="segment",
                hint="Webots caps the motor's speed at maxVelocity, so the joint arrives "
                "late; give each of these moves more time (ungrouped: a finding per segment, "
                "with the time each needs)",
                amount=_amount(u, over, need, t1 - t0),
            ),
        )

    @staticmethod
    def _move(joint: JointSpec, delta: float, dt_ms: int) -> tuple[float, float, str, str]:
        """A move of ``delta`` (rad or m) in ``dt_ms``: its speed (rad/s or m/s), the time it
        needs at the maximum velocity (ms), and how both read in MT303's messages: how far
        above the maximum velocity, and the time needed."""
        speed = float(delta) / (dt_ms / MS_PER_S)
        need_ms = float(delta) / joint.max_velocity * MS_PER_S
        return speed, need_ms, fmt_num(speed - joint.max_velocity), fmt_ms(round(need_ms, 1))

    def _stream(
        self,
        table: Table,
        joints: Sequence[JointSpec],
        limited: list[int],
        fast: npt.NDArray[np.bool_],
    ) -> list[Diagnostic]:
        """The sampled command stream, one diagnostic per joint and segment; read a chunk of
        controller steps at a time (memory stays flat whatever the motion's duration). After
        an edit of the last file checked, the steps around the poses it changed are read, the
        other findings taken from that file's (:attr:`_last`)."""
        import numpy as np

        from motiontool.motionfmt.clock import clock_overflow, end_step

        motion = table.result.motion
        step = self.timestep_ms
        # Where Webots' playback time wraps (MT115), the steps up to the wrap: it may never end.
        overflow = clock_overflow(motion.duration_ms, step)
        last = end_step(motion.duration_ms, step) if overflow is None else overflow.step
        assert last is not None, "a motion that never ends wraps"
        lo, hi = merged(*steps_read(motion, step, last + 1))
        gaps = (hi[:-1] - 1) * step  # a step read, then steps not read: no pair across them
        kept = None if overflow is not None else self._last
        redo = None if kept is None else kept.redo(table, limited, step, last + 1)
        if redo is not None:
            lo, hi = within(lo, hi, redo.steps)
        names = [table.result.joints[group[-1]] for group in table.groups]
        # fast_before[s, i]: how many of joint i's segments before s are MT303 segments.
        fast_before = np.zeros((fast.shape[0] + 1, fast.shape[1]), dtype=np.int32)
        np.cumsum(fast, axis=0, out=fast_before[1:])
        defined = table.defined
        worst: dict[tuple[int, int], Step] = {}
        carried: dict[int, _Sent] = {}
        for elapsed in step_times(lo, hi, step, _STREAM_CHUNK):
            targets, commanded = commands_at(motion, elapsed)
            motors = hold_targets(targets, commanded, table.result.joints, names)
            for i, k, now in _sent_steps(table.times, elapsed, motors, limited, carried):
                fast_steps = self._fast_steps(
                    table.times,
                    now,
                    (joints[k].max_velocity, defined[:, k], fast_before[:, i]),
                    gaps,
                )
                for pose, found in fast_steps:
                    if (i, pose) not in worst or found[0] > worst[(i, pose)][0]:
                        worst[(i, pose)] = found
        if kept is not None and redo is not None:
            worst = kept.spliced(redo, worst)
        keeps = overflow is None and LastStream.keeps(table)
        self._last = (
            LastStream(table.times, table.raw, tuple(table.motors), tuple(limited), worst)
            if keeps
            else None
        )
        return [
            self._step_warning(table, joints[limited[i]], pose, table.col(pose, limited[i]), *w)
            for (i, pose), w in sorted(worst.items())
        ]

    def _fast_steps(
        self,
        times: npt.NDArray[np.int64],
        sent: _Sent,
        motor: tuple[float, npt.NDArray[np.bool_], npt.NDArray[np.int32]],
        gaps: npt.NDArray[np.int64],
    ) -> list[tuple[int, Step]]:
        """The steps of one motor whose target moves faster than its maximum velocity, each
        with the pose to report it on.

        Args:
            times: (P,) the pose times, ms.
            sent: the steps read that send the motor a target.
            motor: its maximum velocity (unit/s), (P,) which poses command it, and (P,) how
                many of its segments before each pose are MT303 segments.
            gaps: (G,) sorted, the times (ms) of the steps read after which steps are not read
                (:func:`~.steps_read`): a motor sent a target there is sent one at every step up
                to the next step read, so the two are not consecutive commands.
        """
        import numpy as np

        step = self.timestep_ms
        vmax, defined, fast_before = motor
        elapsed, targets, after, at_or_after = sent
        with np.errstate(invalid="ignore", over="ignore"):  # 'inf' targets: left to MT302
            per_step = np.abs(np.diff(targets)) / (step / MS_PER_S)
            fast = np.isfinite(per_step) & (per_step > vmax * (1.0 + EPS))
        if gaps.size and fast.any():
            fast[member(elapsed[:-1], gaps)] = False
        n = np.flatnonzero(fast)
        if n.size == 0:
            return []
        at0, at1 = elapsed[n], elapsed[n + 1]
        jump = at1 - at0 > step
        # The steps of a segment MT303 already reports are left to it.
        last_seg = times.shape[0] - 2
        seg_start = np.clip(after[n] - 1, 0, last_seg)
        seg_end = np.clip(at_or_after[n + 1] - 1, 0, last_seg)
        covered = fast_before[seg_end + 1] - fast_before[seg_start] > 0
        poses = seg_end + 1
        if jump.any():  # after a '*' stretch, the first number after the last command restarts
            numbered = np.flatnonzero(defined)
            jumps = np.flatnonzero(jump)
            past = np.searchsorted(times[numbered], at0[jumps], "right")
            poses[jumps] = numbered[np.minimum(past, numbered.shape[0] - 1)]
        return [
            (
                int(poses[m]),
                (float(per_step[n[m]]), int(at0[m]), int(at1[m]), int(at1[m] - at0[m]) // step),
            )
            for m in np.flatnonzero(jump | ~covered)
        ]

    def _step_warning(
        self,
        table: Table,
        joint: JointSpec,
        pose: int,
        col: int,
        speed: float,
        e0: int,
        e1: int,
        gap: int,
    ) -> Diagnostic:
        """MT304 on ``col``'s cell at ``pose``: a controller step from ``e0`` to ``e1`` ms,
        ``gap`` steps apart, at ``speed``."""
        step = self.timestep_ms
        name = fmt_name(joint.name)
        u = joint.unit
        vmax = joint.max_velocity
        delta = speed * step / MS_PER_S
        lag = delta / vmax * MS_PER_S - step
        if gap > 1:
            subject = f"{name}'s target jumps after '*'"
            what = (
                f"{name} gets no command from {e0 + step} ms to {e1 - step} ms ('*'), then "
                f"its target jumps by {fmt_num(delta)} {u} at {e1} ms, within one {step} ms "
                "controller step"
            )
            hint = "write values instead of '*' so that the joint moves there gradually"
        else:
            subject = f"{name}'s target moves"
            what = (
                f"at the {step} ms controller step, {name}'s target moves {fmt_num(delta)} {u} "
                f"from {e0} ms to {e1} ms"
            )
            hint = "spread the move over more time"
        return cell(
            table,
            STREAM_TOO_FAST,
            Severity.WARNING,
            pose,
            col,
            f"{what}: {fmt_num(speed)} {u}/s, above its maximum velocity {fmt_num(vmax)} {u}/s "
            f"by {fmt_num(speed - vmax)} {u}/s; the motor falls {fmt_ms(round(lag, 1))} behind",
            hint,
            time_ms=e1,
            grouping=PoseFinding(
                pose,
                f"{subject} faster than its maximum velocity {fmt_num(vmax)} {u}/s at the "
                f"{step} ms controller step",
                speed,
                f"{u}/s",
                speed - vmax,
            ),
        )


def _at_least(need_ms: float) -> str:
    """The whole ms a move needs, as MT303's hint says it (a move of 1e308 rad needs more than
    a double holds)."""
    return f"{math.ceil(need_ms)} ms" if math.isfinite(need_ms) else "more time than a motion has"


def _amount(unit: str, over: str, need: str, dt_ms: int) -> str:
    """What a grouped MT303 says of its worst segment (:meth:`Velocity._move`'s texts)."""
    return f"{over} {unit}/s above it: that move needs {need}, not {dt_ms} ms"


def _sent_steps(
    times: npt.NDArray[np.int64],
    elapsed_ms: npt.NDArray[np.int64],
    motors: Held,
    limited: list[int],
    last: dict[int, _Sent],
) -> Iterator[tuple[int, int, _Sent]]:
    """For each motor ``limited[i] = k`` sent two targets or more (counting its last of the
    chunks before, kept in ``last[i]``): ``(i, k, sent)``, ``sent`` as
    :meth:`Velocity._fast_steps` takes it, of a chunk of steps (``elapsed_ms`` (S,), ms, and
    what the motors hold then)."""
    import numpy as np

    sent = np.ascontiguousarray(motors.sent.T)  # a row per motor
    # Where each step's time falls among the poses', found once for every motor.
    after = np.searchsorted(times, elapsed_ms, "right")
    at_or_after = np.searchsorted(times, elapsed_ms, "left")
    for i, k in enumerate(limited):
        steps = np.flatnonzero(sent[k])
        if steps.shape[0] == 0:
            continue
        now = _Sent(elapsed_ms[steps], motors.targets[steps, k], after[steps], at_or_after[steps])
        carried = last.get(i)
        if carried is not None:
            now = _Sent._make(np.concatenate(pair) for pair in zip(carried, now, strict=True))
        last[i] = _Sent._make(a[-1:] for a in now)
        if now.elapsed.shape[0] >= 2:
            yield i, k, now


def _times(findings: list[Diagnostic]) -> npt.NDArray[np.int64]:
    """The times (ms) of ``findings``, each of which has one (cell)."""
    import numpy as np

    return np.array([d.time_ms for d in findings], dtype=np.int64)
