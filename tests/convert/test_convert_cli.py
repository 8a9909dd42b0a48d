"""``motiontool convert`` end to end: formats by ending, robot checks before anything is
written, one-line errors, never over the input."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT
from typer.testing import CliRunner

from motiontool.cli.app import app
from motiontool.motionfmt import read_bytes, read_motion, sample
from motiontool.motionfmt.convert import FORMATS

runner = CliRunner()
WAVE = ROOT / "motions" / "nao" / "wave_right.motion"


def _run(*args: str | Path) -> tuple[int, str, str]:
    result = runner.invoke(app, ["convert", *map(str, args)])
    return result.exit_code, result.stdout, result.stderr


def test_motion_to_csv_to_motion(tmp_path: Path) -> None:
    code, _, err = _run(WAVE, tmp_path / "w.csv")
    assert code == 0, err
    assert err.startswith(f"motiontool: wrote {tmp_path / 'w.csv'} (9 poses, 4 joints")
    assert "checked against robot nao: clean" in err
    code, _, err = _run(tmp_path / "w.csv", tmp_path / "w.motion")
    assert code == 0, err
    a, b = sample(read_motion(str(WAVE)), 20), sample(read_motion(str(tmp_path / "w.motion")), 20)
    assert np.array_equal(a.targets.view(np.int64), b.targets.view(np.int64))


def test_stdout_needs_a_format_and_gets_the_bytes(tmp_path: Path) -> None:
    code, _, err = _run(WAVE, "-")
    assert code == 2 and "cannot tell the format of '-' from its name; give --to" in err
    code, out, err = _run(WAVE, "-", "--to", "csv")
    assert code == 0, err
    assert out.startswith("time_ms,RShoulderPitch,")
    assert err.startswith("checked against robot nao: clean")  # no 'wrote' line for stdout


def test_unknown_joint_of_a_named_robot_is_one_error_at_its_cell(tmp_path: Path) -> None:
    src = tmp_path / "bad.csv"
    src.write_text("time_ms,HeadYw,HeadPitch\n0,0.1,0\n100,0.2,\n")
    code, _, err = _run(src, tmp_path / "out.motion", "--robot", "nao")
    assert code == 2
    assert err == (
        f"motiontool: error: {src}:1:9: unknown joint 'HeadYw' for robot nao; "
        "did you mean 'HeadYaw'?\n"
    )
    assert not (tmp_path / "out.motion").exists()


def test_a_limit_error_writes_nothing(tmp_path: Path) -> None:
    src = tmp_path / "fast.csv"
    src.write_text("time_ms,HeadYaw,HeadPitch\n0,0.1,0\n1000,3,0\n")
    code, _, err = _run(src, tmp_path / "out.motion")
    assert code == 1
    assert "not written: the motion fails the checks of robot nao:" in err
    assert f"{src}:3:6: error MT302: HeadYaw = 3 rad at 1000 ms is above its upper limit" in err
    assert not (tmp_path / "out.motion").exists()


def test_the_findings_that_refuse_an_export_are_grouped_as_validate_groups_them(
    tmp_path: Path,
) -> None:
    """A run of one code on one joint is one line with its count (the 26 MB random file got
    1.1 million lines, 96 s and 4.2 GB before; 40 lines in 3 s now)."""
    src = tmp_path / "over.csv"
    rows = [f"{40 * k},{3 if k % 5 else 0.1},0" for k in range(200)]
    src.write_text("time_ms,HeadYaw,HeadPitch\n" + "\n".join(rows) + "\n")
    code, _, err = _run(src, tmp_path / "out.motion")
    assert code == 1 and not (tmp_path / "out.motion").exists()
    over = [line for line in err.splitlines() if "MT302" in line]
    assert len(over) == 1, over
    assert "HeadYaw above its upper limit" in over[0] and "on 160 poses in 40 runs" in over[0]


def test_never_over_the_input(tmp_path: Path) -> None:
    src = tmp_path / "w.csv"
    assert _run(WAVE, src)[0] == 0
    before = src.read_bytes()
    code, _, err = _run(src, src, "--to", "csv")
    assert code == 2 and "is the input file" in err
    assert src.read_bytes() == before


def test_npz_round_trip_through_the_command(tmp_path: Path) -> None:
    assert _run(WAVE, tmp_path / "w.npz")[0] == 0
    code, _, err = _run(tmp_path / "w.npz", tmp_path / "w.motion")
    assert code == 0, err
    assert read_bytes((tmp_path / "w.motion").read_bytes(), "w").motion == read_motion(str(WAVE))


def test_bad_format_names_the_choices(tmp_path: Path) -> None:
    code, _, err = _run(WAVE, tmp_path / "x.out", "--to", "xls")
    assert code == 2 and "--to 'xls': unknown format; choose one of motion, csv, npz" in err


@pytest.mark.parametrize("fmt", [f.name for f in FORMATS if f.write is not None])
def test_an_empty_target_is_a_usage_error(fmt: str, tmp_path: Path) -> None:
    source = tmp_path / "wave.motion"
    source.write_bytes(WAVE.read_bytes())
    code, _, err = _run(source, "", "--to", fmt)
    assert code == 2
    assert err == (
        "motiontool: error: invalid value for 'target': an empty path names no file; "
        "give a file name, or '-' for stdout; see 'motiontool convert --help'\n"
    )
    assert [p.name for p in tmp_path.iterdir()] == ["wave.motion"]


def _robot_check(path: Path) -> object:
    """What the written file says of its robot check, read with each format's own reader
    (json, PyYAML's comments as text, numpy, mcap); None where the format has no place."""
    import json

    name = path.name
    if name.endswith(".naoqi.json"):
        return json.loads(path.read_text())["robot_check"]
    if name.endswith(".trajectory.yaml"):
        lines = [line for line in path.read_text().splitlines() if "robot check" in line]
        return lines[0].split("robot check: ", 1)[1] if lines else None
    if name.endswith(".npz"):
        with np.load(path, allow_pickle=False) as npz:
            return str(npz["robot_check"])
    if name.endswith(".mcap"):
        from mcap.reader import make_reader

        with path.open("rb") as f:
            found = {m.name: m.metadata for m in make_reader(f).iter_metadata()}
        return found["motiontool"]["robot_check"]
    return None


ENDINGS = {"motion": ".motion", "csv": ".csv", "npz": ".npz", "naoqi": ".naoqi.json"}
ENDINGS |= {"ros-trajectory": ".trajectory.yaml", "rosbag": ".mcap"}


@pytest.mark.parametrize(
    "fmt",
    [
        pytest.param(f, marks=pytest.mark.needs("ros")) if f == "rosbag" else f
        for f in sorted(ENDINGS)
    ],
)
def test_robot_none_is_one_rule_and_the_file_says_unchecked(tmp_path: Path, fmt: str) -> None:
    # --robot none: no robot checks, for every format; what has a place for it says so.
    out = tmp_path / f"wave{ENDINGS[fmt]}"
    code, _, err = _run(WAVE, out, "--robot", "none")
    assert code == 0, err
    assert "not checked against a robot: --robot none" in err
    assert _robot_check(out) in (None, "unchecked")
    if fmt in ("motion", "csv"):  # no place a reader skips: stderr alone says it
        return
    assert _robot_check(out) == "unchecked"
    code, _, err = _run(WAVE, out, "--robot", "nao-v5")
    assert code == 0, err
    assert _robot_check(out) == "nao-v5"


def test_urscript_needs_its_arm_even_unchecked(tmp_path: Path) -> None:
    arm = ROOT / "motions" / "ur5e" / "sorting.motion"
    code, _, err = _run(arm, tmp_path / "s.script", "--robot", "none")
    assert code == 2
    assert err == (
        "motiontool: error: --robot none: urscript sends the robot's joints in the robot's "
        "order; name the robot (--robot ur5e, or a model file)\n"
    )


def test_convert_shows_validates_findings_of_the_file(tmp_path: Path) -> None:
    # validate warns MT205 on a joint named twice; convert said "clean".
    src = tmp_path / "dup.motion"
    src.write_text(
        "#WEBOTS_MOTION,V1.0,HeadYaw,HeadYaw\n00:00:000,P1,0.1,0.1\n00:00:400,P2,0.2,0.2\n"
    )
    code, _, err = _run(src, tmp_path / "dup.csv", "--robot", "nao")
    assert code == 0, err
    line = (
        f"{src}:1:29: warning MT205: joint 'HeadYaw' is named twice (columns 1 and 2); both "
        "drive the same motor and the later column wins"
    )
    assert err.splitlines()[1:] == ["checked against robot nao: 1 finding", line]
    validated = runner.invoke(app, ["validate", "--robot", "nao", str(src)]).stdout
    assert line.replace("MT205: ", "MT205: [*] ") in validated


@pytest.mark.parametrize(
    "ending",
    [
        pytest.param(".mcap", marks=pytest.mark.needs("ros")),
        ".trajectory.yaml",
        ".naoqi.json",
        ".npz",
    ],
)
def test_an_unknown_joint_is_one_input_error_for_every_robot_export(
    tmp_path: Path, ending: str
) -> None:
    # A bag exited 1 ("not a motor" of its stream), a YAML 2: one exit code, the input's error.
    src = tmp_path / "unk.motion"
    src.write_text(
        "#WEBOTS_MOTION,V1.0,HeadYaw,HeadYw\n00:00:000,P1,0.1,0.1\n00:00:400,P2,0.2,0.2\n"
    )
    robot = [] if ending != ".npz" else ["--robot", "nao"]
    code, _, err = _run(src, tmp_path / f"unk{ending}", *robot)
    assert code == 2
    assert err.startswith(f"motiontool: error: {src}:1:29: unknown joint 'HeadYw' for robot nao")
    assert err.count("\n") == 1
    assert [p.name for p in tmp_path.iterdir()] == ["unk.motion"]


@pytest.mark.parametrize(
    ("data", "reason"),
    [
        (b"time_ms,HeadYaw\n0,0.1\n", "not a zip archive (an .npz is a zip of .npy arrays)"),
        (b"", "not a zip archive (an .npz is a zip of .npy arrays)"),
        (b"\x93NUMPY\x01\x00", "one .npy array, not an .npz (a zip of .npy arrays)"),
    ],
)
def test_a_file_that_is_no_npz_says_so(tmp_path: Path, data: bytes, reason: str) -> None:
    src = tmp_path / "m.npz"
    src.write_bytes(data)
    code, _, err = _run(src, tmp_path / "m.motion")
    assert code == 2
    assert err == f"motiontool: error: cannot read '{src}' as a .npz file: {reason}\n"
    assert "pickle" not in err


def test_a_lead_in_too_short_for_the_robot_is_refused_with_the_minimum(tmp_path: Path) -> None:
    # wave_right's first pose has RElbowRoll at 0.04 rad: from 0 rad (where the checks take a
    # motor to start) at nao-v5's maxVelocity of 7.19407 rad/s that takes 5.56 ms: 6 ms.
    out = tmp_path / "w.naoqi.json"
    for fmt, target in (("naoqi", out), ("ros-trajectory", tmp_path / "w.trajectory.yaml")):
        code, _, err = _run(WAVE, target, "--to", fmt, "--lead-in", "1", "--robot", "nao-v5")
        assert code == 2
        assert err == (
            "motiontool: error: --lead-in 1 ms: robot nao-v5 cannot reach the first pose in it "
            "from where its motors start (0 rad): RElbowRoll needs 5.56 ms at its maxVelocity "
            "7.19407 rad/s; give --lead-in 6 or more\n"
        )
    assert list(tmp_path.iterdir()) == []
    assert _run(WAVE, out, "--lead-in", "6")[0] == 0


def test_the_goal_names_the_controller_the_robots_driver_starts(tmp_path: Path) -> None:
    # UR's ROS 2 driver starts scaled_joint_trajectory_controller, not joint_trajectory_controller.
    arm = ROOT / "motions" / "ur5e" / "sorting.motion"
    assert _run(arm, tmp_path / "s.trajectory.yaml")[0] == 0
    text = (tmp_path / "s.trajectory.yaml").read_text()
    assert (
        "# ros2 action send_goal /scaled_joint_trajectory_controller/follow_joint_trajectory"
        in text
    )
    assert _run(WAVE, tmp_path / "w.trajectory.yaml")[0] == 0
    text = (tmp_path / "w.trajectory.yaml").read_text()
    assert "# ros2 action send_goal /joint_trajectory_controller/follow_joint_trajectory" in text
    readme = (ROOT / "docs" / "interchange.md").read_text()
    assert (
        "ros2 action send_goal /scaled_joint_trajectory_controller/follow_joint_trajectory"
        in readme
    )
