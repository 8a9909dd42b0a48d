"""Chains: motions played in one run, each from the state the one before left, as a Webots
controller plays them (issue 37 item 3).

A run of several motions is one simulation: the physics state (the joints, the base's pose and
velocities) simply goes on from one motion to the next. What a chain adds is said here, once:

- :func:`loop_counts`: ``--loop N`` (every motion N times) and ``--loop NAME=N`` (one element
  of a chain N times, by its path as given, file name or stem);
- :func:`start_pose`: ``--start-pose FILE[:POSE]``, the motor positions of a pose of a motion
  file (the named pose, else the file's last: where the motion leaves the robot);
- :class:`ElementMeter`: what the base did during each element (displacement, distance,
  heading change), from the frame the element starts at to the frame it ends at.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path, PurePath
from typing import TYPE_CHECKING

from motiontool.errors import MotionToolError
from motiontool.sim.measure import tilt_and_heading
from motiontool.sim.report import FileRun

if TYPE_CHECKING:
    from motiontool.sim.trace import Trace

__all__ = ["ElementMeter", "loop_counts", "start_pose"]


def _is_element(name: str, path: str) -> bool:
    """Whether ``name`` names the element played from ``path``: the path as given, its file
    name or its stem."""
    pure = PurePath(path)
    return name in (path, pure.name, pure.stem)


def loop_counts(
    specs: Sequence[str], names: Sequence[str], *, chain: bool, max_count: int
) -> tuple[int, tuple[int, ...]]:
    """The cycles of each motion from ``--loop`` values: ``N`` (every motion) or ``NAME=N``
    (the elements ``NAME`` names, in a chain only; the others keep ``N``, else 1).

    Returns:
        (the count of every motion, the counts of each one in order; empty: no ``NAME=N``).

    Raises:
        MotionToolError: a count that is no whole number from 1 (to ``max_count``), two
            plain counts, ``NAME=N`` without ``chain`` or naming no element.
    """
    every, named = 1, {}
    plain = [s for s in specs if "=" not in s]
    if len(plain) > 1:
        raise MotionToolError(f"--loop {plain[0]} and --loop {plain[1]}: give one count")
    for spec in specs:
        name, _, text = spec.rpartition("=")
        if not text.isdigit() or not 1 <= int(text) <= max_count:
            raise MotionToolError(
                f"--loop {spec}: the count must be a whole number from 1"
                + (f" to {max_count:,}" if text.isdigit() and int(text) > max_count else "")
            )
        if not name and "=" not in spec:
            every = int(text)
            continue
        if not chain:
            raise MotionToolError(f"--loop {spec} loops one element of a chain: pass --chain")
        if not any(_is_element(name, n) for n in names):
            raise MotionToolError(
                f"--loop {spec}: no element {name!r} in the chain ({', '.join(names)})"
            )
        named[name] = int(text)
    if not named:
        return every, ()
    counts = [next((n for k, n in named.items() if _is_element(k, p)), every) for p in names]
    return every, tuple(counts)


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
        raise MotionToolError(f"--start-pose {spec}: no pose {pose!r} (poses: {', '.join(names)})")
    row = motion.values[index].tolist()
    return tuple((j, float(v)) for j, v in zip(motion.joints, row, strict=True) if math.isfinite(v))


class ElementMeter:
    """What a free-flying robot's base did during each motion of a run, a chunk at a time
    (:func:`motiontool.sim._mujoco.run_chunks`): its position and summed heading change at the
    frames where the elements start and end (``lengths``: each element's control steps)."""

    def __init__(self, lengths: Sequence[int]) -> None:
        self.bounds = [0]
        for n in lengths:
            self.bounds.append(self.bounds[-1] + n)
        self._pos: dict[int, tuple[float, float]] = {}
        self._turn: dict[int, float] = {}
        self._turned = 0.0  # heading change so far, degrees (every frame's, unwrapped)

    def add(self, chunk: Trace) -> None:
        """Take the next chunk of the run (its frame 0 is the last frame of the one before)."""
        import numpy as np

        _tilt, heading = tilt_and_heading(chunk.base_quat)
        steps = (np.diff(heading) + 180.0) % 360.0 - 180.0
        turned = self._turned + np.concatenate(([0.0], np.cumsum(steps)))
        first, n = chunk.first_frame, len(chunk.time_s)
        for frame in self.bounds:
            if first <= frame < first + n:
                x, y = chunk.base_pos[frame - first, :2].tolist()
                self._pos[frame], self._turn[frame] = (x, y), float(turned[frame - first])
        self._turned = float(turned[-1])

    def elements(self, files: Sequence[FileRun]) -> list[FileRun]:
        """``files`` with what the base did during each (unchanged where not measured: a run
        that stopped before)."""
        out = []
        for f, start, end in zip(files, self.bounds[:-1], self.bounds[1:], strict=True):
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
