"""An arm's end effector in ``play``: keyframe poses (MuJoCo FK, checked against Pinocchio's),
lags, the deviation from the commanded path, the tool trail in the recording, ``ee``
expectations, and the UR5e sorting demo reaching its picks and places."""

from __future__ import annotations

import hashlib
import json
import math
import re
import tomllib
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from conftest import ROOT
from rrds import rrd_contents
from typer.testing import CliRunner

from motiontool.cli.app import app
from motiontool.kinematics import load_robot
from motiontool.kinematics.robots import JointSpec, RobotSpec
from motiontool.kinematics.ur5e_tasks import flange_pose, sorting_expectations, sorting_spots
from motiontool.sim import PlayOptions, PlayReport, play
from motiontool.sim import _mujoco as mj
from motiontool.sim.expect import ExpectationError, apply_expectations, evaluate, parse_expectation

runner = CliRunner()

UR5E_JOINTS = (
    "shoulder_pan_joint",
    "shoulder_lift_joint",
    "elbow_joint",
    "wrist_1_joint",
    "wrist_2_joint",
    "wrist_3_joint",
)
# Three keyframes: the start pose, the arm raised, then turned (the hold lets it settle).
ARM = (
    b"#WEBOTS_MOTION,V1.0," + ",".join(UR5E_JOINTS).encode() + b"\n"
    b"00:00:000,start,0,0,0,0,0,0\n"
    b"00:00:400,up,0,-0.5,0.5,0,0,0\n"
    b"00:00:800,turn,0.4,-0.5,0.5,0,*,0\n"
)
NOD = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n00:00:000,A,0,0\n00:00:200,B,0.3,-0.2\n"
SORTING = ROOT / "motions" / "ur5e" / "sorting.motion"


def column(batches: list[Any], name: str) -> list[Any]:
    """Every row of a column over the chunks, in order (a row: that frame's instances)."""
    return [row for b in batches if name in b.schema.names for row in b.column(name).to_pylist()]


@pytest.fixture(scope="module")
def arm_motion(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("arm") / "raise_turn.motion"
    path.write_bytes(ARM)
    return path


@pytest.fixture(scope="module")
def arm_run(arm_motion: Path, tmp_path_factory: pytest.TempPathFactory) -> tuple[PlayReport, Path]:
    rrd = tmp_path_factory.mktemp("rrd") / "arm.rrd"
    report = play([arm_motion], robot="ur5e", options=PlayOptions(hold_s=0.8), rrd=rrd)
    return report, rrd


@pytest.mark.needs("sim")
def test_keyframe_poses_are_the_forward_kinematics_of_the_targets(
    arm_run: tuple[PlayReport, Path],
) -> None:
    report, _rrd = arm_run
    ee = report.end_effector
    assert ee is not None and (ee.frame, ee.kind) == ("tool_slot", "site")
    assert [(k.name, k.time_s) for k in ee.keyframes] == [
        ("start", 0.0),
        ("up", 0.4),
        ("turn", 0.8),
    ]
    # MuJoCo's FK of the keyframe targets == Pinocchio's FK of the same model (the IK's frame,
    # the robot on its 0.6 m box); 'turn' holds wrist_2 at its previous target ('*').
    ur5e = load_robot("ur5e")
    rows = {"start": [0.0] * 6, "up": [0, -0.5, 0.5, 0, 0, 0], "turn": [0.4, -0.5, 0.5, 0, 0, 0]}
    for k in ee.keyframes:
        pose = flange_pose(ur5e, dict(zip(UR5E_JOINTS, rows[k.name], strict=True)))
        np.testing.assert_allclose(k.commanded_position_m, pose.position, atol=1e-6)
        measured_minus_fk = np.subtract(k.measured_position_m, k.commanded_position_m)
        assert k.position_error_mm == pytest.approx(np.linalg.norm(measured_minus_fk) * 1000)
        assert abs(math.fsum(v * v for v in k.commanded_quat_wxyz) - 1.0) < 1e-9
    start, up, turn = ee.keyframes
    assert start.position_error_mm < 1e-6 and start.lag_ms == 0.0  # it starts there
    # The P controller lags behind: at its time, 'up' is not there yet; the hold lets 'turn'
    # settle, so it is reached, some time after its keyframe time.
    assert up.position_error_mm > 10.0
    assert turn.lag_ms is not None and turn.lag_ms > 0
    assert all(k.lag_ms is None or k.lag_ms >= 0 for k in ee.keyframes)
    t_reached = turn.time_s + turn.lag_ms / 1000.0
    i = ee.trail_time_s.index(min(ee.trail_time_s, key=lambda t: abs(t - t_reached - 0.3)))
    assert math.dist(ee.trail_position_m[i], turn.commanded_position_m) < 1e-3  # stays there
    assert 10.0 < ee.max_deviation_mm < 200.0
    assert 0.0 < ee.max_deviation_at_s <= report.simulated_s


@pytest.mark.needs("sim")
def test_the_report_round_trips_through_json_and_the_batch_judges_ee_from_it(
    arm_run: tuple[PlayReport, Path],
) -> None:
    report, _rrd = arm_run
    doc = json.loads(json.dumps(report.to_json()))
    again = PlayReport.from_json(doc)
    assert again.end_effector == report.end_effector
    judged = apply_expectations(doc, ["ee_error[turn]<200mm", "ee[start]=[0,0,0]±1mm"])
    assert [e["passed"] for e in judged["expectations"]] == [True, False]
    assert judged["expectations"][1]["point_m"] == [0.0, 0.0, 0.0]
    assert judged["exit_code"] == 1


@pytest.mark.needs("sim")
def test_ee_expectations_pass_or_fail_with_their_reason(arm_run: tuple[PlayReport, Path]) -> None:
    report, _rrd = arm_run
    ee = report.end_effector
    assert ee is not None
    turn = ee.keyframes[-1]
    x, y, z = turn.commanded_position_m
    sx, sy, sz = ee.keyframes[0].commanded_position_m
    at = f"{ee.trail_time_s[-1]:.3f}s"
    results = evaluate(
        [
            f"ee[start]=[{sx:.6f},{sy:.6f},{sz:.6f}]±1mm",  # where it starts
            f"ee@{at}=[{x:.6f},{y:.6f},{z:.6f}]±2mm",  # at the end
            "ee[turn]=[0.4,0.1,0.3]±20mm",  # unreachable: far from where it goes
            "ee_lag[up]<1000ms",  # a keyframe passed through, never within 1 mm
            "ee_error[turm]<5mm",  # a misspelt keyframe
            "ee@99s=[0,0,0]±1",  # past the end of the run
            "ee_deviation<1mm",
        ],
        report,
    )
    assert [r.passed for r in results] == [True, True, False, False, False, False, False]
    reasons = [r.reason for r in results]
    assert reasons[2].startswith("expected ee[turn] = [0.4, 0.1, 0.3] ± 0.02 m, measured [")
    assert reasons[2].endswith("mm away")
    assert "never came within 1 mm of up (0.40 s)" in reasons[3]
    assert reasons[4].endswith("no keyframe named 'turm' was reached; did you mean 'turn'?")
    assert "99 s is outside the run" in reasons[5]
    assert reasons[6].startswith("expected ee_deviation < 1 mm, measured ")
    assert all("\n" not in r for r in reasons)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("ee[a]<5", "ee is a position: write ee[KEYFRAME] or ee@T"),
        ("ee=[1,2,3]±1", "ee needs one keyframe [KEYFRAME] or one time @T"),
        ("ee[a]=[1,2]±1mm", "expected a point of 3 numbers [x, y, z], found [1,2]"),
        ("ee[a]=[1,2,3]±5%", "a point's tolerance is a distance"),
        ("ee_lag<5deg", "unit 'deg' does not fit ee_lag, which is in ms"),
        ("dx@1s<1", "dx takes no time"),
        ("ee_error<[1,2,3]", "ee_error takes a number, not [x, y, z]"),
    ],
)
def test_bad_ee_expectations_are_one_line_errors(text: str, message: str) -> None:
    with pytest.raises(ExpectationError, match=re.escape(message)):
        parse_expectation(text)


def test_ee_point_is_in_metres_and_the_tolerance_unit_is_its_own() -> None:
    e = parse_expectation("ee[place_1]=[0.55,0,0.70]±5mm")
    assert (e.keyframe, e.point, e.tolerance) == ("place_1", (0.55, 0.0, 0.7), 0.005)
    assert parse_expectation("ee@2500ms=[550,0,700]mm±0.5cm").at_s == 2.5
    assert parse_expectation("ee_lag<0.2s").value == 200.0  # ee_lag is in ms


@pytest.mark.needs("sim")
def test_recording_logs_the_tool_trail_as_the_report_has_it(
    arm_run: tuple[PlayReport, Path],
) -> None:
    report, rrd = arm_run
    ee = report.end_effector
    assert ee is not None
    contents = rrd_contents(rrd)
    assert {"/world/tool", "/world/tool/trail", "/world/tool/keyframes"} <= set(contents)
    rows = column(contents["/world/tool/trail"], "LineStrips3D:strips")
    assert all(len(row) == 1 for row in rows)  # one strip a frame
    strips = [row[0] for row in rows]
    assert len(strips) == len(ee.trail_time_s)  # one growing strip per trail sample
    assert [len(s) for s in strips] == list(range(1, len(ee.trail_time_s) + 1))
    np.testing.assert_allclose(strips[-1], ee.trail_position_m, atol=1e-6)  # float32
    (labels,) = column(contents["/world/tool/keyframes"], "Points3D:labels")
    assert labels == ["start", "up", "turn"]
    points = column(contents["/world/tool"], "Points3D:positions")
    assert len(points) == report.control_steps + 1  # every frame


@pytest.mark.needs("sim")
def test_cli_prints_the_keyframe_table_and_the_schema_takes_the_json(
    arm_motion: Path, tmp_path: Path
) -> None:
    from motiontool.cli import schemas

    json_path = tmp_path / "arm.json"
    result = runner.invoke(
        app, ["play", str(arm_motion), "--headless", "--hold", "0.8", "--json", str(json_path)]
    )
    assert result.exit_code == 0, result.output
    lines = result.output.splitlines()
    head = next(i for i, line in enumerate(lines) if line.startswith("end effector tool_slot:"))
    assert lines[head + 1].split() == ["keyframe", "time", "error", "lag"]
    assert lines[head + 2].split() == ["start", "0.000", "s", "0.0", "mm", "0", "ms"]
    assert lines[head + 3].split()[:2] == ["up", "0.400"]
    doc = json.loads(json_path.read_text())
    assert doc["end_effector"]["frame"] == "tool_slot"
    import jsonschema

    jsonschema.validate(doc, schemas.load("play"))


@pytest.mark.needs("sim")
def test_a_floating_base_has_no_end_effector_and_ee_is_not_measured(tmp_path: Path) -> None:
    nod = tmp_path / "nod.motion"
    nod.write_bytes(NOD)
    json_path = tmp_path / "nod.json"
    result = runner.invoke(
        app,
        [
            *("play", str(nod), "--headless", "--hold", "0", "--json", str(json_path)),
            *("--expect", "ee_error<5mm"),
        ],
    )
    assert result.exit_code == 1
    reason = "expected ee_error < 5 mm, not measured: nao has a free-flying base: no end effector"
    assert f"FAIL {reason} is measured" in result.output
    doc = json.loads(json_path.read_text())
    assert doc["end_effector"] is None
    assert "end effector tool" not in result.output  # no keyframe table


ONE_SITE = """<mujoco model="arm2">
  <compiler angle="radian" autolimits="true"/>
  <worldbody>
    <body name="base">
      <geom type="box" size=".05 .05 .05" pos="0 0 .05"/>
      <body name="link1" pos="0 0 0.2">
        <joint name="j1" type="hinge" axis="0 0 1" range="-3 3"/>
        <geom type="capsule" fromto="0 0 0 0.2 0 0" size="0.01" mass="1"/>
        <body name="link2" pos="0.2 0 0">
          <joint name="j2" type="hinge" axis="0 0 1" range="-3 3"/>
          <geom type="capsule" fromto="0 0 0 0.2 0 0" size="0.01" mass="1"/>
          {site}
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


@pytest.mark.needs("sim")
@pytest.mark.parametrize(
    ("site", "tool"),
    [
        ('<site name="TCP" pos="0.2 0 0"/>', ("TCP", "site")),  # a site named like a tool
        ('<site name="marker" pos="0.1 0 0"/>', ("link2", "body")),  # else the last body
    ],
)
def test_the_tool_of_a_generic_arm(tmp_path: Path, site: str, tool: tuple[str, str]) -> None:
    path = tmp_path / "arm2.xml"
    path.write_text(ONE_SITE.format(site=site))
    joints = tuple(JointSpec(n, -3.0, 3.0, 2.0, 10.0) for n in ("j1", "j2"))
    spec = RobotSpec("arm2", path, hashlib.sha256(path.read_bytes()).hexdigest(), joints, 20)
    scene = mj.build_scene(spec, 20)
    assert scene.tool is not None and scene.tool[:2] == tool
    pos, _quat = mj.tool_poses(scene, np.array([[0.0, 0.0], [math.pi / 2, 0.0]]))
    reach = 0.4 if tool[1] == "site" else 0.2  # the site at the tip, link2's origin mid-way
    np.testing.assert_allclose(pos[:, :2], [[reach, 0.0], [0.0, reach]], atol=1e-9)


@pytest.mark.needs("sim")
def test_the_sorting_demo_reaches_every_pick_and_place() -> None:
    # motions.toml states them as kinematics/ur5e_tasks.py does.
    sidecar = tomllib.loads((ROOT / "motions" / "motions.toml").read_text())
    assert sidecar["sorting"]["expect"] == sorting_expectations()
    spots = sorting_spots()
    assert "ee[grasp_1]=[0.55,0,0.8]±5mm" in sorting_expectations()
    assert spots["pick"].position.tolist() == [0.55, 0.0, 0.8]
    report = play([SORTING], robot="ur5e")
    report.expectations = evaluate(sorting_expectations(), report)
    assert report.clean, report.problems
    ee = report.end_effector
    assert ee is not None
    for n in (1, 2, 3):
        (grasp,) = ee.at(f"grasp_{n}")
        assert math.dist(grasp.measured_position_m, spots["pick"].position) < 0.001
    # Falsifiable: the same checks against the wrong bin fail.
    wrong = evaluate(["ee[release_1]=[0,-0.55,0.7]±5mm"], report)
    assert not wrong[0].passed and "1100" in wrong[0].reason


@pytest.mark.needs("sim")
@pytest.mark.parametrize("motion", ["sorting", "jog"])
def test_the_largest_deviation_is_at_least_every_keyframe_error(motion: str) -> None:
    # A keyframe's error is the tool against its commanded pose at its frame: the deviation from
    # the command stream compares the same frame with the same command, so it cannot be
    # smaller (80.5 mm against a keyframe's 87.3 mm, one step apart).
    report = play([ROOT / "motions" / "ur5e" / f"{motion}.motion"], robot="ur5e")
    ee = report.end_effector
    assert ee is not None and ee.keyframes
    worst = max(ee.keyframes, key=lambda k: k.position_error_mm)
    assert ee.max_deviation_mm >= worst.position_error_mm > 10.0


@pytest.mark.needs("sim")
def test_keyframe_times_follow_loops_and_reverse(arm_motion: Path) -> None:
    # A cycle of the 800 ms motion at 8 ms is ceil(800 / 8) + 1 = 101 steps: the second loop
    # starts at 0.808 s (elapsed_steps); reversed, 'turn' comes first.
    once = play([arm_motion], robot="ur5e", options=PlayOptions(hold_s=0.0))
    looped = play([arm_motion], robot="ur5e", options=PlayOptions(hold_s=0.0, loops=2))
    assert once.end_effector is not None and looped.end_effector is not None
    # One entry per keyframe of the motion: its worst visit of the two.
    assert [(k.name, k.visits) for k in looped.end_effector.keyframes] == [
        ("start", 2),
        ("up", 2),
        ("turn", 2),
    ]
    for first, k in zip(once.end_effector.keyframes, looped.end_effector.keyframes, strict=True):
        assert k.position_error_mm >= first.position_error_mm
        assert round(k.time_s, 6) in {round(first.time_s, 6), round(first.time_s + 0.808, 6)}
        assert k.measured_box_m is not None
        low, high = np.array(k.measured_box_m)
        for p in (first.measured_position_m, k.measured_position_m):
            assert (low <= p).all() and (p <= high).all()
    # The loop jumps back to 'start' from 'turn': its second visit is the worse one.
    start = looped.end_effector.keyframes[0]
    assert round(start.time_s, 6) == 0.808 and start.position_error_mm > 50
    reverse = play([arm_motion], robot="ur5e", options=PlayOptions(hold_s=0.0, reverse=True))
    assert reverse.end_effector is not None
    names = [(k.name, k.time_s, k.visits) for k in reverse.end_effector.keyframes]
    assert names == [("turn", 0.0, 1), ("up", 0.4, 1), ("start", 0.8, 1)]
    first = reverse.end_effector.keyframes[0]
    assert first.position_error_mm > 50  # the arm starts at zero, the motion at 'turn'


@pytest.mark.needs("sim")
def test_a_folded_keyframe_is_the_worst_of_its_visits_and_the_report_does_not_grow(
    arm_motion: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # Each visit measured alone (a one-keyframe-per-visit copy of the looped motion played
    # once) against the looped run's folded entries; then 3 and 12 loops give reports of one
    # size, the trail held to TRAIL_POINTS samples.
    from motiontool.sim import arm

    monkeypatch.setattr(arm, "TRAIL_POINTS", 40)
    runs = {
        n: play([arm_motion], robot="ur5e", options=PlayOptions(hold_s=0.0, loops=n))
        for n in (3, 12)
    }
    sizes = {}
    for n, report in runs.items():
        ee = report.end_effector
        assert ee is not None and len(ee.keyframes) == 3
        assert {k.visits for k in ee.keyframes} == {n}
        assert 20 < len(ee.trail_time_s) <= 41  # the samples kept, and the last frame
        assert ee.trail_time_s[-1] == pytest.approx(report.simulated_s, abs=0.01)
        step = np.diff(ee.trail_time_s[:-1])
        assert np.allclose(step, step[0])  # evenly spaced, the stride doubled as needed
        sizes[n] = len(json.dumps(report.to_json()))
    assert abs(sizes[12] - sizes[3]) < 200  # the same entries, a few digits apart


@pytest.mark.needs("sim")
def test_a_folded_keyframe_is_judged_by_its_worst_visit(
    arm_motion: Path,
) -> None:
    report = play([arm_motion], robot="ur5e", options=PlayOptions(hold_s=0.0, loops=2))
    ee = report.end_effector
    assert ee is not None
    start = ee.keyframes[0]
    assert start.measured_box_m is not None
    low, high = start.measured_box_m
    # From the box's low corner, the farthest visit is at most at the high corner.
    point, lag = evaluate([f"ee[start]=[{low[0]},{low[1]},{low[2]}]±1mm", "ee_lag[up]<1s"], report)
    assert not point.passed
    assert point.measured == pytest.approx(math.dist(low, high))
    assert "worst of 2 visits" in point.reason
    assert not lag.passed  # passed through at speed, at both visits
    assert "never came within 1 mm of up at one of its 2 visits" in lag.reason
