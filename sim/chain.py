"""Chains: motions played in one run, each from the state the one before left, as a Webots
controller plays them.

A run of several motions is one simulation: the physics state (the joints, the base's pose and
velocities) simply goes on from one motion to the next. What a chain adds is said here, once:

- the loop count of each element (``PlayOptions.chain_loops``; ``play --loop NAME=N``,
  :mod:`motiontool.cli.chain_options`);
- :func:`start_pose`: a pose of a motion file to start from (``FILE:POSE``, or ``FILE``: its
  last pose, where the motion leaves the robot), its motor positions, and :func:`posed`, those
  of the robot's motors;
- :class:`ElementMeter`: each element's place in the run (:class:`FileRun`) and what the base
  did during it (displacement, distance, heading change), from the frame the element starts
  at to the frame it ends at.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

from motiontool.errors import MotionToolError
from motiontool.motionfmt.units import MS_PER_S
from motiontool.sim.measure import tilt_and_heading
from motiontool.sim.report import FileRun

if TYPE_CHECKING:
    from motiontool.kinematics.robots import RobotSpec
    from motiontool.sim.trace import Trace

__all__ = ["ElementMeter", "file_runs", "posed", "start_pose"]


def start_pose(spec: str) -> tuple[tuple[str, float], ...]:
    """The motor positions (rad, m) of the pose ``spec`` names: ``FILE:POSE`` (the pose named
    POSE, the first of that name), or ``FILE`` (its last pose: where the motion leaves the
    robot); a ``*`` cell is no position (that motor starts at zero).

    Raises:
        MotionToolError: the file cannot be read or played (as ``play`` reads it), or it has
            no pose of that name.
    """
    from motiontool.sim.play import read_playable

    file, pose = spec, None
    if not Path(spec).is_file() and ":" in spec:
        file, _, pose = spec.rpartition(":")
    motion = read_playable(file)
    names = list(motion.pose_names)
    if pose is None:
        index = len(names) - 1
    elif pose in names:
        index = names.index(pose)
    else:
        raise MotionToolError(f"start pose {spec}: no pose {pose!r} (poses: {', '.join(names)})")
    row = motion.values[index].tolist()
    return tuple((j, float(v)) for j, v in zip(motion.joints, row, strict=True) if math.isfinite(v))


def posed(
    label: str | None, pose: Sequence[tuple[str, float]], robot: RobotSpec
) -> list[tuple[str, float]]:
    """The positions of ``pose`` (:func:`start_pose`, named ``label``; None: no start pose) that
    are the robot's motors (the others are ignored, as a motion's columns are).

    Raises:
        MotionToolError: a start pose none of whose joints is a motor of the robot.
    """
    mine = [(k, v) for k, v in pose if k in robot.joint_names]
    if label is not None and not mine:
        names = ", ".join(k for k, _v in pose)
        raise MotionToolError(
            f"start pose {label}: none of its joints ({names}) is a motor of {robot.name}"
        )
    return mine


def file_runs(
    names: Sequence[str], lengths: Sequence[int], step_ms: int, loops: Sequence[int]
) -> list[FileRun]:
    """Where each motion starts and how long it plays (s, from whole ms: 201 steps of 20 ms
    are 4.02 s, where 201 * 0.02 is 4.0200000000000005), its ``lengths`` in control steps of
    ``step_ms`` ms, its cycles."""
    files = []
    step = 0
    for name, n, cycles in zip(names, lengths, loops, strict=True):
        start, duration = step * step_ms / MS_PER_S, n * step_ms / MS_PER_S
        files.append(FileRun(name, start, duration, n, cycles))
        step += n
    return files


class ElementMeter:
    """Each motion of a run (:func:`file_runs`) and, for a free-flying robot (``floating``),
    what its base did, a chunk at a time (:func:`motiontool.sim._mujoco.run_chunks`): its
    position and summed heading change at the frames where the elements start and end."""

    def __init__(
        self,
        names: Sequence[str],
        lengths: Sequence[int],
        step_ms: int,
        loops: Sequence[int],
        *,
        floating: bool,
    ) -> None:
        self.runs = file_runs(names, lengths, step_ms, loops)
        self.floating = floating
        self.bounds = [0]
        for n in lengths:
            self.bounds.append(self.bounds[-1] + n)
        self._pos: dict[int, tuple[float, float]] = {}
        self._turn: dict[int, float] = {}
        self._turned = 0.0  # heading change so far, degrees (every frame's, unwrapped)

    def add(self, chunk: Trace) -> None:
        """Take the next chunk of the run (its frame 0 is the last frame of the one before)."""
        import numpy as np

        if not self.floating:
            return
        _tilt, heading = tilt_and_heading(chunk.base_quat)
        steps = (np.diff(heading) + 180.0) % 360.0 - 180.0
        turned = self._turned + np.concatenate(([0.0], np.cumsum(steps)))
        first, n = chunk.first_frame, len(chunk.time_s)
        for frame in self.bounds:
            if first <= frame < first + n:
                x, y = chunk.base_pos[frame - first, :2].tolist()
                self._pos[frame], self._turn[frame] = (x, y), float(turned[frame - first])
        self._turned = float(turned[-1])

    def files(self) -> list[FileRun]:
        """Each motion of the run with what the base did during it (not where not measured: a
        fixed base, a run that stopped before)."""
        out = []
        for f, start, end in zip(self.runs, self.bounds[:-1], self.bounds[1:], strict=True):
            if start not in self._pos or end not in self._pos:
                out.append(f)
                continue
            (x0, y0), (x1, y1) = self._pos[start], self._pos[end]
            out.append(
                replace(
                    f,
                    dx_m=x1 - x0,
                    dy_m=y1 - y0,
                    distance_m=math.hypot(x1 - x0, y1 - y0),
                    yaw_change_deg=self._turn[end] - self._turn[start],
                )
            )
        return out
