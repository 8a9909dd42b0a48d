"""Reading a ROS 2 bag back in tests with rosbags' own reader (not the writer's assumptions)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

__all__ = ["read_bag"]


def read_bag(path: Path) -> dict[str, list[tuple[int, Any]]]:
    """Every message of the bag by ``"topic type"``, with rosbags' reader: (bag time ns, msg)."""
    from rosbags.highlevel import AnyReader

    out: dict[str, list[tuple[int, Any]]] = {}
    with AnyReader([path]) as reader:
        for connection, ns, raw in reader.messages():
            msg = reader.deserialize(raw, connection.msgtype)
            out.setdefault(f"{connection.topic} {connection.msgtype}", []).append((ns, msg))
    return out
