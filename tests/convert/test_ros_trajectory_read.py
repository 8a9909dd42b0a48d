"""A JointTrajectory in YAML read back as a motion: the goal ``--to ros-trajectory`` writes, what
``ros2 topic echo`` and ROS 1's ``rostopic echo`` print, the message under a key; the keyframes
reduced within ``--max-error`` with the deviation printed, whole-ms rounding that cannot meet
it refused (exit 1), bad input one line with its position (exit 2)."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT
from typer.testing import CliRunner

from motiontool.cli.app import app
from motiontool.kinematics.builtin_robots import builtin
from motiontool.motionfmt import read_bytes
from motiontool.motionfmt.convert import format_of
from motiontool.motionfmt.convert.base import ExportOptions, ImportOptions
from motiontool.motionfmt.convert.held import held_stream
from motiontool.motionfmt.convert.joint_map import NAO_HANDS
from motiontool.motionfmt.convert.ros_trajectory import write_ros_trajectory
from motiontool.motionfmt.convert.ros_trajectory_read import read_ros_trajectory
from motiontool.motionfmt.motion import Motion

pytestmark = pytest.mark.needs("ros")

runner = CliRunner()
MOTIONS = sorted((ROOT / "motions").glob("*/*.motion"))
MAX_ERROR = 1e-3  # rad
ROUNDING = 1e-9  # rad: floating-point evaluation of the lines

# What `ros2 topic echo /arm/joint_trajectory trajectory_msgs/msg/JointTrajectory` prints
# (Humble): every field of the message, lists in block style, the document ended by `---`.
ECHO = """\
header:
  stamp:
    sec: 0
    nanosec: 0
  frame_id: ''
joint_names:
- shoulder_pan_joint
- elbow_joint
points:
- positions:
  - 0.1
  - -0.5
  velocities: []
  accelerations: []
  effort: []
  time_from_start:
    sec: 1
    nanosec: 0
- positions:
  - 0.4
  - -0.25
  velocities:
  - 0.0
  - 0.0
  accelerations: []
  effort: []
  time_from_start:
    sec: 2
    nanosec: 500000000
- positions:
  - 0.4
  - 0.0
  velocities: []
  accelerations: []
  effort: []
  time_from_start:
    sec: 3
    nanosec: 0
---
"""

# ROS 1's `rostopic echo`: `seq` in the header, `secs`/`nsecs`, flow lists, padded numbers,
# a space after every `key:` and `-` that opens a block.
ROS1_ECHO = """\
header:
  seq: 0
  stamp:
    secs: 0
    nsecs:         0
  frame_id: ''
joint_names: [shoulder_pan_joint, elbow_joint]
points:
  -
    positions: [0.1, -0.5]
    velocities: []
    accelerations: []
    effort: []
    time_from_start:
      secs: 1
      nsecs:         0
  -
    positions: [0.4, -0.25]
    velocities: []
    accelerations: []
    effort: []
    time_from_start:
      secs: 2
      nsecs: 500000000
  -
    positions: [0.4, 0.0]
    velocities: []
    accelerations: []
    effort: []
    time_from_start:
      secs: 3
      nsecs:         0
---
"""
ROS1_ECHO = re.sub(r"([:-])$", r"\1 ", ROS1_ECHO, flags=re.MULTILINE)  # as it pads them


def _run(*args: str | Path) -> tuple[int, str]:
    result = runner.invoke(app, ["convert", *map(str, args)])
    return result.exit_code, result.stderr


def _motion(path: Path) -> Motion:
    return read_bytes(path.read_bytes(), str(path)).motion


def _expected(motion: Motion) -> None:
    """The motion ECHO and ROS1_ECHO hold: the first point at 0 ms, every point a keyframe."""
    assert motion.joints == ("shoulder_pan_joint", "elbow_joint")
    assert motion.times_ms.tolist() == [0, 1500, 2000]
    assert motion.values.tolist() == [[0.1, -0.5], [0.4, -0.25], [0.4, 0.0]]


def _fingers_apart(motion: Motion) -> tuple[tuple[str, str], ...]:
    """The joint map that keeps apart the fingers that move otherwise than their hand's first
    (``salute.motion``'s RPhalanx7 and 8), as ``convert`` asks for: each under its own name."""
    apart = []
    for j, name in enumerate(motion.joints):
        first = f"{name[0]}Phalanx1"
        if name in NAO_HANDS and first in motion.joints:
            a, b = motion.values[:, j], motion.values[:, motion.column(first)]
            if not np.array_equal(a, b, equal_nan=True):
                apart.append((name, name))
    return tuple(apart)


@pytest.mark.parametrize("path", MOTIONS, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_every_shipped_motion_comes_back_within_the_maximum_error(path: Path) -> None:
    """motion -> ros-trajectory -> motion: the same joints, and Webots plays the result within
    the maximum error of the original at every control step."""
    original = _motion(path)
    step = builtin("nao-v5" if "nao" in path.parent.name else "ur5e").default_timestep_ms
    apart = _fingers_apart(original)
    exported = write_ros_trajectory(original, ExportOptions(timestep_ms=step, joint_map=apart))
    imported = read_ros_trajectory(exported.data, "x.yaml", ImportOptions(joint_map=apart))
    back = imported.motion
    assert imported.recording is not None
    assert imported.recording.deviation.max_rad <= MAX_ERROR + ROUNDING
    a, b = held_stream(original, step), held_stream(back, step)
    assert sorted(a.motors) == sorted(b.motors)
    steps = min(a.elapsed_ms.size, b.elapsed_ms.size)
    assert np.array_equal(a.elapsed_ms[:steps], b.elapsed_ms[:steps])
    assert a.elapsed_ms.size - steps <= 1  # the stream's last corner is the motion's end
    columns = [b.motors.index(m) for m in a.motors]
    err = np.abs(a.targets[:steps] - b.targets[:steps, columns])
    assert np.nanmax(err) <= MAX_ERROR + ROUNDING


@pytest.mark.parametrize("text", [ECHO, ROS1_ECHO], ids=["ros2-topic-echo", "rostopic-echo"])
def test_topic_echo_output_reads(tmp_path: Path, text: str) -> None:
    source, out = tmp_path / "echo.yaml", tmp_path / "arm.motion"
    source.write_text(text, encoding="utf-8")
    code, err = _run(source, out, "--from", "ros-trajectory", "--robot", "none")
    assert code == 0, err
    _expected(_motion(out))
    assert (
        "read 3 points of a trajectory_msgs/JointTrajectory (2 joints); its first point, at "
        "1 s, is the motion's 0 ms\n" in err
    )
    assert "keyframes: 3, reduced within 0.001 rad" in err
    assert "worst deviation from the trajectory's points: 0 rad" in err
    assert "  compared: 6 positions of the points, each at its time_from_start\n" in err


def _indented(text: str, by: int) -> str:
    return "".join(" " * by + line if line.strip() else line for line in text.splitlines(True))


def test_the_message_under_a_key() -> None:
    """A FollowJointTrajectory goal with its tolerances, and a MoveIt RobotTrajectory whose
    multi-DOF trajectory is empty: the one trajectory with points is read."""
    message = ECHO.removesuffix("---\n")
    goal = "trajectory:\n" + _indented(message, 2) + "goal_time_tolerance:\n  sec: 1\n"
    moveit = (
        "trajectory:\n  joint_trajectory:\n"
        + _indented(message, 4)
        + "  multi_dof_joint_trajectory:\n    joint_names: []\n    points: []\n"
    )
    for text in (goal, moveit):
        _expected(read_ros_trajectory(text.encode(), "t.yaml").motion)


def test_the_joint_map_is_used_both_ways(tmp_path: Path) -> None:
    """Written with a joint map, the ROS names are the map's; read back with it, the motion's
    own names; read without it, the ROS names."""
    wave = ROOT / "motions" / "nao" / "wave_right.motion"
    joint_map = tmp_path / "nao_ros.yaml"
    joint_map.write_text("RElbowRoll: r_elbow_roll\nRShoulderPitch: r_shoulder_pitch\n")
    goal, back, raw = tmp_path / "w.trajectory.yaml", tmp_path / "b.motion", tmp_path / "r.motion"
    assert _run(wave, goal, "--joint-map", joint_map)[0] == 0
    assert '"r_elbow_roll"' in goal.read_text() and '"RElbowRoll"' not in goal.read_text()
    code, err = _run(goal, back, "--joint-map", joint_map)
    assert code == 0, err
    assert sorted(_motion(back).joints) == sorted(_motion(wave).joints)
    assert _run(goal, raw, "--robot", "none")[0] == 0
    assert {"r_elbow_roll", "r_shoulder_pitch"} <= set(_motion(raw).joints)


def test_by_ending_and_listed_among_what_convert_reads() -> None:
    fmt = format_of("arm.trajectory.yaml")
    assert fmt is not None and fmt.name == "ros-trajectory" and fmt.read is not None
    assert format_of("arm.yaml") is None  # a joint map, a bag's metadata: --from says it


def _point(ms_ns: tuple[int, int], q: float) -> str:
    sec, ns = ms_ns
    return f"- {{positions: [{q}], time_from_start: {{sec: {sec}, nanosec: {ns}}}}}\n"


def test_times_are_rounded_to_whole_ms_within_the_maximum_error(tmp_path: Path) -> None:
    """Sub-ms times: the motion is on whole ms and its deviation from every point at its own
    time is said; where even every point kept cannot meet --max-error, nothing is written."""
    slow = "joint_names: [j]\npoints:\n" + "".join(
        _point((0, ns), q) for ns, q in ((0, 0.0), (300_400_000, 0.3), (600_800_000, 0.6))
    )
    source, out = tmp_path / "slow.yaml", tmp_path / "slow.motion"
    source.write_text(slow)
    code, err = _run(source, out, "--from", "ros-trajectory", "--robot", "none")
    assert code == 0, err
    motion = _motion(out)
    assert motion.times_ms.tolist() == [0, 601]  # one line: 300 ms is within it
    assert "worst deviation from the trajectory's points: " in err
    worst = float(re.search(r"points: (\S+) rad", err).group(1))  # type: ignore[union-attr]
    assert 0 < worst <= MAX_ERROR
    fast = "joint_names: [j]\npoints:\n" + _point((0, 0), 0.0) + _point((0, 400_000), 1.0)
    fast += _point((1, 0), 1.0)
    source.write_text(fast)
    out.unlink()
    code, err = _run(source, out, "--from", "ros-trajectory", "--robot", "none")
    assert code == 1
    assert "not written: on whole ms the motion cannot keep within it:" in err
    assert "rad from the trajectory's points (j at 0 ms)" in err
    assert not out.exists()


GOOD = "joint_names: [a, b]\npoints:\n- positions: [0.1, 0.2]\n  time_from_start: {sec: 1}\n"
BAD = [
    ("a: [1\n", r"x.yaml:2:1: not YAML: expected ',' or ']'"),
    ("", r"x.yaml:1:1: empty: expected a trajectory_msgs/JointTrajectory"),
    (
        GOOD.replace("sec: 1", "sec: 99999999999999999999"),
        r"x.yaml:\d+:\d+: sec: 99999999999999999999 s is past the 2147483647 ms a motion holds",
    ),
    ("x: " + "[" * 5000 + "]" * 5000 + "\n", r"x.yaml:1:1: nested too deeply to read: expected"),
    (  # aliases that would print 9**6 names: the message shows a short beginning
        "a: &a [x, x, x, x, x, x, x, x, x]\n"
        + "".join(
            f"{n}: &{n} [{', '.join([f'*{p}'] * 9)}]\n"
            for p, n in zip("abcde", "bcdef", strict=True)
        )
        + "joint_names: *f\npoints: []\n",
        r"x.yaml:\d+:\d+: joint_names: expected a name, got .{1,60}$",
    ),
    ("points: []\n", r"x.yaml:1:1: expected a trajectory_msgs/JointTrajectory: joint_names and"),
    (GOOD + "---\n" + GOOD, r"x.yaml:6:1: a second message \(2 in all\): give one"),
    (GOOD.replace("[a, b]", "[a, a]"), r"x.yaml:1:18: joint_names: 'a' is given twice"),
    (GOOD.replace("[0.1, 0.2]", "[0.1]"), r"x.yaml:3:3: positions: 1 number for the 2 joint"),
    (
        GOOD.replace("[0.1, 0.2]", "[0.1, x]"),
        r"x.yaml:3:20: positions: expected a finite number, got 'x'",
    ),
    (
        GOOD.replace("[0.1, 0.2]", "[0.1, .nan]"),
        r"x.yaml:3:20: positions: expected a finite number, got nan",
    ),
    (GOOD.replace("positions", "position"), r"x.yaml:3:3: a point without positions"),
    (GOOD.replace("  time_from_start: {sec: 1}\n", ""), r"x.yaml:3:3: a point without time_fr"),
    (GOOD.replace("sec: 1", "sec: 1.5"), r"x.yaml:4:26: sec: expected a whole number >= 0"),
    (GOOD.replace("{sec: 1}", "1.0"), r"x.yaml:4:20: time_from_start: expected \{sec, nanosec\}"),
    (
        GOOD + "- positions: [0.1, 0.2]\n  time_from_start: {secs: 1}\n",
        r"x.yaml:6:3: point 2: time_from_start 1 s is not after point 1's 1 s: time_from_start "
        "must increase",
    ),
    (
        GOOD.replace("{sec: 1}", "{sec: 1, nanosec: 1000000000}"),
        r"x.yaml:4:\d+: nanosec: 1000000000 is not below 1e9",
    ),
]


@pytest.mark.parametrize(("text", "pattern"), BAD, ids=[b[1][8:40] for b in BAD])
def test_bad_input_is_one_line_with_its_position(tmp_path: Path, text: str, pattern: str) -> None:
    source, out = tmp_path / "x.yaml", tmp_path / "out.motion"
    source.write_text(text)
    code, err = _run(source, out, "--from", "ros-trajectory", "--robot", "none")
    assert code == 2
    assert err.count("\n") == 1 and "Traceback" not in err
    assert re.match(rf"motiontool: error: {re.escape(str(tmp_path))}/{pattern}", err), err
    assert not out.exists()
