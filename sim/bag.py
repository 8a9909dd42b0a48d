"""A simulated run as a ROS 2 bag (MCAP), so that a run in simulation and a real robot's bag
compare in the same tools (Foxglove, RViz, PlotJuggler, ``ros2 bag``): what ``play --bag``
writes.

Topics, one message per frame of the trace (:class:`~motiontool.sim.trace.Trace`), stamped
with the simulated time from the run's start (:attr:`BagTarget.start_ns`: 0 s by default, the
frame before the first control step):

- :data:`JOINT_STATES_TOPIC`: ``sensor_msgs/JointState``, ``name`` the motors as the robot's
  model names them (the UR5e's are its ROS driver's names), ``position`` the measured joint
  positions, rad (m for linear joints), ``velocity`` the measured joint velocities, rad/s
  (m/s), ``effort`` the motor torques, N·m (N) (NaN in the first frame: no motor has acted
  yet);
- :data:`BASE_POSE_TOPIC`: ``geometry_msgs/PoseStamped`` of the root body in the world frame
  (``frame_id`` :data:`WORLD_FRAME`), position in m, orientation as a unit quaternion
  (x, y, z, w), for a free-floating robot (the Nao) only;
- :data:`TF_TOPIC`: ``tf2_msgs/TFMessage``, every link that moves against its parent (a joint
  between them; the floating base against :data:`WORLD_FRAME`), its pose in its parent's
  frame, m and unit quaternion, as the simulation measured it (MuJoCo's body poses, made
  relative to the parent body: no second kinematics);
- :data:`TF_STATIC_TOPIC`: the links fixed to their parent (the Nao's foot force sensors, a
  fixed base on its stand), once, latched;
- :data:`DESCRIPTION_TOPIC`: ``std_msgs/String``, the robot's URDF
  (:func:`motiontool.kinematics.export.urdf_bytes`, whose link names are the frame ids of
  ``/tf``), once, latched;
- :data:`CLOCK_TOPIC`: ``rosgraph_msgs/Clock``, the simulated time, for ``use_sim_time``.

The bag is written a chunk of the run at a time (:class:`RunBag`), by the one adapter of the
ROS 2 libraries (:mod:`motiontool.motionfmt.convert._ros`, extra ``ros``).
"""

from __future__ import annotations

import io
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from motiontool.motionfmt.convert._ros import JOINT_STATE, POSE_STAMPED, BagWriter, stamp
from motiontool.sim.bag_frames import WORLD_FRAME, LinkTree, transforms

if TYPE_CHECKING:
    from motiontool.sim._mujoco import Scene
    from motiontool.sim.trace import Trace

__all__ = [
    "BASE_POSE_TOPIC",
    "CLOCK_TOPIC",
    "DESCRIPTION_TOPIC",
    "JOINT_STATES_TOPIC",
    "TF_STATIC_TOPIC",
    "TF_TOPIC",
    "WORLD_FRAME",
    "BagTarget",
    "LinkTree",
    "RunBag",
    "run_bag",
    "scene_bag",
]

JOINT_STATES_TOPIC = "/joint_states"
BASE_POSE_TOPIC = "/base_pose"
TF_TOPIC = "/tf"
TF_STATIC_TOPIC = "/tf_static"
DESCRIPTION_TOPIC = "/robot_description"
CLOCK_TOPIC = "/clock"

_TF = "tf2_msgs/msg/TFMessage"
_STRING = "std_msgs/msg/String"
_CLOCK = "rosgraph_msgs/msg/Clock"
_NS_PER_S = 1e9


@dataclass(frozen=True)
class BagTarget:
    """Where a run's bag goes, and its time.

    Attributes:
        path: the ``.mcap`` file.
        start_ns: the stamp of the run's first frame, ns since the Unix epoch (0: stamps are
            the simulated time from 0).
    """

    path: str | Path
    start_ns: int = 0


class RunBag:
    """The bag of a run, written a chunk of the run at a time into ``stream`` (:meth:`add`
    each chunk of :func:`motiontool.sim._mujoco.run_chunks` in order, then :meth:`finish`):
    each chunk's frames (but its first, the last of the chunk before) on every topic.

    Args:
        joints: the motors, as the trace has them.
        floating_base: whether the root is free-flying (then ``/base_pose``).
        tree: the robot's links and URDF (then ``/tf``, ``/tf_static``,
            ``/robot_description``; the chunks must carry every body's pose).
        start_ns: the stamp of the run's first frame, ns (see :class:`BagTarget`).
    """

    def __init__(
        self,
        stream: Any,
        joints: Sequence[str],
        *,
        floating_base: bool,
        tree: LinkTree | None = None,
        start_ns: int = 0,
    ) -> None:
        topics = {CLOCK_TOPIC: _CLOCK, JOINT_STATES_TOPIC: JOINT_STATE}
        if floating_base:
            topics[BASE_POSE_TOPIC] = POSE_STAMPED
        latched: tuple[str, ...] = ()
        if tree is not None:
            topics.update({TF_TOPIC: _TF, TF_STATIC_TOPIC: _TF, DESCRIPTION_TOPIC: _STRING})
            latched = (TF_STATIC_TOPIC, DESCRIPTION_TOPIC)
        self._writer = BagWriter(stream, topics, "a ROS 2 bag of the run", latched)
        self._names = list(joints)
        self._floating = floating_base
        self._tree = tree
        self._start_ns = start_ns
        self._started = False

    def add(self, chunk: Trace) -> None:
        """Write the frames of the next chunk of the run."""
        new = 1 if self._started else 0
        stamps = [self._start_ns + round(float(t) * _NS_PER_S) for t in chunk.time_s[new:]]
        if not self._started and self._tree is not None:
            self._latched(stamps[0], chunk)
        self._started = True
        for ns in stamps:
            self._writer.write(CLOCK_TOPIC, ns, {"clock": stamp(ns)})
        effort = _efforts(chunk, new)
        rows = zip(stamps, chunk.position[new:], chunk.velocity[new:], effort, strict=True)
        for ns, position, velocity, torque in rows:
            self._writer.write(
                JOINT_STATES_TOPIC, ns, self._joint_state(ns, position, velocity, torque)
            )
        if self._floating:
            base_pos, base_quat = _base(chunk, links=self._tree is not None)
            for ns, pos, quat in zip(stamps, base_pos[new:], base_quat[new:], strict=True):
                self._writer.write(BASE_POSE_TOPIC, ns, _base_pose(ns, pos, quat))
        if self._tree is not None:
            moving = self._tree.moving_links()
            for ns, message in zip(stamps, transforms(self._tree, chunk, moving, new), strict=True):
                self._writer.write(TF_TOPIC, ns, _tf_message(ns, message))

    def finish(self) -> None:
        """Write the bag's summary: the bag is complete."""
        self._writer.finish()

    def _latched(self, ns: int, chunk: Trace) -> None:
        """The messages sent once, at the first frame: the URDF and the fixed links."""
        assert self._tree is not None
        self._writer.write(DESCRIPTION_TOPIC, ns, {"data": self._tree.description})
        fixed = self._tree.fixed_links()
        if fixed:
            (message,) = transforms(self._tree, chunk, fixed, 0, frames=1)
            self._writer.write(TF_STATIC_TOPIC, ns, _tf_message(ns, message))

    def _joint_state(self, ns: int, position: Any, velocity: Any, torque: Any) -> dict[str, Any]:
        return {
            "header": {"stamp": stamp(ns), "frame_id": ""},
            "name": self._names,
            "position": [float(v) for v in position],
            "velocity": [float(v) for v in velocity],
            "effort": [float(v) for v in torque],
        }


def _base(chunk: Trace, *, links: bool) -> tuple[Any, Any]:
    """The root's poses: with the links, as ``/tf`` has it (the first body's, posed on the
    measured joints), else as the report measures it."""
    if links:
        return chunk.body_pos[:, 0], chunk.body_quat[:, 0]
    return chunk.base_pos, chunk.base_quat


def _efforts(chunk: Trace, first: int) -> Any:
    """The motor torques of the chunk's frames from ``first``, N·m (N): step ``k``'s at frame
    ``k + 1``; NaN at the run's first frame, before any step."""
    import numpy as np

    if first:
        return chunk.torque
    return np.vstack([np.full((1, len(chunk.joints)), np.nan), chunk.torque])


def _tf_message(ns: int, links: list[tuple[str, str, Any, Any]]) -> dict[str, Any]:
    """A ``tf2_msgs/TFMessage`` of (parent, child, position m, quaternion w x y z) at ``ns``."""
    out = []
    for parent, child, pos, quat in links:
        w, x, y, z = (float(v) for v in quat)
        translation = {"x": float(pos[0]), "y": float(pos[1]), "z": float(pos[2])}
        out.append(
            {
                "header": {"stamp": stamp(ns), "frame_id": parent},
                "child_frame_id": child,
                "transform": {
                    "translation": translation,
                    "rotation": {"x": x, "y": y, "z": z, "w": w},
                },
            }
        )
    return {"transforms": out}


def _base_pose(ns: int, pos: Any, quat: Any) -> dict[str, Any]:
    w, x, y, z = (float(v) for v in quat)
    pose = {
        "position": {"x": float(pos[0]), "y": float(pos[1]), "z": float(pos[2])},
        "orientation": {"x": x, "y": y, "z": z, "w": w},
    }
    return {"header": {"stamp": stamp(ns), "frame_id": WORLD_FRAME}, "pose": pose}


def scene_bag(stream: Any, scene: Scene, start_ns: int = 0) -> RunBag:
    """The bag of a run in ``scene``, into ``stream``: every topic of the module (the chunks
    must carry every body's pose).

    Raises:
        MotionToolError: the robot cannot be written as URDF
            (:func:`motiontool.kinematics.export.urdf_bytes`).
    """
    from motiontool.kinematics.export import stored_urdf
    from motiontool.sim import _mujoco

    parents, moving = _mujoco.link_tree(scene.model, scene.robot_bodies, scene.floating)
    links = tuple(scene.body_name(int(b)) for b in scene.robot_bodies)
    description = stored_urdf(scene.robot).decode("utf-8")
    tree = LinkTree(links, parents, moving, description)
    return RunBag(stream, scene.joints, floating_base=scene.floating, tree=tree, start_ns=start_ns)


def run_bag(
    trace: Trace, *, floating_base: bool, tree: LinkTree | None = None, start_ns: int = 0
) -> bytes:
    """The bag of ``trace`` (see the module); the base pose only when ``floating_base``, the
    links only with a ``tree`` (the trace then carries every body's pose)."""
    out = io.BytesIO()
    bag = RunBag(out, trace.joints, floating_base=floating_base, tree=tree, start_ns=start_ns)
    bag.add(trace)
    bag.finish()
    return out.getvalue()
