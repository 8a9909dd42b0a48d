"""``expect --infer`` reads names right, on names made up for the test:
the turn angle is the number attached to the turn word, falls and dives expect a fall to the
named side, kicks expect no fall, stand-ups get the lying start they need (played from both
when the name does not say), walks expect progress, and ``upright`` is the fall detector."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from conftest import CORPUS
from typer.testing import CliRunner

from motiontool.cli.app import app
from motiontool.sim import PlayOptions, play
from motiontool.sim.expect import evaluate
from motiontool.sim.infer import infer
from motiontool.sim.sidecar import load_sidecar

runner = CliRunner()

STAND_UP = CORPUS / "projects/robots/softbank/nao/motions/StandUpFromFront.motion"
NOD = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n00:00:000,A,0,0\n00:00:300,B,0.6,-0.3\n"


def hips(roll: float = 0.0, pitch: float = 0.0) -> bytes:
    """Both hips rolled / pitched (rad) in 0.3 s, then held: a lean (pitch -0.2: about 12 deg
    forward, it stands) or a fall (roll -0.4: it topples to its left)."""
    head = "#WEBOTS_MOTION,V1.0,LHipRoll,RHipRoll,LHipPitch,RHipPitch\n"
    pose = f"{roll},{roll},{pitch},{pitch}"
    return f"{head}00:00:000,A,0,0,0,0\n00:00:300,B,{pose}\n00:01:500,C,{pose}\n".encode()


def proposal(name: str) -> tuple[list[str], str | None]:
    inference = infer(name)
    assert inference.notes
    return inference.expect, inference.start


# ------------------------------------------------------------------------------- item 8


@pytest.mark.parametrize(
    ("name", "expect"),
    [
        ("Team5_TurnLeft60", ["yaw=60±9", "upright"]),  # a team number is not the angle
        ("v2_TurnRight30", ["yaw=-30±5", "upright"]),  # nor a version
        ("Turn90Left", ["yaw=90±14", "upright"]),
        ("LeftTurn45_v3", ["yaw=45±7", "upright"]),
        ("TurnLeft_v2", ["yaw>0", "upright"]),  # the number is attached to 'v'
        ("TurnRight1000", ["yaw<0", "upright"]),  # past a full turn: not degrees
        ("TurnLeft10", ["yaw=10±5", "upright"]),  # under 30 deg: a band too
        ("TurnRight20", ["yaw=-20±5", "upright"]),
    ],
)
def test_the_turn_angle_is_the_number_attached_to_the_turn_word(
    name: str, expect: list[str]
) -> None:
    assert proposal(name) == (expect, None)


def test_a_small_turn_says_it_is_the_least_sure() -> None:
    assert "TurnLeft10 turns about 32 deg" in " ".join(infer("TurnLeft15").notes)
    assert "32 deg" not in " ".join(infer("TurnLeft45").notes)


# ------------------------------------------------------------------------------- item 9


@pytest.mark.parametrize(
    ("name", "expect"),
    [
        ("DiveLeft", ["fell", "fall_direction=90±45"]),
        ("Goalie_DiveRight", ["fell", "fall_direction=-90±45"]),
        ("FallBack", ["fell", "fall_direction=180±45"]),
        ("fall_forward", ["fell", "fall_direction=0±45"]),
        ("FallFront2", ["fell", "fall_direction=0±45"]),
        ("Dive", ["fell"]),
        ("KickSideLeft", ["no-fall"]),  # the direction is the ball's: no walk
        ("SidePass_Right", ["no-fall"]),
        ("KickForwardLeft", ["no-fall"]),
        ("ShotRight", ["no-fall"]),
    ],
)
def test_falls_expect_the_named_side_and_kicks_no_fall(name: str, expect: list[str]) -> None:
    assert proposal(name) == (expect, None)


@pytest.mark.needs("sim")
def test_a_dive_to_the_left_is_judged_by_the_side_it_fell_to(tmp_path: Path) -> None:
    folder = tmp_path / "dives"
    folder.mkdir()
    (folder / "DiveLeft.motion").write_bytes(hips(roll=-0.4))
    (folder / "DiveRight.motion").write_bytes(hips(roll=-0.4))  # misnamed: it falls left too
    sidecar = folder / "motions.toml"
    result = runner.invoke(app, ["expect", "--infer", str(folder), "-o", str(sidecar)])
    assert result.exit_code == 0, result.output
    entry = load_sidecar(sidecar).lookup(folder / "DiveLeft.motion")
    assert entry is not None and entry.expect == ("fell", "fall_direction=90±45")
    report = play([folder / "DiveLeft.motion"], robot="nao")
    assert report.base is not None and report.base.fell
    left, right, back = evaluate(
        ["fall_direction=90±45", "fall_direction=-90±45", "fall_direction=180±45"], report
    )
    assert left.passed and 80.0 < (left.measured or 0.0) < 100.0
    assert not right.passed
    assert re.fullmatch(
        r"expected fall_direction = -90 ± 45 deg, measured (8|9)\d\.\d deg", right.reason
    )
    assert not back.passed
    report.expectations = evaluate(["fell", "fall_direction=90±45"], report)
    assert report.clean, report.problems  # the expected fall, to the expected side


# ------------------------------------------------------------------------------- item 10


@pytest.mark.parametrize(
    ("name", "start", "needs_start"),
    [
        ("GetUp", None, True),
        ("GetUpFront", "lying-front", False),
        ("FastUp", None, True),
        ("StandUpFromBack", "lying-back", False),
        ("quick_get_up_belly", "lying-front", False),
        ("Team3_StandUp", None, True),
        ("GenUp", None, True),  # a spelling of GetUp seen in team code
        ("Genup", None, True),
        ("GenUpFront", "lying-front", False),
        ("genup_back", "lying-back", False),
        ("Getup", None, True),
        ("Standup", None, True),
        ("GettingUpFromBack", "lying-back", False),
        ("StandingUp", None, True),
        ("GetUpBack", "lying-back", False),  # Webots' wrestling world
        ("GetUpFront", "lying-front", False),
        ("StandUpFromFront", "lying-front", False),  # Webots' Nao demo
    ],
)
def test_stand_up_variants_get_the_lying_start_they_need(
    name: str, start: str | None, needs_start: bool
) -> None:
    inference = infer(name)
    assert (inference.expect, inference.start, inference.needs_start) == (
        ["upright"],
        start,
        needs_start,
    )
    assert infer("HandsUp").expect == ["upright", "feet-planted"]  # 'up' alone is no stand-up


@pytest.mark.needs("sim")
def test_a_stand_up_that_does_not_say_front_or_back_is_played_from_both(
    tmp_path: Path,
) -> None:
    folder = tmp_path / "ups"
    folder.mkdir()
    (folder / "GetUp.motion").write_bytes(STAND_UP.read_bytes())  # gets up from the front
    (folder / "FastUp.motion").write_bytes(NOD)  # a nod gets up from neither
    sidecar = folder / "motions.toml"
    result = runner.invoke(app, ["expect", "--infer", str(folder), "-o", str(sidecar)])
    assert result.exit_code == 0, result.output
    get_up = load_sidecar(sidecar).lookup(folder / "GetUp.motion")
    fast_up = load_sidecar(sidecar).lookup(folder / "FastUp.motion")
    assert get_up is not None and (get_up.expect, get_up.start) == (("upright",), "lying-front")
    assert fast_up is not None and (fast_up.expect, fast_up.start) == (("upright",), None)
    text = sidecar.read_text(encoding="utf-8")
    assert (
        "[GetUp]  # played from both lying starts: gets up from lying-front, not from lying-back"
        in text
    )
    assert (
        "[FastUp]  # the name does not say front or back, and played it gets up from neither of"
        " lying-front and lying-back: not decidable, set start" in text
    )
    bare = runner.invoke(app, ["expect", "--infer", "GetUp"]).stdout  # a name: nothing to play
    assert "[GetUp]  # the name does not say front or back: set start" in bare


# ------------------------------------------------------------------------------- item 11


@pytest.mark.parametrize(
    ("name", "expect"),
    [
        ("Walk", ["dx_heading>=0.03", "upright"]),
        ("Forwards50", ["dx_heading>=0.03", "upright"]),
        ("v2_WalkForward", ["dx_heading>=0.03", "upright"]),
        ("WalkBack", ["dx_heading<=-0.03", "upright"]),
        ("Backwards", ["dx_heading<=-0.03", "upright"]),
        ("SideStepLeft", ["dy_heading>=0.03", "upright"]),
        ("StepRight", ["dy_heading<=-0.03", "upright"]),
        ("LeanForward", ["upright", "feet-planted"]),  # the upper body: no walk
    ],
)
def test_walks_expect_progress(name: str, expect: list[str]) -> None:
    assert proposal(name) == (expect, None)


@pytest.mark.needs("sim")
def test_upright_is_the_fall_detector_not_a_tilt_bound(tmp_path: Path) -> None:
    lean = tmp_path / "LeanForward.motion"
    lean.write_bytes(hips(pitch=-0.2))
    report = play([lean], robot="nao", options=PlayOptions(hold_s=0.5))
    assert report.base is not None and not report.base.fell
    assert report.base.final_tilt_deg > 11.0  # leans by design
    (upright,) = evaluate(["upright"], report)
    assert upright.passed and upright.measured == report.base.final_tilt_deg
    fallen = tmp_path / "Fall.motion"
    fallen.write_bytes(hips(pitch=-0.8))
    (down,) = evaluate(["upright"], play([fallen], robot="nao"))
    assert not down.passed and down.reason.startswith("expected upright (no fall, up at the end)")


# ----------------------------------------------------------- chains, get-ups, gestures, kicks


@pytest.mark.parametrize(
    "name",
    [
        "Pointing",
        "PointLeft",
        "ThumbsUp",
        "thumb_up",
        "Goodbye",
        "GoodBye",
        "Bye",
        "WaveGoodbye",
        "HandWave",  # Webots' wrestling world
        "HandWaveLeft",
        "WipeForehead",
    ],
)
def test_gestures_keep_the_feet_planted(name: str) -> None:
    assert proposal(name) == (["upright", "feet-planted"], None)


@pytest.mark.parametrize("name", ["Shoot", "Shooting", "ShootLeft", "long_shot", "KickRight"])
def test_shoot_names_are_kicks(name: str) -> None:
    expect, start = proposal(name)
    assert (expect, start) == (["no-fall"], None)
    assert infer(name).notes[0].startswith("kicks")


def test_start_loop_stop_families_are_proposed_as_chains(tmp_path: Path) -> None:
    folder = tmp_path / "steps"
    folder.mkdir()
    for name in ("SideStepLeft_Start", "SideStepLeft_Loop", "SideStepLeft_Stop", "WalkStart",
                 "WalkLoop", "Shoot"):  # fmt: skip
        (folder / f"{name}.motion").write_bytes(NOD)
    sidecar = folder / "motions.toml"
    result = runner.invoke(app, ["expect", "--infer", str(folder), "-o", str(sidecar)])
    assert result.exit_code == 0, result.output
    loaded = load_sidecar(sidecar)
    after = {p.stem: loaded.lookup(p).after for p in sorted(folder.glob("*.motion"))}  # type: ignore[union-attr]
    assert after == {
        "Shoot": None,
        "SideStepLeft_Loop": "SideStepLeft_Start",
        "SideStepLeft_Start": None,
        "SideStepLeft_Stop": "SideStepLeft_Loop",
        "WalkLoop": "WalkStart",
        "WalkStart": None,
    }
    text = sidecar.read_text(encoding="utf-8")
    assert "the loop of SideStepLeft: played after SideStepLeft_Start" in text
    assert "the end of SideStepLeft: played after SideStepLeft_Loop" in text
