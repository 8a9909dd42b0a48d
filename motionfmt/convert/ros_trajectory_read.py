"""A ``trajectory_msgs/JointTrajectory`` in YAML read as a motion, as teams have one:

* the goal ``convert --to ros-trajectory`` writes (the message under ``trajectory:``);
* what ``ros2 topic echo /topic trajectory_msgs/msg/JointTrajectory`` prints (the message at
  the top level, ``time_from_start`` as ``sec`` and ``nanosec``, followed by ``---``), or
  ROS 1's ``rostopic echo`` (``secs`` and ``nsecs``);
* the message under one key of a larger file (a ``FollowJointTrajectory`` goal beside its
  tolerances, ``joint_trajectory:`` of a MoveIt ``RobotTrajectory``).

Each point's ``positions`` are the joints' targets at its ``time_from_start``; its
``velocities``, ``accelerations`` and ``effort`` are ignored (a controller given positions
alone draws straight lines between the points). The points become a motion as a recording's
samples do (:mod:`.rosbag`): the first point is the motion's 0 ms (what comes before it is the
robot reaching it from where it stands: a written goal's lead-in), times in whole ms, ROS names
mapped back (a NAO's ``LHand``: ``LPhalanx1..8``), the keyframes reduced within the maximum
error, and the motion's worst deviation from the points reported.

The YAML is read with ruamel.yaml (extra ``ros``), imported lazily; anything that is not such a
message is one :class:`~motiontool.errors.MotionSyntaxError` at its line and column.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING, Any

from motiontool.errors import MotionSyntaxError
from motiontool.motionfmt.convert._ros import NS_PER_MS, NS_PER_S, JointStates
from motiontool.motionfmt.convert.base import Imported, ImportOptions
from motiontool.motionfmt.convert.rosbag import imported_samples
from motiontool.motionfmt.cscan import INT_MAX
from motiontool.motionfmt.structured_text import load_yaml, shown
from motiontool.motionfmt.units import MS_PER_S

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

__all__ = ["read_ros_trajectory"]

MESSAGE = "trajectory_msgs/JointTrajectory"

_DURATIONS = (("sec", "nanosec"), ("secs", "nsecs"))
"""``time_from_start``'s fields: ROS 2's ``builtin_interfaces/Duration``, ROS 1's."""

_NESTED = 3
"""How deep under keys the message is looked for (``a: {b: {trajectory: ...}}``)."""


class _Where:
    """Line and column of the nodes of one YAML file (ruamel's round-trip marks, 0-based),
    made the 1-based position of a :class:`~motiontool.errors.MotionSyntaxError`."""

    def __init__(self, path: str) -> None:
        self.path = path

    def error(self, node: Any, message: str, key: Any = None) -> MotionSyntaxError:
        """The error at ``node`` (a mapping or list), at its ``key`` (a key, or an index of a
        list) where given."""
        line, col = 0, 0
        marks = getattr(node, "lc", None)
        if marks is not None:
            line, col = marks.line, marks.col
            if key is not None and isinstance(node, list):
                line, col = marks.item(key)
            elif key is not None and key in node:
                line, col = marks.value(key) if _is_scalar(node[key]) else marks.key(key)
        return MotionSyntaxError(message, self.path, line + 1, col + 1)


def _is_scalar(value: Any) -> bool:
    return not isinstance(value, (dict, list))


def _documents(text: str, where: _Where) -> list[Any]:
    """The file's documents that are not empty (``ros2 topic echo`` ends each with ``---``)."""
    documents = load_yaml(text, where.path, f"a {MESSAGE}", round_trip=True)
    return [d for d in documents if d is not None]


def _candidates(node: Any, keys: tuple[str, ...], depth: int) -> Iterator[tuple[str, Any]]:
    """(key path, mapping) of every mapping with ``joint_names`` and ``points`` at ``node`` or
    under its keys, down to ``depth`` keys."""
    if not isinstance(node, dict):
        return
    if "joint_names" in node and "points" in node:
        yield ".".join(keys), node
        return
    if depth > 0:
        for key, value in node.items():
            yield from _candidates(value, (*keys, str(key)), depth - 1)


def _message(text: str, where: _Where) -> dict[str, Any]:
    """The one JointTrajectory of the file: at the top level or under keys; of several (a
    MoveIt ``RobotTrajectory``'s empty ``multi_dof_joint_trajectory``), the one with points."""
    documents = _documents(text, where)
    if not documents:
        raise MotionSyntaxError(f"empty: expected a {MESSAGE}", where.path, 1, 1)
    if len(documents) > 1:
        raise where.error(
            documents[1],
            f"a second message ({len(documents)} in all): give one "
            "(echo a single message, or keep the first document alone)",
        )
    found = list(_candidates(documents[0], (), _NESTED))
    if len(found) > 1:
        found = [(k, m) for k, m in found if isinstance(m["points"], list) and m["points"]]
    if len(found) > 1:
        listed = ", ".join(k or "the top level" for k, _ in found)
        raise where.error(found[1][1], f"{len(found)} trajectories ({listed}): give one")
    if not found:
        raise where.error(
            documents[0],
            f"expected a {MESSAGE}: joint_names and points, at the top level or under a key "
            "(trajectory: of a FollowJointTrajectory goal)",
        )
    return found[0][1]  # type: ignore[no-any-return]


def _joint_names(message: dict[str, Any], where: _Where) -> tuple[str, ...]:
    names = message["joint_names"]
    if not isinstance(names, list) or not names:
        raise where.error(message, "joint_names: expected a list of joint names", "joint_names")
    seen: set[str] = set()
    for k, name in enumerate(names):
        if not isinstance(name, str) or not name:
            raise where.error(names, f"joint_names: expected a name, got {shown(name)}", k)
        if name in seen:
            raise where.error(names, f"joint_names: {shown(name)} is given twice", k)
        seen.add(name)
    return tuple(names)


def _integer(node: dict[str, Any], key: str, where: _Where) -> int:
    value = node.get(key, 0)  # a field left out is 0, as ROS fills a message from YAML
    if isinstance(value, bool) or not isinstance(value, int) or value < 0:
        raise where.error(node, f"{key}: expected a whole number >= 0, got {shown(value)}", key)
    return value


def _time_ns(point: dict[str, Any], where: _Where) -> int:
    """A point's ``time_from_start``, ns: ROS 2's ``{sec, nanosec}`` or ROS 1's
    ``{secs, nsecs}``."""
    if "time_from_start" not in point:
        raise where.error(point, "a point without time_from_start: expected {sec, nanosec}")
    node = point["time_from_start"]
    fields = next((f for f in _DURATIONS if isinstance(node, dict) and set(node) <= set(f)), None)
    if fields is None or not node:
        given = list(node) if isinstance(node, dict) else node
        raise where.error(
            point,
            f"time_from_start: expected {{sec, nanosec}} (ROS 2) or {{secs, nsecs}} (ROS 1), "
            f"got {shown(given)}",
            "time_from_start",
        )
    sec, nanosec = (_integer(node, f, where) for f in fields)
    if nanosec >= NS_PER_S:
        raise where.error(node, f"{fields[1]}: {nanosec} is not below 1e9", fields[1])
    ns = sec * NS_PER_S + nanosec
    if ns > INT_MAX * NS_PER_MS:  # a pose time is a C int of ms: also what int64 ns hold
        raise where.error(
            node, f"{fields[0]}: {shown(sec)} s is past the {INT_MAX} ms a motion holds", fields[0]
        )
    return ns


def _positions(point: dict[str, Any], joints: int, where: _Where) -> npt.NDArray[np.float64]:
    import numpy as np

    values = point.get("positions")
    if not isinstance(values, list):
        found = f"keys {shown(list(point))}" if "positions" not in point else shown(values)
        raise where.error(
            point, f"a point without positions: expected a list of {joints} numbers ({found})"
        )
    if len(values) != joints:
        raise where.error(
            point,
            f"positions: {len(values)} number{'' if len(values) == 1 else 's'} for the "
            f"{joints} joint_names",
            "positions",
        )
    for k, v in enumerate(values):
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not np.isfinite(v):
            raise where.error(values, f"positions: expected a finite number, got {shown(v)}", k)
    return np.asarray(values, dtype=np.float64)


def _points(message: dict[str, Any], joints: int, where: _Where) -> JointStates:
    """Every point as a sample: ``time_from_start`` (ns, increasing) and ``positions``."""
    import numpy as np

    points = message["points"]
    if not isinstance(points, list) or not points:
        raise where.error(message, "points: expected a list of at least one point", "points")
    stamps: list[int] = []
    positions: list[npt.NDArray[np.float64]] = []
    for k, point in enumerate(points):
        if not isinstance(point, dict):
            raise where.error(points, f"point {k + 1}: expected positions and time_from_start", k)
        ns = _time_ns(point, where)
        if stamps and ns <= stamps[-1]:
            raise where.error(
                point,
                f"point {k + 1}: time_from_start {ns / NS_PER_S:.9g} s is not after point "
                f"{k}'s {stamps[-1] / NS_PER_S:.9g} s: time_from_start must increase",
                "time_from_start",
            )
        positions.append(_positions(point, joints, where))
        stamps.append(ns)
    names = [tuple(message["joint_names"])] * len(points)
    return JointStates(np.asarray(stamps, dtype=np.int64), names, positions)


def read_ros_trajectory(data: bytes, path: str, options: ImportOptions | None = None) -> Imported:
    """The motion a JointTrajectory's points make (see the module), its keyframes reduced
    within ``options.max_error_rad`` (rad), names mapped back through ``options.joint_map``.

    Raises:
        MotionSyntaxError: not YAML, no JointTrajectory or several, a missing field,
            ``positions`` of the wrong length or not finite numbers, ``time_from_start`` that
            does not increase: at its line and column.
        MotionToolError: two ROS names that the joint map makes one joint.
    """
    opts = options or ImportOptions()
    where = _Where(path)
    message = _message(data.decode("utf-8", "surrogateescape"), where)
    states = _points(message, len(_joint_names(message, where)), where)
    first_s = int(states.stamps_ns[0]) / NS_PER_MS / MS_PER_S
    heading = (
        f"read {len(states.names)} points of a {MESSAGE} ({len(states.names[0])} joints); "
        f"its first point, at {first_s:g} s, is the motion's 0 ms"
    )
    return imported_samples(
        states,
        path,
        opts,
        heading=heading,
        against="the trajectory's points",
        positions="positions of the points, each at its time_from_start",
    )
