"""The one module that imports the ROS 2 libraries of the extra ``ros``, lazily: rosbags reads a
bag, mcap with mcap-ros2-support writes one.

Writing: one MCAP file (profile ``ros2``, CDR messages), each message type's schema the ROS 2
definition text (``ros2msg``) that rosbags keeps for ROS 2 Humble's types, the format
``ros2 bag record -s mcap`` writes and Foxglove, PlotJuggler and ``ros2 bag`` read. Messages go
in as plain dicts (field name -> value) and are encoded by mcap-ros2-support from that text.

Reading: rosbags' reader (a ``.mcap`` or sqlite3 ``.db3`` file, a ROS 2 bag's folder, a ROS 1
``.bag``), decoded with the definitions the bag
carries. Both are independent of each other: a bag written here is checked by the tests with
the other library's reader.
"""

from __future__ import annotations

import functools
import io
import tempfile
from collections.abc import Collection, Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from motiontool.errors import MotionToolError
from motiontool.extras import require
from motiontool.motionfmt.fileio import Sink

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

__all__ = [
    "JOINT_STATE",
    "JOINT_TRAJECTORY",
    "LATCHED_QOS",
    "NS_PER_MS",
    "NS_PER_S",
    "POSE_STAMPED",
    "BagTopic",
    "BagWriter",
    "JointStates",
    "duration",
    "read_bag_folder",
    "read_joint_states",
    "stamp",
    "write_bag",
]

JOINT_STATE = "sensor_msgs/msg/JointState"
JOINT_TRAJECTORY = "trajectory_msgs/msg/JointTrajectory"
POSE_STAMPED = "geometry_msgs/msg/PoseStamped"

NS_PER_S = 1_000_000_000
NS_PER_MS = 1_000_000
"""Nanoseconds in a millisecond: ROS stamps and bag times are integer ns."""

_EXTRA = "ros"

_INFINITE = "{sec: 9223372036, nsec: 854775807}"  # RMW_DURATION_INFINITE
LATCHED_QOS = (
    f"- history: 1\n  depth: 1\n  reliability: 1\n  durability: 1\n  deadline: {_INFINITE}\n"
    f"  lifespan: {_INFINITE}\n  liveliness: 1\n  liveliness_lease_duration: {_INFINITE}\n"
    "  avoid_ros_namespace_conventions: false"
)
"""The ``offered_qos_profiles`` of a latched topic (``/tf_static``, ``/robot_description``), as
``ros2 bag record`` keeps it in the channel's metadata (Humble's integer form): keep last 1,
reliable, transient local, so that ``ros2 bag play`` republishes it to late subscribers."""


@dataclass(frozen=True)
class BagTopic:
    """One topic to write.

    Attributes:
        name: the topic (``/joint_states``).
        msgtype: its ROS 2 type (``sensor_msgs/msg/JointState``).
        messages: (the bag's time, ns; the message as nested dicts), in time order; read
            once, as the bag is written (a generator makes each message when it is written).
    """

    name: str
    msgtype: str
    messages: Iterable[tuple[int, dict[str, Any]]]


@dataclass(frozen=True)
class JointStates:
    """The ``sensor_msgs/JointState`` messages of one topic, in bag order.

    Attributes:
        stamps_ns: int64 (M,): each message's ``header.stamp``, ns.
        names: each message's ``name`` list.
        positions: each message's ``position``, float64.
        unstamped: how many messages had a zero stamp and are at the time the bag logged them.
    """

    stamps_ns: npt.NDArray[np.int64]
    names: list[tuple[str, ...]]
    positions: list[npt.NDArray[np.float64]]
    unstamped: int = 0


def stamp(ns: int) -> dict[str, int]:
    """A ``builtin_interfaces/Time`` (``sec``, ``nanosec``) of ``ns`` >= 0 nanoseconds."""
    return {"sec": ns // NS_PER_S, "nanosec": ns % NS_PER_S}


def duration(ms: int) -> dict[str, int]:
    """A ``builtin_interfaces/Duration`` (``sec``, ``nanosec``) of ``ms`` >= 0 milliseconds."""
    return stamp(ms * NS_PER_MS)


class BagWriter:
    """An MCAP file written a message at a time into ``stream`` (anything with ``write``; the
    bytes written are counted for MCAP's offsets), each topic's schema registered when its
    first message comes: deterministic, no wall clock in it. :meth:`finish` writes the
    summary.

    Args:
        topics: each topic's ROS 2 type, by topic name.
        what: what needs the libraries, for the missing-extra message (``a ROS 2 bag``).
        latched: the topics offered as latched (:data:`LATCHED_QOS` in their channel's
            metadata); the others carry no QoS (a player's default: reliable, volatile).
    """

    def __init__(
        self, stream: Any, topics: dict[str, str], what: str, latched: Collection[str] = ()
    ) -> None:
        require("rosbags", _EXTRA, what)
        writer_module = require("mcap_ros2.writer", _EXTRA, what)
        typesys = require("rosbags.typesys", _EXTRA, what)
        self._store = typesys.get_typestore(typesys.Stores.ROS2_HUMBLE)
        self._out = _Counted(stream)
        self._writer = _qos_writer(writer_module.Writer)(self._out)
        self._types = topics
        self._latched = set(latched)
        self._schemas: dict[str, Any] = {}
        self._sequence: dict[str, int] = {}

    def write(self, topic: str, ns: int, message: dict[str, Any]) -> None:
        """Write ``message`` (nested dicts) on ``topic`` at the bag time ``ns``."""
        schema = self._schemas.get(topic)
        if schema is None:
            text, _ = self._store.generate_msgdef(self._types[topic], ros_version=2)
            schema = self._schemas[topic] = self._writer.register_msgdef(self._types[topic], text)
            if topic in self._latched:
                qos = {"offered_qos_profiles": LATCHED_QOS}
                self._writer.register_channel(topic, schema.id, qos)
        k = self._sequence.get(topic, 0)
        self._sequence[topic] = k + 1
        self._writer.write_message(topic, schema, message, log_time=ns, publish_time=ns, sequence=k)

    def metadata(self, name: str, fields: dict[str, str]) -> None:
        """Write an MCAP metadata record ``name`` (string -> string)."""
        self._writer.add_metadata(name, fields)

    def finish(self) -> None:
        """Write the bag's summary: the file is complete."""
        self._writer.finish()


@functools.cache
def _qos_writer(base: type[Any]) -> type[Any]:
    """mcap-ros2-support's ``Writer`` (``base``), able to register a channel ahead of its first
    message with the channel's metadata (its own registers each channel bare)."""

    class QosWriter(base):  # type: ignore[misc]
        def register_channel(self, topic: str, schema_id: int, metadata: dict[str, str]) -> None:
            self._channel_ids[topic] = self._writer.register_channel(
                topic=topic, message_encoding="cdr", schema_id=schema_id, metadata=metadata
            )

    return QosWriter


class _Counted(Sink):
    """A write-only stream that counts what it writes (MCAP's writer asks where it is)."""

    __slots__ = ("_written",)

    def __init__(self, stream: Any) -> None:
        super().__init__(stream)
        self._written = 0

    def write(self, data: bytes | bytearray | memoryview) -> int:
        n = super().write(data)
        self._written += n
        return n

    def tell(self) -> int:
        return self._written


def write_bag(
    topics: Sequence[BagTopic], what: str, metadata: dict[str, dict[str, str]] | None = None
) -> bytes:
    """The MCAP file holding ``topics``, one after another (:class:`BagWriter`), and the
    ``metadata`` records (name -> fields).

    Args:
        what: what needs the libraries, for the missing-extra message (``a ROS 2 bag``).
    """
    out = io.BytesIO()
    writer = BagWriter(out, {t.name: t.msgtype for t in topics}, what)
    for name, fields in (metadata or {}).items():
        writer.metadata(name, fields)
    for topic in topics:
        for ns, message in topic.messages:
            writer.write(topic.name, ns, message)
    writer.finish()
    return out.getvalue()


def _topics(reader: Any) -> str:
    listed = sorted((c.topic, c.msgtype) for c in reader.connections)
    return ", ".join(f"{t} ({m})" for t, m in listed) or "none"


def _messages(reader: Any, path: str, topic: str) -> JointStates:
    """The JointState messages of ``topic``, each at its ``header.stamp``, or at the time the
    bag logged it where the stamp is zero (a publisher that stamps nothing)."""
    import numpy as np

    connections = [c for c in reader.connections if c.topic == topic]
    if not connections:
        raise MotionToolError(f"'{path}' has no topic {topic}; its topics: {_topics(reader)}")
    other = [c.msgtype for c in connections if c.msgtype != JOINT_STATE]
    if other:
        raise MotionToolError(
            f"'{path}': topic {topic} holds {other[0]}, not {JOINT_STATE}; choose a topic of "
            f"that type (its topics: {_topics(reader)})"
        )
    stamps: list[int] = []
    names: list[tuple[str, ...]] = []
    positions: list[npt.NDArray[np.float64]] = []
    unstamped = 0
    for connection, logged_ns, raw in reader.messages(connections=connections):
        msg = reader.deserialize(raw, connection.msgtype)
        ns = int(msg.header.stamp.sec) * NS_PER_S + int(msg.header.stamp.nanosec)
        if ns == 0:
            ns, unstamped = int(logged_ns), unstamped + 1
        stamps.append(ns)
        names.append(tuple(str(n) for n in msg.name))
        positions.append(np.asarray(msg.position, dtype=np.float64))
    return JointStates(np.asarray(stamps, dtype=np.int64), names, positions, unstamped)


_MAGIC = {
    b"\x89MCAP": (".mcap", "a ROS 2 bag (MCAP)"),
    b"SQLite format 3\x00": (".db3", "a ROS 2 bag (sqlite3)"),
    b"#ROSBAG V2.0": (".bag", "a ROS 1 bag"),
}
"""How a bag's first bytes say its storage: the file name rosbags reads it by, and its name."""


def _storage(data: bytes) -> tuple[str, str]:
    return next((v for k, v in _MAGIC.items() if data.startswith(k)), (".mcap", "a ROS 2 bag"))


def read_joint_states(data: bytes, path: str, topic: str) -> JointStates:
    """Every ``sensor_msgs/JointState`` message of ``topic`` in the bag ``data``: one
    ``.mcap`` or sqlite3 ``.db3`` file of a ROS 2 bag, or a ROS 1 ``.bag`` (told by their
    first bytes), with rosbags' reader.

    Raises:
        MotionToolError: not a bag rosbags can read, no such topic, or a topic of another type
            (the message lists the bag's topics and types).
    """
    suffix, what = _storage(data)
    with tempfile.TemporaryDirectory(prefix="motiontool-bag-") as folder:
        bag = Path(folder) / f"bag{suffix}"
        bag.write_bytes(data)
        return _read(bag, path, topic, what)


def read_bag_folder(folder: str, topic: str) -> JointStates:
    """:func:`read_joint_states` of a ROS 2 bag's folder (its ``metadata.yaml`` and the
    ``.mcap`` or ``.db3`` files it lists), as ``ros2 bag record`` leaves it."""
    return _read(Path(folder), folder, topic, "a ROS 2 bag folder")


def _read(bag: Path, path: str, topic: str, what: str) -> JointStates:
    highlevel = require("rosbags.highlevel", _EXTRA, "reading a ROS 2 bag")
    try:
        with highlevel.AnyReader([bag]) as reader:
            return _messages(reader, path, topic)
    except MotionToolError:
        raise
    except Exception as exc:  # rosbags' own errors and what a damaged file raises inside
        reason = str(exc).replace(str(bag), "the file") or type(exc).__name__
        raise MotionToolError(f"cannot read '{path}' as {what}: {reason}") from exc
