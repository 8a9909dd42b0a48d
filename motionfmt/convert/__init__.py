"""Other formats a motion goes to and comes from: one module per format, one row each in
:data:`FORMATS`, the table ``motiontool convert`` and its tests iterate over.

* :mod:`.motion_file`: Webots' ``.motion`` (read exactly as Webots reads it).
* :mod:`.wide_csv`: ``time_ms`` then one column per joint; both ways, lossless.
* :mod:`.npz`: NumPy arrays ``times_ms``, ``names``, ``positions``, ``commanded``; both ways,
  lossless.
* :mod:`.naoqi`: a real NAO: ``ALMotion.angleInterpolationBezier``'s arguments as JSON and a
  script that sends them.
* :mod:`.choregraphe_xml`: Choregraphe's timelines (``.xar``): the curves of their keys,
  sampled at the control step and reduced within the maximum error (:mod:`.choregraphe`).
* :mod:`.choregraphe_py`: the Python Choregraphe exports (``names``, ``times``, ``keys`` for
  ``angleInterpolationBezier``), read as literals (never run); written from the NAOqi keys.
* :mod:`.urscript`: a real UR arm: ``servoj`` at every control step (or ``movej`` per keyframe).
* :mod:`.ros_trajectory`: a robot under ros2_control: a ``FollowJointTrajectory`` goal (YAML);
  back, a ``JointTrajectory`` in YAML (that goal, ``ros2 topic echo``'s) with its keyframes
  reduced (:mod:`.ros_trajectory_read`).
* :mod:`.rosbag`: ROS 2 bags (MCAP): the command stream as ``sensor_msgs/JointState`` and the
  trajectory; back, a recorded ``/joint_states`` as a motion with its keyframes reduced, from
  an ``.mcap`` or sqlite3 ``.db3`` file, a bag's folder, or a ROS 1 ``.bag``.

A format for a real robot writes what reproduces Webots' command stream there and says how far
it is from it (:class:`~.base.Deviation`); the robot checks of an export are the caller's (the
robot layer), before it writes anything. To add a format: one module with a ``read`` and/or a
``write`` function (:class:`~.base.Format`), and one row in :data:`FORMATS`.

Pure: the standard library and numpy, and the ROS 2 libraries (extra ``ros``) imported lazily
by :mod:`._ros` alone. Import each format from its module.

May import the rest of ``motionfmt`` and the top-level modules, as ``motionfmt`` may.
"""

from __future__ import annotations

from motiontool.motionfmt.convert.base import Format
from motiontool.motionfmt.convert.choregraphe_py import (
    read_choregraphe_py,
    write_choregraphe_py,
)
from motiontool.motionfmt.convert.choregraphe_xml import read_timeline
from motiontool.motionfmt.convert.motion_file import read_motion_file, write_motion_file
from motiontool.motionfmt.convert.naoqi import write_naoqi
from motiontool.motionfmt.convert.npz import read_npz, write_npz
from motiontool.motionfmt.convert.ros_trajectory import write_ros_trajectory
from motiontool.motionfmt.convert.ros_trajectory_read import read_ros_trajectory
from motiontool.motionfmt.convert.rosbag import read_rosbag, read_rosbag_folder, write_rosbag
from motiontool.motionfmt.convert.urscript import write_urscript
from motiontool.motionfmt.convert.wide_csv import read_csv, write_csv

__all__ = ["FORMATS", "Format", "format_named", "format_of"]

FORMATS: tuple[Format, ...] = (
    Format(
        "motion",
        (".motion",),
        "Webots .motion file",
        read=read_motion_file,
        write=write_motion_file,
    ),
    Format(
        "csv",
        (".csv",),
        "wide CSV: time_ms, then one column per joint (an empty cell: no command)",
        read=read_csv,
        write=write_csv,
    ),
    Format(
        "npz",
        (".npz",),
        "NumPy arrays times_ms, names, positions, commanded (and pose_names)",
        read=read_npz,
        write=write_npz,
    ),
    Format(
        "naoqi",
        (".naoqi.json",),
        "a real NAO: ALMotion.angleInterpolationBezier arguments (JSON) and a qi script",
        write=write_naoqi,
        for_robot=True,
        default_robot="nao-v5",
        uses=frozenset({"script_name", "lead_in_ms"}),
    ),
    Format(
        "choregraphe",
        (".xar", ".pml"),
        "a Choregraphe timeline (behavior.xar): its joint curves, sampled at the control step",
        read=read_timeline,
        default_robot="nao-v5",
        uses=frozenset({"max_error_rad", "timestep_ms"}),
    ),
    Format(
        "choregraphe-py",
        (".py",),
        "a Choregraphe Python export: names, times, keys for angleInterpolationBezier "
        "(read as literals, never run)",
        read=read_choregraphe_py,
        write=write_choregraphe_py,
        for_robot=True,
        default_robot="nao-v5",
        uses=frozenset({"max_error_rad", "timestep_ms", "lead_in_ms"}),
    ),
    Format(
        "urscript",
        (".script", ".urscript"),
        "a real UR arm: servoj at every control step (or movej per keyframe), URScript",
        write=write_urscript,
        for_robot=True,
        default_robot="ur5e",
        uses=frozenset({"joint_order", "limits", "blend_rad_s2", "max_error_rad"}),
    ),
    Format(
        "ros-trajectory",
        (".trajectory.yaml",),
        "a robot under ros2_control: a FollowJointTrajectory goal (YAML) for ros2 action "
        "send_goal; back, a JointTrajectory in YAML (that goal, ros2 topic echo's)",
        read=read_ros_trajectory,
        write=write_ros_trajectory,
        for_robot=True,
        uses=frozenset({"joint_map", "lead_in_ms", "max_error_rad"}),
    ),
    Format(
        "rosbag",
        (".mcap",),
        "ROS 2 bag (MCAP): the command stream as sensor_msgs/JointState and the trajectory; "
        "back, a recorded JointState topic",
        read=read_rosbag,
        write=write_rosbag,
        uses=frozenset({"joint_map", "topic", "max_error_rad", "lead_in_ms"}),
        read_folder=read_rosbag_folder,
    ),
    Format(
        "rosbag-db3",
        (".db3",),
        "ROS 2 bag in sqlite3 storage (Humble's default; or its folder, as rosbag): a "
        "recorded JointState topic",
        read=read_rosbag,
        uses=frozenset({"joint_map", "topic", "max_error_rad"}),
        read_folder=read_rosbag_folder,
    ),
    Format(
        "rosbag1",
        (".bag",),
        "ROS 1 bag: a recorded sensor_msgs/JointState topic",
        read=read_rosbag,
        uses=frozenset({"joint_map", "topic", "max_error_rad"}),
    ),
)
"""Every format, in the order the help lists them."""


def format_named(name: str) -> Format | None:
    """The format called ``name`` (case-insensitive), or None."""
    return next((f for f in FORMATS if f.name == name.lower()), None)


def format_of(path: str) -> Format | None:
    """The format a file name selects by its ending (the longest that matches), or None."""
    lower = path.lower()
    matches = [(len(s), f) for f in FORMATS for s in f.suffixes if lower.endswith(s)]
    return max(matches, key=lambda m: m[0])[1] if matches else None
