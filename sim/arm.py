"""The end effector of a fixed-base arm over a run: where each keyframe puts the tool, where the
simulated tool is, how long it takes to get there.

For every keyframe the run reaches (each motion's poses in the order they are played: reversed
with ``--reverse``, repeated with ``--loop``), the commanded tool pose is the forward kinematics
of the keyframe's joint targets, computed by MuJoCo on the scene's own model
(:func:`motiontool.sim._mujoco.tool_poses`): the commanded and the measured poses come from one
model in one world frame (the arm on its box), and ``play`` needs no Pinocchio.

The targets are the keyframe's values, clipped to the motor limits as the motors see them; a
``*`` cell, or a motor the motion does not name, holds the target in force. The measured pose is
the simulated tool at the first frame at or after the keyframe time.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence
from dataclasses import replace
from typing import TYPE_CHECKING, Any

from motiontool.motionfmt.units import MM_PER_M, MS_PER_S
from motiontool.sim.commands import each_loops
from motiontool.sim.recording_paths import Thinned
from motiontool.sim.report import EndEffectorStats, KeyframePose

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.motionfmt import Motion
    from motiontool.sim._mujoco import Scene
    from motiontool.sim.trace import Trace

__all__ = ["DEFAULT_REACH_TOLERANCE_MM", "TRAIL_POINTS", "TRAIL_STEP_S", "ToolMeter"]

DEFAULT_REACH_TOLERANCE_MM = 1.0
"""A keyframe counts as reached once the tool is this close (mm) to its commanded position."""

TRAIL_STEP_S = 0.05
"""About how often the report samples the tool's path, s (a whole number of control steps)."""

TRAIL_POINTS = 5_000
"""The most samples of the tool's path a report keeps (250 s of run at :data:`TRAIL_STEP_S`):
past them, every other one is let go, as often as needed (samples every 100 ms, 200 ms, ...)."""


def _keyframe_steps(
    motions: Sequence[Motion],
    lengths: Sequence[int],
    timestep_ms: int,
    reverse: bool,
    loops: Sequence[int],
) -> Iterator[tuple[int, int, int, int]]:
    """(file index, pose index, time ms, first control step at or after it) of every keyframe,
    in the order played (:func:`motiontool.motionfmt.player.elapsed_steps`: each cycle of a
    motion has ceil(D / T) + 1 steps, its playback time ``k T`` at its step ``k``)."""
    start = 0
    for f, (motion, length) in enumerate(zip(motions, lengths, strict=True)):
        duration = int(motion.duration_ms)
        cycle = -(-duration // timestep_ms) + 1
        poses = range(motion.n_poses - 1, -1, -1) if reverse else range(motion.n_poses)
        for loop in range(loops[f]):
            for p in poses:
                t_ms = int(motion.times_ms[p])
                played_ms = duration - t_ms if reverse else t_ms
                k = -(-played_ms // timestep_ms)
                step = start + loop * cycle + k
                time_ms = (start + loop * cycle) * timestep_ms + played_ms
                yield f, p, time_ms, step
        start += length


def _angle_deg(a: npt.NDArray[np.float64], b: npt.NDArray[np.float64]) -> float:
    """Angle between two orientations given as unit quaternions (w, x, y, z), degrees."""
    import numpy as np

    dot = min(1.0, abs(float(np.dot(a, b))))
    return math.degrees(2.0 * math.acos(dot))


class _Visit:
    """A visit of a keyframe whose lag is not known yet (see :meth:`ToolMeter.add`)."""

    __slots__ = ("end", "entry", "next_frame", "position", "step", "time_ms")

    def __init__(self, entry: _Entry, step: int, time_ms: int, position: Any) -> None:
        self.entry, self.step, self.time_ms, self.position = entry, step, time_ms, position
        self.next_frame = step  # the next frame to look at for its lag
        self.end: int | None = None  # the last frame to look at: None while not known


class _Entry:
    """A keyframe of a motion over the visits measured so far: the visit with the largest
    position error, how many, the longest lag found, whether a visit never came within the
    tolerance, the box of the measured positions (m)."""

    __slots__ = ("high", "lag_ms", "low", "never", "pose", "visits")

    def __init__(self, pose: KeyframePose) -> None:
        self.pose, self.visits = pose, 1
        self.low = self.high = pose.measured_position_m
        self.lag_ms: float | None = None
        self.never = False

    def visit(self, pose: KeyframePose) -> None:
        self.visits += 1
        p = pose.measured_position_m
        self.low = (min(self.low[0], p[0]), min(self.low[1], p[1]), min(self.low[2], p[2]))
        self.high = (max(self.high[0], p[0]), max(self.high[1], p[1]), max(self.high[2], p[2]))
        if pose.position_error_mm > self.pose.position_error_mm:
            self.pose = pose

    def reached(self, lag_ms: float) -> None:
        self.lag_ms = lag_ms if self.lag_ms is None else max(self.lag_ms, lag_ms)

    def folded(self, never: bool) -> KeyframePose:
        """The report's entry; ``never``: a visit's lag is still open at the end of the run."""
        lag = None if self.never or never else self.lag_ms
        box = (self.low, self.high)
        return replace(self.pose, lag_ms=lag, visits=self.visits, measured_box_m=box)


class ToolMeter:
    """The tool's keyframe poses, lags and deviation over a run, measured a chunk at a time as
    :class:`motiontool.sim.measure.RunMeter` measures the rest (:meth:`add` each chunk, then
    :meth:`stats`); a keyframe stays held only until its lag is known.

    For every keyframe reached, the commanded pose is the forward kinematics of its targets
    and the measured one the tool at its frame. Its lag is looked for from its frame until the
    motion goes on to another position (the frame of the next keyframe reached whose commanded
    position is further than the tolerance) or the run ends. The visits of one keyframe of a
    motion (``--loop``) fold into one entry (:class:`KeyframePose`), and the trail keeps at
    most :data:`TRAIL_POINTS` samples: what the meter holds does not grow with the run.
    """

    def __init__(
        self,
        scene: Scene,
        motions: Sequence[Motion],
        lengths: Sequence[int],
        timestep_ms: int,
        *,
        reverse: bool = False,
        loops: int | Sequence[int] = 1,
        reach_tolerance_mm: float = DEFAULT_REACH_TOLERANCE_MM,
    ) -> None:
        assert scene.tool is not None
        self.scene, self.motions = scene, motions
        self.reach_tolerance_mm = reach_tolerance_mm
        self._tolerance_m = reach_tolerance_mm / MM_PER_M
        self._step_ms = timestep_ms
        counts = each_loops(loops, len(motions))
        self._coming = _keyframe_steps(motions, lengths, timestep_ms, reverse, counts)
        self._next = next(self._coming, None)
        self._entries: dict[tuple[int, int], _Entry] = {}  # (file, pose): in the order first met
        self._open: list[_Visit] = []
        self._worst: tuple[Any, float] | None = None  # deviation m, at s
        self._trail = Thinned(TRAIL_POINTS)  # rows (time s, x, y, z m), by sample index
        self._last: Trace | None = None

    def add(self, chunk: Trace) -> None:
        """Measure the next chunk of the run."""
        import numpy as np

        from motiontool.sim import _mujoco

        assert chunk.tool_pos is not None and chunk.tool_quat is not None
        lim = self.scene.limits
        targets = np.clip(chunk.targets[: chunk.steps_done], lim.lower, lim.upper)
        reached = self._reached(chunk.first_frame + len(targets))
        rows = self._keyframe_targets(reached, targets, chunk.first_frame)
        fk_pos, fk_quat = _mujoco.tool_poses(self.scene, np.concatenate([rows, targets]))
        self._new_keyframes(chunk, reached, fk_pos[: len(rows)], fk_quat[: len(rows)])
        self._lags(chunk)
        # The command stream: the target step k sends at time_s[k] against the tool at that
        # time (frame k), aligned as the keyframes are (their target and the tool at their frame).
        deviation = np.linalg.norm(chunk.tool_pos[: len(targets)] - fk_pos[len(rows) :], axis=1)
        if len(deviation):
            k = int(np.argmax(deviation))
            if self._worst is None or deviation[k] > self._worst[0]:
                self._worst = (deviation[k], float(chunk.time_s[k]))
        self._sample_trail(chunk)
        self._last = chunk

    def _reached(self, steps: int) -> list[tuple[int, int, int, int]]:
        """The keyframes not met yet whose step is before ``steps`` (the steps simulated)."""
        out = []
        while self._next is not None and self._next[3] < steps:
            out.append(self._next)
            self._next = next(self._coming, None)
        return out

    def _keyframe_targets(
        self,
        reached: Sequence[tuple[int, int, int, int]],
        targets: npt.NDArray[np.float64],
        first: int,
    ) -> npt.NDArray[np.float64]:
        """(K, J) the motor targets of each keyframe reached: the targets in force at its step
        (row ``step - first`` of ``targets``) with the keyframe's own commands over them,
        clipped to the motor limits."""
        import numpy as np

        scene, lim = self.scene, self.scene.limits
        column = {name: j for j, name in enumerate(scene.joints)}
        rows = np.empty((len(reached), len(scene.joints)))
        for i, (f, p, _t, step) in enumerate(reached):
            row = targets[step - first].copy()
            motion = self.motions[f]
            for m, name in enumerate(motion.joints):
                if name in column and bool(motion.commanded[p, m]):
                    row[column[name]] = motion.values[p, m]
            rows[i] = np.clip(row, lim.lower, lim.upper)
        return rows

    def _new_keyframes(
        self,
        chunk: Trace,
        reached: Sequence[tuple[int, int, int, int]],
        kf_pos: npt.NDArray[np.float64],
        kf_quat: npt.NDArray[np.float64],
    ) -> None:
        """Measure the keyframes ``reached`` in ``chunk`` (commanded pose ``kf_pos`` m,
        ``kf_quat`` w, x, y, z), and close the lag window of those before that they end."""
        import numpy as np

        assert chunk.tool_pos is not None and chunk.tool_quat is not None
        for (f, p, time_ms, step), pos, quat in zip(reached, kf_pos, kf_quat, strict=True):
            for earlier in self._open:
                if (
                    earlier.end is None
                    and np.linalg.norm(pos - earlier.position) > self._tolerance_m
                ):
                    earlier.end = max(earlier.step, step)
            measured_pos, measured_quat = (
                chunk.tool_pos[step - chunk.first_frame],
                chunk.tool_quat[step - chunk.first_frame],
            )
            pose = KeyframePose(
                file_index=f,
                name=self.motions[f].pose_names[p],
                time_s=time_ms / MS_PER_S,
                commanded_position_m=_vec3(pos),
                commanded_quat_wxyz=_vec4(quat),
                measured_position_m=_vec3(measured_pos),
                measured_quat_wxyz=_vec4(measured_quat),
                position_error_mm=float(np.linalg.norm(measured_pos - pos)) * MM_PER_M,
                orientation_error_deg=_angle_deg(quat, measured_quat),
                lag_ms=None,
            )
            entry = self._entries.get((f, p))
            if entry is None:
                entry = self._entries[f, p] = _Entry(pose)
            else:
                entry.visit(pose)
            self._open.append(_Visit(entry, step, time_ms, pos))

    def _lags(self, chunk: Trace) -> None:
        """Look for each open keyframe's lag in the frames of ``chunk``; a keyframe whose lag
        is found, or whose window is over, is closed."""
        import numpy as np

        assert chunk.tool_pos is not None
        still = []
        for kf in self._open:
            stop = chunk.last_frame if kf.end is None else min(kf.end, chunk.last_frame)
            dist = np.linalg.norm(
                chunk.tool_pos[kf.next_frame - chunk.first_frame : stop - chunk.first_frame + 1]
                - kf.position,
                axis=1,
            )
            within = np.flatnonzero(dist <= self._tolerance_m)
            if len(within):
                frame = kf.next_frame + int(within[0]) - chunk.first_frame
                lag_ms = (chunk.first_frame + frame) * self._step_ms - kf.time_ms  # whole ms
                kf.entry.reached(float(lag_ms))
                continue
            kf.next_frame = stop + 1
            if kf.end is None or kf.next_frame <= kf.end:
                still.append(kf)
            else:
                kf.entry.never = True
        self._open = still

    def _sample_trail(self, chunk: Trace) -> None:
        """The tool's trail in ``chunk``: a frame every :data:`TRAIL_STEP_S`."""
        assert chunk.tool_pos is not None
        import numpy as np

        stride = max(1, round(TRAIL_STEP_S / chunk.control_step_s))
        new = 0 if self._last is None else 1
        first = -(-(chunk.first_frame + new) // stride) * stride
        frames = np.arange(first, chunk.last_frame + 1, stride) - chunk.first_frame
        if len(frames):
            rows = np.column_stack([chunk.time_s[frames], chunk.tool_pos[frames]])
            self._trail.add(first // stride, rows)

    def stats(self) -> EndEffectorStats:
        """The end effector's report over the chunks measured."""
        last = self._last
        assert last is not None and last.tool_pos is not None and self.scene.tool is not None
        trail = [(float(r[0]), _vec3(r[1:])) for r in self._trail.kept(4)]
        if not trail or trail[-1][0] != float(last.time_s[-1]):  # the last frame, always
            trail.append((float(last.time_s[-1]), _vec3(last.tool_pos[-1])))
        open_at_end = {id(kf.entry) for kf in self._open}
        keyframes = tuple(e.folded(id(e) in open_at_end) for e in self._entries.values())
        worst_m, worst_s = self._worst if self._worst is not None else (0.0, 0.0)
        return EndEffectorStats(
            frame=self.scene.tool[0],
            kind=self.scene.tool[1],
            reach_tolerance_mm=self.reach_tolerance_mm,
            keyframes=keyframes,
            max_deviation_mm=float(worst_m) * MM_PER_M,
            max_deviation_at_s=worst_s,
            trail_time_s=tuple(t for t, _ in trail),
            trail_position_m=tuple(p for _, p in trail),
        )


def _vec3(v: npt.NDArray[np.float64]) -> tuple[float, float, float]:
    return (float(v[0]), float(v[1]), float(v[2]))


def _vec4(v: npt.NDArray[np.float64]) -> tuple[float, float, float, float]:
    return (float(v[0]), float(v[1]), float(v[2]), float(v[3]))
