"""``play --bag`` (issue #18 item 5): a simulated run as a ROS 2 bag, read back with rosbags' own
reader: the measured joint states as sensor_msgs/JointState, a floating base's pose as
geometry_msgs/PoseStamped, every link on /tf and /tf_static, the URDF, /clock, stamped with the
simulated time (from a given start)."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from bags import read_bag
from conftest import ROOT
from typer.testing import CliRunner

from motiontool.cli.app import app
from motiontool.cli.play_bag import parse_bag_start
from motiontool.motionfmt import read_motion
from motiontool.sim.bag import run_bag
from motiontool.sim.trace import Trace

runner = CliRunner()


def _trace(frames: int, joints: tuple[str, ...], step_s: float) -> Trace:
    rng = np.random.default_rng(3)
    s, j = frames - 1, len(joints)
    quat = rng.normal(size=(frames, 4))
    return Trace(
        joints=joints,
        control_step_s=step_s,
        physics_step_s=step_s / 4,
        time_s=np.arange(frames) * step_s,
        commanded=np.ones((s, j), dtype=bool),
        targets=np.zeros((s, j)),
        velocity_cmd=np.zeros((s, j)),
        torque=rng.normal(size=(s, j)),
        position=rng.normal(size=(frames, j)),
        velocity=rng.normal(size=(frames, j)),
        base_pos=rng.normal(size=(frames, 3)),
        base_quat=quat / np.linalg.norm(quat, axis=1, keepdims=True),
        feet=(),
        foot_pos=np.zeros((frames, 0, 3)),
        foot_contact=np.zeros((frames, 0), dtype=bool),
        bodies=(),
        body_pos=np.zeros((0, 0, 3)),
        body_quat=np.zeros((0, 0, 4)),
        steps_done=s,
    )


@pytest.mark.needs("ros", "sim")
@pytest.mark.parametrize("floating", [True, False])
def test_the_bag_holds_every_frame_as_measured(tmp_path: Path, floating: bool) -> None:
    trace = _trace(51, ("HeadYaw", "HeadPitch", "LShoulderPitch"), 0.02)
    path = tmp_path / "run.mcap"
    path.write_bytes(run_bag(trace, floating_base=floating))
    topics = read_bag(path)
    states = topics.pop("/joint_states sensor_msgs/msg/JointState")
    clock = topics.pop("/clock rosgraph_msgs/msg/Clock")
    assert len(states) == len(clock) == 51
    for k, (ns, msg) in enumerate(states):
        assert (
            ns == round(k * 0.02 * 1e9) == msg.header.stamp.sec * 10**9 + msg.header.stamp.nanosec
        )
        assert clock[k][0] == ns == clock[k][1].clock.sec * 10**9 + clock[k][1].clock.nanosec
        assert tuple(msg.name) == trace.joints
        assert np.array_equal(msg.position, trace.position[k])  # the doubles as measured
        assert np.array_equal(msg.velocity, trace.velocity[k])
        if k == 0:  # before the first step: no torque yet
            assert len(msg.effort) == 3 and np.isnan(msg.effort).all()
        else:
            assert np.array_equal(msg.effort, trace.torque[k - 1])
    if not floating:
        assert topics == {}
        return
    poses = topics.pop("/base_pose geometry_msgs/msg/PoseStamped")
    assert topics == {} and len(poses) == 51
    for k, (ns, msg) in enumerate(poses):
        assert msg.header.frame_id == "world" and ns == states[k][0]
        p, q = msg.pose.position, msg.pose.orientation
        assert (p.x, p.y, p.z) == tuple(trace.base_pos[k])
        assert (q.w, q.x, q.y, q.z) == tuple(trace.base_quat[k])  # ROS: x, y, z, w fields


START = "2024-05-01T12:00:00.25+02:00"
START_NS = 1_714_557_600_250_000_000  # 10:00:00.25 UTC


@pytest.mark.needs("sim")
def test_play_bag_of_the_nao(tmp_path: Path) -> None:
    motion = ROOT / "motions" / "nao" / "head_no.motion"
    bag, report_path = tmp_path / "run.mcap", tmp_path / "run.json"
    result = runner.invoke(
        app,
        [
            "play",
            str(motion),
            "--headless",
            "--hold",
            "0.2",
            "--bag",
            str(bag),
            "--bag-start",
            START,
            "--json",
            str(report_path),
        ],
    )
    assert result.exit_code == 0, result.stderr
    assert result.stderr.startswith(
        f"motiontool: wrote {bag} (ROS 2 bag, MCAP: measured joint states on /joint_states, the "
        "links on /tf and /tf_static, the URDF on /robot_description, /clock, the base pose on "
        "/base_pose, "
    )
    topics = read_bag(bag)
    states = topics["/joint_states sensor_msgs/msg/JointState"]
    poses = topics["/base_pose geometry_msgs/msg/PoseStamped"]
    played = read_motion(str(motion))
    steps = math.ceil(played.duration_ms / 20) + 1 + 10  # the motion's steps, then 0.2 s held
    assert len(states) == len(poses) == steps + 1  # the frame before the first step too
    assert [ns for ns, _ in states] == [START_NS + k * 20_000_000 for k in range(steps + 1)]
    names = list(states[0][1].name)
    assert "HeadYaw" in names and len(names) > 20  # every motor of the robot, measured
    for _, msg in states:
        assert len(msg.position) == len(msg.velocity) == len(msg.effort) == len(names)
    # At the end the head holds the last pose's targets, within the tracking error.
    last = states[-1][1]
    for joint in ("HeadYaw", "HeadPitch"):
        assert (
            abs(last.position[names.index(joint)] - played.values[-1, played.column(joint)]) < 0.05
        )
    z = [msg.pose.position.z for _, msg in poses]
    assert min(z) > 0.2 and max(z) < 0.4  # standing: the Nao's torso height, m
    clock = [ns for ns, _ in topics["/clock rosgraph_msgs/msg/Clock"]]
    assert clock == [ns for ns, _ in states]  # one tick a frame, strictly increasing
    _the_links_rebuild_the_robot(bag, topics, json.loads(report_path.read_text()))


def _the_links_rebuild_the_robot(bag: Path, topics: dict[str, Any], report: Any) -> None:
    """/tf and /tf_static alone give every link's world pose: the torso's is the report's, the
    left foot's MuJoCo's forward kinematics of the measured joints and base; the frames are the
    links of /robot_description, which Pinocchio reads as URDF; the latched topics say so."""
    import mujoco
    import pinocchio
    from rosbags.highlevel import AnyReader
    from rosbags.interfaces import QosDurability

    (_, description), *more = topics["/robot_description std_msgs/msg/String"]
    (_, static), *more_static = topics["/tf_static tf2_msgs/msg/TFMessage"]
    assert not more and not more_static
    urdf = pinocchio.buildModelFromXML(description.data, pinocchio.JointModelFreeFlyer())
    links = {f.name for f in urdf.frames if str(f.type) == "BODY"}
    dynamic = topics["/tf tf2_msgs/msg/TFMessage"]
    edges = [t for _, m in (dynamic[-1], (0, static)) for t in m.transforms]
    assert {t.child_frame_id for t in edges} == links  # every link, each once
    assert {t.header.frame_id for t in edges} <= links | {"world"}
    world = _chain(edges)
    start = _chain([t for t in dynamic[0][1].transforms] + list(static.transforms))
    base = report["base"]
    torso, torso_start = world["torso"][0], start["torso"][0]
    assert abs(torso[2] - base["final_height_m"]) < 1e-6
    assert abs(torso[0] - torso_start[0] - base["dx_m"]) < 1e-6
    assert abs(torso[1] - torso_start[1] - base["dy_m"]) < 1e-6
    # The left foot: MuJoCo's FK of the last /joint_states and /base_pose on the robot's model.
    model = mujoco.MjModel.from_xml_path(str(ROOT / "kinematics" / "models" / "nao.xml"))
    data = mujoco.MjData(model)
    state = topics["/joint_states sensor_msgs/msg/JointState"][-1][1]
    pose = topics["/base_pose geometry_msgs/msg/PoseStamped"][-1][1].pose
    p, q = pose.position, pose.orientation
    data.qpos[:7] = [p.x, p.y, p.z, q.w, q.x, q.y, q.z]
    for name, value in zip(state.name, state.position, strict=True):
        data.qpos[model.jnt_qposadr[model.joint(name).id]] = value
    mujoco.mj_kinematics(model, data)
    foot_pos, foot_quat = world["l_foot"]
    assert np.abs(foot_pos - data.body("l_foot").xpos).max() < 1e-6
    assert (
        min(
            np.abs(foot_quat - data.body("l_foot").xquat).max(),
            np.abs(foot_quat + data.body("l_foot").xquat).max(),
        )
        < 1e-9
    )
    with AnyReader([bag]) as reader:
        latched = {
            c.topic
            for c in reader.connections
            if any(
                q.durability == QosDurability.TRANSIENT_LOCAL for q in c.ext.offered_qos_profiles
            )
        }
    assert latched == {"/tf_static", "/robot_description"}


def _chain(edges: list[Any]) -> dict[str, tuple[Any, Any]]:
    """Every frame's world pose (position m, quaternion w x y z), chaining ``edges`` from
    ``world`` with quaternion algebra (not the writer's code)."""
    by_child = {t.child_frame_id: t for t in edges}
    out: dict[str, tuple[Any, Any]] = {"world": (np.zeros(3), np.array([1.0, 0, 0, 0]))}

    def pose(frame: str) -> tuple[Any, Any]:
        if frame not in out:
            t = by_child[frame]
            p_pos, p_quat = pose(t.header.frame_id)
            tr, r = t.transform.translation, t.transform.rotation
            local = np.array([r.w, r.x, r.y, r.z])
            rotation = _matrix(p_quat)
            out[frame] = (p_pos + rotation @ [tr.x, tr.y, tr.z], _product(p_quat, local))
        return out[frame]

    for child in by_child:
        pose(child)
    return out


def _matrix(q: Any) -> Any:
    w, x, y, z = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def _product(a: Any, b: Any) -> Any:
    aw, av = a[0], np.asarray(a[1:])
    bw, bv = b[0], np.asarray(b[1:])
    return np.concatenate([[aw * bw - av @ bv], aw * bv + bw * av + np.cross(av, bv)])


@pytest.mark.needs("sim")
def test_bag_output_mistakes_are_refused_before_the_run(tmp_path: Path) -> None:
    motion = ROOT / "motions" / "nao" / "head_no.motion"
    for args, message in [
        (["--bag", "-"], "--bag writes a binary file beside the report: give it a path"),
        (
            ["--bag", str(tmp_path / "x"), "--json", str(tmp_path / "x")],
            f"--json and --bag both write '{tmp_path / 'x'}'",
        ),
        (["--bag", str(motion)], f"--bag '{motion}' is the input file"),
        (
            ["--bag", str(tmp_path / "x"), "--bag-start", "yesterday"],
            "invalid value for '--bag-start': 'yesterday' is not a time: give ISO-8601 "
            "(2024-05-01T12:00:00Z) or ns since the Unix epoch (1714564800000000000)",
        ),
        (
            ["--bag", str(tmp_path / "x"), "--bag-start", "1969-12-31T23:59:59Z"],
            "invalid value for '--bag-start': '1969-12-31T23:59:59Z' is before the Unix epoch",
        ),
        (["--bag-start", "0"], "--bag-start stamps the bag: give --bag FILE too"),
    ]:
        result = runner.invoke(app, ["play", str(motion), "--headless", *args])
        assert result.exit_code == 2
        assert result.stderr.startswith(f"motiontool: error: {message}"), result.stderr
        assert result.stderr.count("\n") == 1
    assert not (tmp_path / "x").exists()


def test_bag_start_reads_iso_8601_and_ns() -> None:
    assert parse_bag_start("1714564800000000001") == 1_714_564_800_000_000_001
    assert parse_bag_start("2024-05-01T12:00:00Z") == 1_714_564_800 * 10**9
    assert parse_bag_start("2024-05-01T12:00:00") == 1_714_564_800 * 10**9  # naive: UTC
    assert parse_bag_start(START) == START_NS  # its offset, and the fraction to the ns
    assert parse_bag_start("1970-01-01T00:00:00.000001Z") == 1_000
