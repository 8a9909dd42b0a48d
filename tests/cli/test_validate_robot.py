"""``validate`` against a robot, and ``motiontool robots``, through the command line."""

from __future__ import annotations

import json
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import CORPUS, DATA
from typer.testing import CliRunner

from motiontool.cli.app import app
from motiontool.kinematics import load_robot

runner = CliRunner()
SALUTE = DATA / "robots" / "salute.motion"
FIXED = DATA / "robots" / "salute_fixed.motion"
NAO_HASH = load_robot("nao").model_hash
V5_HASH = load_robot("nao-v5").model_hash
ANSI = re.compile(r"\x1b\[[0-9;]*m")


def invoke(*args: str) -> tuple[int, str, str]:
    result = runner.invoke(app, list(args))
    return result.exit_code, ANSI.sub("", result.stdout), result.stderr


def test_salute_with_twelve_values_is_rejected() -> None:
    code, out, _ = invoke("validate", str(SALUTE))
    assert code == 1
    # Webots rejects it: no robot check ran, and the robot line says so.
    assert out.splitlines()[0] == "robot: not checked against a robot: 1 file Webots rejects"
    assert f"{SALUTE}:2:47: error MT110: expected 11 values (one per joint), found 12" in out
    assert out.endswith("checked 1 file: 1 error, 0 warnings, 0 notes\n")


@pytest.mark.needs("kinematics")
def test_fixed_salute_passes_on_the_webots_nao() -> None:
    code, out, _ = invoke("validate", "--robot", "nao", str(FIXED))
    assert code == 0
    lines = out.splitlines()
    assert lines[0] == (
        f"robot: nao (20 ms controller step, model sha256 {NAO_HASH[:12]}); checks: limits,"
        " velocity, collision (overlaps under 15 mm ignored)"
    )
    assert [line for line in lines if f"{FIXED}:" in line] == [
        f"{FIXED}:2:1: warning MT206: first pose is at 1000 ms: Webots commands it at once"
        " (t = 0), so the robot jumps to it instead of moving there in 1000 ms",
        f"{FIXED}:2:1: warning MT307: HeadPitch body 'head' and RWristYaw body 'r_hand' overlap"
        " by 25.0 mm at 1000 ms (pose 'Pose1')",
    ]
    assert lines[-1] == "checked 1 file: 0 errors, 2 warnings, 0 notes"


@pytest.mark.needs("kinematics")
def test_fixed_salute_breaks_the_real_nao_elbow_limit_at_line_3() -> None:
    code, out, _ = invoke("validate", "--robot", "nao-v5", str(FIXED))
    assert code == 1
    assert out.splitlines()[0].startswith(
        f"robot: nao-v5 (20 ms controller step, model sha256 {V5_HASH[:12]})"
    )
    assert (
        f"{FIXED}:3:23: error MT302: RElbowRoll = 0 rad at 2000 ms is below its lower limit"
        " 0.0349066 rad by 0.0349066 rad\n"
        " 3 | 00:02:000,Pose2,1.5,0,0,0,0,0,0,0,0,0,0\n"
        "   |                       ^\n"
        "   = hint: the real robot's range is [0.0349066, 1.54462] rad (robot nao-v5)\n"
    ) in out
    assert f"{FIXED}:2:1: warning MT206: first pose is at 1000 ms" in out
    assert out.endswith(
        "checked 1 file: 1 error, 2 warnings, 0 notes; 1 fixable with --fix --unsafe-fixes\n"
    )


def test_auto_is_the_default_and_says_which_robot_per_file(tmp_path: Path) -> None:
    (tmp_path / "a.motion").write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,P,0\n")
    (tmp_path / "b.motion").write_bytes(b"#WEBOTS_MOTION,V1.0,elbow_joint\n0,P,0\n")
    (tmp_path / "c.motion").write_bytes(b"#WEBOTS_MOTION,V1.0,wheel\n0,P,0\n")
    code, out, _ = invoke("validate", "--checks", "limits", str(tmp_path))
    assert code == 0
    ur5e = load_robot("ur5e").model_hash
    assert out.splitlines()[0] == (
        f"robot: nao (1 file, 20 ms controller step, model sha256 {NAO_HASH[:12]}); ur5e (1 file,"
        f" 8 ms controller step, model sha256 {ur5e[:12]}); none for 1 file (MT901); checks:"
        " limits"
    )
    assert "info MT901: robot checks skipped" in out
    assert "hint: name the robot with --robot" in out


def test_a_typo_in_a_joint_name_keeps_the_robot_checks(tmp_path: Path) -> None:
    typo = tmp_path / "typo.motion"
    typo.write_bytes(
        b"#WEBOTS_MOTION,V1.0,RShoulderPitch,RShoulderRoll,RElbowYaw,RElbowRol\n"
        b"00:00:000,A,0,0,0,0\n00:00:500,B,-3,-0.3,1,2\n"
    )
    code, out, _ = invoke("validate", "--strict", str(typo))
    assert code == 1  # was 0: no robot detected, every robot check skipped
    assert out.startswith("robot: nao (20 ms controller step")
    assert (
        f"{typo}:1:60: warning MT301: unknown joint 'RElbowRol' for robot nao; did you mean"
        " 'RElbowRoll'?" in out
    )
    assert f"{typo}:3:13: error MT302: RShoulderPitch = -3 rad" in out  # the joints it has


def test_files_webots_rejects_are_listed_as_unchecked(tmp_path: Path) -> None:
    (tmp_path / "a.motion").write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,P,0\n")
    (tmp_path / "b.motion").write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,P,abc\n")
    (tmp_path / "c.motion").write_bytes(b"#WEBOTS_MOTION,V1.0,wheel\n0,P,0\n")
    code, out, _ = invoke("validate", "--checks", "limits", str(tmp_path))
    assert code == 1
    assert out.splitlines()[0] == (
        f"robot: nao (1 file, 20 ms controller step, model sha256 {NAO_HASH[:12]}); none for 1"
        " file (MT901); checks: limits; not checked against a robot: 1 file Webots rejects"
    )
    code, out, _ = invoke("validate", "--checks", "limits", "-f", "json", str(tmp_path))
    doc = json.loads(out)
    assert doc["robot"]["unchecked_files"] == [
        str(tmp_path / "b.motion"),
        str(tmp_path / "c.motion"),
    ]
    assert doc["robot"]["robots"][0]["files"] == [str(tmp_path / "a.motion")]


@pytest.mark.needs("kinematics")
def test_json_report_stamps_the_robot_and_its_model_hash() -> None:
    code, out, _ = invoke("validate", "--robot", "nao-v5", "--format", "json", str(FIXED))
    assert code == 1
    doc = json.loads(out)
    assert doc["stamps"]["model_sha256"] == V5_HASH
    assert doc["robot"] == {
        "requested": "nao-v5",
        "checks": ["limits", "velocity", "collision"],
        "collision_tolerance_mm": 15.0,
        "robots": [
            {
                "name": "nao-v5",
                "model_sha256": V5_HASH,
                "model_file": "nao.xml",
                "timestep_ms": 20,
                "files": [str(FIXED)],
            }
        ],
        "unchecked_files": [],
        "skipped_checks": [],  # Pinocchio is installed: collision ran
    }
    (diags,) = [f["diagnostics"] for f in doc["files"]]
    mt302 = next(d for d in diags if d["code"] == "MT302")
    assert (mt302["line"], mt302["column"], mt302["joint"], mt302["time_ms"]) == (
        3,
        23,
        "RElbowRoll",
        2000,
    )


@pytest.mark.needs("kinematics")
def test_sarif_carries_the_robot_too(tmp_path: Path) -> None:
    out_file = tmp_path / "r.sarif"
    code, _, _ = invoke(
        "validate", "--robot", "nao", "-f", "sarif", "-o", str(out_file), str(FIXED)
    )
    assert code == 0
    run = json.loads(out_file.read_text())["runs"][0]
    assert run["properties"]["stamps"]["model_sha256"] == NAO_HASH
    assert run["properties"]["robot"]["robots"][0]["name"] == "nao"
    assert {r["ruleId"] for r in run["results"]} == {"MT206", "MT307"}


@pytest.mark.needs("kinematics")
def test_robot_none_is_syntax_only_and_collision_tolerance_is_an_option() -> None:
    code, out, _ = invoke("validate", "--robot", "none", str(FIXED))
    assert code == 0
    assert out.splitlines()[0] == "robot: none (--robot none): Webots syntax checks only"
    assert "MT307" not in out
    code, out, _ = invoke("validate", "--collision-tolerance", "30", str(FIXED))
    assert code == 0 and "MT307" not in out and "(overlaps under 30 mm ignored)" in out


def test_timestep_sets_the_command_stream_step(tmp_path: Path) -> None:
    path = tmp_path / "gap.motion"
    path.write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,A,0\n500,B,*\n1000,C,1\n2000,D,1\n")
    _, out, _ = invoke("validate", "--timestep", "10", str(path))
    assert "then its target jumps by 1 rad at 1010 ms, within one 10 ms controller step" in out
    assert "(10 ms controller step" in out.splitlines()[0]


@pytest.mark.needs("kinematics")
@pytest.mark.parametrize(
    ("robot", "step"),
    [("nao", "20"), ("auto", "20"), ("ur5e", "8")],
)
def test_without_timestep_the_robot_s_step_is_the_step_checked(
    tmp_path: Path, robot: str, step: str
) -> None:
    """-t's help says the default is the robot's step (Nao: 20 ms), yet a file ending at
    2147483647 ms passed with exit 0, no MT115 and no MT209, while ``sample -t 20`` refused
    it: the pose times are checked at the robot's step, as with -t given."""
    joints = "HeadYaw" if robot != "ur5e" else "shoulder_pan_joint"
    path = tmp_path / "long.motion"
    path.write_bytes(f"#WEBOTS_MOTION,V1.0,{joints}\n0,P1,0\n2147483647,P2,0.5\n".encode())
    given = invoke("validate", "--no-cache", "--robot", robot, "-t", step, str(path))
    default = invoke("validate", "--no-cache", "--robot", robot, str(path))
    assert default == given
    code, out, _ = default
    assert code == 1
    assert f"error MT115: at a {step} ms time step the playback time passes" in out
    assert f"warning MT209: pose at 2147483647 ms is not a multiple of the {step} ms" in out
    assert out.endswith("checked 1 file: 1 error, 1 warning, 0 notes\n")
    code, out, _ = invoke("validate", "--no-cache", "--robot", "none", str(path))
    assert code == 0 and "MT115" not in out  # no robot: no step to check against


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (
            ["validate", "--checks", "limits,speed", "x.motion"],
            "motiontool: error: unknown check 'speed'; choose from limits, velocity, collision,"
            " balance or all\n",
        ),
        (
            ["validate", "--robot", "nao6", "x.motion"],
            "motiontool: error: unknown robot 'nao6'; did you mean 'nao'? choose auto, none, nao,"
            " nao-v5, ur5e, a .urdf/.xml path, or erd:<name>\n",
        ),
        (
            ["validate", "--robot", "ur5e", "--checks", "balance", "x.motion"],
            "motiontool: error: robot ur5e has no feet: the balance check needs a humanoid model"
            " with sole geometries (nao, nao-v5); leave 'balance' out of --checks\n",
        ),
        (
            ["validate", "--robot", "missing.urdf", "x.motion"],
            "motiontool: error: robot model file 'missing.urdf' not found\n",
        ),
        (
            ["robots", "show", "pepper"],
            "motiontool: error: unknown robot 'pepper'; choose nao, nao-v5, ur5e, a .urdf/.xml"
            " path, or erd:<name>\n",
        ),
        (
            ["robots", "export", "nao"],
            "motiontool: error: robots export: name an output with --mjcf FILE and/or --urdf"
            " FILE\n",
        ),
    ],
)
def test_usage_errors_exit_2_with_one_line(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, args: list[str], message: str
) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "x.motion").write_bytes(FIXED.read_bytes())
    assert invoke(*args) == (2, "", message)


def test_robots_lists_the_builtins_and_how_to_name_others() -> None:
    code, out, _ = invoke("robots")
    assert code == 0
    lines = out.splitlines()
    assert [line.split()[0] for line in lines[:3]] == ["nao", "nao-v5", "ur5e"]
    assert lines[0].startswith("nao     40 motors, floating base, 20 ms step: Webots Nao")
    assert lines[2].startswith("ur5e    6 motors, fixed base, 8 ms step")
    assert "--robot erd:<name>" in out and "--robot path/to/robot.urdf" in out


def test_robots_show_prints_limits_with_units() -> None:
    code, out, _ = invoke("robots", "show", "nao")
    assert code == 0
    rows = {line.split()[0]: line.split() for line in out.splitlines() if line.strip()}
    assert rows["joint"] == ["joint", "kind", "lower", "upper", "unit", "max", "velocity", "max",
                             "torque"]  # fmt: skip
    assert rows["RElbowRoll"] == ["RElbowRoll", "hinge", "0", "1.54462", "rad", "7.19407", "rad/s",
                                  "5", "N·m"]  # fmt: skip
    assert rows["model"][-1] == f"{NAO_HASH})"
    code, out, _ = invoke("robots", "show", "nao-v5")
    assert "one motor for  LHipYawPitch = RHipYawPitch; LPhalanx1..8; RPhalanx1..8" in out
    assert re.search(r"RElbowRoll\s+hinge\s+0.0349066\s+1.54462", out)


def test_robots_show_json() -> None:
    code, out, _ = invoke("robots", "show", "nao-v5", "--format", "json")
    assert code == 0
    doc = json.loads(out)
    assert doc["schema"] == "motiontool.robot" and doc["model_sha256"] == V5_HASH
    assert doc["stamps"]["model_sha256"] == V5_HASH
    assert len(doc["joints"]) == 40 and doc["default_timestep_ms"] == 20
    elbow = next(j for j in doc["joints"] if j["name"] == "RElbowRoll")
    assert elbow == {
        "name": "RElbowRoll",
        "kind": "hinge",
        "unit": "rad",
        "lower": 0.0349066,
        "upper": 1.54462,
        "max_velocity": 7.19407,
        "max_torque": 1.532,
    }
    assert doc["coupled_joints"][0] == ["LHipYawPitch", "RHipYawPitch"]
    assert len(doc["head_pitch_envelope"]) == 13


@pytest.mark.usefixtures("corpus")
def test_mt309_hint_names_the_mirror_command_and_ignore_option() -> None:
    dancing = CORPUS / "projects/robots/softbank/dancing_nao/motions"
    code, out, _ = invoke("validate", "--checks", "limits", str(dancing / "HandHighLeft.motion"))
    assert code == 0
    assert (
        "= hint: 'motiontool mirror HandHighRight.motion -o HandHighLeft.motion' writes the true"
        " mirror; if the motion is meant to be asymmetric, --ignore MT309"
    ) in out


@pytest.mark.needs("kinematics")
def test_robots_export_writes_model_files(tmp_path: Path) -> None:
    mjcf, urdf = tmp_path / "ur5e.xml", tmp_path / "ur5e.urdf"
    code, out, err = invoke("robots", "export", "ur5e", "--mjcf", str(mjcf), "--urdf", str(urdf))
    assert code == 0 and out == ""
    assert mjcf.read_bytes() == load_robot("ur5e").model_path.read_bytes()
    assert err.splitlines() == [
        f"motiontool: wrote {mjcf} (MJCF, {mjcf.stat().st_size} bytes, robot ur5e)",
        f"motiontool: wrote {urdf} (URDF, {urdf.stat().st_size} bytes, robot ur5e)",
    ]
    assert load_robot(str(urdf)).joints == load_robot("ur5e").joints
    code, _, err = invoke("robots", "export", str(urdf), "--mjcf", str(tmp_path / "u.xml"))
    assert code == 2 and "comes from a URDF file" in err and "export it with --urdf, or" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ur5e.urdf", "ur5e.xml"]  # no temp left
    code, _, err = invoke("robots", "export", "ur5e", "--mjcf", str(mjcf / "under-a-file.xml"))
    assert code == 2 and err.startswith("motiontool: error: cannot write")
    code, _, _ = invoke("robots", "export", "ur5e", "--mjcf", str(tmp_path / "new" / "x.xml"))
    assert code == 0 and (tmp_path / "new" / "x.xml").is_file()  # missing folders are made


def test_installed_script_lists_robots_and_validates_with_one() -> None:
    script = shutil.which("motiontool", path=str(Path(sys.executable).parent))
    assert script
    proc = subprocess.run(
        [script, "validate", "--robot", "nao-v5", str(FIXED)],
        capture_output=True,
        text=True,
        check=False,
    )
    assert proc.returncode == 1
    assert "error MT302: RElbowRoll = 0 rad at 2000 ms" in proc.stdout
    proc = subprocess.run([script, "robots"], capture_output=True, text=True, check=False)
    assert proc.returncode == 0 and proc.stdout.startswith("nao ")


@pytest.mark.needs("kinematics")
def test_self_collision_hint_names_the_robot_in_use(tmp_path: Path) -> None:
    fold = tmp_path / "fold.motion"
    fold.write_bytes(b"#WEBOTS_MOTION,V1.0,elbow_joint\n0,A,0\n1000,B,3.0\n")
    code, out, _ = invoke("validate", "--robot", "ur5e", "--checks", "collision", str(fold))
    assert (
        code == 0
        and "warning MT307: elbow_joint body 'forearm_link' and shoulder_pan_joint body 'shoulder_link' overlap"
        in out
    )
    hints = {line for line in out.splitlines() if "hint:" in line}
    assert len(hints) == 1  # the same hint under each of the overlapping pairs
    (hint,) = hints
    assert "Nao" not in hint  # was "(Webots' Nao has selfCollision off)" on every robot
    assert hint.endswith("the real ur5e does not")
