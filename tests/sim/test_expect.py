"""Expectations: the parser, judging real play reports, the verdict, ``--start lying-back``."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path
from typing import Any

import pytest
from typer.testing import CliRunner

from motiontool.cli import schemas
from motiontool.cli.app import app
from motiontool.sim import PlayOptions, PlayReport, play
from motiontool.sim.expect import (
    FLAGS,
    QUANTITIES,
    ExpectationError,
    apply_expectations,
    evaluate,
    parse_expectation,
)

runner = CliRunner()

NOD = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n00:00:000,A,0,0\n00:00:300,B,0.6,-0.3\n00:00:600,C,0,0\n"


@pytest.fixture(scope="module")
def nod(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("nod") / "nod.motion"
    path.write_bytes(NOD)
    return path


@pytest.fixture(scope="module")
def nod_report(nod: Path) -> PlayReport:
    return play([nod], robot="nao", options=PlayOptions(hold_s=0.2))


# ------------------------------------------------------------------------------- parsing


@pytest.mark.parametrize(
    ("text", "quantity", "op", "value", "tolerance"),
    [
        ("dx>=0.3", "dx", ">=", 0.3, 0.0),
        (" dx >= 0.3 m ", "dx", ">=", 0.3, 0.0),
        ("yaw=60±10", "yaw", "=", 60.0, 10.0),
        ("yaw=60+-10", "yaw", "=", 60.0, 10.0),
        ("yaw==-60 +/- 5deg", "yaw", "=", -60.0, 5.0),
        ("torso_height=33±1cm", "torso_height", "=", 0.33, 0.01),
        ("torso_height=0.33m±1cm", "torso_height", "=", 0.33, 0.01),
        ("yaw=60±15%", "yaw", "=", 60.0, 9.0),
        ("final_tilt<10", "final_tilt", "<", 10.0, 0.0),
        ("torso_height>30cm", "torso_height", ">", 0.3, 0.0),
        ("feet_slip<0.5cm", "feet_slip", "<", 5.0, 0.0),
        ("max_tilt≤0.1rad", "max_tilt", "<=", math.degrees(0.1), 0.0),
        ("fell_at<=660ms", "fell_at", "<=", 0.66, 0.0),
        ("dy<-1e-2", "dy", "<", -0.01, 0.0),
        ("self_collisions=0", "self_collisions", "=", 0.0, 0.0),
    ],
)
def test_parse_quantities_units_and_tolerances(
    text: str, quantity: str, op: str, value: float, tolerance: float
) -> None:
    e = parse_expectation(text)
    assert (e.text, e.quantity, e.op, e.joint) == (text, quantity, op, None)
    assert e.value == pytest.approx(value) and e.tolerance == pytest.approx(tolerance)


def test_parse_flags_and_joints() -> None:
    for text, flag in [("upright", "upright"), ("No_Fall", "no-fall"), (" fell ", "fell")]:
        e = parse_expectation(text)
        assert (e.quantity, e.op) == (flag, None)
    e = parse_expectation("tracking_error[HeadYaw]<0.2")
    assert (e.quantity, e.joint, e.op, e.value) == ("tracking_error", "HeadYaw", "<", 0.2)
    assert e.describe() == "tracking_error[HeadYaw] < 0.2 rad"
    assert parse_expectation("yaw=60±10").describe() == "yaw = 60 ± 10 deg"
    assert set(FLAGS) == {"upright", "fell", "no-fall", "no-self-collision", "feet-planted"}


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("dxx>=0.3", r"unknown quantity 'dxx'; did you mean 'dx'\? \(valid: dx, dy, "),
        ("uprigth", r"unknown quantity 'uprigth'; did you mean 'upright'\?"),
        ("speed>1", r"unknown quantity 'speed' \(valid: .*feet-planted\)$"),
        ("yaw=60", r"'=' needs a tolerance, e.g. 'yaw=60±1'"),
        ("dx>3deg", r"unit 'deg' does not fit dx, which is in m \(m, cm, mm\)"),
        ("dx>3furlong", r"unit 'furlong' does not fit dx"),
        ("dx<0.3±0.1", r"±TOL goes with '=' only"),
        ("dx>=abc", r"expected QUANTITY OP VALUE\[UNIT\]"),
        ("", r"expected QUANTITY OP VALUE\[UNIT\]"),
        ("dx[HeadYaw]>0", r"dx takes no joint \(only tracking_error, tracking_rms, velocity_cap"),
        ("yaw>60%", r"'%' is for a tolerance"),
        ("yaw=60±-5", r"the tolerance must be >= 0"),
    ],
)
def test_bad_expectations_are_one_line_errors(text: str, message: str) -> None:
    with pytest.raises(ExpectationError, match=message) as info:
        parse_expectation(text)
    assert "\n" not in str(info.value) and str(info.value).startswith(f"expectation {text!r}")


# ------------------------------------------------------------------------------- judging


@pytest.mark.needs("sim")
def test_a_real_run_is_judged_with_units_and_one_line_reasons(nod_report: PlayReport) -> None:
    base = nod_report.base
    assert base is not None
    results = evaluate(
        [
            "upright",
            "no-fall",
            "feet-planted",
            "no-self-collision",
            "dx>=0.3",
            "fell",
            "fell_at<1",
            "tracking_error[HeadYaw]<1",
            "tracking_error[HeadYw]<1",
            f"torso_height={base.final_height_m * 100:.4f}±0.1cm",
        ],
        nod_report,
    )
    verdicts = {r.expectation.text: r for r in results}
    assert [r.passed for r in results] == [
        True,
        True,
        True,
        True,
        False,
        False,
        False,
        True,
        False,
        True,
    ]
    dx = verdicts["dx>=0.3"]
    assert dx.measured == base.dx_m and dx.unit == "m"
    assert dx.reason == f"expected dx >= 0.3 m, measured {base.dx_m:.3f} m"
    assert verdicts["fell"].reason == "expected a fall, the robot did not fall"
    assert verdicts["fell_at<1"].reason == "expected fell_at < 1 s, not measured: it did not fall"
    head = next(j for j in nod_report.joints if j.name == "HeadYaw")
    assert verdicts["tracking_error[HeadYaw]<1"].measured == head.max_error
    assert verdicts["tracking_error[HeadYw]<1"].reason.endswith(
        "not measured: nao has no joint 'HeadYw'; did you mean 'HeadYaw'?"
    )
    assert verdicts["upright"].measured == base.final_tilt_deg
    doc = verdicts["dx>=0.3"].to_json()
    assert doc == {
        "text": "dx>=0.3",
        "quantity": "dx",
        "joint": None,
        "expected": "dx >= 0.3 m",
        "passed": False,
        "measured": {"value": base.dx_m, "unit": "m"},
        "reason": dx.reason,
    }


@pytest.mark.needs("sim")
def test_a_failed_expectation_fails_the_run_and_an_expected_fall_passes(
    nod_report: PlayReport,
) -> None:
    doc = nod_report.to_json()
    assert doc["clean"] and doc["expectations"] == []
    judged = apply_expectations({**doc, "perturbation": {"friction": 1.1}}, ["dx>=0.3", "upright"])
    assert judged["perturbation"] == {"friction": 1.1}  # other keys are kept
    assert (judged["clean"], judged["exit_code"]) == (False, 1)
    assert judged["reason"] == judged["expectations"][0]["reason"]
    assert re.fullmatch(r"expected dx >= 0\.3 m, measured -?0\.00\d m", judged["reason"])
    assert judged["expectations"][1]["passed"] is True

    # The same run, had the robot fallen: not clean ... unless the fall is what it must do.
    fallen = json.loads(json.dumps(doc))
    fallen["base"].update(fell=True, fell_at_s=0.5, upright_at_end=False)
    assert apply_expectations(fallen, [])["reason"] == "fell at 0.50 s"
    assert apply_expectations(fallen, ["fell"])["clean"] is True
    assert apply_expectations(fallen, ["fell_at<0.6"])["clean"] is True
    late = apply_expectations(fallen, ["fell_at>1"])
    assert late["reason"] == "expected fell_at > 1 s, measured 0.50 s"
    assert apply_expectations(fallen, ["upright"])["reason"] == (
        "fell at 0.50 s; expected upright (no fall, up at the end), fell at 0.50 s"
    )
    assert apply_expectations(fallen, ["no-fall"])["reason"] == "expected no fall, fell at 0.50 s"


@pytest.mark.needs("sim")
def test_fall_direction_takes_the_short_way_round_and_says_why_it_is_not_measured(
    nod_report: PlayReport,
) -> None:
    doc = nod_report.to_json()
    fallen = json.loads(json.dumps(doc))
    fallen["base"].update(fell=True, fell_at_s=0.5, upright_at_end=False)
    fallen["base"]["fall_direction_deg"] = -170.0  # back, a little to the right
    judged = apply_expectations(fallen, ["fall_direction=180±45"])
    assert judged["clean"] is True  # -170 is 10 deg from 180: the expected fall
    assert judged["expectations"][0]["measured"] == {"value": -170.0, "unit": "deg"}
    assert apply_expectations(fallen, ["fall_direction=90±45"])["reason"] == (
        "expected fall_direction = 90 ± 45 deg, measured -170.0 deg"
    )
    assert apply_expectations(fallen, ["fall_direction=-135±40"])["clean"] is True
    assert apply_expectations(fallen, ["fall_direction<0"])["clean"] is True
    (standing,) = evaluate(["fall_direction=0±45"], nod_report)  # it did not fall
    assert standing.reason == "expected fall_direction = 0 ± 45 deg, not measured: it did not fall"
    del fallen["base"]["fall_direction_deg"]  # a cached report made before it existed
    assert apply_expectations(fallen, ["fall_direction=180±45"])["reason"].endswith(
        "not measured: the report does not say which way (made before fall_direction existed)"
    )


@pytest.mark.needs("sim")
def test_report_json_round_trips(nod_report: PlayReport) -> None:
    doc = nod_report.to_json()
    assert PlayReport.from_json(doc).to_json() == doc


@pytest.mark.needs("sim")
def test_heading_frame_follows_the_start_yaw(nod: Path) -> None:
    report = play([nod], robot="nao", options=PlayOptions(hold_s=0.1, start_yaw_deg=90.0))
    assert report.base is not None
    along, left = (r.measured for r in evaluate(["dx_heading>-1", "dy_heading>-1"], report))
    assert along == pytest.approx(report.base.dy_m, abs=1e-12)
    assert left == pytest.approx(-report.base.dx_m, abs=1e-12)


@pytest.mark.needs("sim")
def test_fixed_base_robots_say_why_base_quantities_are_not_measured() -> None:
    from conftest import ROOT

    report = play([ROOT / "motions/ur5e/jog.motion"], robot="ur5e", options=PlayOptions(hold_s=0))
    up, dx, collision, track = evaluate(
        ["upright", "dx>0", "no-self-collision", "tracking_error<0.2"], report
    )
    assert up.reason == "expected upright, not measured: ur5e has a fixed base: it cannot fall"
    assert dx.reason == "expected dx > 0 m, not measured: ur5e has a fixed base: no base motion"
    assert collision.passed and track.passed


def test_every_quantity_has_a_unit_and_help() -> None:
    # Every unit a quantity reports is one the play schema allows (ee_lag: ms).
    measured = schemas.load("play")["properties"]["expectations"]["items"]["properties"]
    units = measured["measured"]["properties"]["unit"]["enum"]
    for q in QUANTITIES.values():
        assert q.unit in units and q.help


# ------------------------------------------------------------------------------- CLI


def schema_errors(doc: Any, name: str) -> list[str]:
    import jsonschema

    validator = jsonschema.Draft202012Validator(schemas.load(name))
    return [f"{list(e.absolute_path)}: {e.message}" for e in validator.iter_errors(doc)]


@pytest.mark.needs("sim")
def test_play_with_a_wrong_expectation_exits_1_with_the_reason(nod: Path, tmp_path: Path) -> None:
    out = tmp_path / "run.json"
    result = runner.invoke(
        app,
        [
            "play",
            str(nod),
            "--headless",
            "--hold",
            "0.2",
            "--expect",
            "dx>=0.3",
            "--expect",
            "upright",
            "--json",
            str(out),
        ],
    )
    assert result.exit_code == 1, result.output
    lines = result.stdout.splitlines()
    assert re.fullmatch(r"result: expected dx >= 0\.3 m, measured -?0\.00\d m", lines[1])
    assert lines[2] == "expectations: 1 of 2 met"
    assert lines[3].startswith("  FAIL expected dx >= 0.3 m, measured")
    assert lines[4].startswith("  ok   upright")
    doc = json.loads(out.read_text())
    assert not schema_errors(doc, "play")
    assert doc["exit_code"] == 1 and doc["reason"] == lines[1].removeprefix("result: ")
    assert [e["passed"] for e in doc["expectations"]] == [False, True]
    assert doc["expectations"][0]["measured"]["unit"] == "m"


@pytest.mark.needs("sim")
def test_play_reads_the_sidecar_and_a_bad_one_exits_2(nod: Path, tmp_path: Path) -> None:
    motion = tmp_path / "nod.motion"
    motion.write_bytes(NOD)
    sidecar = tmp_path / "motions.toml"
    sidecar.write_text('[nod]\nexpect = ["yaw=90±5"]\n')
    args = ["play", str(motion), "--headless", "--hold", "0.1"]
    result = runner.invoke(app, args)
    assert result.exit_code == 1 and "FAIL expected yaw = 90 ± 5 deg, measured" in result.stdout
    assert runner.invoke(app, [*args, "--no-sidecar"]).exit_code == 0
    sidecar.write_text('[nod]\n\nexpect = ["yaw=90"]\n')
    result = runner.invoke(app, args)
    assert result.exit_code == 2
    assert result.stderr == (
        f"motiontool: error: {sidecar}:3: expectation 'yaw=90': '=' needs a tolerance, "
        "e.g. 'yaw=90±1'\n"
    )


# ------------------------------------------------------------------------------- lying-back


@pytest.mark.needs("sim")
def test_lying_back_starts_face_up_and_lying_front_face_down() -> None:
    from motiontool.kinematics.robots import load_robot
    from motiontool.sim import _mujoco

    nao = load_robot("nao")
    for start, up in [("lying-back", 1.0), ("lying-front", -1.0)]:
        scene = _mujoco.build_scene(nao, 20, start=start)  # type: ignore[arg-type]
        torso = scene.data.xmat[scene.root_body].reshape(3, 3)
        assert torso[2, 0] == pytest.approx(up, abs=1e-9)  # the chest faces the sky / floor
        assert abs(torso[2, 2]) < 1e-9  # the torso lies flat


@pytest.mark.needs("sim")
def test_a_run_started_lying_back_starts_down(nod: Path) -> None:
    report = play([nod], robot="nao", options=PlayOptions(start="lying-back", hold_s=0.2))
    base = report.base
    assert base is not None
    assert base.started_down and not base.upright_at_end and not base.fell
    assert base.final_height_m < 0.1 and base.final_tilt_deg > 80.0  # on its back
    assert report.problems == ["started down and did not get up"]
    assert report.options["start"] == "lying-back"
