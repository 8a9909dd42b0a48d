"""ROS 2 both ways (issue #18 item 2): the FollowJointTrajectory goal YAML, bags written and read
back with rosbags' own reader, a recorded ``/joint_states`` (written with rosbags' own writer,
as ``ros2 bag record -s mcap`` lays it out) imported with the reduction of ``resample``."""

from __future__ import annotations

import functools
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml
from bags import read_bag
from conftest import ROOT
from typer.testing import CliRunner

from motiontool.cli.app import app
from motiontool.kinematics.robots import resolve_robot
from motiontool.motionfmt import read_bytes, read_motion, sample
from motiontool.motionfmt.convert import format_named
from motiontool.motionfmt.convert.base import ExportOptions, ImportOptions
from motiontool.motionfmt.document import loads
from motiontool.motionfmt.motion import Motion
from motiontool.motionfmt.resample import resample
from motiontool.motionfmt.writer import format_motion

runner = CliRunner()
UR = sorted((ROOT / "motions" / "ur5e").glob("*.motion"))
NAO = ROOT / "motions" / "nao" / "wave_right.motion"
SORTING = ROOT / "motions" / "ur5e" / "sorting.motion"

#: The fields of control_msgs/action/FollowJointTrajectory's goal (ros-controls/control_msgs,
#: FollowJointTrajectory.action): ``ros2 action send_goal`` sets these from the YAML and
#: refuses any other key.
GOAL_FIELDS = {
    "trajectory",
    "multi_dof_trajectory",
    "path_tolerance",
    "component_path_tolerance",
    "goal_tolerance",
    "component_goal_tolerance",
    "goal_time_tolerance",
}
#: The joint names Universal Robots' ROS 2 driver publishes for a UR5e (ur_description).
UR_ROS_JOINTS = (
    "shoulder_pan_joint",
    "shoulder_lift_joint",
    "elbow_joint",
    "wrist_1_joint",
    "wrist_2_joint",
    "wrist_3_joint",
)

#: The order the recordings of these tests name the joints in (not the model's).
DRIVER_ORDER = tuple(reversed(UR_ROS_JOINTS))


@functools.cache
def _store() -> Any:
    """rosbags' store of ROS 2 Humble's message types."""
    from rosbags.typesys import Stores, get_typestore

    return get_typestore(Stores.ROS2_HUMBLE)


def _run(*args: str | Path) -> tuple[int, str]:
    result = runner.invoke(app, ["convert", *map(str, args)])
    return result.exit_code, result.stderr


def _held(motion: Motion, step: int) -> tuple[np.ndarray, np.ndarray]:
    """Webots' stream at ``step`` held per joint (plain loop): (elapsed ms, targets)."""
    stream = sample(motion, step)
    held = np.full(stream.targets.shape, np.nan)
    last = np.full(motion.n_joints, np.nan)
    for k in range(stream.targets.shape[0]):
        sent = stream.commanded[k]
        last = np.where(sent, stream.targets[k], last)
        held[k] = last
    return stream.elapsed_ms, held


_RANGES = {"int32": (-(2**31), 2**31 - 1), "uint32": (0, 2**32 - 1)}


def _build(typename: str, values: Any) -> Any:
    """``values`` (parsed YAML) as a message of ``typename`` of rosbags' store, as
    rosidl_runtime_py's set_message_fields does for ``ros2 action send_goal``: every key must
    be a field, every field missing takes its default, numbers of their type and range."""
    _, fields = _store().fielddefs[typename]
    given = dict(values)
    unknown = set(given) - {name for name, _ in fields}
    assert not unknown, (typename, unknown)
    kwargs: dict[str, Any] = {}
    for name, (kind, spec) in fields:
        value = given.get(name)
        if kind == 2:  # a message
            kwargs[name] = _build(spec, value or {})
        elif kind in (3, 4):  # an array or a sequence
            (inner_kind, inner), _ = spec
            if inner_kind == 2:
                kwargs[name] = [_build(inner, v) for v in value or []]
            elif inner[0] == "string":
                assert all(isinstance(v, str) for v in value or []), (name, value)
                kwargs[name] = list(value or [])
            else:
                assert all(isinstance(v, float) for v in value or []), (name, value)
                kwargs[name] = np.array(value or [], dtype=np.float64)
        else:
            base = spec[0]
            if base in _RANGES:
                value = 0 if value is None else value
                lo, hi = _RANGES[base]
                assert isinstance(value, int) and lo <= value <= hi, (name, value)
            elif base == "string":
                value = value or ""
            kwargs[name] = value
    return _store().types[typename](**kwargs)


# --------------------------------------------------------------------------- the goal YAML


@pytest.mark.needs("ros")
@pytest.mark.parametrize("path", [*UR, NAO], ids=lambda p: p.name)
def test_goal_yaml_is_what_send_goal_takes_and_gives_webots_stream(
    path: Path, tmp_path: Path
) -> None:
    out = tmp_path / f"{path.stem}.trajectory.yaml"
    code, err = _run(path, out)
    assert code == 0, err
    goal = yaml.safe_load(out.read_text())
    assert set(goal) == {"trajectory"} and set(goal) <= GOAL_FIELDS
    traj = goal["trajectory"]
    assert set(traj) == {"joint_names", "points"}
    message = _build("trajectory_msgs/msg/JointTrajectory", traj)  # no unknown field
    _store().serialize_cdr(message, "trajectory_msgs/msg/JointTrajectory")  # a valid message
    motion = read_motion(str(path))
    assert traj["joint_names"] == list(dict.fromkeys(motion.joints))
    step = resolve_robot("auto", motion.joints).default_timestep_ms
    elapsed, held = _held(motion, step)
    times = []
    for point in traj["points"]:
        assert set(point) == {"positions", "time_from_start"}
        t = point["time_from_start"]
        assert set(t) == {"sec", "nanosec"} and 0 <= t["nanosec"] < 10**9
        assert all(isinstance(q, float) for q in point["positions"])  # YAML floats, not str
        times.append(t["sec"] * 1000 + t["nanosec"] / 1e6)
    keys = np.array([p["positions"] for p in traj["points"]])
    t_ms = np.array(times) - 1000  # the default lead-in
    assert t_ms[0] == 0 and np.all(np.diff(t_ms) > 0)
    # joint_trajectory_controller: straight lines between points given as positions.
    for j in range(held.shape[1]):
        line = np.interp(elapsed.astype(float), t_ms, keys[:, j])
        assert np.max(np.abs(line - held[:, j])) < 1e-12
    assert "worst deviation from Webots' command stream:" in err


def test_ur5e_motors_are_the_ur_ros_driver_names() -> None:
    """So the UR5e needs no built-in joint map: Webots' names are the driver's."""
    assert resolve_robot("ur5e").joint_names == UR_ROS_JOINTS


def test_a_joint_without_a_first_target_is_refused(tmp_path: Path) -> None:
    src = tmp_path / "late.motion"
    src.write_text("#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n0,P0,0,*\n400,P1,0.2,0.1\n")
    code, err = _run(src, tmp_path / "late.trajectory.yaml")
    assert code == 2
    assert err == (
        "motiontool: error: HeadPitch has no target in the first pose ('*'): a trajectory "
        "point sets every joint at once; give it a number there\n"
    )


# --------------------------------------------------------------------------- bags, written


@pytest.mark.needs("ros")
def test_bag_holds_the_stream_bit_for_bit_and_the_trajectory(tmp_path: Path) -> None:
    out = tmp_path / "sorting.mcap"
    code, err = _run(SORTING, out)
    assert code == 0, err
    topics = read_bag(out)
    assert set(topics) == {
        "/joint_states sensor_msgs/msg/JointState",
        "/joint_trajectory trajectory_msgs/msg/JointTrajectory",
    }
    elapsed, held = _held(read_motion(str(SORTING)), 8)
    states = topics["/joint_states sensor_msgs/msg/JointState"]
    assert len(states) == elapsed.shape[0] == 1877
    for k, (ns, msg) in enumerate(states):
        assert ns == elapsed[k] * 1_000_000
        assert msg.header.stamp.sec * 10**9 + msg.header.stamp.nanosec == ns
        assert tuple(msg.name) == UR_ROS_JOINTS
        assert np.array_equal(msg.position.view(np.int64), held[k].view(np.int64))
    ((ns, traj),) = topics["/joint_trajectory trajectory_msgs/msg/JointTrajectory"]
    goal = tmp_path / "sorting.trajectory.yaml"
    assert _run(SORTING, goal)[0] == 0
    points = yaml.safe_load(goal.read_text())["trajectory"]["points"]
    assert ns == 0 and len(traj.points) == len(points) == 27
    for p, q in zip(traj.points, points, strict=True):
        assert p.positions.tolist() == q["positions"]
        assert (p.time_from_start.sec, p.time_from_start.nanosec) == tuple(
            q["time_from_start"].values()
        )


@pytest.mark.needs("ros")
def test_motion_to_bag_to_motion_keeps_the_stream(tmp_path: Path) -> None:
    path = ROOT / "motions" / "ur5e" / "jog.motion"
    assert _run(path, tmp_path / "jog.mcap")[0] == 0
    code, err = _run(tmp_path / "jog.mcap", tmp_path / "back.motion", "--max-error", "0")
    assert code == 0, err
    a, b = read_motion(str(path)), read_motion(str(tmp_path / "back.motion"))
    assert b.joints == a.joints and b.times_ms[0] == 0
    assert b.n_poses <= a.n_poses  # only the corners of the stream are kept
    ea, ha = _held(a, 8)
    eb, hb = _held(b, 8)
    n = min(ea.shape[0], eb.shape[0])
    assert np.max(np.abs(ha[:n] - hb[:n])) < 1e-12
    assert "worst deviation from the recording: " in err


# --------------------------------------------------------------------------- a recording


def _recording(
    folder: Path,
    *,
    hz: float = 500.0,
    seconds: float = 4.0,
    names: tuple[str, ...] = UR_ROS_JOINTS,
    stamps: np.ndarray | None = None,
    topic: str = "/joint_states",
) -> tuple[Path, np.ndarray, np.ndarray]:
    """A real arm's ``/joint_states`` as ``ros2 bag record -s mcap`` writes it (rosbags' own
    writer): stamps from a wall clock with jitter, the joints in another order than the
    model's (the motion keeps the recording's order). The bag's receive times increase even
    where ``stamps`` (the header's) do not. Returns (the .mcap file, stamps ns, positions
    (M, J) in ``names`` order)."""
    from rosbags.rosbag2 import StoragePlugin, Writer

    store = _store()
    rng = np.random.default_rng(7)
    n = round(hz * seconds)
    if stamps is None:
        t = 1_700_000_000 + np.arange(n) / hz + rng.uniform(-1e-4, 1e-4, n)
        stamps = np.rint(t * 1e9).astype(np.int64)
    tt = (stamps - stamps[0]) / 1e9
    q = np.stack([0.6 * np.sin(0.9 * tt + j) - 0.2 * j for j in range(len(names))], axis=1)
    js = store.types["sensor_msgs/msg/JointState"]
    header, time = store.types["std_msgs/msg/Header"], store.types["builtin_interfaces/msg/Time"]
    order = list(reversed(range(len(names))))  # the driver's order, not the model's
    with Writer(folder, version=9, storage_plugin=StoragePlugin.MCAP) as writer:
        conn = writer.add_connection(topic, "sensor_msgs/msg/JointState", typestore=store)
        for k, ns in enumerate(stamps):
            stamp = time(sec=int(ns) // 10**9, nanosec=int(ns) % 10**9)
            msg = js(
                header=header(stamp=stamp, frame_id=""),
                name=[names[j] for j in order],
                position=q[k, order],
                velocity=np.zeros(len(names)),
                effort=np.zeros(len(names)),
            )
            received = int(stamps[0]) + k * 2_000_000 + 500_000
            writer.write(conn, received, store.serialize_cdr(msg, "sensor_msgs/msg/JointState"))
    return folder / f"{folder.name}.mcap", stamps, q


@pytest.mark.needs("ros")
def test_a_recording_becomes_a_motion_reduced_as_resample_reduces(tmp_path: Path) -> None:
    bag, stamps, q = _recording(tmp_path / "arm")
    out = tmp_path / "arm.motion"
    code, err = _run(bag, out, "--max-error", "0.002")
    assert code == 0, err
    got = read_motion(str(out))
    assert got.joints == DRIVER_ORDER and got.times_ms[0] == 0
    assert got.times_ms[-1] == round((stamps[-1] - stamps[0]) / 1e6)
    assert 2 < got.n_poses < 100  # 2000 samples, reduced
    # The same reduction as resample --max-error on the recording put on whole ms.
    ms = np.rint((stamps - stamps[0]) / 1e6).astype(np.int64)
    q = q[:, ::-1]  # as the driver orders them
    full = Motion(
        DRIVER_ORDER, tuple(f"Pose{t}ms" for t in ms), ms, q, np.ones(q.shape, dtype=bool)
    )
    doc = loads(format_motion(full).encode(), "x")
    assert resample(doc, max_error=0.002).document.motion == got
    # The worst deviation said is the motion against every sample at its own stamp.
    t = (stamps - stamps[0]) / 1e6
    worst = max(
        np.max(np.abs(np.interp(t, got.times_ms.astype(float), got.values[:, j]) - q[:, j]))
        for j in range(q.shape[1])
    )
    assert worst < 0.002 + 1e-3 * 0.6 * 0.9  # the bound, and 0.1 ms of time rounding
    line = next(x for x in err.splitlines() if x.startswith("worst deviation from the recording"))
    assert f"{worst:.6g} rad" in line
    assert "read 2000 sensor_msgs/JointState messages of /joint_states (3.998" in err
    assert "checked against robot ur5e: clean" in err


@pytest.mark.needs("ros")
def test_joint_map_names_both_ways(tmp_path: Path) -> None:
    ros = tuple(f"arm_{j}" for j in range(6))
    table = tmp_path / "map.toml"
    table.write_text("".join(f'{a} = "{b}"\n' for a, b in zip(UR_ROS_JOINTS, ros, strict=True)))
    bag, _, _ = _recording(tmp_path / "arm", names=ros, seconds=1.0)
    code, err = _run(bag, tmp_path / "a.motion", "--joint-map", table)
    assert code == 0, err
    assert read_motion(str(tmp_path / "a.motion")).joints == DRIVER_ORDER
    ymap = tmp_path / "map.yaml"
    ymap.write_text("".join(f"{a}: {b}\n" for a, b in zip(UR_ROS_JOINTS, ros, strict=True)))
    code, err = _run(SORTING, tmp_path / "s.trajectory.yaml", "--joint-map", ymap)
    assert code == 0, err
    goal = yaml.safe_load((tmp_path / "s.trajectory.yaml").read_text())
    assert goal["trajectory"]["joint_names"] == list(ros)


@pytest.mark.parametrize(
    ("text", "name", "message"),
    [
        (
            'HeadYaw = "a"\nHeadPitch = 3\n',
            "m.toml",
            "{d}/m.toml:2:1: HeadPitch: the ROS name must",
        ),
        ("HeadYaw = \n", "m.toml", "{d}/m.toml:1:11: Invalid value"),
        pytest.param(  # YAML is read by ruamel.yaml, of the ros extra
            "HeadYaw: a\n  HeadPitch: [b\n",
            "m.yaml",
            "{d}/m.yaml:2:12: not YAML: ",
            marks=pytest.mark.needs("ros"),
        ),
        pytest.param(
            "- a\n",
            "m.yaml",
            "{d}/m.yaml:1:1: a joint map is a table",
            marks=pytest.mark.needs("ros"),
        ),
        ("a = 1\n", "m.json", "'{d}/m.json': a joint map is a .toml or a .yaml (.yml) file"),
    ],
)
def test_a_bad_joint_map_is_one_located_error(
    tmp_path: Path, text: str, name: str, message: str
) -> None:
    (tmp_path / name).write_text(text)
    code, err = _run(NAO, tmp_path / "w.trajectory.yaml", "--joint-map", tmp_path / name)
    assert code == 2
    assert err.startswith("motiontool: error: " + message.format(d=tmp_path)), err
    assert err.count("\n") == 1
    assert not (tmp_path / "w.trajectory.yaml").exists()


@pytest.mark.needs("ros")
def test_bad_recordings_are_one_line_each(tmp_path: Path) -> None:
    bag, _, _ = _recording(tmp_path / "ok", seconds=0.1)
    code, err = _run(bag, tmp_path / "x.motion", "--topic", "/nope")
    assert (code, err) == (
        2,
        f"motiontool: error: '{bag}' has no topic /nope; its topics: /joint_states "
        "(sensor_msgs/msg/JointState)\n",
    )
    stamps = np.array([0, 2, 4, 3, 6], dtype=np.int64) * 1_000_000 + 10**18
    back, _, _ = _recording(tmp_path / "back", stamps=stamps)
    code, err = _run(back, tmp_path / "x.motion")
    assert (code, err) == (
        2,
        f"motiontool: error: '{back}': /joint_states message 4 is stamped 1000000000.003000000 "
        "s, not after message 3's 1000000000.004000000 s: header stamps must increase\n",
    )
    garbage = tmp_path / "garbage.mcap"
    garbage.write_bytes(b"not a bag at all")
    code, err = _run(garbage, tmp_path / "x.motion")
    assert code == 2 and err.startswith(f"motiontool: error: cannot read '{garbage}' as a ROS 2")
    assert err.count("\n") == 1
    assert not (tmp_path / "x.motion").exists()


@pytest.mark.needs("ros")
def test_a_topic_of_another_type_is_refused(tmp_path: Path) -> None:
    assert _run(SORTING, tmp_path / "s.mcap")[0] == 0
    code, err = _run(tmp_path / "s.mcap", tmp_path / "x.motion", "--topic", "/joint_trajectory")
    assert code == 2
    assert err.startswith(
        f"motiontool: error: '{tmp_path / 's.mcap'}': topic /joint_trajectory holds "
        "trajectory_msgs/msg/JointTrajectory, not sensor_msgs/msg/JointState"
    )


def test_ros_options_are_refused_where_no_format_reads_them(tmp_path: Path) -> None:
    code, err = _run(NAO, tmp_path / "w.csv", "--max-error", "0.1")
    assert code == 2 and err.endswith(", not to motion -> csv\n") and err.count("\n") == 1
    able = err.removeprefix("motiontool: error: --max-error applies to ").split(", not to")[0]
    assert {"choregraphe", "choregraphe-py", "ros-trajectory", "rosbag", "rosbag1"} <= set(
        able.split(", ")
    )


@pytest.mark.needs("ros", "sim")
def test_library_round_trip_through_the_registry() -> None:
    motion = read_bytes(NAO.read_bytes(), "w.motion").motion
    fmt = format_named("rosbag")
    assert fmt is not None and fmt.write is not None and fmt.read is not None
    data = fmt.write(motion, ExportOptions(timestep_ms=20)).data
    back = fmt.read(data, "w.mcap", ImportOptions(max_error_rad=0.0))
    assert back.recording is not None and back.recording.messages == 221
    assert back.recording.deviation.max_rad < 1e-12


# --------------------------------------------------------------------------- Nao hands, many-to-one

HAND = [f"LPhalanx{i}" for i in range(1, 9)]


def _hand_motion(path: Path, fingers: list[str] | None = None) -> Path:
    """HeadYaw and the left hand's eight phalanges, all at one value unless ``fingers`` gives
    each finger's cells of the second pose."""
    second = fingers or ["0.8"] * 8
    path.write_text(
        "#WEBOTS_MOTION,V1.0,HeadYaw," + ",".join(HAND) + "\n"
        "00:00:000,P1,0," + ",".join(["0.2"] * 8) + "\n"
        "00:00:400,P2,0.3," + ",".join(second) + "\n"
    )
    return path


@pytest.mark.parametrize(
    "ending", [".trajectory.yaml", pytest.param(".mcap", marks=pytest.mark.needs("ros"))]
)
def test_nao_fingers_become_naoqis_hand(tmp_path: Path, ending: str) -> None:
    # The README: the Nao's names are NAOqi's, which naoqi_driver publishes: one LHand.
    src = _hand_motion(tmp_path / "grip.motion")
    out = tmp_path / f"grip{ending}"
    code, err = _run(src, out, "--robot", "nao")
    assert code == 0, err
    if ending == ".mcap":
        states = read_bag(out)["/joint_states sensor_msgs/msg/JointState"]
        assert [tuple(msg.name) for _, msg in states] == [("HeadYaw", "LHand")] * len(states)
        assert states[-1][1].position.tolist() == [0.3, 0.8]
        return
    goal = yaml.safe_load(out.read_text())["trajectory"]
    assert goal["joint_names"] == ["HeadYaw", "LHand"]
    assert [p["positions"] for p in goal["points"]] == [[0.0, 0.2], [0.3, 0.8]]


def test_fingers_apart_are_refused_at_the_cell(tmp_path: Path) -> None:
    src = _hand_motion(tmp_path / "grip.motion", ["0.8"] * 6 + ["0.1", "0.8"])
    code, err = _run(src, tmp_path / "grip.trajectory.yaml", "--robot", "nao")
    assert code == 2
    column = len("00:00:400,P2,0.3,") + len("0.8,") * 6 + 1
    assert err == (
        f"motiontool: error: {src}:3:{column}: LPhalanx7 = 0.1 rad at 400 ms is not "
        "LPhalanx1's 0.8 rad: both go to ROS joint 'LHand', which has one position; "
        'keep them apart in --joint-map (LPhalanx7 = "LPhalanx7")\n'
    )
    assert not (tmp_path / "grip.trajectory.yaml").exists()
    keep = tmp_path / "keep.toml"
    keep.write_text('LPhalanx7 = "LPhalanx7"\n')
    code, err = _run(src, tmp_path / "grip.trajectory.yaml", "--joint-map", keep)
    assert code == 0, err
    goal = yaml.safe_load((tmp_path / "grip.trajectory.yaml").read_text())["trajectory"]
    assert goal["joint_names"] == ["HeadYaw", "LHand", "LPhalanx7"]


@pytest.mark.needs("ros")
def test_joint_map_takes_many_to_one_where_the_columns_agree(tmp_path: Path) -> None:
    src = tmp_path / "m.csv"
    src.write_text("time_ms,HeadYaw,HeadPitch\n0,0.1,0.1\n500,0.2,0.2\n1000,0.2,0.3\n")
    table = tmp_path / "map.yaml"
    table.write_text("HeadYaw: head\nHeadPitch: head\n")
    code, err = _run(src, tmp_path / "m.trajectory.yaml", "--joint-map", table)
    assert code == 2
    assert err.startswith(
        f"motiontool: error: {src}:4:10: HeadPitch = 0.3 rad at 1000 ms is not HeadYaw's 0.2 rad: "
        "both go to ROS joint 'head'"
    ), err
    src.write_text("time_ms,HeadYaw,HeadPitch\n0,0.1,0.1\n500,0.2,0.2\n")
    code, err = _run(src, tmp_path / "m.trajectory.yaml", "--joint-map", table)
    assert code == 0, err
    goal = yaml.safe_load((tmp_path / "m.trajectory.yaml").read_text())["trajectory"]
    assert goal["joint_names"] == ["head"]


@pytest.mark.needs("ros")
def test_a_real_naos_hand_reads_back_as_the_eight_phalanges(tmp_path: Path) -> None:
    # Both ways: naoqi_driver's one LHand is the Webots Nao's LPhalanx1..8, all at its value.
    bag, _, _ = _recording(tmp_path / "nao", names=("HeadYaw", "LHand"), seconds=0.5)
    code, err = _run(bag, tmp_path / "nao.motion", "--max-error", "0.001")
    assert code == 0, err
    motion = read_motion(str(tmp_path / "nao.motion"))
    assert motion.joints == ("LPhalanx1", *HAND[1:], "HeadYaw")  # the recording's order
    assert (motion.values[:, :8] == motion.values[:, :1]).all()
    assert "unknown joint" not in err
