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
from collections.abc import Sequence
from typing import TYPE_CHECKING

from motiontool.motionfmt.units import MM_PER_M, MS_PER_S
from motiontool.sim.report import EndEffectorStats, KeyframePose

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.motionfmt import Motion
    from motiontool.sim._mujoco import Scene
    from motiontool.sim.trace import Trace

__all__ = ["DEFAULT_REACH_TOLERANCE_MM", "TRAIL_STEP_S", "measure_end_effector"]

DEFAULT_REACH_TOLERANCE_MM = 1.0
"""A keyframe counts as reached once the tool is this close (mm) to its commanded position."""

TRAIL_STEP_S = 0.05
"""About how often the report samples the tool's path, s (a whole number of control steps)."""


def _keyframe_steps(
    motions: Sequence[Motion], lengths: Sequence[int], timestep_ms: int, reverse: bool, loops: int
) -> list[tuple[int, int, float, int]]:
    """(file index, pose index, time s, first control step at or after it) of every keyframe,
    in the order played (:func:`motiontool.motionfmt.player.elapsed_steps`: each cycle of a
    motion has ceil(D / T) + 1 steps, its playback time ``k T`` at its step ``k``)."""
    out = []
    start = 0
    for f, (motion, length) in enumerate(zip(motions, lengths, strict=True)):
        duration = int(motion.duration_ms)
        cycle = -(-duration // timestep_ms) + 1
        poses = range(motion.n_poses - 1, -1, -1) if reverse else range(motion.n_poses)
        for loop in range(loops):
            for p in poses:
                t_ms = int(motion.times_ms[p])
                played_ms = duration - t_ms if reverse else t_ms
                k = -(-played_ms // timestep_ms)
                step = start + loop * cycle + k
                time_ms = (start + loop * cycle) * timestep_ms + played_ms
                out.append((f, p, time_ms / MS_PER_S, step))
        start += length
    return out


def _angle_deg(a: npt.NDArray[np.float64], b: npt.NDArray[np.float64]) -> float:
    """Angle between two orientations given as unit quaternions (w, x, y, z), degrees."""
    import numpy as np

    dot = min(1.0, abs(float(np.dot(a, b))))
    return math.degrees(2.0 * math.acos(dot))


def measure_end_effector(
    scene: Scene,
    trace: Trace,
    motions: Sequence[Motion],
    lengths: Sequence[int],
    timestep_ms: int,
    *,
    reverse: bool = False,
    loops: int = 1,
    reach_tolerance_mm: float = DEFAULT_REACH_TOLERANCE_MM,
) -> EndEffectorStats | None:
    """The tool's keyframe poses, lags and deviation over the run; None without a tool.

    Args:
        scene: the scene that was run (its ``tool``, model and motor limits).
        trace: the run (``tool_pos`` / ``tool_quat`` every frame).
        motions: the motions played, in order; lengths: the control steps of each.
        timestep_ms: the control step, ms; reverse, loops: as played.
        reach_tolerance_mm: the distance within which a keyframe counts as reached, mm.
    """
    import numpy as np

    from motiontool.sim import _mujoco

    if scene.tool is None or trace.tool_pos is None or trace.tool_quat is None:
        return None
    lim = scene.limits
    targets = np.clip(trace.targets, lim.lower, lim.upper)  # (S', J), S' = steps simulated
    reached = [  # every keyframe the run reached
        kf
        for kf in _keyframe_steps(motions, lengths, timestep_ms, reverse, loops)
        if kf[3] < len(targets) and kf[3] < len(trace.time_s)
    ]
    rows = _keyframe_targets(scene, motions, reached, targets)
    fk_pos, fk_quat = _mujoco.tool_poses(scene, np.concatenate([rows, targets]))
    keyframes = _keyframe_poses(
        trace, motions, reached, fk_pos[: len(rows)], fk_quat[: len(rows)], reach_tolerance_mm
    )
    # The command stream: the target step k sends at time_s[k] against the tool at that time
    # (frame k), aligned as the keyframes are (their target and the tool at their frame).
    deviation = np.linalg.norm(trace.tool_pos[: len(targets)] - fk_pos[len(rows) :], axis=1)
    worst = int(np.argmax(deviation)) if len(deviation) else -1
    samples = _trail_frames(trace)
    return EndEffectorStats(
        frame=scene.tool[0],
        kind=scene.tool[1],
        reach_tolerance_mm=reach_tolerance_mm,
        keyframes=tuple(keyframes),
        max_deviation_mm=float(deviation[worst]) * MM_PER_M if worst >= 0 else 0.0,
        max_deviation_at_s=float(trace.time_s[worst]) if worst >= 0 else 0.0,
        trail_time_s=tuple(float(trace.time_s[k]) for k in samples),
        trail_position_m=tuple(_vec3(trace.tool_pos[k]) for k in samples),
    )


def _keyframe_targets(
    scene: Scene,
    motions: Sequence[Motion],
    reached: Sequence[tuple[int, int, float, int]],
    targets: npt.NDArray[np.float64],
) -> npt.NDArray[np.float64]:
    """(K, J) the motor targets of each keyframe reached: the targets in force at its step with
    the keyframe's own commands over them, clipped to the motor limits."""
    import numpy as np

    lim = scene.limits
    column = {name: j for j, name in enumerate(scene.joints)}
    rows = np.empty((len(reached), len(scene.joints)))
    for i, (f, p, _t, step) in enumerate(reached):
        row = targets[step].copy()
        motion = motions[f]
        for m, name in enumerate(motion.joints):
            if name in column and bool(motion.commanded[p, m]):
                row[column[name]] = motion.values[p, m]
        rows[i] = np.clip(row, lim.lower, lim.upper)
    return rows


def _keyframe_poses(
    trace: Trace,
    motions: Sequence[Motion],
    reached: Sequence[tuple[int, int, float, int]],
    kf_pos: npt.NDArray[np.float64],
    kf_quat: npt.NDArray[np.float64],
    reach_tolerance_mm: float,
) -> list[KeyframePose]:
    """Each keyframe reached: the tool's commanded pose (``kf_pos`` m, ``kf_quat`` w, x, y, z)
    against the measured one at its frame, and its lag: from the keyframe's frame until the
    tool is within the reach tolerance, looked for until the motion goes on to another
    position (None: not reached before)."""
    import numpy as np

    assert trace.tool_pos is not None and trace.tool_quat is not None
    tolerance_m = reach_tolerance_mm / MM_PER_M
    keyframes = []
    for i, (f, p, time_s, step) in enumerate(reached):
        end = len(trace.time_s) - 1
        for later in range(i + 1, len(reached)):
            if np.linalg.norm(kf_pos[later] - kf_pos[i]) > tolerance_m:
                end = max(step, reached[later][3])
                break
        dist = np.linalg.norm(trace.tool_pos[step : end + 1] - kf_pos[i], axis=1)
        within = np.flatnonzero(dist <= tolerance_m)
        lag = (
            None if not len(within) else (float(trace.time_s[step + within[0]]) - time_s) * MS_PER_S
        )
        keyframes.append(
            KeyframePose(
                file_index=f,
                name=motions[f].pose_names[p],
                time_s=time_s,
                commanded_position_m=_vec3(kf_pos[i]),
                commanded_quat_wxyz=_vec4(kf_quat[i]),
                measured_position_m=_vec3(trace.tool_pos[step]),
                measured_quat_wxyz=_vec4(trace.tool_quat[step]),
                position_error_mm=float(np.linalg.norm(trace.tool_pos[step] - kf_pos[i]))
                * MM_PER_M,
                orientation_error_deg=_angle_deg(kf_quat[i], trace.tool_quat[step]),
                lag_ms=lag,
            )
        )
    return keyframes


def _trail_frames(trace: Trace) -> list[int]:
    """The frames of the tool's trail: one every :data:`TRAIL_STEP_S`, and the last."""
    frames = len(trace.time_s)
    stride = max(1, round(TRAIL_STEP_S / trace.control_step_s))
    samples = list(range(0, frames, stride))
    if samples[-1] != frames - 1:
        samples.append(frames - 1)
    return samples


def _vec3(v: npt.NDArray[np.float64]) -> tuple[float, float, float]:
    return (float(v[0]), float(v[1]), float(v[2]))


def _vec4(v: npt.NDArray[np.float64]) -> tuple[float, float, float, float]:
    return (float(v[0]), float(v[1]), float(v[2]), float(v[3]))
