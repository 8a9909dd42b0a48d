"""The play session: what a sidecar and the caller ask of a run, the run judged,
a run that cannot start; the batch's plan from the same resolution; the commands only render."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest
from conftest import ROOT

from motiontool.errors import MotionSyntaxError
from motiontool.kinematics.robots import UnknownRobotError
from motiontool.sim.batch import plan_batch
from motiontool.sim.expect import ExpectationError
from motiontool.sim.play import PlayOptions
from motiontool.sim.session import plan_motion, plan_play
from motiontool.sim.sidecar import SidecarError
from motiontool.sim.start import StartState

NOD = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n00:00:000,A,0,0\n00:00:300,B,0.6,-0.3\n00:00:600,C,0,0\n"
SIDECAR = (
    '[nod]\nexpect = ["upright", "dx>=0.3"]\nstart = "lying-back"\n\n["*"]\nexpect = ["no-fall"]\n'
)
QUICK = PlayOptions(hold_s=0.2)


@pytest.fixture
def nod(tmp_path: Path) -> Path:
    (tmp_path / "motions.toml").write_text(SIDECAR)
    path = tmp_path / "nod.motion"
    path.write_bytes(NOD)
    (tmp_path / "shake.motion").write_bytes(NOD)
    return path


def test_the_sidecar_comes_first_and_the_given_start_wins(nod: Path) -> None:
    motion = plan_motion(nod, ["feet-planted"])
    assert motion.expect == ("upright", "dx>=0.3", "no-fall", "feet-planted")
    assert [e.quantity for e in motion.expectations] == ["upright", "dx", "no-fall", "feet-planted"]
    assert motion.start is StartState.LYING_BACK
    assert plan_motion(nod, start="standing").start is StartState.STANDING
    assert plan_motion(nod.with_name("shake.motion")).start is None
    unread = plan_motion(nod, ["feet-planted"], sidecar=False)
    assert (unread.expect, unread.start) == (("feet-planted",), None)


def test_play_reads_the_sidecar_of_one_file_only(nod: Path) -> None:
    one = plan_play([nod], expect=["feet-planted"])
    assert one.motion.expect[-1] == "feet-planted" and one.start is StartState.LYING_BACK
    two = plan_play([nod, nod.with_name("shake.motion")], expect=["feet-planted"])
    assert two.motion.expect == ("feet-planted",) and two.start is StartState.STANDING
    assert plan_play([Path("-")]).motion.expect == ()
    assert plan_play([nod], sidecar=False).start is StartState.STANDING


def test_a_bad_expectation_or_sidecar_stops_the_plan_before_anything_is_read(
    tmp_path: Path,
) -> None:
    never_read = tmp_path / "missing.motion"
    with pytest.raises(ExpectationError, match="did you mean 'dx'"):
        plan_play([never_read], expect=["dxx>1"])
    (tmp_path / "motions.toml").write_text('[missing]\nexpect = ["upright", "tilt<3"]\n')
    with pytest.raises(SidecarError, match=r"motions.toml:2: .*unknown quantity 'tilt'"):
        plan_play([never_read])


@pytest.mark.needs("sim")
def test_the_run_is_judged_and_stamped(nod: Path) -> None:
    result = plan_play([nod], start="standing").run(robot="nao", options=QUICK)
    report = result.report
    assert result.error is None and report is not None
    assert report.options["start"] == "standing"
    judged = {r.expectation.text: r.passed for r in report.expectations}
    assert judged == {"upright": True, "dx>=0.3": False, "no-fall": True}
    assert result.exit_code == report.exit_code == 1
    assert result.stamps["model_sha256"] == report.stamps["model_sha256"] is not None
    doc = result.to_json()
    assert doc["schema"] == "motiontool.play" and doc["reason"].startswith("expected dx >= 0.3 m")
    lying = plan_play([nod]).run(robot="nao", options=QUICK).report
    assert lying is not None and lying.options["start"] == "lying-back"


def test_a_run_that_cannot_start_is_a_result_with_its_error(nod: Path, tmp_path: Path) -> None:
    bad = tmp_path / "bad.motion"
    bad.write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n00:00:000,A,nan\n")
    result = plan_play([bad]).run(robot="nao", options=QUICK)
    assert isinstance(result.error, MotionSyntaxError) and result.report is None
    assert result.exit_code == 2
    assert result.to_json() == {
        "schema": "motiontool.play",
        "schema_version": 1,
        "stamps": result.stamps,
        "files": [{"path": str(bad)}],
        "clean": False,
        "exit_code": 2,
        "reason": str(result.error),
        "error": str(result.error),
    }
    assert result.stamps["model_sha256"] is None  # the robot was never resolved
    unknown = plan_play([nod]).run(robot="nosuch", options=QUICK)
    assert isinstance(unknown.error, UnknownRobotError)


def test_the_batch_plans_each_file_with_its_sidecar(nod: Path, tmp_path: Path) -> None:
    files = [nod, nod.with_name("shake.motion")]
    specs = plan_batch(
        files,
        {f: ["nao"] for f in files},
        options={"profile": "webots"},
        timesteps={nod: 40, files[1]: None},
        expect=["feet-planted"],
        rrd_dir=tmp_path / "rrd",
    )
    by_name = {Path(s.path).name: s for s in specs}
    assert by_name["nod.motion"].expect == ("upright", "dx>=0.3", "no-fall", "feet-planted")
    assert by_name["shake.motion"].expect == ("no-fall", "feet-planted")
    nod_options, shake_options = dict(by_name["nod.motion"].options), dict(specs[1].options)
    assert nod_options["start"] == "lying-back" and "start" not in shake_options  # none: standing
    assert (nod_options["timestep_ms"], shake_options["timestep_ms"]) == (40, None)
    assert nod_options["profile"] == "webots" and nod_options["rrd_name"] == "nod"
    assert not (tmp_path / "rrd").exists()  # made by the caller once it checked the plan
    plain = plan_batch(files, {f: ["nao"] for f in files}, options={}, timesteps={}.fromkeys(files))
    assert [s.expect for s in plain] == [("upright", "dx>=0.3", "no-fall"), ("no-fall",)]


def test_a_bad_given_expectation_stops_the_batch_before_any_sidecar(nod: Path) -> None:
    (nod.parent / "motions.toml").write_text('[nod]\nexpect = ["tilt<3"]\n')
    with pytest.raises(ExpectationError, match="'dxx'"):
        plan_batch([nod], {nod: ["nao"]}, options={}, timesteps={nod: None}, expect=["dxx>1"])
    with pytest.raises(SidecarError):
        plan_batch([nod], {nod: ["nao"]}, options={}, timesteps={nod: None})


PLUMBING = {
    "expectations_for",
    "lookup",
    "parse_expectations",
    "evaluate",
    "read_playable",
    "resolve_robot",
    "stamps",
    "play",
    "write_failure",
}
"""What ``play`` and ``batch`` once did themselves: the session does it."""


@pytest.mark.parametrize("command", ["cli/play.py", "cli/batch.py"])
def test_the_commands_call_the_session_and_render(command: str) -> None:
    tree = ast.parse((ROOT / command).read_text(encoding="utf-8"))
    called = {
        node.func.id if isinstance(node.func, ast.Name) else getattr(node.func, "attr", "")
        for node in ast.walk(tree)
        if isinstance(node, ast.Call)
    }
    imported = {
        alias.name
        for node in ast.walk(tree)
        if isinstance(node, ast.ImportFrom)
        for alias in node.names
    }
    assert not (called | imported) & PLUMBING
