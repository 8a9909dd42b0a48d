"""``play --world FILE.wbt``: reading Webots worlds (tests/data/worlds, the real wrestling and
Nao demo worlds) and what a run takes from them, said field by field in its report."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import jsonschema
import pytest
from conftest import DATA, SHARED, require
from typer.testing import CliRunner

from motiontool.cli import schemas
from motiontool.cli.app import app
from motiontool.errors import MotionSyntaxError, MotionToolError
from motiontool.sim.wbt import parse_wbt
from motiontool.sim.world import read_world
from motiontool.sim.world_run import world_run

WORLDS = DATA / "worlds"
runner = CliRunner()


@pytest.fixture(scope="module")
def worlds() -> Path:
    return require(WORLDS / "MANIFEST.tsv", "Webots worlds").parent


@pytest.fixture
def wrestling(worlds: Path, tmp_path: Path) -> Path:
    """A copy of the wrestling world's folder (worlds/, protos/, controllers/motions/)."""
    shutil.copytree(worlds / "wrestling", tmp_path / "wrestling")
    return tmp_path / "wrestling"


# -- the vendored worlds


def test_the_vendored_worlds_are_as_listed_and_unmodified(worlds: Path) -> None:
    header, *rows = (worlds / "MANIFEST.tsv").read_text(encoding="utf-8").splitlines()
    assert header.split("\t") == ["path", "repository", "commit", "bytes"]
    listed = {}
    for row in rows:
        path, _repo, commit, size = row.split("\t")
        assert (worlds / path).stat().st_size == int(size), path
        assert len(commit) == 40
        listed[path] = (worlds / path).read_bytes()
    found = {p.relative_to(worlds).as_posix() for p in worlds.rglob("*") if p.is_file()}
    ours = {"MANIFEST.tsv", "NOTICE", "wrestling/controllers/motions/motions.toml"}
    assert found == set(listed) | ours
    assert "Apache License, Version 2.0" in (worlds / "NOTICE").read_text(encoding="utf-8")
    upstream = SHARED / "worlds"
    if upstream.is_dir():  # the machine the copies were taken on
        for path, data in listed.items():
            assert (upstream / path).read_bytes() == data, path


# -- reading


def test_the_wrestling_world_as_read(worlds: Path) -> None:
    world = read_world(worlds / "wrestling/worlds/wrestling.wbt", "participant", "nao")
    assert (world.version, world.coordinate_system) == ("R2023b", "ENU")
    assert world.basic_time_step_ms == 10
    assert world.gravity == (0.0, 0.0, -9.81)
    assert world.contact_properties == ()
    robot = world.robot
    assert (robot.name, robot.def_name, robot.type) == ("participant", "WRESTLER_RED", "Nao")
    assert robot.translation == (-0.88, 0.0, 0.384)
    assert robot.self_collision is True  # written in the world
    assert robot.foot_material == "NAO foot material"  # the local Nao.proto's default
    floor, ring = world.supports
    assert (floor.node, floor.kind, floor.size, floor.top_z) == ("Floor", "plane", (6, 6, 0), 0)
    # The ring's bounding box is read from its local PROTO, its translation from the default.
    assert (ring.node, ring.name, ring.kind) == ("WrestlingRing", "wrestling ring", "box")
    assert ring.size == (2.0, 2.0, 0.05) and ring.top_z == pytest.approx(0.05)
    assert ring.top_at(-0.88, 0.0) == pytest.approx(0.05) and ring.top_at(1.5, 0) is None
    skipped = "\n".join(world.skipped)
    assert "EXTERNPROTO URLs are never fetched): RubberDuck line 60, RubberDuck line 65" in skipped
    assert "solids with physics" in skipped and "WrestlingPole line 44" in skipped
    assert "'opponent' (DEF WRESTLER_BLUE, Nao) line 78" in skipped
    assert "'referee' (WrestlingReferee) line 89" in skipped


def test_the_robot_node_is_chosen_by_name_or_def(worlds: Path) -> None:
    path = worlds / "wrestling/worlds/wrestling.wbt"
    blue = read_world(path, "WRESTLER_BLUE", "nao")
    assert blue.robot.name == "opponent"
    assert world_run(blue).start_yaw_deg == pytest.approx(180.0, abs=1e-3)
    red = world_run(read_world(path, "participant", "nao"))
    assert red.start_xy == (-0.88, 0.0) and red.control_step_ms == 10
    assert red.surface == ("wrestling ring", pytest.approx(0.05))
    # The scene is lowered so that the ring's top is at z = 0.
    assert {g.name: g.center[2] for g in red.ground} == {
        "floor": pytest.approx(-0.05),
        "floor:wrestling ring": pytest.approx(-0.025),
    }


def test_the_nao_demo_world_a_nue_world_with_its_foot_contact(worlds: Path) -> None:
    world = read_world(worlds / "webots-nao/nao_demo.wbt", None, "nao")
    assert (world.version, world.coordinate_system, world.basic_time_step_ms) == (
        "R2021c",
        "NUE",
        20,
    )
    assert world.robot.name == "NAO" and world.robot.translation is None
    contact = world.contact("default")  # the Floor's material against the Nao's feet
    assert (contact.coulomb_friction, contact.bounce, contact.line) == (7.0, 0.3, 14)
    assert world.contact("rubber").coulomb_friction == 1.0  # none matches: Webots' defaults
    assert world_run(world).friction(None) == 7.0


def _wrestling_text(worlds: Path) -> str:
    return (worlds / "wrestling/worlds/wrestling.wbt").read_text(encoding="utf-8")


@pytest.mark.parametrize(
    ("edit", "robot_node", "message"),
    [
        (lambda t: t[: t.index("DEF WRESTLER_BLUE") + 40], None,
         r"wrestling\.wbt:79:17: unexpected end of file: '\{' opened at 78:23 is not closed"),
        (lambda t: t.replace("Floor {", "Floor (", 1), None,
         r"wrestling\.wbt:36:7: expected '\{' after node type 'Floor', got '\('"),
        (lambda t: t.replace('  name "participant"', '  name "participant', 1), None,
         r"wrestling\.wbt:72:8: string not closed on its line"),
        (lambda t: t.replace("#VRML_SIM", "#VRML", 1), None,
         r"wrestling\.wbt:1:1: not a Webots world or PROTO file"),
        (lambda t: t, None,
         r"wrestling\.wbt:1:1: 2 robot nodes could play it: 'participant' \(DEF WRESTLER_RED, "
         r"Nao\), 'opponent' \(DEF WRESTLER_BLUE, Nao\); name the one that plays \(its name or DEF\)"),
        (lambda t: t, "blue",
         r"wrestling\.wbt:1:1: no robot node named 'blue' \(name or DEF\) in this world; its "
         r"robots: 'participant'"),
        (lambda t: t, "referee",
         r"wrestling\.wbt:89:1: robot node 'referee' \(WrestlingReferee\) is a WrestlingReferee,"
         r" not a known robot: it cannot play a motion for nao"),
        (lambda t: t[: t.index("DEF WRESTLER_RED")] + t[t.index("WrestlingReferee {") :], None,
         r"wrestling\.wbt:1:1: no robot node for nao in this world \(its robots: 'referee'"),
        (lambda t: t.replace("basicTimeStep 10", "basicTimeStep TRUE"), None,
         r"wrestling\.wbt:13:1: WorldInfo\.basicTimeStep must be one number, got TRUE"),
    ],
    ids=["truncated", "unknown-syntax", "open-string", "no-header", "two-robots", "no-such-robot",
         "not-a-nao", "no-nao", "bad-field"],
)  # fmt: skip
def test_a_bad_world_is_one_located_line(
    wrestling: Path, edit: object, robot_node: str | None, message: str
) -> None:
    path = wrestling / "worlds" / "wrestling.wbt"
    path.write_text(edit(path.read_text(encoding="utf-8")), encoding="utf-8")  # type: ignore[operator]
    with pytest.raises(MotionSyntaxError, match=message):
        read_world(path, robot_node, "nao")


def test_template_protos_give_their_interface_and_base_type(worlds: Path) -> None:
    nao = parse_wbt((worlds / "wrestling/protos/Nao.proto").read_text(encoding="utf-8")).protos[0]
    assert (nao.name, nao.base_type, nao.body) == ("Nao", "Robot", None)  # JavaScript body
    assert nao.defaults["translation"] == (0.0, 0.0, 0.334)
    referee = (worlds / "wrestling/protos/WrestlingReferee.proto").read_text(encoding="utf-8")
    assert parse_wbt(referee).protos[0].base_type == "Robot"  # a Lua template in its body


# -- playing in a world


def _schema_errors(doc: object) -> list[str]:
    validator = jsonschema.Draft202012Validator(schemas.load("play"), registry=schemas.registry())
    return [f"{list(e.absolute_path)}: {e.message}" for e in validator.iter_errors(doc)]


def _play(folder: Path, *args: str) -> tuple[dict, str]:  # type: ignore[type-arg]
    motion = folder / "controllers" / "motions" / "HandWave.motion"
    out = folder / "run.json"
    result = runner.invoke(
        app,
        ["play", "--headless", "--hold", "0", "--json", str(out), *args, str(motion)],
    )
    assert result.exit_code in (0, 1), result.output
    return json.loads(out.read_text(encoding="utf-8")), result.stdout


def _by_field(entries: list[dict]) -> dict[str, dict]:  # type: ignore[type-arg]
    return {e["field"]: e for e in entries}


@pytest.mark.needs("sim")
def test_play_in_the_wrestling_world_applies_it_and_says_so(wrestling: Path) -> None:
    world = wrestling / "worlds" / "wrestling.wbt"
    doc, text = _play(wrestling, "--world", str(world), "--robot-node", "WRESTLER_RED")
    assert _schema_errors(doc) == []
    assert doc["stamps"]["control_step_ms"] == 10  # the world's basicTimeStep
    assert doc["stamps"]["physics_step_ms"] == 2  # MuJoCo's finer step, kept
    assert doc["physics"]["friction"] == 1.0  # Webots' default ContactProperties
    w = doc["world"]
    assert w["path"] == str(world) and w["robot_node"] == {
        "name": "participant",
        "def": "WRESTLER_RED",
        "type": "Nao",
    }
    applied, not_applied = _by_field(w["applied"]), _by_field(w["not_applied"])
    assert applied["WorldInfo.basicTimeStep"]["value"] == 10
    assert applied["WorldInfo.gravity"] == {
        "field": "WorldInfo.gravity",
        "value": 9.81,
        "unit": "m/s^2",
        "applied_as": "gravity, down",
    }
    assert applied["ContactProperties.coulombFriction"]["value"] == 1.0
    assert "Webots' default" in applied["ContactProperties.coulombFriction"]["applied_as"]
    assert applied["Nao 'participant'.translation"]["value"] == [-0.88, 0.0, 0.384]
    assert applied["WrestlingRing 'wrestling ring'.boundingObject"]["value"] == [2, 2, 0.05]
    assert applied["Nao 'participant'.selfCollision"]["value"] is True
    assert "collide" in applied["Nao 'participant'.selfCollision"]["applied_as"]
    assert {"WorldInfo.ERP", "WorldInfo.CFM", "ContactProperties.softCFM"} <= set(not_applied)
    assert (
        "5 steps per control step"
        in not_applied["WorldInfo.basicTimeStep as the physics step"]["reason"]
    )
    assert any("RubberDuck" in line for line in w["skipped_nodes"])
    # The robot stood on the ring: heights from its top, no contact with anything else.
    assert doc["base"]["final_height_m"] == pytest.approx(0.334, abs=0.002)
    assert doc["scene_contacts"] == [] and not doc["base"]["fell"]
    assert "world: " in text and "robot node 'participant' (DEF WRESTLER_RED)" in text
    assert "applied: Nao 'participant'.selfCollision TRUE" in text


@pytest.mark.needs("sim")
def test_another_world_changes_what_is_applied(wrestling: Path) -> None:
    world = wrestling / "worlds" / "wrestling.wbt"
    text = world.read_text(encoding="utf-8").replace(
        "  basicTimeStep 10\n",
        "  basicTimeStep 20\n  gravity 9.5\n  contactProperties [\n    ContactProperties {\n"
        '      material1 "NAO foot material"\n      coulombFriction [ 0.5 ]\n      bounce 0.2\n'
        "    }\n  ]\n",
    )
    world.write_text(text, encoding="utf-8")
    doc, _text = _play(wrestling, "--world", str(world), "--robot-node", "participant")
    assert _schema_errors(doc) == []
    assert doc["stamps"]["control_step_ms"] == 20
    assert doc["physics"]["friction"] == 0.5
    applied = _by_field(doc["world"]["applied"])
    assert applied["WorldInfo.gravity"]["value"] == 9.5
    assert applied["ContactProperties.coulombFriction"]["value"] == 0.5
    assert "line 23" in applied["ContactProperties.coulombFriction"]["applied_as"]
    not_applied = _by_field(doc["world"]["not_applied"])
    assert not_applied["ContactProperties.bounce"]["value"] == 0.2
    assert "critically damped" in not_applied["ContactProperties.bounce"]["reason"]
    # The options win over the world, and the report says so.
    doc, _text = _play(
        wrestling, "--world", str(world), "--robot-node", "participant", "-t", "40",
        "--friction", "0.8",
    )  # fmt: skip
    assert doc["stamps"]["control_step_ms"] == 40 and doc["physics"]["friction"] == 0.8
    not_applied = _by_field(doc["world"]["not_applied"])
    assert not_applied["WorldInfo.basicTimeStep"]["reason"] == "a control step was given"
    assert not_applied["ContactProperties.coulombFriction"]["value"] == 0.5


@pytest.mark.needs("sim")
def test_a_bad_world_on_the_command_line_is_one_line_exit_2(
    wrestling: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(wrestling)
    world = Path("worlds", "wrestling.wbt")
    motion = Path("controllers", "motions", "HandWave.motion")
    result = runner.invoke(app, ["play", "--headless", "--world", str(world), str(motion)])
    assert result.exit_code == 2
    assert result.stderr.strip().splitlines() == [
        f"motiontool: error: {world}:1:1: 2 robot nodes could play it: 'participant' (DEF "
        "WRESTLER_RED, Nao), 'opponent' (DEF WRESTLER_BLUE, Nao); name the one that plays (its "
        "name or DEF)"
    ]
    result = runner.invoke(app, ["play", "--headless", "--robot-node", "x", str(motion)])
    assert result.exit_code == 2
    assert "--robot-node names a robot node of --world" in result.stderr


@pytest.mark.needs("sim")
def test_the_world_step_wins_over_the_configuration_and_timestep_over_both(
    wrestling: Path,
) -> None:
    """--world is asked for on the command line: its basicTimeStep beats the configuration's
    ``timestep`` (which stands for the robot's usual world); -t beats both."""
    config = wrestling / "motiontool.toml"
    config.write_text("timestep = 40\n", encoding="utf-8")
    world = str(wrestling / "worlds" / "wrestling.wbt")
    doc, _text = _play(
        wrestling, "--config", str(config), "--world", world, "--robot-node", "participant"
    )
    assert doc["stamps"]["control_step_ms"] == 10
    doc, _text = _play(wrestling, "--config", str(config))
    assert doc["stamps"]["control_step_ms"] == 40 and doc["world"] is None


# -- batch in a world


@pytest.mark.needs("sim")
def test_batch_plays_every_run_in_the_world_and_caches_by_its_content(
    wrestling: Path, tmp_path: Path
) -> None:
    """batch --world: each run's report carries the world's settings; the cache key holds the
    world's content (a changed world is played again, not answered from the cache)."""
    world = wrestling / "worlds" / "wrestling.wbt"
    motion = wrestling / "controllers" / "motions" / "HandWave.motion"
    cache = tmp_path / "cache"
    args = [
        "batch",
        str(motion),
        "-j",
        "1",
        "--cache-dir",
        str(cache),
        "--json",
        str(tmp_path / "b.json"),
    ]
    world_args = ["--world", str(world), "--robot-node", "participant"]
    result = runner.invoke(app, [*args, *world_args])
    assert result.exit_code == 0, result.output
    (run,) = json.loads((tmp_path / "b.json").read_text(encoding="utf-8"))["runs"]
    assert run["report"]["stamps"]["control_step_ms"] == 10
    assert run["report"]["world"]["robot_node"]["def"] == "WRESTLER_RED"
    world.write_text(
        world.read_text(encoding="utf-8").replace("basicTimeStep 10", "basicTimeStep 20"),
        encoding="utf-8",
    )
    result = runner.invoke(app, [*args, *world_args])
    assert result.exit_code == 0, result.output
    (run,) = json.loads((tmp_path / "b.json").read_text(encoding="utf-8"))["runs"]
    assert run["report"]["stamps"]["control_step_ms"] == 20  # played again, not cached
    result = runner.invoke(app, [*args, "--world", str(world)])  # two Nao, none chosen
    assert result.exit_code == 2
    assert "2 robot nodes could play it" in result.stderr and "Traceback" not in result.output
    result = runner.invoke(app, [*args, "--robot-node", "participant"])
    assert result.exit_code == 2
    assert "robot node 'participant' given without a world" in result.stderr


# -- worlds written for the tests


def test_static_solids_are_supports_and_others_are_named(tmp_path: Path) -> None:
    world = tmp_path / "box.wbt"
    world.write_text(
        """#VRML_SIM R2023b utf8
WorldInfo { gravity 3.7 }
Solid {
  translation 0.5 0 0.1
  rotation 0 0 1 1.5708
  name "step"
  contactMaterial "wood"
  boundingObject Pose { translation 0 0 0 children [ Box { size 2 1 0.2 } ] }
}
Solid { translation 3 0 0 boundingObject Cylinder { radius 0.1 height 1 } }
DEF BOT Nao { translation 0.5 0.8 0.534 rotation 0 0 1 -1.5708 }
""",
        encoding="utf-8",
    )
    read = read_world(world, None, "nao")
    assert read.gravity == (0.0, 0.0, -3.7) and read.basic_time_step_ms == 32  # Webots' default
    (step,) = read.supports
    assert (step.name, step.material, step.top_z) == ("step", "wood", pytest.approx(0.2))
    assert step.top_at(0.5, 0.8) == pytest.approx(0.2)  # turned 90 degrees: 1 m wide along x
    assert step.top_at(1.2, 0.0) is None
    assert read.skipped == (
        "not simulated (bounding objects other than Box and Plane): Solid line 10",
    )
    run = world_run(read)
    assert run.surface == ("step", pytest.approx(0.2)) and run.start_yaw_deg == pytest.approx(
        -90, abs=1e-3
    )
    assert run.control_step_ms == 32 and run.friction(None) == 1.0  # no ContactProperties


def test_a_nue_world_is_turned_z_up(tmp_path: Path) -> None:
    world = tmp_path / "nue.wbt"
    world.write_text(
        """#VRML_SIM R2021c utf8
WorldInfo { coordinateSystem "NUE" basicTimeStep 16 }
Nao { translation 1 0.334 2 rotation 0 1 0 0.5 }
""",
        encoding="utf-8",
    )
    run = world_run(read_world(world, None, "nao"))
    assert run.start_xy == (2.0, 1.0)  # NUE: x north, y up, z east; z up: (east, north)
    assert run.start_yaw_deg == pytest.approx(28.6479, abs=1e-3)
    assert run.control_step_ms == 16
    world.write_text(world.read_text().replace("basicTimeStep 16", "basicTimeStep 7.5"))
    with pytest.raises(MotionToolError, match=r"basicTimeStep 7\.5 ms is not a whole number"):
        world_run(read_world(world, None, "nao"))


def test_a_solid_turned_by_a_negative_angle_turns_clockwise(tmp_path: Path) -> None:
    world = tmp_path / "turned.wbt"
    world.write_text(
        """#VRML_SIM R2023b utf8
Solid { rotation 0 0 1 -0.5 boundingObject Box { size 2 1 0.1 } }
Solid { translation 5 0 0 rotation 0 0 -1 0.5 boundingObject Box { size 2 1 0.1 } }
Nao { }
""",
        encoding="utf-8",
    )
    first, second = read_world(world, None, "nao").supports
    assert first.yaw_rad == -0.5 and second.yaw_rad == -0.5  # axis down: the same turn


# -- the world of a motion, in its motions.toml


@pytest.mark.needs("sim")
def test_a_sidecar_names_the_world_of_its_motions(wrestling: Path, tmp_path: Path) -> None:
    """``world`` and ``robot-node`` in motions.toml (the world's path from the sidecar's
    folder): play and batch use them; --world on the command line wins."""
    sidecar = wrestling / "controllers" / "motions" / "motions.toml"
    sidecar.write_text(
        '["Hand*"]\nworld = "../../worlds/wrestling.wbt"\nrobot-node = "opponent"\n',
        encoding="utf-8",
    )
    doc, _text = _play(wrestling)
    assert doc["world"]["robot_node"]["name"] == "opponent"
    assert doc["stamps"]["control_step_ms"] == 10
    motion = wrestling / "controllers" / "motions" / "HandWave.motion"
    out = tmp_path / "b.json"
    result = runner.invoke(app, ["batch", str(motion), "-j", "1", "--no-cache", "--json", str(out)])
    assert result.exit_code == 0, result.output
    (run,) = json.loads(out.read_text(encoding="utf-8"))["runs"]
    assert run["report"]["world"]["robot_node"]["name"] == "opponent"
    world = wrestling / "worlds" / "wrestling.wbt"
    doc, _text = _play(wrestling, "--world", str(world), "--robot-node", "participant")
    assert doc["world"]["robot_node"]["name"] == "participant"  # the command line wins


@pytest.mark.needs("sim")
def test_a_sidecar_world_that_is_not_there_is_its_line(
    wrestling: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(wrestling / "controllers")
    sidecar = Path("motions", "motions.toml")
    sidecar.write_text(
        '[HandWave]\nexpect = ["upright"]\nworld = "nowhere.wbt"\n', encoding="utf-8"
    )
    result = runner.invoke(app, ["play", "--headless", "motions/HandWave.motion"])
    assert result.exit_code == 2
    assert result.stderr.strip().splitlines() == [
        f"motiontool: error: {sidecar}:3: world 'nowhere.wbt' in [HandWave]: no such file"
        f" ({sidecar.parent / 'nowhere.wbt'})"
    ]
