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
    read_bag_folder,
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
from motiontool.motionfmt.convert.joint_states import Merged, joint_deviation, merged
from motiontool.motionfmt.convert.ros_trajectory import (
    deviation,
    trajectory,
    trajectory_message,
)
from motiontool.motionfmt.convert.sampled import reduced
from motiontool.motionfmt.cscan import INT_MAX
from motiontool.motionfmt.writer import check_name

if TYPE_CHECKING:
    from motiontool.motionfmt.motion import Motion

__all__ = [
    "TRAJECTORY_TOPIC",
    "imported_samples",
    "read_rosbag",
    "read_rosbag_folder",
    "write_rosbag",
]

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


def _reduced(
    joints: tuple[str, ...],
    samples: Merged,
    columns: list[int],
    max_error: float,
    path: str,
    positions: str,
) -> tuple[Motion, int, float, Deviation]:
    """The motion on whole ms within ``max_error`` (rad) of every recorded sample at its own
    stamp where whole ms allow it: reduced within ``max_error``, then, where rounding the
    times put it beyond, within less (by the overshoot, then 0: every sample kept).
    Returns (motion, samples left out on a shared ms, the bound it was reduced within (rad),
    its worst deviation from the recording); ``positions`` says what a sample is, for the
    report."""
    q = samples.q[:, columns]
    compared = f"{sum(samples.own[c][0].size for c in columns)} {positions}"
    bound = max_error
    for attempt in range(_TRIES):
        motion, merged = reduced(joints, samples.t_ms, q, bound, path)
        worst = joint_deviation(motion, samples, columns, compared)
        over = worst.max_rad - max_error
        if over <= _SLACK_RAD or bound == 0:
            break
        bound = bound - over if bound > over and attempt < _TRIES - 2 else 0.0
    return motion, merged, bound, worst


_TRIES = 4
"""Reductions tried, the last within 0 rad (every sample kept)."""
_SLACK_RAD = 1e-9
"""Slack on ``max_error`` for float rounding, rad (:meth:`~.base.Recording.within`'s)."""


def _notes(states: JointStates, samples: Merged) -> tuple[str, ...]:
    notes = []
    if samples.publishers > 1:
        notes.append(
            f"{samples.publishers} sets of joint names merged by name, each joint "
            "interpolated between its own samples onto every stamp"
        )
    if states.unstamped:
        notes.append(
            f"{states.unstamped} unstamped messages placed at the time the bag logged them"
        )
    return tuple(notes)


def imported_samples(
    states: JointStates,
    path: str,
    opts: ImportOptions,
    *,
    heading: str | None = None,
    against: str = "the recording",
    positions: str = "recorded positions, each at its own stamp",
) -> Imported:
    """The motion ``states`` record (see the module), and what it held
    (:class:`~.base.Recording`). Another source of samples than a bag's topic (a
    trajectory's points) says what it read (``heading``), what the motion is compared against
    (``against``) and what a sample is (``positions``), for the report.

    Raises:
        MotionToolError: a bad message (:func:`~.joint_states.merged`), a name that is no
            joint name, a recording beyond the longest motion.
    """
    samples = merged(states, path, opts.topic)
    joints, columns = spread_hands(from_ros(samples.names, opts.joint_map))
    for joint in joints:
        check_name(joint, "joint")
    if samples.t_ms[-1] > INT_MAX:
        raise MotionToolError(f"'{path}': {samples.t_ms[-1]:.0f} ms long, beyond {INT_MAX} ms")
    motion, left_out, bound, worst = _reduced(
        joints, samples, columns, opts.max_error_rad, path, positions
    )
    recording = Recording(
        opts.topic,
        len(states.names),
        round(float(samples.t_ms[-1])),
        left_out,
        opts.max_error_rad,
        worst,
        bound,
        _notes(states, samples),
        heading,
        against,
    )
    return Imported(motion, path, recording=recording)


def read_rosbag(data: bytes, path: str, options: ImportOptions | None = None) -> Imported:
    """The motion a bag's ``sensor_msgs/JointState`` topic records (see the module): a
    ``.mcap`` or ``.db3`` file of a ROS 2 bag, or a ROS 1 ``.bag``.

    Raises:
        MotionToolError: not a bag, no such topic, a topic of another type, stamps that do not
            increase, a message whose names and positions disagree, a non-finite position.
    """
    opts = options or ImportOptions()
    return imported_samples(read_joint_states(data, path, opts.topic), path, opts)


def read_rosbag_folder(folder: str, options: ImportOptions | None = None) -> Imported:
    """:func:`read_rosbag` of a ROS 2 bag's folder (``metadata.yaml`` and its files)."""
    opts = options or ImportOptions()
    return imported_samples(read_bag_folder(folder, opts.topic), folder, opts)
