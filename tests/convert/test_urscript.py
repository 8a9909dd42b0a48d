"""URScript export: the script, parsed back, sends every target of Webots' command stream bit
for bit with servoj; the header moves slowly to the first pose; the arm's limits are checked
before anything is written."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT
from typer.testing import CliRunner

from motiontool.cli.app import app
from motiontool.cli.convert_checks import stream_findings
from motiontool.errors import MotionToolError
from motiontool.kinematics.robots import load_robot
from motiontool.motionfmt import read_bytes, sample
from motiontool.motionfmt.convert.base import ExportOptions, RobotStream
from motiontool.motionfmt.convert.urscript import number, write_urscript

UR = load_robot("ur5e")
ARM = sorted((ROOT / "motions" / "ur5e").glob("*.motion"))
OPTIONS = ExportOptions(timestep_ms=8, joint_order=UR.joint_names, robot="ur5e")
_CALL = re.compile(r"^  (servoj|movej)\(\[([^\]]*)\](.*)\)$")


def _calls(script: str) -> list[tuple[str, np.ndarray, str]]:
    """Every servoj/movej of the program: (name, targets, the other arguments)."""
    out = []
    for line in script.splitlines():
        m = _CALL.match(line)
        if m:
            out.append((m[1], np.array([float(x) for x in m[2].split(",")]), m[3]))
    return out


@pytest.mark.parametrize("path", ARM, ids=lambda p: p.name)
def test_servoj_targets_are_webots_stream_bit_for_bit(path: Path) -> None:
    motion = read_bytes(path.read_bytes(), str(path)).motion
    script = write_urscript(motion, OPTIONS).data.decode()
    calls = _calls(script)
    (name, home, args), servo = calls[0], calls[1:]
    assert name == "movej" and args == ", a=0.5, v=0.2"
    stream = sample(motion, 8)
    assert stream.commanded.all()  # every joint commanded at every step in these files
    order = [motion.column(j) for j in UR.joint_names]
    want = stream.targets[:, order]
    assert len(servo) == want.shape[0]
    got = np.array([targets for _, targets, _ in servo])
    assert np.array_equal(got.view(np.int64), want.view(np.int64))
    assert np.array_equal(home.view(np.int64), want[0].view(np.int64))
    assert {a for n, _, a in servo} == {", t=0.008, lookahead_time=0.1, gain=300"}
    assert script.endswith("  stopj(2.0)\nend\nmotiontool_motion()\n")  # runs as pasted


def test_keyframes_are_one_movej_each_with_its_time() -> None:
    motion = read_bytes(
        b"#WEBOTS_MOTION,V1.0,"
        + ",".join(UR.joint_names).encode()
        + b"\n0,A,0,-1,1,0,0,0\n500,B,0.1,-1,1,0,*,0\n1250,C,0.2,-1,1,0,0.5,0\n",
        "k",
    ).motion
    out = write_urscript(motion, ExportOptions(joint_order=UR.joint_names, keyframes=True))
    calls = _calls(out.data.decode())
    assert [(n, a) for n, _, a in calls] == [
        ("movej", ", a=0.5, v=0.2"),
        ("movej", ", t=0.5, r=0"),
        ("movej", ", t=0.75, r=0"),
    ]
    assert calls[1][1].tolist() == [0.1, -1, 1, 0, 0, 0]  # '*': the joint holds its target
    assert out.deviation is None


def test_numbers_read_back_exactly_and_have_no_exponent() -> None:
    for x in (1e-05, -0.0, 0.1, 2.0 / 3.0, -6.283185307179586, 1e-300, 123456789.123):
        text = number(x)
        assert "e" not in text and float(text) == x
        assert np.float64(float(text)).view(np.int64) == np.float64(x).view(np.int64)


@pytest.mark.parametrize(
    ("cells", "message"),
    [
        ("0,0,0,0,0", "no column for wrist_3_joint"),
        ("*,0,0,0,0,0", "shoulder_pan_joint has no target before 104 ms"),
    ],
)
def test_every_joint_needs_a_target_from_the_start(cells: str, message: str) -> None:
    names = UR.joint_names[: len(cells.split(","))]
    data = f"#WEBOTS_MOTION,V1.0,{','.join(names)}\n0,A,{cells}\n100,B,{cells.replace('*', '0')}\n"
    with pytest.raises(MotionToolError, match=message):
        write_urscript(read_bytes(data.encode(), "m").motion, OPTIONS)


def test_beyond_the_arm_limits_nothing_is_written(tmp_path: Path) -> None:
    src = tmp_path / "far.motion"
    src.write_text(
        "#WEBOTS_MOTION,V1.0,"
        + ",".join(UR.joint_names)
        + "\n0,A,0,0,0,0,0,0\n2000,B,0,0,3.5,0,0,0\n"
    )
    result = CliRunner().invoke(app, ["convert", str(src), str(tmp_path / "far.script")])
    assert result.exit_code == 1
    assert "error MT302: elbow_joint = 3.5 rad" in result.stderr
    assert not (tmp_path / "far.script").exists()


def test_the_stream_check_catches_a_jump_and_a_limit() -> None:
    targets = np.zeros((3, 6))
    targets[2, 0] = 0.1  # 0.1 rad in 8 ms: 12.5 rad/s > 3.14 rad/s
    targets[1, 2] = 3.3  # elbow beyond pi
    stream = RobotStream(UR.joint_names, np.array([0, 8, 16]), targets)
    found = stream_findings(stream, UR, "x")
    assert any("shoulder_pan_joint moves at 12.5 rad/s from 8 ms to 16 ms" in f for f in found)
    assert any(
        "elbow_joint = 3.3 rad at 8 ms is outside [-3.14159, 3.14159] rad" in f for f in found
    )


def test_the_command_reports_a_bit_identical_stream(tmp_path: Path) -> None:
    args = ["convert", str(ARM[0]), str(tmp_path / "a.script"), "--limits", "webots"]
    result = CliRunner().invoke(app, args)
    assert result.exit_code == 0, result.stderr
    assert "worst deviation from Webots' command stream: 0 rad (bit-identical)" in result.stderr
    assert "checked against robot ur5e: clean" in result.stderr
