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

The bag is written a chunk of the run at a time (:class:`RunBag`), by the one adapter of the
ROS 2 libraries (:mod:`motiontool.motionfmt.convert._ros`, extra ``ros``).
"""

from __future__ import annotations

import io
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from motiontool.motionfmt.convert._ros import JOINT_STATE, POSE_STAMPED, BagWriter, stamp

if TYPE_CHECKING:
    from motiontool.sim.trace import Trace

__all__ = ["BASE_POSE_TOPIC", "JOINT_STATES_TOPIC", "WORLD_FRAME", "RunBag", "run_bag"]

JOINT_STATES_TOPIC = "/joint_states"
BASE_POSE_TOPIC = "/base_pose"
WORLD_FRAME = "world"

_NS_PER_S = 1e9


class RunBag:
    """The bag of a run, written a chunk of the run at a time into ``stream`` (:meth:`add`
    each chunk of :func:`motiontool.sim._mujoco.run_chunks` in order, then :meth:`finish`):
    each chunk's frames (but its first, the last of the chunk before) on every topic."""

    def __init__(self, stream: Any, joints: Sequence[str], *, floating_base: bool) -> None:
        topics = {JOINT_STATES_TOPIC: JOINT_STATE}
        if floating_base:
            topics[BASE_POSE_TOPIC] = POSE_STAMPED
        self._writer = BagWriter(stream, topics, "a ROS 2 bag of the run")
        self._names = list(joints)
        self._floating = floating_base
        self._started = False

    def add(self, chunk: Trace) -> None:
        """Write the frames of the next chunk of the run."""
        new = 1 if self._started else 0
        self._started = True
        stamps = [round(float(t) * _NS_PER_S) for t in chunk.time_s[new:]]
        for ns, row in zip(stamps, chunk.position[new:], strict=True):
            self._writer.write(JOINT_STATES_TOPIC, ns, self._joint_state(ns, row))
        if self._floating:
            for ns, pos, quat in zip(
                stamps, chunk.base_pos[new:], chunk.base_quat[new:], strict=True
            ):
                self._writer.write(BASE_POSE_TOPIC, ns, _base_pose(ns, pos, quat))

    def finish(self) -> None:
        """Write the bag's summary: the bag is complete."""
        self._writer.finish()

    def _joint_state(self, ns: int, row: Any) -> dict[str, Any]:
        return {
            "header": {"stamp": stamp(ns), "frame_id": ""},
            "name": self._names,
            "position": [float(v) for v in row],
            "velocity": [],
            "effort": [],
        }


def _base_pose(ns: int, pos: Any, quat: Any) -> dict[str, Any]:
    w, x, y, z = (float(v) for v in quat)
    pose = {
        "position": {"x": float(pos[0]), "y": float(pos[1]), "z": float(pos[2])},
        "orientation": {"x": x, "y": y, "z": z, "w": w},
    }
    return {"header": {"stamp": stamp(ns), "frame_id": WORLD_FRAME}, "pose": pose}


def run_bag(trace: Trace, *, floating_base: bool) -> bytes:
    """The bag of ``trace`` (see the module); the base pose only when ``floating_base``."""
    out = io.BytesIO()
    bag = RunBag(out, trace.joints, floating_base=floating_base)
    bag.add(trace)
    bag.finish()
    return out.getvalue()
