"""``play --robustness N``: every verdict replayed over N perturbed members (real MuJoCo runs of
a short Nao motion, on the batch's local pool), holds / fragile / fails, and ``--strict``."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path
from typing import Any

import jsonschema
import pytest
from conftest import DATA, ROOT, require
from typer.testing import CliRunner

from motiontool.cli import schemas
from motiontool.cli.app import app
from motiontool.sim.batch import PERTURBATIONS, RunSpec, draw
from motiontool.sim.robustness import ENSEMBLE, member_specs, physics_steps

runner = CliRunner()
SCRIPT = str(Path(sys.executable).parent / "motiontool")
# A head shake: 2.4 s of motion, the robot standing still (max tilt about 0.26 deg).
HEAD_NO = ROOT / "motions" / "nao" / "head_no.motion"


@pytest.fixture
def head_no(tmp_path: Path) -> Path:
    """A copy without its motions.toml (the tests give their own expectations)."""
    path = tmp_path / "head_no.motion"
    shutil.copyfile(HEAD_NO, path)
    return path


def play(*args: str | Path, cache: Path | None = None) -> tuple[int, str, dict[str, Any]]:
    """``play --headless ... --json`` on the local pool: exit code, text, the JSON report
    (checked against the play schema)."""
    out = Path(str(args[0])).with_suffix(".json")
    more = ["--no-cache"] if cache is None else []
    env = {} if cache is None else {"XDG_CACHE_HOME": str(cache)}
    argv = ["play", "--headless", *map(str, args), "--hold", "0.2", "--json", str(out), *more]
    result = runner.invoke(app, argv, env=env)
    doc = json.loads(out.read_text(encoding="utf-8"))
    validator = jsonschema.Draft202012Validator(schemas.load("play"), registry=schemas.registry())
    assert [e.message for e in validator.iter_errors(doc)] == []
    return result.exit_code, result.output, doc


def verdicts(doc: dict[str, Any]) -> dict[str, dict[str, Any]]:
    return {v["name"]: v for v in doc["robustness"]["verdicts"]}


def test_the_ensemble_draws_batch_perturbations_and_steps_dividing_the_control_step() -> None:
    assert all(p.name in PERTURBATIONS for p in ENSEMBLE)
    nominal = RunSpec("a.motion", "0" * 64, "nao", options=(("rrd_dir", "r"), ("timestep_ms", 20)))
    members = member_specs(nominal, 3, seed=7, control_step_ms=20)
    assert [m.sample for m in members] == [1, 2, 3]
    assert [m.params for m in members] == [draw(ENSEMBLE, 7, k) for k in (1, 2, 3)]
    assert sorted(dict(m.options)["physics_step_ms"] for m in members) == [1.0, 2.0, 4.0]
    assert all("rrd_dir" not in dict(m.options) for m in members)  # no member records
    keys = {m.cache_key("model") for m in members} | {nominal.cache_key("model")}
    assert len(keys) == 4  # each member is a batch run of its own in the cache
    # A Webots world's basicTimeStep of 10 ms bounds the steps; 25 ms leaves 1 ms alone.
    assert physics_steps(10) == (1, 2) and physics_steps(25) == (1,) and physics_steps(1) == (1,)
    in_world = member_specs(nominal, 5, seed=0, control_step_ms=10)
    assert {dict(m.options)["physics_step_ms"] for m in in_world} == {1.0, 2.0}


@pytest.mark.needs("sim")
def test_a_verdict_every_member_agrees_with_holds(head_no: Path) -> None:
    code, text, doc = play(head_no, "--expect", "no-fall", "--robustness", "3")
    assert code == 0, text
    rob = doc["robustness"]
    assert rob["members"] == 3 and not rob["fragile"]
    assert {name: v["status"] for name, v in verdicts(doc).items()} == {
        "clean": "holds",
        "no-fall": "holds",
    }
    assert sorted(d["values"]["physics-step"] for d in rob["draws"]) == [1, 2, 4]
    assert "robustness: 3 members (seed 0)" in text and "holds    no-fall" in text


@pytest.mark.needs("sim")
def test_a_threshold_at_the_nominal_measure_is_fragile_and_strict_fails_on_it(
    head_no: Path,
) -> None:
    # The nominal head shake tilts the torso 0.26 deg; perturbed members tilt 0.4 to 1 deg.
    code, text, doc = play(head_no, "--expect", "max_tilt<=0.5", "--robustness", "4")
    assert code == 0, text  # fragile is a warning
    tilt = verdicts(doc)["max_tilt<=0.5"]
    assert tilt["status"] == "fragile"
    assert 1 <= len(tilt["disagree"]) < 4
    first = tilt["disagree"][0]
    assert set(first["values"]) == {"friction", "mass", "start-yaw", "start-noise", "physics-step"}
    assert not first["passed"] and first["why"].startswith("expected max_tilt <= 0.5 deg")
    assert verdicts(doc)["clean"]["status"] == "holds"
    assert doc["robustness"]["fragile"] and doc["exit_code"] == 0
    n = len(tilt["disagree"])
    assert f"fragile  max_tilt<=0.5: {n} of 4 members disagree" in text
    assert f"#{first['sample']} (friction " in text
    assert "warning: a verdict is fragile under --robustness" in text

    code, text, doc = play(head_no, "--expect", "max_tilt<=0.5", "--robustness", "4", "--strict")
    assert code == 1 and doc["exit_code"] == 1, text


@pytest.mark.needs("sim")
def test_a_verdict_the_nominal_run_fails_fails(head_no: Path) -> None:
    code, text, doc = play(head_no, "--expect", "dx>=0.3", "--robustness", "3")
    assert code == 1, text
    assert verdicts(doc)["dx>=0.3"]["status"] == "fails"
    assert verdicts(doc)["dx>=0.3"]["disagree"] == []  # no member walks 0.3 m either


@pytest.mark.needs("sim")
def test_members_are_cached_as_batch_runs(head_no: Path, tmp_path: Path) -> None:
    cache = tmp_path / "cache"
    play(head_no, "--robustness", "3", cache=cache)
    stored = sorted(p.stem for p in (cache / "motiontool" / "batch").rglob("*.json"))
    assert len(stored) == 3
    # A member's cached report says it fell: the next play reads it instead of playing again.
    first = next((cache / "motiontool" / "batch").rglob("*.json"))
    cached = json.loads(first.read_text(encoding="utf-8"))
    cached["report"]["base"].update(fell=True, fell_at_s=1.0)
    first.write_text(json.dumps(cached), encoding="utf-8")
    code, text, doc = play(head_no, "--robustness", "3", cache=cache)
    assert code == 0 and verdicts(doc)["clean"]["status"] == "fragile", text
    assert [d["why"] for d in verdicts(doc)["clean"]["disagree"]] == ["fell at 1.00 s"]
    assert sorted(p.stem for p in (cache / "motiontool" / "batch").rglob("*.json")) == stored


@pytest.mark.needs("sim")
def test_members_in_a_world_play_at_steps_dividing_its_basic_time_step(head_no: Path) -> None:
    world = require(DATA / "worlds" / "wrestling" / "worlds" / "wrestling.wbt", "Webots worlds")
    _code, text, doc = play(
        head_no, "--world", world, "--robot-node", "participant", "--robustness", "3"
    )
    assert doc["stamps"]["control_step_ms"] == 10, text
    steps = {d["values"]["physics-step"] for d in doc["robustness"]["draws"]}
    assert steps == {1, 2}  # 4 ms does not divide the wrestling world's 10 ms


def _members(cache: Path) -> list[dict[str, Any]]:
    """The members' reports in a batch cache, by sample."""
    docs = [json.loads(p.read_text(encoding="utf-8")) for p in cache.rglob("*.json")]
    return sorted((d["report"] for d in docs), key=lambda r: r["stamps"]["seed"])


@pytest.mark.needs("sim")
def test_members_replay_the_chain_and_start_pose_deterministically(
    head_no: Path, tmp_path: Path
) -> None:
    second = tmp_path / "second.motion"
    shutil.copyfile(head_no, second)
    pose = ROOT / "motions" / "nao" / "bow.motion"  # its last pose: bent forward
    args = [head_no, second, "--chain", "--loop", "second=2", "--start-pose", pose]
    code, text, doc = play(*args, "--robustness", "2", cache=tmp_path / "one")
    assert code == 0 and verdicts(doc)["clean"]["status"] == "holds", text
    runs = [doc, *_members(tmp_path / "one" / "motiontool" / "batch")]
    assert len(runs) == 3  # the run, then its 2 members
    for report in runs:  # each member plays every element, from the start pose
        assert [(Path(f["path"]).name, f["loops"]) for f in report["files"]] == [
            ("head_no.motion", 1),
            ("second.motion", 2),
        ]
        assert report["options"]["start_pose"] == str(pose)
    assert runs[1]["stamps"]["seed"] == 1 and runs[1]["options"]["friction_scale"] != 1.0
    # The same seed plays the same members: a second cache holds the same reports.
    play(*args, "--robustness", "2", cache=tmp_path / "two")
    again = _members(tmp_path / "two" / "motiontool" / "batch")
    assert [r["base"] for r in again] == [r["base"] for r in runs[1:]]


@pytest.mark.needs("sim")
@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--strict"], "--strict fails on a fragile verdict: pass --robustness N"),
        (["--robustness", "3", "-"], "--robustness replays motion files, not standard input"),
        (["--robustness", "3", "--executor", "nope"], "'nope': choose local or ray"),
    ],
)
def test_robustness_usage_errors_exit_2_in_one_line(
    head_no: Path, args: list[str], message: str
) -> None:
    argv = [str(head_no) if a == "SECOND" else a for a in args]
    result = runner.invoke(app, ["play", "--headless", str(head_no), *argv])
    assert result.exit_code == 2
    assert message in result.output
    assert "Traceback" not in result.output


@pytest.mark.needs("sim")
def test_batch_robustness_reports_fragile_runs_in_every_format(
    head_no: Path, tmp_path: Path
) -> None:
    out = {ext: tmp_path / f"report.{ext}" for ext in ("json", "md", "xml")}
    argv = ["batch", str(head_no), "--expect", "max_tilt<=0.5", "--robustness", "4", "--no-cache"]
    argv += ["--json", str(out["json"]), "--markdown", str(out["md"]), "--junit", str(out["xml"])]
    result = runner.invoke(app, argv)
    assert result.exit_code == 0, result.output  # fragile is a warning
    assert "warning: 1 of 1 runs have a fragile verdict under --robustness" in result.stderr
    assert "fragile  max_tilt<=0.5" in result.stdout
    doc = json.loads(out["json"].read_text(encoding="utf-8"))
    validator = jsonschema.Draft202012Validator(schemas.load("batch"), registry=schemas.registry())
    assert [e.message for e in validator.iter_errors(doc)] == []
    (run,) = doc["runs"]  # the members are not runs of the batch
    assert run["status"] == "clean"
    tilt = {v["name"]: v for v in run["robustness"]["verdicts"]}["max_tilt<=0.5"]
    assert tilt["status"] == "fragile" and 1 <= len(tilt["disagree"]) < 4
    member = tilt["disagree"][0]
    markdown = out["md"].read_text(encoding="utf-8")
    assert "#### Robustness" in markdown and "| fragile |" in markdown
    assert f"#{member['sample']} (friction " in markdown
    junit = out["xml"].read_text(encoding="utf-8")
    assert "fragile  max_tilt&lt;=0.5" in junit and "<failure" not in junit

    strict = runner.invoke(app, [*argv, "--strict"])
    assert strict.exit_code == 1, strict.output
    doc = json.loads(out["json"].read_text(encoding="utf-8"))
    assert doc["runs"][0]["status"] == "failed"
    assert "fragile under --robustness: max_tilt<=0.5" in doc["runs"][0]["reason"]
    assert "<failure" in out["xml"].read_text(encoding="utf-8")


@pytest.mark.needs("sim")
def test_batch_robustness_replays_an_after_chain(head_no: Path, tmp_path: Path) -> None:
    before = tmp_path / "before.motion"
    shutil.copyfile(head_no, before)
    out = tmp_path / "batch.json"
    argv = ["batch", str(head_no), "--after", str(before), "--robustness", "2", "--no-cache"]
    result = runner.invoke(app, [*argv, "--json", str(out)])
    assert result.exit_code == 0, result.output
    (run,) = json.loads(out.read_text(encoding="utf-8"))["runs"]
    assert run["spec"]["chain"] == [str(before)]
    assert [Path(f["path"]).name for f in run["report"]["files"]] == [before.name, head_no.name]
    assert run["robustness"]["members"] == 2
    assert "before.motion + " in result.stdout and "holds    clean" in result.stdout


@pytest.mark.needs("sim")
def test_batch_robustness_holds_and_refuses_perturb(head_no: Path) -> None:
    result = runner.invoke(app, ["batch", str(head_no), "--robustness", "3", "--no-cache"])
    assert result.exit_code == 0, result.output
    assert "robustness: 3 members (seed 0)" in result.stdout
    assert "--robustness: 3 members played besides the runs, in the wall time" in result.stdout
    assert "holds    clean" in result.stdout and "fragile" not in result.stdout
    refused = runner.invoke(
        app, ["batch", str(head_no), "--robustness", "3", "--perturb", "mass=0.9:1.1"]
    )
    assert refused.exit_code == 2
    assert "not with --perturb or --samples" in refused.output


@pytest.mark.slow
@pytest.mark.needs("ray")
def test_members_on_ray_give_the_local_verdicts(
    head_no: Path, tmp_path: Path, one_ray: None
) -> None:
    second = tmp_path / "second.motion"  # a chain from a start pose: its elements travel too
    shutil.copyfile(head_no, second)
    chain = [str(head_no), str(second), "--chain", "--start-pose", str(HEAD_NO)]
    docs = {}
    for executor in ("local", "ray"):
        out = tmp_path / f"{executor}.json"
        argv = ["play", *chain, "--headless", "--hold", "0.2", "--expect", "max_tilt<=0.5"]
        argv += ["--robustness", "3", "--no-cache", "--executor", executor, "--json", str(out)]
        home = tmp_path / "home"  # a local Ray of its own (no ~/.ray of an earlier one)
        env = {**os.environ, "HOME": str(home)}
        subprocess.run([SCRIPT, *argv], check=True, capture_output=True, timeout=300, env=env)
        docs[executor] = json.loads(out.read_text(encoding="utf-8"))["robustness"]
    assert docs["ray"] == docs["local"]
    assert {v["status"] for v in docs["ray"]["verdicts"]} == {"holds", "fragile"}
