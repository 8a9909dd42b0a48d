"""``play --bag`` (issue #18 item 5): a simulated run as a ROS 2 bag, read back with rosbags' own
reader: the measured joint positions as sensor_msgs/JointState, a floating base's pose as
geometry_msgs/PoseStamped, stamped with the simulated time."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from bags import read_bag
from conftest import ROOT
from typer.testing import CliRunner

from motiontool.cli.app import app
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
        torque=np.zeros((s, j)),
        position=rng.normal(size=(frames, j)),
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


@pytest.mark.parametrize("floating", [True, False])
def test_the_bag_holds_every_frame_as_measured(tmp_path: Path, floating: bool) -> None:
    trace = _trace(51, ("HeadYaw", "HeadPitch", "LShoulderPitch"), 0.02)
    path = tmp_path / "run.mcap"
    path.write_bytes(run_bag(trace, floating_base=floating))
    topics = read_bag(path)
    states = topics.pop("/joint_states sensor_msgs/msg/JointState")
    assert len(states) == 51
    for k, (ns, msg) in enumerate(states):
        assert (
            ns == round(k * 0.02 * 1e9) == msg.header.stamp.sec * 10**9 + msg.header.stamp.nanosec
        )
        assert tuple(msg.name) == trace.joints
        assert np.array_equal(msg.position, trace.position[k])  # the doubles as measured
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


def test_play_bag_of_the_nao(tmp_path: Path) -> None:
    motion = ROOT / "motions" / "nao" / "head_no.motion"
    bag = tmp_path / "run.mcap"
    result = runner.invoke(
        app, ["play", str(motion), "--headless", "--hold", "0.2", "--bag", str(bag)]
    )
    assert result.exit_code == 0, result.stderr
    assert result.stderr.startswith(
        f"motiontool: wrote {bag} (ROS 2 bag, MCAP: measured joint positions on /joint_states, "
        "the base pose on /base_pose, "
    )
    topics = read_bag(bag)
    states = topics["/joint_states sensor_msgs/msg/JointState"]
    poses = topics["/base_pose geometry_msgs/msg/PoseStamped"]
    played = read_motion(str(motion))
    steps = math.ceil(played.duration_ms / 20) + 1 + 10  # the motion's steps, then 0.2 s held
    assert len(states) == len(poses) == steps + 1  # the frame before the first step too
    assert [ns for ns, _ in states] == [k * 20_000_000 for k in range(steps + 1)]
    names = list(states[0][1].name)
    assert "HeadYaw" in names and len(names) > 20  # every motor of the robot, measured
    # At the end the head holds the last pose's targets, within the tracking error.
    last = states[-1][1]
    for joint in ("HeadYaw", "HeadPitch"):
        assert (
            abs(last.position[names.index(joint)] - played.values[-1, played.column(joint)]) < 0.05
        )
    z = [msg.pose.position.z for _, msg in poses]
    assert min(z) > 0.2 and max(z) < 0.4  # standing: the Nao's torso height, m


def test_bag_output_mistakes_are_refused_before_the_run(tmp_path: Path) -> None:
    motion = ROOT / "motions" / "nao" / "head_no.motion"
    for args, message in [
        (["--bag", "-"], "--bag writes a binary file beside the report: give it a path"),
        (
            ["--bag", str(tmp_path / "x"), "--json", str(tmp_path / "x")],
            f"--json and --bag both write '{tmp_path / 'x'}'",
        ),
        (["--bag", str(motion)], f"--bag '{motion}' is the input file"),
    ]:
        result = runner.invoke(app, ["play", str(motion), "--headless", *args])
        assert result.exit_code == 2
        assert result.stderr.startswith(f"motiontool: error: {message}"), result.stderr
        assert result.stderr.count("\n") == 1
    assert not (tmp_path / "x").exists()
