"""``expect --infer`` plays as ``play`` plays: its stand-up probes run in
``--world`` (the proposal then says ``world`` and ``robot-node``, and ``batch`` plays it there),
from ``--start-pose``, and with ``--robustness N`` over play's ensemble (a start is proposed only
where every member agrees; fragile: a comment, a warning, exit 1 with ``--strict``); its
``_Start``/``_Loop``/``_Stop`` chains reach every batch report. Real MuJoCo runs."""

from __future__ import annotations

import json
import re
import shutil
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
from conftest import CORPUS, DATA, require
from typer.testing import CliRunner, Result

from motiontool.cli.app import app
from motiontool.sim.sidecar import load_sidecar

runner = CliRunner()
STAND_UP = CORPUS / "projects/robots/softbank/nao/motions/StandUpFromFront.motion"
NOD = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n00:00:000,A,0,0\n00:00:300,B,0.6,-0.3\n"
MEMBER = re.compile(
    r"^# disagrees: from lying-(front|back), member #\d \(friction [0-9.]+, mass [0-9.]+, "
    r"start-noise [0-9.e-]+, start-yaw [0-9.e-]+, physics-step [12]\): ",
    re.MULTILINE,
)


@pytest.fixture
def wrestling(tmp_path: Path) -> Path:
    """The wrestling world's worlds/ and protos/, and in controllers/motions/ two of its
    motions: HandWave, and GetUp (GetUpFront under a name that does not say front or back)."""
    worlds = require(DATA / "worlds" / "MANIFEST.tsv", "Webots worlds").parent / "wrestling"
    get_up = require(worlds / "controllers" / "motions" / "GetUpFront.motion", "GetUpFront")
    folder = tmp_path / "wrestling"
    for name in ("worlds", "protos"):
        shutil.copytree(worlds / name, folder / name)
    motions = folder / "controllers" / "motions"
    motions.mkdir(parents=True)
    shutil.copyfile(
        worlds / "controllers" / "motions" / "HandWave.motion", motions / "HandWave.motion"
    )
    shutil.copyfile(get_up, motions / "GetUp.motion")
    return folder


def expect(*args: str | Path, env: dict[str, str] | None = None) -> Result:
    return runner.invoke(app, ["expect", "--infer", *map(str, args)], env=env)


@pytest.mark.needs("sim")
def test_the_probes_play_in_the_world_and_the_proposal_plays_there_in_batch(
    wrestling: Path, tmp_path: Path
) -> None:
    motions = wrestling / "controllers" / "motions"
    world = wrestling / "worlds" / "wrestling.wbt"
    sidecar = motions / "motions.toml"
    cache = tmp_path / "cache"
    result = expect(
        motions, "--world", world, "--robot-node", "participant", "--robustness", "2",
        "-o", sidecar, env={"XDG_CACHE_HOME": str(cache)},
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    text = sidecar.read_text(encoding="utf-8")
    assert text.count('world = "../../worlds/wrestling.wbt"') == 2  # from the sidecar's folder
    assert text.count('robot-node = "participant"') == 2
    assert f"# A stand-up played to find its lying start plays in the world {world}." in text
    assert (
        "[GetUp]  # played from both lying starts: gets up from lying-front, not from "
        "lying-back; holds over an ensemble of 2 members (seed 0)" in text
    )
    loaded = load_sidecar(sidecar)
    get_up = loaded.lookup(motions / "GetUp.motion")
    assert get_up is not None and get_up.start == "lying-front"
    assert get_up.world is not None and get_up.world.resolve() == world.resolve()
    # The members played in the world: its 10 ms control step, its robot node, steps of 1, 2 ms.
    members = [json.loads(p.read_text()) for p in (cache / "motiontool" / "batch").rglob("*.json")]
    assert len(members) == 4  # 2 members from each lying start
    for member in members:
        report = member["report"]
        assert report["stamps"]["control_step_ms"] == 10
        assert report["world"]["robot_node"]["name"] == "participant"
        assert report["stamps"]["physics_step_ms"] in (1, 2)
    out = tmp_path / "batch.json"
    batched = runner.invoke(app, ["batch", str(motions / "GetUp.motion"), "--no-cache",
                                  "--json", str(out)])  # fmt: skip
    assert batched.exit_code in (0, 1), batched.output
    (run,) = json.loads(out.read_text())["runs"]
    assert run["report"]["world"]["robot_node"]["name"] == "participant"
    assert run["report"]["stamps"]["control_step_ms"] == 10
    assert run["report"]["options"]["start"] == "lying-front"
    assert [r["passed"] for r in run["report"]["expectations"]] == [True]


@pytest.mark.needs("sim")
@pytest.mark.slow
def test_the_configuration_world_is_where_the_probes_play_when_no_world_is_given(
    wrestling: Path, tmp_path: Path
) -> None:
    """As play: the configuration's world (its path from the configuration's folder) where
    --world names none, else its control step; the proposal leaves the world to the
    configuration; --isolated reads none (the Nao's 20 ms)."""
    (wrestling / "motiontool.toml").write_text(
        'timestep = 40\nworld = "worlds/wrestling.wbt"\nrobot-node = "opponent"\n',
        encoding="utf-8",
    )
    steps = tmp_path / "steps.toml"  # no world: the configuration's control step
    steps.write_text("timestep = 40\n", encoding="utf-8")
    get_up = wrestling / "controllers" / "motions" / "GetUp.motion"
    cases = [([], 10, "opponent"), (["--config", str(steps)], 40, None), (["--isolated"], 20, None)]
    for args, step, node in cases:
        cache = tmp_path / f"cache{step}"
        result = expect(get_up, "--robustness", "1", *args, env={"XDG_CACHE_HOME": str(cache)})
        assert result.exit_code == 0, result.output
        assert "\nworld = " not in result.stdout  # the configuration says it to batch too
        members = [json.loads(p.read_text()) for p in cache.rglob("*.json")]
        assert len(members) == 2  # one member from each lying start
        for member in members:
            assert member["report"]["stamps"]["control_step_ms"] == step
            played_in = member["report"]["world"]
            assert (played_in and played_in["robot_node"]["name"]) == node


@pytest.mark.needs("sim")
def test_robustness_members_start_from_the_start_pose(wrestling: Path, tmp_path: Path) -> None:
    get_up = wrestling / "controllers" / "motions" / "GetUp.motion"
    pose = f"{get_up}:Pose1"
    cache = tmp_path / "cache"
    result = expect(get_up, "--robustness", "1", "--start-pose", pose,
                    env={"XDG_CACHE_HOME": str(cache)})  # fmt: skip
    assert result.exit_code == 0, result.output
    members = [json.loads(p.read_text()) for p in cache.rglob("*.json")]
    assert len(members) == 2  # one member from each lying start, each from the pose
    assert {m["report"]["options"]["start_pose"] for m in members} == {pose}
    assert {m["report"]["options"]["start"] for m in members} == {"lying-front", "lying-back"}


@pytest.mark.needs("sim")
@pytest.mark.slow
def test_a_fragile_start_is_not_proposed_warned_and_strict_fails_the_same_way_each_time(
    tmp_path: Path,
) -> None:
    """Webots' StandUpFromFront gets up from the front at friction 1 and 2 ms, and falls in
    members of the ensemble (docs/simulation.md, Robustness)."""
    folder = tmp_path / "ups"
    folder.mkdir()
    shutil.copyfile(STAND_UP, folder / "GetUp.motion")
    result = expect(folder, "--robustness", "4", "--no-cache")
    assert result.exit_code == 0, result.output  # fragile is a warning
    text = result.stdout
    assert "start =" not in text
    assert re.search(
        r"\[GetUp\]  # played from both lying starts: gets up from lying-front, not from "
        r"lying-back, but fragile over an ensemble \(seed 0\): [1-4] of 4 members from "
        r"lying-(front|back)( and [1-4] of 4 members from lying-back)? disagree: set start;",
        text,
    ), text
    assert MEMBER.search(text), text
    assert (
        "motiontool: warning: GetUp: the lying start it needs is fragile under --robustness: "
        "no start proposed\n" in result.stderr
    )
    strict = expect(folder, "--robustness", "4", "--no-cache", "--strict")
    assert strict.exit_code == 1
    assert strict.stdout == text  # the same draws, the same runs: the same proposal
    assert "(--strict: exit 1)" in strict.stderr


@pytest.mark.needs("sim")
def test_the_start_pose_reaches_the_probes(wrestling: Path) -> None:
    motions = wrestling / "controllers" / "motions"
    pose = f"{motions / 'GetUp.motion'}:Pose1"
    result = expect(motions / "GetUp.motion", "--start-pose", pose)
    assert result.exit_code == 0, result.output
    assert (
        f"# A stand-up played to find its lying start plays from the start pose {pose}."
        in result.stdout
    )
    assert 'start = "lying-front"' in result.stdout


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--robot-node", "participant"], "--robot-node names a robot node of --world: pass "),
        (["--world", "WORLD"], "wrestling.wbt:1:1: 2 robot nodes could play it: 'participant'"),
        (["--world", "WORLD", "--robot-node", "nobody"], "no robot node named 'nobody'"),
        (["--world", "missing.wbt"], "cannot read 'missing.wbt'"),
        (["--strict"], "--strict fails on a fragile verdict: pass --robustness N"),
        (["--start-pose", "BADPOSE"], "GetUp.motion:Nope: no pose 'Nope' (poses: Pose1, "),
    ],
)
def test_a_bad_world_or_option_is_one_line_exit_2_and_nothing_written(
    wrestling: Path, args: list[str], message: str
) -> None:
    motions = wrestling / "controllers" / "motions"
    world = str(wrestling / "worlds" / "wrestling.wbt")
    pose = f"{motions / 'GetUp.motion'}:Pose1"
    given = {"WORLD": world, "POSE": pose, "BADPOSE": f"{motions / 'GetUp.motion'}:Nope"}
    argv = [given.get(a, a) for a in args]
    sidecar = motions / "motions.toml"
    result = expect(motions, *argv, "-o", sidecar)
    assert result.exit_code == 2, result.output
    assert message in result.stderr and result.stderr.count("\n") == 1, result.stderr
    assert not sidecar.exists()


@pytest.mark.needs("sim")
def test_a_proposed_start_loop_stop_chain_is_named_whole_in_every_batch_report(
    tmp_path: Path,
) -> None:
    """Expect proposes Walk_Stop after Walk_Loop after Walk_Start; batch plays
    Walk_Stop as the chain of the three, and its JSON, Markdown and JUnit name each."""
    folder = tmp_path / "walk"
    folder.mkdir()
    for name in ("Walk_Start", "Walk_Loop", "Walk_Stop"):
        (folder / f"{name}.motion").write_bytes(NOD)
    assert expect(folder, "-o", folder / "motions.toml").exit_code == 0
    out = tmp_path / "report"
    reports = ["--json", f"{out}.json", "--markdown", f"{out}.md", "--junit", f"{out}.xml"]
    stop = folder / "Walk_Stop.motion"
    result = runner.invoke(app, ["batch", str(stop), "--no-cache", *reports])
    assert result.exit_code == 1, result.output  # a nod walks nowhere: dx_heading fails
    elements = [str(folder / f"{n}.motion") for n in ("Walk_Start", "Walk_Loop", "Walk_Stop")]
    chain = " + ".join(elements)
    (run,) = json.loads(Path(f"{out}.json").read_text())["runs"]
    assert [f["path"] for f in run["report"]["files"]] == elements
    assert run["spec"]["chain"] == elements[:2]
    assert chain in Path(f"{out}.md").read_text(encoding="utf-8")
    (case,) = ET.parse(f"{out}.xml").getroot().iter("testcase")
    assert chain in (case.get("name") or "")
