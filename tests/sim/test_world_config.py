"""``world`` and ``robot-node`` in the configuration (``motiontool.toml``, ``[tool.motiontool]``):
the world play and batch play in when neither the command line nor motions.toml names one."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
from conftest import DATA, require
from typer.testing import CliRunner

from motiontool.cli.app import app

pytestmark = pytest.mark.needs("sim")

runner = CliRunner()
MOTION = Path("controllers", "motions", "HandWave.motion")


@pytest.fixture
def wrestling(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A copy of the wrestling world's folder, the working directory."""
    folder = require(DATA / "worlds" / "MANIFEST.tsv", "Webots worlds").parent / "wrestling"
    shutil.copytree(folder, tmp_path / "wrestling")
    monkeypatch.chdir(tmp_path / "wrestling")
    return tmp_path / "wrestling"


def _play(*args: str) -> dict:  # type: ignore[type-arg]
    result = runner.invoke(
        app, ["play", "--headless", "--hold", "0", "--json", "run.json", *args, str(MOTION)]
    )
    assert result.exit_code in (0, 1), result.output
    return json.loads(Path("run.json").read_text(encoding="utf-8"))  # type: ignore[no-any-return]


def test_the_configuration_world_is_played_in_below_the_sidecar_and_command_line(
    wrestling: Path,
) -> None:
    """Its path from the configuration file's folder; the world's basicTimeStep beats the
    configuration's timestep; motions.toml beats the configuration, --world beats both;
    --isolated reads none of it."""
    (wrestling / "pyproject.toml").write_text(
        '[tool.motiontool]\ntimestep = 40\nworld = "worlds/wrestling.wbt"\n'
        'robot-node = "opponent"\n',
        encoding="utf-8",
    )
    world = wrestling / "worlds" / "wrestling.wbt"
    doc = _play()
    assert doc["world"]["path"] == str(world)
    assert doc["world"]["robot_node"]["name"] == "opponent"
    assert doc["stamps"]["control_step_ms"] == 10
    assert _play("--isolated")["world"] is None
    doc = _play("--world", str(world), "--robot-node", "WRESTLER_RED")
    assert doc["world"]["robot_node"]["name"] == "participant"
    (wrestling / MOTION.parent / "motions.toml").write_text(
        '[HandWave]\nworld = "../../worlds/wrestling.wbt"\nrobot-node = "participant"\n',
        encoding="utf-8",
    )
    assert _play()["world"]["robot_node"]["name"] == "participant"


def test_batch_plays_in_the_configuration_world(wrestling: Path) -> None:
    """As play: the world's basicTimeStep beats the configuration's timestep, -t beats both;
    motions.toml beats the configuration; --isolated reads none of it."""
    (wrestling / "motiontool.toml").write_text(
        'timestep = 40\nworld = "worlds/wrestling.wbt"\nrobot-node = "WRESTLER_BLUE"\n',
        encoding="utf-8",
    )
    args = ["batch", str(MOTION), "-j", "1", "--no-cache", "--json", "b.json"]
    result = runner.invoke(app, args)
    assert result.exit_code == 0, result.output
    (run,) = json.loads(Path("b.json").read_text(encoding="utf-8"))["runs"]
    assert run["report"]["world"]["robot_node"]["name"] == "opponent"
    assert run["report"]["stamps"]["control_step_ms"] == 10
    options = dict(run["spec"]["options"])
    assert options["world"] == str(wrestling / "worlds" / "wrestling.wbt")
    assert len(options["world_sha256"]) == 64
    result = runner.invoke(app, [*args, "--isolated"])
    assert result.exit_code == 0, result.output
    (run,) = json.loads(Path("b.json").read_text(encoding="utf-8"))["runs"]
    assert run["report"]["world"] is None
    (wrestling / MOTION.parent / "motions.toml").write_text(
        '[HandWave]\nworld = "../../worlds/wrestling.wbt"\nrobot-node = "participant"\n',
        encoding="utf-8",
    )
    for more, step in (([], 10), (["-t", "40"], 40)):
        result = runner.invoke(app, [*args, *more])
        assert result.exit_code == 0, result.output
        (run,) = json.loads(Path("b.json").read_text(encoding="utf-8"))["runs"]
        assert run["report"]["world"]["robot_node"]["name"] == "participant"
        assert run["report"]["stamps"]["control_step_ms"] == step


@pytest.mark.parametrize(
    ("body", "message"),
    [
        ("world = 3\n", "pyproject.toml:5: 'world' must be a Webots world file (a path, string)"),
        (
            'robot = "nao"\nworld = "nowhere.wbt"\n',
            "pyproject.toml:6: 'world': no such file 'nowhere.wbt' (",
        ),
        ('robot-node = "opponent"\n', "pyproject.toml:5: 'robot-node' names a node of 'world'"),
        ('world = "worlds/wrestling.wbt"\nrobot-node = ""\n', "pyproject.toml:6: 'robot-node'"),
        ('wrold = "worlds/wrestling.wbt"\n', "did you mean 'world'?"),
    ],
)
def test_a_bad_world_key_is_one_line_naming_file_and_line(
    wrestling: Path, body: str, message: str
) -> None:
    (wrestling / "pyproject.toml").write_text(
        f"[project]\nname = 'x'\n\n[tool.motiontool]\n{body}", encoding="utf-8"
    )
    for command in (["play", "--headless"], ["batch", "--no-cache"]):
        result = runner.invoke(app, [*command, str(MOTION)])
        assert result.exit_code == 2, result.output
        assert result.stderr.startswith("motiontool: error: ") and message in result.stderr
        assert result.stderr.count("\n") == 1 and "Traceback" not in result.output
    assert runner.invoke(app, ["play", "--headless", "--isolated", str(MOTION)]).exit_code == 0
