"""A simulated run as a ROS 2 bag (MCAP), so that a run in simulation and a real robot's bag
compare in the same tools (Foxglove, PlotJuggler, ``ros2 bag``): what ``play --bag`` writes.

Topics, one message per frame of the trace (:class:`~motiontool.sim.trace.Trace`), stamped
with the simulated time from 0 s (the frame before the first control step):

- :data:`JOINT_STATES_TOPIC`: ``sensor_msgs/JointState``, ``position`` the measured joint
  positions, rad (m for linear joints), ``name`` the motors as the robot's model names them
  (the UR5e's are its ROS driver's names);
- :data:`BASE_POSE_TOPIC`: ``geometry_msgs/PoseStamped`` of the root body in the world frame
  (``frame_id`` :data:`WORLD_FRAME`), position in m, orientation as a unit quaternion
  (x, y, z, w), for a free-floating robot (the Nao) only.

The bag is written by the one adapter of the ROS 2 libraries
(:mod:`motiontool.motionfmt.convert._ros`, extra ``ros``).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

from motiontool.motionfmt.convert._ros import (
    JOINT_STATE,
    POSE_STAMPED,
    BagTopic,
    stamp,
    write_bag,
)
from motiontool.motionfmt.fileio import atomic_write

if TYPE_CHECKING:
    from motiontool.sim.trace import Trace

__all__ = ["BASE_POSE_TOPIC", "JOINT_STATES_TOPIC", "WORLD_FRAME", "run_bag", "write_run_bag"]

JOINT_STATES_TOPIC = "/joint_states"
BASE_POSE_TOPIC = "/base_pose"
WORLD_FRAME = "world"

_NS_PER_S = 1e9


def _stamps_ns(trace: Trace) -> list[int]:
    return [round(float(t) * _NS_PER_S) for t in trace.time_s]


def _joint_states(trace: Trace, stamps: list[int]) -> BagTopic:
    names = list(trace.joints)
    messages: list[tuple[int, dict[str, Any]]] = [
        (
            ns,
            {
                "header": {"stamp": stamp(ns), "frame_id": ""},
                "name": names,
                "position": [float(v) for v in row],
                "velocity": [],
                "effort": [],
            },
        )
        for ns, row in zip(stamps, trace.position, strict=True)
    ]
    return BagTopic(JOINT_STATES_TOPIC, JOINT_STATE, messages)


def _base_pose(trace: Trace, stamps: list[int]) -> BagTopic:
    messages: list[tuple[int, dict[str, Any]]] = []
    for ns, pos, quat in zip(stamps, trace.base_pos, trace.base_quat, strict=True):
        w, x, y, z = (float(v) for v in quat)
        pose = {
            "position": {"x": float(pos[0]), "y": float(pos[1]), "z": float(pos[2])},
            "orientation": {"x": x, "y": y, "z": z, "w": w},
        }
        header = {"stamp": stamp(ns), "frame_id": WORLD_FRAME}
        messages.append((ns, {"header": header, "pose": pose}))
    return BagTopic(BASE_POSE_TOPIC, POSE_STAMPED, messages)


def run_bag(trace: Trace, *, floating_base: bool) -> bytes:
    """The bag of ``trace`` (see the module); the base pose only when ``floating_base``."""
    stamps = _stamps_ns(trace)
    topics = [_joint_states(trace, stamps)]
    if floating_base:
        topics.append(_base_pose(trace, stamps))
    return write_bag(topics, "a ROS 2 bag of the run")


def write_run_bag(path: str | Path, trace: Trace, *, floating_base: bool) -> None:
    """Write :func:`run_bag` to ``path`` (``-``: standard output), whole or not at all."""
    atomic_write(path, run_bag(trace, floating_base=floating_base))
