"""The targets in Webots' wrestling world that hold (docs/simulation.md, *The wrestling
world's targets*): played as a user plays them, through ``motiontool play`` with the vendored
motions' ``motions.toml`` (the world, the robot node ``participant``, the start or the Stand
before, ``expect --infer``'s expectations), in real MuJoCo. ``dev/wrestling_table.py`` measures
them all under ``--robustness``; these runs are its nominal ones."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from conftest import DATA, require
from typer.testing import CliRunner

from motiontool.cli.app import app
from motiontool.sim import commands

pytestmark = [pytest.mark.slow, pytest.mark.needs("sim")]

runner = CliRunner()


@pytest.fixture(scope="module")
def motions() -> Path:
    worlds = require(DATA / "worlds" / "MANIFEST.tsv", "Webots worlds").parent
    return worlds / "wrestling" / "controllers" / "motions"


def _play(motions: Path, tmp_path: Path, name: str, *args: str) -> dict:  # type: ignore[type-arg]
    out = tmp_path / f"{name}.json"
    result = runner.invoke(
        app, ["play", "--headless", str(motions / f"{name}.motion"), "--json", str(out), *args]
    )
    assert result.exit_code in (0, 1), result.output
    doc: dict = json.loads(out.read_text(encoding="utf-8"))  # type: ignore[type-arg]
    assert doc["world"]["robot_node"]["name"] == "participant"
    assert doc["stamps"]["control_step_ms"] == 10 and doc["self_collision"]["physics"]
    return doc


def _met(doc: dict) -> dict[str, bool]:  # type: ignore[type-arg]
    return {e["text"]: e["passed"] for e in doc["expectations"]}


def test_get_up_front_ends_upright(motions: Path, tmp_path: Path) -> None:
    doc = _play(motions, tmp_path, "GetUpFront")
    assert doc["base"]["started_down"] and _met(doc) == {"upright": True}
    # Laid at the robot node's x (-0.88 m), 0.23 m back, it stands beside the ring (edge at
    # -1.0 m): its torso 0.306 m above the floor, 0.256 m above the ring's top.
    assert doc["base"]["final_tilt_deg"] < 5 and doc["base"]["final_height_m"] > 0.25


def test_get_up_back_kneels_at_the_fall_height_without_falling(
    motions: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """From 2.8 s to 4.0 s it kneels, its torso at 0.199-0.201 m, the fall height (0.2 m) to
    the millimetre: the fall detector's hysteresis does not read that as up, then down."""
    doc = _play(motions, tmp_path, "GetUpBack")
    base = doc["base"]
    assert base["started_down"] and not base["fell"] and _met(doc) == {"upright": True}
    assert base["final_tilt_deg"] < 5 and base["final_height_m"] > 0.25
    monkeypatch.setattr(commands, "CHUNK_STEPS", 7)  # the detector's state crosses chunks
    chunked = _play(motions, tmp_path, "GetUpBack")["base"]
    yaw = chunked.pop("yaw_change_deg")  # a sum: chunks add its terms in another order
    assert yaw == pytest.approx(base.pop("yaw_change_deg"), abs=1e-9) and chunked == base


@pytest.mark.parametrize(("name", "sign"), [("SideStepLeftLoop", 1), ("SideStepRightLoop", -1)])
def test_side_step_loops_step_sideways_without_falling(
    motions: Path, tmp_path: Path, name: str, sign: int
) -> None:
    """Looped 4 times after Stand (its sidecar's after), as the controller loops a *Loop
    motion. SideStepRightLoop fell at 1.74 s while a world's contacts were damped by its bounce
    (0.5: a ratio of 0.22)."""
    doc = _play(motions, tmp_path, name, "--loop", f"{name}=4")
    assert [(Path(f["path"]).stem, f["loops"]) for f in doc["files"]] == [("Stand", 1), (name, 4)]
    assert all(_met(doc).values()), doc["expectations"]
    assert doc["clean"] and not doc["base"]["fell"]
    assert 0.06 < sign * doc["base"]["dy_m"] < 0.25 and abs(doc["base"]["dx_m"]) < 0.03


@pytest.mark.parametrize(
    ("name", "low", "high"),
    [("TurnLeft20", 15, 25), ("TurnRight20", -25, -15), ("TurnLeft60", 51, 69)],
)
def test_turns_after_stand_turn_within_their_band(
    motions: Path, tmp_path: Path, name: str, low: float, high: float
) -> None:
    doc = _play(motions, tmp_path, name)
    assert [Path(f["path"]).stem for f in doc["files"]] == ["Stand", name]
    assert all(_met(doc).values()), doc["expectations"]
    assert low <= doc["base"]["yaw_change_deg"] <= high


def test_hand_wave_for_a_minute_keeps_the_feet_planted(motions: Path, tmp_path: Path) -> None:
    world = motions.parent.parent / "worlds" / "wrestling.wbt"
    doc = _play(
        motions, tmp_path, "HandWave", "--loop", "12", "--world", str(world),
        "--robot-node", "participant", "--expect", "feet-planted", "--expect", "upright",
    )  # fmt: skip
    assert doc["simulated_s"] > 60 and doc["clean"]
    assert max(f["max_displacement_m"] for f in doc["feet"]) < 0.005


def test_the_world_s_bounce_is_not_a_damping_ratio(motions: Path, tmp_path: Path) -> None:
    """Webots' default bounce 0.5 (no ContactProperties in the world) is said, not applied."""
    doc = _play(motions, tmp_path, "TurnLeft20")
    (bounce,) = [e for e in doc["world"]["not_applied"] if e["field"].endswith(".bounce")]
    assert bounce["value"] == 0.5 and "critically damped" in bounce["reason"]
