"""ROS 2 bags (MCAP storage, one ``.mcap`` file), both ways.

Written: Webots' command stream at the control step as ``sensor_msgs/JointState`` on the topic
asked for (``/joint_states`` by default): one message per step, ``position`` the targets each
motor holds (:mod:`.held`; the doubles as they are), ``header.stamp`` Webots' playback time from
0 s; and on ``/joint_trajectory`` one ``trajectory_msgs/JointTrajectory`` at 0 s, the points
:mod:`.ros_trajectory` sends to a robot (``time_from_start`` with the lead-in). Names go to ROS
through the joint map (a Nao's phalanges as NAOqi's ``LHand``, ``RHand``). A metadata record
``motiontool`` holds ``source`` and ``robot_check`` (the robot the export was checked against,
or ``unchecked``).

Read: the ``sensor_msgs/JointState`` messages of one topic (a real robot's ``/joint_states``,
at 125 to 500 Hz) become a motion: times from the first stamp, in whole ms (a sample whose ms
an earlier one already has is left out), ROS names mapped back (a NAO's ``LHand``:
``LPhalanx1..8``), then the keyframes reduced within ``max_error_rad`` by the same reduction as
``resample --max-error`` (:func:`~motiontool.motionfmt.resample.resample`). What is reported is
the motion against every recorded sample at its own stamp (:class:`~.base.Recording`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from motiontool.errors import MotionToolError
from motiontool.motionfmt.convert._ros import (
    JOINT_STATE,
    JOINT_TRAJECTORY,
    NS_PER_MS,
    BagTopic,
    JointStates,
    read_joint_states,
    stamp,
    write_bag,
)
from motiontool.motionfmt.convert.base import (
    Deviation,
    Exported,
    ExportOptions,
    Imported,
    ImportOptions,
    Recording,
    RobotStream,
    robot_check,
)
from motiontool.motionfmt.convert.joint_map import from_ros, spread_hands
from motiontool.motionfmt.convert.ros_trajectory import (
    deviation,
    trajectory,
    trajectory_message,
)
from motiontool.motionfmt.convert.sampled import deviation_at, reduced
from motiontool.motionfmt.cscan import INT_MAX
from motiontool.motionfmt.writer import check_name

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.motionfmt.motion import Motion

__all__ = ["TRAJECTORY_TOPIC", "read_rosbag", "write_rosbag"]

TRAJECTORY_TOPIC = "/joint_trajectory"
"""Where a written bag holds the trajectory (``joint_trajectory_controller``'s topic name)."""


def write_rosbag(motion: Motion, options: ExportOptions) -> Exported:
    """The bag (see the module)."""
    import numpy as np

    traj = trajectory(motion, options)
    names = list(traj.ros_names)
    states = (  # made one at a time as the bag is written, from the stream a chunk at a time
        (
            int(ms) * NS_PER_MS,
            {
                "header": {"stamp": stamp(int(ms) * NS_PER_MS), "frame_id": ""},
                "name": names,
                "position": row.tolist(),
                "velocity": [],
                "effort": [],
            },
        )
        for elapsed, targets in traj.held()
        for ms, row in zip(elapsed, targets, strict=True)
    )
    data = write_bag(
        [
            BagTopic(options.topic, JOINT_STATE, states),
            BagTopic(TRAJECTORY_TOPIC, JOINT_TRAJECTORY, [(0, trajectory_message(traj))]),
        ],
        "a ROS 2 bag",
        {"motiontool": {"source": options.source, "robot_check": robot_check(options)}},
    )
    worst = deviation(traj)
    n_states = traj.steps
    compared = (
        f"{n_states} JointState messages (the stream's own doubles) and the trajectory's "
        f"{worst.compared}"
    )
    detail = (
        f"{options.topic}: sensor_msgs/JointState every {options.timestep_ms} ms, "
        f"{len(names)} joints; {TRAJECTORY_TOPIC}: a JointTrajectory of "
        f"{traj.elapsed_ms.shape[0]} points"
    )
    empty = np.zeros(0, dtype=np.int64)
    stream = RobotStream(traj.motors, empty, np.zeros((0, len(names))), traj.held)
    return Exported(
        data,
        n_states,
        detail,
        Deviation(worst.max_rad, worst.joint, worst.at_ms, compared),
        stream=stream,
    )


def _seconds(ns: int) -> str:
    """``ns`` nanoseconds as seconds with all nine decimals, exactly."""
    return f"{'-' if ns < 0 else ''}{abs(ns) // 10**9}.{abs(ns) % 10**9:09d}"


def _checked(states: JointStates, path: str, topic: str) -> tuple[str, ...]:
    """The ROS names every message gives, in the first message's order; raises at the first
    message that disagrees, is not after the one before, or holds a non-finite position."""
    import numpy as np

    if not states.names:
        raise MotionToolError(f"'{path}': topic {topic} holds no message")
    first = states.names[0]
    if not first or len(set(first)) != len(first):
        raise MotionToolError(
            f"'{path}': {topic} message 1 names {list(first)}: no joint or one twice"
        )
    for i, (names, q) in enumerate(zip(states.names, states.positions, strict=True)):
        where = f"'{path}': {topic} message {i + 1}"
        if set(names) != set(first) or len(names) != len(first):
            raise MotionToolError(f"{where} names {list(names)}, the first names {list(first)}")
        if q.shape != (len(names),):
            raise MotionToolError(f"{where} has {q.shape[0]} positions for {len(names)} names")
        if not np.isfinite(q).all():
            bad = names[int(np.argmax(~np.isfinite(q)))]
            raise MotionToolError(f"{where}: {bad} = {float(q[names.index(bad)])!r} is not finite")
        if i and states.stamps_ns[i] <= states.stamps_ns[i - 1]:
            raise MotionToolError(
                f"{where} is stamped {_seconds(int(states.stamps_ns[i]))} s, not after message "
                f"{i}'s {_seconds(int(states.stamps_ns[i - 1]))} s: header stamps must increase"
            )
    return first


def _samples(
    states: JointStates, order: tuple[str, ...], path: str
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """(times from the first stamp, ms, float64 (M,); positions float64 (M, J) in ``order``)."""
    import numpy as np

    t_ms = (states.stamps_ns - states.stamps_ns[0]) / NS_PER_MS
    if t_ms[-1] > INT_MAX:
        raise MotionToolError(f"'{path}': {t_ms[-1]:.0f} ms long, beyond {INT_MAX} ms")
    q = np.empty((len(states.names), len(order)))
    for i, (names, row) in enumerate(zip(states.names, states.positions, strict=True)):
        q[i] = row if names == order else row[[names.index(n) for n in order]]
    return t_ms, q


def read_rosbag(data: bytes, path: str, options: ImportOptions | None = None) -> Imported:
    """The motion a bag's ``sensor_msgs/JointState`` topic records (see the module).

    Raises:
        MotionToolError: not a bag, no such topic, a topic of another type, stamps that do not
            increase, messages that disagree on their joints, a non-finite position.
    """
    opts = options or ImportOptions()
    states = read_joint_states(data, path, opts.topic)
    order = _checked(states, path, opts.topic)
    joints, columns = spread_hands(from_ros(order, opts.joint_map))
    for joint in joints:
        check_name(joint, "joint")
    t_ms, q = _samples(states, order, path)
    q = q[:, columns]
    motion, merged = reduced(joints, t_ms, q, opts.max_error_rad, path)
    compared = f"{q.size} recorded positions ({q.shape[0]} messages), each at its own stamp"
    worst = deviation_at(motion, t_ms, q, compared)
    recording = Recording(
        opts.topic, len(states.names), round(float(t_ms[-1])), merged, opts.max_error_rad, worst
    )
    return Imported(motion, path, recording=recording)
