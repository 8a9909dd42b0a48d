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
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from motiontool.errors import MotionToolError
from motiontool.motionfmt.convert._ros import duration
from motiontool.motionfmt.convert.base import (
    Deviation,
    Exported,
    ExportOptions,
    RobotStream,
    StreamChunk,
    WorstError,
    robot_check,
)
from motiontool.motionfmt.convert.held import Corners, held_chunks
from motiontool.motionfmt.convert.joint_map import to_ros
from motiontool.motionfmt.convert.urscript import number

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.motionfmt.motion import Motion

__all__ = [
    "CONTROLLER",
    "CONTROLLERS",
    "Trajectory",
    "controller",
    "trajectory",
    "trajectory_message",
    "write_ros_trajectory",
]

ACTION = "control_msgs/action/FollowJointTrajectory"
"""The action whose goal the YAML is."""

CONTROLLER = "joint_trajectory_controller"
"""The controller whose action the goal is sent to, unless the robot's driver starts another
(:data:`CONTROLLERS`)."""

CONTROLLERS: dict[str, str] = {"ur5e": "scaled_joint_trajectory_controller"}
"""Robot -> the trajectory controller its ROS 2 driver starts: Universal Robots' driver
(ur_robot_driver's ``ur_control.launch.py``) starts ``scaled_joint_trajectory_controller``,
which scales the trajectory with the speed slider, and leaves ``joint_trajectory_controller``
inactive."""


def controller(robot: str | None) -> str:
    """The trajectory controller of ``robot``'s ROS 2 driver (:data:`CONTROLLERS`)."""
    return CONTROLLERS.get(robot or "", CONTROLLER)


_ROWS = 1 << 16
"""Steps compared at once: the comparison's arrays are of this size, whatever the length."""


@dataclass(frozen=True)
class Trajectory:
    """The points of a trajectory that reproduces Webots' stream.

    Attributes:
        motors: the N motors, in the stream's order.
        ros_names: each motor's ROS name, in that order.
        elapsed_ms: int64 (K,): Webots' playback time of each point, ms.
        positions: float64 (K, N): each point's positions, rad (m).
        lead_in_ms: added to Webots' playback time in ``time_from_start``, ms.
        held: what makes the stream it reproduces a chunk of steps at a time
            (:func:`~.held.held_chunks`), each time it is called.
        steps: how many steps that stream has.
    """

    motors: tuple[str, ...]
    ros_names: tuple[str, ...]
    elapsed_ms: npt.NDArray[np.int64]
    positions: npt.NDArray[np.float64]
    lead_in_ms: int
    held: Callable[[], Iterator[StreamChunk]]
    steps: int

    @property
    def times_ms(self) -> npt.NDArray[np.int64]:
        """int64 (K,): each point's ``time_from_start``, ms."""
        return self.elapsed_ms + self.lead_in_ms


def _every_joint_from_the_start(motors: tuple[str, ...], first: npt.NDArray[np.float64]) -> None:
    import numpy as np

    unset = np.isnan(first)
    if unset.any():
        name = motors[int(np.argmax(unset))]
        raise MotionToolError(
            f"{name} has no target in the first pose ('*'): a trajectory point sets every "
            "joint at once; give it a number there"
        )


def trajectory(motion: Motion, options: ExportOptions) -> Trajectory:
    """The points of ``motion`` at ``options.timestep_ms``, named through
    ``options.joint_map`` (:func:`~.joint_map.to_ros`; of several motors with one ROS name, the
    first gives its position: the caller checks that the others agree): the steps where any
    joint's held target has a corner, found with the stream made a chunk of steps at a time,
    then their positions (a second pass).

    Raises:
        MotionToolError: a joint without a target from the first step, a ``nan``/``inf``
            command.
    """
    import numpy as np

    every, held = held_chunks(motion, options.timestep_ms)
    named = to_ros(every, options.joint_map)
    keep = [named.index(name) for name in dict.fromkeys(named)]
    motors, names = tuple(every[k] for k in keep), tuple(named[k] for k in keep)

    def chunks() -> Iterator[StreamChunk]:  # one column per ROS name: its first motor's
        for elapsed, targets in held():
            yield elapsed, targets[:, keep]

    corners = [Corners() for _ in motors]
    for elapsed, targets in chunks():
        if corners[0].count == 0:
            _every_joint_from_the_start(motors, targets[0])
        for k, found in enumerate(corners):
            found.add(elapsed, targets[:, k])
    points = np.unique(np.concatenate([found.keys()[0] for found in corners]))
    positions = np.concatenate(
        [targets[np.isin(elapsed, points)] for elapsed, targets in chunks()]
    ).reshape(-1, len(motors))
    return Trajectory(
        motors, names, points, positions, options.lead_in_ms, chunks, corners[0].count
    )


def deviation(traj: Trajectory) -> Deviation:
    """The points interpolated in straight lines at every control step, against Webots'
    stream (rad), the stream made a chunk of steps at a time."""
    import numpy as np

    key_t = traj.elapsed_ms.astype(np.float64)
    worst, row = WorstError(), 0
    for elapsed, want in traj.held():
        for lo in range(0, elapsed.shape[0], _ROWS):  # each step alone: the same in blocks
            at = elapsed[lo : lo + _ROWS]
            t, block = at.astype(np.float64), want[lo : lo + _ROWS]
            err = np.empty_like(block)
            for k in range(len(traj.motors)):
                err[:, k] = np.abs(np.interp(t, key_t, traj.positions[:, k]) - block[:, k])
            worst.update(err, row, at)
            row += block.shape[0]
    return Deviation(
        worst.rad,
        traj.motors[worst.column],
        worst.at_ms,
        f"{traj.elapsed_ms.shape[0]} points interpolated in straight lines, against Webots' "
        f"stream at every step ({traj.steps * len(traj.motors)} targets)",
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
        f"Webots' command stream every {options.timestep_ms} ms as "
        f"{traj.elapsed_ms.shape[0]} points",
        "# (joint_trajectory_controller draws straight lines between points given as positions),",
        f"# the first at {traj.lead_in_ms} ms: the robot reaches it from where it stands.",
        f"# robot check: {robot_check(options)}",
        f"# ros2 action send_goal /{controller(options.robot)}/follow_joint_trajectory \\",
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
    stream = RobotStream(traj.motors, traj.elapsed_ms, traj.positions)
    detail = f"{len(traj.ros_names)} joints, the first at {traj.lead_in_ms} ms, a goal of {ACTION}"
    points = traj.elapsed_ms.shape[0]
    return Exported(_yaml(traj, options), points, detail, deviation(traj), (), stream)
