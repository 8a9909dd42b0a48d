"""Self-collision physics: with Webots' ``selfCollision`` on (the world's robot
node, or ``--self-collision``) the robot's parts collide with each other in MuJoCo, but solids
joined by a joint; off (Webots' default for the Nao) they pass through each other."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import jsonschema
import numpy as np
import pytest
from conftest import DATA, require
from typer.testing import CliRunner

from motiontool.cli import schemas
from motiontool.cli.app import app
from motiontool.kinematics import resolve_robot
from motiontool.sim import _mujoco
from motiontool.sim._mujoco.scene import ROBOT_CLASSES

pytestmark = pytest.mark.needs("sim")

runner = CliRunner()

# The left arm hangs with the elbow bent across the belly, then its shoulder rolls inward to
# the motor's limit (-0.314 rad): the forearm and hand are driven through the torso.
HUG = (
    b"#WEBOTS_MOTION,V1.0,LShoulderPitch,LShoulderRoll,LElbowYaw,LElbowRoll\n"
    b"00:00:000,Zero,0,0,0,0\n"
    b"00:01:000,Out,1.5,0.5,0,-1.54\n"
    b"00:02:000,In,1.5,-0.31,0,-1.54\n"
)


def _reached_roll(self_collision: bool | None) -> float:
    """LShoulderRoll where a 3 s run of HUG's command leaves it, rad (MuJoCo itself)."""
    scene = _mujoco.build_scene(resolve_robot("nao", []), 20, self_collision=self_collision)
    j = {name: i for i, name in enumerate(scene.joints)}
    steps = 150
    targets = np.zeros((steps, len(scene.joints)))
    sent = np.zeros_like(targets, dtype=bool)
    for name, value in (("LShoulderPitch", 1.5), ("LElbowYaw", 0.0), ("LElbowRoll", -1.54)):
        targets[:, j[name]], sent[:, j[name]] = value, True
    ramp = 0.5 - 0.81 * np.arange(steps) / 50  # 0.5 -> -0.31 rad in 1 s, then held
    targets[:, j["LShoulderRoll"]], sent[:, j["LShoulderRoll"]] = np.maximum(ramp, -0.31), True
    trace = _mujoco.run(scene, targets, sent)
    return float(trace.position[-1, j["LShoulderRoll"]])


def test_the_torso_stops_an_arm_driven_through_it_only_with_self_collision() -> None:
    through = _reached_roll(False)
    stopped = _reached_roll(True)
    assert through == pytest.approx(-0.31, abs=0.01)  # off: the arm passes through the torso
    assert stopped > 0.1  # on: the torso holds the forearm out, 0.4 rad short of the target
    assert _reached_roll(None) == pytest.approx(through, abs=1e-9)  # the Nao's default: off


def _pairs_that_can_collide(scene: _mujoco.Scene) -> set[tuple[str, str]]:
    """The pairs of robot bodies MuJoCo's collision detection reports in a pose where every
    robot geometry overlaps every other (all moved to one point)."""
    import mujoco

    model, data = scene.model, scene.data
    robot = [g for g in range(model.ngeom) if scene.geom_class[g] in ROBOT_CLASSES]
    mujoco.mj_kinematics(model, data)
    root = data.xpos[scene.root_body].copy()
    for g in robot:  # every robot geometry at the torso's origin
        data.geom_xpos[g] = root
    for b in scene.robot_bodies:
        data.xpos[b] = root
        data.xipos[b] = root
    mujoco.mj_collision(model, data)
    names = {int(model.geom_bodyid[g]): scene.body_name(int(model.geom_bodyid[g])) for g in robot}
    out = set()
    for a, b in data.contact.geom[: data.ncon].tolist():
        if a in robot and b in robot:
            pair = sorted((names[int(model.geom_bodyid[a])], names[int(model.geom_bodyid[b])]))
            out.add((pair[0], pair[1]))
    return out


def test_a_touch_within_one_limb_fails_only_where_the_model_collides_its_parts() -> None:
    """The Nao in a world that turns self-collision on: its fingers touch its palm and its
    foot sensors its soles as in Webots (not a self-collision), an arm on the torso or one foot
    on the other is one; the UR5e's model collides its parts, and every touch counts."""
    nao = _mujoco.build_scene(resolve_robot("nao", []), 20, self_collision=True)
    assert not nao.touch_fails
    assert not nao.touch_counts("r_hand", "r_phalanx3")  # a fist: fingertips on the palm
    assert not nao.touch_counts("r_phalanx1", "r_phalanx8")
    assert not nao.touch_counts("RFsr", "r_ankle")
    assert nao.touch_counts("l_forearm", "torso")
    assert nao.touch_counts("LFsr", "RFsr")
    assert nao.touch_counts("l_phalanx2", "r_phalanx2")  # the two hands
    arm = _mujoco.build_scene(resolve_robot("ur5e", []), 8)
    assert arm.self_collision and arm.touch_fails
    assert arm.touch_counts("wrist_1_link", "wrist_3_link")


def test_solids_joined_by_a_joint_never_collide() -> None:
    # Webots' rule (Robot.selfCollision): no collision between two solids attached by a
    # joint, nor along a chain of joints sharing an anchor (the model's helper frames without
    # geometry: neck_virtual, l_shoulder_virtual); every other pair of bodies can collide.
    on = _mujoco.build_scene(resolve_robot("nao", []), 20, self_collision=True)
    pairs = _pairs_that_can_collide(on)
    assert ("l_forearm", "torso") in pairs and ("l_hand", "torso") in pairs
    assert ("l_thigh", "r_thigh") in pairs
    for parent, child in (
        ("torso", "l_upper_arm"),  # l_shoulder_virtual between them
        ("torso", "head"),  # neck_virtual between them
        ("l_upper_arm", "l_elbow"),
        ("l_elbow", "l_forearm"),
        ("l_hand", "l_phalanx1"),
        ("l_thigh", "l_tibia"),
    ):
        assert tuple(sorted((parent, child))) not in pairs
    # The pairs are those the self-collision probe watches (one rule for both).
    assert on.probe is not None
    probe = on.probe[0]
    watched = {
        tuple(sorted(on.body_name(int(probe.geom_bodyid[g])) for g in pair))
        for pair in zip(probe.pair_geom1.tolist(), probe.pair_geom2.tolist(), strict=True)
    }
    assert pairs == watched
    off = _mujoco.build_scene(resolve_robot("nao", []), 20, self_collision=False)
    assert _pairs_that_can_collide(off) == set() and not off.self_collision
    # The UR5e's model collides with itself (its Webots PROTO: selfCollision TRUE) unless told.
    ur5e = resolve_robot("ur5e", [])
    assert _mujoco.build_scene(ur5e, 8).self_collision
    assert not _mujoco.build_scene(ur5e, 8, self_collision=False).self_collision


def _schema_errors(doc: object) -> list[str]:
    validator = jsonschema.Draft202012Validator(schemas.load("play"), registry=schemas.registry())
    return [f"{list(e.absolute_path)}: {e.message}" for e in validator.iter_errors(doc)]


def _play(tmp_path: Path, *args: str) -> tuple[dict, str]:  # type: ignore[type-arg]
    motion = tmp_path / "hug.motion"
    motion.write_bytes(HUG)
    out = tmp_path / "run.json"
    result = runner.invoke(
        app, ["play", "--headless", "--hold", "1", "--json", str(out), *args, str(motion)]
    )
    assert result.exit_code in (0, 1), result.output
    return json.loads(out.read_text(encoding="utf-8")), result.stdout


def _roll_error(doc: dict) -> float:  # type: ignore[type-arg]
    """LShoulderRoll's largest |target - position|, rad."""
    return float(next(j for j in doc["joints"] if j["name"] == "LShoulderRoll")["max_error"])


def test_play_self_collision_option_and_its_report(tmp_path: Path) -> None:
    doc, text = _play(tmp_path, "--self-collision")
    assert _schema_errors(doc) == []
    sc = doc["self_collision"]
    assert (sc["physics"], sc["source"], sc["why"]) == (True, "option", "asked for")
    assert sc["touching_pairs"] >= 2 and sc["touching_s"] > 0
    assert _roll_error(doc) > 0.4  # held off by the torso, 1 s on
    pairs = {(c["body_a"], c["body_b"]) for c in doc["self_collisions"]}
    assert ("l_forearm", "torso") in pairs or ("l_hand", "torso") in pairs
    assert "self-collision physics: on (--self-collision);" in text
    assert "pairs of bodies touched" in text

    doc, text = _play(tmp_path, "--no-self-collision")
    assert _schema_errors(doc) == []
    assert doc["self_collision"] == {
        "physics": False,
        "source": "option",
        "why": "turned off, whatever the world says",
        "touching_pairs": 0,
        "touching_s": 0,
    }
    assert _roll_error(doc) < 0.15  # only the P controller's lag on the way in
    assert "self-collision physics: off (--no-self-collision)" in text

    doc, text = _play(tmp_path)  # Webots' default for the Nao: off, not said in the text
    assert doc["self_collision"]["physics"] is False
    assert doc["self_collision"]["source"] == "robot model"
    assert _roll_error(doc) < 0.15 and "self-collision physics" not in text


@pytest.fixture
def wrestling(tmp_path: Path) -> Path:
    """A copy of the vendored wrestling world's folder (its Nao: selfCollision TRUE)."""
    worlds = require(DATA / "worlds" / "MANIFEST.tsv", "Webots worlds").parent
    shutil.copytree(worlds / "wrestling", tmp_path / "wrestling")
    return tmp_path / "wrestling" / "worlds" / "wrestling.wbt"


def test_the_wrestling_worlds_self_collision_turns_it_on(wrestling: Path, tmp_path: Path) -> None:
    doc, text = _play(tmp_path, "--world", str(wrestling), "--robot-node", "participant")
    assert _schema_errors(doc) == []
    sc = doc["self_collision"]
    assert (sc["physics"], sc["source"]) == (True, "world")
    assert sc["why"].startswith("Nao 'participant'.selfCollision TRUE, line ")
    assert _roll_error(doc) > 0.4
    applied = {e["field"]: e for e in doc["world"]["applied"]}
    assert applied["Nao 'participant'.selfCollision"]["value"] is True
    assert "self-collision physics: on (Nao 'participant'.selfCollision TRUE" in text
    # The option wins over the world, and the world's part of the report says so.
    doc, _text = _play(
        tmp_path, "--world", str(wrestling), "--robot-node", "participant", "--no-self-collision"
    )
    assert doc["self_collision"]["physics"] is False and _roll_error(doc) < 0.15
    not_applied = {e["field"]: e for e in doc["world"]["not_applied"]}
    assert "option was given" in not_applied["Nao 'participant'.selfCollision"]["reason"]


def test_batch_self_collision_option_reaches_every_run_and_its_cache_key(tmp_path: Path) -> None:
    motion = tmp_path / "hug.motion"
    motion.write_bytes(HUG)
    args = ["batch", str(motion), "--robot", "nao", "--cache-dir", str(tmp_path / "cache")]
    docs = {}
    for flag in ("--self-collision", "--no-self-collision"):
        out = tmp_path / f"batch{flag}.json"
        result = runner.invoke(app, [*args, flag, "--json", str(out)])
        assert result.exit_code in (0, 1), result.output
        (run,) = json.loads(out.read_text(encoding="utf-8"))["runs"]
        docs[flag] = run["report"]
    assert docs["--self-collision"]["self_collision"]["physics"] is True
    assert docs["--self-collision"]["self_collision"]["source"] == "option"
    assert _roll_error(docs["--self-collision"]) > 0.4
    # Not answered from the first run's cache entry: the option is in the key.
    assert docs["--no-self-collision"]["self_collision"]["physics"] is False
    assert _roll_error(docs["--no-self-collision"]) < 0.15
