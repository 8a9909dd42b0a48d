"""ROS 2 (a real robot under ros2_control): a ``trajectory_msgs/JointTrajectory`` as the YAML goal
that ``ros2 action send_goal /<controller>/follow_joint_trajectory
control_msgs/action/FollowJointTrajectory`` takes.

What it reproduces: the targets each motor holds while Webots plays the motion at the control
step (:mod:`.held`). ``joint_trajectory_controller`` interpolates a trajectory whose points
give positions only in straight lines between them, so the points are the corners of that
stream (:func:`~.held.corner_keys` of every joint, on one common set of steps: a trajectory
point sets every joint); the deviation each export reports is that linear interpolation,
evaluated at every control step, against Webots' stream.

Times: ``time_from_start`` of a point is Webots' playback time plus a lead-in
(:data:`~.base.DEFAULT_LEAD_IN_MS`): the controller moves from where the robot stands to the
first point in the lead-in (a first point at 0 s would be a jump), then plays the motion as
Webots does. Every joint needs a target from the first step (a point sets them all); names go
to ROS through the joint map (:mod:`.joint_map`).

The goal holds ``trajectory`` only (``joint_names``, ``points`` with ``positions`` and
``time_from_start`` as ``sec`` and ``nanosec``): the tolerances are the controller's defaults.
Numbers are the shortest decimals that read back to the same double, always with a point, so
that YAML reads them as floats.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from motiontool.errors import MotionToolError
from motiontool.motionfmt.convert._ros import duration
from motiontool.motionfmt.convert.base import (
    Deviation,
    Exported,
    ExportOptions,
    RobotStream,
    WorstError,
)
from motiontool.motionfmt.convert.held import HeldStream, corner_keys, held_stream
from motiontool.motionfmt.convert.joint_map import to_ros
from motiontool.motionfmt.convert.urscript import number

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.motionfmt.motion import Motion

__all__ = ["Trajectory", "trajectory", "trajectory_message", "write_ros_trajectory"]

ACTION = "control_msgs/action/FollowJointTrajectory"
"""The action whose goal the YAML is."""

_ROWS = 1 << 16
"""Steps compared at once: the comparison's arrays are of this size, whatever the length."""


@dataclass(frozen=True)
class Trajectory:
    """The points of a trajectory that reproduces Webots' stream.

    Attributes:
        held: the stream it reproduces.
        ros_names: each motor's ROS name, in the order of ``held.motors``.
        steps: intp (K,): the steps of ``held`` that are points.
        lead_in_ms: added to Webots' playback time in ``time_from_start``, ms.
    """

    held: HeldStream
    ros_names: tuple[str, ...]
    steps: npt.NDArray[np.intp]
    lead_in_ms: int

    @property
    def times_ms(self) -> npt.NDArray[np.int64]:
        """int64 (K,): each point's ``time_from_start``, ms."""
        return self.held.elapsed_ms[self.steps] + self.lead_in_ms

    @property
    def positions(self) -> npt.NDArray[np.float64]:
        """float64 (K, N): each point's positions, rad (m)."""
        return self.held.targets[self.steps]


def _every_joint_from_the_start(held: HeldStream) -> None:
    import numpy as np

    unset = np.isnan(held.targets[0])
    if unset.any():
        name = held.motors[int(np.argmax(unset))]
        raise MotionToolError(
            f"{name} has no target in the first pose ('*'): a trajectory point sets every "
            "joint at once; give it a number there"
        )


def trajectory(motion: Motion, options: ExportOptions) -> Trajectory:
    """The points of ``motion`` at ``options.timestep_ms``, named through
    ``options.joint_map``.

    Raises:
        MotionToolError: a joint without a target from the first step, a ``nan``/``inf``
            command, two joints with one ROS name.
    """
    import numpy as np

    held = held_stream(motion, options.timestep_ms)
    _every_joint_from_the_start(held)
    names = to_ros(held.motors, options.joint_map)
    keys = [corner_keys(held.targets[:, k]) for k in range(len(held.motors))]
    steps = np.unique(np.concatenate(keys)).astype(np.intp)
    return Trajectory(held, names, steps, options.lead_in_ms)


def deviation(traj: Trajectory) -> Deviation:
    """The points interpolated in straight lines at every control step, against Webots'
    stream (rad)."""
    import numpy as np

    held = traj.held
    key_t = held.elapsed_ms[traj.steps].astype(np.float64)
    key_q = held.targets[traj.steps]
    worst = WorstError()
    for lo in range(0, held.elapsed_ms.shape[0], _ROWS):  # each step alone: the same in blocks
        t = held.elapsed_ms[lo : lo + _ROWS].astype(np.float64)
        want = held.targets[lo : lo + _ROWS]
        err = np.empty_like(want)
        for k in range(len(held.motors)):
            err[:, k] = np.abs(np.interp(t, key_t, key_q[:, k]) - want[:, k])
        worst.update(err, lo)
    return Deviation(
        worst.rad,
        held.motors[worst.column],
        int(held.elapsed_ms[worst.row]),
        f"{traj.steps.shape[0]} points interpolated in straight lines, against Webots' stream "
        f"at every step ({held.targets.size} targets)",
    )


def trajectory_message(traj: Trajectory) -> dict[str, Any]:
    """The ``trajectory_msgs/JointTrajectory`` as nested dicts (header stamp 0: start now)."""
    return {
        "header": {"stamp": {"sec": 0, "nanosec": 0}, "frame_id": ""},
        "joint_names": list(traj.ros_names),
        "points": [
            {
                "positions": [float(v) for v in row],
                "velocities": [],
                "accelerations": [],
                "effort": [],
                "time_from_start": duration(int(ms)),
            }
            for ms, row in zip(traj.times_ms, traj.positions, strict=True)
        ],
    }


def _yaml(traj: Trajectory, options: ExportOptions) -> bytes:
    names = ", ".join(json.dumps(n) for n in traj.ros_names)
    lines = [
        f"# motiontool convert: {options.source} for {options.robot or 'a ROS 2 robot'}: "
        f"Webots' command stream every {options.timestep_ms} ms as {traj.steps.shape[0]} points",
        "# (joint_trajectory_controller draws straight lines between points given as positions),",
        f"# the first at {traj.lead_in_ms} ms: the robot reaches it from where it stands.",
        "# ros2 action send_goal /joint_trajectory_controller/follow_joint_trajectory \\",
        f'#   {ACTION} "$(cat {options.target_name or "THIS_FILE"})"',
        "trajectory:",
        f"  joint_names: [{names}]",
        "  points:",
    ]
    for ms, row in zip(traj.times_ms, traj.positions, strict=True):
        t = duration(int(ms))
        q = ", ".join(number(float(v)) for v in row)
        lines.append(
            f"  - {{positions: [{q}], time_from_start: {{sec: {t['sec']}, "
            f"nanosec: {t['nanosec']}}}}}"
        )
    return ("\n".join(lines) + "\n").encode("utf-8", "surrogateescape")


def write_ros_trajectory(motion: Motion, options: ExportOptions) -> Exported:
    """The goal YAML (see the module)."""
    traj = trajectory(motion, options)
    stream = RobotStream(traj.held.motors, traj.held.elapsed_ms[traj.steps], traj.positions)
    detail = f"{len(traj.ros_names)} joints, the first at {traj.lead_in_ms} ms, a goal of {ACTION}"
    return Exported(_yaml(traj, options), traj.steps.shape[0], detail, deviation(traj), (), stream)
