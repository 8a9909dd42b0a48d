"""Recorded joint states as teams keep them, each written here with rosbags' own writers (no
vendored binaries): a ROS 2 bag's folder in sqlite3 (Humble's default) and MCAP storage, a bare
``.db3``, a ROS 1 ``.bag``, JointState split across two publishers, unstamped messages; and
``--max-error`` kept after the times are put on whole ms, or refused with the error reached."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from typer.testing import CliRunner

from motiontool.cli.app import app
from motiontool.motionfmt import read_motion

pytestmark = pytest.mark.needs("ros")

JOINTS = ("shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint")
T0 = 1_700_000_000 * 10**9


def _q(t_s: np.ndarray, j: int) -> np.ndarray:
    return 0.6 * np.sin(0.9 * t_s + j) - 0.2 * j


def _run(*args: str | Path) -> tuple[int, str]:
    result = CliRunner().invoke(app, ["convert", *map(str, args)])
    return result.exit_code, result.stderr


Message = tuple[int, int, tuple[str, ...], np.ndarray]  # (log ns, stamp ns, names, positions)


def _messages(hz: float = 250.0, seconds: float = 1.0) -> list[Message]:
    n = round(hz * seconds)
    stamps = T0 + np.rint(np.arange(n) / hz * 1e9).astype(np.int64)
    t = (stamps - T0) / 1e9
    q = np.stack([_q(t, j) for j in range(len(JOINTS))], axis=1)
    return [(int(s) + 300_000, int(s), JOINTS, q[k]) for k, s in enumerate(stamps)]


def _ros2(folder: Path, messages: list[Message], storage: str) -> Path:
    """``messages`` on /joint_states with rosbags' rosbag2 Writer; the bag's folder."""
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS2_HUMBLE)
    plugin = StoragePlugin.SQLITE3 if storage == "sqlite3" else StoragePlugin.MCAP
    with Writer(folder, version=8, storage_plugin=plugin) as writer:
        conn = writer.add_connection(  # both publishers on one: ros2 bag record keeps one
            "/joint_states", "sensor_msgs/msg/JointState", typestore=store
        )
        for log_ns, stamp_ns, names, q in messages:
            raw = store.serialize_cdr(_msg(store, stamp_ns, names, q), "sensor_msgs/msg/JointState")
            writer.write(conn, log_ns, raw)
    return folder


def _msg(store: Any, stamp_ns: int, names: tuple[str, ...], q: np.ndarray) -> Any:
    t = store.types
    stamp = t["builtin_interfaces/msg/Time"](sec=stamp_ns // 10**9, nanosec=stamp_ns % 10**9)
    return t["sensor_msgs/msg/JointState"](
        header=t["std_msgs/msg/Header"](stamp=stamp, frame_id=""),
        name=list(names),
        position=np.asarray(q, dtype=np.float64),
        velocity=np.zeros(0),
        effort=np.zeros(0),
    )


def _ros1(path: Path, messages: list[Message]) -> Path:
    """``messages`` on /joint_states with rosbags' rosbag1 Writer (ROS 1 Noetic's types)."""
    from rosbags.rosbag1 import Writer
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS1_NOETIC)
    with Writer(path) as writer:
        conn = writer.add_connection("/joint_states", "sensor_msgs/msg/JointState", typestore=store)
        for log_ns, stamp_ns, names, q in messages:
            t = store.types
            stamp = t["builtin_interfaces/msg/Time"](
                sec=stamp_ns // 10**9, nanosec=stamp_ns % 10**9
            )
            msg = t["sensor_msgs/msg/JointState"](
                header=t["std_msgs/msg/Header"](seq=0, stamp=stamp, frame_id=""),
                name=list(names),
                position=np.asarray(q, dtype=np.float64),
                velocity=np.zeros(0),
                effort=np.zeros(0),
            )
            writer.write(conn, log_ns, store.serialize_ros1(msg, "sensor_msgs/msg/JointState"))
    return path


def _within(motion_path: Path, messages: list[Message], bound: float) -> None:
    """Every recorded sample within ``bound`` rad of the motion's straight lines."""
    motion = read_motion(str(motion_path))
    key = motion.times_ms.astype(float)
    t0 = max(min(s for _, s, n, _ in messages if j in n) for j in JOINTS)
    for _, stamp, names, q in messages:
        t_ms = (stamp - t0) / 1e6
        if t_ms < 0 or t_ms > key[-1]:
            continue
        for name, value in zip(names, q, strict=True):
            got = np.interp(t_ms, key, motion.values[:, motion.column(name)])
            assert abs(got - value) <= bound + 1e-9, (name, t_ms)


BAGS: dict[str, Callable[[Path, list[Message]], Path]] = {
    "sqlite3 folder": lambda p, m: _ros2(p / "rec", m, "sqlite3"),
    "mcap folder": lambda p, m: _ros2(p / "rec", m, "mcap"),
    "bare .db3": lambda p, m: _ros2(p / "rec", m, "sqlite3") / "rec.db3",
    "ROS 1 .bag": lambda p, m: _ros1(p / "rec.bag", m),
}


@pytest.mark.parametrize("kind", BAGS)
def test_every_storage_reads_the_same_motion(tmp_path: Path, kind: str) -> None:
    messages = _messages()
    bag = BAGS[kind](tmp_path, messages)
    code, err = _run(bag, tmp_path / "rec.motion", "--max-error", "0.001", "--robot", "none")
    assert code == 0, err
    assert "read 250 sensor_msgs/JointState messages of /joint_states (0.996 s" in err
    _within(tmp_path / "rec.motion", messages, 0.001)
    reference = tmp_path / "ref"
    reference.mkdir()
    mcap = _ros2(reference / "rec", messages, "mcap") / "rec.mcap"
    assert _run(mcap, reference / "rec.motion", "--max-error", "0.001", "--robot", "none")[0] == 0
    assert read_motion(str(tmp_path / "rec.motion")) == read_motion(str(reference / "rec.motion"))


def test_joint_states_split_across_two_publishers_merge_by_name(tmp_path: Path) -> None:
    # The arm's driver publishes two joints at 250 Hz; another node the third at 100 Hz,
    # stamped 1.5 ms apart from the driver's.
    arm = [(lg, s, JOINTS[:2], q[:2]) for lg, s, _, q in _messages(250.0)]
    stamps = T0 + 1_500_000 + np.arange(100) * 10_000_000
    wrist = [(int(s) + 1, int(s), JOINTS[2:], _q(np.array([(s - T0) / 1e9]), 2)) for s in stamps]
    messages = sorted(arm + wrist, key=lambda m: m[0])
    bag = _ros2(tmp_path / "rec", messages, "sqlite3")
    code, err = _run(bag, tmp_path / "rec.motion", "--max-error", "0.001", "--robot", "none")
    assert code == 0, err
    assert "2 sets of joint names merged by name" in err
    motion = read_motion(str(tmp_path / "rec.motion"))
    assert motion.joints == JOINTS
    _within(tmp_path / "rec.motion", messages, 0.001)


def test_unstamped_messages_are_at_their_log_time(tmp_path: Path) -> None:
    messages = [(lg, 0, n, q) for lg, _, n, q in _messages()]
    bag = _ros2(tmp_path / "rec", messages, "mcap")
    code, err = _run(bag, tmp_path / "rec.motion", "--max-error", "0.001", "--robot", "none")
    assert code == 0, err
    assert "250 unstamped messages placed at the time the bag logged them" in err
    logged = [(lg, lg, n, q) for lg, _, n, q in messages]
    _within(tmp_path / "rec.motion", logged, 0.001)


def test_whole_ms_that_cannot_meet_max_error_write_nothing(tmp_path: Path) -> None:
    # 4 kHz of a fast joint: four samples share each whole ms, 0.25 ms apart at 3 rad/s.
    n = 400
    stamps = T0 + np.arange(n) * 250_000
    q = np.sin(np.arange(n) * 0.00075 * 4)[:, None] * np.ones((1, 3))
    messages = [(int(s), int(s), JOINTS, q[k]) for k, s in enumerate(stamps)]
    bag = _ros2(tmp_path / "rec", messages, "mcap")
    out = tmp_path / "rec.motion"
    code, err = _run(bag, out, "--max-error", "0.0001", "--robot", "none")
    assert code == 1 and not out.exists()
    assert err.startswith("not written: on whole ms the motion cannot keep within it:\n")
    assert "--max-error 0.0001 rad: every sample kept, the motion is " in err
    code, err = _run(bag, out, "--max-error", "0.01", "--robot", "none")
    assert code == 0, err


def test_bad_bags_are_one_line(tmp_path: Path) -> None:
    # Two publishers never recorded at once.
    early = [(lg, s, JOINTS[:2], q[:2]) for lg, s, _, q in _messages()[:10]]
    late = [(lg, s, JOINTS[2:], q[2:]) for lg, s, _, q in _messages()[20:30]]
    bag = _ros2(tmp_path / "rec", early + late, "mcap")
    code, err = _run(bag, tmp_path / "x.motion")
    assert code == 2 and err.count("\n") == 1
    assert "no time has a sample of every joint" in err and str(bag) in err
    empty = tmp_path / "empty"
    empty.mkdir()
    code, err = _run(empty, tmp_path / "x.motion")
    assert code == 2 and err.count("\n") == 1
    assert err.startswith(f"motiontool: error: cannot read '{empty}' as a ROS 2 bag folder")
    assert not (tmp_path / "x.motion").exists()
