"""``play`` on short motions: determinism, the report, the CLI, the Rerun recording."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest
from conftest import ROOT
from rrds import rrd_contents
from typer.testing import CliRunner

from motiontool.cli.app import app
from motiontool.sim import PlayOptions, play

runner = CliRunner()

NOD = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n00:00:000,A,0,0\n00:00:300,B,0.6,-0.3\n00:00:600,C,0,0\n"
# LShoulderRoll's motor range is [-0.314159, 1.32645]: -1 is clipped; NotAJoint is ignored.
OUT_OF_RANGE = b"#WEBOTS_MOTION,V1.0,LShoulderRoll,NotAJoint,HeadYaw\n0,A,0,1,0\n200,B,-1,1,0.1\n"
UR5E_MOTION = ROOT / "motions" / "ur5e" / "jog.motion"


@pytest.fixture
def nod(tmp_path: Path) -> Path:
    path = tmp_path / "nod.motion"
    path.write_bytes(NOD)
    return path


def column(batches: list[Any], name: str) -> list[Any]:
    """Every instance of a column over the chunks (a component row is a list of instances)."""
    values: list[Any] = []
    for batch in batches:
        if name in batch.schema.names:
            for row in batch.column(name).to_pylist():
                values += row if isinstance(row, list) else [row]
    return values


@pytest.mark.needs("sim")
def test_same_inputs_give_the_same_report_bit_for_bit(nod: Path) -> None:
    first = play([nod], robot="nao").to_json()
    second = play([nod], robot="nao").to_json()
    assert json.dumps(first) == json.dumps(second)
    assert first["clean"] and first["exit_code"] == 0


@pytest.mark.needs("sim")
def test_report_of_a_head_nod(nod: Path) -> None:
    report = play([nod], options=PlayOptions(hold_s=0.5), stamps={"motiontool": "x"})
    assert report.robot == "nao"
    assert report.simulated_s == pytest.approx(0.62 + 0.5)  # 31 steps + 25 held, 20 ms each
    assert report.control_steps == 56
    assert report.stamps["control_step_ms"] == 20
    assert report.stamps["physics_step_ms"] == pytest.approx(2.0)
    assert report.stamps["model_sha256"] and report.stamps["motiontool"] == "x"
    yaw = next(j for j in report.joints if j.name == "HeadYaw")
    assert yaw.commanded and yaw.limb == "Head" and yaw.unit == "rad"
    # The P controller lags a ramp of 2 rad/s by about v / P = 0.2 rad.
    assert 0.1 < yaw.max_error < 0.3
    assert yaw.velocity_cap_s == 0.0 and yaw.torque_cap_s == 0.0
    assert not next(j for j in report.joints if j.name == "LKneePitch").commanded
    assert report.base is not None and not report.base.fell
    assert abs(report.base.dx_m) < 0.005 and report.base.max_tilt_deg < 2.0
    assert all(f.max_displacement_m < 0.002 for f in report.feet)
    assert [f.name for f in report.feet] == ["LFsr", "RFsr"]


@pytest.mark.needs("sim")
def test_clipped_targets_and_ignored_joints_are_reported(tmp_path: Path) -> None:
    path = tmp_path / "clip.motion"
    path.write_bytes(OUT_OF_RANGE)
    rrd = tmp_path / "clip.rrd"
    report = play([path], robot="nao", options=PlayOptions(hold_s=0.2), rrd=rrd)
    roll = next(j for j in report.joints if j.name == "LShoulderRoll")
    # The ramp 0 -> -1 over 200 ms is below -0.314159 at the steps 80, 100, ..., 200 ms (7),
    # then held for 0.2 s (10 steps): 17 steps of 20 ms.
    assert roll.target_clipped_s == pytest.approx(17 * 0.02)
    assert report.ignored_joints == ["NotAJoint"]
    events = column(rrd_contents(rrd)["/events"], "TextLog:text")
    assert any("LShoulderRoll target" in e and "clipped" in e for e in events)


def _report(**changes: Any) -> Any:
    from dataclasses import replace

    from motiontool.sim import PlayReport

    base = PlayReport(
        robot="nao",
        files=[],
        options={},
        stamps={},
        simulated_s=1.0,
        control_steps=50,
        joints=[],
        base=None,
        feet=[],
        self_collisions=[],
        scene_contacts=[],
        ground_contacts=[],
        warnings={"bad_qacc": 0},
    )
    return replace(base, **changes)


def test_a_simulator_warning_makes_a_run_unclean_and_an_error_exits_2() -> None:
    assert _report().clean and _report().exit_code == 0
    warned = _report(warnings={"bad_qacc": 3})
    assert not warned.clean and warned.exit_code == 1
    assert warned.to_json()["reason"] == "MuJoCo warning bad_qacc x3"
    stopped = _report(error="simulation stopped at step 7: boom")
    assert stopped.exit_code == 2 and stopped.to_json()["error"].endswith("boom")


@pytest.mark.needs("sim")
def test_sequence_plays_files_one_after_another(nod: Path) -> None:
    report = play([nod, nod], options=PlayOptions(hold_s=0.0))
    assert [(f.start_s, f.steps) for f in report.files] == [(0.0, 31), (pytest.approx(0.62), 31)]
    assert report.simulated_s == pytest.approx(1.24)


@pytest.mark.needs("sim")
def test_ur5e_stands_on_its_box_and_plays_clean() -> None:
    report = play([UR5E_MOTION], robot="ur5e", options=PlayOptions(hold_s=0.0))
    assert report.base is None and report.feet == []
    assert report.stamps["control_step_ms"] == 8
    assert report.clean, report.problems
    assert max(j.rms_error for j in report.joints) < 0.5


@pytest.mark.needs("sim")
def test_ur5e_arm_swung_into_its_box_is_a_scene_contact(tmp_path: Path) -> None:
    # At zero the UR5e's arm is stretched out horizontally; +2 rad of shoulder lift swings it
    # down through the top of the 0.6 m box it stands on.
    path = tmp_path / "swing.motion"
    path.write_bytes(b"#WEBOTS_MOTION,V1.0,shoulder_lift_joint\n0,A,0\n1000,B,2\n")
    report = play([path], robot="ur5e", options=PlayOptions(hold_s=0.2))
    assert [(c.body_a, c.body_b) for c in report.scene_contacts] == [
        ("upper_arm_link", "wooden_box")
    ]
    assert report.exit_code == 1
    lift = next(j for j in report.joints if j.name == "shoulder_lift_joint")
    assert lift.torque_cap_s > 0.5  # pushing against the box at maxTorque


@pytest.mark.needs("sim")
def test_ur5e_folding_onto_itself_is_a_self_collision(tmp_path: Path) -> None:
    # Webots' UR5e collides with itself (selfCollision TRUE): its links touch, they do not
    # pass through each other, so any depth counts (no tolerance as for the Nao's overlaps).
    path = tmp_path / "fold.motion"
    path.write_bytes(
        b"#WEBOTS_MOTION,V1.0,shoulder_lift_joint,elbow_joint\n0,A,-1.5,0\n1500,B,-1.5,3.1\n"
    )
    report = play([path], robot="ur5e", options=PlayOptions(hold_s=0.3))
    pairs = {(c.body_a, c.body_b) for c in report.self_collisions}
    assert ("upper_arm_link", "wrist_2_link") in pairs
    assert all(c.max_depth_m < 0.015 for c in report.self_collisions)
    assert report.scene_contacts == [] and report.exit_code == 1


@pytest.mark.needs("sim")
def test_lying_front_needs_a_free_flying_robot() -> None:
    from motiontool.motionfmt import MotionToolError

    with pytest.raises(MotionToolError, match="free-flying"):
        play([UR5E_MOTION], robot="ur5e", options=PlayOptions(start="lying-front"))


@pytest.mark.needs("sim", "rerun")
def test_cli_writes_json_and_rrd(nod: Path, tmp_path: Path) -> None:
    json_path, rrd_path = tmp_path / "run.json", tmp_path / "run.rrd"
    result = runner.invoke(
        app,
        ["play", str(nod), "--headless", "--json", str(json_path), "--rrd", str(rrd_path)],
    )
    assert result.exit_code == 0, result.output
    assert "result: clean" in result.stdout
    assert "HeadYaw" in result.stdout
    doc = json.loads(json_path.read_text())
    assert doc["schema"] == "motiontool.play" and doc["schema_version"] == 1
    assert doc["exit_code"] == 0 and doc["robot"] == "nao"
    assert {"motiontool", "mujoco", "pinocchio", "rerun", "model_sha256", "seed"} <= set(
        doc["stamps"]
    )
    assert doc["stamps"]["control_step_ms"] == 20
    assert set(doc["base"]) >= {"dx_m", "dy_m", "yaw_change_deg", "max_tilt_deg", "fell"}
    assert all(j["unit"] == "rad" for j in doc["joints"])

    contents = rrd_contents(rrd_path)
    steps = doc["control_steps"]
    commanded = contents["/joints/Head/HeadYaw/commanded"]
    assert len(column(commanded, "Scalars:scalars")) == steps
    times = column(commanded, "sim_time")
    assert len(times) == steps and times == sorted(times)
    assert len(column(contents["/joints/Head/HeadYaw/measured"], "Scalars:scalars")) == steps + 1
    assert column(contents["/joints/Head/HeadYaw/upper"], "Scalars:scalars") == [2.08567] * 2
    torso = contents["/world/robot/torso"]
    assert len(column(torso, "Transform3D:translation")) == steps + 1
    assert column(contents["/world/robot/torso/capsules"], "Capsules3D:radii") == [
        pytest.approx(0.055)
    ]
    assert "/world/base_trail" in contents and "/world/scene/world/planes" in contents
    events = column(contents["/events"], "TextLog:text")
    assert any("start nod.motion" in e for e in events)
    stamps = contents["/__properties/stamps"]
    assert column(stamps, "mujoco") == [doc["stamps"]["mujoco"]]
    assert column(stamps, "model_sha256") == [doc["stamps"]["model_sha256"]]

    from rerun.chunk import RrdReader

    assert RrdReader(rrd_path).blueprints(), "no blueprint in the recording"


@pytest.mark.needs("sim")
def test_cli_json_and_rrd_are_written_when_the_file_is_rejected(tmp_path: Path) -> None:
    bad = tmp_path / "bad.motion"
    bad.write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,A,abc\n")
    json_path, rrd_path = tmp_path / "run.json", tmp_path / "run.rrd"
    result = runner.invoke(
        app, ["play", str(bad), "--headless", "--json", str(json_path), "--rrd", str(rrd_path)]
    )
    assert result.exit_code == 2
    assert "bad.motion:2:" in result.stderr
    doc = json.loads(json_path.read_text())
    assert doc["exit_code"] == 2 and "bad.motion:2:" in doc["error"]
    events = column(rrd_contents(rrd_path)["/events"], "TextLog:text")
    assert "bad.motion:2:" in events[0]


@pytest.mark.needs("sim")
def test_cli_unknown_robot_lists_choices(nod: Path) -> None:
    result = runner.invoke(app, ["play", str(nod), "--headless", "--robot", "nao7"])
    assert result.exit_code == 2
    assert "choose" in result.stderr


# Joint names of the Robotis Darwin-OP: none is a motor of the Nao.
DARWIN = b"#WEBOTS_MOTION,V1.0,ShoulderR,ArmUpperR\n0,A,0,0\n200,B,0.3,0.2\n"


@pytest.mark.needs("sim")
def test_a_motion_with_no_motor_of_the_robot_is_not_a_clean_run(tmp_path: Path) -> None:
    path = tmp_path / "darwin.motion"
    path.write_bytes(DARWIN)
    json_path = tmp_path / "run.json"
    result = runner.invoke(
        app,
        ["play", str(path), "--headless", "--robot", "nao", "--hold", "0.1", "--json",
         str(json_path)],
    )  # fmt: skip
    assert result.exit_code == 1, result.output  # was 0: every column ignored, "clean"
    reason = "no joint of this motion is a motor of nao: nothing was played"
    assert f"result: {reason}" in result.stdout
    doc = json.loads(json_path.read_text())
    assert (doc["clean"], doc["exit_code"], doc["reason"]) == (False, 1, reason)
    assert doc["unplayed_files"] == [str(path)]
    # A motion that has one motor of the robot still plays (the other column is ignored).
    nod = tmp_path / "half.motion"
    nod.write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw,ArmUpperR\n0,A,0,0\n200,B,0.3,0.2\n")
    report = play([nod], robot="nao", options=PlayOptions(hold_s=0.1))
    assert report.clean and report.unplayed_files == [] and report.ignored_joints == ["ArmUpperR"]


@pytest.mark.needs("sim")
def test_warning_names_come_from_mujoco_itself() -> None:
    import mujoco

    from motiontool.sim._mujoco import warning_label, warning_labels

    members = {
        int(v): n for n, v in mujoco.mjtWarning.__members__.items() if n.startswith("mjWARN_")
    }
    labels = warning_labels()
    assert sorted(labels) == sorted(members) == list(range(len(members)))
    assert labels[int(mujoco.mjtWarning.mjWARN_BADQACC)] == "bad_qacc"
    assert labels[int(mujoco.mjtWarning.mjWARN_CONTACTFULL)] == "contact_full"
    assert labels[int(mujoco.mjtWarning.mjWARN_CNSTRFULL)] == "constraint_full"
    assert labels[int(mujoco.mjtWarning.mjWARN_INERTIA)] == "inertia"
    assert warning_label("mjWARN_SOMETHINGNEW") == "somethingnew"  # a later MuJoCo's warning
    report = play([UR5E_MOTION], robot="ur5e", options=PlayOptions(hold_s=0.0))
    assert list(report.warnings) == list(labels.values())


@pytest.mark.needs("sim")
def test_ur5e_joints_are_grouped_as_arm_and_wrist(tmp_path: Path) -> None:
    from motiontool.cli._plotting import limb_groups
    from motiontool.kinematics import load_robot

    rrd = tmp_path / "jog.rrd"
    report = play([UR5E_MOTION], robot="ur5e", options=PlayOptions(hold_s=0.0), rrd=rrd)
    limbs = {j.name: j.limb for j in report.joints}
    # Before: every joint under "shoulder_link", the one child of the base.
    assert limbs == {
        "shoulder_pan_joint": "arm",
        "shoulder_lift_joint": "arm",
        "elbow_joint": "arm",
        "wrist_1_joint": "wrist",
        "wrist_2_joint": "wrist",
        "wrist_3_joint": "wrist",
    }
    paths = set(rrd_contents(rrd))
    assert "/joints/arm/elbow_joint/commanded" in paths
    assert "/joints/wrist/wrist_3_joint/measured" in paths
    ur5e = load_robot("ur5e")
    groups = limb_groups(ur5e.joint_names[::-1], "ur5e", ur5e.joint_names)
    assert groups == [
        (limb, [j for j in ur5e.joint_names if limbs[j] == limb]) for limb in ("arm", "wrist")
    ]


@pytest.mark.needs("sim")
def test_play_takes_motion_objects_and_reports_them_as_the_files(nod: Path) -> None:
    from motiontool.sim import read_playable

    from_file = play([nod], robot="nao", options=PlayOptions(hold_s=0.1)).to_json()
    motion = read_playable(nod)
    from_motion = play([motion], names=[str(nod)], robot="nao", options=PlayOptions(hold_s=0.1))
    assert json.dumps(from_motion.to_json()) == json.dumps(from_file)  # bit for bit
    unnamed = play([motion, nod], robot="nao", options=PlayOptions(hold_s=0.0))
    assert [f.path for f in unnamed.files] == ["<motion 1>", str(nod)]
    from motiontool.motionfmt import MotionToolError

    with pytest.raises(MotionToolError, match="1 names for 2 motions"):
        play([motion, motion], names=["a"], robot="nao")


@pytest.mark.needs("sim")
def test_cli_warns_once_per_ignored_joint(tmp_path: Path) -> None:
    # A subprocess: in-process, pytest's log capture hides the library's log line, which Python
    # printed on stderr too (before: the warning twice, once from the log, once from the CLI).
    import subprocess
    import sys

    path = tmp_path / "clip.motion"
    path.write_bytes(OUT_OF_RANGE)
    code = (
        "from motiontool.cli.app import app\n"
        f"app(['play', {str(path)!r}, '--headless', '--hold', '0'], prog_name='motiontool')\n"
    )
    proc = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=False, timeout=120
    )
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr == "motiontool: warning: joint 'NotAJoint' is not a motor of nao: ignored\n"
    assert "ignored (not motors of the robot): NotAJoint" in proc.stdout


@pytest.mark.needs("sim")
def test_geoms_are_classed_with_an_enum(nod: Path) -> None:
    from motiontool.kinematics import load_robot
    from motiontool.sim._mujoco import GeomClass, build_scene

    scene = build_scene(load_robot("nao"), 20)
    classes = [GeomClass(int(c)) for c in scene.geom_class]
    assert classes[scene.model.geom("floor").id] is GeomClass.FLOOR
    assert [classes[g] for g in scene.foot_geoms.tolist()] == [GeomClass.FOOT] * 2
    assert GeomClass.ROBOT in classes and GeomClass.SCENE not in classes  # the Nao: no box
    box = build_scene(load_robot("ur5e"), 8)
    assert box.geom_class[box.model.geom("wooden_box").id] == GeomClass.SCENE
